"""Matplotlib conventions of the report: the paper's colours, PNG + SVG output, mode maps.

Headless (Agg).  Output is reproducible byte for byte where matplotlib allows
(no dates or software stamps in the files, fixed SVG ids), so a regenerated
reference report differs from the committed one only where results differ.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.patches import Patch

from crosscheck.theory.analytic import Mode

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
    "GB_TYPE_COLORS",
    "OUTCOME_COLORS",
    "outcome_legend",
    "pb_plane",
    "pb_orbits",
    "pb_eigenvectors",
    "strong_weak_colors",
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

PI_TICKS_VARPHI = (
    [-np.pi, -3 * np.pi / 4, -np.pi / 2, -np.pi / 4, 0],
    ["$-\\pi$", "$-3\\pi/4$", "$-\\pi/2$", "$-\\pi/4$", "0"],
)

plt.rcParams.update(
    {
        "figure.dpi": 100,
        "savefig.dpi": 110,
        "font.size": 9,
        "axes.titlesize": 9,
        "svg.fonttype": "none",  # text stays text: smaller, searchable SVG
        "svg.hashsalt": "crosscheck",  # fixed element ids: reproducible SVG
        "image.interpolation": "nearest",
        # constrained layout fits labels at draw time: no bbox_inches="tight" (an extra draw per file)
        "figure.constrained_layout.use": True,
    }
)


def _share_mathtext_parses(size: int = 2048):
    """Parse each mathtext label ($\\theta$, $\\Psi_L$, a log axis's $10^{-3}$) once per output kind, dpi and font;
    returns the shared cache (None where it could not be installed).

    Matplotlib caches parses per renderer, and every savefig makes a new renderer: the report's ~110 figures
    parsed their ~230 distinct labels 1254 times, a tenth of the render's CPU (measured on the quick report).  A
    parse depends on the parser only through its output kind (raster for Agg, vector for SVG), so one cache keyed
    by that kind returns what each renderer's own parse would: the figures are byte for byte the same.  Where a
    matplotlib release no longer has this private method the renderers keep their own caches.

    A forked process starts with the cache empty, as matplotlib empties its font cache: a vector parse holds its
    fonts, and a FreeType font read in two processes shares one file offset, so a glyph or table read in one
    process can return the bytes the other sought (the render's workers are forked while this process draws).
    """
    import functools
    import os

    from matplotlib.mathtext import MathTextParser

    parse = getattr(getattr(MathTextParser, "_parse_cached", None), "__wrapped__", None)
    if parse is None or getattr(MathTextParser, "_crosscheck_shared", None) is not None:
        return getattr(MathTextParser, "_crosscheck_shared", None)
    parser_of: dict[str, MathTextParser] = {}

    @functools.lru_cache(size)
    def shared(kind, s, dpi, prop, antialiased, load_glyph_flags):
        return parse(parser_of[kind], s, dpi, prop, antialiased, load_glyph_flags)

    def _parse_cached(self, s, dpi, prop, antialiased, load_glyph_flags):
        parser_of.setdefault(self._output_type, self)
        return shared(self._output_type, s, dpi, prop, antialiased, load_glyph_flags)

    shared.matplotlib_parse = parse  # the parse itself, as each renderer's cache calls it
    if hasattr(os, "register_at_fork"):
        os.register_at_fork(after_in_child=shared.cache_clear)
    MathTextParser._parse_cached = _parse_cached
    MathTextParser._crosscheck_shared = shared
    return shared


#: The cache of mathtext parses every figure of this process shares (``_share_mathtext_parses``).
MATHTEXT_PARSES = _share_mathtext_parses()


#: Fig. 17's colours for the type of a GB point (md1 stable node, md2 saddle, md3 unstable node,
#: md5 unstable focus); the paper shows no stable focus or degenerate point: grey and black here.
GB_TYPE_COLORS = {
    0: LINE_COLORS[0],
    1: LINE_COLORS[1],
    2: LINE_COLORS[2],
    3: (0.6, 0.6, 0.6),
    4: LINE_COLORS[4],
    5: (0, 0, 0),
}


#: Colours of ``crosscheck.Outcome`` in maps: an outcome looks like the mode it leads into (SLIP
#: yellow as slipping, LIFTOFF orange, JAM lime as the inconsistent region it enters), STICK blue,
#: GB (b = p = 0 reached) purple, DIVERGED black.
OUTCOME_COLORS = {
    0: MODE_COLORS[Mode.SLIP],
    1: MODE_COLORS[Mode.LIFTOFF],
    2: (0.55, 0.75, 0.95),
    3: MODE_COLORS[Mode.INCONSISTENT],
    4: (0.0, 0.0, 0.0),
    5: MODE_COLORS[Mode.INDETERMINATE],
    6: (0.85, 0.45, 0.0),
}


def outcome_legend(ax, codes=None, **kw):
    """Legend of the outcome colours (only ``codes`` if given)."""
    from crosscheck.outcome import Outcome

    codes = sorted(OUTCOME_COLORS) if codes is None else sorted(set(int(c) for c in codes))
    return ax.legend(handles=[Patch(color=OUTCOME_COLORS[c], label=Outcome(c).name.lower()) for c in codes], **kw)


def pb_plane(ax, p_lim: float, b_lim: float) -> None:
    """Shade the (p, b) plane by mode as Figs. 12 and 13: p > 0, b < 0 slipping; p > 0, b > 0 lift-off;
    p < 0, b < 0 inconsistent; p < 0, b > 0 indeterminate."""
    for (x0, y0), m in (
        ((0, -1), Mode.SLIP),
        ((0, 0), Mode.LIFTOFF),
        ((-1, -1), Mode.INCONSISTENT),
        ((-1, 0), Mode.INDETERMINATE),
    ):
        ax.add_patch(plt.Rectangle((x0 * p_lim, y0 * b_lim), p_lim, b_lim, color=MODE_COLORS[m], alpha=0.55, lw=0))
    ax.axhline(0, color="k", lw=0.5)
    ax.axvline(0, color="k", lw=0.5)
    ax.set_xlim(-p_lim, p_lim)
    ax.set_ylim(-b_lim, b_lim)
    ax.set_xlabel("p")
    ax.set_ylabel("b")


def pb_orbits(ax, p: np.ndarray, b: np.ndarray, orbit: np.ndarray, *, color: str = "0.35", radius: float = 1.5) -> None:
    """Draw orbits in the (p, b) plane (samples of each orbit in order, ``orbit`` its id), inside ``radius``, each with an
    arrow at its middle in the direction of its samples (increasing s)."""
    for j in np.unique(orbit):
        o = orbit == j
        x, y = p[o], b[o]
        keep = np.flatnonzero(np.hypot(x, y) < radius)
        ax.plot(x[keep], y[keep], color=color, lw=0.6)
        if keep.size > 3:
            m = keep[keep.size // 2]
            ax.annotate(
                "", xy=(x[m + 1], y[m + 1]), xytext=(x[m], y[m]), arrowprops=dict(arrowstyle="->", color=color, lw=0.6)
            )


def pb_eigenvectors(ax, e_plus, e_minus, colors: tuple, *, lw: float = 2.0) -> None:
    """Draw the eigen-directions e_+ and e_- through the origin of the (p, b) plane in ``colors`` (one per vector)."""
    for v, color in zip((e_plus, e_minus), colors):
        v = np.asarray(v, float)
        ax.plot([-v[0], v[0]], [-v[1], v[1]], color=color, lw=lw)


def strong_weak_colors(strong: str) -> tuple:
    """(colour of e_+, colour of e_-): blue for the strong eigenvector (larger |lambda|; ``strong`` "plus" or "minus"), red for the weak."""
    return (LINE_COLORS[0], LINE_COLORS[6]) if strong == "plus" else (LINE_COLORS[6], LINE_COLORS[0])


#: Artists with more drawn elements than this (a map's cells, a surface's facets) go into the SVG as one embedded image
#: at savefig.dpi: the vector copy of a 32 x 32 map's 1024 cells or a surface's facets costs more to write, and to open,
#: than the whole rest of the figure, and adds nothing a reader zooms for (axes, labels and lines stay vectors).
RASTER_ELEMENTS = 400


def _rasterize_heavy(fig) -> None:
    from matplotlib.collections import Collection
    from matplotlib.image import AxesImage

    for ax in fig.axes:
        for artist in ax.get_children():
            heavy = isinstance(artist, AxesImage) or (
                isinstance(artist, Collection) and len(artist.get_paths()) > RASTER_ELEMENTS
            )
            if heavy and not artist.get_rasterized():
                artist.set_rasterized(True)


def save_figure(fig, stem: Path) -> None:
    """Write ``<stem>.png`` and ``<stem>.svg`` and close ``fig``.

    The layout is computed once, for the PNG: the SVG keeps the positions it
    gave (constrained layout is most of a figure's drawing time), and heavy
    artists go into the SVG rasterised (``RASTER_ELEMENTS``).
    """
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    # The layout as savefig would compute it for the PNG (at its dpi: text is measured at the size it is drawn), then
    # no layout engine at all for either file.  savefig draws a figure that has an engine twice, once with its drawing
    # turned off to lay it out (the quick report's render took 13.7-14.4 s that way, 12.1-13.2 s this way, in turn);
    # set_layout_engine("none") would leave a placeholder engine that savefig counts as one.  The rc context keeps it off: savefig puts back the figure's
    # engine with set_layout_engine, which would make a new constrained one from the rc parameters.
    engine = fig.get_layout_engine()
    if engine is not None:
        shown, saved = fig.dpi, plt.rcParams["savefig.dpi"]
        fig.dpi = shown if saved == "figure" else saved
        try:
            engine.execute(fig)
        finally:
            fig.dpi = shown
    with plt.rc_context({"figure.constrained_layout.use": False, "figure.autolayout": False}):
        fig.set_layout_engine(None)
        # not with_suffix: a stem may contain a dot ("mu1.4")
        fig.savefig(stem.parent / f"{stem.name}.png", metadata={"Software": None})
        _rasterize_heavy(fig)
        fig.savefig(stem.parent / f"{stem.name}.svg", metadata={"Date": None, "Creator": None})
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
    return ax.imshow(
        np.ma.masked_less(idx, 0), origin="lower", extent=_extent(x, y), aspect="auto", cmap=cmap, norm=norm
    )


def mode_legend(ax, *, extra: list | None = None, **kw):
    """Legend of the four modes (and any extra handles)."""
    handles = [Patch(color=MODE_COLORS[m], label=m.name.lower()) for m in sorted(MODE_COLORS)]
    return ax.legend(handles=handles + (extra or []), **kw)
