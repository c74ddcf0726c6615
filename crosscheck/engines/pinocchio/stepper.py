"""The rigid engine: the rod stepped by ``crosscheck.engines.pinocchio.step.Stepper`` (a Moreau / Stewart-Trinkle step
on Pinocchio's constraint solvers with the exact Coulomb cone), its records, ``simulate`` and ``sweep``.

The closed form (``solver="closed_form"``; the default "auto" uses it for every sweep and PGS for
``simulate``).  The same step with Pinocchio's terms written out
(``closed_form``: equal to Pinocchio's to ~eps / cos^2 theta) and the NCP solved in closed form
(``ncp``: lambda = 0 when u_n >= 0, the sticking impulse, or a slip along a root of a trigonometric
polynomial of degree 2 in the slip angle), a batch of states stepped together in numpy (``sweep``
steps all its states at once; ``simulate`` is a batch of one, whose numpy calls cost ~10x a
PGS step, hence "auto" keeps PGS there).  Where the step's NCP has several solutions (the
stick and the slip just before p = 0, above mu_P) the choice is PGS's, not the problem's, so those
steps are made by ``Stepper.step`` itself with its retries and sticking guess: the outcomes are the
PGS engine's (the quick report's rigid sections: every outcome and event time equal).  The two
differ beyond the solver's tolerance only where PGS misses it on an NCP with one solution (it cycles
at large mu) and the closed form has the exact impulse: ``Run.solver`` then counts fewer unconverged
steps, and 0 iterations for a step solved in closed form.

Everything this module takes and returns is in the paper's scaled units
(section 2.1); the Pinocchio model itself is physical (``Rod``).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.base import (
    STATE_KEYS,
    Run,
    SweepResult,
    check_states,
    n_steps_within_memory,
    run_inputs,
    summaries,
    sweep_by_simulate,
    sweep_mu_workers,
)
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.pinocchio.options import SOLVERS, Options
from crosscheck.engines.pinocchio.step import StepInfo, Stepper
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["NAME", "Options", "Stepper", "StepInfo", "SOLVERS", "simulate", "sweep"]

#: The engine's registry name.
NAME = "pinocchio"

#: Bytes per record row (the raw row, the Record's columns and the classifier's temporaries): the peak
#: resident memory of a 2e5-step run grew by 980 bytes per row; 1.5 x that as a margin.
ROW_BYTES = 1536


@dataclass(frozen=True)
class SolverHealth:
    """Per-run solver statistics: steps with the contact in the NCP, iterations, and steps that missed the tolerance."""

    contact_steps: int
    max_iterations: int
    mean_iterations: float
    max_complementarity: float
    unconverged_steps: int


def _record(rod: Rod, raw: np.ndarray, dt: float, timestep: float) -> Record:
    """The scaled ``Record`` of rows (..., n, >= 17) [physical] (``batch.BatchStepper.step`` lays them out), column by column."""
    n = raw.shape[-2]
    L, w = rod.length, rod.omega
    pos, vel, acc = raw[..., 0:3] / L, raw[..., 3:6] / (L * w), raw[..., 6:9] / rod.gravity
    force = raw[..., 9:12] / (dt * rod.force_scale)
    slip = vel.copy()
    slip[..., 2] = 0.0
    return Record(
        t=np.broadcast_to(timestep * np.arange(n), raw.shape[:-1]).copy(),
        tip_pos=pos,
        tip_vel=vel,
        tip_acc=acc,
        force=force,
        normal_force=force[..., 2].copy(),
        active=raw[..., 16] > 0.5,
        gap=pos[..., 2].copy(),
        slip_vel=slip,
        psi=raw[..., 12].copy(),
        theta=raw[..., 13].copy(),
        Psi=raw[..., 14] / w,
        Theta=raw[..., 15] / w,
    )


def _health(raw: np.ndarray) -> SolverHealth:
    """``SolverHealth`` of one run's rows (n, 20)."""
    active, iters, compl, conv = raw[:, 16] > 0.5, raw[:, 17], raw[:, 18], raw[:, 19] > 0.5
    return SolverHealth(
        contact_steps=int(active.sum()),
        max_iterations=int(iters.max(initial=0)),
        mean_iterations=float(iters[active].mean()) if active.any() else 0.0,
        max_complementarity=float(compl.max(initial=0.0)),
        unconverged_steps=int((~conv).sum()),
    )


def _rows_by_pgs(rod: Rod, q: np.ndarray, v: np.ndarray, mu: float, opts: Options, n: int) -> np.ndarray:
    """``n`` rows (n, 20) of one state stepped by ``Stepper`` (Pinocchio's solver at every step)."""
    stepper = Stepper(rod, mu, opts)
    raw = np.empty((n, 20))
    for k in range(n):
        q1, v1, info = stepper.step(q, v)
        r = raw[k]
        r[0:3], r[3:6], r[6:9], r[9:12] = info.tip_pos, info.tip_vel, info.tip_acc, info.impulse
        r[12], r[13], r[14], r[15] = q[3], q[4], v[3], v[4]
        r[16], r[17], r[18], r[19] = info.active, info.iterations, info.complementarity, info.converged
        q, v = q1, v1
    return raw


def simulate(
    rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds | None = None, **options
) -> Run:
    """Run one slipping state with the rigid engine and classify its first event.

    The tip starts on the plane (z_A = 0) with the velocities of ``state``
    (``crosscheck.coordinates``); ``ceil(horizon / timestep)`` steps.  Row k
    of the record is the state at t_k = k timestep with the impulse of the
    step that starts there (force = impulse / dt).  ``Run.solver`` holds the
    solver health (``SolverHealth``).
    """
    mu, horizon, opts = run_inputs(state, mu, horizon, options, Options)
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES)  # the record holds every row: refuse before allocating
    q, v = to_generalized(rod, state)
    if opts.solver == "closed_form":
        from crosscheck.engines.pinocchio.batch import run_batch

        raw = run_batch(rod, q[None], v[None], np.array([mu]), opts, n)[0][0]
    else:
        raw = _rows_by_pgs(rod, q, v, mu, opts, n)
    record = _record(rod, raw, opts.timestep / rod.omega, opts.timestep)
    c = classify(
        record, mu=mu, alpha=rod.alpha, timestep=opts.timestep, friction_timeconst=0.0, rigid=True, thresholds=th
    )
    run = Run.from_classification(
        NAME, c, record, state=state, mu=mu, alpha=rod.alpha, options=opts, thresholds=th, horizon=horizon, nstep=n
    )
    return dataclasses.replace(run, solver=_health(raw))


#: States stepped together by the closed-form solver: from ~100 on, a step's arithmetic costs more than its numpy calls.
BATCH = 128


def _rows_closed_form(rod: Rod, q: np.ndarray, v: np.ndarray, mu: np.ndarray, opts: Options, n: int) -> np.ndarray:
    """Rows (B, n, 20) of B states stepped ``BATCH`` at a time by ``batch.run_batch``."""
    from crosscheck.engines.pinocchio.batch import run_batch

    return np.concatenate(
        [
            run_batch(rod, q[a : a + BATCH], v[a : a + BATCH], mu[a : a + BATCH], opts, n)[0]
            for a in range(0, len(q), BATCH)
        ]
    )


def _sweep_closed_form(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None,
    progress: bool | None,
    workers: int,
    n_series: int = 200,
    **options,
) -> SweepResult:
    """``sweep`` with ``solver="closed_form"``: the states stepped together (``batch``), one classifier on the stacked records."""
    states = check_states(states)
    _, horizon, opts = run_inputs(states[0], 0.0, horizon, options, Options)  # every state was checked above
    mu = sweep_mu_workers(mu, len(states), workers)
    B = len(states)
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES, copies=B, what="the records of a sweep")
    t0 = time.perf_counter()
    qv = [to_generalized(rod, s) for s in states]
    q, v = np.array([a for a, _ in qv]), np.array([b for _, b in qv])
    if (
        workers == 1 or B < workers * BATCH // 2
    ):  # a smaller share per process costs more in per-step overhead than it saves
        raw = _rows_closed_form(rod, q, v, mu, opts, n)
    else:
        from crosscheck.workers import pool as worker_pool

        cuts = np.linspace(0, B, workers + 1).astype(int)
        with worker_pool(workers) as pool:
            futures = [
                pool.submit(_rows_closed_form, rod, q[a:b], v[a:b], mu[a:b], opts, n)
                for a, b in zip(cuts[:-1], cuts[1:])
            ]
            raw = np.concatenate([f.result() for f in futures])
    record = _record(rod, raw, opts.timestep / rod.omega, opts.timestep)
    c = classify(
        record, mu=mu, alpha=rod.alpha, timestep=opts.timestep, friction_timeconst=0.0, rigid=True, thresholds=th
    )
    summary, series = summaries(record, c, mu, rod.alpha, max(1, n // max(1, n_series)))
    health = [_health(r) for r in raw]
    solver = {f.name: np.array([getattr(h, f.name) for h in health]) for f in dataclasses.fields(SolverHealth)}
    wall = time.perf_counter() - t0
    return SweepResult(
        engine=NAME,
        outcome=c.outcome,
        event_time=c.event_time,
        exit_time=c.exit_time,
        diverged_time=c.diverged_time,
        states={k: np.array([getattr(s, k) for s in states]) for k in STATE_KEYS},
        mu=mu.copy(),
        summary=summary,
        series=series,
        alpha=rod.alpha,
        horizon=horizon,
        nstep=n,
        options=opts,
        thresholds=th,
        wall_time=wall,
        steps_per_second=B * n / wall,
        solver=solver,
    )


def sweep(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    progress: bool | None = None,
    workers: int = 2,
    **options,
) -> SweepResult:
    """Every state through the engine (one classifier, the same records as ``simulate``'s), on ``workers`` processes (both
    cores by default): with ``solver="closed_form"`` or "auto", all states stepped together (on one process below
    ``workers * BATCH / 2`` states); otherwise one ``simulate`` per state."""
    solver = options.get("solver", Options.solver)
    if solver in ("closed_form", "auto"):
        return _sweep_closed_form(
            rod, states, mu, horizon=horizon, thresholds=thresholds, progress=progress, workers=workers, **options
        )
    return sweep_by_simulate(
        get(NAME),
        rod,
        states,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        progress=progress,
        workers=workers,
        **options,
    )
