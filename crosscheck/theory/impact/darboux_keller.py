"""Impact without collision in 3D: the rigid rod's tangential impulse at a jam, integrated in normal impulse P (Darboux-Keller).

Where a slipping rod reaches p = 0 with b < 0 the rigid model has no slipping
solution (Corollary 4.2) and the paper recalls the classical way out:
Lecornu's "arc-boutement dynamique", an impulse with no collision (Darboux,
Keller).  During the impulse the configuration does not move and the
velocities change with the normal impulse P as the independent variable:

    dv/dP = M^-1 J^T (f_t, 1),     so the tip velocity u = J v obeys du/dP = G (f_t, 1),

with M the rod's mass matrix, J the tip Jacobian (rows x, y, z of the world),
G = J M^-1 J^T the Delassus matrix (constant during the impulse) and f_t the
friction per unit normal impulse:

* slip: f_t = -mu u_t / |u_t|, opposite the *instantaneous* slip of the tip,
  so in 3D the slip direction (and with it varphi and p) turns during the
  impulse; du_n/dP = G_nn + G_nt f_t is eq. p for the current direction.
  With p < 0 the tip is driven into the plane (u_n < 0: compression) while
  the slip decelerates;
* stick: when the slip stops, the tangential impulse that keeps u_t = 0 is
  f_s = -G_tt^-1 G_tn, and du_n/dP = G_nn + G_nt f_s = S > 0 (the Schur
  complement of G, positive since G is).

Why a stopped slip always sticks (no re-slip for this rod), why the compression never ends while the tip slips
(an impulse is a slip phase to its stop, then a stick phase where compression ends at P_c and Poisson's hypothesis
ends the impulse at P_f = (1 + e) P_c), and how a start on the boundary p = 0 is the limit of starts inside it
(``P_TOLERANCE``; ``boundary=True`` for a GB arrival): ``docs/darboux_keller.md``.

Everything is in the paper's scaled units (m = l = g = 1, I0 = 1/alpha;
impulses in m g / omega, velocities in l omega).  The mass matrix and the
Jacobian are the analytic model's (eq. inertia, eq. tipfromcentre), checked
against Pinocchio's Delassus operator in tests.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import ALPHA, MU, check
from crosscheck.coordinates import qv_to_paper, to_generalized
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.tolerances import GB_REACHED

__all__ = ["Phase", "Impact", "delassus", "turning_rate", "impact", "P_TOLERANCE"]

#: A state counts as at or past p = 0 when eq. p is at most this (rounding of the O(1 + alpha)
#: terms of eq. p, times a margin; the slipping flow stops its runs at p = -1e-8).
P_TOLERANCE = 1e-12

#: Relative accuracy of the integration in P (DOP853) and the slip speed counted as stopped.
_RTOL, _ATOL = 1e-12, 1e-14


@dataclass(frozen=True)
class Phase:
    """One phase of the impulse: "slip" or "stick", between normal impulses [P_start, P_end]."""

    name: str
    P_start: float
    P_end: float


@dataclass(frozen=True, eq=False)
class Impact:
    """What ``impact`` computed (scaled units).

    Attributes:
      state: the state before the impulse.
      mu, alpha, restitution: the parameters.
      Theta, Psi: rates after the impulse.
      eta, varphi: slip speed and slip angle of the tip after it: 0 and None
        (the slip always stops within the impulse, module docstring; eta is
        the computed speed where it exceeds the integration's stop speed).
      w: normal velocity of the tip after it (0 for e = 0; > 0 lifts off).
      normal_impulse: P_f; compression_impulse: P_c.
      tangential_impulse: (2,) world x, y [m g / omega].
      phases: the ``Phase``s in order.
      energy_lost: kinetic energy before minus after [m g l], never negative.
      v_before, v_after: generalised velocities (5,) [scaled].
    """

    state: SlipState
    mu: float
    alpha: float
    restitution: float
    Theta: float
    Psi: float
    eta: float
    varphi: float | None
    w: float
    normal_impulse: float
    compression_impulse: float
    tangential_impulse: np.ndarray
    phases: tuple
    energy_lost: float
    v_before: np.ndarray = field(repr=False)
    v_after: np.ndarray = field(repr=False)


def _mass_and_jacobian(theta: float, psi: float, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """Scaled M = diag(1, 1, 1, I0 cos^2 theta, I0) (eq. inertia, I0 = 1/alpha) and the tip Jacobian J (3, 5) (eq. tipfromcentre)."""
    I0 = 1.0 / alpha
    s, c, sp, cp = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    M = np.diag([1.0, 1.0, 1.0, I0 * c * c, I0])
    J = np.array([[1.0, 0.0, 0.0, c * cp, -s * sp], [0.0, 1.0, 0.0, c * sp, s * cp], [0.0, 0.0, 1.0, 0.0, -c]])
    return M, J


def delassus(state: SlipState, alpha: float) -> np.ndarray:
    """G = J M^-1 J^T at the state's configuration, world axes (x, y, z), scaled units."""
    M, J = _mass_and_jacobian(state.theta, state.psi, float(check("alpha", alpha, ALPHA)))
    return J @ np.linalg.solve(M, J.T)


def _p_of(G: np.ndarray, u_t: np.ndarray, mu: float) -> float:
    """du_n/dP while slipping along u_t: eq. p for the current direction."""
    n = np.linalg.norm(u_t)
    return float(G[2, 2] - mu * G[2, :2] @ u_t / n)


def turning_rate(G: np.ndarray, u_t: np.ndarray, mu: float) -> float:
    """k = -dp/dP at the start of a slipping impulse (module docstring): >= 0 in the paper's domain, 0 on varphi = -pi/2."""
    n = float(np.linalg.norm(u_t))
    u_hat = u_t / n
    du_t = G[:2, :2] @ (-mu * u_hat) + G[:2, 2]
    return float(mu * G[2, :2] @ ((np.eye(2) - np.outer(u_hat, u_hat)) @ du_t) / n)


def _check_p(p0: float, boundary: bool) -> None:
    """ValueError unless eq. p at the start, p0, allows an impact without collision: |p0| <= ``GB_REACHED.atol`` on
    the ``boundary``, p0 <= ``P_TOLERANCE`` otherwise."""
    if boundary and not abs(p0) <= GB_REACHED.atol:
        raise ValueError(
            f"p must be in [-{GB_REACHED.atol:g}, {GB_REACHED.atol:g}] for an impact on the boundary p = 0; got p = {p0!r}"
        )
    if not boundary and p0 > P_TOLERANCE:
        raise ValueError(
            f"p must be <= {P_TOLERANCE:g} (at or past the paradox boundary) for an impact without collision; "
            f"got p = {p0!r} at this state: it can slip (a state known to be on p = 0, a GB arrival, takes boundary=True)"
        )


def _slip_to_stop(G: np.ndarray, u0: np.ndarray, mu: float, *, shift: float, scale: float, stop: float):
    """The slipping compression in the normal impulse P from the tip velocity u0 (3,) until the slip speed falls to
    ``stop``: returns (P_s, y) with y = (u_x, u_y, u_n, L_x, L_y) there, u_n measured from the start's 0 and its
    rate du_n/dP less ``shift`` (the start's p_0 on the boundary, module docstring)."""

    def slip_rhs(_P, y):
        ut = y[:2]
        f = -mu * ut / np.linalg.norm(ut)
        du = G @ np.array([f[0], f[1], 1.0])
        du[2] -= shift
        return np.concatenate([du, f])

    def slip_stop(_P, y):
        return np.linalg.norm(y[:2]) - stop

    slip_stop.terminal, slip_stop.direction = True, -1
    y = np.concatenate([u0, [0.0, 0.0]])
    y[2] = 0.0
    sol = solve_ivp(
        slip_rhs, (0.0, 1e3 * scale), y, method="DOP853", rtol=_RTOL, atol=_ATOL * scale, events=[slip_stop]
    )
    if sol.status != 1:
        raise RuntimeError(f"impulse integration failed: {sol.message or 'the slip did not stop within P = 1e3 scale'}")
    return float(sol.t[-1]), sol.y[:, -1].copy()


def impact(state: SlipState, mu: float, alpha: float, *, restitution: float = 0.0, boundary: bool = False) -> Impact:
    """The impulse of an impact without collision from a slipping state at or past p = 0.

    Args:
      state: a ``SlipState`` on the plane (tip normal velocity 0) with eq. p
        <= ``P_TOLERANCE`` and eta > 0.
      mu: friction coefficient (> 0 for a paradox).
      alpha: m l^2 / I0.
      restitution: Poisson's coefficient e in [0, 1].
      boundary: the caller knows ``state`` is on p = 0 to within
        ``crosscheck.tolerances.GB_REACHED`` (a GB arrival of the slipping
        flow): its impulse is the limit p -> 0- (module docstring).  A state
        with |p| <= ``P_TOLERANCE`` gets that limit without being told.

    Returns:
      ``Impact``.  On the boundary, ``w`` is the limit's normal velocity (the
      start's own p_0 P_f, rounding of its position on p = 0, left out; the
      generalised ``v_after`` keeps it).

    Raises:
      ValueError: an argument out of range, eta <= 0, p > ``P_TOLERANCE``
        (no impulse: the rod can slip; use ``crosscheck.theory.slipping``),
        or, with ``boundary``, |p| > ``GB_REACHED.atol``.
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    e = float(check("restitution", restitution))
    if not 0.0 <= e <= 1.0:
        raise ValueError(f"restitution must be in [0, 1]; got {restitution!r}")
    if not state.eta > 0.0:
        raise ValueError(f"eta must be in (0, inf) for an impact without collision (a slipping tip); got {state.eta!r}")
    rod = Rod.scaled(alpha)
    q, v0 = to_generalized(rod, state)
    M, J = _mass_and_jacobian(state.theta, state.psi, alpha)
    Minv_JT = np.linalg.solve(M, J.T)
    G = J @ Minv_JT
    u0 = J @ v0
    p0 = _p_of(G, u0[:2], mu)
    _check_p(p0, boundary)
    on_boundary = boundary or abs(p0) <= P_TOLERANCE
    scale = 1.0 + float(np.linalg.norm(u0))
    stop = 1e-12 * scale
    f_s = -np.linalg.solve(G[:2, :2], G[:2, 2])
    if not np.linalg.norm(f_s) < mu:
        # unreachable for the slender rod (module docstring): an impulse starts only where mu > |f_s|
        raise RuntimeError(
            f"the sticking impulse |f_s| = {np.linalg.norm(f_s)!r} is outside the cone mu = {mu!r} at a state with p <= 0"
        )
    S = float(G[2, 2] + G[2, :2] @ f_s)
    # On the boundary the slip's du_n/dP is measured from the start's p_0: the limit p_0 -> 0- (module docstring).
    shift = p0 if on_boundary else 0.0

    phases: list[Phase] = []
    # 1. slipping compression, to the slip stop (p never increases along the slip: the compression cannot end before it)
    P_s, y = _slip_to_stop(G, u0, mu, shift=shift, scale=scale, stop=stop)
    phases.append(Phase("slip", 0.0, P_s))
    # 2. stick (|f_s| < mu): u_n rises linearly at S from its value at the stop; compression ends at P_c, Poisson's impulse at P_f
    y[:2] = 0.0
    P_c = P_s + max(0.0, -y[2]) / S
    P = (1.0 + e) * P_c
    y[2] += S * (P - P_s)
    y[3:] += f_s * (P - P_s)
    phases.append(Phase("stick", P_s, P))
    L = np.array([y[3], y[4], P])
    v1 = v0 + Minv_JT @ L
    d = qv_to_paper(rod, q, v1)
    u1 = J @ v1
    eta1 = float(np.hypot(u1[0], u1[1]))
    stuck = eta1 <= 10 * stop
    energy = 0.5 * float(v0 @ M @ v0 - v1 @ M @ v1)
    return Impact(
        state=state,
        mu=mu,
        alpha=alpha,
        restitution=e,
        Theta=float(d["Theta"]),
        Psi=float(d["Psi"]),
        eta=0.0 if stuck else eta1,
        varphi=None if stuck else float(d["varphi"]),
        w=float(y[2]) if on_boundary else float(u1[2]),
        normal_impulse=float(P),
        compression_impulse=float(P_c),
        tangential_impulse=L[:2].copy(),
        phases=tuple(phases),
        energy_lost=energy,
        v_before=v0,
        v_after=v1,
    )
