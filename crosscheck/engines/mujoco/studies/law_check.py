"""Is ``crosscheck.engines.mujoco.law`` MuJoCo's law?  Its force against mj_forward's, and MuJoCo's approach to it as dt -> 0.

* ``random_contact`` / ``efc_agreement``: at seeded random penetrating,
  slipping contacts (random alpha, mu, radius, solref, solreffriction,
  solimp, impratio, depth), MuJoCo's ``mj_forward`` with its Newton solver
  run to the iteration limit (solver_tolerance 0), against the law's
  problem and force: efc_force, efc_R, efc_aref.
* ``convergence_order``: one slipping state run by MuJoCo at several
  timesteps and by the continuous-time engine "mujoco_law"; the RMS over
  rows of the tip's horizontal position error and the fitted order.

Scaled units (section 2.1) at the interface; MuJoCo's arrays are physical.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import mujoco
import numpy as np

from crosscheck.engines import get
from crosscheck.engines.mujoco.law import contact_problem
from crosscheck.engines.mujoco.model import build_model, initial_state
from crosscheck.engines.mujoco.options import Options
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["random_contact", "efc_agreement", "convergence_order"]


def random_contact(rng: np.random.Generator):
    """A penetrating, slipping capsule with random parameters and MuJoCo's forward at it.

    Returns (rod, mu, options, impratio, model, data) with ``data`` after ``mj_forward``.
    """
    rod = Rod.scaled(float(rng.choice([1.5, 3.0, 6.0])))
    s = SlipState(
        theta=rng.uniform(0.1, 1.45),
        varphi=-rng.uniform(0.05, 3.1),
        Theta=0.7 * rng.normal(),
        Psi=rng.normal(),
        eta=rng.uniform(0.2, 3),
        psi=rng.uniform(-3, 3),
    )
    mu = float(rng.choice([0.0, rng.uniform(0.05, 2.5)], p=[0.1, 0.9]))
    opts = Options(
        radius=rng.uniform(0.005, 0.05),
        solver_tolerance=0.0,
        timeconst=rng.uniform(0.02, 0.1),
        dampratio=rng.uniform(0.5, 1.5),
        friction_timeconst=[None, rng.uniform(0.01, 0.1)][rng.integers(2)],
        solimp=(
            rng.uniform(0.5, 0.9),
            rng.uniform(0.91, 0.99),
            rng.uniform(5e-4, 3e-3),
            rng.uniform(0.2, 0.8),
            rng.uniform(1, 3),
        ),
    )
    impratio = float(rng.choice([1.0, 0.3, 5.0]))
    opts = dataclasses.replace(
        opts, impratio=impratio
    )  # drawn after the others, so the draws stay those of earlier reports
    model = build_model(rod, mu, opts)
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, initial_state(model, rod, s, opts.radius), mujoco.mjtState.mjSTATE_FULLPHYSICS)
    data.qpos[2] -= rng.uniform(1e-6, 4e-3) * rod.length  # inside and beyond solimp's width
    mujoco.mj_forward(model, data)
    return rod, mu, opts, impratio, model, data


def efc_agreement(n: int, rng: np.random.Generator) -> dict[str, float]:
    """Worst relative differences over n random contacts: force (of max |efc_force|), R (of efc_R), aref (of its terms' size)."""
    worst = {"force": 0.0, "R": 0.0, "aref": 0.0}
    for _ in range(n):
        rod, mu, opts, impratio, model, data = random_contact(rng)
        pb = contact_problem(
            rod, data.qpos, data.qvel, mu, opts
        )  # the law reads impratio from the options, as build_model does
        terms = np.abs(data.efc_KBIP[:, 1] * data.efc_vel) + np.abs(
            data.efc_KBIP[:, 0] * data.efc_KBIP[:, 2] * data.efc_pos
        )
        f = pb.force()
        scale = max(
            np.abs(data.efc_force).max(), np.abs(f).max()
        )  # both 0 where the contact separates: then equal exactly
        worst["force"] = max(worst["force"], float(np.abs(f - data.efc_force).max() / scale) if scale > 0 else 0.0)
        worst["R"] = max(worst["R"], float(np.abs(pb.R - data.efc_R).max() / np.abs(data.efc_R).max()))
        worst["aref"] = max(worst["aref"], float(np.abs(pb.aref - data.efc_aref).max() / terms.max()))
    return worst


def convergence_order(
    rod: Rod,
    state: SlipState,
    mu: float,
    *,
    timesteps: Sequence[float] = (2e-4, 1e-4, 5e-5),
    horizon: float = 0.4,
    spacing: float = 1e-2,
) -> dict:
    """MuJoCo at each timestep against the continuous-time law: RMS tip (x, y) error over rows ``spacing`` apart, and its order."""
    law = get("mujoco_law").simulate(rod, state, mu, horizon=horizon, timestep=spacing).record
    rms = []
    for dt in timesteps:
        M = get("mujoco").simulate(rod, state, mu, horizon=horizon, timestep=dt).record
        idx = np.arange(0, len(M.t), int(round(spacing / dt)))[: len(law.t)]
        if np.abs(M.t[idx] - law.t).max() > 1e-9:
            raise ValueError(f"spacing {spacing:g} must be a multiple of every timestep; got {dt:g}")
        rms.append(float(np.sqrt(np.mean(np.sum((M.tip_pos[idx, :2] - law.tip_pos[:, :2]) ** 2, -1)))))
    order = float(np.polyfit(np.log(timesteps), np.log(rms), 1)[0])
    return {"timesteps": list(map(float, timesteps)), "rms": rms, "order": order}
