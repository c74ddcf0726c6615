"""The first event of the same slipping states by the analytic model and by MuJoCo, as arrays.

Analytic: ``crosscheck.gb.slip_until_event`` (F_z = -b/p, desingularised
time; LIFTOFF, JAM, STICK, GB or SLIP, with the real time and the rule that
fired).  MuJoCo: ``crosscheck.mujoco_sweep.sweep`` (batched rollouts, the
same classifier as ``crosscheck.mujoco_rod.simulate``).  Both run for the
same scaled horizon.  The LCP mode of each start (section 3.1) is recorded
too: a start that is not slipping has its "event" at t = 0.
"""

from __future__ import annotations

from typing import Callable, Iterable, Sequence

import numpy as np

from crosscheck import analytic
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState

__all__ = ["OUTCOME_NAMES", "first_events", "confusion", "boundary_cells"]

OUTCOME_NAMES = [o.name for o in Outcome]


def first_events(states: Sequence[SlipState], mu: np.ndarray, alpha: float, *, horizon: float, progress: Callable[..., Iterable] = lambda x, **_: x,
                 show_progress: bool = False, mujoco_options: dict | None = None) -> dict[str, np.ndarray]:
    """Analytic and MuJoCo first events of ``states`` (one mu each).

    Returns a dict of (B,) arrays: the start (theta, varphi, Theta, Psi, eta,
    mu), its LCP ``mode`` and b, p; ``analytic_outcome`` (``Outcome`` code),
    ``analytic_time``, ``analytic_reason``; ``mujoco_outcome``, ``mujoco_time``
    (NaN when none).
    """
    from crosscheck import gb, mujoco_sweep
    from crosscheck.rod import Rod

    mu = np.broadcast_to(np.asarray(mu, float), (len(states),))
    out: dict[str, list] = {k: [] for k in ("theta", "varphi", "Theta", "Psi", "eta", "mu", "b", "p", "mode", "analytic_outcome", "analytic_time", "analytic_reason")}
    for s, m in progress(list(zip(states, mu)), desc="analytic first events"):
        r = gb.slip_until_event(s, m, alpha, t_max=horizon)
        bb, pp = float(analytic.b(s.Psi, s.Theta, s.theta)), float(analytic.p(s.theta, s.varphi, m, alpha))
        for k, v in (("theta", s.theta), ("varphi", s.varphi), ("Theta", s.Theta), ("Psi", s.Psi), ("eta", s.eta), ("mu", m), ("b", bb), ("p", pp),
                     ("mode", int(analytic.mode(bb, pp))), ("analytic_outcome", int(r.outcome)), ("analytic_time", r.time), ("analytic_reason", r.reason)):
            out[k].append(v)
    res = {k: np.asarray(v) for k, v in out.items()}
    sw = mujoco_sweep.sweep(Rod.scaled(alpha), list(states), mu, horizon=horizon, progress=show_progress, **(mujoco_options or {}))
    res["mujoco_outcome"] = np.asarray(sw.outcome, dtype=int)
    res["mujoco_time"] = np.asarray(sw.event_time, dtype=float)
    return res


def confusion(analytic_outcome: np.ndarray, mujoco_outcome: np.ndarray) -> np.ndarray:
    """(len(Outcome), len(Outcome)) counts: row = analytic outcome, column = MuJoCo outcome."""
    n = len(Outcome)
    c = np.zeros((n, n), dtype=int)
    np.add.at(c, (np.asarray(analytic_outcome, int), np.asarray(mujoco_outcome, int)), 1)
    return c


def boundary_cells(codes: np.ndarray) -> np.ndarray:
    """Cells of a 2D map of codes with a 4-neighbour of a different code (the map's boundaries)."""
    c = np.asarray(codes)
    edge = np.zeros(c.shape, bool)
    edge[1:, :] |= c[1:, :] != c[:-1, :]
    edge[:-1, :] |= c[:-1, :] != c[1:, :]
    edge[:, 1:] |= c[:, 1:] != c[:, :-1]
    edge[:, :-1] |= c[:, :-1] != c[:, 1:]
    return edge
