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
    left, bottom, top = 46.0, 34.0, 20.0
    w, h = left + nx * cell + 8, top + ny * cell + bottom
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0f}" height="{h:.0f}" viewBox="0 0 {w:.0f} {h:.0f}" role="img">',
           f'<text x="{left + nx * cell / 2:.1f}" y="14" text-anchor="middle" class="pt">{html.escape(p.title)}</text>']
    for j in range(ny):
        yy = top + (ny - 1 - j) * cell  # y grows upwards as in the PNG maps
        for i in range(nx):
            v = p.codes[j, i]
            if not np.isfinite(v):
                continue
            fill = _rgb(colors.get(int(v), (1, 1, 1)))
            out.append(f'<rect x="{left + i * cell:.1f}" y="{yy:.1f}" width="{cell:.2f}" height="{cell:.2f}" fill="{fill}">'
                       f"<title>{html.escape(m.tooltips[j][i])}</title></rect>")
    out.append(f'<rect x="{left}" y="{top}" width="{nx * cell:.1f}" height="{ny * cell:.1f}" fill="none" stroke="#444" stroke-width="0.8"/>')
    for k in np.unique(np.linspace(0, nx - 1, min(nx, 5)).round().astype(int)):
        out.append(f'<text x="{left + (k + 0.5) * cell:.1f}" y="{top + ny * cell + 13:.1f}" text-anchor="middle" class="tk">{m.x[k]:.3g}</text>')
    for k in np.unique(np.linspace(0, ny - 1, min(ny, 5)).round().astype(int)):
        out.append(f'<text x="{left - 4:.1f}" y="{top + (ny - 1 - k + 0.5) * cell + 3:.1f}" text-anchor="end" class="tk">{m.y[k]:.3g}</text>')
    out.append(f'<text x="{left + nx * cell / 2:.1f}" y="{h - 4:.1f}" text-anchor="middle" class="ax">{html.escape(m.x_name)}</text>')
    out.append(f'<text x="12" y="{top + ny * cell / 2:.1f}" text-anchor="middle" class="ax" transform="rotate(-90 12 {top + ny * cell / 2:.1f})">'
               f"{html.escape(m.y_name)}</text>")
    out.append("</svg>")
    return "".join(out)


_CSS = ("body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:1.5em;color:#222}"
        "h1{font-size:1.3em}h2{font-size:1.1em;margin-top:1.6em}.row{display:flex;flex-wrap:wrap;gap:.8em}"
        "svg .pt{font-size:12px;font-weight:600}svg .tk{font-size:10px;fill:#333}svg .ax{font-size:12px;font-style:italic}"
        "svg rect[fill]:hover{stroke:#000;stroke-width:1.5}.legend span{display:inline-block;margin-right:1.2em;font-size:.9em}"
        ".legend i{display:inline-block;width:.9em;height:.9em;margin-right:.3em;vertical-align:-.1em;border:1px solid #777}p{max-width:70em}")


def outcome_maps_page(title: str, maps: list[GridMap], *, colors: dict[int, tuple], names: dict[int, str], intro: str = "") -> str:
    """The whole page: a legend of ``names`` in ``colors`` and, for each map, its panels side by side at one cell size."""
    legend = "".join(f'<span><i style="background:{_rgb(colors[k])}"></i>{html.escape(names[k])}</span>' for k in names)
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">', f"<title>{html.escape(title)}</title>", f"<style>{_CSS}</style></head><body>",
             f"<h1>{html.escape(title)}</h1>", f"<p>{html.escape(intro)}</p>" if intro else "", f'<p class="legend">{legend}</p>']
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
    lines.append(f"analytic: {_outcome(t['analytic_outcome'][k])}{_t(float(t['analytic_time'][k]))}" + (f" ({reason})" if reason and reason != "nan" else "")
                 + f"; compared up to t = {float(t['comparison_time'][k]):.4g}")
    return "\n".join(lines)


def engine_line(t: dict, k: int, column: str, name: str) -> str:
    """``name``: the engine's outcome (column ``column``) and event time (``column``_time) at row ``k``."""
    if int(t["slipping"][k]) != 1:
        return f"{name}: not compared"
    return f"{name}: {_outcome(t[column][k])}{_t(float(t[column + '_time'][k]))}"
