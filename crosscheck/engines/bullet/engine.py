"""The Bullet engine: the capsule rod of ``models/rod.xml`` stepped by pybullet (Bullet's Featherstone multibody and its PGS contact solver).

``simulate`` runs one slipping state; ``sweep`` runs one ``simulate`` per
state (``crosscheck.engines.base.sweep_by_simulate``, on ``workers``
processes), so a state gives the same numbers either way.  The model, its
settings and the rollout are in ``crosscheck.engines.bullet.model``.

Bullet's contact step.  Each step Bullet runs collision detection at the
state q_k (the capsule against the plane: one contact point at C = A - r K
while the capsule is within ``Options.contact_margin`` of the plane), then
v_free = v_k + dt a_free(q_k, v_k), then solves for the contact impulse with
projected Gauss-Seidel (btMultiBodyConstraintSolver) on rows built at q_k:

* the normal row: a unilateral velocity constraint J_n v_k+1 >= -d_k / dt for
  a point at distance d_k > 0 (a speculative contact: the gap may close
  within the step, not more), and J_n v_k+1 >= contact_erp |d_k| / dt for a
  penetration d_k < 0;
* two friction rows along world -y and x (``btPlaneSpace1`` of the normal +z),
  whose impulses are clipped together to the disk of radius mu times the
  normal impulse (``enableConeFriction``; no position error: no anchors);

then v_k+1 = v_free + M^-1 J^T lambda and q_k+1 = q_k + dt v_k+1.  That is an
impulse-based rigid time-stepper (Moreau / Stewart-Trinkle at velocity level,
like the rigid engine's), hence the tags "rigid" and "time_stepping", and
``Options.contact_time`` = ``friction_time`` = 0 (the classifier's rigid
rules).  What differs from the rigid engine (no dt dJ v term, the friction
direction of two separately updated rows, ...), all measured in
tests/test_engine_bullet.py, is listed in ``docs/bullet_engine.md``.

Row k of the record is the state after k steps (t_k = k timestep) with the
contact force of step k -> k+1 (its impulse / dt, as Bullet reports it in
``getContactPoints``) and the tip acceleration (v_A,k+1 - v_A,k) / dt.

Units.  Everything this module takes and returns is in the paper's scaled
units (section 2.1): time in 1/omega, lengths in l, velocities in l omega,
accelerations in g, forces in m g; so are the options.  Bullet itself runs in
SI from the ``Rod``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from crosscheck.checks import Interval
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.adapter import record_from_chain
from crosscheck.engines.base import Run, SweepResult, n_steps_within_memory, run_inputs, sweep_by_simulate
from crosscheck.engines.bullet.model import Raw, world
from crosscheck.engines.bullet.options import MU_MAX, Options
from crosscheck.engines.classifier import Thresholds, classify, first_event_final
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["NAME", "Options", "BulletHealth", "simulate", "sweep", "record_from_raw", "health"]

#: The engine's registry name.
NAME = "bullet"

#: mu for Bullet: [0, 10] (``options.MU_MAX``: Bullet clamps the combined friction there).
BULLET_MU = Interval(0.0, MU_MAX, lo_open=False, hi_open=False)

#: Bytes per record row (the raw rollout, the Record's columns and the classifier's temporaries): the peak of
#: Python's allocations (tracemalloc) in a 2e5-step run was 491 bytes per row; ~3 x that as a margin.
ROW_BYTES = 1536


@dataclass(frozen=True)
class BulletHealth:
    """Per-run statistics of Bullet's contact and solver, over the rows before theta leaves (0, pi/2) (a rod that
    falls flat lands on both caps: two points, a penetration, PGS cycling between them; no event is read there).

    contact_steps: steps with a contact point (a row in Bullet's solve).
    max_iterations, mean_iterations: PGS sweeps per step (Bullet's solver analytics), the most and the mean over
      contact steps.
    unconverged_steps: steps that ended at ``Options.solver_iterations`` with their last sweep still changing a
      row's velocity by more than ``Options.solver_tolerance`` (the fixed point not reached).
    max_residual: the largest velocity change of a row in a step's last sweep [l omega] (at most
      ``Options.solver_tolerance`` when every step reached it).
    max_points: the most contact points in one step (1: the capsule's end cap).
    max_penetration: the deepest penetration Bullet reported at a step's collision detection [l] (0 if none).
    """

    contact_steps: int
    max_iterations: int
    mean_iterations: float
    unconverged_steps: int
    max_residual: float
    max_points: int
    max_penetration: float


def record_from_raw(raw: Raw, rod: Rod, options: Options) -> Record:
    """The scaled, world-frame ``Record`` of a rollout (row k: state k and step k -> k+1; the shared conversion
    ``crosscheck.engines.adapter.record_from_chain``, tip acceleration (v_A,k+1 - v_A,k) / dt)."""
    return record_from_chain(
        rod,
        raw.q,
        raw.v,
        raw.force,
        raw.points > 0,
        timestep=options.timestep,
        radius=options.radius,
        computed=raw.computed,
    )


def simulate(
    rod: Rod,
    state: SlipState,
    mu: float,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    until_event: bool = False,
    **options,
) -> Run:
    """Run one slipping state in Bullet and classify its first event.

    The capsule starts touching the plane (z_A = r, C on the plane) with the
    velocities of ``state`` (``crosscheck.coordinates.to_generalized``);
    ``ceil(horizon / timestep)`` steps.  ``Run.solver`` holds ``BulletHealth``.

    Args:
      rod: physical rod (``Rod.scaled(alpha)`` for the paper's units).
      state: the paper's scaled slipping state.
      mu: friction coefficient in [0, 10] (Bullet clamps larger ones).
      horizon: scaled time to simulate, > 0, at least one timestep.
      thresholds: outcome criteria (``Thresholds()`` by default).
      until_event: stop the rollout once its first event is judged (``first_event_final``): the outcome and
        event time are the whole run's, the record's later rows NaN (time too), the health over the steps
        taken.  Sweeps use it: they keep only the first event.
      **options: the fields of ``Options`` (unknown -> ValueError naming it).
    """
    mu, horizon, opts = run_inputs(state, mu, horizon, options, Options)
    if mu > MU_MAX:
        raise ValueError(
            f"mu must be in {BULLET_MU} for Bullet (it clamps the combined friction to {MU_MAX:g}); got {mu!r}"
        )
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES)  # the record holds every row: refuse before allocating
    q0, v0 = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    rules = dict(
        mu=mu, alpha=rod.alpha, timestep=opts.timestep, friction_timeconst=opts.friction_time, rigid=True, thresholds=th
    )

    def judged(raw: Raw) -> bool:
        return first_event_final(classify(record_from_raw(raw, rod, opts), **rules), raw.computed, th, opts.timestep)

    raw = world(rod, mu, opts).rollout(q0, v0, n, judged if until_event else None)
    record = record_from_raw(raw, rod, opts)
    c = classify(record, **rules)
    run = Run.from_classification(
        NAME, c, record, state=state, mu=mu, alpha=rod.alpha, options=opts, thresholds=th, horizon=horizon, nstep=n
    )
    return dataclasses.replace(run, solver=health(raw, record, rod, opts))


def health(raw: Raw, record: Record, rod: Rod, opts: Options) -> BulletHealth:
    """``BulletHealth`` of a rollout, over the rows before theta leaves (0, pi/2)."""
    inside = (record.theta > 0.0) & (record.theta < np.pi / 2)
    m = len(record) if inside.all() else int(np.argmin(inside))
    points, distance, iterations, residual = raw.points[:m], raw.distance[:m], raw.iterations[:m], raw.residual[:m]
    contact = points > 0
    scale = rod.length * rod.omega
    unconverged = (iterations >= opts.solver_iterations) & (residual > (opts.solver_tolerance * scale) ** 2)
    deepest = float(np.min(distance[contact], initial=0.0))
    return BulletHealth(
        contact_steps=int(contact.sum()),
        max_iterations=int(iterations.max(initial=0)),
        mean_iterations=float(iterations[contact].mean()) if contact.any() else 0.0,
        unconverged_steps=int(unconverged.sum()),
        max_residual=float(np.sqrt(residual.max(initial=0.0))) / scale,
        max_points=int(points.max(initial=0)),
        max_penetration=max(0.0, -deepest) / rod.length,
    )


def sweep(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    progress: bool | None = None,
    workers: int = 1,
    **options,
) -> SweepResult:
    """Every state through ``simulate`` (one classifier, the same records), on ``workers`` processes.

    Each rollout stops once its first event is judged (``simulate``'s ``until_event``): a sweep keeps the first
    event only (measured over the full report's Bullet maps: the event and its look-ahead need 46 % of the
    horizon on average).  One process by default (``EngineSpec.one_core``); a step costs ~20-30 us
    (``benchmarks/bench_bullet.py``), a run to horizon 2 at the default
    timestep ~0.04-0.06 s; ``workers=2`` uses both cores of this machine.
    """
    return sweep_by_simulate(
        get(NAME),
        rod,
        states,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        progress=progress,
        workers=workers,
        until_event=True,
        **options,
    )
