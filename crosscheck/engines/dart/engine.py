"""The DART engine: the capsule rod of ``models/rod.xml`` as a dartpy skeleton under DART's boxed-LCP contact solver.

``simulate`` runs one slipping state; ``sweep`` runs one ``simulate`` per state
(``crosscheck.engines.base.sweep_by_simulate``), so a state gives the same numbers either way.  The model and
its settings are in ``crosscheck.engines.dart.model``.

DART's contact step.  Each step DART finds the capsule-plane contact (penetration or touching: no
speculative margin), builds one normal row and two friction rows along world x and y (its default first
friction direction is the normal's, so it falls back to fixed axes), and solves the step's boxed LCP for the
impulses with Dantzig's pivoting method (ODE's solver, with friction indices): the normal impulse unilateral,
each friction impulse boxed to [-mu, mu] times the normal impulse *as solved before the friction rows enter*,
a bound that is not updated afterwards.  An impulse-based rigid time-stepper (Stewart-Trinkle at velocity
level), hence the tags "rigid" and "time_stepping", with ``Options.contact_time`` = ``friction_time`` = 0.
What differs from the rigid theory is its friction law, measured in tests/test_engine_dart.py:

* the bound: a slipping tip's friction row saturates at mu F_n0, F_n0 the step's normal force without friction,
  while the friction's own moment raises the normal force to F_n > F_n0 (F_n / F_n0 = 1.19 at mu 0.5, 1.78 at
  mu 2 on theta = 0.5): the friction falls short of Coulomb's mu F_n by that ratio, and the feedback behind a
  rigid rod's jam (friction growing with the normal force it raises, eq. p < 0) is cut.  In the quick report's
  maps DART slips from every start where the theory sticks or jams;
* the cone: the two rows are boxed separately, a square pyramid (|F_t| = sqrt(2) mu F_n0 where both saturate).

Row k of the record is the state after k steps with the contact force of step k -> k+1 (the rod's constraint
force along the prismatic joints) and the tip acceleration (v_A,k+1 - v_A,k) / dt.  Scaled units (section 2.1)
in and out; DART runs in SI from the ``Rod``.
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
from crosscheck.engines.dart.console import captured
from crosscheck.engines.dart.model import World
from crosscheck.engines.dart.options import Options
from crosscheck.engines.physx.chain import Raw
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["NAME", "WARNING_KIND", "Options", "DartHealth", "simulate", "sweep", "health"]

#: The engine's registry name.
NAME = "dart"

#: The kind ``sweep`` counts DART's warning lines under (``SweepResult.warnings``).
WARNING_KIND = "DART warning"

#: Bytes per record row, as Bullet's (~3 x the measured peak of a chain rollout's arrays).
ROW_BYTES = 1536


@dataclass(frozen=True)
class DartHealth:
    """Per-run statistics of DART's contact, over the rows before theta leaves (0, pi/2).

    contact_steps: steps with a contact point.
    max_points: the most contact points in one step (1: the capsule's end cap).
    max_penetration: the deepest penetration DART's collision detection reported [l] (0 if none).
    warnings: DART's own warning lines over the whole run (``crosscheck.engines.dart.console``; "Non-finite joint
      accelerations detected ..." once its state has blown up), captured from stderr instead of printed.
    """

    contact_steps: int
    max_points: int
    max_penetration: float
    warnings: int = 0


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
    """Run one slipping state in DART and classify its first event.

    The capsule starts touching the plane (z_A = r, C on the plane) with the velocities of ``state``
    (``crosscheck.coordinates.to_generalized``); ``ceil(horizon / timestep)`` steps.  ``Run.solver`` holds
    ``DartHealth``.  ``until_event``: stop once the first event is judged (``first_event_final``), later rows NaN.
    Other arguments as Bullet's (``crosscheck.engines.bullet.engine.simulate``); ``**options`` the fields of
    ``Options`` (unknown -> ValueError naming it).
    """
    mu, horizon, opts = run_inputs(state, mu, horizon, options, Options)
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES)
    q0, v0 = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    rules = dict(
        mu=mu, alpha=rod.alpha, timestep=opts.timestep, friction_timeconst=opts.friction_time, rigid=True, thresholds=th
    )

    def judged(raw: Raw) -> bool:
        record = _record(raw, rod, opts)
        return first_event_final(classify(record, **rules), raw.computed, th, opts.timestep)

    with captured() as console:  # DART's C++ warnings counted, not printed
        raw = World(rod, mu, opts).rollout(q0, v0, n, judged if until_event else None)
    record = _record(raw, rod, opts)
    c = classify(record, **rules)
    run = Run.from_classification(
        NAME, c, record, state=state, mu=mu, alpha=rod.alpha, options=opts, thresholds=th, horizon=horizon, nstep=n
    )
    return dataclasses.replace(run, solver=health(raw, record, rod, warnings=console.warnings))


def health(raw: Raw, record, rod: Rod, *, warnings: int = 0) -> DartHealth:
    """``DartHealth`` of a rollout, over the rows before theta leaves (0, pi/2); ``warnings``: DART's warning lines."""
    inside = (record.theta > 0.0) & (record.theta < np.pi / 2)
    m = len(record) if inside.all() else int(np.argmin(inside))
    points, separation = raw.points[:m], raw.separation[:m]
    contact = points > 0
    deepest = float(np.min(separation[contact], initial=0.0))
    return DartHealth(
        contact_steps=int(contact.sum()),
        max_points=int(points.max(initial=0)),
        max_penetration=max(0.0, -deepest) / rod.length,
        warnings=warnings,
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
    """Every state through ``simulate``, on ``workers`` processes, each stopped once its first event is judged.

    ``SweepResult.warnings``: DART's warning lines over the runs (``DartHealth.warnings``), as ``WARNING_KIND``."""
    result = sweep_by_simulate(
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
    warned = int(np.sum(result.solver["warnings"]))
    return dataclasses.replace(result, warnings={WARNING_KIND: warned} if warned else {})
