"""MuJoCo vs analytic: outcome maps over (Psi, mu) and over (theta, Theta) slices, confusion matrix, event-time errors.

Every cell of each map is one slipping start (tip on the plane, contact not
yet active in MuJoCo).  For each start the report records its LCP mode
(section 3.1), the analytic first event (``crosscheck.gb.slip_until_event``:
F_z = -b/p integrated until lift-off, p = 0 with b < 0 (JAM), eta = 0 (STICK)
or b = p = 0 (GB)) and MuJoCo's outcome (``crosscheck.mujoco_sweep.sweep``),
over the same horizon.  A start that is not slipping has its analytic event
at t = 0 (LIFTOFF if b > 0, JAM if p <= 0 with b <= 0).

The agreement map marks disagreements; a cell on an analytic boundary (a
4-neighbour with another analytic outcome) is where a finite grid, a soft
contact and a finite timestep are expected to differ, and the report counts
disagreements there and in the interior separately.  Event-time errors are
MuJoCo's event time minus the analytic one where both see the same event.
"""

from __future__ import annotations

import numpy as np

from crosscheck.outcome import Outcome
from crosscheck.report.grids import cell_centres
from crosscheck.report.outcomes import OUTCOME_NAMES, boundary_cells, confusion, first_events
from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text
from crosscheck.state import SlipState

SLUG = "mujoco_maps"


def params(quick: bool) -> dict:
    n = 10 if quick else 36
    return {
        "alpha": 3.0, "horizon": 2.0, "mujoco_options": {},
        "Psi_mu": {"theta": 1.0, "varphi": -1.9, "Theta": 0.0, "eta": 1.0, "Psi": [0.0, 3.0], "mu": [0.0, 3.0], "n_Psi": n, "n_mu": n},
        "theta_Theta": [{"Psi": 0.0, "mu": 1.4, "varphi": -1.9, "eta": 1.0}, {"Psi": 1.7, "mu": 1.4, "varphi": -1.9, "eta": 1.0}],
        "theta": [0.2, 1.5], "Theta": [-1.5, 1.5], "n_theta": n, "n_Theta": n,
    }


def _grids(P):
    """(name, title, x name, x values, y name, y values, state(x, y) -> (SlipState, mu))."""
    g = P["Psi_mu"]
    Psi, mu = cell_centres(*g["Psi"], g["n_Psi"]), cell_centres(*g["mu"], g["n_mu"])
    out = [("Psi_mu", f"(Psi, mu) at theta = {g['theta']:g}, varphi = {g['varphi']:g}, Theta = {g['Theta']:g}, eta = {g['eta']:g}", "Psi", Psi, "mu", mu,
            lambda x, y, g=g: (SlipState(theta=g["theta"], varphi=g["varphi"], Theta=g["Theta"], Psi=x, eta=g["eta"]), y))]
    theta, Theta = cell_centres(*P["theta"], P["n_theta"]), cell_centres(*P["Theta"], P["n_Theta"])
    for i, s in enumerate(P["theta_Theta"]):
        out.append((f"theta_Theta_{i}", f"(theta, Theta) at Psi = {s['Psi']:g}, mu = {s['mu']:g}, varphi = {s['varphi']:g}, eta = {s['eta']:g}", "theta", theta, "Theta", Theta,
                    lambda x, y, s=s: (SlipState(theta=x, varphi=s["varphi"], Theta=y, Psi=s["Psi"], eta=s["eta"]), s["mu"])))
    return out


def run(ctx: RunContext) -> None:
    P = ctx.params
    grids = []
    for name, title, xn, xv, yn, yv, make in _grids(P):
        pairs = [make(x, y) for y in yv for x in xv]  # row-major: rows are y
        res = first_events([s for s, _ in pairs], np.array([m for _, m in pairs]), P["alpha"], horizon=P["horizon"], progress=ctx.progress,
                           show_progress=ctx.show_progress, mujoco_options=P["mujoco_options"])
        ctx.store.write_table(f"events_{name}", res)
        grids.append({"name": name, "title": title, "x": {"name": xn, "values": xv}, "y": {"name": yn, "values": yv}})
        ctx.store.write_json("grids", grids)

    all_a, all_m, rows = [], [], {k: [] for k in ("grid", "outcome", "analytic_time", "mujoco_time", "difference")}
    boundary = []
    for g in grids:
        t = ctx.store.read_table(f"events_{g['name']}", text=("analytic_reason",))
        a, m = t["analytic_outcome"].astype(int), t["mujoco_outcome"].astype(int)
        all_a.append(a)
        all_m.append(m)
        shape = (len(g["y"]["values"]), len(g["x"]["values"]))
        edge = boundary_cells(a.reshape(shape)).ravel()
        differ = a != m
        boundary.append({"grid": g["name"], "cells": int(a.size), "boundary_cells": int(edge.sum()), "disagree": int(differ.sum()),
                         "disagree_at_boundary": int((differ & edge).sum()), "disagree_interior": int((differ & ~edge).sum())})
        same = (a == m) & np.isin(a, [Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM]) & np.isfinite(t["mujoco_time"])
        for i in np.flatnonzero(same):
            for k, v in (("grid", g["name"]), ("outcome", Outcome(a[i]).name), ("analytic_time", t["analytic_time"][i]), ("mujoco_time", t["mujoco_time"][i]),
                         ("difference", t["mujoco_time"][i] - t["analytic_time"][i])):
                rows[k].append(v)
    ctx.store.write_json("confusion", {"rows_analytic": OUTCOME_NAMES, "columns_mujoco": OUTCOME_NAMES,
                                       "counts": confusion(np.concatenate(all_a), np.concatenate(all_m))})
    ctx.store.write_json("boundary", boundary)
    ctx.store.write_table("event_time_errors", rows)


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import OUTCOME_COLORS, categorical_image, mode_image, mode_legend, outcome_legend, plt

    P = ctx.params
    grids = ctx.store.read_json("grids")
    blocks = [Text(f"Each cell: one slipping start (alpha = {P['alpha']:g}), run for the scaled horizon {P['horizon']:g} by the analytic model and by MuJoCo "
                   f"(options {P['mujoco_options'] or 'default'}). Left to right: the LCP mode of the start, the analytic first event, MuJoCo's outcome, and where they differ.")]
    for g in grids:
        t = ctx.store.read_table(f"events_{g['name']}", text=("analytic_reason",))
        x, y = np.asarray(g["x"]["values"]), np.asarray(g["y"]["values"])
        shape = (y.size, x.size)
        a, m = t["analytic_outcome"].reshape(shape), t["mujoco_outcome"].reshape(shape)
        fig, axes = plt.subplots(1, 4, figsize=(15, 3.6), sharey=True)
        mode_image(axes[0], x, y, t["mode"].reshape(shape))
        axes[0].set_title("LCP mode at the start")
        mode_legend(axes[0], loc="upper left", fontsize=6)
        categorical_image(axes[1], x, y, a, OUTCOME_COLORS)
        axes[1].set_title("analytic first event")
        categorical_image(axes[2], x, y, m, OUTCOME_COLORS)
        axes[2].set_title("MuJoCo outcome")
        outcome_legend(axes[2], np.concatenate([a.ravel(), m.ravel()]), loc="upper left", fontsize=6)
        edge = boundary_cells(a)
        agree = np.where(a == m, 0, np.where(edge, 1, 2))
        categorical_image(axes[3], x, y, agree, {0: (0.9, 0.9, 0.9), 1: (0.95, 0.6, 0.2), 2: (0.8, 0.0, 0.0)})
        axes[3].set_title("disagreement (orange: on a boundary, red: interior)")
        for ax in axes:
            ax.set_xlabel(f"$\\{g['x']['name']}$")  # the axes are Greek letters of the paper
        axes[0].set_ylabel(f"$\\{g['y']['name']}$")
        n_diff = int((a != m).sum())
        blocks.append(ctx.figure(f"map_{g['name']}", fig,
                                 f"Analytic vs MuJoCo over {g['title']}: {a.size} starts, {a.size - n_diff} agree ({100 * (a.size - n_diff) / a.size:.0f}%).",
                                 [f"events_{g['name']}.csv", "grids.json"]))
    conf = ctx.store.read_json("confusion")
    counts = np.asarray(conf["counts"])
    used = [i for i in range(len(OUTCOME_NAMES)) if counts[i].sum() or counts[:, i].sum()]
    fig, ax = plt.subplots(figsize=(4.6, 3.8))
    sub = counts[np.ix_(used, used)]
    ax.imshow(np.log1p(sub), cmap="Blues")
    for i in range(len(used)):
        for j in range(len(used)):
            ax.text(j, i, str(sub[i, j]), ha="center", va="center", fontsize=9, color="k" if sub[i, j] < sub.max() / 2 else "w")
    names = [OUTCOME_NAMES[i].lower() for i in used]
    ax.set_xticks(range(len(used)), names, rotation=30)
    ax.set_yticks(range(len(used)), names)
    ax.set_xlabel("MuJoCo outcome")
    ax.set_ylabel("analytic first event")
    total = counts.sum()
    agree = int(np.trace(counts))
    blocks.append(ctx.figure("confusion", fig, f"Confusion matrix over all {total} starts of the maps: {agree} ({100 * agree / total:.0f}%) on the diagonal.", ["confusion.json"]))
    blocks.append(Table(caption="Confusion matrix (rows: analytic first event; columns: MuJoCo outcome).", header=["analytic \\ MuJoCo"] + names,
                        rows=[[names[i]] + [str(v) for v in sub[i]] for i in range(len(used))], data=ctx.data("confusion.json")))
    bnd = ctx.store.read_json("boundary")
    rows = []
    for b in bnd:
        frac_cells = b["boundary_cells"] / b["cells"]
        frac_dis = b["disagree_at_boundary"] / b["disagree"] if b["disagree"] else float("nan")
        rows.append([b["grid"], str(b["cells"]), f"{b['boundary_cells']} ({100 * frac_cells:.0f}%)", str(b["disagree"]), f"{b['disagree_at_boundary']} ({100 * frac_dis:.0f}%)" if b["disagree"] else "0",
                     str(b["disagree_interior"])])
    blocks.append(Table(caption="Where the disagreements are: cells on an analytic boundary (a neighbour with another analytic first event) against the interior.",
                        header=["map", "cells", "boundary cells", "disagree", "of which on a boundary", "interior"], rows=rows, data=ctx.data("boundary.json")))
    e = ctx.store.read_table("event_time_errors", text=("grid", "outcome"))
    if len(e["difference"]):
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.6))
        for name, code in (("LIFTOFF", 1), ("STICK", 2), ("JAM", 3)):
            s = e["outcome"] == name
            if s.any():
                a1.hist(e["difference"][s], bins=30, color=OUTCOME_COLORS[code], alpha=0.8, label=f"{name.lower()} ({int(s.sum())})", edgecolor="k", lw=0.3)
                a2.plot(e["analytic_time"][s], e["difference"][s], "o", ms=3, color=OUTCOME_COLORS[code], mec="k", mew=0.3, label=name.lower())
        a1.set_xlabel("MuJoCo event time - analytic event time (scaled)")
        a1.set_ylabel("starts")
        a1.legend(fontsize=7)
        a2.axhline(0, color="k", lw=0.5)
        a2.set_xlabel("analytic event time (scaled)")
        a2.set_ylabel("MuJoCo - analytic")
        blocks.append(ctx.figure("event_time_errors", fig, "Event-time errors where both see the same event (LIFTOFF, STICK or JAM), all maps together.", ["event_time_errors.csv"]))
        rows = []
        for name in ("LIFTOFF", "STICK", "JAM"):
            s = e["outcome"] == name
            if s.any():
                d = e["difference"][s]
                rows.append([name.lower(), str(int(s.sum())), f"{np.median(d):+.3g}", f"{np.median(np.abs(d)):.3g}", f"{np.max(np.abs(d)):.3g}"])
        blocks.append(Table(caption="Event-time differences (MuJoCo - analytic, scaled time).", header=["event", "n", "median", "median |diff|", "max |diff|"], rows=rows,
                            data=ctx.data("event_time_errors.csv")))
    return blocks


SECTION = Section(slug=SLUG, title="MuJoCo vs analytic: outcome maps, confusion matrix, event times", paper="sections 3.1, 4 (Corollary 4.2); issue 4 item 5c",
                  params=params, run=run, render=render, requires=("crosscheck.mujoco_sweep", "crosscheck.gb"))
