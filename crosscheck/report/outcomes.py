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

__all__ = ["OUTCOME_NAMES", "analytic_events", "mujoco_events", "first_events", "confusion", "boundary_cells"]

OUTCOME_NAMES = [o.name for o in Outcome]


def analytic_events(states: Sequence[SlipState], mu: np.ndarray, alpha: float, *, horizon: float,
                    progress: Callable[..., Iterable] = lambda x, **_: x) -> dict[str, np.ndarray]:
    """The start (theta, varphi, Theta, Psi, eta, mu), its b, p and LCP ``mode``, and the analytic first event.

    Returns a dict of (B,) arrays; ``analytic_outcome`` is an ``Outcome`` code,
    ``analytic_time`` the real scaled time, ``analytic_reason`` the rule that fired.
    """
    from crosscheck import gb

    mu = np.broadcast_to(np.asarray(mu, float), (len(states),))
    out: dict[str, list] = {k: [] for k in ("theta", "varphi", "Theta", "Psi", "eta", "mu", "b", "p", "mode", "analytic_outcome", "analytic_time", "analytic_reason")}
    for s, m in progress(list(zip(states, mu)), desc="analytic first events"):
        r = gb.slip_until_event(s, m, alpha, t_max=horizon)
        bb, pp = float(analytic.b(s.Psi, s.Theta, s.theta)), float(analytic.p(s.theta, s.varphi, m, alpha))
        for k, v in (("theta", s.theta), ("varphi", s.varphi), ("Theta", s.Theta), ("Psi", s.Psi), ("eta", s.eta), ("mu", m), ("b", bb), ("p", pp),
                     ("mode", int(analytic.mode(bb, pp))), ("analytic_outcome", int(r.outcome)), ("analytic_time", r.time), ("analytic_reason", r.reason)):
            out[k].append(v)
    return {k: np.asarray(v) for k, v in out.items()}


def mujoco_events(states: Sequence[SlipState], mu: np.ndarray, alpha: float, *, horizon: float, show_progress: bool = False,
                  mujoco_options: dict | None = None) -> dict[str, np.ndarray]:
    """MuJoCo's outcome (``Outcome`` code) and event time (NaN when none) of each start, one batched sweep."""
    from crosscheck import mujoco_sweep
    from crosscheck.rod import Rod

    mu = np.broadcast_to(np.asarray(mu, float), (len(states),))
    sw = mujoco_sweep.sweep(Rod.scaled(alpha), list(states), mu, horizon=horizon, progress=show_progress, **(mujoco_options or {}))
    return {"mujoco_outcome": np.asarray(sw.outcome, dtype=int), "mujoco_time": np.asarray(sw.event_time, dtype=float)}


def first_events(states: Sequence[SlipState], mu: np.ndarray, alpha: float, *, horizon: float, progress: Callable[..., Iterable] = lambda x, **_: x,
                 show_progress: bool = False, mujoco_options: dict | None = None) -> dict[str, np.ndarray]:
    """``analytic_events`` and ``mujoco_events`` of the same starts, in one dict of (B,) arrays."""
    return {**analytic_events(states, mu, alpha, horizon=horizon, progress=progress),
            **mujoco_events(states, mu, alpha, horizon=horizon, show_progress=show_progress, mujoco_options=mujoco_options)}


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
