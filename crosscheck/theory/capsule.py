"""The rigid rod with its contact at the capsule point C = A - r K: eqs. b and p at C and the slipping flow to the first event.

MuJoCo's rod is a capsule of radius r (units of l): the end cap is centred on
the tip A and, for theta in (0, pi/2), touches the plane at C = A - r K,
straight below A.  Everything else here is the paper's model: a rigid
unilateral contact and exact Coulomb friction, now acting at C.  The
difference between this model and the paper's (r = 0) is geometry alone.

Kinematics (scaled units, section 2.1; i = (cos psi, sin psi, 0),
j = (-sin psi, cos psi, 0) the horizontal axes of the rod's vertical plane,
j pointing from A towards the centre of mass S).  The rod has no axial spin,
so its angular velocity is Psi K + Theta i and C's material velocity is

    v_C = v_A + omega x (-r K) = v_A + r Theta j,

horizontal part eta_C (cos varphi_C i + sin varphi_C j): ``contact_slip``.

Dynamics.  The gap is z_A - r, so its free acceleration is still b (eq. b).
A force F = F_i i + F_j j + F_z K at C adds to eq. rotode the torque
(C - S) x F, whose theta component is (sin theta + r) F_j - cos theta F_z (the
lever of F_j is r longer than at A) and whose psi component is unchanged,
cos theta F_i.  With Coulomb friction opposite C's slip,
F_i = -mu F_z cos varphi_C, F_j = -mu F_z sin varphi_C, the gap's normal
acceleration is b + p_C F_z with

    p_C = 1 + alpha cos^2 theta + alpha mu cos theta (sin theta + r) sin varphi_C      (``p``)

(eq. p at r = 0: 1 + alpha + alpha sin theta (mu cos theta sin varphi - sin theta)).
The offset lowers p by alpha mu r cos theta |sin varphi_C| on the paradox side
varphi_C in (-pi, 0).  While slipping F_z = -b / p_C (eq. FZ at C) and the
horizontal acceleration of C in the (i, j) frame is

    a_i = (1 + alpha) F_i - r Theta Psi,
    a_j = (1 + alpha (sin theta + r)^2) F_j - alpha cos theta (sin theta + r) F_z
          + cos theta (Psi^2 cos^2 theta + Theta^2) - r sin theta cos theta Psi^2,

which gives eta_C' = a_i cos varphi_C + a_j sin varphi_C and
eta_C (varphi_C' + Psi) = a_j cos varphi_C - a_i sin varphi_C, together with
Psi' = alpha F_i / cos theta + 2 tan theta Psi Theta and
Theta' = alpha ((sin theta + r) F_j - cos theta F_z) - sin theta cos theta Psi^2
(eq. rotode with the force at C).  At r = 0 these are eq. polareqs_varphi with
the coefficients of Appendix A, term by term.

One flow.  These equations are ``crosscheck.theory.slipping``'s with the
radius as a parameter (``slipping.slip_rhs(x, mu, alpha, radius=r)``; r = 0
is the paper's rod): this module adds the capsule's start (C's slip from the
tip's state), its domain rule and its result.

How ``slip_until_event`` desingularises time near eta = 0 and what the offset r changes near p = 0 (measured):
``docs/capsule.md``."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crosscheck.checks import ALPHA, BOUNDED, HORIZON, MU, THETA, Interval, check
from crosscheck.coordinates import tip_velocity, to_generalized
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic, slipping
from crosscheck.theory.slipping import RADIUS, SlipResult, _start_outcome, _state_from
from crosscheck.tolerances import SLIP_INTEGRATION

__all__ = ["RADIUS", "CapsuleSlipResult", "b", "p", "contact_slip", "tip_slip", "slip_until_event"]


_HALF_PI = 0.5 * math.pi


def b(Psi, Theta, theta):
    """Scaled free normal acceleration of the capsule's gap z_A - r, eq. b (the same as at A).

    b = (Psi^2 cos^2 theta + Theta^2) sin theta - 1 (units of g); vectorised.
    """
    return analytic.b(Psi, Theta, theta)


def p(theta, varphi_C, mu, alpha, radius):
    """Normal acceleration of the gap per unit normal force at C, slipping with friction opposite C's slip (eq. p at C).

    p_C = 1 + alpha cos^2 theta + alpha mu cos theta (sin theta + r) sin varphi_C,
    eq. p at r = 0 (see the module docstring for the derivation).

    Args:
      theta: polar angle [rad], in (0, pi/2).
      varphi_C: relative slip angle of C's material velocity [rad] (any finite value).
      mu: friction coefficient; alpha: m l^2 / I0.
      radius: capsule radius r [units of l], in [0, 0.5).

    Returns:
      p_C (units of g per m g), broadcast over the arguments.
    """
    theta = check("theta", theta, THETA)
    varphi_C = check("varphi_C", varphi_C, BOUNDED)
    mu, alpha = check("mu", mu, MU), check("alpha", alpha, ALPHA)
    r = check("radius", radius, RADIUS)
    c = np.cos(theta)
    return 1.0 + alpha * c * c + alpha * mu * c * (np.sin(theta) + r) * np.sin(varphi_C)


def contact_slip(state: SlipState, *, radius) -> tuple[float, float]:
    """(eta_C, varphi_C): scaled speed and relative slip angle of C's material velocity v_A + r Theta j.

    The state's eta and varphi are the tip A's (as ``crosscheck.coordinates.to_generalized``
    and the MuJoCo engine read them); C's velocity is formed from the same (q, v),
    with the tip at height r so that the capsule touches the plane.  varphi_C is
    wrapped to (-pi, pi]: it may leave the paper's (-pi, 0] when r Theta is
    comparable to eta sin varphi.
    """
    r = float(check("radius", radius, RADIUS))
    rod = Rod.scaled()  # kinematics only: alpha does not enter
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, r))
    vA = tip_velocity(rod, q, v)
    psi = q[3]
    u = vA[:2] + r * v[4] * np.array([-math.sin(psi), math.cos(psi)])  # omega x (-r K), omega = Psi K + Theta i
    eta_C = float(math.hypot(u[0], u[1]))
    varphi_C = float(np.angle(np.exp(1j * (math.atan2(u[1], u[0]) - psi))))
    return eta_C, varphi_C


def tip_slip(eta_C, varphi_C, Theta, *, radius) -> tuple[np.ndarray, np.ndarray]:
    """(eta, varphi) of the tip A from C's slip: v_A = v_C - r Theta j (inverse of ``contact_slip``); varphi in (-pi, pi]."""
    r = check("radius", radius, RADIUS)
    eta_C, varphi_C, Theta = (check(n, x) for n, x in (("eta_C", eta_C), ("varphi_C", varphi_C), ("Theta", Theta)))
    ui = eta_C * np.cos(varphi_C)
    uj = eta_C * np.sin(varphi_C) - r * Theta
    return np.hypot(ui, uj), np.arctan2(uj, ui)


@dataclass(frozen=True, eq=False)
class CapsuleSlipResult(SlipResult):
    """``SlipResult`` of a run with the contact at C.

    ``state`` is the state at the event with eta, varphi those of C's slip
    (clamped to the paper's domain on a domain exit, as in ``crosscheck.theory.slipping``);
    ``p`` is p_C; the columns eta, varphi of ``x`` are eta_C, varphi_C.
    ``tip_eta``, ``tip_varphi``: the tip A's slip at the event (``tip_slip``);
    ``mu``, ``alpha``: the run's; ``normal_force``: -b / p_C along the trajectory.
    """

    radius: float = 0.0
    tip_eta: float = math.nan
    tip_varphi: float = math.nan
    mu: float = math.nan
    alpha: float = math.nan

    @property
    def normal_force(self) -> np.ndarray:
        """(n,) F_z = -b / p_C (eq. FZ at C, units of m g) along the trajectory ``t``."""
        x = self.x
        with np.errstate(divide="ignore", invalid="ignore"):
            return -b(x[:, 3], x[:, 5], x[:, 4]) / p(x[:, 4], x[:, 1], self.mu, self.alpha, self.radius)


def slip_until_event(
    state: SlipState,
    mu,
    alpha,
    *,
    radius,
    t_max: float = 10.0,
    s_max: float = 1e4,
    rtol: float | None = None,
    atol: float | None = None,
    friction=None,
) -> CapsuleSlipResult:
    """Integrate the rigid rod slipping with its contact at C from ``state`` to its first event.

    The start is MuJoCo's: (q, v) = ``to_generalized(rod, state, tip=(0, 0, radius))``,
    i.e. ``state``'s eta and varphi are the tip A's; C's slip is v_A + r Theta j.
    F_z = -b / p_C and friction opposite C's slip; integrated in s, eta_C p_C ds = dt,
    with ``solve_ivp`` (DOP853).  Events, domain exits and start rules: the module
    docstring (those of ``crosscheck.theory.slipping`` judged at C).

    Args:
      state: the initial ``SlipState`` (scaled; eta, varphi of the tip A).
      mu: friction coefficient, >= 0; alpha: m l^2 / I0.
      radius: capsule radius r [units of l], in [0, 0.5).
      t_max: horizon in real scaled time; s_max: horizon in s.
      rtol, atol: integrator tolerances (default ``SLIP_INTEGRATION``, as ``crosscheck.theory.slipping``).
      friction: ``friction(y) -> varphi_f``, the friction's angle at the 7-state y of ``slipping.integrate`` where it is
        not opposite C's slip (``crosscheck.engines.bullet.law``); p_C is then the p of that friction.  None: Coulomb's.

    Returns:
      A ``CapsuleSlipResult`` (a ``SlipResult``): outcome, real time, state at C, trajectory.  (Its ``normal_force``
      is Coulomb's -b / p_C: not that of another ``friction``.)
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    r = float(check("radius", radius, RADIUS))
    mu = float(check("mu", mu, MU))
    alpha = float(check("alpha", alpha, ALPHA))
    t_max = float(check("t_max", t_max, HORIZON))
    s_max = float(check("s_max", s_max, Interval(0.0, 1e8, lo_open=True, hi_open=False)))
    rtol = (
        SLIP_INTEGRATION.rtol
        if rtol is None
        else float(check("rtol", rtol, Interval(1e-14, 1e-3, lo_open=False, hi_open=False)))
    )
    atol = (
        SLIP_INTEGRATION.atol
        if atol is None
        else float(check("atol", atol, Interval(1e-16, 1e-3, lo_open=False, hi_open=False)))
    )

    eta_C, varphi_C = contact_slip(state, radius=r)
    y0 = np.array([eta_C, varphi_C, state.psi, state.Psi, state.theta, state.Theta, 0.0])

    def angle(y):
        return None if friction is None else friction(y)

    def result(outcome, t, y, reason, s_arr, Y, *, eta_out=None):
        bb, pp, *_ = slipping._coefficients(y[1], y[3], y[4], y[5], mu, alpha, r, angle(y))
        eta_A, varphi_A = tip_slip(y[0] if eta_out is None else eta_out, y[1], y[5], radius=r)
        return CapsuleSlipResult(
            outcome,
            t,
            _state_from(y, eta=eta_out),
            reason,
            bb,
            pp,
            s_arr,
            Y[:, 6].copy(),
            Y[:, :6].copy(),
            radius=r,
            tip_eta=float(eta_A),
            tip_varphi=float(varphi_A),
            mu=mu,
            alpha=alpha,
        )

    b0, p0, *_ = slipping._coefficients(varphi_C, state.Psi, state.theta, state.Theta, mu, alpha, r, angle(y0))
    early = _start_outcome(eta_C, b0, p0)
    if early is None and not -math.pi < varphi_C <= 0.0:
        # C slips across the rod's vertical plane: outside the paper's domain, where a run would stop
        early, reason = Outcome.SLIP, ("varphi=0" if varphi_C < _HALF_PI else "varphi=-pi")
    else:
        reason = "start"
    if early is not None:
        return result(early, 0.0, y0, reason, np.zeros(1), y0[None, :].copy())

    outcome, t_end, y, reason, s_arr, Y, eta_out = slipping.integrate(
        y0, mu, alpha, r, t_max=t_max, s_max=s_max, rtol=rtol, atol=atol, friction=friction
    )
    return result(outcome, t_end, y, reason, s_arr, Y, eta_out=eta_out)
