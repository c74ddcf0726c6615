"""The time series every contact engine records, in the paper's scaled units and the world frame."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Record", "FIELDS", "row_times"]

#: The fields of a ``Record``, in order.
FIELDS = (
    "t",
    "tip_pos",
    "tip_vel",
    "tip_acc",
    "force",
    "normal_force",
    "active",
    "gap",
    "slip_vel",
    "psi",
    "theta",
    "Psi",
    "Theta",
)


def row_times(n: int, timestep: float, computed: int | None = None) -> np.ndarray:
    """The scaled times k timestep of a record's n rows; NaN from row ``computed`` on when only the first rows were
    computed (a run stopped once its first event was judged: ``crosscheck.engines.classifier.first_event_final``)."""
    t = timestep * np.arange(n)
    if computed is not None and computed < n:
        t[computed:] = np.nan
    return t


@dataclass(frozen=True, eq=False)
class Record:
    """Time series of one run (or a batch of runs: leading batch axes), scaled units, world frame.

    Row k is the state at time t[k] and what the engine's contact computed
    there.  Every engine fills the same fields with the same meaning, so one
    classifier (``crosscheck.engines.classifier``) and every study read any
    engine's runs.

    Attributes (N rows; vectors have a trailing axis of 3; shapes
    (..., N) and (..., N, 3)):
      t: scaled time omega t.
      tip_pos: tip A / l.
      tip_vel: velocity of A / (l omega).
      tip_acc: acceleration of A / g, gravity included (a free rod has
        tip_acc = b along z, eq. b).
      force: contact force on the rod / (m g), world frame.
      normal_force: its component along the plane's normal +z, / (m g).
      active: the engine has a rod-plane contact in this row.
      gap: height of the rod's contact point above the plane / l: the tip A
        for a rigid contact at the tip, the capsule's lowest point
        C = A - r K for MuJoCo's capsule of radius r.
      slip_vel: horizontal velocity of the rod's material point at the
        contact point / (l omega) (z component 0): v_A for the tip,
        v_A + r theta' (-sin psi, cos psi, 0) at C.
      psi, theta: angles [rad]; Psi, Theta: rates psi' / omega, theta' / omega.
    """

    t: np.ndarray
    tip_pos: np.ndarray
    tip_vel: np.ndarray
    tip_acc: np.ndarray
    force: np.ndarray
    normal_force: np.ndarray
    active: np.ndarray
    gap: np.ndarray
    slip_vel: np.ndarray
    psi: np.ndarray
    theta: np.ndarray
    Psi: np.ndarray
    Theta: np.ndarray

    def __len__(self) -> int:
        return int(np.shape(self.t)[-1])

    @property
    def eta(self) -> np.ndarray:
        """Scaled slip speed of the contact point, |slip_vel|."""
        return np.hypot(self.slip_vel[..., 0], self.slip_vel[..., 1])

    @property
    def varphi(self) -> np.ndarray:
        """Relative slip angle beta - psi of the contact point's velocity [rad], wrapped to (-pi, pi]."""
        beta = np.arctan2(self.slip_vel[..., 1], self.slip_vel[..., 0])
        return np.angle(np.exp(1j * (beta - self.psi)))

    @property
    def b(self) -> np.ndarray:
        """Eq. b on the recorded states: the free vertical tip acceleration / g."""
        st, ct = np.sin(self.theta), np.cos(self.theta)
        return (self.Psi * self.Psi * ct * ct + self.Theta * self.Theta) * st - 1.0

    def p(self, mu, alpha: float) -> np.ndarray:
        """Eq. p on the recorded states with slip direction ``varphi`` (mu: scalar or one per run)."""
        mu = np.asarray(mu, dtype=float)[..., None]
        st, ct = np.sin(self.theta), np.cos(self.theta)
        with np.errstate(invalid="ignore"):
            return 1.0 + alpha + alpha * st * (mu * ct * np.sin(self.varphi) - st)

    def rows(self, index) -> Record:
        """The record restricted to ``index`` along the row axis (a slice, an int array, ...)."""
        out = {}
        for name in FIELDS:
            x = getattr(self, name)
            vector = name in ("tip_pos", "tip_vel", "tip_acc", "force", "slip_vel")
            out[name] = x[..., index, :] if vector else x[..., index]
        return Record(**out)

    def run(self, i: int) -> Record:
        """Run ``i`` of a batch with one batch axis, as a record of its own (copies)."""
        return Record(**{name: np.array(getattr(self, name)[i]) for name in FIELDS})

    def at(self, row: np.ndarray) -> Record:
        """One row per run of a batch: ``row`` has the batch shape; returns a record with N = 1."""
        row = np.asarray(row)
        out = {}
        for name in FIELDS:
            x = getattr(self, name)
            vector = name in ("tip_pos", "tip_vel", "tip_acc", "force", "slip_vel")
            if vector:
                out[name] = np.take_along_axis(x, row[..., None, None], axis=-2)
            else:
                out[name] = np.take_along_axis(x, row[..., None], axis=-1)
        return Record(**out)
