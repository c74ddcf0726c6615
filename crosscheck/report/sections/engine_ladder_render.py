"""An engine's ladder section drawn: its causes, detours and reruns, each map coloured by cause, IC2 through the rungs.

Renders what ``crosscheck.report.sections.engine_ladder`` saved (``summary``,
``ladders``, ``causes_<map>``, ``cause_maps``, ``ic2``) without running anything.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, Table, Text

__all__ = ["render", "cause_codes", "CAUSE_COLORS", "NOT_SLIPPING", "AGREE", "NOT_RUN"]

#: Map code of a start that does not slip at t = 0 (as ``engine_maps``), of a rated start that agrees, and of a
#: disagreement the section did not ladder.
NOT_SLIPPING, AGREE, NOT_RUN = -2, -3, -4


def cause_codes() -> dict:
    """Integer code of each cause (``crosscheck.studies.ladder.CAUSES``, in order): the cause maps' CSV column."""
    from crosscheck.studies.ladder import CAUSES

    return {c: i for i, c in enumerate(CAUSES)}


#: The maps' colours of the causes (and of the three codes above); every one used appears in the legend.
CAUSE_COLORS = {
    "geometry": (0.12, 0.47, 0.71),
    "compliance": (1.0, 0.5, 0.05),
    "friction law": (0.17, 0.63, 0.17),
    "feed-forward": (0.55, 0.34, 0.29),
    "discretisation": (0.58, 0.4, 0.74),
    "relaxation": (0.09, 0.75, 0.81),
    "pyramid cone": (0.89, 0.47, 0.76),
    "friction bound": (0.74, 0.74, 0.13),
    "position projection": (0.1, 0.2, 0.5),
    "float32": (1.0, 0.8, 0.2),
    "unexplained": (0.84, 0.15, 0.16),
    "undetermined": (0.5, 0.5, 0.5),
    "agree": (0.96, 0.96, 0.96),
    "not rated": (0.75, 0.75, 0.6),
}


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.studies.ladder import CAUSES

    name = engine_label(ctx.params["ladder_engine"])
    summary, ladders = ctx.store.read_json("summary"), ctx.store.read_json("ladders")
    rows = [[c, str(summary["counts"][c])] for c in CAUSES if summary["counts"].get(c)]
    blocks = [
        Table(
            caption=f"{name}: causes of {summary['n_disagree']} of the {summary['n_disagreements_on_maps']} disagreements on its maps "
            f"(the first rung of the final stretch whose outcomes, compared as the agreement study compares, equal {name}'s).",
            header=["cause", "starts"],
            rows=rows or [["(no disagreement on the maps)", "0"]],
            data=ctx.data("summary.json"),
        )
    ]
    if ladders:
        blocks += [_detail(ctx, ladders), _detours(ctx, summary, ladders, name), _reruns(summary)]
    blocks += [_cause_map(ctx, m, name) for m in ctx.store.read_json("cause_maps")]
    blocks += _ic2(ctx, name)
    return blocks


def _detail(ctx: RenderContext, ladders: list) -> Table:
    """Each laddered start: its map, start, mu, each rung's label as compared, and the cause."""
    rung_names = [r["name"] for r in ladders[0]["rungs"]]
    detail = []
    for ld in ladders:
        s = ld["state"]
        detail.append(
            [
                ld["map"],
                f"theta {s['theta']:.3g}, varphi {s['varphi']:.3g}, Theta {s['Theta']:.3g}, Psi {s['Psi']:.3g}, eta {s['eta']:.3g}",
                f"{ld['mu']:.3g}",
                *[(r["label"] or r["status"]).lower() for r in ld["rungs"]],
                ld["cause"],
            ]
        )
    return Table(
        caption="Each laddered start: its map, start, mu, each rung's outcome as compared, and the cause. Rungs: "
        + ", ".join(f"{r['name']} ({r['cause'] or 'the theory'})" for r in ladders[0]["rungs"])
        + ".",
        header=["map", "start", "mu", *rung_names, "cause"],
        rows=detail,
        data=ctx.data("ladders.json"),
    )


def _detours(ctx: RenderContext, summary: dict, ladders: list, name: str) -> Table:
    """The detours per cause named and per cause of the rung that ends them."""
    from crosscheck.studies.ladder import CAUSES

    det, n = summary["detours"], summary["n_disagree"]
    ends = [c for c in (*CAUSES, "none") if det["ended_by"].get(c)]
    named = [c for c in CAUSES if summary["counts"].get(c)]
    ended = [(ld["cause"], ld["detour_ended_by"] or "none") for ld in ladders if ld["detour"]]
    rows = [[c] + [str(ended.count((c, e))) for e in ends] for c in named]
    return Table(
        caption=f"Detours: {det['n']} of {n} ladders pass through an outcome that is neither the theory's nor {name}'s (a "
        f"ladder without one is monotone: each rung keeps the theory's outcome or takes {name}'s). Per cause named "
        "(rows), the cause of the rung that ends the detour (columns; 'none': no later rung does).",
        header=["cause \\ detour ended by", *ends],
        rows=rows if ends else [["no detour"]],
        data=ctx.data("summary.json", "ladders.json"),
    )


def _reruns(summary: dict) -> Text:
    n, rerun, rounding = summary["n_disagree"], summary["reference_mismatch"], summary["rounding_decided"]
    return Text(
        "The last rung is the engine itself at the same options, rerun to the comparison time plus the lag, so it "
        f"reproduces the maps' label whenever the rerun is faithful ({rerun} of {n} did not; of those, {rounding} give "
        "the maps' label 1-2 units in the last place of theta away: the outcome is decided by the start's last bits "
        "there, which the maps' array-built starts and the ladder's one-by-one starts round differently)."
    )


def _cause_map(ctx: RenderContext, m: dict, name: str):
    """One map of the engine's maps, each cell coloured by its ladder's cause."""
    from matplotlib.patches import Patch

    from crosscheck.report.plotting import categorical_image, plt
    from crosscheck.studies.ladder import CAUSES

    e = ctx.store.read_table(f"causes_{m['name']}")
    x, y = cell_centres(*m["x_range"], m["n"]), cell_centres(*m["y_range"], m["n"])
    xi = np.abs(e[m["x"]][:, None] - x[None, :]).argmin(axis=1)
    yi = np.abs(e[m["y"]][:, None] - y[None, :]).argmin(axis=1)
    img = np.full((y.size, x.size), np.nan)
    img[yi, xi] = e["code"]
    codes = cause_codes()
    colors = {codes[c]: CAUSE_COLORS[c] for c in CAUSES}
    colors.update({NOT_SLIPPING: (0.8, 0.8, 0.8), AGREE: (0.96, 0.96, 0.96), NOT_RUN: (0.3, 0.3, 0.3)})
    names = {codes[c]: c for c in CAUSES}
    names.update(
        {
            NOT_SLIPPING: "not slipping at t = 0 (not compared)",
            AGREE: f"{name} agrees with the theory",
            NOT_RUN: "disagrees, not laddered",
        }
    )
    fig, ax = plt.subplots(figsize=(5.2, 4.4), layout="constrained")
    categorical_image(ax, x, y, img, colors)
    ax.set_xlabel(f"$\\{m['x']}$")
    ax.set_ylabel(f"$\\{m['y']}$")
    used = sorted({int(c) for c in e["code"]})
    fig.legend(
        handles=[Patch(color=colors[c], label=names[c]) for c in used],
        loc="outside right center",
        fontsize=7,
        frameon=False,
    )
    fixed = ", ".join(f"{k} = {v:g}" for k, v in m["fixed"].items())
    laddered = int(np.sum(e["code"] >= 0))
    return ctx.figure(
        f"causes_{m['name']}",
        fig,
        f"Cause of each {name}-theory disagreement over ({m['x']}, {m['y']}) at {fixed}: "
        f"{laddered} laddered disagreements on this map.",
        [f"causes_{m['name']}.csv", "cause_maps.json"],
    )


def _ic2(ctx: RenderContext, name: str) -> list:
    """IC2 of Fig. 20 through every rung: a bar per rung to its first event (``plot_ladder``), and a table."""
    from crosscheck.outcome import Outcome
    from crosscheck.report.trajectory_plot import plot_ladder

    ic2, P = ctx.store.read_json("ic2"), ctx.params
    rungs = [
        SimpleNamespace(
            **{
                **r,
                "time": math.nan if r["time"] is None else r["time"],
                "outcome": None if r["outcome"] is None else Outcome[r["outcome"]],
                "label": None if r["label"] is None else Outcome[r["label"]],
            }
        )
        for r in ic2["rungs"]
    ]
    ladder = SimpleNamespace(rungs=rungs, until=ic2["comparison_time"], lag=ic2["lag"], cause=ic2["cause"])
    st = P["ic2"]
    fig = plot_ladder(ladder, title=f"{name}: IC2 through its ladder, cause {ic2['cause']}")
    caption = (
        f"IC2 of Fig. 20 (theta {st['theta']:g}, varphi {st['varphi']:g}, Theta {st['Theta']:g}, Psi {st['Psi']:g}, "
        f"eta {st['eta']:g}, mu {P['ic2_mu']:g}) through {name}'s ladder: each rung's first event, compared up to "
        f"t = {ic2['comparison_time'] + ic2['lag']:.4g}; cause {ic2['cause']}."
    )
    table = Table(
        caption="IC2 through the ladder (labels as the agreement study compares them).",
        header=["rung", "model", "cause", "status", "outcome", "t", "label"],
        rows=[
            [
                str(r.rung),
                r.name,
                r.cause or "the theory",
                r.status,
                r.outcome.name if r.outcome is not None else "-",
                "-" if not math.isfinite(r.time) else f"{r.time:.5g}",
                r.label.name if r.label is not None else "-",
            ]
            for r in rungs
        ],
        data=ctx.data("ic2.json"),
    )
    return [ctx.figure("ic2_rungs", fig, caption, ["ic2.json"]), table]
