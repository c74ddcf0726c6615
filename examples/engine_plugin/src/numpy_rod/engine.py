"""A penalty-contact rod stepped by semi-implicit Euler, in SI units: the engine a solver developer would write.

The rod's five coordinates q = (x, y, z, psi, theta) (centre of mass S, rotation Rz(psi) Rx(theta), axis
d = (-sin psi cos theta, cos psi cos theta, sin theta), tip A = S - l d) with the mass matrix diag(m, m, m,
I0 cos^2 theta, I0).  Its capsule touches the plane at C = A - r K; while C is below the plane (penetration
delta = -z_C > 0) the plane pushes with a Kelvin-Voigt spring-damper F_n = k delta - c dz_C/dt (never pulling) and
a Coulomb friction regularised at slip speeds below ``slip_regularisation``:  F_t = -mu F_n u / sqrt(|u|^2 + eps^2).
Semi-implicit Euler: v_k+1 = v_k + dt M^-1 Q(q_k, v_k), q_k+1 = q_k + dt v_k+1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crosscheck.engines import adapter


@dataclass(frozen=True, kw_only=True)
class Options(adapter.Options):
    """timestep omega dt and radius r / l (scaled, as every crosscheck engine's); stiffness k l / (m g) (the spring in
    units of the rod's weight per length: 1e4 sinks ~1e-4 l under the weight); damping_ratio of the spring with the
    rod's mass; slip_regularisation: the slip speed / (l omega) below which friction is smoothed."""

    LABEL = "numpy penalty rod"  # how messages name the engine: its label
    stiffness: float = 1e4
    damping_ratio: float = 1.0
    slip_regularisation: float = 1e-4

    @property
    def contact_time(self) -> float:
        """The spring's time constant 1 / sqrt(k) in scaled time (its frequency is sqrt(k) omega)."""
        return 1.0 / math.sqrt(self.stiffness)

    @property
    def spring_time(self) -> float:
        """eps of a normal force that is a spring delta / eps^2 (damping aside): a jam lags the rigid one by
        s* (eps^4 / (k |b|))^(1/5) (``crosscheck.theory.jam_lag``), which the comparison allows it."""
        return self.contact_time


def _forces(p: adapter.Problem, k: float, c: float, eps: float, q, v):
    """(generalised force Q (5,), contact force F (3,) [N], contact point C (3,) [m] or None) at (q, v)."""
    m, l, r, g = p.mass, p.length, p.radius, p.gravity
    x, y, z, psi, th = q
    sp, cp, st, ct = math.sin(psi), math.cos(psi), math.sin(th), math.cos(th)
    d = (-sp * ct, cp * ct, st)
    e1 = (cp, sp, 0.0)  # the theta joint's axis
    Q = [0.0, 0.0, -m * g, 2.0 * p.inertia * ct * st * v[4] * v[3], -p.inertia * ct * st * v[3] ** 2]
    arm = (-l * d[0], -l * d[1], -l * d[2] - r)  # C - S
    zc = z + arm[2]
    if zc >= 0.0:
        return Q, (0.0, 0.0, 0.0), None
    w = (v[4] * cp, v[4] * sp, v[3])  # angular velocity psi' K + theta' e1
    vc = (  # velocity of the material point at C: v_S + w x (C - S)
        v[0] + w[1] * arm[2] - w[2] * arm[1],
        v[1] + w[2] * arm[0] - w[0] * arm[2],
        v[2] + w[0] * arm[1] - w[1] * arm[0],
    )
    fn = max(0.0, -k * zc - c * vc[2])
    s = math.sqrt(vc[0] ** 2 + vc[1] ** 2 + eps**2)
    F = (-p.mu * fn * vc[0] / s, -p.mu * fn * vc[1] / s, fn)
    tau = (arm[1] * F[2] - arm[2] * F[1], arm[2] * F[0] - arm[0] * F[2], arm[0] * F[1] - arm[1] * F[0])
    Q[0] += F[0]
    Q[1] += F[1]
    Q[2] += F[2]
    Q[3] += tau[2]  # about K
    Q[4] += tau[0] * e1[0] + tau[1] * e1[1]  # about e1
    return Q, F, (x + arm[0], y + arm[1], zc)


def run(p: adapter.Problem) -> adapter.Rows:
    """The rod of ``p`` over ``p.steps`` steps of ``p.timestep`` seconds (``crosscheck.engines.adapter``)."""
    o = p.options
    scale = p.mass * p.gravity / p.length  # N/m per unit of scaled stiffness
    k = o.stiffness * scale
    c = 2.0 * o.damping_ratio * math.sqrt(k * p.mass)
    eps = o.slip_regularisation * p.length * math.sqrt(p.gravity / p.length)
    dt, n = p.timestep, p.steps
    q, v = np.empty((n + 1, 5)), np.empty((n + 1, 5))
    force, point = np.zeros((n, 3)), np.full((n, 3), np.nan)
    qk, vk = [float(a) for a in p.q0], [float(a) for a in p.v0]
    q[0], v[0] = qk, vk
    minv = (1.0 / p.mass, 1.0 / p.mass, 1.0 / p.mass, 0.0, 1.0 / p.inertia)
    for i in range(n):
        Q, F, C = _forces(p, k, c, eps, qk, vk)
        ct = math.cos(qk[4])
        inv = minv[:3] + (1.0 / (p.inertia * ct * ct) if ct * ct > 1e-12 else 0.0,) + minv[4:]
        vk = [vk[j] + dt * inv[j] * Q[j] for j in range(5)]
        qk = [qk[j] + dt * vk[j] for j in range(5)]
        q[i + 1], v[i + 1], force[i] = qk, vk, F
        if C is not None:
            point[i] = C
        if not math.isfinite(qk[2]) or abs(qk[2]) > 1e6 * p.length:  # blown up: the rest is NaN (DIVERGED)
            q[i + 2 :], v[i + 2 :], force[i + 1 :] = np.nan, np.nan, np.nan
            break
    return adapter.Rows(q=q, v=v, force=force, point=point)


#: What crosscheck runs (``EngineSpec(engine="numpy_rod.engine:ENGINE")``).
ENGINE = adapter.Adapted(name="numpy_rod", run=run, Options=Options)
