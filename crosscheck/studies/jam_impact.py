"""The impact without collision in size: an engine's state once its contact settles after a jam, against the theory's.

Where the theory's slip reaches p = 0 with b < 0 (Corollary 4.2) the rigid rod
takes the 3D Darboux-Keller impulse (``crosscheck.theory.impact.darboux_keller``):
Theta jumps to Theta+, Psi to Psi+, the slip stops (eta+ = 0), the normal
impulse is P_N and kinetic energy is lost.  An engine's contact spreads that
impulse over its contact time, so its state is read once the contact has
settled: at t* = t_jam + settle, settle = ``event_lag`` (``LAG_TAU`` contact
times, at least ``LAG_STEPS`` timesteps; the lag the agreement study already
allows an engine's event).  Over settle the theory's own state moves on (the
stuck rod pivots about its tip: Psi changes by ~10 per unit time at IC1), so
the engine is compared with the theory's hybrid continuation
(``crosscheck.theory.impact.continuation.run``) at the same t*, and the engine's
"Theta+" is its Theta at t* moved back to the impact by the theory's own
drift over settle:

    Theta+_engine = Theta+_theory + (Theta_engine(t*) - Theta_theory(t*))

(the same for Psi+).  The slip after the impact is eta at t*, the energy the
mechanical energy E = |v_S|^2 / 2 + (Theta^2 + cos^2 theta Psi^2) / (2 alpha) + Z_S
at t* (both from the same start, so their difference is the energy the engine
dissipates more than the theory), and the engine's P_N is its classifier's
jam impulse (NaN where it does not jam).

Scaled units (section 2.1): rates in omega, energies in m g l, impulses in m g / omega.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from crosscheck import engines
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.studies.comparison import event_lag
from crosscheck.theory.impact import continuation
from crosscheck.theory.impact.darboux_keller import impact
from crosscheck.theory.slipping import slip_until_event

__all__ = [
    "COLUMNS",
    "compare_jam",
    "compare_jams",
    "engine_after_jam",
    "impact_study",
    "mechanical_energy",
    "settle_time",
    "stiffness_convergence",
    "theory_after_jam",
]

#: The numbers of one start of ``impact_study``, in its table's column order.
COLUMNS = (
    "theta",
    "varphi",
    "Theta",
    "Psi",
    "eta",
    "mu",
    "t_jam",
    "settle",
    "Theta_plus",
    "Psi_plus",
    "P_N",
    "energy_lost_impact",
    "theory_Theta",
    "theory_Psi",
    "theory_eta",
    "theory_energy",
    "engine_outcome",
    "engine_time",
    "engine_jammed",
    "engine_Theta",
    "engine_Psi",
    "engine_eta",
    "engine_energy",
    "engine_P_N",
    "Theta_plus_engine",
    "Psi_plus_engine",
    "Theta_plus_error",
)


def mechanical_energy(theta, psi, Theta, Psi, tip_vel, tip_z, alpha: float):
    """E = |v_S|^2 / 2 + (Theta^2 + cos^2 theta Psi^2) / (2 alpha) + Z_S [m g l] from the tip's motion (scaled).

    The centre S = A - d with d = (cos theta sin psi, -cos theta cos psi, -sin theta) (eq. tipfromcentre), so
    v_S = v_A - d'.  ``tip_vel``: (..., 3); the others (...,).
    """
    theta, psi, Theta, Psi = (np.asarray(x, float) for x in (theta, psi, Theta, Psi))
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    dd = np.stack((-st * sp * Theta + ct * cp * Psi, st * cp * Theta + ct * sp * Psi, -ct * Theta), -1)
    v = np.asarray(tip_vel, float) - dd
    kinetic = 0.5 * np.sum(v * v, -1) + 0.5 * (Theta**2 + (ct * Psi) ** 2) / alpha
    return kinetic + np.asarray(tip_z, float) + st


def _state_energy(s: SlipState, alpha: float) -> float:
    a = s.varphi + s.psi
    tip_vel = np.array([s.eta * math.cos(a), s.eta * math.sin(a), 0.0])
    return float(mechanical_energy(s.theta, s.psi, s.Theta, s.Psi, tip_vel, 0.0, alpha))


def _free_flight(s: SlipState, duration: float, alpha: float) -> SlipState:
    """The rod thrown from ``s`` (tip on the plane, w = 0) after ``duration`` of torque-free flight: theta'' = -sin
    theta
    cos theta Psi^2, (cos^2 theta Psi)' = 0, the centre's horizontal velocity constant; eta is the tip's horizontal
    speed
    (energy is conserved: the caller keeps the lift-off's)."""
    from scipy.integrate import solve_ivp

    a = s.varphi + s.psi
    st, ct, sp, cp = math.sin(s.theta), math.cos(s.theta), math.sin(s.psi), math.cos(s.psi)
    d_dot = np.array([-st * sp * s.Theta + ct * cp * s.Psi, st * cp * s.Theta + ct * sp * s.Psi])
    v_S = np.array([s.eta * math.cos(a), s.eta * math.sin(a)]) - d_dot

    def rhs(_t, y):
        theta, _psi, Theta, Psi = y
        return [Theta, Psi, -math.sin(theta) * math.cos(theta) * Psi * Psi, 2.0 * math.tan(theta) * Theta * Psi]

    y = solve_ivp(rhs, (0.0, duration), [s.theta, s.psi, s.Theta, s.Psi], rtol=1e-10, atol=1e-12).y[:, -1]
    theta, psi, Theta, Psi = (float(x) for x in y)
    st, ct, sp, cp = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    tip = v_S + np.array([-st * sp * Theta + ct * cp * Psi, st * cp * Theta + ct * sp * Psi])
    return SlipState(theta=theta, varphi=-math.pi / 2, Theta=Theta, Psi=Psi, eta=float(np.hypot(*tip)), psi=psi)


def settle_time(options) -> float:
    """How long after a jam an engine at ``options`` (its ``Options``) is read: ``event_lag``, the lag its events are
    allowed."""
    return float(event_lag(float(options.contact_time), float(options.timestep)))


def theory_after_jam(state: SlipState, mu: float, alpha: float, *, settle: float, t_max: float = 2.0) -> dict | None:
    """The theory's jam from ``state``: its time, the impact (Theta+, Psi+, P_N, energy lost) and the hybrid state at
    t_jam + ``settle`` (Theta, Psi, eta, energy); None if the slip does not jam (or reach the GB point) by ``t_max``."""
    a = slip_until_event(state, mu, alpha, t_max=t_max)
    if a.outcome not in (Outcome.JAM, Outcome.GB):
        return None
    iwc = impact(a.state, mu, alpha, boundary=a.outcome is Outcome.GB)
    h = continuation.run(state, mu, alpha, horizon=a.time + settle)
    last = h.segments[-1]
    end = last.stick.state if isinstance(last, continuation.StickSegment) else last.slip.state
    if isinstance(last, continuation.Segment) and last.impact is not None:  # the run ended at the impact itself
        end = SlipState(theta=end.theta, varphi=end.varphi, Theta=iwc.Theta, Psi=iwc.Psi, eta=0.0, psi=end.psi)
    energy = _state_energy(end, alpha)
    if h.outcome is Outcome.LIFTOFF and h.time < a.time + settle:  # the rod flies from there (IC1 does, at once)
        end = _free_flight(end, a.time + settle - h.time, alpha)
    return {
        "t_jam": float(a.time),
        "settle": float(settle),
        "Theta_plus": iwc.Theta,
        "Psi_plus": iwc.Psi,
        "P_N": iwc.normal_impulse,
        "energy_lost_impact": iwc.energy_lost,
        "theory_Theta": end.Theta,
        "theory_Psi": end.Psi,
        "theory_eta": end.eta,
        "theory_energy": energy,
    }


def engine_after_jam(spec, rod: Rod, state: SlipState, mu: float, t_star: float, options: Mapping) -> dict:
    """``spec``'s run from ``state`` read at ``t_star``: its first event and its Theta, Psi, eta, energy there."""
    return _read_after_jam(_runs_after_jam(spec, rod, [(state, mu)], [t_star], options)[0], rod, t_star)


def _runs_after_jam(spec, rod: Rod, starts: Sequence[tuple], t_stars: Sequence[float], options: Mapping) -> list:
    """``spec``'s run of each (state, mu) of ``starts`` to its t* + 2 timesteps, in one call where the engine batches."""
    dt = float(spec.options(**options).timestep)
    return spec.simulate_each(
        rod, [s for s, _ in starts], [mu for _, mu in starts], horizon=[t + 2 * dt for t in t_stars], **options
    )


def _read_after_jam(run, rod: Rod, t_star: float) -> dict:
    """An engine's ``run`` read at ``t_star`` (``engine_after_jam``)."""
    R = run.record
    k = min(int(np.searchsorted(R.t, t_star)), len(R) - 1)
    return {
        "engine_outcome": run.outcome.name,
        "engine_time": float(run.event_time),
        "engine_jammed": int(run.outcome == Outcome.JAM),
        "engine_Theta": float(R.Theta[k]),
        "engine_Psi": float(R.Psi[k]),
        "engine_eta": float(R.eta[k]),
        "engine_energy": float(
            mechanical_energy(R.theta[k], R.psi[k], R.Theta[k], R.Psi[k], R.tip_vel[k], R.tip_pos[k, 2], rod.alpha)
        ),
        "engine_P_N": float(run.jam_impulse),
    }


def compare_jam(spec, rod: Rod, state: SlipState, mu: float, options: Mapping, *, t_max: float = 2.0) -> dict | None:
    """One start through the theory's jam and ``spec`` at ``options``: the row of ``COLUMNS`` (None: no theory jam)."""
    return compare_jams(spec, rod, [(state, mu)], options, t_max=t_max)[0]


def compare_jams(spec, rod: Rod, starts: Sequence[tuple], options: Mapping, *, t_max: float = 2.0) -> list:
    """``compare_jam`` of every (state, mu) of ``starts``, the engine's runs in one call (``EngineSpec.simulate_each``):
    one row or None per start, in order."""
    settle = settle_time(spec.options(**options))
    theory = [theory_after_jam(s, mu, rod.alpha, settle=settle, t_max=t_max) for s, mu in starts]
    jammed = [i for i, th in enumerate(theory) if th is not None]
    t_stars = [theory[i]["t_jam"] + settle for i in jammed]
    runs = _runs_after_jam(spec, rod, [starts[i] for i in jammed], t_stars, options) if jammed else []
    rows: list = [None] * len(starts)
    for i, run, t_star in zip(jammed, runs, t_stars):
        (state, mu), th = starts[i], theory[i]
        e = _read_after_jam(run, rod, t_star)
        row = {**{k: getattr(state, k) for k in ("theta", "varphi", "Theta", "Psi", "eta")}, "mu": float(mu), **th, **e}
        row["Theta_plus_engine"] = th["Theta_plus"] + (e["engine_Theta"] - th["theory_Theta"])
        row["Psi_plus_engine"] = th["Psi_plus"] + (e["engine_Psi"] - th["theory_Psi"])
        row["Theta_plus_error"] = row["Theta_plus_engine"] - th["Theta_plus"]
        rows[i] = row
    return rows


def impact_study(
    engine: str,
    starts: Sequence[tuple[SlipState, float]],
    options: Mapping,
    *,
    alpha: float = 3.0,
    t_max: float = 2.0,
    progress=lambda x, **_: x,
) -> list[dict]:
    """``compare_jam`` of every (state, mu) of ``starts`` on ``engine`` at ``options``; starts without a theory jam are
    left out."""
    spec, rod = engines.get(engine), Rod.scaled(alpha)
    rows = compare_jams(spec, rod, list(progress(starts, desc="jams")), options, t_max=t_max)
    return [r for r in rows if r is not None]


def stiffness_convergence(
    engine: str, state: SlipState, mu: float, settings: Sequence[Mapping], *, alpha: float = 3.0
) -> list[dict]:
    """``compare_jam`` of one start at each of ``settings``, with each setting's contact time, stiffest (shortest
    contact time) last: a compliant contact whose jam tends to the theory's impact has |Theta+ error| falling down
    it."""
    spec, rod = engines.get(engine), Rod.scaled(alpha)
    rows = []
    for opts in settings:
        o = spec.options(**opts)
        r = compare_jam(spec, rod, state, mu, opts)
        if r is not None:
            rows.append({**r, "contact_time": float(o.contact_time), "timestep": float(o.timestep)})
    return sorted(rows, key=lambda r: (-r["contact_time"], -r["timestep"]))
