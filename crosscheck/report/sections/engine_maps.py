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
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.outcomes import OUTCOME_NAMES, boundary_cells
from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text

#: Map code of a start that does not slip at t = 0 (not compared).
NOT_SLIPPING = -2


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
    MuJoCo's and the rigid engine's 32 x 32 and Drake's five 12 x 12 in the full report), kept once under the report's
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


def _floors(maps: list) -> str:
    floors = sorted({r["stick_floor"] for mp in maps for r in mp["runs"] if r.get("stick_floor") is not None})
    return ", ".join(f"{f:g}" for f in floors) or "-"


def _stick_as_slip(maps: list) -> str:
    n = sum(int(r.get("stick_as_slip") or 0) for mp in maps for r in mp["runs"])
    return f"{n} start{'' if n == 1 else 's'}"


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
        ctx.store.write_json("jams_below_mu_P", {"compliant_twin": twin, "jams": sorted_})
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


def _label(name: str) -> str:
    return f"$\\{name}$"  # the axes are Greek letters of the paper


def _beside(ctx: RenderContext, slug: str | None):
    """The saved results of the section drawn beside this one (its store and its engine's name), or (None, "") if absent."""
    from crosscheck.report.store import SectionStore

    if not slug:
        return None, ""
    store = SectionStore(ctx.store.root.parent / slug)
    if not store.exists("maps.json") or not store.exists("status.json"):
        return None, ""
    return store, store.read_json("status")["params"]["engine"]


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.report.interactive import outcome_maps_page, write_page
    from crosscheck.report.plotting import OUTCOME_COLORS

    P = ctx.params
    engine, name = P["engine"], engine_label(P["engine"])
    maps = ctx.store.read_json("maps")
    colors = {**OUTCOME_COLORS, NOT_SLIPPING: (0.8, 0.8, 0.8)}
    opts = ", ".join(f"{k} {v:g}" for k, v in P["options"].items())
    other, other_engine = _beside(ctx, P.get("beside"))
    blocks = [_intro(ctx, maps, name, opts, None if other is None else engine_label(other_engine))]
    blocks += _warnings(maps, name)
    blocks += _compliant_jams(ctx, name)
    page_rel = f"figures/{ctx.slug}/outcome_maps.html"
    pages, boundary_rows = [], []
    conf = 0
    diffs = {"difference": [], "outcome": []}
    for mp in maps:
        block, page, row = _map(ctx, mp, engine, name, other, other_engine, colors)
        block.data.append(page_rel)
        blocks.append(block)
        pages.append(page)
        boundary_rows.append(row)
        (run,) = mp["runs"]
        conf = conf + np.asarray(run["confusion"])
        for k in ("difference", "outcome"):
            diffs[k] += mp["time_difference"][k]
    names_ = {
        **{k: OUTCOME_NAMES[k].lower() for k in sorted(OUTCOME_COLORS)},
        NOT_SLIPPING: "not slipping at t = 0 (not compared)",
    }
    write_page(
        ctx.out / page_rel,
        outcome_maps_page(
            f"Analytic vs {name}: outcome maps (hover a cell)",
            pages,
            colors=colors,
            names=names_,
            intro=f"Each cell is one start (alpha = {P['alpha']:g}, scaled units); its tooltip gives the state, b and p "
            f"(eqs. b, p), the analytic first event and time, and each engine's outcome and time ({name}: {opts}).",
        ),
    )
    blocks.append(_confusion(ctx, maps, conf, name))
    blocks.append(
        Table(
            caption=f"Where {name} disagrees: compared starts on an analytic boundary of the map against the interior.",
            header=["map", "compared", "on a boundary", "disagree", "of which on a boundary", "interior"],
            rows=boundary_rows,
            data=ctx.data("maps.json"),
        )
    )
    blocks += _by_distance(ctx, maps)
    if diffs["difference"]:
        blocks += _event_time_errors(ctx, diffs, name)
    return blocks


def _intro(ctx: RenderContext, maps: list, name: str, opts: str, other_name: str | None) -> Text:
    """What a cell and each panel of the maps are."""
    P = ctx.params
    return Text(
        f"Each cell is one start (alpha = {P['alpha']:g}), compared over the scaled horizon {P['horizon']:g} by "
        f"`crosscheck.studies.agreement.agreement_study` ({name}: {opts}). Grey: not "
        f"slipping at t = 0 (b >= 0 or p <= 0), not compared. Panels: the analytic first event, {name}'s outcome (counted only up to the "
        "analytic comparison time; a JAM is judged against the engine's own friction direction), "
        + (f"{other_name}'s outcome on the same starts (its own section), " if other_name is not None else "")
        + "and where "
        f"{name} and the analytic model disagree. A {name} STICK where the theory slips on but slower than {name}'s STICK "
        f"floor (slip speed {_floors(maps)}, below which the classifier calls a contact stuck) is compared as that slip, "
        f"which it cannot be told from (`crosscheck.studies.comparison.stick_from`; {_stick_as_slip(maps)} here). Hover the cells of the interactive maps (`figures/{ctx.slug}/outcome_maps.html`, "
        "linked under each map) for each start's state and its analytic and engine outcomes and times."
    )


def _warnings(maps: list, name: str) -> list:
    """The engine's own console warnings during the runs, captured (crosscheck.engines.mujoco.warning_counts)."""
    warned: dict[str, int] = {}
    for mp in maps:
        for r in mp["runs"]:
            for kind, count in (r.get("engine_warnings") or {}).items():
                warned[kind] = warned.get(kind, 0) + int(count)
    if not warned:
        return []
    return [
        Text(
            f"{name} warned during these runs: "
            + "; ".join(f'{n} x "{k}"' for k, n in sorted(warned.items()))
            + ". Each is MuJoCo resetting a run after an instability; the classifier records the run's divergence (DIVERGED unless an event came first)."
        )
    ]


def _compliant_jams(ctx: RenderContext, name: str) -> list:
    """The JAMs below mu_P that the engine's compliant law gives (``_check_no_iwc``): an engine finding, named."""
    if not ctx.store.exists("jams_below_mu_P.json"):
        return []
    doc = ctx.store.read_json("jams_below_mu_P")
    jams, twin = [j for j in doc["jams"] if j["kind"] == "compliant"], doc["compliant_twin"]
    if not jams:
        return []
    starts = "; ".join(
        f"theta {j['theta']:g}, varphi {j['varphi']:g}, Psi {j['Psi']:g}, Theta {j['Theta']:g}, mu {j['mu']:g} "
        f"(JAM at t = {j['event_time']:g})"
        for j in jams
    )
    return [
        Text(
            f"Engine finding: below mu_P, where the rigid theory forbids it (p > 0), {name} jams from {len(jams)} "
            f"start{'' if len(jams) == 1 else 's'}: {starts}. The compliant rod with its contact law (eps "
            f"{twin['eps']:g}, xi {twin['xi']:g}, r {twin['radius']:g}) jams there too and slips at eps / {STIFFER:g}: "
            "a compliant contact of finite eps stops the slip hard where p > 0 is small (its normal mode's time "
            "eps / sqrt(p) is not short against the slip), which only the rigid limit eps -> 0 rules out."
        )
    ]


def _map(ctx: RenderContext, mp: dict, engine: str, name: str, other, other_engine, colors: dict):
    """One map: its figure (analytic, engine, the engine beside, where they differ), its interactive page and its row
    of the boundary table."""
    from matplotlib.patches import Patch

    from crosscheck.report.format import engine_label
    from crosscheck.report.interactive import GridMap, Panel, engine_line, start_tooltip
    from crosscheck.report.plotting import categorical_image, outcome_legend, plt

    other_name = engine_label(other_engine)
    t = ctx.store.read_table(f"events_{mp['name']}", text=("analytic_reason",))
    x, y = np.asarray(mp["x"]["values"]), np.asarray(mp["y"]["values"])
    # EventGrid points are in C order of (theta, varphi, Theta, Psi, mu, eta): put them on the (y, x) image grid
    xi = np.abs(t[mp["x"]["name"]][:, None] - x[None, :]).argmin(axis=1)  # nearest: the CSV keeps 12 digits
    yi = np.abs(t[mp["y"]["name"]][:, None] - y[None, :]).argmin(axis=1)

    def image(values):
        img = np.full((y.size, x.size), np.nan)
        img[yi, xi] = values
        return img

    slipping = t["slipping"] == 1
    a = np.where(slipping, t["analytic_outcome"], NOT_SLIPPING)
    o = (
        other.read_table(f"events_{mp['name']}", text=("analytic_reason",))
        if other is not None and other.exists(f"events_{mp['name']}.csv")
        else None
    )
    panels = 3 if o is None else 4
    fig, axes = plt.subplots(1, panels, figsize=(3.85 * panels, 3.6), sharey=True)
    categorical_image(axes[0], x, y, image(a), colors)
    axes[0].set_title("analytic first event")
    categorical_image(axes[1], x, y, image(t[engine]), colors)
    axes[1].set_title(name)
    # below the panels, not over the data, with every colour used: grey is "not compared"
    used = [a[slipping], t[engine][slipping]] + ([o[other_engine][o["slipping"] == 1]] if o is not None else [])
    handles = outcome_legend(axes[1], np.concatenate(used)).legend_handles
    axes[1].get_legend().remove()
    handles.append(Patch(color=colors[NOT_SLIPPING], label="not slipping at t = 0 (not compared)"))
    fig.legend(
        handles=handles, loc="outside lower center", ncol=len(handles), fontsize=7, frameon=False
    )  # constrained layout makes room
    if o is not None:
        oi = np.abs(o[mp["x"]["name"]][:, None] - x[None, :]).argmin(axis=1)
        oj = np.abs(o[mp["y"]["name"]][:, None] - y[None, :]).argmin(axis=1)
        img = np.full((y.size, x.size), np.nan)
        img[oj, oi] = o[other_engine]
        categorical_image(axes[2], x, y, img, colors)
        axes[2].set_title(f"{other_name} (beside)")
    a_img = image(a)
    edge = boundary_cells(np.nan_to_num(a_img, nan=-9))
    m_img = image(t[engine])
    # the same panels as SVG cells whose tooltips give each start (crosscheck.report.interactive)
    tips = [[""] * x.size for _ in y]
    for k in range(a.size):
        tips[yi[k]][xi[k]] = start_tooltip(t, k) + "\n" + engine_line(t, k, engine, name)
    svg_panels = [Panel("analytic first event", a_img), Panel(name, m_img)]
    if o is not None:
        for k in range(len(o[other_engine])):
            tips[oj[k]][oi[k]] += "\n" + engine_line(o, k, other_engine, other_name)
        svg_panels.append(Panel(f"{other_name} (beside)", img))
    agree = np.where(a_img == NOT_SLIPPING, NOT_SLIPPING, np.where(a_img == m_img, 0, np.where(edge, 1, 2)))
    categorical_image(
        axes[-1],
        x,
        y,
        agree,
        {NOT_SLIPPING: (0.8, 0.8, 0.8), 0: (0.95, 0.95, 0.95), 1: (0.95, 0.6, 0.2), 2: (0.8, 0.0, 0.0)},
    )
    axes[-1].set_title(f"{name} differs (orange: boundary, red: interior)", fontsize=9)
    for ax in axes:
        ax.set_xlabel(_label(mp["x"]["name"]))
    axes[0].set_ylabel(_label(mp["y"]["name"]))
    fixed = ", ".join(f"{k} = {v:g}" for k, v in mp["fixed"].items())
    (run,) = mp["runs"]
    block = ctx.figure(
        f"map_{mp['name']}",
        fig,
        f"Analytic vs {name} over ({mp['x']['name']}, {mp['y']['name']}) at {fixed}: {int(slipping.sum())} of {a.size} starts slip at t = 0; "
        f"{name} agrees on {100 * run['agreement']:.0f}% of the rated ones.",
        [f"events_{mp['name']}.csv", f"study_{mp['name']}.json", "maps.json"],
    )
    page = GridMap(
        f"({mp['x']['name']}, {mp['y']['name']}) at {fixed}",
        mp["x"]["name"],
        mp["y"]["name"],
        x,
        y,
        svg_panels,
        tips,
    )
    differ = (agree == 1) | (agree == 2)
    row = [
        mp["name"],
        str(int(slipping.sum())),
        str(int((edge & (agree != NOT_SLIPPING)).sum())),
        str(int(differ.sum())),
        str(int((agree == 1).sum())),
        str(int((agree == 2).sum())),
    ]
    return block, page, row


def _confusion(ctx: RenderContext, maps: list, conf, name: str):
    """The confusion matrix of all maps as a figure (the counts in its cells)."""
    from crosscheck.report.plotting import plt

    used = [
        i for i in range(len(conf)) if conf[i].sum() or conf[:, i].sum()
    ]  # results saved before an outcome was added have fewer
    sub = conf[np.ix_(used, used)]
    names = [OUTCOME_NAMES[i].lower() for i in used]
    fig, ax = plt.subplots(figsize=(4.6, 3.8))
    ax.imshow(np.log1p(sub), cmap="Blues")
    for i in range(len(used)):
        for j in range(len(used)):
            ax.text(
                j,
                i,
                str(sub[i, j]),
                ha="center",
                va="center",
                fontsize=9,
                color="k" if sub[i, j] < sub.max() / 2 else "w",
            )
    ax.set_xticks(range(len(used)), names, rotation=30)
    ax.set_yticks(range(len(used)), names)
    ax.set_xlabel(name)
    ax.set_ylabel("analytic first event")
    total, diag = int(sub.sum()), int(np.trace(sub))
    # the counts are printed in the cells and saved in maps.json: no second copy as a table
    return ctx.figure(
        "confusion",
        fig,
        f"Confusion matrix, all maps (rows: analytic first event; columns: {name} as compared; the count "
        f"in each cell): {diag} of {total} compared starts on the diagonal ({100 * diag / max(total, 1):.0f}%).",
        ["maps.json"] + [f"study_{mp['name']}.json" for mp in maps],
    )


def _by_distance(ctx: RenderContext, maps: list) -> list:
    """Agreement by the probed distance of a start to the analytic boundary (a table, when the maps probed it)."""
    dist_rows = []
    for mp in maps:
        (run,) = mp["runs"]
        for b in run.get("by_distance", []):
            if b["n"] and b["agreement"] is not None:
                dist_rows.append(
                    [
                        mp["name"],
                        f"[{b['distance'][0]:g}, {b['distance'][1]:g})",
                        str(b["n"]),
                        f"{100 * b['agreement']:.0f}%",
                    ]
                )
    if not dist_rows:  # the quick report does not probe the distance (boundary_directions = 0)
        return []
    return [
        Table(
            caption="Agreement by the probed distance of the start to the analytic event boundary (scaled units).",
            header=["map", "distance", "n", "agreement"],
            rows=dist_rows,
            data=ctx.data(*[f"study_{mp['name']}.json" for mp in maps]),
        )
    ]


def _event_time_errors(ctx: RenderContext, diffs: dict, name: str) -> list:
    """Where the engine and the analytic model report the same event: a histogram of their time differences and a
    table of them."""
    from crosscheck.report.plotting import OUTCOME_COLORS, plt

    dd, oo = np.asarray(diffs["difference"]), np.asarray(diffs["outcome"])
    fig, ax = plt.subplots(figsize=(6, 3.6))
    rows = []
    bins = np.histogram_bin_edges(dd, bins=30)  # one set of bins for every event, stacked: each stays visible
    stack, colors_, labels = [], [], []
    for event, code in (("LIFTOFF", 1), ("STICK", 2), ("JAM", 3)):
        s = oo == event
        if s.any():
            stack.append(dd[s])
            colors_.append(OUTCOME_COLORS[code])
            labels.append(f"{event.lower()} ({int(s.sum())})")
            rows.append(
                [
                    event.lower(),
                    str(int(s.sum())),
                    f"{np.median(dd[s]):+.3g}",
                    f"{np.median(np.abs(dd[s])):.3g}",
                    f"{np.max(np.abs(dd[s])):.3g}",
                ]
            )
    ax.hist(stack, bins=bins, color=colors_, label=labels, stacked=True, edgecolor="k", lw=0.3)
    ax.set_xlabel(f"t_{name} - t_analytic (scaled)")
    ax.set_ylabel("starts (stacked by event)")
    ax.legend(fontsize=7)
    return [
        ctx.figure(
            "event_time_errors",
            fig,
            f"Event-time errors where {name} and the analytic model report the same event, all maps.",
            ["maps.json"],
        ),
        Table(
            caption=f"Event-time differences ({name} - analytic, scaled time).",
            header=["event", "n", "median", "median |diff|", "max |diff|"],
            rows=rows,
            data=ctx.data("maps.json"),
        ),
    ]


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
