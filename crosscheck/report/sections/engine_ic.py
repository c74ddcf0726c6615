"""An engine through the paper's two initial conditions of Fig. 20 (IC1, IC2): its trajectory beside the theory's first event.

IC1 and IC2 (``crosscheck.theory.paper.FIG20_INITIAL_CONDITIONS``, alpha = 3,
mu = 1.4 > mu_P) start close to each other near p = 0; the theory jams from
one and lifts off from the other.  Each engine runs both at the options of
its outcome maps; the section draws theta, the slip speed eta and the
window-mean normal force against the theory's slipping solution (eq. FZ up to
its event) and tabulates both first events.  One section per registered
engine with maps (``<slug>_ic``).  Scaled units (section 2.1).
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table


def params(quick: bool, engine: str, options: dict) -> dict:
    return {"engine": engine, "options": dict(options), "alpha": 3.0, "mu": 1.4, "horizon": 0.5}


def run(ctx: RunContext) -> None:
    from crosscheck import engines
    from crosscheck.engines.classifier import Thresholds, window_sum
    from crosscheck.rod import Rod
    from crosscheck.state import SlipState
    from crosscheck.theory import analytic
    from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS
    from crosscheck.theory.slipping import slip_until_event

    P = ctx.params
    spec = engines.get(P["engine"])
    rod, mu, alpha = Rod.scaled(P["alpha"]), P["mu"], P["alpha"]
    runs = []
    starts = [SlipState(**ic) for ic in FIG20_INITIAL_CONDITIONS]
    engine_runs = spec.simulate_each(rod, starts, mu, horizon=P["horizon"], **P["options"])
    for k, (s, e) in enumerate(zip(starts, engine_runs), start=1):
        a = slip_until_event(s, mu, alpha, t_max=P["horizon"])
        rec = e.record
        w = Thresholds().window_rows(e.options.timestep)
        mean_force = window_sum(rec.normal_force, w) / w
        keep = slice(None, None, max(1, len(rec) // 400))
        ctx.store.write_table(
            f"engine_ic{k}",
            {
                "t": rec.t[keep],
                "theta": rec.theta[keep],
                "eta": rec.eta[keep],
                "normal_force_window_mean": mean_force[keep],
                "gap": rec.gap[keep],
            },
        )
        x = a.x
        Fz = analytic.normal_force(x[:, 3], x[:, 5], x[:, 4], x[:, 1], mu, alpha) if len(x) > 1 else np.array([np.nan])
        ctx.store.write_table(f"analytic_ic{k}", {"t": a.t, "theta": x[:, 4], "eta": x[:, 0], "normal_force": Fz})
        runs.append(
            {
                "ic": k,
                "analytic_outcome": a.outcome.name,
                "analytic_time": a.time,
                "engine_outcome": e.outcome.name,
                "engine_time": e.event_time,
                "same_event": a.outcome.name == e.outcome.name,
            }
        )
    ctx.store.write_json("runs", runs)


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.report.plotting import LINE_COLORS, plt

    P = ctx.params
    name = engine_label(P["engine"])
    runs = ctx.store.read_json("runs")
    fig, axes = plt.subplots(3, len(runs), figsize=(10, 7), sharex="col", squeeze=False)
    for j, r in enumerate(runs):
        e, a = ctx.store.read_table(f"engine_ic{r['ic']}"), ctx.store.read_table(f"analytic_ic{r['ic']}")
        for i, (key, akey, label) in enumerate(
            (
                ("theta", "theta", "theta [rad]"),
                ("eta", "eta", "eta (slip speed)"),
                ("normal_force_window_mean", "normal_force", "normal force [m g]"),
            )
        ):
            ax = axes[i, j]
            ax.plot(
                e["t"], e[key], color=LINE_COLORS[1], lw=1.2, label=f"{name}" + (" (window mean)" if i == 2 else "")
            )
            ax.plot(a["t"], a[akey], "--", color=LINE_COLORS[0], lw=1.2, label="theory (to its event)")
            ax.set_ylabel(label)
            if i == 2:
                ax.set_xlabel("t (scaled)")
                top = np.nanpercentile(np.abs(e[key]), 99) if np.isfinite(e[key]).any() else 1.0
                ax.set_ylim(-0.1 * top - 0.1, 1.2 * top + 0.1)
        axes[0, j].set_title(
            f"IC{r['ic']}: theory {r['analytic_outcome'].lower()}, {name} {r['engine_outcome'].lower()}"
        )
    axes[0, 0].legend(fontsize=7)
    cap = (
        f"The paper's IC1 and IC2 (Fig. 20; mu = {P['mu']:g}, alpha = {P['alpha']:g}) in {name} (solid, options {P['options']}) against the "
        "theory's slipping solution to its first event (dashed; normal force -b/p, eq. FZ)."
    )
    rows = [
        [
            f"IC{r['ic']}",
            f"{r['analytic_outcome']} at {r['analytic_time']:.4g}",
            f"{r['engine_outcome']} at {r['engine_time']:.4g}"
            if r["engine_time"] is not None and np.isfinite(r["engine_time"])
            else r["engine_outcome"],
            "yes" if r["same_event"] else "no",
        ]
        for r in runs
    ]
    data = [f"{w}_ic{r['ic']}.csv" for r in runs for w in ("engine", "analytic")] + ["runs.json"]
    return [
        ctx.figure("ic", fig, cap, data),
        Table(
            caption=f"First events from IC1 and IC2: the theory and {name}.",
            header=["start", "theory", name, "same event"],
            rows=rows,
            data=ctx.data("runs.json"),
        ),
    ]


def section(spec, options: dict) -> Section:
    """The IC section ``<slug>_ic`` of the engine ``spec`` at ``options`` ({"quick": ..., "full": ...})."""
    return Section(
        slug=f"{spec.slug}_ic",
        title=f"{spec.label}: the paper's IC1 and IC2 (Fig. 20)",
        paper="Fig. 20; eqs. FZ, f",
        params=lambda quick: params(quick, spec.name, options["quick" if quick else "full"]),
        run=run,
        render=render,
        requires=(spec.module or "crosscheck.engines", "crosscheck.theory.slipping"),
    )
