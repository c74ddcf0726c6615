"""The Newton engines: the capsule rod of ``models/rod.xml`` stepped by one of Newton's solvers, a batch of worlds at once.

``sweep`` puts its states into blocks of worlds of one Newton model (``crosscheck.engines.newton.model.Batch``:
``SIZES`` worlds, the last block's spare worlds running copies of its last state), steps each block together and reads
its states back after each step; ``simulate`` is a sweep of one state (the smallest block), so a state gives the same
numbers either way: Newton's worlds do not interact (tests assert equality).

What the record holds.  Newton's solvers return float32 body poses and twists; row k of the record is the state after
k steps (row 0 the exact start in float64, as given) and the contact force of step k -> k+1 is read from the centre
of mass's change of velocity, F = m (v_S,k+1 - v_S,k) / dt + m g e_z (the only forces on the rod are gravity and the
contact, and the D6 joint's translations are the centre of mass's own coordinates): the impulse of the step / dt,
whatever the solver's contact model, without reading any solver's contact buffers.  Its float32 rounding is
~ulp(|v|) / dt, 1e-4 m g at |v| = 5 l omega and timestep 1e-3; a force within ``FORCE_ROUNDING`` times that reads
as none (free flight then records F = 0 exactly, as the engines that read a solver's contact force do).  ``active`` is the solver's contact: the capsule's
lowest point below the plane at the step's collision detection (every shape has margin and gap 0: MuJoCo Warp's
pair and the penalty force exist only then); for XPBD, whose projection leaves a resting contact point on the plane
to rounding, within ``RESTING_GAP`` of it.

Units.  Everything this module takes and returns is in the paper's scaled units (section 2.1); the model runs in SI
from the ``Rod`` (``crosscheck.engines.newton.model``).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from crosscheck.checks import POSITIVE
from crosscheck.coordinates import tip_position, tip_velocity, to_generalized
from crosscheck.engines.base import (
    STATE_KEYS,
    Run,
    SweepResult,
    check_states,
    n_steps_within_memory,
    run_inputs,
    summaries,
    sweep_mu_workers,
)
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.newton import model as newton_model
from crosscheck.engines.newton.options import Options
from crosscheck.engines.record import Record, row_times
from crosscheck.progress import bar
from crosscheck.rod import Rod
from crosscheck.state import SlipState, real_scalar

__all__ = [
    "Options",
    "NewtonHealth",
    "simulate",
    "simulate_batch",
    "sweep",
    "record_from_raw",
    "SIZES",
    "preload",
    "provenance",
]

#: World counts of the Newton models a sweep uses: the smallest that holds the states, else blocks of the largest.
#: A MuJoCo Warp step on CPU costs ~10 ms at 4 worlds and ~16 ms at 256 (its kernel launches, not its worlds), so
#: spare worlds are cheap; three sizes keep the models (and their ~5 s of building) few.
SIZES = (4, 64, 256)

#: Bytes per state and row: the float32 poses and twists read back (52), the float64 generalized arrays, the Record
#: and the classifier's temporaries; ~3 x the Record's 8-byte columns as a margin.
ROW_BYTES = 1024


#: float32's machine epsilon: Warp's states are float32.
EPS32 = float(np.finfo(np.float32).eps)

#: A step's force within this many eps32 (|v_k| + |v_k+1| + g dt) / (g dt) of zero is rounding: no force.  The
#: difference of two float32 velocities errs by up to eps32 (|v_k| + |v_k+1|) / 2 per component; 4 x that leaves room
#: for the solver's own rounding of the step's v_k+1 (measured in free flight: 2.9e-6 m g at |v| ~ 1, timestep 3e-3,
#: where eps32 |v| / (g dt) = 4e-5).  The floor is 3e-4 m g at |v| ~ 1 and timestep 3e-3: the force resolution of a
#: float32 engine read from its velocities.
FORCE_ROUNDING = 4.0


def _name(opts: Options) -> str:
    return f"newton_{opts.solver}"


@dataclass(frozen=True)
class NewtonHealth:
    """Per-run statistics of the solver's state over the rows before theta leaves (0, pi/2).

    max_spin: the largest angular speed about the rod's own axis [omega] (0 where the solver holds the D6 joint
      exactly: MuJoCo Warp and Featherstone, in reduced coordinates; XPBD projects the joint and the semi-implicit
      solver springs it, and both leave some).
    max_penetration: the deepest the capsule went below the plane [l] (0 if never).
    """

    max_spin: float
    max_penetration: float


def record_from_raw(raw: newton_model.Raw, rod: Rod, options: Options, q0: np.ndarray, v0: np.ndarray) -> Record:
    """The scaled, world-frame ``Record`` of B rollouts (rows k = 0..n-1: state k and step k -> k+1); row 0 holds the
    float64 start (q0, v0), each (B, 5) SI, the later rows Warp's float32 states."""
    q, v = raw.q.copy(), raw.v.copy()  # (B, n + 1, 5)
    n = q.shape[1] - 1
    L, w, g = rod.length, rod.omega, rod.gravity
    dt = options.timestep / w
    vel = tip_velocity(rod, q, v)
    acc = (vel[:, 1:] - vel[:, :-1]) / (dt * g)
    force = (v[:, 1:, :3] - v[:, :-1, :3]) / (dt * g)  # [m g]: (F - m g) / (m g) ...
    force[..., 2] += 1.0  # ... plus gravity's m g: the contact force alone
    # a step without contact leaves rounding here, not 0: v_k+1 - v_k of float32 velocities is exact only to
    # ~eps32 (|v_k| + |v_k+1|), so a force within FORCE_ROUNDING times that / (dt g) reads as no force (the classifier's
    # lift-off asks for F_n <= 0 exactly; +3e-6 m g of rounding in free flight made a lifted rod STICK)
    speed = np.abs(v[:, 1:, :3]).max(axis=-1) + np.abs(v[:, :-1, :3]).max(axis=-1) + dt * g
    floor = FORCE_ROUNDING * EPS32 * speed / (dt * g)
    force[np.all(np.abs(force) <= floor[..., None], axis=-1)] = 0.0
    q[:, 0], v[:, 0] = q0, v0
    pos, vel = tip_position(rod, q[:, :n]), tip_velocity(rod, q[:, :n], v[:, :n])
    psi, theta = np.ascontiguousarray(q[:, :n, 3]), np.ascontiguousarray(q[:, :n, 4])
    Psi, Theta = v[:, :n, 3] / w, v[:, :n, 4] / w
    tip_pos, tip_vel = pos / L, vel / (L * w)
    r = options.radius
    slip = np.zeros_like(tip_vel)
    slip[..., 0] = tip_vel[..., 0] - r * Theta * np.sin(psi)
    slip[..., 1] = tip_vel[..., 1] + r * Theta * np.cos(psi)
    gap = tip_pos[..., 2] - r
    return Record(
        t=np.broadcast_to(row_times(n, options.timestep), gap.shape).copy(),
        tip_pos=tip_pos,
        tip_vel=tip_vel,
        tip_acc=acc,
        force=force,
        normal_force=force[..., 2].copy(),
        active=gap < (RESTING_GAP if options.solver == "xpbd" else 0.0),
        gap=gap,
        slip_vel=slip,
        psi=psi,
        theta=theta,
        Psi=Psi,
        Theta=Theta,
    )


#: XPBD's ``active`` threshold [l]: its projection leaves a resting contact point on the plane to float32 rounding,
#: on either side, so a flag at gap < 0 flips with the rounding (it differed between a scaled and a physical rod's
#: same run); a contact point within 1e-6 l of the plane counts as in contact.
RESTING_GAP = 1e-6


def _health(raw: newton_model.Raw, record: Record, rod: Rod) -> dict:
    inside = (record.theta > 0.0) & (record.theta < np.pi / 2)
    keep = np.cumprod(inside, axis=-1).astype(bool)  # the rows before theta first leaves (0, pi/2)
    spin = np.where(keep, np.abs(raw.spin[:, :-1]), 0.0).max(axis=-1) / rod.omega
    pen = np.where(keep, np.maximum(-record.gap, 0.0), 0.0).max(axis=-1)
    return {"max_spin": spin, "max_penetration": pen}


def _blocks(rod: Rod, states: list, mu: np.ndarray, n: int, opts: Options, progress):
    """(q0, v0, and per block of ``SIZES`` worlds (first state, Raw of its states)): every state's n steps."""
    q0, v0 = (np.array(x) for x in zip(*(to_generalized(rod, s, tip=(0.0, 0.0, opts.radius)) for s in states)))
    B = len(states)
    # (MuJoCo in C through Newton steps one world: one start per model)
    size = 1 if opts.mujoco_cpu else next((s for s in SIZES if s >= B), SIZES[-1])
    blocks = []
    for a in bar(list(range(0, B, size)), progress=progress, desc=f"{_name(opts)} sweep", unit="block"):
        idx = np.minimum(np.arange(a, a + size), B - 1)  # spare worlds repeat the last state
        raw = newton_model.batch(rod, opts, size).run(q0[idx], v0[idx], mu[idx], n)
        m = min(size, B - a)
        blocks.append((a, newton_model.Raw(q=raw.q[:m], v=raw.v[:m], spin=raw.spin[:m])))
    return q0, v0, blocks


def _rollouts(rod: Rod, states: list, mu: np.ndarray, n: int, opts: Options, progress) -> tuple:
    """(Record, health) of every state, through blocks of ``SIZES`` worlds."""
    q0, v0, blocks = _blocks(rod, states, mu, n, opts, progress)
    records, healths = [], []
    for a, raw in blocks:
        m = raw.q.shape[0]
        record = record_from_raw(raw, rod, opts, q0[a : a + m], v0[a : a + m])
        records.append(record)
        healths.append(_health(raw, record, rod))
    record = (
        records[0]
        if len(records) == 1
        else Record(**{f: np.concatenate([getattr(r, f) for r in records]) for f in Record.__dataclass_fields__})
    )
    health = {k: np.concatenate([h[k] for h in healths]) for k in healths[0]}
    return record, health


def _classify(record: Record, mu, rod: Rod, opts: Options, th: Thresholds):
    return classify(
        record,
        mu=mu,
        alpha=rod.alpha,
        timestep=opts.timestep,
        friction_timeconst=opts.friction_time,
        rigid=opts.contact_time == 0.0,
        contact_time=opts.contact_time,
        radius=opts.radius,
        thresholds=th,
    )


def _run(rod, state, mu, horizon, raw, q0, v0, opts, th) -> Run:
    """The ``Run`` of one state from its Raw (1, n + 1, ...) and its start (q0, v0), each (1, 5)."""
    record = record_from_raw(raw, rod, opts, q0, v0)
    health = _health(raw, record, rod)
    one = Record(**{f: getattr(record, f)[0] for f in Record.__dataclass_fields__})
    c = _classify(one, mu, rod, opts, th)
    n = raw.q.shape[1] - 1
    run = Run.from_classification(
        _name(opts), c, one, state=state, mu=mu, alpha=rod.alpha, options=opts, thresholds=th, horizon=horizon, nstep=n
    )
    return dataclasses.replace(run, solver=NewtonHealth(**{k: float(v[0]) for k, v in health.items()}))


def simulate(
    rod: Rod,
    state: SlipState,
    mu: float,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    options_class: type = Options,
    **options,
) -> Run:
    """Run one slipping state in Newton (a sweep of one: the same numbers as its row of ``sweep``).

    The capsule starts touching the plane (z_A = r) with the velocities of ``state``; ``ceil(horizon / timestep)``
    steps.  ``Run.solver`` holds ``NewtonHealth``.  ``options``: the fields of ``Options`` (unknown -> ValueError
    naming it); ``options_class``: the engine's ``Options`` subclass (``crosscheck.engines.newton.solvers``).
    """
    mu, horizon, opts = run_inputs(state, mu, horizon, options, options_class)
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES * SIZES[0])
    q0, v0, [(_, raw)] = _blocks(rod, [state], np.array([mu]), n, opts, False)
    return _run(rod, state, mu, horizon, raw, q0, v0, opts, th)


def simulate_batch(
    rod: Rod,
    states: Sequence[SlipState],
    mu: Sequence[float],
    *,
    horizon: Sequence[float],
    thresholds: Thresholds | None = None,
    options_class: type = Options,
    **options,
) -> list[Run]:
    """``simulate`` of every state at its own mu and horizon (one each), the states stepped together in blocks of
    worlds: the same ``Run`` of each, record for record, as its own ``simulate`` (worlds do not interact, and a run's
    first k steps do not depend on how many follow: each state's rows are the first of the longest run's).  MuJoCo
    Warp on CPU costs ~7 ms a step at 4 worlds and at 64, so n states cost about one ``simulate`` (tests assert the
    equality)."""
    states = check_states(states)
    if not (len(mu) == len(horizon) == len(states)):
        raise ValueError(f"mu and horizon must have one value per state ({len(states)}); got {len(mu)}, {len(horizon)}")
    inputs = [run_inputs(s, m, h, options, options_class) for s, m, h in zip(states, mu, horizon)]
    opts = inputs[0][2]
    th = thresholds or Thresholds()
    ns = [n_steps_within_memory(h, opts.timestep, ROW_BYTES * min(len(states), SIZES[-1])) for _, h, _ in inputs]
    q0, v0, blocks = _blocks(rod, states, np.array([m for m, _, _ in inputs]), max(ns), opts, False)
    runs = []
    for a, raw in blocks:
        for j in range(raw.q.shape[0]):
            i, rows = a + j, slice(0, ns[a + j] + 1)
            one = newton_model.Raw(q=raw.q[j : j + 1, rows], v=raw.v[j : j + 1, rows], spin=raw.spin[j : j + 1, rows])
            mu_i, h_i, _ = inputs[i]
            runs.append(_run(rod, states[i], mu_i, h_i, one, q0[i : i + 1], v0[i : i + 1], opts, th))
    return runs


def sweep(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    n_series: int = 200,
    progress: bool | None = None,
    options_class: type = Options,
    **options,
) -> SweepResult:
    """Every state in Newton, in blocks of worlds stepped together (module docstring); one classifier.

    mu: a scalar or one per state (set per world).  ``options``, ``options_class``: as for ``simulate``.
    """
    states = check_states(states)
    horizon = real_scalar("horizon", horizon, POSITIVE)
    opts = options_class.from_kwargs(options)
    mu = sweep_mu_workers(mu, len(states), 1)
    th = thresholds or Thresholds()
    B = len(states)
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES * min(B, SIZES[-1]))
    t0 = time.perf_counter()
    record, health = _rollouts(rod, states, mu, n, opts, progress)
    c = _classify(record, mu, rod, opts, th)
    summary, series = summaries(record, c, mu, rod.alpha, max(1, n // max(1, n_series)))
    wall = time.perf_counter() - t0
    return SweepResult(
        engine=_name(opts),
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
        solver=health,
    )


#: The start ``preload`` steps once: the contract test's slipping start (b < 0 < p at mu = 0.5).
_PRELOAD_START = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)


def preload(options_class: type = Options) -> None:
    """Warp's one-time work of this process for ``options_class``'s solver: Newton's import, the loads (or the
    compilation) of its kernels and the solver's first step (``compile_seconds``), by one step of the scaled rod at
    the default options.  A process forked afterwards (a report section) inherits them: measured, a section's first
    MuJoCo Warp model and step then cost 0.15 CPU s instead of 5.3 (2.1 import, 2.7 first model, 0.55 first step)."""
    opts = options_class()
    simulate(Rod.scaled(3.0), _PRELOAD_START, 0.5, horizon=opts.timestep, options_class=options_class)


def provenance(options_class: type = Options) -> dict:
    """{"kernel_compile_seconds": CPU seconds of the solver's first step in this process} ({} before it): Warp's
    kernel compilation or cache loads, kept out of every per-step cost."""
    solver = options_class().solver
    seconds = newton_model.compile_seconds()
    return {"kernel_compile_seconds": seconds[solver]} if solver in seconds else {}
