"""A contact engine vs analytic: outcome maps over (Psi, mu) and over (theta, Theta) slices, confusion matrices, event-time errors.

Each map is a ``crosscheck.studies.grids.EventGrid`` with two axes varied
and the others fixed, run through ``crosscheck.studies.agreement.agreement_study``
with the engine and options named in the parameters (``section(spec, ...)``
builds one such section per registered engine whose ``ReportPlan`` has maps,
``<slug>_maps``, drawn beside another engine's maps where it says so): the analytic first event of
every start (``slip_until_event``), and for every start that slips at t = 0
(b < 0 < p) the engine's outcome by the one classifier
(``crosscheck.engines.classifier``, whose JAM rule measures the force against
the engine's own friction direction), compared only up to the analytic
comparison time (``comparison_labels``: a later engine event counts as SLIP;
the analytic run stops when the state leaves the paper's domain).  Starts
that do not slip at t = 0 are not compared (grey).

Where they disagree: a cell on an analytic boundary (a 4-neighbour with
another analytic outcome) against the interior; in the full report also the
study's probed distance to the analytic boundary (``boundary_distance``).
Event-time errors: t_engine - t_analytic where both report the same event.
The figures, tables and interactive page: ``engine_map_figures``.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.outcomes import NOT_SLIPPING, OUTCOME_NAMES
from crosscheck.report.section import RunContext, Section
from crosscheck.report.sections.engine_map_figures import render


def params(quick: bool, engine: str, options: dict, beside: str | None = None, n: int | None = None) -> dict:
    """The section's parameters: ``engine`` with ``options`` on three maps of n x n starts (10 quick, 32 full by default)."""
    n = n or (10 if quick else 32)
    return {
        "engine": engine,
        "alpha": 3.0,
        "horizon": 2.0,
        "options": dict(options),
        "beside": beside,
        "boundary_directions": 0 if quick else 3,
        "maps": [
            {
                "name": "Psi_mu",
                "x": "Psi",
                "y": "mu",
                "x_range": [0.0, 3.0],
                "y_range": [0.0, 3.0],
                "n": n,
                "fixed": {"theta": 1.0, "varphi": -1.9, "Theta": 0.0, "eta": 1.0},
            },
            {
                "name": "theta_Theta_0",
                "x": "theta",
                "y": "Theta",
                "x_range": [0.2, 1.5],
                "y_range": [-1.5, 1.5],
                "n": n,
                "fixed": {"Psi": 0.0, "mu": 1.4, "varphi": -1.9, "eta": 1.0},
            },
            {
                "name": "theta_Theta_1",
                "x": "theta",
                "y": "Theta",
                "x_range": [0.2, 1.5],
                "y_range": [-1.5, 1.5],
                "n": n,
                "fixed": {"Psi": 1.7, "mu": 1.4, "varphi": -1.9, "eta": 1.0},
            },
        ],
    }


def _grid(m: dict):
    from crosscheck.studies.grids import EventGrid

    x, y = cell_centres(*m["x_range"], m["n"]), cell_centres(*m["y_range"], m["n"])
    axes = {k: (v,) for k, v in m["fixed"].items()}
    axes[m["x"]], axes[m["y"]] = tuple(x), tuple(y)
    return EventGrid(**axes), x, y


def _sweeps(ctx: RunContext, name: str) -> dict:
    """The section's sweep settings with one store per map."""
    return {} if ctx.sweeps is None else {**ctx.sweeps, "store": ctx.sweeps["store"] / name}


def _probes(ctx: RunContext, m: dict, P: dict) -> dict:
    """The theory's side of map ``m``, which every engine that maps the same grid shares (the engines' quick maps, and
    MuJoCo's, the rigid engine's and Bullet's 24 x 24 and the 12 x 12 of Drake's five, PhysX's two and DART in the full
    report), kept once under the report's
    sweeps directory and read by the others (``RunContext.shared``):

    * the analytic first events (``agreement_study``'s ``analytic_cache``): eight engines map the quick report's grids;
    * the boundary probes (``boundary_cache``): a stream seeded by the report's seed and the map itself, so every
      engine gets the same distances.
    """
    theory = {"map": m, "alpha": P["alpha"], "horizon": P["horizon"]}
    events, _ = ctx.shared("analytic_events", m["name"], theory, ".npz")
    cache, digest = ctx.shared(
        "boundary_distance", m["name"], {**theory, "directions": P["boundary_directions"], "seed": ctx.seed}, ".npy"
    )
    rng = np.random.default_rng([ctx.seed, int(digest, 16) & 0xFFFFFFFF])
    return {"rng": rng, "boundary_cache": cache, "analytic_cache": events}


def run(ctx: RunContext) -> None:
    from crosscheck import engines
    from crosscheck.outcome import Outcome
    from crosscheck.studies.agreement import agreement_study
    from crosscheck.theory import critical

    P = ctx.params
    engine = P["engine"]
    # an engine whose friction can exceed mu F_n (a pyramid's corners: sqrt(2) mu F_n) may have p < 0 from
    # mu_P / that factor on: the theory's guarantee below mu_P is Coulomb's cone's (Options.friction_excess, 1 if absent)
    excess = float(getattr(engines.get(engine).options(**P["options"]), "friction_excess", 1.0))
    mu_P = float(critical.mu_P(P["alpha"])) / excess
    below_mu_P, jams_below = 0, []
    summary = []
    for m in ctx.progress(P["maps"], desc="agreement maps"):
        grid, x, y = _grid(m)
        res = agreement_study(
            grid,
            engine=engine,
            settings=(P["options"],),
            alpha=P["alpha"],
            horizon=P["horizon"],
            boundary_directions=P["boundary_directions"],
            progress=ctx.show_progress,
            **_probes(ctx, m, P),
            **_sweeps(ctx, m["name"]),
        )
        (ctx.store.root / f"study_{m['name']}.json").write_text(res.to_json() + "\n")
        pts, a = res.points, res.analytic
        n = len(a.outcome)
        cols = {k: pts[k] for k in ("theta", "varphi", "Theta", "Psi", "mu", "eta")}
        cols.update(
            {
                "b0": a.b0,
                "p0": a.p0,
                "slipping": a.slipping.astype(int),
                "analytic_outcome": a.outcome.astype(int),
                "analytic_time": a.time,
                "analytic_reason": a.reason,
                "comparison_time": a.until,
            }
        )
        dist = np.full(n, np.nan)
        dist[res.index] = res.distance
        cols["boundary_distance"] = dist
        (r,) = res.runs
        lab, t = np.full(n, NOT_SLIPPING), np.full(n, np.nan)
        lab[res.index], t[res.index] = r.label, r.event_time
        cols[engine], cols[f"{engine}_time"] = lab, t
        below = pts["mu"][res.index] < mu_P
        below_mu_P += int(below.sum())
        for i in np.flatnonzero(below & (r.label == Outcome.JAM)):
            k = res.index[i]
            jams_below.append(
                (
                    {q: float(pts[q][k]) for q in ("theta", "varphi", "Theta", "Psi", "eta")},
                    float(pts["mu"][k]),
                    float(r.event_time[i]),
                )
            )
        ctx.store.write_table(f"events_{m['name']}", cols)
        summary.append(
            {
                "name": m["name"],
                "x": {"name": m["x"], "values": x},
                "y": {"name": m["y"], "values": y},
                "fixed": m["fixed"],
                "runs": [
                    {k: v for k, v in r.summary().items() if k not in ("time_difference", "time_difference_outcome")}
                    for r in res.runs
                ],
                "time_difference": {
                    "difference": r.time_difference.tolist(),
                    "outcome": [OUTCOME_NAMES[int(o)] for o in r.time_difference_outcome],
                    "analytic_time": a.time[res.index][
                        (r.label == a.outcome[res.index]) & np.isin(a.outcome[res.index], [1, 2, 3])
                    ].tolist(),
                },
            }
        )
        ctx.store.write_json("maps", summary)
    _check_no_iwc(ctx, engine, P, mu_P, excess, below_mu_P, jams_below)


#: A compliant twin's eps is divided by this to see its JAM vanish towards the rigid limit (eps -> 0).
STIFFER = 10.0


def _check_no_iwc(ctx: RunContext, engine: str, P: dict, mu_P: float, excess: float, rated: int, jams: list) -> None:
    """Physics: below mu_P, p > 0 for every state (eq. mup2D), so no paradox and no impact without collision exists.

    Each JAM label there is rerun and sorted (``jams_below_mu_P.json``): a landing after the engine's own hop (the tip
    off the plane, then landing hard) is a collision, not an impact without one; for an engine whose contact is a
    compliant law (``Options.compliant_twin``: the compliant rod of the same eps, xi, radius), a JAM that the compliant
    rod at that eps also gives and no longer gives at eps / ``STIFFER`` is that law's finite compliance (a slip stopped
    hard where p > 0 is small), an engine finding the report names.  Only the others count against the theory.
    """
    from crosscheck import engines
    from crosscheck.report.format import engine_label

    twin = getattr(engines.get(engine).options(**P["options"]), "compliant_twin", None)
    sorted_ = [dict(start, mu=mu, event_time=t, kind=_jam_kind(engine, P, twin, start, mu, t)) for start, mu, t in jams]
    if sorted_:
        ctx.store.write_json("jams_below_mu_P", {"compliant_twin": twin, "stiffer": STIFFER, "jams": sorted_})
    count = {k: sum(j["kind"] == k for j in sorted_) for k in ("landing", "compliant", "iwc")}
    name = engine_label(engine)
    bound = (
        f"mu_P = {mu_P:.4f} (p > 0 for every state there, eq. mup2D)"
        if excess == 1.0
        else f"mu_P / {excess:.4g} = {mu_P:.4f} (its friction reaches {excess:.4g} mu F_n; p > 0 for every state "
        "there, eq. mup2D with that friction)"
    )
    but = (
        ""
        if twin is None
        else f", other than its compliant law's (the compliant rod at eps {twin['eps']:g}, xi {twin['xi']:g}, r "
        f"{twin['radius']:g} jams there too and not at eps / {STIFFER:g})"
    )
    named = "; ".join(
        f"theta {j['theta']:g}, varphi {j['varphi']:g}, Psi {j['Psi']:g}, Theta {j['Theta']:g}, mu {j['mu']:g}: JAM at "
        f"t = {j['event_time']:g}"
        for j in sorted_
        if j["kind"] == "compliant"
    )
    ctx.check(
        f"{name}: no impact without collision below {bound}{but}",
        count["iwc"] == 0,
        value=count["iwc"],
        allowance=0,
        detail=f"{rated} rated starts below mu_P on the maps; {count['landing']} JAM labels there are landings "
        f"after a hop of the engine's own (contact point above the plane by more than {LANDING_GAP:g} l before)"
        + ("" if twin is None else f"; {count['compliant']} are its compliant law's (an engine finding)")
        + (f": {named}" if named else ""),
    )


def _jam_kind(engine: str, P: dict, twin: dict | None, state: dict, mu: float, event_time: float) -> str:
    """ "landing", "compliant" (the compliant twin's JAM too, gone at eps / STIFFER) or "iwc" of a JAM below mu_P."""
    from crosscheck import engines
    from crosscheck.outcome import Outcome
    from crosscheck.rod import Rod
    from crosscheck.state import SlipState

    if _landed(engine, P, state, mu, event_time):
        return "landing"
    if twin is None:
        return "iwc"
    rod, start, rod_model = Rod.scaled(P["alpha"]), SlipState(**state), engines.get("compliant")
    jams = [
        rod_model.simulate(rod, start, mu, horizon=P["horizon"], **{**twin, "eps": eps}).outcome == Outcome.JAM
        for eps in (twin["eps"], twin["eps"] / STIFFER)
    ]
    return "compliant" if jams == [True, False] else "iwc"


#: A contact point this far above the plane (l) before a JAM has left it: 1000 times a start's gap above the plane
#: (``crosscheck.engines.mujoco.model.START_GAP``), far below a hop's (2.8e-5 l one step after Drake SAP's launch).
LANDING_GAP = 1e-9


def _landed(engine: str, P: dict, state: dict, mu: float, event_time: float) -> bool:
    """Whether the engine's run from ``state`` left the plane before its JAM (a landing, not an impact without collision)."""
    from crosscheck import engines
    from crosscheck.rod import Rod
    from crosscheck.state import SlipState

    spec = engines.get(engine)
    opts = spec.options(**P["options"])
    run = spec.simulate(
        Rod.scaled(P["alpha"]), SlipState(**state), mu, horizon=event_time + 2 * opts.timestep, **P["options"]
    )
    k = int(np.searchsorted(run.record.t, event_time))
    return bool(k > 0 and np.max(run.record.gap[:k]) > LANDING_GAP)


def section(spec, options: dict, beside: str | None = None, n: dict | None = None) -> Section:
    """The maps of the engine ``spec`` (an ``EngineSpec``) as the section ``<slug>_maps``, drawn beside the maps of the
    section ``beside`` if given.  ``options``: {"quick": {...}, "full": {...}}, the engine's options in each report."""
    title = f"{spec.label} vs analytic: outcome maps, confusion matrices, event times" + (
        f" (beside {beside})" if beside else ""
    )
    return Section(
        slug=f"{spec.slug}_maps",
        title=title,
        paper="sections 3.1, 4 (Corollary 4.2)",
        params=lambda quick: params(
            quick,
            spec.name,
            options["quick" if quick else "full"],
            beside,
            None if n is None else n["quick" if quick else "full"],
        ),
        run=run,
        render=render,
        requires=("crosscheck.studies.agreement", spec.module or "crosscheck.engines", "crosscheck.theory.gb"),
    )
