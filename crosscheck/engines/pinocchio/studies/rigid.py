"""Checks only a rigid time-stepper has: one step against eq. FZ, first-order slipping, and the aftermath of a jam against the IWC.

A rigid contact (``crosscheck.engines.pinocchio.stepper``) answers within one step,
so three things can be checked that a soft contact cannot give:

* ``one_step``: while the tip slips, the step's normal impulse / dt is the
  analytic force F_z = -b/p (eq. FZ), with the friction direction of the
  slip at the end of the step, and the tangential impulse is mu times the
  normal one, opposite that slip;
* ``slip_order``: a slipping trajectory converges to ``slip_until_event``
  at first order in dt (semi-implicit Euler);
* ``jam_aftermath``: where the theory reaches p = 0 with b < 0 (Corollary
  4.2), or starts in the impasse p < 0, b < 0, the engine's state right
  after its jam row converges to ``crosscheck.theory.impact.darboux_keller.impact`` (the impact
  without collision) as dt -> 0, and its jam time to the analytic one.

Scaled units throughout (section 2.1: m = l = g = 1, time 1/omega).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.pinocchio.stepper import Options, Stepper
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic
from crosscheck.theory.corollary import corollary_states
from crosscheck.theory.critical import theta_12
from crosscheck.theory.impact.darboux_keller import delassus, impact
from crosscheck.theory.slipping import slip_until_event

__all__ = [
    "checks",
    "StepCheck",
    "one_step",
    "sticking_admissible",
    "slipping_states",
    "slip_order",
    "planar_impasse",
    "Aftermath",
    "jam_aftermath",
    "corollary_aftermath",
    "order",
]

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@dataclass(frozen=True)
class StepCheck:
    """One step of a slipping tip against eq. FZ (forces in m g, velocities in l omega).

    normal_force: the step's normal impulse / dt; slipping_force: -b/p with
    p for ``varphi_end``, the slip direction at the end of the step (what the
    step's Coulomb law sees); friction_ratio: |tangential| / normal impulse;
    cos_opposite: cosine between the tangential impulse and -slip (1: exactly
    opposite); w_end: the normal velocity of the tip at the end of the step.
    """

    normal_force: float
    slipping_force: float
    friction_ratio: float
    cos_opposite: float
    varphi_end: float
    w_end: float


def one_step(rod: Rod, state: SlipState, mu: float, options: Options | None = None) -> StepCheck:
    """One step of the rigid engine from ``state`` (tip on the plane), measured against eq. FZ."""
    st = Stepper(rod, mu, options or Options())
    dt = st.dt
    q, v = to_generalized(rod, state)
    _, v1, info = st.step(q, v)
    lam = info.impulse
    # the contact velocity at the end of the step: J v1 + dt dJ v (Stepper.step's own linearisation)
    pin.forwardKinematics(st.model, st.data, q, v, np.zeros(st.model.nv))
    dJv = pin.getFrameClassicalAcceleration(st.model, st.data, st.tip, _LWA).linear
    pin.forwardKinematics(st.model, st.data, q, v1)
    u = (pin.getFrameVelocity(st.model, st.data, st.tip, _LWA).linear + dt * dJv) / (rod.length * rod.omega)
    varphi = math.atan2(u[1], u[0]) - q[3]
    force = lam / dt / rod.force_scale
    ft = math.hypot(force[0], force[1])
    cos = -(force[0] * u[0] + force[1] * u[1]) / (ft * math.hypot(u[0], u[1])) if ft > 0 else math.nan
    b = analytic.b(state.Psi, state.Theta, state.theta)
    p = analytic.p(state.theta, varphi, mu, rod.alpha)
    return StepCheck(
        normal_force=float(force[2]),
        slipping_force=float(-b / p),
        friction_ratio=ft / force[2] if force[2] > 0 else math.nan,
        cos_opposite=float(cos),
        varphi_end=float(varphi),
        w_end=float(u[2]),
    )


def sticking_admissible(state: SlipState, mu: float, alpha: float) -> bool:
    """Whether the sticking impulse -G^-1 (u_t, 0) of a slipping tip lies in the Coulomb cone (G: eq.-based Delassus, ``crosscheck.theory.impact.darboux_keller``).

    If it does, a time step's NCP has a second solution beside the slip: the
    tip stopped by one impulse (an impact without collision inside the step),
    whatever dt (the impulse tends to that finite value as dt -> 0).  This
    happens only above mu_P, near p = 0; PGS then may return either solution
    (measured: 20 of 1600 random slipping states at mu < 2 are ambiguous, PGS
    converged to the sticking one in 2 of them, e.g. p = 0.085 at mu = 1.79:
    a normal force of 240 m g where -b/p = 0.81).  A one-step check against
    eq. FZ is meaningful only where the slip is the step's only solution.
    """
    G = delassus(state, alpha)
    a = state.varphi + state.psi  # the slip direction in world axes
    lam = -np.linalg.solve(G, np.array([state.eta * math.cos(a), state.eta * math.sin(a), 0.0]))
    return bool(lam[2] > 0.0 and math.hypot(lam[0], lam[1]) <= mu * lam[2])


def slipping_states(
    n: int, rng: np.random.Generator, alpha: float = 3.0, *, min_force: float = 1e-2
) -> list[tuple[SlipState, float]]:
    """``n`` random (state, mu) that slip at t = 0 (b < 0 < p) with a normal force -b/p of at least ``min_force`` m g,
    and whose time step has the slip as its only solution (not ``sticking_admissible``).

    theta in (0.1, 1.45), varphi in (-3.1, -0.05), Theta and Psi standard
    normal, eta in (0.3, 3), psi in (-3, 3), mu in (0, 2).
    """
    out = []
    while len(out) < n:
        s = SlipState(
            theta=rng.uniform(0.1, 1.45),
            varphi=-rng.uniform(0.05, 3.1),
            Theta=rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.3, 3),
            psi=rng.uniform(-3, 3),
        )
        mu = rng.uniform(0.0, 2.0)
        b, p = analytic.b(s.Psi, s.Theta, s.theta), analytic.p(s.theta, s.varphi, mu, alpha)
        if b < 0 < p and -b / p >= min_force and not sticking_admissible(s, mu, alpha):
            out.append((s, mu))
    return out


def order(timesteps: Sequence[float], errors: Sequence[float]) -> float:
    """Slope of log(error) against log(dt): the observed order of convergence."""
    return float(np.polyfit(np.log(timesteps), np.log(errors), 1)[0])


#: The slipping start of ``slip_order``: slips without an event for t <= 0.3 at mu = 0.5, alpha = 3.
SLIP_ORDER_STATE = SlipState(theta=0.6, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.0)


def slip_order(
    rod: Rod,
    *,
    state: SlipState = SLIP_ORDER_STATE,
    mu: float = 0.5,
    t_end: float = 0.3,
    timesteps: Sequence[float] = (4e-3, 2e-3, 1e-3, 5e-4),
) -> tuple[float, np.ndarray]:
    """Order of convergence of the rigid engine's slipping state at ``t_end`` to ``slip_until_event``.

    Returns (order, errors): the error at each timestep is the largest of
    |theta|, |eta|, |Theta|, |Psi| differences at t_end (scaled).
    """
    a = slip_until_event(state, mu, rod.alpha, t_max=t_end)
    if a.outcome != Outcome.SLIP:
        raise ValueError(
            f"state must slip without an event up to t_end = {t_end:g}; it ends with {a.outcome.name} at {a.time:g}"
        )
    errs = []
    engine = get("pinocchio")
    for dt in timesteps:
        R = engine.simulate(rod, state, mu, horizon=t_end + dt / 2, timestep=dt).record
        k = int(round(t_end / dt))
        if abs(R.t[k] - t_end) > 1e-9 * t_end:
            raise ValueError(f"timesteps must divide t_end = {t_end:g}; got {dt:g} (row {k} is at t = {R.t[k]:g})")
        errs.append(
            max(
                abs(R.theta[k] - a.state.theta),
                abs(R.eta[k] - a.state.eta),
                abs(R.Theta[k] - a.state.Theta),
                abs(R.Psi[k] - a.state.Psi),
            )
        )
    errs = np.array(errs)
    return order(timesteps, errs), errs


def planar_impasse(mu: float, Theta: float, alpha: float = 3.0) -> SlipState:
    """On the planar section (varphi = -pi/2, Psi = 0) midway between theta_1 and theta_2 (p < 0), eta = 1: Painleve's impasse if b < 0."""
    t1, t2 = theta_12(mu, alpha)
    return SlipState(theta=0.5 * (float(t1) + float(t2)), varphi=-math.pi / 2, Theta=Theta, Psi=0.0, eta=1.0)


@dataclass(frozen=True)
class Aftermath:
    """The rigid engine's jams of some states at several timesteps against the IWC (arrays (n_timesteps, n_states)).

    jammed: the engine's first event is a JAM; time_error: t_engine - t_analytic
    of the JAM (NaN otherwise); impulse_error: its normal impulse minus the
    IWC's (m g / omega); rate_error: the largest |difference| of Theta, Psi,
    eta one row after the jam row against the IWC's post-impulse rates.
    stop_lead (n_states,): how long before the analytic jam the theory's slip
    reaches states whose time step admits a second solution, the tip stopped
    by one impulse (``sticking_admissible``), read at the theory's integration
    rows (so at least this long; NaN: never before the jam).  From then on PGS
    may return the stop, and the engine then jams early by up to this lead.
    """

    timesteps: np.ndarray
    jammed: np.ndarray
    time_error: np.ndarray
    impulse_error: np.ndarray
    rate_error: np.ndarray
    stop_lead: np.ndarray | None = None

    def orders(self) -> np.ndarray:
        """Per state jammed at every timestep: the order of convergence of rate_error (NaN otherwise)."""
        ok = self.jammed.all(axis=0) & (self.rate_error > 0).all(axis=0)
        return np.array(
            [order(self.timesteps, self.rate_error[:, i]) if ok[i] else math.nan for i in range(self.jammed.shape[1])]
        )

    def as_dict(self) -> dict:
        return {
            "timesteps": self.timesteps.tolist(),
            "jammed": self.jammed.tolist(),
            "time_error": self.time_error.tolist(),
            "impulse_error": self.impulse_error.tolist(),
            "rate_error": self.rate_error.tolist(),
            "orders": self.orders().tolist(),
            **({} if self.stop_lead is None else {"stop_lead": self.stop_lead.tolist()}),
        }


def jam_aftermath(
    rod: Rod,
    states: Sequence[SlipState],
    mu: float,
    *,
    timesteps: Sequence[float] = (1e-3, 3e-4, 1e-4),
    after: float = 0.05,
    t_max: float = 2.0,
) -> Aftermath:
    """The rigid engine through the analytic jam of each state (Corollary 4.2 states, or impasses at t = 0) against the IWC.

    Each state is run analytically to its jam (``slip_until_event``, which must
    end in JAM by ``t_max``; a state already in the impasse p < 0, b < 0 jams
    at t = 0), the IWC computed there (``crosscheck.theory.impact.darboux_keller.impact``), and the
    engine run to ``after`` past the analytic jam at each timestep.
    """
    timesteps = np.asarray(timesteps, float)
    n = len(states)
    jammed = np.zeros((len(timesteps), n), bool)
    t_err, imp_err, rate_err = (np.full((len(timesteps), n), np.nan) for _ in range(3))
    stop_lead = np.full(n, np.nan)
    engine = get("pinocchio")
    for i, s in enumerate(states):
        if analytic.p(s.theta, s.varphi, mu, rod.alpha) <= 0.0 and analytic.b(s.Psi, s.Theta, s.theta) < 0.0:
            t_jam, at = 0.0, s
        else:
            a = slip_until_event(s, mu, rod.alpha, t_max=t_max)
            if a.outcome != Outcome.JAM:
                raise ValueError(
                    f"states[{i}] must jam analytically by t_max = {t_max:g}; it ends with {a.outcome.name}"
                )
            t_jam, at = float(a.time), a.state
            stop_lead[i] = _stop_lead(a, mu, rod.alpha)
        iwc = impact(at, mu, rod.alpha)
        for j, dt in enumerate(timesteps):
            run = engine.simulate(rod, s, mu, horizon=t_jam + after, timestep=float(dt))
            if run.outcome != Outcome.JAM:
                continue
            jammed[j, i] = True
            R, k = run.record, int(round(run.event_time / dt)) + 1
            t_err[j, i] = run.event_time - t_jam
            imp_err[j, i] = run.jam_impulse - iwc.normal_impulse
            rate_err[j, i] = max(abs(R.Theta[k] - iwc.Theta), abs(R.Psi[k] - iwc.Psi), abs(R.eta[k] - iwc.eta))
    return Aftermath(
        timesteps=timesteps,
        jammed=jammed,
        time_error=t_err,
        impulse_error=imp_err,
        rate_error=rate_err,
        stop_lead=stop_lead,
    )


def _stop_lead(slip, mu: float, alpha: float) -> float:
    """t_jam - the first row of the theory's slip (a ``SlipResult`` ending in JAM) whose step admits the impulsive stop."""
    for t, (eta, varphi, psi, Psi, theta, Theta) in zip(slip.t[:-1], slip.x[:-1]):
        if sticking_admissible(
            SlipState(theta=theta, varphi=varphi, Theta=Theta, Psi=Psi, eta=eta, psi=psi), mu, alpha
        ):
            return float(slip.time - t)
    return math.nan


def corollary_aftermath(rod: Rod, mu: float, n: int, rng: np.random.Generator, **kw) -> Aftermath:
    """``jam_aftermath`` of ``n`` Corollary 4.2 states at ``mu`` (``crosscheck.theory.corollary.corollary_states``)."""
    states, _, _ = corollary_states(mu, n, rng, alpha=rod.alpha)
    return jam_aftermath(rod, states, mu, **kw)


def checks(rod, n_states, rng):
    """One step's impulse against -b/p, the slipping convergence order and the post-jam rates against the impact without collision."""
    from crosscheck.engines.pinocchio import tolerances as pinocchio_tol
    from crosscheck.error_stats import error_stat

    stats = []
    steps = [(s, m, one_step(rod, s, m)) for s, m in slipping_states(min(n_states, 40), rng, rod.alpha)]
    where = {
        k: np.array([getattr(s, k) for s, _, _ in steps]) for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi")
    }
    where["mu"] = np.array([m for _, m, _ in steps])
    stats.append(
        error_stat(
            "one-step normal impulse / dt vs -b/p",
            [c.normal_force for _, _, c in steps],
            [c.slipping_force for _, _, c in steps],
            pinocchio_tol.RIGID_STEP_FORCE,
            where,
        )
    )
    rate, errs = slip_order(rod)
    stats.append(
        error_stat(
            "slipping convergence order",
            [rate],
            [1.0],
            pinocchio_tol.RIGID_SLIP_ORDER,
            {"error_at_smallest_dt": errs[-1:]},
        )
    )
    impasses = [planar_impasse(m, T, rod.alpha) for m, T in ((1.4, 0.5), (1.4, -0.3), (2.0, 0.5))]
    after = [jam_aftermath(rod, [s], m) for s, m in zip(impasses, (1.4, 1.4, 2.0))]
    stats.append(
        error_stat(
            "post-jam rates vs IWC order (planar impasse)",
            [a.orders()[0] for a in after],
            [1.0] * len(after),
            pinocchio_tol.RIGID_IWC_ORDER,
            {"mu": np.array([1.4, 1.4, 2.0]), "Theta": np.array([0.5, -0.3, 0.5])},
        )
    )
    return stats
