"""MuJoCo-only measurements: its contact force against eq. linode2 at the capsule point, and its friction direction.

Two properties of MuJoCo's contact that no other engine shares and that the
event studies need to explain what they see:

* ``capsule_tip_acceleration`` / ``contact_acceleration``: MuJoCo applies its
  contact force at the capsule's contact point, a radius (plus half the
  penetration) below the tip A, not at A; with that offset, eq. linode2
  reproduces MuJoCo's tip acceleration to the solver's accuracy.
* ``friction_skew``: MuJoCo's soft elliptic friction saturates the cone
  (|F_t| = mu F_z) but is not anti-parallel to the slip off the planar
  section, so its slipping normal force is -b/p_eff, not -b/p.

Scaled units (section 2.1) unless a docstring says physical.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from mujoco import rollout

from crosscheck.checks import ALPHA, MU, POSITIVE, check
from crosscheck.engines.base import n_steps
from crosscheck.engines.mujoco.model import SensorLayout, build_model, initial_state, record_from_sensordata
from crosscheck.engines.mujoco.options import Options
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory.analytic import tip_acceleration

__all__ = ["checks", "capsule_tip_acceleration", "contact_acceleration", "friction_skew"]


def capsule_tip_acceleration(rod: Rod, psi, theta, psi_dot, theta_dot, force, offset) -> np.ndarray:
    """Tip acceleration of eq. linode2 when the force acts a distance ``offset`` below A.

    The capsule touches the plane at P = A - offset K (offset = r for the lowest
    point of the cap; MuJoCo applies the force midway into the penetration,
    offset = r + dist / 2 with dist < 0).  Moving the force from A to P adds the
    torque (-offset K) x F = offset (F_y, -F_x, 0); its component on the theta
    axis i = (cos psi, sin psi, 0) is offset (F_y cos psi - F_x sin psi), its
    component on the psi axis K is 0, and the rest is carried by the joints
    (the rod has no axial rotation).  The extra theta'' = that torque / I0
    moves A by d(A - S)/d theta = l (-sin theta sin psi, sin theta cos psi,
    -cos theta).

    Args: as ``crosscheck.theory.analytic.tip_acceleration`` (physical units, force
      (..., 3) world frame [N]), plus offset [m], broadcasting.

    Returns:
      (..., 3) tip accelerations [m/s^2], world frame, gravity included.
    """
    a = tip_acceleration(rod, psi, theta, psi_dot, theta_dot, force)
    f = np.asarray(force, dtype=float)
    psi, theta, offset = (np.asarray(x, dtype=float) for x in (psi, theta, offset))
    extra = offset * (f[..., 1] * np.cos(psi) - f[..., 0] * np.sin(psi)) / rod.inertia
    l = rod.length
    lever = np.stack(
        np.broadcast_arrays(-l * np.sin(theta) * np.sin(psi), l * np.sin(theta) * np.cos(psi), -l * np.cos(theta)), -1
    )
    return a + extra[..., None] * lever


def contact_acceleration(
    rod: Rod, n: int, rng: np.random.Generator, *, radius: float = 0.02, depth: float = 1e-4
) -> dict[str, np.ndarray]:
    """MuJoCo's tip acceleration with an active contact against eq. linode2 at the contact point.

    n random slipping states (psi random too), the capsule ``depth`` (scaled)
    into the plane, ``mj_forward`` with the solver run to its iteration limit
    (solver_tolerance 0) and mu ~ U(0, 2).  Returns (n,) / (n, 3) arrays:
    ``got`` and ``want`` tip accelerations and ``scale`` (all / g), the state
    variables and mu.
    """
    got, want, scale = np.empty((n, 3)), np.empty((n, 3)), np.empty(n)
    states = {k: np.empty(n) for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi", "mu")}
    for i in range(n):
        s = SlipState(
            theta=rng.uniform(0.1, 1.45),
            varphi=-rng.uniform(0.05, 3.1),
            Theta=0.7 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.2, 3),
            psi=rng.uniform(-3, 3),
        )
        mu = rng.uniform(0.0, 2.0)
        model = build_model(rod, mu, Options(radius=radius, solver_tolerance=0.0))
        data = mujoco.MjData(model)
        layout = SensorLayout.from_model(model)
        mujoco.mj_setState(model, data, initial_state(model, rod, s, radius), mujoco.mjtState.mjSTATE_FULLPHYSICS)
        data.qpos[2] -= depth * rod.length
        mujoco.mj_forward(model, data)
        rec = record_from_sensordata(data.sensordata, layout, rod, radius)
        F = rec.force * rod.force_scale
        dist = data.sensordata[layout.dist]
        q, v = data.qpos[3:], data.qvel[3:]
        got[i] = rec.tip_acc
        want[i] = capsule_tip_acceleration(rod, q[0], q[1], v[0], v[1], F, radius * rod.length + dist / 2) / rod.gravity
        scale[i] = 1 + rod.alpha * np.abs(F).sum() / rod.force_scale
        for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi"):
            states[k][i] = getattr(s, k)
        states["mu"][i] = mu
    return {"got": got, "want": want, "scale": scale, **states}


def friction_skew(
    states: Sequence[SlipState], mu, *, alpha: float = 3.0, duration: float = 0.1, **options
) -> dict[str, np.ndarray]:
    """MuJoCo's friction force against the rigid Coulomb law, over the first ``duration`` of each run.

    For every row with a normal force, the friction force F_t (world frame,
    horizontal) is compared with the slip velocity u of the contact point:
    the rigid law (eq. friction) has F_t = -mu F_z u/|u|.  Returned, per state
    (each (B,), normal-force weighted means over the rows):

      skew: signed angle [rad] from -u to F_t (counter-clockwise positive);
        0 on the planar section by symmetry.
      saturation: |F_t| / (mu F_z) (1 = slipping on the cone's surface).
      p, p_eff: eq. p on MuJoCo's states, and the vertical tip acceleration
        per unit normal force with MuJoCo's actual force, from eq. linode2:
        p_eff = 1 + alpha - alpha sin^2 theta - alpha sin theta cos theta
        (F_t . e) / F_z, e = (-sin psi, cos psi) the rod's horizontal direction
        (equal to p when F_t = -mu F_z u/|u|).
      force, rigid_force, rigid_force_eff: window-mean normal force over the
        duration, -b/p and -b/p_eff (b of eq. b, row means) [m g].

    Args:
      states: B slipping states; mu: scalar or (B,); alpha: the rod's.
      duration: scaled time simulated (default 0.1, before the state changes much).
      **options: MuJoCo ``Options``.
    """
    opts = Options.from_kwargs(options)
    rod = Rod.scaled(float(check("alpha", alpha, ALPHA)))
    states = list(states)
    mu = np.broadcast_to(check("mu", mu, MU), (len(states),)).astype(float)
    nstep = n_steps(float(check("duration", duration, POSITIVE)), opts.timestep)
    out = {
        k: np.full(len(states), np.nan)
        for k in ("skew", "saturation", "p", "p_eff", "force", "rigid_force", "rigid_force_eff")
    }
    for i, (s, m) in enumerate(zip(states, mu)):
        model = build_model(rod, m, opts)
        layout = SensorLayout.from_model(model)
        x0 = initial_state(model, rod, s, opts.radius)
        _, sd = rollout.rollout(model, mujoco.MjData(model), x0[None], nstep=nstep)
        R = record_from_sensordata(sd[0], layout, rod, opts.radius)
        Fz = R.normal_force
        on = Fz > 0
        if not on.any():
            continue
        w = Fz[on]
        Ft = R.force[on, :2]
        u = R.slip_vel[on, :2]
        ang = np.arctan2(Ft[:, 1], Ft[:, 0]) - np.arctan2(-u[:, 1], -u[:, 0])
        ang = np.angle(np.exp(1j * ang))
        st, ct = np.sin(R.theta), np.cos(R.theta)
        e = np.stack([-np.sin(R.psi[on]), np.cos(R.psi[on])], axis=-1)
        p_eff_rows = 1 + rod.alpha - rod.alpha * st[on] ** 2 - rod.alpha * st[on] * ct[on] * (Ft * e).sum(-1) / w
        p_rows = 1 + rod.alpha + rod.alpha * st * (m * ct * np.sin(R.varphi) - st)
        b_rows = (R.Psi**2 * ct**2 + R.Theta**2) * st - 1
        out["skew"][i] = np.sum(w * ang) / w.sum()
        out["saturation"][i] = np.sum(np.hypot(Ft[:, 0], Ft[:, 1])) / (m * w.sum())
        out["p"][i] = np.sum(w * p_rows[on]) / w.sum()
        out["p_eff"][i] = np.sum(w * p_eff_rows) / w.sum()
        out["force"][i] = Fz.mean()
        out["rigid_force"][i] = -b_rows.mean() / out["p"][i]
        out["rigid_force_eff"][i] = -b_rows.mean() / out["p_eff"][i]
    return out


def checks(rod, n_states, rng):
    """MuJoCo's contact force at one instant against the rigid tip acceleration (``validate``'s first check)."""
    from crosscheck.engines.mujoco import tolerances as mujoco_tol
    from crosscheck.error_stats import error_stat

    ca = contact_acceleration(rod, min(n_states, 100), rng)
    where = {k: ca[k] for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi", "mu")}
    return [
        error_stat(
            "tip acceleration with contact",
            ca["got"] / ca["scale"][:, None],
            ca["want"] / ca["scale"][:, None],
            mujoco_tol.MUJOCO_CONTACT_ACCELERATION,
            where,
        )
    ]
