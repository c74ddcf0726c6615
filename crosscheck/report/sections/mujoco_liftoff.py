"""MuJoCo's lift-off onset against Psi_L (eq. psil) and its convergence in the timestep.

At theta = theta_L, Theta = 0, varphi = -pi/2 (eta = 1) the free acceleration
b = Psi^2 cos^2 theta_L sin theta_L - 1 changes sign at Psi = Psi_L, for every
mu: below Psi_L the rod slips, above it lifts off (eqs. thetal, psil).  For
each mu and MuJoCo timestep the smallest Psi at which MuJoCo reports LIFTOFF
at t = 0 (the instantaneous decision the paper's Psi_L is about; a slipping
tip can also be thrown up a step later by the soft contact's friction spike,
which is not this onset) is bracketed by repeated sweeps (``crosscheck.mujoco_sweep.sweep``): each
round runs ``n_per_round`` values of Psi across the current bracket and keeps
the interval where the outcome switches, so the bracket shrinks by
(n_per_round - 1) per round.  The bracket's ends are chosen off Psi_L (an
asymmetric start), so Psi_L is never a sample.

Reported: the onset (midpoint of the final bracket), its half-width, and the
difference from Psi_L against the timestep.  Check, at every timestep with a
derived tolerance: onset - Psi_L within ``MUJOCO_LIFTOFF_ONSET`` (timesteps up
to the default 3e-4) or ``MUJOCO_LIFTOFF_ONSET_COARSE`` (up to 3.13e-3), the
MuJoCo leg's bound (Psi_L^3/6)(3 dt)^2 for the three rows of b > 0 that
LIFTOFF needs, widened by the bracket's half-width (the measurement's
resolution).
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck import critical
from crosscheck.outcome import Outcome
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.state import SlipState

SLUG = "mujoco_liftoff"


def params(quick: bool) -> dict:
    return {"alpha": 3.0, "eta": 1.0, "mu": [0.5, 1.4] if quick else [0.3, 0.5, 1.0, 1.4, 3.0],
            "timestep": [3e-3, 1e-3, 3e-4] if quick else [3e-3, 1e-3, 3e-4, 1e-4, 3e-5],
            "bracket": [-0.9e-3, 1.1e-3], "n_per_round": 9, "rounds": 5 if quick else 6, "horizon": 0.03}


def _onset(ctx, mu, dt, P, log):
    from crosscheck import mujoco_sweep
    from crosscheck.rod import Rod

    rod = Rod.scaled(P["alpha"])
    lo, hi = critical.Psi_L + P["bracket"][0], critical.Psi_L + P["bracket"][1]
    for r in range(P["rounds"]):
        Psi = np.linspace(lo, hi, P["n_per_round"])
        states = [SlipState(theta=critical.theta_L, varphi=-math.pi / 2, Theta=0.0, Psi=float(p), eta=P["eta"]) for p in Psi]
        res = mujoco_sweep.sweep(rod, states, mu, horizon=P["horizon"], progress=False, timestep=dt)
        lift = (np.asarray(res.outcome) == Outcome.LIFTOFF) & (np.asarray(res.event_time) == 0.0)
        for p, o, t in zip(Psi, res.outcome, res.event_time):
            for k, v in (("mu", mu), ("timestep", dt), ("round", r), ("Psi", p), ("outcome", Outcome(int(o)).name), ("event_time", t)):
                log[k].append(v)
        if not lift.any() or lift[0]:
            raise RuntimeError(f"mu = {mu}, timestep = {dt}: no switch to LIFTOFF inside [{lo:.6f}, {hi:.6f}] (outcomes {[Outcome(int(o)).name for o in res.outcome]})")
        i = int(np.argmax(lift))
        lo, hi = float(Psi[i - 1]), float(Psi[i])
    return lo, hi


def run(ctx: RunContext) -> None:
    P = ctx.params
    log = {k: [] for k in ("mu", "timestep", "round", "Psi", "outcome", "event_time")}
    cols = {k: [] for k in ("mu", "timestep", "Psi_lo", "Psi_hi", "onset", "half_width", "onset_minus_Psi_L")}
    pairs = [(mu, dt) for mu in P["mu"] for dt in P["timestep"]]
    for mu, dt in ctx.progress(pairs, desc="lift-off onset"):
        lo, hi = _onset(ctx, mu, dt, P, log)
        mid = 0.5 * (lo + hi)
        for k, v in (("mu", mu), ("timestep", dt), ("Psi_lo", lo), ("Psi_hi", hi), ("onset", mid), ("half_width", 0.5 * (hi - lo)), ("onset_minus_Psi_L", mid - critical.Psi_L)):
            cols[k].append(v)
        ctx.store.write_table("onset", cols)
        ctx.store.write_table("sweeps", log)
    from crosscheck.tolerances import MUJOCO_LIFTOFF_ONSET, MUJOCO_LIFTOFF_ONSET_COARSE

    for i in range(len(cols["mu"])):
        dt = cols["timestep"][i]
        tol, name = (MUJOCO_LIFTOFF_ONSET, "MUJOCO_LIFTOFF_ONSET") if dt <= 3e-4 * (1 + 1e-9) else (MUJOCO_LIFTOFF_ONSET_COARSE, "MUJOCO_LIFTOFF_ONSET_COARSE")
        if dt > 3.13e-3 * (1 + 1e-9):
            continue  # no derived bound for coarser steps
        err = cols["onset_minus_Psi_L"][i]
        hw = cols["half_width"][i]
        ctx.check(f"mu = {cols['mu'][i]:g}, timestep {dt:g}: MuJoCo's lift-off onset = Psi_L = {critical.Psi_L:.7f}", -hw <= err <= tol.atol + hw,
                  value=err, allowance=tol.atol + hw, detail=f"bracket [{cols['Psi_lo'][i]:.8f}, {cols['Psi_hi'][i]:.8f}]; {name}: {tol.why}")


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, plt

    P = ctx.params
    t = ctx.store.read_table("onset")
    fig, ax = plt.subplots(figsize=(5.6, 4.0))
    for i, mu in enumerate(P["mu"]):
        s = t["mu"] == mu
        err = np.abs(t["onset_minus_Psi_L"][s])
        ax.errorbar(t["timestep"][s] * (1 + 0.04 * i), np.maximum(err, 1e-9), yerr=t["half_width"][s], fmt="o-", ms=4, capsize=2, color=LINE_COLORS[i % 7], label=f"$\\mu$ = {mu:g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("MuJoCo timestep $\\omega\\, dt$ (scaled)")
    ax.set_ylabel("|onset - $\\Psi_L$|")
    ax.legend(fontsize=8)
    cap = (f"Lift-off onset (LIFTOFF at t = 0) in MuJoCo at theta = theta_L, Theta = 0, varphi = -pi/2, eta = {P['eta']:g}: |onset - Psi_L| against the timestep; "
           f"error bars: half-width of the final bracket ({P['rounds']} rounds of {P['n_per_round']} runs). An error below the bracket width is drawn at 1e-9.")
    blocks = [ctx.figure("liftoff_onset", fig, cap, ["onset.csv", "sweeps.csv"])]
    rows = [[f"{t['mu'][i]:g}", f"{t['timestep'][i]:g}", f"[{t['Psi_lo'][i]:.8f}, {t['Psi_hi'][i]:.8f}]", f"{t['onset'][i]:.8f}", f"{t['onset_minus_Psi_L'][i]:+.2e}"]
            for i in range(len(t["mu"]))]
    blocks.append(Table(caption=f"Lift-off onset (LIFTOFF at t = 0) against Psi_L = {critical.Psi_L:.8f} (eq. psil).", header=["mu", "timestep", "bracket", "onset", "onset - Psi_L"], rows=rows,
                        data=ctx.data("onset.csv")))
    return blocks


SECTION = Section(slug=SLUG, title="MuJoCo: lift-off onset against Psi_L", paper="eqs. thetal, psil (section 3.3); issue 4 item 5b",
                  params=params, run=run, render=render, requires=("crosscheck.mujoco_sweep",))
