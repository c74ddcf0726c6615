"""MuJoCo vs analytic agreement as the timestep and the contact time constant shrink (a convergence table).

The (theta, Theta) grid of slipping starts of the first outcome map (coarser; many
of its starts slip for a while before their event, so event times are compared) is run
in MuJoCo with several (timestep, timeconst) settings; the analytic first
events are computed once.  For each setting: the fraction of starts with the
same event, the disagreements on analytic boundaries and in the interior
(``crosscheck.report.outcomes.boundary_cells``), and the median |event-time
difference| where both see the same LIFTOFF, STICK or JAM of a slipping start
(analytic event time > 0).  A rigid contact
is the limit dt -> 0, timeconst -> 0 (with timeconst >= 2 dt, MuJoCo's
"refsafe"), so disagreement should shrink along the table.
"""

from __future__ import annotations

import numpy as np

from crosscheck.outcome import Outcome
from crosscheck.report.grids import cell_centres
from crosscheck.report.outcomes import analytic_events, boundary_cells, mujoco_events
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.state import SlipState

SLUG = "mujoco_convergence"


def params(quick: bool) -> dict:
    settings = [{"timestep": 3e-3, "timeconst": 0.06}, {"timestep": 1e-3, "timeconst": 0.06}, {"timestep": 3e-4, "timeconst": 0.06},
                {"timestep": 3e-4, "timeconst": 0.02}]
    if not quick:
        settings += [{"timestep": 1e-4, "timeconst": 0.02}, {"timestep": 1e-4, "timeconst": 0.006}]
    n = 8 if quick else 24
    return {"alpha": 3.0, "horizon": 2.0, "Psi": 0.0, "mu": 1.4, "varphi": -1.9, "eta": 1.0, "theta": [0.2, 1.5], "Theta": [-1.5, 1.5], "n_theta": n, "n_Theta": n,
            "settings": settings}


def run(ctx: RunContext) -> None:
    P = ctx.params
    theta, Theta = cell_centres(*P["theta"], P["n_theta"]), cell_centres(*P["Theta"], P["n_Theta"])
    states = [SlipState(theta=x, varphi=P["varphi"], Theta=y, Psi=P["Psi"], eta=P["eta"]) for y in Theta for x in theta]  # rows are Theta
    mus = np.full(len(states), P["mu"])
    ana = analytic_events(states, mus, P["alpha"], horizon=P["horizon"], progress=ctx.progress)
    ctx.store.write_table("analytic", ana)
    a = ana["analytic_outcome"].astype(int)
    edge = boundary_cells(a.reshape(Theta.size, theta.size)).ravel()
    cols = {k: [] for k in ("timestep", "timeconst", "agree_fraction", "disagree_at_boundary", "disagree_interior", "median_abs_time_difference", "events_compared")}
    for i, opt in enumerate(ctx.progress(P["settings"], desc="MuJoCo settings")):
        mj = mujoco_events(states, mus, P["alpha"], horizon=P["horizon"], mujoco_options=opt)
        ctx.store.write_table(f"mujoco_{i}", mj)
        m = mj["mujoco_outcome"]
        differ = a != m
        # timed events: both see the same LIFTOFF, STICK or JAM of a slipping start (analytic time > 0)
        same = ~differ & np.isin(a, [Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM]) & np.isfinite(mj["mujoco_time"]) & (ana["analytic_time"] > 0)
        dt = np.abs(mj["mujoco_time"][same] - ana["analytic_time"][same])
        for k, v in (("timestep", opt["timestep"]), ("timeconst", opt["timeconst"]), ("agree_fraction", float(np.mean(~differ))),
                     ("disagree_at_boundary", int((differ & edge).sum())), ("disagree_interior", int((differ & ~edge).sum())),
                     ("median_abs_time_difference", float(np.median(dt)) if dt.size else float("nan")), ("events_compared", int(same.sum()))):
            cols[k].append(v)
        ctx.store.write_table("convergence", cols)
    ctx.store.write_json("grid", {"theta": theta, "Theta": Theta, "boundary_cells": int(edge.sum()), "cells": int(edge.size)})


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, plt

    P = ctx.params
    c = ctx.store.read_table("convergence")
    g = ctx.store.read_json("grid")
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.6))
    for j, tc in enumerate(sorted(set(c["timeconst"]), reverse=True)):
        s = c["timeconst"] == tc
        a1.plot(c["timestep"][s], 100 * c["agree_fraction"][s], "o-", color=LINE_COLORS[j], label=f"timeconst {tc:g}")
        a2.plot(c["timestep"][s], c["median_abs_time_difference"][s], "o-", color=LINE_COLORS[j], label=f"timeconst {tc:g}")
    for ax in (a1, a2):
        ax.set_xscale("log")
        ax.set_xlabel("MuJoCo timestep (scaled)")
        ax.invert_xaxis()
        ax.legend(fontsize=7)
    a1.set_ylabel("same first event [%]")
    a2.set_ylabel("median |t_MuJoCo - t_analytic|")
    if np.nanmin(c["median_abs_time_difference"]) > 0:
        a2.set_yscale("log")
    cap = (f"Agreement with the analytic first event on a {P['n_theta']} x {P['n_Theta']} (theta, Theta) grid (Psi = {P['Psi']:g}, mu = {P['mu']:g}, "
           f"varphi = {P['varphi']:g}, eta = {P['eta']:g}) as the timestep (right: smaller) and the contact time constant shrink.")
    rows = [[f"{c['timestep'][i]:g}", f"{c['timeconst'][i]:g}", f"{100 * c['agree_fraction'][i]:.1f}%", f"{int(c['disagree_at_boundary'][i])}", f"{int(c['disagree_interior'][i])}",
             f"{c['median_abs_time_difference'][i]:.3g}", f"{int(c['events_compared'][i])}"] for i in range(len(c["timestep"]))]
    return [ctx.figure("convergence", fig, cap, ["convergence.csv", "analytic.csv"] + [f"mujoco_{i}.csv" for i in range(len(rows))]),
            Table(caption=f"Convergence table ({g['cells']} starts, {g['boundary_cells']} on an analytic boundary).",
                  header=["timestep", "timeconst", "same event", "disagree on boundary", "disagree interior", "median |dt event|", "events timed"], rows=rows,
                  data=ctx.data("convergence.csv"))]


SECTION = Section(slug=SLUG, title="MuJoCo vs analytic: convergence in timestep and contact time constant", paper="issue 4 item 5c",
                  params=params, run=run, render=render, requires=("crosscheck.mujoco_sweep", "crosscheck.gb"))
