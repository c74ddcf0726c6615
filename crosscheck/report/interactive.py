"""Interactive outcome maps: one self-contained HTML page of inline SVG grids whose cells tell their start on hover.

No script and no network: each cell is an SVG ``<rect>`` with a ``<title>``
(the browser's own tooltip), so the page opens from disk, offline, in any
browser, and stays readable as text.  Used by the outcome-map sections
(``crosscheck.report.sections.engine_maps``) beside their PNG maps.
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["Panel", "GridMap", "outcome_maps_page", "write_page", "start_tooltip", "engine_line"]


@dataclass
class Panel:
    """One map panel: ``codes`` (ny, nx) of small integer codes (NaN: no start there), drawn in ``GridMap.colors``."""

    title: str
    codes: np.ndarray


@dataclass
class GridMap:
    """Panels over one grid: x (nx,) and y (ny,) cell centres named ``x_name``, ``y_name``; ``tooltips`` (ny, nx) text per cell."""

    title: str
    x_name: str
    y_name: str
    x: np.ndarray
    y: np.ndarray
    panels: list[Panel]
    tooltips: list[list[str]]
    note: str = ""
    extra: dict = field(default_factory=dict)


def _rgb(c) -> str:
    r, g, b = (int(round(255 * float(v))) for v in tuple(c)[:3])
    return f"rgb({r},{g},{b})"


def _svg_panel(m: GridMap, p: Panel, colors: dict[int, tuple], *, cell: float) -> str:
    nx, ny = m.x.size, m.y.size
    left, bottom, top = 62.0, 36.0, 20.0  # left: room for the tick labels and, apart from them, the rotated axis name
    w, h = left + nx * cell + 8, top + ny * cell + bottom
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0f}" height="{h:.0f}" viewBox="0 0 {w:.0f} {h:.0f}" role="img">',
        f'<text x="{left + nx * cell / 2:.1f}" y="14" text-anchor="middle" class="pt">{html.escape(p.title)}</text>',
    ]
    for j in range(ny):
        yy = top + (ny - 1 - j) * cell  # y grows upwards as in the PNG maps
        for i in range(nx):
            v = p.codes[j, i]
            if not np.isfinite(v):
                continue
            fill = _rgb(colors.get(int(v), (1, 1, 1)))
            out.append(
                f'<rect x="{left + i * cell:.1f}" y="{yy:.1f}" width="{cell:.2f}" height="{cell:.2f}" fill="{fill}">'
                f"<title>{html.escape(m.tooltips[j][i])}</title></rect>"
            )
    out.append(
        f'<rect x="{left}" y="{top}" width="{nx * cell:.1f}" height="{ny * cell:.1f}" fill="none" stroke="#444" stroke-width="0.8"/>'
    )
    for pos, label in _ticks(m.x):  # pos: in cells from the left edge
        out.append(
            f'<line x1="{left + pos * cell:.1f}" x2="{left + pos * cell:.1f}" y1="{top + ny * cell:.1f}" y2="{top + ny * cell + 3:.1f}" stroke="#444"/>'
        )
        out.append(
            f'<text x="{left + pos * cell:.1f}" y="{top + ny * cell + 14:.1f}" text-anchor="middle" class="tk">{label}</text>'
        )
    for pos, label in _ticks(m.y):  # pos: in cells from the bottom edge
        out.append(
            f'<line x1="{left - 3:.1f}" x2="{left:.1f}" y1="{top + (ny - pos) * cell:.1f}" y2="{top + (ny - pos) * cell:.1f}" stroke="#444"/>'
        )
        out.append(
            f'<text x="{left - 5:.1f}" y="{top + (ny - pos) * cell + 3:.1f}" text-anchor="end" class="tk">{label}</text>'
        )
    out.append(
        f'<text x="{left + nx * cell / 2:.1f}" y="{h - 4:.1f}" text-anchor="middle" class="ax">{html.escape(m.x_name)}</text>'
    )
    out.append(
        f'<text x="12" y="{top + ny * cell / 2:.1f}" text-anchor="middle" class="ax" transform="rotate(-90 12 {top + ny * cell / 2:.1f})">'
        f"{html.escape(m.y_name)}</text>"
    )
    out.append("</svg>")
    return "".join(out)


def _ticks(centres: np.ndarray, n: int = 5) -> list[tuple[float, str]]:
    """Round tick values on an axis of grid cells: (position in cells from the first cell's outer edge, label).

    A uniform grid gets the values ``matplotlib.ticker.MaxNLocator`` picks inside its extent (cell edges), placed where
    they fall; a single cell or an irregular grid gets labelled cell centres, rounded to 3 digits."""
    from matplotlib.ticker import MaxNLocator

    c = np.asarray(centres, dtype=float)
    if c.size > 1 and np.allclose(np.diff(c), c[1] - c[0], rtol=1e-6, atol=0):
        d = c[1] - c[0]
        lo, hi = sorted((c[0] - d / 2, c[-1] + d / 2))
        vals = [
            v for v in MaxNLocator(n, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi) if lo - 1e-12 <= v <= hi + 1e-12
        ]
        return [((v - (c[0] - d / 2)) / d, f"{v:.6g}" if abs(v) > 1e-12 * abs(hi - lo) else "0") for v in vals]
    idx = np.unique(np.linspace(0, c.size - 1, min(c.size, n)).round().astype(int))
    return [(k + 0.5, f"{c[k]:.3g}") for k in idx]


_CSS = (
    "body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:1.5em;color:#222}"
    "h1{font-size:1.3em}h2{font-size:1.1em;margin-top:1.6em}.row{display:flex;flex-wrap:wrap;gap:.8em}"
    "svg .pt{font-size:12px;font-weight:600}svg .tk{font-size:10px;fill:#333}svg .ax{font-size:12px;font-style:italic}"
    "svg rect[fill]:hover{stroke:#000;stroke-width:1.5}.legend span{display:inline-block;margin-right:1.2em;font-size:.9em}"
    ".legend i{display:inline-block;width:.9em;height:.9em;margin-right:.3em;vertical-align:-.1em;border:1px solid #777}p{max-width:70em}"
)


def outcome_maps_page(
    title: str, maps: list[GridMap], *, colors: dict[int, tuple], names: dict[int, str], intro: str = ""
) -> str:
    """The whole page: a legend of ``names`` in ``colors`` and, for each map, its panels side by side at one cell size."""
    legend = "".join(f'<span><i style="background:{_rgb(colors[k])}"></i>{html.escape(names[k])}</span>' for k in names)
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(title)}</title>",
        f"<style>{_CSS}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f"<p>{html.escape(intro)}</p>" if intro else "",
        f'<p class="legend">{legend}</p>',
    ]
    for m in maps:
        cell = float(np.clip(330.0 / max(m.x.size, m.y.size), 6.0, 34.0))
        parts.append(f"<h2>{html.escape(m.title)}</h2>")
        if m.note:
            parts.append(f"<p>{html.escape(m.note)}</p>")
        parts.append('<div class="row">' + "".join(_svg_panel(m, p, colors, cell=cell) for p in m.panels) + "</div>")
    parts.append("</body></html>")
    return "\n".join(x for x in parts if x) + "\n"


def write_page(path: Path | str, text: str) -> Path:
    """Write the page (UTF-8), creating its directory."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def _outcome(code) -> str:
    from crosscheck.report.outcomes import OUTCOME_NAMES

    c = int(code)
    return OUTCOME_NAMES[c].lower() if 0 <= c < len(OUTCOME_NAMES) else "not compared"


def _t(v) -> str:
    return "" if not np.isfinite(v) else f" at t = {v:.4g}"


def start_tooltip(t: dict, k: int) -> str:
    """The start of row ``k`` of an events table (``mujoco_maps``: theta ... eta, b0, p0, analytic_*): its state and analytic first event.

    Scaled units of the paper (theta, varphi in rad; Theta, Psi rates; t scaled time).
    """
    state = ", ".join(f"{n} = {float(t[n][k]):.4g}" for n in ("theta", "varphi", "Theta", "Psi", "mu", "eta"))
    lines = [state, f"b = {float(t['b0'][k]):.3g}, p = {float(t['p0'][k]):.3g}"]
    if int(t["slipping"][k]) != 1:
        lines.append("not slipping at t = 0 (b >= 0 or p <= 0): not compared")
        return "\n".join(lines)
    reason = str(t["analytic_reason"][k])
    lines.append(
        f"analytic: {_outcome(t['analytic_outcome'][k])}{_t(float(t['analytic_time'][k]))}"
        + (f" ({reason})" if reason and reason != "nan" else "")
        + f"; compared up to t = {float(t['comparison_time'][k]):.4g}"
    )
    return "\n".join(lines)


def engine_line(t: dict, k: int, column: str, name: str) -> str:
    """``name``: the engine's outcome (column ``column``) and event time (``column``_time) at row ``k``."""
    if int(t["slipping"][k]) != 1:
        return f"{name}: not compared"
    return f"{name}: {_outcome(t[column][k])}{_t(float(t[column + '_time'][k]))}"
