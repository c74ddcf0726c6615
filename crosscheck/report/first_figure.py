"""The report's first figure: every engine's agreement with the theory against its cost, at every setting it ran.

Left (ann-benchmarks' recall against queries per second): agreement with its Wilson 95 % interval against runs per
second, one colour and one line per engine through its convergence settings, its map setting a large open marker, the
Pareto frontier over every point dashed.  Middle (a work-precision diagram in SciML's sense): the same settings, the
median |event time - theory's| against runs per second.  Right: what each engine does at its map setting where the
theory jams, and how often it throws the rod off the plane while b < 0 (LAUNCH).  Drawn from the engine table's
records (``crosscheck.report.engine_table``) alone; its data, numbers only, in ``data/first_figure.json``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from matplotlib.patches import Patch

from crosscheck.report.plotting import plt, save_figure
from crosscheck.report.section import Figure

__all__ = ["figure_block", "pareto", "STEM", "DATA"]

#: Where the figure and its data go, under the report directory.
STEM, DATA = Path("figures") / "overview" / "agreement_cost", Path("data") / "first_figure.json"

_FIELDS = (
    "engine", "label", "rigid", "role", "setting", "timestep", "n_rated", "n_agree", "agreement", "ci_low", "ci_high",
    "runs_per_s", "us_per_step", "median_abs_event_time_error", "n_launch", "n_theory_jam", "agree_theory_jam",
)  # fmt: skip


#: One colour per engine, registry order: tab10 without its red (LAUNCH's) and grey (the frontier's), then tab20b's dark
#: shades and Dark2's teal, magenta and mustard: 16 distinct colours, so the 15 registered engines share none.
_PALETTE = (
    [plt.get_cmap("tab10")(i) for i in (0, 1, 2, 4, 5, 6, 8, 9)]
    + [plt.get_cmap("tab20b")(i) for i in (0, 4, 8, 12, 16)]
    + [plt.get_cmap("Dark2")(i) for i in (0, 3, 5)]
)


def pareto(points: list[tuple[float, float]]) -> list[bool]:
    """Which of ``points`` (x, y), both better when larger, no other point beats in both (ties kept)."""
    finite = [all(math.isfinite(v) for v in p) for p in points]
    return [
        f and not any(g and q[0] >= p[0] and q[1] >= p[1] and q != p for q, g in zip(points, finite))
        for p, f in zip(points, finite)
    ]


def _points(records: list[dict]) -> list[dict]:
    pts = [{k: r.get(k) for k in _FIELDS} for r in records if r["n_rated"]]
    front = pareto([(p["runs_per_s"], p["agreement"]) for p in pts])
    err = [p["median_abs_event_time_error"] for p in pts]
    front_wp = pareto([(p["runs_per_s"], -e if e is not None else math.nan) for p, e in zip(pts, err)])
    for p, a, b in zip(pts, front, front_wp):
        p["pareto_agreement_cost"], p["pareto_error_cost"] = a, b
    return pts


def _frontier(ax, pts: list[dict], x: str, y: str, key: str) -> None:
    on = sorted((p for p in pts if p[key]), key=lambda p: p[x])
    if on:
        ax.plot(
            [p[x] for p in on],
            [p[y] for p in on],
            ls="--",
            c="0.35",
            lw=2.2,
            alpha=0.6,
            label="Pareto frontier",
            zorder=1,
        )


def _engine_lines(axes, pts: list[dict], colors: dict) -> None:
    left, mid = axes
    for name, color in colors.items():
        conv = sorted(
            (p for p in pts if p["engine"] == name and p["role"] == "convergence"), key=lambda p: p["runs_per_s"]
        )
        for p in (p for p in pts if p["engine"] == name):
            big = p["role"] == "map"
            style = dict(marker="D" if big else "o", ms=9 if big else 4.5, mfc="none" if big else color, mec=color,
                         mew=1.8 if big else 1, c=color, zorder=4 if big else 3)  # fmt: skip
            lo, hi = max(0.0, p["agreement"] - p["ci_low"]), max(0.0, p["ci_high"] - p["agreement"])
            left.errorbar([p["runs_per_s"]], [p["agreement"]], yerr=[[lo], [hi]], elinewidth=0.8, capsize=2, **style)
            if p["median_abs_event_time_error"] is not None:
                mid.plot([p["median_abs_event_time_error"]], [p["runs_per_s"]], ls="none", **style)
        if conv:
            left.plot([p["runs_per_s"] for p in conv], [p["agreement"] for p in conv], c=color, lw=1.2, zorder=2)
            wp = [p for p in conv if p["median_abs_event_time_error"] is not None]
            mid.plot([p["median_abs_event_time_error"] for p in wp], [p["runs_per_s"] for p in wp], c=color, lw=1.2)


def _jams_and_launch(ax, pts: list[dict], colors: dict) -> None:
    maps = [p for p in pts if p["role"] == "map"][::-1]
    y = range(len(maps))
    jam = [p["agree_theory_jam"] / p["n_theory_jam"] if p["n_theory_jam"] else 0 for p in maps]
    launch = [p["n_launch"] / p["n_rated"] for p in maps]
    ax.barh([i + 0.2 for i in y], jam, height=0.38, color=[colors[p["engine"]] for p in maps])
    ax.barh([i - 0.2 for i in y], launch, height=0.38, color="#c00", hatch="///", ec="w")
    ax.set_ylim(-0.7, len(maps) - 0.3)
    for i, p, j, la in zip(y, maps, jam, launch):
        ax.text(j + 0.02, i + 0.2, f"{p['agree_theory_jam']}/{p['n_theory_jam']}", va="center", fontsize=7)
        if p["n_launch"]:
            ax.text(la + 0.02, i - 0.2, f"{p['n_launch']}/{p['n_rated']}", va="center", fontsize=7, color="#a00")
    ax.set_yticks(list(y), [p["label"] + (" (rigid)" if p["rigid"] else "") for p in maps])
    for tick, p in zip(ax.get_yticklabels(), maps):
        tick.set_color(colors[p["engine"]])
    ax.set_xlim(0, 1.3)
    ax.set_xticks([0, 0.5, 1], ["0", "50 %", "100 %"])
    ax.set_title("map setting: at the theory's jams; LAUNCH")
    handles = [Patch(color="0.55", label="jams where the theory jams (engine's colour)"),
               Patch(facecolor="#c00", hatch="///", ec="w", label="LAUNCH (b < 0)")]  # fmt: skip
    ax.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.06), ncol=2, fontsize=7, frameon=False)


def _draw(pts: list[dict]):
    colors = {n: _PALETTE[i % len(_PALETTE)] for i, n in enumerate(dict.fromkeys(p["engine"] for p in pts))}
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.7), width_ratios=[1.25, 1.0, 0.9])
    left, mid, right = axes
    _engine_lines((left, mid), pts, colors)
    _frontier(left, pts, "runs_per_s", "agreement", "pareto_agreement_cost")
    wp = [p for p in pts if p["median_abs_event_time_error"] is not None]
    _frontier(mid, [{**p, "x": p["median_abs_event_time_error"]} for p in wp], "x", "runs_per_s", "pareto_error_cost")
    left.set(xscale="log", xlabel="runs per second (one core; log)", ylabel="agreement with the theory (95 % interval)")
    left.set_ylim(0, 1.02)
    left.set_title("agreement against cost\n(◇ map setting, ● convergence)")
    left.axhspan(0.95, 1.02, color="#d4f4d4", zorder=0, lw=0)
    left.legend(loc="lower left", fontsize=7, frameon=False)
    mid.set(xscale="log", yscale="log", xlabel="median |event time - theory's| (scaled time; log)",
            ylabel="runs per second (log)", title="work-precision:\nevent-time error against cost")  # fmt: skip
    _jams_and_launch(right, pts, colors)
    return fig


def figure_block(out: Path, records: list[dict]) -> Figure | None:
    """The figure as a report block, its data written to ``data/first_figure.json``; None without an engine."""
    pts = _points(records)
    if not pts:
        return None
    out = Path(out)
    clean = [{k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in p.items()} for p in pts]
    (out / DATA).write_text(json.dumps({"points": clean}, indent=1) + "\n")
    save_figure(_draw(pts), out / STEM)
    n = len({p["engine"] for p in pts})
    return Figure(
        stem=str(STEM),
        data=[str(DATA)],
        caption=f"Every engine ({n}) at every setting the report ran. Left: agreement with the theory's first event "
        "(Wilson 95 % interval; green: the >= 95 % band of the verdict agrees) against runs per second; the open "
        "diamond is the outcome maps' setting on their grid, the dots and line the convergence settings on the "
        "convergence grid; dashed: the Pareto frontier. Middle: the median event-time error of the agreeing starts "
        "against the same cost (SciML's work-precision diagram). Right: at the map setting, the share of the "
        "theory's jams the engine jams at, and the share of starts it LAUNCHes (thrown off the plane while b < 0).",
    )
