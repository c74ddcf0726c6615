"""Bullet's friction law in continuous time: the rigid capsule whose friction opposes diag(D)^-1 u in world axes, not the slip.

Bullet's multibody solver (btMultiBodyConstraintSolver) puts the two friction
rows of a contact with the plane z = 0 along fixed world axes (btPlaneSpace1
of the normal +z: -y and x; the branch that would align the first row with
the slip is commented out in ``convertMultiBodyContact``), and its cone
friction (``enableConeFriction``) updates each row with its own diagonal
D_x, D_y of the Delassus operator before clipping the pair to the disk
|F_t| <= mu F_n.  At the fixed point of those sweeps a slipping contact's
friction lies on the disk's edge along

    -diag(1 / D_x, 1 / D_y) u        (world axes; u: C's slip velocity),

not along -u.  With the rod's tangential Delassus block diagonal in its own
(i, j) frame, A_ii = 1 + alpha across the rod and A_jj = 1 + alpha (sin theta
+ r)^2 along its horizontal projection (scaled units; the MuJoCo law's
docstring derives them), the world diagonals are

    D_x = A_ii cos^2 psi + A_jj sin^2 psi,   D_y = A_ii sin^2 psi + A_jj cos^2 psi,

so the friction turns off the slip by up to 13-28 degrees at theta ~ 0.2-0.35
(A_ii / A_jj ~ 3), and by an amount that depends on the rod's azimuth psi:
Bullet's outcome from a start changes when the start is turned about the
vertical, which the theory's does not (measured at dt = 1e-3 from theta 0.227,
varphi -1.9, Theta 0.5625, Psi 1.7, mu 1.4: lift-off at 0.224, 0.214, 0.216,
0.230 for psi = 0, pi/8, pi/4, 3 pi/8; the theory 0.2138).

This module is that law in continuous time: the rigid capsule of
``crosscheck.theory.capsule`` (contact at C = A - r K, F_z = -b / p_eff) with
the friction along the direction above, the angle varphi_f of
``friction_angle`` in the rod's frame taking the place of C's slip angle in
every force term (p_eff is eq. p at C with varphi_f; the projections of the
acceleration on the slip keep varphi).  It is the capsule theory's own
desingularised flow, events and start rules with that friction
(``crosscheck.theory.capsule.slip_until_event``'s ``friction``), so with
``axes="slip"`` (varphi_f = varphi) it is the capsule theory to the last bit.  Bullet's ladder (``crosscheck.studies.ladder``) has it as the rung
between the rigid capsule and Bullet's own step.

Scaled units (section 2.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from crosscheck.engines.bullet.options import FRICTION_AXES
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.theory import capsule

__all__ = ["AXES", "friction_angle", "slip_until_event", "LawRun", "friction_law"]

#: Where the friction rows lie: "world" (Bullet's fixed x, y axes) or "slip" (along C's slip: Coulomb's law).
AXES = FRICTION_AXES


def friction_angle(varphi, psi, theta, alpha, r):
    """varphi_f: the friction's direction -(cos varphi_f i + sin varphi_f j) in the rod's frame, for C's slip at varphi
    (module docstring; scalars)."""
    cpsi, spsi = math.cos(psi), math.sin(psi)
    a_ii, a_jj = 1.0 + alpha, 1.0 + alpha * (math.sin(theta) + r) ** 2
    d_x, d_y = a_ii * cpsi * cpsi + a_jj * spsi * spsi, a_ii * spsi * spsi + a_jj * cpsi * cpsi
    ui, uj = math.cos(varphi), math.sin(varphi)
    ux, uy = (cpsi * ui - spsi * uj) / d_x, (spsi * ui + cpsi * uj) / d_y  # diag(D)^-1 u in world axes
    return math.atan2(-spsi * ux + cpsi * uy, cpsi * ux + spsi * uy)  # back in the rod's (i, j) frame


def slip_until_event(
    state: SlipState, mu, alpha, *, radius, axes: str = "world", t_max: float = 10.0, s_max: float = 1e4
):
    """The rigid capsule with Bullet's friction law from ``state`` (its psi included) to its first event: the capsule
    theory (``crosscheck.theory.capsule.slip_until_event``: its start rules, events and result) with the friction along
    ``friction_angle``, and eq. p at C taken at that angle (p_eff).  ``axes``: "world" (Bullet's) or "slip" (Coulomb's:
    the capsule theory itself).  Returns a ``crosscheck.theory.capsule.CapsuleSlipResult`` (its ``p``: p_eff).
    """
    if axes not in AXES:
        raise ValueError(f"axes must be one of {', '.join(AXES)}; got {axes!r}")
    friction = None if axes == "slip" else (lambda y: friction_angle(y[1], y[2], y[4], float(alpha), float(radius)))
    return capsule.slip_until_event(state, mu, alpha, radius=radius, t_max=t_max, s_max=s_max, friction=friction)


@dataclass(frozen=True)
class LawRun:
    """A rung's outcome for the ladder: the first event and its time (``result``: the whole ``CapsuleSlipResult``)."""

    outcome: Outcome
    event_time: float
    result: object


def friction_law(rod, state: SlipState, mu, *, horizon, thresholds=None, options) -> LawRun:
    """Bullet's ladder rung "friction law": this law at Bullet's capsule radius and friction axes, to ``horizon``."""
    res = slip_until_event(state, mu, rod.alpha, radius=options.radius, axes=options.friction_axes, t_max=horizon)
    return LawRun(Outcome(int(res.outcome)), float(res.time), res)
