"""Matplotlib conventions of the report: the paper's colours, PNG + SVG output, mode maps.

Headless (Agg).  Output is reproducible byte for byte where matplotlib allows
(no dates or software stamps in the files, fixed SVG ids), so a regenerated
reference report differs from the committed one only where results differ.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from crosscheck.analytic import Mode  # noqa: E402

__all__ = [
    "MODE_COLORS",
    "MODE_CMAP",
    "MODE_NORM",
    "B_COLOR",
    "P_COLOR",
    "LINE_COLORS",
    "plt",
    "save_figure",
    "mode_image",
    "mode_legend",
    "categorical_image",
    "PI_TICKS_VARPHI",
]

# The paper's shading (ex_shared.tex: myyellow, myorange, mylime, mypurple), Fig. 3a caption:
# slipping yellow, lift-off orange, inconsistent lime, indeterminate purple.
MODE_COLORS = {
    Mode.SLIP: (246 / 255, 235 / 255, 24 / 255),
    Mode.LIFTOFF: (246 / 255, 134 / 255, 59 / 255),
    Mode.INCONSISTENT: (150 / 255, 201 / 255, 61 / 255),
    Mode.INDETERMINATE: (186 / 255, 83 / 255, 159 / 255),
}
MODE_CMAP = ListedColormap([MODE_COLORS[m] for m in sorted(MODE_COLORS)], name="painleve_modes")
MODE_NORM = BoundaryNorm(np.arange(-0.5, len(MODE_COLORS)), MODE_CMAP.N)

#: The paper draws b = 0 in red (myred) and p = 0 in blue (myblue).
B_COLOR = (0.8, 0.1, 0.1)
P_COLOR = (0.1, 0.4, 0.8)

#: The paper's line colours md1..md7 (MATLAB's default order).
LINE_COLORS = [
    (0, 0.4470, 0.7410),
    (0.8500, 0.3250, 0.0980),
    (0.9290, 0.6940, 0.1250),
    (0.4940, 0.1840, 0.5560),
    (0.4660, 0.6740, 0.1880),
    (0.3010, 0.7450, 0.9330),
    (0.6350, 0.0780, 0.1840),
]

PI_TICKS_VARPHI = ([-np.pi, -3 * np.pi / 4, -np.pi / 2, -np.pi / 4, 0], ["$-\\pi$", "$-3\\pi/4$", "$-\\pi/2$", "$-\\pi/4$", "0"])

plt.rcParams.update(
    {
        "figure.dpi": 100,
        "savefig.dpi": 110,
        "font.size": 9,
        "axes.titlesize": 9,
        "svg.fonttype": "none",  # text stays text: smaller, searchable SVG
        "svg.hashsalt": "crosscheck",  # fixed element ids: reproducible SVG
        "image.interpolation": "nearest",
    }
)


def save_figure(fig, stem: Path) -> None:
    """Write ``<stem>.png`` and ``<stem>.svg`` and close ``fig``."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(stem.with_suffix(".png"), metadata={"Software": None}, bbox_inches="tight")
    fig.savefig(stem.with_suffix(".svg"), metadata={"Date": None, "Creator": None}, bbox_inches="tight")
    plt.close(fig)


def _extent(x: np.ndarray, y: np.ndarray) -> list[float]:
    # cell-centred samples: the image spans half a cell beyond the first and last sample
    dx = (x[-1] - x[0]) / max(len(x) - 1, 1)
    dy = (y[-1] - y[0]) / max(len(y) - 1, 1)
    return [x[0] - dx / 2, x[-1] + dx / 2, y[0] - dy / 2, y[-1] + dy / 2]


def mode_image(ax, x: np.ndarray, y: np.ndarray, modes: np.ndarray):
    """Draw a map of ``Mode`` codes (shape (len(y), len(x))) in the paper's colours."""
    return ax.imshow(modes, origin="lower", extent=_extent(x, y), aspect="auto", cmap=MODE_CMAP, norm=MODE_NORM)


def categorical_image(ax, x: np.ndarray, y: np.ndarray, codes: np.ndarray, colors: dict[int, tuple]):
    """Draw a map of small integer codes with one colour per code (codes absent from ``colors``: white)."""
    keys = sorted(colors)
    lut = {k: i for i, k in enumerate(keys)}
    idx = np.vectorize(lambda c: lut.get(int(c), -1) if np.isfinite(c) else -1)(codes) if codes.size else codes
    cmap = ListedColormap([colors[k] for k in keys]).with_extremes(under="white")
    norm = BoundaryNorm(np.arange(-0.5, len(keys)), cmap.N)
    return ax.imshow(np.ma.masked_less(idx, 0), origin="lower", extent=_extent(x, y), aspect="auto", cmap=cmap, norm=norm)


def mode_legend(ax, *, extra: list | None = None, **kw):
    """Legend of the four modes (and any extra handles)."""
    handles = [Patch(color=MODE_COLORS[m], label=m.name.lower()) for m in sorted(MODE_COLORS)]
    return ax.legend(handles=handles + (extra or []), **kw)
