"""The rod's tip kinematics, free acceleration and Delassus operator in closed form, vectorised over a batch of states.

These are the terms Pinocchio computes for one step of the rigid engine
(``crosscheck.engines.pinocchio.stepper``), written out for the chain PX,
PY, PZ, RZ (psi), RX (theta) of ``crosscheck.engines.pinocchio.model``, so
that a batch of B states is one numpy expression per term instead of B
Python loops over Pinocchio calls.  Physical units, world axes; q = (X, Y, Z,
psi, theta), v its rate; c = cos theta, s = sin theta.

* Tip A = S + Rz(psi) Rx(theta) (0, -l, 0) = (X + l c sin psi, Y - l c cos psi, Z - l s).
* J = dA/dq: the identity on (X, Y, Z), J_psi = l c (cos psi, sin psi, 0),
  J_theta = (-l s sin psi, l s cos psi, -l c).
* dJ v (the classical tip acceleration at qdd = 0):
  (-l [c sin psi (Theta^2 + Psi^2) + 2 s cos psi Theta Psi],
   l [c cos psi (Theta^2 + Psi^2) - 2 s sin psi Theta Psi], l s Theta^2) with
  (Psi, Theta) = (psi', theta') here in rad/s.
* M = diag(m, m, m, I0 c^2, I0) (the slender rod of eq. inertia) and
  C v + g = (0, 0, m g, -2 I0 c s theta' psi', I0 c s psi'^2) (Lagrange's
  equations of T = m |v_S|^2 / 2 + I0 (c^2 psi'^2 + theta'^2) / 2), so the
  free acceleration M^-1 (-C v - g) = (0, 0, -g, 2 tan theta theta' psi', -c s psi'^2).
* G = J M^-1 J^T = I / m + l^2 / I0 (e_psi e_psi^T + (s e_perp - c e_z)(s e_perp - c e_z)^T)
  with e_psi = (cos psi, sin psi, 0), e_perp = (-sin psi, cos psi, 0): the
  J_psi / c of M^-1 never divides by cos theta, so G has no condition number
  1 / cos^2 theta (Pinocchio's, ``crosscheck.engines.pinocchio.tolerances``).

tests/test_engine_pinocchio_batch.py checks every term against Pinocchio's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crosscheck.rod import Rod

__all__ = ["Angles", "TipTerms", "angles", "tip_terms", "jacobian_times", "free_velocity", "velocity_change"]


@dataclass(frozen=True)
class Angles:
    """cos and sin of theta and psi at B states, (B,) each: computed once per step, shared by every term."""

    c: np.ndarray
    s: np.ndarray
    cp: np.ndarray
    sp: np.ndarray


def angles(q: np.ndarray) -> Angles:
    """``Angles`` of q (B, 5)."""
    return Angles(np.cos(q[:, 4]), np.sin(q[:, 4]), np.cos(q[:, 3]), np.sin(q[:, 3]))


@dataclass(frozen=True)
class TipTerms:
    """The tip's terms at B states (physical units, world axes).

    Attributes:
      pos: (B, 3) tip A [m].
      dJv: (B, 3) its classical acceleration at qdd = 0 [m/s^2].
      G: (B, 3, 3) the Delassus operator J M^-1 J^T [m/s per N s].
    """

    pos: np.ndarray
    dJv: np.ndarray
    G: np.ndarray


def jacobian_times(rod: Rod, A: Angles, x: np.ndarray) -> np.ndarray:
    """J x, (..., B, 3), for generalised velocities x (..., B, 5) (leading axes: several vectors per state)."""
    L = rod.length
    out = x[..., :3].copy()
    lc_psi, ls_theta = L * A.c * x[..., 3], L * A.s * x[..., 4]
    out[..., 0] += lc_psi * A.cp - ls_theta * A.sp
    out[..., 1] += lc_psi * A.sp + ls_theta * A.cp
    out[..., 2] -= L * A.c * x[..., 4]
    return out


def tip_terms(rod: Rod, q: np.ndarray, v: np.ndarray, A: Angles | None = None) -> TipTerms:
    """``TipTerms`` at the states (q, v), each (B, 5) [physical] (the tip's velocity is ``jacobian_times(rod, A, v)``)."""
    A = A if A is not None else angles(q)
    L, c, s, cp, sp = rod.length, A.c, A.s, A.cp, A.sp
    Psi, Theta = v[:, 3], v[:, 4]
    B = q.shape[0]
    pos = np.empty((B, 3))
    pos[:, 0] = q[:, 0] + L * c * sp
    pos[:, 1] = q[:, 1] - L * c * cp
    pos[:, 2] = q[:, 2] - L * s
    rates2, cross = Theta * Theta + Psi * Psi, 2.0 * s * Theta * Psi
    dJv = np.empty((B, 3))
    dJv[:, 0] = -L * (c * sp * rates2 + cross * cp)
    dJv[:, 1] = L * (c * cp * rates2 - cross * sp)
    dJv[:, 2] = L * s * Theta * Theta
    # G = I/m + (l^2/I0) (e_psi e_psi^T + w w^T), w = J_theta / l = (-s sin psi, s cos psi, -c)
    k, m_inv = L * L / rod.inertia, 1.0 / rod.mass
    wx, wy = -s * sp, s * cp
    G = np.empty((B, 3, 3))
    G[:, 0, 0] = k * (cp * cp + wx * wx) + m_inv
    G[:, 1, 1] = k * (sp * sp + wy * wy) + m_inv
    G[:, 2, 2] = k * c * c + m_inv
    G[:, 0, 1] = G[:, 1, 0] = k * (cp * sp + wx * wy)
    G[:, 0, 2] = G[:, 2, 0] = -k * c * wx
    G[:, 1, 2] = G[:, 2, 1] = -k * c * wy
    return TipTerms(pos=pos, dJv=dJv, G=G)


def free_velocity(rod: Rod, q: np.ndarray, v: np.ndarray, dt: float, A: Angles | None = None) -> np.ndarray:
    """v + dt M^-1 (-C v - g), (B, 5): the step's velocity without contact (Pinocchio's ``aba`` with tau = 0)."""
    A = A if A is not None else angles(q)
    c, s, Psi, Theta = A.c, A.s, v[:, 3], v[:, 4]
    out = v.copy()
    out[:, 2] -= dt * rod.gravity
    out[:, 3] += dt * (2.0 * (s / c) * Theta * Psi)
    out[:, 4] -= dt * (c * s * Psi * Psi)
    return out


def velocity_change(rod: Rod, q: np.ndarray, impulse: np.ndarray, A: Angles | None = None) -> np.ndarray:
    """M^-1 J^T lambda, (B, 5), for tip impulses lambda (B, 3) [N s, world axes]."""
    A = A if A is not None else angles(q)
    L, c, s, cp, sp = rod.length, A.c, A.s, A.cp, A.sp
    lx, ly, lz = impulse[:, 0], impulse[:, 1], impulse[:, 2]
    out = np.empty((q.shape[0], 5))
    out[:, :3] = impulse / rod.mass
    # J_psi^T lambda / (I0 c^2) = l (cos psi lx + sin psi ly) / (I0 c)
    out[:, 3] = L * (cp * lx + sp * ly) / (rod.inertia * c)
    out[:, 4] = L * (s * (cp * ly - sp * lx) - c * lz) / rod.inertia
    return out
