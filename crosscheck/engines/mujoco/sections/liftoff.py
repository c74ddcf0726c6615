"""MuJoCo's lift-off onset against Psi_L (eq. psil) and its convergence in the timestep.

At theta = theta_L, Theta = 0, varphi = -pi/2 (eta = 1) the free acceleration
b = Psi^2 cos^2 theta_L sin theta_L - 1 changes sign at Psi = Psi_L, for every
mu: below Psi_L the rod slips, above it lifts off (eqs. thetal, psil).  For
each mu and MuJoCo timestep the smallest Psi at which MuJoCo reports LIFTOFF
at t = 0 (the instantaneous decision the paper's Psi_L is about; a slipping
tip can also be thrown up a step later by the soft contact's friction spike,
which is not this onset) is found by ``crosscheck.studies.onset.liftoff_onset``
(bisection over the engine's batched sweeps: ``rounds`` grids of ``n_per_round`` values of
Psi from Psi_L +- ``half_width``; the onset is the first grid value that
lifts off, the resolution the final grid spacing).

Reported: the onset, the resolution, and the difference from Psi_L against
the timestep.  Check, at every timestep with a
derived tolerance: onset - Psi_L within ``MUJOCO_LIFTOFF_ONSET`` (timesteps up
to the default 3e-4) or ``MUJOCO_LIFTOFF_ONSET_COARSE`` (up to 3.13e-3), the
MuJoCo leg's bound (Psi_L^3/6)(3 dt)^2 for the three rows of b > 0 that
LIFTOFF needs, widened by the grid's resolution.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import critical

SLUG = "mujoco_liftoff"


def params(quick: bool) -> dict:
    return {
        "engine": "mujoco",
        "alpha": 3.0,
        "mu": [0.5, 1.4] if quick else [0.3, 0.5, 1.0, 1.4, 3.0],
        "timestep": [3e-3, 1e-3, 3e-4] if quick else [3e-3, 1e-3, 3e-4, 1e-4, 3e-5],
        "half_width": 1e-3,
        "n_per_round": 17 if quick else 33,
        "rounds": 4 if quick else 5,
    }


def run(ctx: RunContext) -> None:
    from crosscheck.engines.mujoco.tolerances import MUJOCO_LIFTOFF_ONSET, MUJOCO_LIFTOFF_ONSET_COARSE
    from crosscheck.rod import Rod
    from crosscheck.studies.onset import liftoff_onset

    P = ctx.params
    rod = Rod.scaled(P["alpha"])
    cols = {k: [] for k in ("mu", "timestep", "onset", "resolution", "onset_minus_Psi_L", "bound")}
    pairs = [(mu, dt) for mu in P["mu"] for dt in P["timestep"]]
    for mu, dt in ctx.progress(pairs, desc="lift-off onset"):
        onset, res = liftoff_onset(
            rod, mu, engine=P["engine"], timestep=dt, rounds=P["rounds"], n=P["n_per_round"], half_width=P["half_width"]
        )
        # the MuJoCo leg's bound on the delay of the onset (three rows of b > 0; crosscheck.tolerances, MUJOCO_LIFTOFF_ONSET)
        bound = critical.Psi_L**3 / 6 * (3 * dt) ** 2
        for k, v in (
            ("mu", mu),
            ("timestep", dt),
            ("onset", onset),
            ("resolution", res),
            ("onset_minus_Psi_L", onset - critical.Psi_L),
            ("bound", bound),
        ):
            cols[k].append(v)
        ctx.store.write_table("onset", cols)
        # the onset is the first grid value that lifts off: Psi_L - res < onset <= Psi_L + bound + res
        if dt <= 3e-4 * (1 + 1e-9):
            tol, name = MUJOCO_LIFTOFF_ONSET, "MUJOCO_LIFTOFF_ONSET"
        elif dt <= 3.13e-3 * (1 + 1e-9):
            tol, name = MUJOCO_LIFTOFF_ONSET_COARSE, "MUJOCO_LIFTOFF_ONSET_COARSE"
        else:
            continue  # no derived bound for coarser steps
        err = onset - critical.Psi_L
        ctx.check(
            f"mu = {mu:g}, timestep {dt:g}: MuJoCo's lift-off onset = Psi_L = {critical.Psi_L:.7f}",
            -res <= err <= tol.atol + res,
            value=err,
            allowance=tol.atol + res,
            detail=f"onset {onset:.9f}, grid resolution {res:.1e}; {name}: {tol.why}",
        )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, plt

    P = ctx.params
    t = ctx.store.read_table("onset")
    fig, ax = plt.subplots(figsize=(5.6, 4.0))
    order = np.argsort(t["timestep"])
    ax.loglog(t["timestep"][order], t["bound"][order], "k--", lw=1, label="bound $(\\Psi_L^3/6)(3\\,\\omega dt)^2$")
    for i, mu in enumerate(P["mu"]):
        s = t["mu"] == mu
        # the threshold lies in (onset - resolution, onset]: draw |onset - Psi_L| with the grid step as its bar
        err = np.abs(t["onset_minus_Psi_L"][s])
        ax.errorbar(
            t["timestep"][s] * (1 + 0.05 * i),
            np.maximum(err, 1e-12),
            yerr=[np.zeros(s.sum()), t["resolution"][s]],
            fmt="o",
            ms=4,
            capsize=2,
            color=LINE_COLORS[i % 7],
            label=f"$\\mu$ = {mu:g}",
        )
    ax.set_xlabel("MuJoCo timestep $\\omega\\, dt$ (scaled)")
    ax.set_ylabel("|onset - $\\Psi_L$|")
    ax.legend(fontsize=8)
    cap = (
        f"Lift-off onset (LIFTOFF at t = 0) in MuJoCo at theta = theta_L, Theta = 0, varphi = -pi/2, eta = 1: |onset - Psi_L| against the timestep; "
        f"bars: the grid's resolution ({P['rounds']} rounds of {P['n_per_round']} runs); dashed: the MuJoCo leg's bound on the delay of the onset "
        "(three rows of b > 0, MUJOCO_LIFTOFF_ONSET). Exact agreement is drawn at 1e-12."
    )
    blocks = [ctx.figure("liftoff_onset", fig, cap, ["onset.csv"])]
    rows = [
        [
            f"{t['mu'][i]:g}",
            f"{t['timestep'][i]:g}",
            f"{t['onset'][i]:.10f}",
            f"{t['resolution'][i]:.1e}",
            f"{t['onset_minus_Psi_L'][i]:+.2e}",
        ]
        for i in range(len(t["mu"]))
    ]
    blocks.append(
        Table(
            caption=f"Lift-off onset (LIFTOFF at t = 0) against Psi_L = {critical.Psi_L:.10f} (eq. psil).",
            header=["mu", "timestep", "onset", "resolution", "onset - Psi_L"],
            rows=rows,
            data=ctx.data("onset.csv"),
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="MuJoCo: lift-off onset against Psi_L",
    paper="eqs. thetal, psil (section 3.3)",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.studies.onset", "crosscheck.engines.mujoco.engine"),
)
