"""An engine's ladder: the disagreements of its outcome maps through the models between it and the theory, each named a cause.

The starts are those of the engine's own map section (``<slug>_maps``, saved
events: the analytic outcome and the engine's label as the agreement study
compares them); every start where they differ (or an even spread of them,
``max_states``) runs through the ladder the engine declares
(``crosscheck.studies.ladder``), judged against the study's label.  The section
counts the causes, the detours (ladders that pass through an outcome that is
neither the theory's nor the engine's, with the cause of the rung that ends
each), and the last rungs (the engine rerun) that differ from the study's label
and whether 1-2 ulp of theta decide them; it draws each map coloured by cause
(``engine_ladder_render``) and the paper's Fig. 20 initial condition IC2
through every rung.  One section per registered engine whose
``ReportPlan.ladder`` is set (``<slug>_ladder``), after its map section.
Scaled units (section 2.1).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from crosscheck.report.section import RunContext, Section, SkipSection
from crosscheck.report.sections.engine_ladder_render import AGREE, NOT_RUN, NOT_SLIPPING, cause_codes, render

#: How many of the maps' disagreements are laddered where the engine's plan does not say (an even spread): 12 Drake
#: ladder starts cost 1.9-3.2 s of section time in the full report and their interventions 2.3-10.5 s (Bullet's 0.2
#: and 1.6 s), since the compliant rod's grazes no longer chatter and the engines stop at their judged first event;
#: 30 give each engine's confirmed share more than a dozen starts to rest on.
MAX_STATES = {"quick": 3, "full": 30}


def params(quick: bool, engine: str, options: dict, maps_slug: str, states: dict | None = None) -> dict:
    from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS

    key = "quick" if quick else "full"
    # ladder_engine: whose disagreements these are (the engine table reads each engine's causes from it)
    return {
        "ladder_engine": engine,
        "options": dict(options),
        "alpha": 3.0,
        "horizon": 2.0,
        "maps": maps_slug,
        "max_states": (states or MAX_STATES)[key],
        "ic2": dict(FIG20_INITIAL_CONDITIONS[1]),
        "ic2_mu": 1.4,
    }


def _saved_events(ctx: RunContext) -> tuple[dict, list]:
    """The engine's map section's saved event tables and its maps (SkipSection when that section has not run ok with
    these options)."""
    P = ctx.params
    found = ctx.finished(P["maps"])
    status, store = found if found else ({}, None)
    theirs = status.get("params", {})
    if not found or theirs.get("options") != P["options"] or theirs.get("engine") != P["ladder_engine"]:
        raise SkipSection(
            f"needs the {P['maps']} section's results at the same options: run it first (the report runs it before this one)"
        )
    events = {m["name"]: store.read_table(f"events_{m['name']}", text=("analytic_reason",)) for m in theirs["maps"]}
    return events, theirs["maps"]


def _chosen(events: dict, engine: str, max_states: int | None) -> tuple[list, int]:
    """((map, table, row) of the disagreements laddered, how many the maps have): rated analytic outcome, the engine's
    label compared and different; an even spread of at most ``max_states`` (None: all), deterministic."""
    from crosscheck.studies.comparison import RATED

    chosen = []
    for name, t in events.items():
        a, e = np.asarray(t["analytic_outcome"], int), np.asarray(t[engine], int)
        for i in np.flatnonzero(np.isin(a, [int(o) for o in RATED]) & (e >= 0) & (e != a)):
            chosen.append((name, t, int(i)))
    n_all = len(chosen)
    if max_states is not None and n_all > max_states:
        chosen = [chosen[int(k)] for k in np.linspace(0, n_all - 1, max_states).round().astype(int)]
    return chosen, n_all


def _cause_maps(ctx: RunContext, events: dict, maps: list, chosen: list, lds: list) -> None:
    """Per map, each start's code: its ladder's cause, or NOT_SLIPPING, AGREE, NOT_RUN (``causes_<map>.csv``)."""
    engine, codes = ctx.params["ladder_engine"], cause_codes()
    for m in maps:
        e = events[m["name"]]
        agree = e["analytic_outcome"] == e[engine]
        code = np.where(e["slipping"] == 1, np.where(agree, AGREE, NOT_RUN), NOT_SLIPPING).astype(int)
        for (name, _, i), ld in zip(chosen, lds):
            if name == m["name"]:
                code[i] = codes[ld.cause]
        ctx.store.write_table(f"causes_{m['name']}", {m["x"]: e[m["x"]], m["y"]: e[m["y"]], "code": code})
    ctx.store.write_json("cause_maps", maps)


def run(ctx: RunContext) -> None:
    from crosscheck.engines.spec import LADDER_CAUSES
    from crosscheck.outcome import Outcome
    from crosscheck.state import SlipState
    from crosscheck.studies.ladder import CAUSES, decided_by_rounding, run_ladder

    P = ctx.params
    engine, kw = P["ladder_engine"], {"alpha": P["alpha"], "horizon": P["horizon"], **P["options"]}
    events, maps = _saved_events(ctx)
    chosen, n_all = _chosen(events, engine, P["max_states"])
    lds = []
    for _, t, i in ctx.progress(chosen, desc=f"{engine} ladder"):
        s = SlipState(**{k: float(t[k][i]) for k in ("theta", "varphi", "Theta", "Psi", "eta")})
        lds.append(run_ladder(engine, s, float(t["mu"][i]), reference=Outcome(int(t[engine][i])), **kw))
    ctx.store.write_json("ladders", [{"map": n, "row": i, **ld.as_dict()} for (n, _, i), ld in zip(chosen, lds)])
    _cause_maps(ctx, events, maps, chosen, lds)
    # the last rung is the engine rerun at the same options: where it differs from the study's label, is the start
    # the same in all but its last bits?
    mismatched = [ld for ld in lds if ld.rungs[-1].ok and ld.rungs[-1].label != ld.reference]
    rounding = sum(decided_by_rounding(engine, ld, ld.reference, **P["options"]) for ld in mismatched)
    ic2 = run_ladder(engine, SlipState(**P["ic2"]), P["ic2_mu"], alpha=P["alpha"], horizon=P["horizon"], **P["options"])
    ctx.store.write_json("ic2", ic2.as_dict())
    counts = {c: sum(1 for ld in lds if ld.cause == c) for c in CAUSES}
    ended = [ld.detour_ended_by or "none" for ld in lds if ld.detour is not None]
    missing = {r.name: sum(1 for ld in lds if not ld.rungs[r.rung - 1].ok) for r in ic2.rungs}
    summary = {
        "engine": engine,
        "n_disagreements_on_maps": n_all,
        "n_disagree": len(lds),
        "counts": counts,
        "attributed": sum(counts[c] for c in LADDER_CAUSES) / len(lds) if lds else None,
        "missing": missing,
        "reference_mismatch": len(mismatched),
        "rounding_decided": rounding,
        "detours": {"n": len(ended), "ended_by": {c: ended.count(c) for c in dict.fromkeys(ended)}},
    }
    ctx.store.write_json("summary", summary)
    _checks(ctx, summary, lds, ic2)


def _checks(ctx: RunContext, summary: dict, lds: list, ic2) -> None:
    """Every rung ran; the engine rerun reproduces the study's labels (or 1-2 ulp away); IC2's rung 1 as the paper
    quotes it; the attributed share against the ladder's goal (a regression guard)."""
    from crosscheck.tolerances import LADDER_ATTRIBUTED, LADDER_QUOTED_TIME

    failures = sorted({f"{r.name}: {r.detail}" for ld in [*lds, ic2] for r in ld.rungs if not r.ok})
    ctx.check(
        "every rung ran at every laddered start and at IC2 (none failed)",
        not failures,
        value=summary["missing"],
        allowance=0,
        detail="; ".join(failures[:5]),
    )
    n, rerun, rounding = summary["n_disagree"], summary["reference_mismatch"], summary["rounding_decided"]
    ctx.check(
        "the last rung (the engine rerun at the same options) reproduces the map's label at every laddered "
        "disagreement, or 1-2 ulp of theta away (the outcome decided by the start's last bits)",
        rerun == rounding,
        value=rerun - rounding,
        allowance=0,
        detail=f"{n} disagreements laddered; the rerun runs only to the comparison time + lag, as the study compares; "
        f"{rerun} reruns differ, {rounding} of them decided by the start's last bits",
    )
    one = ic2.rungs[0]
    ctx.check(
        "IC2: rung 1 (the paper's rod) lifts off at t = 0.01654",
        one.outcome is not None and one.outcome.name == "LIFTOFF" and LADDER_QUOTED_TIME.ok(one.time, 0.01654),
        value=one.time,
        allowance=LADDER_QUOTED_TIME.atol,
        detail=one.outcome.name if one.outcome is not None else one.status,
    )
    att, goal = summary["attributed"], 1.0 - LADDER_ATTRIBUTED.atol
    ctx.check(
        f"at least {100 * goal:.0f}% of the laddered disagreements attributed to a named cause",
        att is None or bool(math.isfinite(att) and att >= goal),
        value=att,
        allowance=goal,
        guard=True,
        detail=", ".join(f"{c} {v}" for c, v in summary["counts"].items() if v) + f" of {n}",
    )


def finding(data: Path) -> list:
    """The findings line: the split of the engine's laddered disagreements by cause, and IC2's cause."""
    from crosscheck.report.finding import Finding, read_json
    from crosscheck.report.format import engine_label
    from crosscheck.tolerances import LADDER_ATTRIBUTED

    summary = read_json(data / "summary.json")
    if not summary or not summary.get("n_disagree"):
        return []
    counts = summary["counts"]
    causes = ", ".join(f"{k} {v}" for k, v in counts.items() if v)
    name = engine_label(summary["engine"])
    text = (
        f"{summary['n_disagree']} of its {summary['n_disagreements_on_maps']} disagreements "
        f"laddered, {100 * summary['attributed']:.0f} % attributed to a named cause: {causes}"
    )
    ic2 = read_json(data / "ic2.json") or {}
    if ic2.get("cause") and ic2.get("reference"):
        theory = ic2["rungs"][0]["label"]
        text += f"; the paper's IC2 (theory {theory}, {name} {ic2['reference']}): {ic2['cause']}"
    goal = 1.0 - LADDER_ATTRIBUTED.atol
    verdict = "explained" if summary["attributed"] >= goal else "partly explained"
    return [Finding(f"{name}: causes of disagreement", text, verdict, data.name)]


def section(spec, options: dict, maps_slug: str, states: dict | None = None) -> Section:
    """The ladder section ``<slug>_ladder`` of the engine ``spec`` on the disagreements of the map section ``maps_slug``
    (``states``: how many it ladders, as ``ReportPlan.ladder_states``)."""
    return Section(
        slug=f"{spec.slug}_ladder",
        title=f"{spec.label}: a named cause for each disagreement (its ladder)",
        paper="Fig. 20 (IC2); sections 2, 4",
        params=lambda quick: params(quick, spec.name, options["quick" if quick else "full"], maps_slug, states),
        run=run,
        render=render,
        requires=("crosscheck.studies.ladder", spec.module or "crosscheck.engines"),
        finding=finding,
        after=(maps_slug,),
    )
