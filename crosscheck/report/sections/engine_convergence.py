"""A contact engine's agreement with the analytic first event as the timestep and the contact time constant shrink.

``crosscheck.studies.agreement.agreement_study`` on one grid of starts with
several (timestep, timeconst) settings of the engine named in the parameters
(MuJoCo here; the rigid engine in ``rigid_convergence``), and its ``convergence_table``: per setting, the agreement with the
analytic first event (also
with a JAM counted as any stop, and split into starts on the planar section
varphi = -pi/2, Psi = 0 and off it) and the median |t_MuJoCo - t_analytic|.
A rigid contact is the limit dt -> 0, timeconst -> 0 (timeconst >= 2 dt,
MuJoCo's "refsafe"), so disagreement should shrink down the table if the
soft contact were the only difference.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text


def params(quick: bool, engine: str, settings: list, n: int | None = None) -> dict:
    """The section's parameters: ``engine`` at each of ``settings`` on an n x n grid in (theta, Theta) (7 quick, 20 full by default)."""
    settings = [dict(s) for s in settings]
    n = n or (7 if quick else 20)
    return {
        "engine": engine,
        "alpha": 3.0,
        "horizon": 2.0,
        "settings": settings,
        "grid": {
            "theta": [0.2, 1.5, n],
            "varphi": [-1.9, -1.5707963267948966],
            "Theta": [-1.5, 1.5, n],
            "Psi": [0.0],
            "mu": [1.4],
            "eta": [1.0],
        },
    }


def run(ctx: RunContext) -> None:
    from crosscheck.studies.agreement import agreement_study, convergence_table
    from crosscheck.studies.grids import EventGrid

    P = ctx.params
    g = P["grid"]
    grid = EventGrid(
        theta=tuple(cell_centres(*g["theta"])),
        varphi=tuple(g["varphi"]),
        Theta=tuple(cell_centres(*g["Theta"])),
        Psi=tuple(g["Psi"]),
        mu=tuple(g["mu"]),
        eta=tuple(g["eta"]),
    )
    # the theory's events of this grid, which every engine's convergence section shares (``RunContext.shared``)
    events, _ = ctx.shared(
        "analytic_events", "convergence", {"grid": g, "alpha": P["alpha"], "horizon": P["horizon"]}, ".npz"
    )
    res = agreement_study(
        grid,
        engine=P["engine"],
        settings=P["settings"],
        alpha=P["alpha"],
        horizon=P["horizon"],
        rng=ctx.rng,
        boundary_directions=0,
        progress=ctx.show_progress,
        analytic_cache=events,
        **(ctx.sweeps or {}),
    )
    (ctx.store.root / "study.json").write_text(res.to_json() + "\n")
    rows = convergence_table(res)
    ctx.store.write_table("convergence", {k: [r[k] for r in rows] for k in rows[0]})


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.report.plotting import LINE_COLORS, plt

    P = ctx.params
    name = engine_label(P["engine"])
    c = ctx.store.read_table("convergence", text=("engine",))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.6))
    for k, tc in enumerate(sorted(set(c["timeconst"]), reverse=True)):
        s = c["timeconst"] == tc
        a1.plot(c["timestep"][s], 100 * c["agreement"][s], "o-", color=LINE_COLORS[k % 7], label=f"timeconst {tc:g}")
        a2.plot(
            c["timestep"][s],
            c["median_abs_time_difference"][s],
            "o-",
            color=LINE_COLORS[k % 7],
            label=f"timeconst {tc:g}",
        )
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator

    from crosscheck.report.finding import CONVERGED, NOT_CONVERGED

    # the whole 0-100 % range, with the verdict rule's two thresholds: a few points of change are not drawn as a cliff
    a1.set_ylim(0, 100)
    for y, txt in ((100 * CONVERGED, "converges above"), (100 * NOT_CONVERGED, "does not converge below")):
        a1.axhline(y, color="0.6", lw=0.8, ls="--")
        a1.text(
            0.02,
            y,
            f" {txt} {y:.0f} %",
            transform=a1.get_yaxis_transform(),
            fontsize=6,
            color="0.4",
            va="bottom" if y > 92 else "top",
        )
    steps = sorted(set(float(x) for x in c["timestep"]))
    for ax in (a1, a2):
        ax.set_xscale("log")
        ax.set_xticks(steps, [f"{x:g}" for x in steps])  # the timesteps run, labelled as set
        ax.xaxis.set_minor_locator(NullLocator())
        ax.set_xlabel(f"{name} timestep (scaled)")
        ax.invert_xaxis()
        ax.legend(fontsize=6, loc="lower right" if ax is a1 else "best")
    a1.set_ylabel("same first event [%]")
    a2.set_ylabel(f"median |t_{name} - t_analytic|")
    medians = np.asarray(c["median_abs_time_difference"], float)
    medians = medians[~np.isnan(medians)]  # NaN: no event shared with the theory at that setting
    if medians.size and medians.min() > 0:
        a2.set_yscale("log")
        a2.yaxis.set_major_locator(
            LogLocator(base=10, subs=(1.0, 2.0, 5.0), numticks=12)
        )  # 1-2-5 ticks: labelled within one decade too
        a2.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        a2.yaxis.set_minor_formatter(NullFormatter())  # minor labels crowded the major ones
    g = P["grid"]
    varphi = " and ".join(_angle(v) for v in g["varphi"])
    cap = (
        f"{name}'s agreement with the analytic first event (crosscheck.studies.agreement.convergence_table) on {g['theta'][2]} x {g['Theta'][2]} starts in (theta, Theta) "
        f"at varphi = {varphi}, Psi = {g['Psi'][0]:g}, mu = {g['mu'][0]:g}, eta = {g['eta'][0]:g}, as the timestep (right: smaller) and the contact time constant shrink: "
        "one line per contact time constant. Left: the full 0-100 % range, dashed at the verdict rule's 95 % and 90 %."
    )
    rows = [
        [
            f"{c['timestep'][i]:g}",
            f"{c['timeconst'][i]:g}",
            f"{int(c['n_rated'][i])}",
            f"{100 * c['agreement'][i]:.1f}%",
            f"{100 * c['agreement_jam_as_stop'][i]:.1f}%",
            f"{100 * c['agreement_planar'][i]:.1f}% of {int(c['n_planar'][i])}",
            f"{100 * c['agreement_off_plane'][i]:.1f}% of {int(c['n_off_plane'][i])}",
            f"{c['median_abs_time_difference'][i]:.3g}",
        ]
        for i in range(len(c["timestep"]))
    ]
    header = ["timestep", "timeconst", "rated", "agreement", "JAM as stop", "planar", "off plane", "median |dt event|"]
    caption = "Convergence table: agreement (also with JAM counted as any stop; on and off the planar section) and median |event-time difference|."
    if (
        "engine_warnings" in c and np.nansum(c["engine_warnings"]) > 0
    ):  # the engine's own warnings (each a run it reset: DIVERGED)
        header += [f"{name} warnings"]
        for i, r in enumerate(rows):
            r.append(str(int(c["engine_warnings"][i])))
    if "unconverged_steps" in c:  # an engine with a solver: its health beside every row
        header += ["steps missing the solver tolerance (states)"]
        for i, r in enumerate(rows):
            r.append(f"{int(c['unconverged_steps'][i])} ({int(c['unconverged_states'][i])})")
        caption += " Solver health: steps whose NCP missed the tolerance after every retry, and in how many states."
    return [
        ctx.figure("convergence", fig, cap, ["convergence.csv", "study.json"]),
        _trends(c, P["engine"]),
        Table(caption=caption, header=header, rows=rows, data=ctx.data("convergence.csv", "study.json")),
    ]


def _angle(v: float) -> str:
    """An angle as the paper writes it: -pi/2 rather than -1.5707963267948966, else rounded."""
    for k, word in ((-0.5, "-pi/2"), (0.5, "pi/2"), (1.0, "pi"), (-1.0, "-pi"), (0.0, "0")):
        if abs(v - k * np.pi) < 1e-12:
            return word
    return f"{v:.4g}"


def _trends(c: dict, engine: str) -> Text:
    """The table read one parameter at a time (``findings.convergence_trends``), with the verdict and the rule that gave it."""
    from crosscheck import engines
    from crosscheck.report.finding import convergence_trends

    rows = [{k: c[k][i] for k in ("timestep", "timeconst", "agreement")} for i in range(len(c["timestep"]))]
    words = {"timestep": "timestep", "timeconst": "contact time constant"}
    parts = []
    for t in convergence_trends(rows):
        at = ", ".join(f"{words[o]} {v:g}" for o, v in t.fixed.items())
        parts.append(
            f"In the {words[t.parameter]}"
            + (f" at {at}" if at else "")
            + ": "
            + " -> ".join(f"{100 * float(r['agreement']):.1f} %" for r in t.rows)
            + f" ({words[t.parameter]} "
            + " -> ".join(f"{float(r[t.parameter]):g}" for r in t.rows)
            + f"): {t.verdict} ({t.why})."
        )
    try:
        compliant = engines.get(engine).has("compliant")
    except ValueError:
        compliant = False
    if compliant:
        parts.append(
            "The rigid theory is this engine's limit only as the contact time constant goes to 0 (with the timestep below it); "
            "the timestep going to 0 at a fixed time constant tends to the compliant model, whose first events can differ from the theory's."
        )
    return Text(" ".join(parts))


def section(spec, settings: dict, n: dict | None = None) -> Section:
    """The convergence of the engine ``spec`` (an ``EngineSpec``) over ``settings`` ({"quick": [...], "full": [...]} of
    option dicts) as the section ``<slug>_convergence``, on an n x n grid in (theta, Theta) (``n``: {"quick": ..., "full": ...})."""
    full = settings["full"]
    varied = sorted(k for k in {k for s in full for k in s} if len({repr(s.get(k)) for s in full}) > 1)
    return Section(
        slug=f"{spec.slug}_convergence",
        title=f"{spec.label} vs analytic: convergence in {' and '.join(varied)}",
        paper="sections 3.1, 4",
        params=lambda quick: params(
            quick,
            spec.name,
            settings["quick" if quick else "full"],
            None if n is None else n["quick" if quick else "full"],
        ),
        run=run,
        render=render,
        requires=("crosscheck.studies.agreement", spec.module or "crosscheck.engines"),
    )
