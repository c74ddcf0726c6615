"""The compliant rod's dynamics: mass matrix, contact-point Jacobian, forces of each contact mode, and their stiff Jacobian.

Scaled units throughout (section 2.1 of the paper): m = l = g = 1, I0 = 1/alpha
(eq. inertia), time in 1/omega, forces in m g.  Generalised coordinates are
those of ``crosscheck.coordinates``, q = (X, Y, Z, psi, theta), with the
diagonal mass matrix M = diag(1, 1, 1, I0 cos^2 theta, I0) and

    M q'' = Q(q, q') + J_C(q)^T F,    Q = (0, 0, -1, 2 I0 cos theta sin theta theta' psi', -I0 cos theta sin theta psi'^2),

F the world contact force at the rod's material point C = A - r K (the
capsule's lowest point; C = A for r = 0) and J_C its Jacobian (rows x, y, z):

    J_C = [[1, 0, 0, cos theta cos psi, -(sin theta + r) sin psi],
           [0, 1, 0, cos theta sin psi,  (sin theta + r) cos psi],
           [0, 0, 1, 0,                  -cos theta           ]]

(eq. tipfromcentre plus r theta' (-sin psi, cos psi, 0) of the capsule's
rotation).  C's acceleration is a_C = a_free + G F with G = J_C M^-1 J_C^T
the Delassus matrix and a_free = J_C M^-1 Q + J_C' q'.

The integrator's state replaces Z by the gap g = z_A - r = Z - sin theta - r
of the contact point (and Z' by g' = Z' - cos theta theta'): y = (X, Y, g,
psi, theta, X', Y', g', psi', theta').  The stiff force depends on (g, g')
directly, so the solver's error control can be given an absolute tolerance
on g of order eps^2 (the penetration's own scale) without asking the same
of Z and theta, whose difference it would otherwise be.

Contact modes (``FREE``, ``SLIP``, ``STICK``): the normal force is the law's
``push`` (``crosscheck.engines.compliant.laws``), unclipped inside a contact mode
(events end the mode where it crosses zero, so the right-hand side stays
smooth within a mode); friction is exact Coulomb: -mu F_n s/|s| opposite the
slip s = J_t q' of C while slipping, and while stuck the two tangential
unknowns that make C's tangential acceleration vanish,
F_t = -G_tt^-1 (a_free_t + G_tn F_n).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crosscheck.engines.compliant.laws import NormalLaw

__all__ = ["FREE", "SLIP", "STICK", "MODES", "Dynamics", "q_from_y", "y_from_qv", "restart_direction"]

FREE, SLIP, STICK = 0, 1, 2
#: Mode names by code.
MODES = ("free", "slip", "stick")


def y_from_qv(q, v, radius: float) -> np.ndarray:
    """The integrator's state y (gap coordinates) from generalised (q, v), scaled units."""
    q, v = np.asarray(q, float), np.asarray(v, float)
    th = q[..., 4]
    g = q[..., 2] - np.sin(th) - radius
    gd = v[..., 2] - np.cos(th) * v[..., 4]
    return np.concatenate([q[..., :2], g[..., None], q[..., 3:5], v[..., :2], gd[..., None], v[..., 3:5]], axis=-1)


def q_from_y(y, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """Generalised (q, v) [scaled] from the integrator's state y; works on (..., 10) arrays."""
    y = np.asarray(y, float)
    th = y[..., 4]
    Z = y[..., 2] + np.sin(th) + radius
    Zd = y[..., 7] + np.cos(th) * y[..., 9]
    q = np.concatenate([y[..., :2], Z[..., None], y[..., 3:5]], axis=-1)
    v = np.concatenate([y[..., 5:7], Zd[..., None], y[..., 8:10]], axis=-1)
    return q, v


def restart_direction(a_t: np.ndarray, G_tt: np.ndarray, mu_Fn: float) -> np.ndarray:
    """The unit slip direction d in which sliding friction is consistent from rest.

    C at rest with tangential free acceleration a_t (what it would do under the
    normal force alone) and friction -mu F_n d starts to slip along its
    acceleration a_t - mu F_n G_tt d = lambda d with lambda >= 0, so
    d = (lambda I + mu F_n G_tt)^-1 a_t with |d| = 1.  |d(lambda)| falls
    monotonically from |G_tt^-1 a_t| / (mu F_n) (> 1 outside the friction
    cone) to 0, so the root is unique; in G_tt's eigenbasis |d|^2 =
    sum a_i^2 / (lambda + mu F_n g_i)^2 is convex and decreasing, and Newton's
    method from lambda = 0 rises to it monotonically.  On the cone's edge
    (lambda = 0) d = -F_stick / |F_stick|: friction is continuous there.
    Without friction to resist (mu F_n = 0) d = a_t / |a_t|.
    """
    if not mu_Fn > 0.0:
        # no friction to resist (F_n = 0 as a contact just closes, or mu = 0): C slips along its free acceleration
        n = math.hypot(a_t[0], a_t[1])
        return a_t / n if n > 0 else np.array([1.0, 0.0])
    w, V = np.linalg.eigh(G_tt)
    a = V.T @ a_t
    lam = 0.0
    for _ in range(60):
        den = lam + mu_Fn * w
        f = float(np.sum((a / den) ** 2)) - 1.0
        if f <= 1e-15:
            break
        df = float(-2.0 * np.sum(a * a / den**3))
        lam -= f / df
    d = V @ (a / (lam + mu_Fn * w))
    n = math.hypot(d[0], d[1])
    return d / n if n > 0 else np.array([1.0, 0.0])


@dataclass(frozen=True)
class Dynamics:
    """The rod's equations of motion with a compliant unilateral contact at C, in the gap coordinates y.

    Attributes:
      alpha: m l^2 / I0.  mu: Coulomb friction coefficient.  eps, xi: the
      normal law's small parameter and damping.  radius: r / l.  law: the
      ``NormalLaw``.  slip_floor: below this slip speed of C the friction
      direction is the restart direction (``restart_direction``) instead of
      s/|s|, which is undefined at s = 0.  It must lie strictly below the
      slip-stop event's speed (``crosscheck.engines.compliant.tolerances.SLIP_FLOOR``): the
      force is discontinuous at the floor, and the event must be met where
      it is smooth.
    """

    alpha: float
    mu: float
    eps: float
    xi: float
    radius: float
    law: NormalLaw
    slip_floor: float

    # ------------------------------------------------------------------ kinematics
    def terms(self, y):
        """(Minv diag, Q, J_C, dJ_C q', q', G, a_free) at state y (scalar state, (10,))."""
        r, I0 = self.radius, 1.0 / self.alpha
        th, psi = y[4], y[3]
        s, c, sp, cp = math.sin(th), math.cos(th), math.sin(psi), math.cos(psi)
        dpsi, dth = y[8], y[9]
        qd = np.array([y[5], y[6], y[7] + c * dth, dpsi, dth])
        Minv = np.array([1.0, 1.0, 1.0, self.alpha / (c * c), self.alpha])
        Q = np.array([0.0, 0.0, -1.0, 2.0 * I0 * c * s * dth * dpsi, -I0 * c * s * dpsi * dpsi])
        sr = s + r
        J = np.array([[1.0, 0.0, 0.0, c * cp, -sr * sp], [0.0, 1.0, 0.0, c * sp, sr * cp], [0.0, 0.0, 1.0, 0.0, -c]])
        w2 = dpsi * dpsi + dth * dth
        pt = dpsi * dth
        dJv = np.array([-c * sp * w2 - (2.0 * s + r) * cp * pt, c * cp * w2 - (2.0 * s + r) * sp * pt, s * dth * dth])
        MJt = Minv[:, None] * J.T
        G = J @ MJt
        a_free = J @ (Minv * Q) + dJv
        return Minv, Q, J, dJv, qd, G, a_free, MJt

    def slip(self, y) -> np.ndarray:
        """Tangential velocity s of C's material point (world x, y) [l omega]."""
        _, _, J, _, qd, *_ = self.terms(y)
        return J[:2] @ qd

    def push(self, y) -> float:
        """The law's unclipped normal force at y (its sign decides contact)."""
        return self.law.push(-y[2], -y[7], self.eps, self.xi)

    # ------------------------------------------------------------------ forces per mode
    def force(self, y, mode: int, direction=None, terms=None) -> np.ndarray:
        """World contact force F at C [m g] in ``mode`` at state y.

        ``direction``: the restart direction to use while |s| < slip_floor (SLIP).
        """
        if mode == FREE:
            return np.zeros(3)
        Minv, Q, J, dJv, qd, G, a_free, MJt = terms if terms is not None else self.terms(y)
        Fn = self.push(y)
        if mode == SLIP:
            if self.mu == 0.0:
                return np.array([0.0, 0.0, Fn])
            s = J[:2] @ qd
            n = math.hypot(s[0], s[1])
            if n > self.slip_floor:
                u = s / n
            else:
                # C (nearly) at rest: the self-consistent direction of the current state, in which the slip's acceleration
                # is parallel to its friction (``restart_direction``); the segment's ``direction`` only where that is
                # undefined (no normal force yet, or no tangential acceleration)
                a_t = a_free[:2] + G[:2, 2] * Fn
                if Fn > 0.0 and math.hypot(a_t[0], a_t[1]) > 0.0:
                    u = restart_direction(a_t, G[:2, :2], self.mu * Fn)
                else:
                    u = direction if direction is not None else np.array([1.0, 0.0])
            return np.array([-self.mu * Fn * u[0], -self.mu * Fn * u[1], Fn])
        Ft = -np.linalg.solve(G[:2, :2], a_free[:2] + G[:2, 2] * Fn)
        return np.array([Ft[0], Ft[1], Fn])

    def accel(self, y, F, terms=None) -> np.ndarray:
        """(X'', Y'', g'', psi'', theta'') at state y under the contact force F at C (a smooth function of both)."""
        Minv, Q, J, dJv, qd, G, a_free, MJt = terms if terms is not None else self.terms(y)
        qdd = Minv * Q + MJt @ F
        return np.array([qdd[0], qdd[1], a_free[2] + G[2] @ F, qdd[3], qdd[4]])

    def rhs(self, y, mode: int, direction=None) -> np.ndarray:
        """dy/dt in ``mode``."""
        T = self.terms(y)
        out = np.empty(10)
        out[:5] = y[5:]
        out[5:] = self.accel(y, self.force(y, mode, direction, T), T)
        return out

    def _stick_force_at(self, y, Fn) -> np.ndarray:
        """The stuck tangential force at y for a given normal force Fn (the smooth part of the stick force)."""
        Minv, Q, J, dJv, qd, G, a_free, MJt = self.terms(y)
        return -np.linalg.solve(G[:2, :2], a_free[:2] + G[:2, 2] * Fn)

    def jac(self, y, mode: int, direction=None) -> np.ndarray:
        """The right-hand side's Jacobian d(dy/dt)/dy, its stiff and singular parts analytic.

        dy/dt = (y_vel, accel(y, F(y))) with accel smooth and linear in the
        contact force F, so d accel/dy = d accel/dy|_F + B dF/dy, B = d accel/dF
        (exact: M^-1 J_C^T rows and the normal Delassus row).  Analytic:

        * the normal force's dependence on (g, g'), -d push/d delta and
          -d push/d delta' (1/eps^2 and xi/eps: the stiff part), carried
          through the mode's force direction dF/dF_n = (-mu u, 1) slipping or
          (-G_tt^-1 G_tn, 1) stuck;
        * while slipping, the friction direction's dependence u = s/|s| on the
          angles and rates, -mu F_n (I - u u^T)/|s| ds/dy, which grows
          without bound as the slip stops (s = J_t(q) q').

        The O(1) rest (gravity, Coriolis and geometry in d accel/dy|_F; the
        stuck force's dependence on y at fixed F_n) by forward differences
        with steps sqrt(machine eps) (1 + |y_i|): 10 evaluations of the
        smooth functions, relative error ~1e-8, ample for Newton's iteration.

        Measured: leaving that O(1) rest out (only the stiff and direction
        parts) cost 2.8-4.9x the time on a slip-stop-stick run (Newton's
        iteration converges slowly at the solver's steps h ~ 0.01-0.1, where
        h |O(1) Jacobian error| is not small); with it, scipy's own
        finite-difference Jacobian of the whole right-hand side takes 1.25x
        the CPU time of this one (``benchmarks/bench_compliant.py``, 12
        slipping states, eps = 1e-2), at the same accuracy.
        """
        jac = np.zeros((10, 10))
        jac[:5, 5:] = np.eye(5)
        T = self.terms(y)
        Minv, Q, J, dJv, qd, G, a_free, MJt = T
        F = self.force(y, mode, direction, T)
        acc0 = self.accel(y, F, T)
        h = 1.4901161193847656e-08 * (1.0 + np.abs(y))
        stuck = mode == STICK
        Fn = F[2]
        for i in range(10):
            yi = y.copy()
            yi[i] += h[i]
            Fi = F
            if stuck:
                Fi = np.array([*self._stick_force_at(yi, Fn), Fn])
            jac[5:, i] = (self.accel(yi, Fi) - acc0) / h[i]
        if mode == FREE:
            return jac
        B = np.vstack([MJt[0], MJt[1], G[2], MJt[3], MJt[4]])
        kd, cd = self.law.dpush(-y[2], -y[7], self.eps, self.xi)
        th, psi = y[4], y[3]
        c, sn, sp, cp = math.cos(th), math.sin(th), math.sin(psi), math.cos(psi)
        if mode == SLIP:
            s = J[:2] @ qd
            n = math.hypot(s[0], s[1])
            if self.mu == 0.0:
                dF = np.array([0.0, 0.0, 1.0])
            elif n > self.slip_floor:
                u = s / n
                dF = np.array([-self.mu * u[0], -self.mu * u[1], 1.0])
                # ds/dy: s = J_t(psi, theta) q', q' = (X', Y', g' + cos theta theta', psi', theta'); J_t has no Z' column
                dpsi, dth, r = y[8], y[9], self.radius
                ds = np.zeros((2, 10))
                ds[0, 3] = -c * sp * dpsi - (sn + r) * cp * dth
                ds[1, 3] = c * cp * dpsi - (sn + r) * sp * dth
                ds[0, 4] = -sn * cp * dpsi - c * sp * dth
                ds[1, 4] = -sn * sp * dpsi + c * cp * dth
                ds[:, 5], ds[:, 6] = J[:2, 0], J[:2, 1]
                ds[:, 8], ds[:, 9] = J[:2, 3], J[:2, 4]
                P = (np.eye(2) - np.outer(u, u)) / n
                jac[5:] += B[:, :2] @ (-self.mu * Fn * (P @ ds))
            else:
                u = direction if direction is not None else np.array([1.0, 0.0])
                dF = np.array([-self.mu * u[0], -self.mu * u[1], 1.0])
        else:
            dF = np.append(-np.linalg.solve(G[:2, :2], G[:2, 2]), 1.0)
        col = B @ dF
        # F_n = push(delta = -g, delta' = -g'): dF_n/dg = -kd, dF_n/dg' = -cd
        jac[5:, 2] += -kd * col
        jac[5:, 7] += -cd * col
        return jac

    def tip_acceleration(self, y, F, terms=None) -> np.ndarray:
        """Acceleration of the tip A (world, / g, gravity included) under contact force F at C (``terms``: ``terms(y)``
        when the caller has them)."""
        Minv, Q, J, dJv, qd, G, a_free, MJt = terms if terms is not None else self.terms(y)
        qdd = Minv * Q + MJt @ F
        th, psi = y[4], y[3]
        s, c, sp, cp = math.sin(th), math.cos(th), math.sin(psi), math.cos(psi)
        JA = J.copy()
        JA[0, 4], JA[1, 4] = -s * sp, s * cp
        dpsi, dth = y[8], y[9]
        w2, pt = dpsi * dpsi + dth * dth, dpsi * dth
        dJvA = np.array([-c * sp * w2 - 2.0 * s * cp * pt, c * cp * w2 - 2.0 * s * sp * pt, s * dth * dth])
        return JA @ qdd + dJvA

    def energy(self, y) -> float:
        """Total mechanical energy [m g l]: kinetic + gravity (Z) + the law's elastic energy while penetrating.

        Non-increasing for xi >= 0 and mu >= 0: the dashpot dissipates xi/eps delta'^2,
        friction mu F_n |s|, and where the clipped force is zero at delta > 0 the
        spring energy only drains (module docstring of ``crosscheck.engines.compliant``).
        """
        q, v = q_from_y(y, self.radius)
        c = math.cos(q[4])
        T = 0.5 * (v[0] ** 2 + v[1] ** 2 + v[2] ** 2) + 0.5 / self.alpha * (c * c * v[3] ** 2 + v[4] ** 2)
        delta = -y[2]
        return T + q[2] + (self.law.energy(delta, self.eps) if delta > 0 else 0.0)
