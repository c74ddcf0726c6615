"""An engine after the theory's jams: its state once its contact settles against the impact without collision.

The starts are the paper's IC1 (the theory jams at t = 4.34e-4) and an even
spread of the slipping starts of the engine's outcome maps where the theory
jams (``<slug>_maps``' saved events), each run on the engine at its maps'
options and read at t_jam + settle against the theory's impact and hybrid
continuation (``crosscheck.studies.jam_impact``: Theta+, Psi+, the slip after
it, P_N, energy).  A compliant engine with a convergence plan also runs IC1 at
each of its convergence settings, stiffest last: whether its jam tends to the
theory's impact as its contact stiffens.  One section per engine with maps
(``<slug>_impact``); the figure of every engine's Theta+ against the theory's
is drawn by ``impact_engines``.  Scaled units (section 2.1).
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text

#: Map starts where the theory jams, beside IC1, by cost: a start costs one engine run to t_jam + settle (measured
#: 0.1-0.6 s with the theory's continuation, MuJoCo's slowest at its 0.12 settle) and 8 engines share 2 cores, so 4
#: keep the quick report's eight sections under ~10 s together and 12 the full report's under ~30 s.
#: An engine with smaller maps gets fewer (``cost_scale``).
MAX_STARTS = {"quick": 4, "full": 12}

#: The numbers the table and the engine table read (``summary.json``).
_IC1 = "IC1"


#: The map sections' default size (``engine_maps.params``): an engine whose runs cost more declares smaller maps.
DEFAULT_MAPS_N = {"quick": 10, "full": 32}


def cost_scale(engine: str, key: str) -> float:
    """The share of the default number of starts an engine gets: (its maps' n / the default n)^2, the share of runs its
    own maps make (1 for an engine at the default; Drake's 6 x 6 quick maps 0.36, Newton's 4 x 4 0.16): the engines that
    declared smaller maps by their measured cost (Newton's psi section took 456-588 s at 120 starts) get fewer
    starts."""
    from crosscheck import engines

    plan = engines.get(engine).report
    n = (plan.maps_n or {}).get(key) if plan is not None else None
    return 1.0 if not n else min(1.0, (n / DEFAULT_MAPS_N[key]) ** 2)


def params(quick: bool, engine: str, options: dict, convergence: list | None) -> dict:
    key = "quick" if quick else "full"
    return {
        "engine": engine,
        "alpha": 3.0,
        "t_max": 2.0,
        "options": dict(options),
        # one run per start (the Psi section's are many): the linear share, the square root of the cost scale
        "max_starts": max(1, round(MAX_STARTS[key] * cost_scale(engine, key) ** 0.5)),
        "convergence": [dict(s) for s in convergence or ()],
    }


def _map_jams(ctx: RunContext, slug: str, n: int) -> list:
    """(label, state, mu) of an even spread of at most ``n`` slipping map starts whose theory jams (none if the maps
    section did not finish)."""
    from crosscheck.outcome import Outcome
    from crosscheck.state import SlipState

    done = ctx.finished(f"{slug}_maps")
    if done is None:
        return []
    status, store = done
    found = []
    for m in status["params"]["maps"]:
        t = store.read_table(f"events_{m['name']}")
        for i in np.flatnonzero((t["slipping"] == 1) & (t["analytic_outcome"] == int(Outcome.JAM))):
            s = SlipState(**{k: float(t[k][i]) for k in ("theta", "varphi", "Theta", "Psi", "eta")})
            found.append((f"{m['name']} #{i}", s, float(t["mu"][i])))
    if len(found) > n:
        found = [found[int(k)] for k in np.linspace(0, len(found) - 1, n).round()]
    return found


def run(ctx: RunContext) -> None:
    from crosscheck import engines
    from crosscheck.rod import Rod
    from crosscheck.state import SlipState
    from crosscheck.studies.jam_impact import COLUMNS, compare_jams, stiffness_convergence
    from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS

    P = ctx.params
    spec, rod = engines.get(P["engine"]), Rod.scaled(P["alpha"])
    ic1 = SlipState(**FIG20_INITIAL_CONDITIONS[0])
    starts = [(_IC1, ic1, 1.4), *_map_jams(ctx, spec.slug, P["max_starts"])]
    # the engine's runs of every start in one call (a batched engine steps them together: the same runs)
    compared = compare_jams(spec, rod, [(s, mu) for _, s, mu in starts], P["options"], t_max=P["t_max"])
    rows = [{"start": label, **r} for (label, _, _), r in zip(starts, compared) if r is not None]
    ctx.store.write_table("jams", {k: [r[k] for r in rows] for k in ("start", *COLUMNS)})
    conv = stiffness_convergence(spec.name, ic1, 1.4, P["convergence"], alpha=P["alpha"]) if P["convergence"] else []
    if conv:
        keys = (
            "contact_time",
            "timestep",
            "engine_outcome",
            "Theta_plus_engine",
            "Psi_plus_engine",
            "Theta_plus_error",
        )
        ctx.store.write_table("stiffness", {k: [r[k] for r in conv] for k in keys})
    ctx.store.write_json("summary", _summary(spec.name, rows, conv))


def _summary(engine: str, rows: list, conv: list) -> dict:
    both = [r for r in rows if r["engine_jammed"]]
    errs = [abs(r["Theta_plus_error"]) for r in both]
    ic1 = next((r for r in rows if r["start"] == _IC1), None)
    out = {
        "engine": engine,
        "n": len(rows),
        "n_jammed": len(both),
        "median_abs_Theta_plus_error_jammed": float(np.median(errs)) if errs else None,
        "median_abs_Theta_plus_error": float(np.median([abs(r["Theta_plus_error"]) for r in rows])) if rows else None,
        "ic1": None
        if ic1 is None
        else {
            k: ic1[k]
            for k in (
                "t_jam",
                "settle",
                "Theta_plus",
                "Psi_plus",
                "P_N",
                "engine_outcome",
                "Theta_plus_engine",
                "Psi_plus_engine",
                "engine_eta",
                "theory_eta",
                "engine_energy",
                "theory_energy",
                "engine_P_N",
            )
        },
    }
    if len(conv) >= 2:
        soft, stiff = abs(conv[0]["Theta_plus_error"]), abs(conv[-1]["Theta_plus_error"])
        out["stiffness"] = {
            "contact_times": [r["contact_time"] for r in conv],
            "abs_errors": [abs(r["Theta_plus_error"]) for r in conv],
            "tends_to_impact": bool(stiff < soft),
        }
    return out


def _fmt(x, f=".3g") -> str:
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, f)


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label

    P = ctx.params
    name = engine_label(P["engine"])
    t = ctx.store.read_table("jams", text=("start", "engine_outcome"))
    s = ctx.store.read_json("summary")
    rows = [
        [
            t["start"][i],
            f"{t['mu'][i]:g}",
            _fmt(t["t_jam"][i], ".4g"),
            f"{t['Theta_plus'][i]:.4f} / {t['Psi_plus'][i]:.4f}",
            f"{t['engine_outcome'][i]}",
            f"{t['Theta_plus_engine'][i]:.4f} / {t['Psi_plus_engine'][i]:.4f}",
            f"{t['engine_eta'][i]:.3g} ({t['theory_eta'][i]:.3g})",
            f"{t['P_N'][i]:.3g} / {_fmt(t['engine_P_N'][i])}",
            f"{t['engine_energy'][i] - t['theory_energy'][i]:+.3g}",
        ]
        for i in range(len(t["start"]))
    ]
    blocks = [
        Table(
            caption=(
                f"{name} after the theory's jams (options {P['options']}): the theory's impact without collision "
                "(Theta+, Psi+, "
                "P_N) against the engine's state read at t_jam + settle (settle: 2 contact times, at least 3 "
                "timesteps) and moved "
                "back to the impact by the theory's own drift over settle (`crosscheck.studies.jam_impact`); the slip "
                "speed eta "
                "there (the theory's in brackets), the engine's jam impulse ('-': its first event is not a JAM) and "
                "its energy "
                f"minus the theory's at t* [m g l]. Median |Theta+ error| over the {s['n_jammed']} of {s['n']} starts "
                "the engine "
                f"also jams: {_fmt(s['median_abs_Theta_plus_error_jammed'])}; over all: "
                f"{_fmt(s['median_abs_Theta_plus_error'])}."
            ),
            header=[
                "start",
                "mu",
                "t_jam",
                "theory Theta+ / Psi+",
                name,
                f"{name} Theta+ / Psi+",
                "eta after",
                "P_N theory / engine",
                "energy - theory",
            ],
            rows=rows,
            data=ctx.data("jams.csv", "summary.json"),
        )
    ]
    if s.get("stiffness"):
        c = ctx.store.read_table("stiffness", text=("engine_outcome",))
        verdict = "tends to" if s["stiffness"]["tends_to_impact"] else "does not tend to"
        blocks.append(
            Table(
                caption=f"{name} at IC1 over its convergence settings, softest first: its jam {verdict} the theory's "
                "impact "
                "(|Theta+ error| at the stiffest setting against the softest).",
                header=["contact time", "timestep", "outcome", "Theta+ / Psi+", "Theta+ - theory"],
                rows=[
                    [
                        f"{c['contact_time'][i]:.3g}",
                        f"{c['timestep'][i]:.3g}",
                        c["engine_outcome"][i],
                        f"{c['Theta_plus_engine'][i]:.4f} / {c['Psi_plus_engine'][i]:.4f}",
                        f"{c['Theta_plus_error'][i]:+.3g}",
                    ]
                    for i in range(len(c["contact_time"]))
                ],
                data=ctx.data("stiffness.csv"),
            )
        )
    elif not len(t["start"]):
        blocks.append(Text("No start jams in the theory."))
    return blocks


def section(spec, options: dict) -> Section:
    """The section ``<slug>_impact`` of the engine ``spec`` at its maps' ``options`` ({"quick": ..., "full": ...})."""
    plan = spec.report
    conv = plan.convergence if plan is not None and "compliant" in spec.tags else None
    return Section(
        slug=f"{spec.slug}_impact",
        title=f"{spec.label}: the impact without collision in size",
        paper="Corollary 4.2, section 6 (impact without collision)",
        params=lambda quick: params(
            quick,
            spec.name,
            options["quick" if quick else "full"],
            None if conv is None else conv["quick" if quick else "full"],
        ),
        run=run,
        render=render,
        requires=("crosscheck.studies.jam_impact", spec.module or "crosscheck.engines"),
        after=(f"{spec.slug}_maps",),
    )
