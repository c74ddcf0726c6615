"""The PhysX engine: the capsule rod of ``models/rod.xml`` as a PhysX 5 articulation (SAPIEN 3, CPU), TGS or PGS.

``simulate`` runs one slipping state; ``sweep`` runs one ``simulate`` per state
(``crosscheck.engines.base.sweep_by_simulate``), so a state gives the same numbers either way.  The model and
its settings are in ``crosscheck.engines.physx.model``.

PhysX's contact step.  Each step PhysX finds the capsule-plane contact while the capsule is within the
contact offset of the plane (a speculative contact: its row lets the gap close within the step, not more),
builds one normal row and PhysX's patch friction (two friction rows along two tangent axes of the patch,
each clipped to mu times the normal impulse: a square pyramid, |F_t| up to sqrt(2) mu F_n where both
saturate) and solves them by Gauss-Seidel sweeps: TGS substeps the rows over its position iterations
(each one a substep of dt / n integrating the bodies), PGS solves the velocity problem of the whole step.
Either is an impulse-based rigid time-stepper, hence the tags "rigid" and "time_stepping", with
``Options.contact_time`` = ``friction_time`` = 0 (the classifier's rigid rules).

Row k of the record is the state after k steps (t_k = k timestep) with the contact force of step k -> k+1
(the momentum of the moving links) and the tip acceleration (v_A,k+1 - v_A,k) / dt.  PhysX computes in
float32, so a record's digits beyond ~1e-7 relative are rounding.  The contact row aims at the gap PhysX
computes from float32 positions (~6e-8 l for a rod near the origin), and a gap error e asks for a velocity
e / dt and a force ~m e / dt^2: at dt = 1e-3 / omega that is ~0.06-0.3 m g, the scatter of the normal force
from step to step about the rigid value on a steady slip (measured on the slip theta = 1, varphi = -1.9,
mu = 0.5: standard deviation 0.07-0.3 m g over 100 steps, mean within 0.05 of Bullet's 0.82).

Units.  Everything this module takes and returns is in the paper's scaled units (section 2.1); PhysX runs
in SI from the ``Rod``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.adapter import record_from_chain
from crosscheck.engines.base import Run, SweepResult, n_steps_within_memory, run_inputs, sweep_by_simulate
from crosscheck.engines.classifier import Thresholds, classify, first_event_final
from crosscheck.engines.physx.chain import Raw
from crosscheck.engines.physx.model import World
from crosscheck.engines.physx.options import Options, PgsOptions
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["Options", "PhysxHealth", "simulate", "sweep", "health"]

#: Bytes per record row (raw rollout, the Record and the classifier's temporaries), as Bullet's: ~3 x the measured peak.
ROW_BYTES = 1536


@dataclass(frozen=True)
class PhysxHealth:
    """Per-run statistics of PhysX's contact, over the rows before theta leaves (0, pi/2).

    contact_steps: steps with a contact point.
    max_points: the most contact points in one step (1: the capsule's end cap; PhysX's persistent manifold may
      keep up to 4 on one patch).
    max_penetration: the deepest penetration PhysX reported at a step's contact [l] (0 if none).
    """

    contact_steps: int
    max_points: int
    max_penetration: float


def _options_class(options: dict) -> type:
    """The registered name's ``Options`` class for these options (``PgsOptions`` for solver "pgs")."""
    return PgsOptions if options.get("solver") == "pgs" else Options


def _name(opts: Options) -> str:
    return f"physx_{opts.solver}"


def _record(raw: Raw, rod: Rod, opts):
    """The scaled ``Record`` of a rollout (the shared conversion ``crosscheck.engines.adapter.record_from_chain``)."""
    return record_from_chain(
        rod, raw.q, raw.v, raw.force, raw.points > 0, timestep=opts.timestep, radius=opts.radius, computed=raw.computed
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
    """Run one slipping state in PhysX and classify its first event.

    The capsule starts touching the plane (z_A = r, C on the plane) with the velocities of ``state``
    (``crosscheck.coordinates.to_generalized``), which PhysX stores rounded to float32 (row 0 holds the start as
    given); ``ceil(horizon / timestep)`` steps.  ``Run.solver`` holds ``PhysxHealth``.

    Args:
      rod: physical rod (``Rod.scaled(alpha)`` for the paper's units).
      state: the paper's scaled slipping state.
      mu: friction coefficient (static = dynamic).
      horizon: scaled time to simulate, > 0, at least one timestep.
      thresholds: outcome criteria (``Thresholds()`` by default).
      until_event: stop the rollout once its first event is judged (``first_event_final``); later rows NaN.
      **options: the fields of ``Options`` (unknown -> ValueError naming it).
    """
    mu, horizon, opts = run_inputs(state, mu, horizon, options, _options_class(options))
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES)
    q0, v0 = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    rules = dict(
        mu=mu, alpha=rod.alpha, timestep=opts.timestep, friction_timeconst=opts.friction_time, rigid=True, thresholds=th
    )

    def judged(raw: Raw) -> bool:
        record = _record(raw, rod, opts)
        return first_event_final(classify(record, **rules), raw.computed, th, opts.timestep)

    raw = World(rod, mu, opts).rollout(q0, v0, n, judged if until_event else None)
    record = _record(raw, rod, opts)
    c = classify(record, **rules)
    run = Run.from_classification(
        _name(opts),
        c,
        record,
        state=state,
        mu=mu,
        alpha=rod.alpha,
        options=opts,
        thresholds=th,
        horizon=horizon,
        nstep=n,
    )
    return dataclasses.replace(run, solver=health(raw, record, rod))


def health(raw: Raw, record, rod: Rod) -> PhysxHealth:
    """``PhysxHealth`` of a rollout, over the rows before theta leaves (0, pi/2)."""
    inside = (record.theta > 0.0) & (record.theta < np.pi / 2)
    m = len(record) if inside.all() else int(np.argmin(inside))
    points, separation = raw.points[:m], raw.separation[:m]
    contact = points > 0
    deepest = float(np.min(separation[contact], initial=0.0))
    return PhysxHealth(
        contact_steps=int(contact.sum()),
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
    """Every state through ``simulate`` (one classifier, the same records), on ``workers`` processes, each rollout
    stopped once its first event is judged (a sweep keeps the first event only)."""
    name = _name(_options_class(options).from_kwargs(options))
    return sweep_by_simulate(
        get(name),
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
