"""A rollout of the five-joint chain (X, Y, Z, psi, theta) in SI: states 0..n and each step's contact (``Raw``).

Shared by the engines that step the chain of ``models/rod.xml`` (PhysX, DART); their ``Record`` is made by the
shared conversion ``crosscheck.engines.adapter.record_from_chain``: row k the state after k steps with the contact
force of step k -> k+1 and the tip acceleration (v_A,k+1 - v_A,k) / dt, all scaled (section 2.1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Raw"]


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
