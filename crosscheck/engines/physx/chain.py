"""The ``Record`` of a rollout of the five-joint chain (X, Y, Z, psi, theta) in SI: states 0..n and each step's force.

Shared by the engines that step the chain of ``models/rod.xml`` and return physical arrays (PhysX, DART), as
Bullet's ``record_from_raw`` does for Bullet: row k is the state after k steps with the contact force of step
k -> k+1 and the tip acceleration (v_A,k+1 - v_A,k) / dt, all scaled (section 2.1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crosscheck.coordinates import tip_position, tip_velocity
from crosscheck.engines.record import Record, row_times
from crosscheck.rod import Rod

__all__ = ["Raw", "record_from_raw"]


@dataclass(frozen=True)
class Raw:
    """One rollout in physical units.

    q, v: (n + 1, 5) joint positions and velocities after k steps [m, rad; m/s, rad/s] (float64; NaN after
      ``computed``).
    force: (n, 3) contact force on the rod over step k -> k+1 [N], world frame.
    points: (n,) contact points the engine had in that step (0: none).
    separation: (n,) the least separation the engine reported for them [m] (negative: penetration; NaN: none).
    computed: the steps taken (n, or fewer when the rollout stopped once its first event was judged).
    """

    q: np.ndarray
    v: np.ndarray
    force: np.ndarray
    points: np.ndarray
    separation: np.ndarray
    computed: int | None = None

    def head(self, k: int) -> Raw:
        """The first k steps (what a rollout has computed after k steps)."""
        return Raw(self.q[: k + 1], self.v[: k + 1], self.force[:k], self.points[:k], self.separation[:k], computed=k)


def record_from_raw(raw: Raw, rod: Rod, timestep: float, radius: float) -> Record:
    """The scaled, world-frame ``Record`` of a rollout (row k: state k and step k -> k+1); ``timestep``, ``radius``
    scaled (omega dt, r / l)."""
    n = len(raw.force)
    L, w, g = rod.length, rod.omega, rod.gravity
    dt = timestep / w
    q, v = raw.q, raw.v
    pos = tip_position(rod, q)
    vel = tip_velocity(rod, q, v)
    acc = (vel[1:] - vel[:-1]) / (dt * g)
    psi, theta = np.ascontiguousarray(q[:n, 3]), np.ascontiguousarray(q[:n, 4])
    Psi, Theta = v[:n, 3] / w, v[:n, 4] / w
    tip_pos, tip_vel = pos[:n] / L, vel[:n] / (L * w)
    force = raw.force / rod.force_scale
    # the capsule's material point C = A - r K: v_A + Omega x (-r K), Omega = theta' i + psi' K
    slip = np.zeros((n, 3))
    slip[:, 0] = tip_vel[:, 0] - radius * Theta * np.sin(psi)
    slip[:, 1] = tip_vel[:, 1] + radius * Theta * np.cos(psi)
    return Record(
        t=row_times(n, timestep, raw.computed),
        tip_pos=tip_pos,
        tip_vel=tip_vel,
        tip_acc=acc,
        force=force,
        normal_force=force[:, 2].copy(),
        active=raw.points > 0,
        gap=tip_pos[:, 2] - radius,
        slip_vel=slip,
        psi=psi,
        theta=theta,
        Psi=Psi,
        Theta=Theta,
    )
