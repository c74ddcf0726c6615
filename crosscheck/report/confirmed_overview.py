"""The causes confirmed on every engine in one figure, beside the engine table: where each engine's disagreements end up
once the engine itself is changed the way the ladder's cause names, and how that depends on the theory's own margins.

Derived at render time from the saved summaries of the engines' interventions sections
(``crosscheck.report.sections.engine_interventions``), like the engine table, so it is never older than they are.
Left: per engine, the shares of its attributed disagreements confirmed by their own cause's intervention (the ladder's
overdetermined pairs by both together apart), removed by another cause's instead, only jointly, by none.  Right: the
share confirmed against the start's distance to the theory's event boundary (the map sections' probe), one line per
engine, and the pooled share with its Wilson 95 % interval; without probed distances (the quick report) the right
panel splits by how close the theory's slip comes to p = 0 instead.
"""

from __future__ import annotations

import json
from pathlib import Path

__all__ = ["overview", "confirmed_block"]

#: Where the figure and its data go, under the report directory.
STEM, DATA = Path("figures") / "overview" / "causes_confirmed", Path("data") / "causes_confirmed.json"


def overview(data: Path) -> list[dict]:
    """Per engine with attributed disagreements: its counts from ``<slug>_interventions/summary.json`` (engine order of
    the files' names)."""
    from crosscheck.engines.spec import LADDER_CAUSES
    from crosscheck.report.format import engine_label
    from crosscheck.report.sections.engine_interventions import other_starts, pairs_confirmed

    rows = []
    for path in sorted(Path(data).glob("*_interventions/summary.json")):
        s = json.loads(path.read_text())
        if not s.get("attributed"):
            continue
        per = [r for c, r in s["per_cause"].items() if c in LADDER_CAUSES]  # the attributed ones only
        pairs = sum(pairs_confirmed(r) for r in per)
        other = sum(other_starts(r) for r in per)
        rows.append(
            {
                "engine": s["engine"],
                "label": engine_label(s["engine"]),
                "section": path.parent.name,
                "attributed": s["attributed"],
                "confirmed": s["confirmed"] - pairs,
                "pairs": pairs,
                "other": other,
                "jointly": sum(sum(r["jointly"].values()) for r in per),
                "none": sum(r["none"] for r in per),
                "no_intervention": sum(r.get("no_intervention", 0) for r in per),
                "by_distance": s.get("by_distance") or [],
                "by_p": s.get("by_p"),
            }
        )
    return rows


def _figure(rows: list[dict]):
    import matplotlib.pyplot as plt
    import numpy as np

    from crosscheck.sweeps.store_diff import wilson_interval

    fig, (left, right) = plt.subplots(
        1,
        2,
        figsize=(11.0, 0.9 + 0.42 * max(len(rows), 5)),
        layout="constrained",
        gridspec_kw={"width_ratios": (1.25, 1.0)},
    )
    parts = (
        ("confirmed by its own cause's intervention", "confirmed", "#2a9d4b"),
        ("overdetermined pair, by both together", "pairs", "#8fd19e"),
        ("removed by another cause's instead", "other", "#e9a23b"),
        ("only jointly (no pair named)", "jointly", "#6c8ebf"),
        ("removed by none", "none", "#c0392b"),
    )
    names = [f"{r['label']} ({r['attributed']})" for r in rows]
    start = np.zeros(len(rows))
    for label, key, colour in parts:
        share = np.array([r[key] / r["attributed"] for r in rows])
        left.barh(names, share, left=start, color=colour, label=label)
        start += share
    left.axvline(0.8, color="0.2", lw=0.8, ls="--")
    left.invert_yaxis()
    left.set_xlim(0, 1)
    left.set_xlabel("share of the engine's attributed disagreements")
    left.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, fontsize=7.5, frameon=False)
    ticks, counts, xlabel = _bins(rows)
    x = np.arange(len(ticks))
    for j, (r, kn) in enumerate(
        zip(rows, counts)
    ):  # each engine's share as a dot, its area the disagreements behind it (few for Drake)
        n = np.array([n for _, n in kn])
        y = np.array([k / n if n else np.nan for k, n in kn])
        right.scatter(x + 0.05 * (j - (len(rows) - 1) / 2), y, s=6 + 4 * n, alpha=0.55, label=r["label"])
    pooled = [(i, sum(kn[i][0] for kn in counts), sum(kn[i][1] for kn in counts)) for i in range(len(ticks))]
    pooled = [(i, k, n) for i, k, n in pooled if n]
    if pooled:
        at, k, n = (np.array(c) for c in zip(*pooled))
        lo_hi = np.array([wilson_interval(a, b) for a, b in zip(k, n)])
        share = k / n
        right.errorbar(
            at,
            share,
            yerr=np.clip(
                [share - lo_hi[:, 0], lo_hi[:, 1] - share], 0.0, None
            ),  # a share of 0 or 1 is its bound: -1e-17
            color="k",
            lw=2,
            capsize=3,
            label="all engines (95 %)",
        )
    right.set_xticks(x, ticks)
    right.set_xlim(-0.5, len(ticks) - 0.5)
    right.set_xlabel(xlabel)
    right.axhline(0.8, color="0.2", lw=0.8, ls="--")
    right.set_ylim(0, 1.02)
    right.set_ylabel("share confirmed")
    right.legend(fontsize=7, frameon=False, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, markerscale=0.6)
    return fig


def _bins(rows: list[dict]) -> tuple[list[str], list[list[tuple[int, int]]], str]:
    """(tick labels, per engine the (confirmed, attributed) of each bin, axis label): by boundary distance where any engine
    has probed distances, else by the theory slip's closest approach to p = 0."""
    if any(r["by_distance"] for r in rows):
        keys = sorted({float(b["distance"]) for r in rows for b in r["by_distance"]})
        got = [{float(b["distance"]): (b["confirmed"], b["attributed"]) for b in r["by_distance"]} for r in rows]
        return (
            [("beyond" if k == float("inf") else f"{k:g}") for k in keys],
            [[g.get(k, (0, 0)) for k in keys] for g in got],
            "distance to the theory's event boundary (probe radius)",
        )
    band = next((r["by_p"]["p_band"] for r in rows if r["by_p"]), 0.2)
    sides = ("in_band", "above")
    return (
        [f"enters p <= {band:g}", f"keeps p > {band:g}"],
        [
            [(r["by_p"][s]["confirmed"], r["by_p"][s]["attributed"]) if r["by_p"] else (0, 0) for s in sides]
            for r in rows
        ],
        "the theory's slip (no boundary distances probed)",
    )


def confirmed_block(out: Path):
    """The figure as a report block (a ``Figure``), its data written to ``data/causes_confirmed.json``; None when fewer
    than two engines have attributed disagreements."""
    from crosscheck.report.plotting import save_figure
    from crosscheck.report.section import Figure

    out = Path(out)
    rows = overview(out / "data")
    if len(rows) < 2:
        return None
    (out / DATA).write_text(json.dumps(rows, indent=1, default=str) + "\n")
    save_figure(_figure(rows), out / STEM)
    n, k = sum(r["attributed"] for r in rows), sum(r["confirmed"] + r["pairs"] for r in rows)
    return Figure(
        stem=str(STEM),
        data=[str(DATA)],
        caption=f"Causes confirmed on the engines themselves: {k} of {n} attributed disagreements over {len(rows)} engines. Left: "
        "per engine (attributed disagreements in brackets), the shares removed by their own cause's intervention, "
        "by the two interventions of an overdetermined pair the ladder named, by another cause's instead, only "
        "jointly with another cause's, or by none; the dashed line is the 80 % goal. Right: the share confirmed "
        "where the theory's own outcome is close to turning and where it is not, per engine and pooled.",
    )
