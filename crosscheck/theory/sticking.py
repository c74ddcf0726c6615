"""The rod pivoting about its stuck tip: the contact force that holds it there, and how it lets go (lift-off, or slip in the direction the theory gives).

A tip at rest on the plane (u = 0, z = 0) has three rigid modes, decided from
the tip's accelerations a = G F + a_free (eq. linode2, G the Delassus matrix
of ``crosscheck.theory.impact.darboux_keller``):

* stick: a = 0 with F in the cone, F_n >= 0, |F_t| <= mu F_n;
* lift-off: F = 0 with a_n = b >= 0 (eq. b is the tip's free normal acceleration);
* slip onset: a_n = 0, F_t = -mu F_n u_hat, a_t = sigma u_hat with F_n >= 0, sigma >= 0.

Closed forms.  In the rod's frame (i horizontal and normal to the rod, j along
its horizontal projection from the tip towards the centre S, n up) with
s, c = sin, cos theta and W = Psi^2 c^2 + Theta^2, eq. linode2 at F = 0 gives
a_free = (0, c W, b), b = s W - 1 (no i component: the i terms of the
centripetal and Coriolis accelerations cancel), and G = [[1 + alpha, 0, 0],
[0, 1 + alpha s^2, -alpha s c], [0, -alpha s c, 1 + alpha c^2]], whose (j, n)
block has determinant 1 + alpha.  Solving G F = -a_free:

    F_i = 0,   F_j = alpha s c / (1 + alpha) - c W,   F_n = (1 + alpha s^2) / (1 + alpha) - s W = -alpha c^2 / (1 + alpha) - b.

Sticking needs b <= -alpha c^2 / (1 + alpha) < 0: a stuck tip with b > -alpha
c^2 / (1 + alpha) needs a pull from the plane.  With F, eq. rotode becomes
the inverted spherical pendulum about the tip,

    Theta' = -alpha c / (1 + alpha) - Psi^2 s c,   Psi' = 2 Psi Theta tan(theta)

(c F_n - s F_j = c / (1 + alpha); Psi c^2, the vertical angular momentum
about the tip, and the energy (1 + alpha)/(2 alpha) (Theta^2 + c^2 Psi^2) + s
are conserved).

How a stick ends.  Where F_n reaches 0 the friction needed is F_j = -c /
((1 + alpha) s) != 0, so |F_j| / F_n grows without bound before F_n = 0: for
any finite mu the friction leaves the cone first and a sticking rod never
lifts off directly; it slips.  Lift-off from rest happens only where the
rest state itself has b > 0 (after an impact without collision, or as given).
At the cone's edge the slip starts opposite the friction, u_hat = -sign(F_j) j:
varphi = -pi/2 (outwards, away from S) for F_j > 0, +pi/2 (towards S, outside
the paper's domain (-pi, 0]) for F_j < 0.

Slip onset from rest (``at_rest``, where stick is inconsistent and b <= 0).  A
slip along u_hat needs no lateral acceleration; the i row gives
-(1 + alpha) mu F_n u_i = sigma u_i, so u_hat = +-j (varphi = -+pi/2).  Along
u_hat = sigma_j j, eq. p is p = 1 + alpha c^2 + sigma_j alpha mu s c, F_n = -b/p
(eq. FZ) and sigma = F_n (-mu (1 + alpha s^2) - sigma_j alpha s c) + sigma_j c W.
A direction is consistent where F_n >= 0 and sigma >= 0.  At most one is:
with B = -b >= 0, h = 1 + alpha c^2, g = 1 + alpha s^2 and p_+- = h +- alpha
mu s c > 0 (F_n >= 0 on both needs both p > 0, or b = 0),

    p_+ p_- (sigma_- + sigma_+) = B [(alpha s c - mu g) p_+ - (mu g + alpha s c) p_-] = -2 mu (1 + alpha) B,

(alpha^2 s^2 c^2 - g h = -(1 + alpha)), negative unless B = 0, and at B = 0
sigma_- = -c W < 0 (W = 0 would make b = -1).  So a slip from rest has one
direction (none was found either in 36,725 random rest states over alpha,
mu in [0.007, 1100]; ``at_rest`` says "inconsistent" if it ever happens).

The slipping flow (``crosscheck.theory.slipping``) cannot start at eta = 0 (an
equilibrium of eq. f): a slip onset hands it eta = ``SLIP_ONSET_SPEED``.
Scaled units (section 2.1) throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import ALPHA, HORIZON, MU, check
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.tolerances import STICK_SPEED, THETA_MARGIN

__all__ = ["SLIP_ONSET_SPEED", "stick_force", "stick_rates", "Rest", "at_rest", "StickResult", "stick_until_event"]

#: The slip speed [l omega] handed to the slipping flow at a slip onset: 100 x its stick speed (STICK_SPEED, 1e-9), so the
#: flow's own stick event cannot fire on the onset's rounding, and small enough that the tip velocity it adds changes the
#: motion by O(1e-7), far below the rigid engine's O(dt) >= 1e-5 at the timesteps the tests use.
SLIP_ONSET_SPEED = 100.0 * STICK_SPEED.atol
#: Integration of the pivoting rod (DOP853): a smooth 4-state ODE with O(1) rates.
_RTOL, _ATOL = 1e-11, 1e-13
_HALF_PI = 0.5 * math.pi


def stick_force(theta, Psi, Theta, alpha) -> tuple[float, float, float]:
    """(F_i, F_j, F_n): the contact force [m g] that keeps the tip at rest, in the rod's frame (module docstring);
    floats for floats, arrays (F_i still 0.0) for arrays of states."""
    if np.ndim(theta) or np.ndim(Psi) or np.ndim(Theta):
        s, c = np.sin(theta), np.cos(theta)
        W = Psi * Psi * c * c + Theta * Theta
        return 0.0, alpha * s * c / (1.0 + alpha) - c * W, (1.0 + alpha * s * s) / (1.0 + alpha) - s * W
    s, c = math.sin(theta), math.cos(theta)
    W = Psi * Psi * c * c + Theta * Theta
    return 0.0, alpha * s * c / (1.0 + alpha) - c * W, (1.0 + alpha * s * s) / (1.0 + alpha) - s * W


def stick_rates(theta, Psi, Theta, alpha) -> tuple[float, float]:
    """(Psi', Theta') of the rod pivoting about its stuck tip (eq. rotode with ``stick_force``)."""
    s, c = math.sin(theta), math.cos(theta)
    return 2.0 * Psi * Theta * s / c, -alpha * c / (1.0 + alpha) - Psi * Psi * s * c


@dataclass(frozen=True)
class Rest:
    """The mode of a tip at rest on the plane (``at_rest``).

    mode: "stick", "liftoff", "slip" or "inconsistent" (no rigid mode).
    varphi: the slip direction for "slip" (-pi/2 or +pi/2), else None.
    force: (F_i, F_j, F_n) of the mode [m g] (the sticking force for "stick", 0 for "liftoff", the sliding force for "slip").
    b: eq. b at the state.
    """

    mode: str
    varphi: float | None
    force: tuple
    b: float


def _onset(theta, Psi, Theta, mu, alpha, sign_j) -> tuple[float, float]:
    """(F_n, sigma) of a slip starting from rest along u_hat = sign_j j (module docstring)."""
    s, c = math.sin(theta), math.cos(theta)
    W = Psi * Psi * c * c + Theta * Theta
    b = s * W - 1.0
    p = 1.0 + alpha * c * c + sign_j * alpha * mu * s * c
    F_n = 0.0 if b == 0.0 else (-b / p if p != 0.0 else math.inf)
    return F_n, F_n * (-mu * (1.0 + alpha * s * s) - sign_j * alpha * s * c) + sign_j * c * W


def at_rest(state: SlipState, mu: float, alpha: float) -> Rest:
    """The rigid mode of ``state``'s tip if it is at rest (its eta and varphi ignored): stick, lift-off or slip onset."""
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    theta, Psi, Theta = state.theta, state.Psi, state.Theta
    F = stick_force(theta, Psi, Theta, alpha)
    b = math.sin(theta) * (Psi * Psi * math.cos(theta) ** 2 + Theta * Theta) - 1.0
    if F[2] >= 0.0 and abs(F[1]) <= mu * F[2]:
        return Rest("stick", None, F, b)
    if b > 0.0:
        return Rest("liftoff", None, (0.0, 0.0, 0.0), b)
    ok = {}
    for sign_j in (-1.0, 1.0):
        F_n, sigma = _onset(theta, Psi, Theta, mu, alpha, sign_j)
        if 0.0 <= F_n < math.inf and sigma >= 0.0:
            ok[sign_j] = F_n
    if not ok:
        return Rest("inconsistent", None, F, b)
    if len(ok) > 1:
        raise RuntimeError(
            f"two slip directions are consistent at rest at {state!r} (mu = {mu!r}): excluded by the module docstring"
        )
    sign_j, F_n = next(iter(ok.items()))
    return Rest("slip", sign_j * _HALF_PI, (0.0, -mu * F_n * sign_j, F_n), b)


@dataclass(frozen=True, eq=False)
class StickResult:
    """A stick from ``start`` to its end (``stick_until_event``).

    Attributes:
      outcome: SLIP (the friction left the cone, or theta left the domain: ``reason`` says which) or STICK (``t_max``).
      time: real scaled time of the end.
      state: the rod at the end, tip at rest (eta = 0; varphi a placeholder, -pi/2).
      reason: "cone", "t_max", "theta=0" or "theta=pi/2".
      varphi: the slip direction at a cone exit (-pi/2 or +pi/2), else None; the slipping flow takes over from the end
        state at that varphi and eta = ``SLIP_ONSET_SPEED`` (``crosscheck.theory.impact.continuation``).
      force: (F_i, F_j, F_n) at the end [m g].
      t: (n,) times; y: (n, 4) states (psi, theta, Psi, Theta) along the stick.
    """

    outcome: Outcome
    time: float
    state: SlipState
    reason: str
    varphi: float | None
    force: tuple
    t: np.ndarray = field(repr=False)
    y: np.ndarray = field(repr=False)


def stick_until_event(state: SlipState, mu: float, alpha: float, *, t_max: float) -> StickResult:
    """Integrate the rod pivoting about its stuck tip from ``state`` (its eta and varphi ignored) until the friction leaves the cone.

    The start must stick (``at_rest(state).mode == "stick"``).  Events: the
    friction ratio reaches mu (mu F_n - |F_j| falls to 0: SLIP "cone", with
    the slip direction), theta within ``THETA_MARGIN`` of 0 or pi/2 (SLIP,
    the run leaves the domain), ``t_max`` (STICK "t_max").  F_n = 0 needs no
    event: the cone is left before it (module docstring).
    """
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    t_max = float(check("t_max", t_max, HORIZON))
    rest = at_rest(state, mu, alpha)
    if rest.mode != "stick":
        raise ValueError(f"state must stick at rest (F_n >= 0, |F_j| <= mu F_n); its mode at rest is {rest.mode}")

    def rhs(_t, y):
        Psi_dot, Theta_dot = stick_rates(y[1], y[2], y[3], alpha)
        return [y[2], y[3], Psi_dot, Theta_dot]

    def cone(_t, y):
        _, F_j, F_n = stick_force(y[1], y[2], y[3], alpha)
        return mu * F_n - abs(F_j)

    margin = THETA_MARGIN.atol
    events = [cone, lambda _t, y: y[1] - margin, lambda _t, y: _HALF_PI - margin - y[1]]
    reasons = ["cone", "theta=0", "theta=pi/2"]
    for g in events:
        g.terminal, g.direction = True, -1
    y0 = [state.psi, state.theta, state.Psi, state.Theta]
    sol = solve_ivp(rhs, (0.0, t_max), y0, method="DOP853", rtol=_RTOL, atol=_ATOL, events=events)
    if sol.status == -1:
        raise RuntimeError(f"the sticking rod's integration failed: {sol.message}")
    fired = [i for i, te in enumerate(sol.t_events) if len(te)]
    if fired:
        i = min(fired, key=lambda k: sol.t_events[k][0])
        t_end, y = float(sol.t_events[i][0]), sol.y_events[i][0]
        reason = reasons[i]
    else:
        t_end, y, reason = t_max, sol.y[:, -1], "t_max"
    keep = sol.t < t_end
    ts, ys = np.append(sol.t[keep], t_end), np.vstack([sol.y.T[keep], y])
    theta = min(max(float(y[1]), margin), _HALF_PI - margin)
    end = SlipState(theta=theta, varphi=-_HALF_PI, Theta=float(y[3]), Psi=float(y[2]), eta=0.0, psi=float(y[0]))
    F = stick_force(end.theta, end.Psi, end.Theta, alpha)
    varphi = (-_HALF_PI if F[1] > 0.0 else _HALF_PI) if reason == "cone" else None
    outcome = Outcome.STICK if reason == "t_max" else Outcome.SLIP
    return StickResult(outcome, t_end, end, reason, varphi, F, ts, ys)
