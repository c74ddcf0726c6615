"""The interventions section's runs: every start its engine's ladder laddered, rerun through the engine's interventions.

The starts and the ladder's options, alpha and horizon are read from the ladder section's results; each start gets
its map's boundary distance (``boundary_distances``) and runs through ``crosscheck.studies.interventions``, the
results saved as they finish.  The figures and tables: ``engine_interventions``.
"""

from __future__ import annotations

import json
import time

import numpy as np

from crosscheck.report.section import RunContext, Section, SkipSection

__all__ = ["SAVE_EVERY", "params", "run", "boundary_distances"]

#: Seconds between two saves of the starts finished so far (the file is rewritten whole: at every one of MuJoCo's 291
#: starts that cost 127 s of the section's 241 s, profiled).
SAVE_EVERY = 10.0


def params(quick: bool, engine: str, ladder: Section) -> dict:
    # the ladder's own parameters: a change there reruns this section too
    return {
        "engine": engine,
        "ladder": ladder.slug,
        "ladder_params": json.loads(json.dumps(ladder.params(quick), default=str)),
    }


def _laddered(ctx: RunContext) -> tuple[list[dict], dict]:
    """(disagreements as {map, state, mu, cause, reference}, the ladder's options/alpha/horizon) from the ladder section's
    ``ladders.json``, the format every ladder section publishes."""
    P = ctx.params
    found = ctx.finished(P["ladder"])
    if found is None:
        raise SkipSection(
            f"needs the {P['ladder']} section's results: run it first (the report runs it before this one)"
        )
    status, store = found
    lp = status["params"]
    starts = [
        {
            "map": ld["map"],
            "state": {k: ld["state"][k] for k in ("theta", "varphi", "Theta", "Psi", "eta")},
            "mu": ld["mu"],
            "cause": ld["cause"],
            "reference": ld["reference"],
        }
        for ld in store.read_json("ladders")
        if ld["cause"] not in ("agree", "not rated")
    ]
    _with_boundary_distance(ctx, starts, lp["maps"] if isinstance(lp.get("maps"), str) else lp.get("reuse"), lp)
    return starts, {"options": lp["options"], "alpha": lp["alpha"], "horizon": lp["horizon"]}


def _with_boundary_distance(ctx: RunContext, starts: list[dict], maps: str | None, ladder: dict) -> None:
    """Each start's distance to the theory's event boundary as the engine's map section probed it (``boundary_distance``:
    "inf" beyond the largest probe; None where that section did not probe, as in the quick report, is not there, ran
    at another alpha, horizon or options than the ladder's, or holds no such start)."""
    found = ctx.finished(maps) if maps else None
    if found is not None and any(
        found[0].get("params", {}).get(k) != ladder.get(k) for k in ("alpha", "horizon", "options")
    ):
        found = None  # (the ladder then ran a study of its own: these are not its starts' distances)
    tables = {}
    if found is not None:
        for name in {st["map"] for st in starts}:
            try:
                tables[name] = found[1].read_table(f"events_{name}", text=("analytic_reason",))
            except (OSError, ValueError):
                pass
    boundary_distances(starts, tables)


def boundary_distances(starts: list[dict], tables: dict) -> None:
    """Set each start's ``boundary_distance`` from its map's events table (map name -> columns): the row with the
    start's very state and mu (the ladder took its starts from these tables), None without one such row, without the
    column or where it is NaN (not probed)."""
    for st in starts:
        st["boundary_distance"] = None
        t = tables.get(st["map"])
        if t is None or "boundary_distance" not in t:
            continue
        at = np.ones(len(t["theta"]), bool)
        for k, v in (*st["state"].items(), ("mu", st["mu"])):
            at &= np.asarray(t[k], float) == v
        d = np.asarray(t["boundary_distance"], float)[at]
        if len(d) == 1 and not np.isnan(d[0]):
            st["boundary_distance"] = float(d[0])


def run(ctx: RunContext) -> None:
    from crosscheck.state import SlipState
    from crosscheck.studies.interventions import causes_with_interventions, intervene, summarise

    P = ctx.params
    starts, at = _laddered(ctx)
    results = []
    written = time.monotonic()
    for st in ctx.progress(starts, desc=f"{P['engine']} interventions"):
        iv = intervene(
            P["engine"],
            SlipState(**st["state"]),
            st["mu"],
            alpha=at["alpha"],
            horizon=at["horizon"],
            named=st["cause"],
            reference=st["reference"],
            **at["options"],
        )
        results.append({**st, "interventions": iv})
        if (
            time.monotonic() - written >= SAVE_EVERY
        ):  # the starts so far, for a reader of a long run; not at every start:
            ctx.store.write_json("interventions", results)  # the whole file each time (0.4 s at MuJoCo's 291 starts)
            written = time.monotonic()
    ctx.store.write_json("interventions", results)
    ctx.store.write_json(
        "summary",
        {
            "engine": P["engine"],
            "causes": causes_with_interventions(P["engine"]),
            "options": at["options"],
            **summarise(results),
        },
    )
