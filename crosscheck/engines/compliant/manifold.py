"""The compliant rod's slow manifold: the quasi-static penetration and rate of a slipping rod (eq. FZ in the limit eps -> 0).

While the contact point C slips, the rigid rod's normal force is the one that
keeps C's normal acceleration zero, F_z = -a_free_n / (G_nn - mu G_nt u)
(u the slip direction, G the Delassus matrix at C, a_free_n C's free normal
acceleration); at the tip (r = 0) this is eq. FZ, F_z = -b/p.  The compliant
rod follows the rigid one up to O(eps^2) when its penetration tracks that
force: push(delta, delta') = F_z with delta' = eps^2 dF_z/dt (the
derivative of delta = eps^2 F_z along the slipping flow).  For Kelvin-Voigt
that is delta = eps^2 (F_z - xi eps dF_z/dt).  A start off this manifold
excites the contact's fast oscillation (decaying at the rate ~xi/eps with
damping) and costs the slow variables an extra O(eps^2) offset.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.engines.compliant.model import Dynamics
from crosscheck.engines.compliant.trajectory import make_dynamics, start_state
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["rigid_normal_force", "slow_manifold"]


def rigid_normal_force(dyn: Dynamics, y) -> float:
    """The rigid rod's slipping normal force at C [m g] at state y: C's normal acceleration zero (eq. FZ at r = 0)."""
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    s = J[:2] @ qd
    n = math.hypot(s[0], s[1])
    u = s / n if n > 0 else np.zeros(2)
    return float(-a_free[2] / (G[2, 2] - dyn.mu * G[2, :2] @ u))


def _slipping_rate(dyn: Dynamics, y) -> np.ndarray:
    """dy/dt of the rigid slipping rod (force rigid_normal_force, friction against the slip)."""
    Fz = rigid_normal_force(dyn, y)
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    s = J[:2] @ qd
    u = s / math.hypot(s[0], s[1])
    F = np.array([-dyn.mu * Fz * u[0], -dyn.mu * Fz * u[1], Fz])
    return np.concatenate([y[5:], dyn.accel(y, F)])


def slow_manifold(
    rod: Rod, state: SlipState, mu: float, *, eps: float, xi: float, radius: float = 0.0, law="kelvin-voigt"
) -> tuple[float, float]:
    """(gap, gap_rate) that start ``integrate`` on the slow manifold from a slipping ``state``.

    The penetration delta = -gap solves push(delta, delta') = F_z (Newton on
    the law, from delta = eps^2 F_z) with delta' = eps^2 dF_z/dt = -gap_rate;
    dF_z/dt by a central difference along the rigid slipping flow (step 1e-5:
    truncation 1e-10, rounding 1e-11 relative).  Requires a slipping start
    (C's slip speed > 0) with F_z > 0.
    """
    dyn = make_dynamics(rod.alpha, mu, eps=eps, xi=xi, radius=radius, law=law)
    y = start_state(rod, state, dyn, gap=0.0, gap_rate=0.0)
    if not math.hypot(*dyn.slip(y)) > 0.0:
        raise ValueError("state must slip at its contact point for a slow-manifold start; got a contact point at rest")
    Fz = rigid_normal_force(dyn, y)
    if not Fz > 0.0:
        raise ValueError(
            f"state must press on the plane (rigid normal force > 0) for a slow-manifold start; got F_z = {Fz:g}"
        )
    h = 1e-5
    f = _slipping_rate(dyn, y)
    dFz = (rigid_normal_force(dyn, y + h * f) - rigid_normal_force(dyn, y - h * f)) / (2.0 * h)
    rate = eps * eps * dFz
    delta = eps * eps * Fz
    for _ in range(50):
        r = dyn.law.push(delta, rate, eps, xi) - Fz
        kd, _ = dyn.law.dpush(delta, rate, eps, xi)
        step = r / kd
        delta -= step
        if abs(step) <= 1e-15 * abs(delta):
            break
    return -delta, -rate
