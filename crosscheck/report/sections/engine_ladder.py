"""An engine's ladder: the disagreements of its outcome maps through the models between it and the theory, each named a cause.

The starts are the engine's own map section's (``<slug>_maps``, saved events:
the analytic outcome and the engine's label as the agreement study compares
them); every start where they differ (or an even spread of them, ``max_states``)
runs through the ladder the engine declares (``crosscheck.studies.ladder``),
judged against the study's label.  One section per registered engine whose
``ReportPlan.ladder`` is set (``<slug>_ladder``), after its map section.
Scaled units (section 2.1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, SkipSection, Table

#: Map code of a start the agreement study did not compare (as ``engine_maps``).
NOT_SLIPPING = -2


def params(quick: bool, engine: str, options: dict, maps_slug: str) -> dict:
    # ladder_engine: whose disagreements these are (the engine table reads each engine's causes from it)
    # an even spread of at most 3 (quick) or 30 (full) disagreements: 12 Drake ladder starts cost 1.9-3.2 s of section time in
    # the full report and their interventions 2.3-10.5 s (Bullet's 0.2 and 1.6 s), since the compliant rod's grazes no
    # longer chatter and the engines stop at their judged first event; 30 give each engine's confirmed share more than a
    # dozen starts to rest on
    return {
        "ladder_engine": engine,
        "options": dict(options),
        "alpha": 3.0,
        "horizon": 2.0,
        "maps": maps_slug,
        "max_states": 3 if quick else 30,
    }


def _saved_events(ctx: RunContext) -> dict:
    """The engine's map section's saved event tables (SkipSection when that section has not run ok with these options)."""
    P = ctx.params
    found = ctx.finished(P["maps"])
    status, store = found if found else ({}, None)
    theirs = status.get("params", {})
    if not found or theirs.get("options") != P["options"] or theirs.get("engine") != P["ladder_engine"]:
        raise SkipSection(
            f"needs the {P['maps']} section's results at the same options: run it first (the report runs it before this one)"
        )
    return {m["name"]: store.read_table(f"events_{m['name']}", text=("analytic_reason",)) for m in theirs["maps"]}


def run(ctx: RunContext) -> None:
    from crosscheck.engines.spec import LADDER_CAUSES
    from crosscheck.outcome import Outcome
    from crosscheck.state import SlipState
    from crosscheck.studies.comparison import RATED
    from crosscheck.studies.ladder import CAUSES, run_ladder

    P = ctx.params
    engine = P["ladder_engine"]
    chosen = []
    for name, t in _saved_events(ctx).items():
        a, e = np.asarray(t["analytic_outcome"], int), np.asarray(t[engine], int)
        for i in np.flatnonzero(np.isin(a, [int(o) for o in RATED]) & (e >= 0) & (e != a)):
            chosen.append((name, t, int(i)))
    n_all = len(chosen)
    if n_all > P["max_states"]:  # an even spread over the maps' disagreements, deterministic
        chosen = [chosen[int(k)] for k in np.linspace(0, n_all - 1, P["max_states"]).round().astype(int)]
    ladders = []
    for name, t, i in ctx.progress(chosen, desc=f"{engine} ladder"):
        s = SlipState(**{k: float(t[k][i]) for k in ("theta", "varphi", "Theta", "Psi", "eta")})
        ld = run_ladder(
            engine,
            s,
            float(t["mu"][i]),
            alpha=P["alpha"],
            horizon=P["horizon"],
            reference=Outcome(int(t[engine][i])),
            **P["options"],
        )
        ladders.append({"map": name, "row": i, **ld.as_dict()})
    counts = {c: sum(1 for ld in ladders if ld["cause"] == c) for c in CAUSES}
    named = sum(counts[c] for c in LADDER_CAUSES)
    ctx.store.write_json("ladders", ladders)
    ctx.store.write_json(
        "summary",
        {
            "engine": engine,
            "n_disagreements_on_maps": n_all,
            "n_disagree": len(ladders),
            "counts": counts,
            "attributed": named / len(ladders) if ladders else None,
        },
    )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.studies.ladder import CAUSES

    P = ctx.params
    name = engine_label(P["ladder_engine"])
    summary, ladders = ctx.store.read_json("summary"), ctx.store.read_json("ladders")
    rows = [[c, str(summary["counts"][c])] for c in CAUSES if summary["counts"].get(c)]
    blocks = [
        Table(
            caption=f"{name}: causes of {summary['n_disagree']} of the {summary['n_disagreements_on_maps']} disagreements on its maps "
            f"(the first rung whose outcome, compared as the agreement study compares, equals {name}'s).",
            header=["cause", "starts"],
            rows=rows or [["(no disagreement on the maps)", "0"]],
            data=ctx.data("summary.json"),
        )
    ]
    if ladders:
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
        blocks.append(
            Table(
                caption="Each laddered start: its map, start, mu, each rung's outcome as compared, and the cause. Rungs: "
                + ", ".join(f"{r['name']} ({r['cause'] or 'the theory'})" for r in ladders[0]["rungs"])
                + ".",
                header=["map", "start", "mu", *rung_names, "cause"],
                rows=detail,
                data=ctx.data("ladders.json"),
            )
        )
    return blocks


def finding(data: Path) -> list:
    """The findings line: the split of the engine's laddered disagreements by cause."""
    from crosscheck.report.finding import Finding, read_json
    from crosscheck.report.format import engine_label

    summary = read_json(data / "summary.json")
    if not summary or not summary.get("n_disagree"):
        return []
    counts = summary["counts"]
    causes = ", ".join(f"{k} {v}" for k, v in counts.items() if v)
    name = engine_label(summary["engine"])
    return [
        Finding(
            f"{name}: causes of disagreement",
            f"{summary['n_disagree']} of its {summary['n_disagreements_on_maps']} disagreements "
            f"laddered, {100 * summary['attributed']:.0f} % attributed to a named cause: {causes}",
            "explained" if summary["attributed"] >= 0.9 else "partly explained",
            data.name,
        )
    ]


def section(spec, options: dict, maps_slug: str) -> Section:
    """The ladder section ``<slug>_ladder`` of the engine ``spec`` on the disagreements of the map section ``maps_slug``."""
    return Section(
        slug=f"{spec.slug}_ladder",
        title=f"{spec.label}: a named cause for each disagreement (its ladder)",
        paper="sections 2, 4",
        params=lambda quick: params(quick, spec.name, options["quick" if quick else "full"], maps_slug),
        run=run,
        render=render,
        requires=("crosscheck.studies.ladder", spec.module or "crosscheck.engines"),
        finding=finding,
        after=(maps_slug,),
    )
