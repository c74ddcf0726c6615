"""The Drake engines: the rod of ``crosscheck.engines.drake.model`` run by a discrete contact approximation or a continuous plant.

One module serves every registered name (``drake_continuous``, ``drake_sap``,
``drake_similar``, ``drake_lagged``, ``drake_tamsi``): ``Options.approximation``
selects the plant, and the run's ``engine`` is the name of its approximation.

Start.  The capsule touches the plane (z_A = r, so C = A - r K is on it up to
rounding) with the velocities of the ``SlipState`` at A
(``crosscheck.coordinates.to_generalized``), as MuJoCo's start.

Rows.  Row k is the state at t_k = k timestep and what Drake's contact
computed there (a fresh context per run, so a run's numbers do not depend on
what ran before it in the same process):

* discrete approximations: the plant's own fixed step dt = timestep / omega.
  The state x_k is set in the plant's context, the contact results of that
  context are read (with unsampled output ports they are those of the step
  from x_k, and the step is computed once for both), and
  ``EvalUniquePeriodicDiscreteUpdate`` gives x_k+1.  So row k holds the force
  of the step k -> k+1 (the contact impulse / dt), as MuJoCo's row does.  The
  generalised acceleration of row k is that step's (v_k+1 - v_k) / dt, which
  for Drake's semi-implicit scheme is M(q_k)^-1 (tau(q_k, v_k) + J^T F_k):
  in a force-free step exactly the free acceleration.
* continuous: a ``Simulator`` with the error-controlled ``Options.integrator``
  at ``Options.accuracy`` (steps at most dt long) is advanced to each row time;
  the row holds the state there, the contact force at that state and the
  plant's generalised acceleration at that state (its output port).

tip_acc = J v' + J' v of the tip A from those generalised accelerations
(``crosscheck.engines.adapter.tip_acceleration``), gravity included (a free rod has tip_acc_z = b).
The force is Drake's point-pair force on the rod (``PointPairContactInfo``:
the force on body B, negated when the rod is body A), world frame.  A run that
Drake aborts (a solver or integrator failure) keeps its rows up to there and
NaN after, which the classifier calls DIVERGED; ``Run.solver.failed`` is 1.

Gliding (measured; tests/test_engine_drake.py).  SAP and Similar are convex
relaxations: in a sliding step they treat the slip speed |v_t| as a
separation speed mu |v_t| (the cone complementarity of Anitescu, which
``crosscheck.engines.pinocchio.stepper`` shows launching a rigid tip at
w = mu |u_t|), and the compliant law turns it into an extra normal force:
mu |v_t| k (dt + tau_d) for SAP's Kelvin-Voigt law, mu |v_t| k dt (1 + d mu |v_t|)
for Similar's Hunt & Crossley law (at first contact, scaled units; measured
to ~2 % when R_n >> the Delassus entry).  While that is below the rigid force
-b/p_C the tip glides on the plane and the window-mean force is the rigid
one; above it the tip is pushed off and hops.  So for a slipping rod,
G = mu eta k (dt + tau_d) / (-b/p_C) < 1 is SAP's condition to stay in
contact, and a stiffer SAP or Similar contact does not tend to the rigid
theory: the excess grows with k.  At the defaults (k = 1e4, tau_d = 2/sqrt(k),
d = 2 sqrt(k), dt = 1e-3) G is ~100 for eta ~ 1: both hop, in contact in ~1 %
of the rows.  Lagged and TAMSI do not glide; the continuous plant has no
relaxation.  Lagged's reported ``ContactResults`` force misses its own step
(J v' + J' v against eq. linode2 with that force) by 2e-5 .. 1e-3 of the term
scale in every contact row, where the other approximations agree to their
solver tolerance (continuous exactly): its friction is capped by the normal
force lagged from the step's start, and what it reports is not exactly what
it applied.

Units.  Everything this module takes and returns is in the paper's scaled
units (section 2.1); the plant is SI.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator

from crosscheck.coordinates import to_generalized
from crosscheck.engines.adapter import record_from_chain
from crosscheck.engines.base import (
    Run,
    SweepResult,
    n_steps_within_memory,
    run_inputs,
    sweep_by_simulate,
)
from crosscheck.engines.classifier import FIRST_CHECK, Thresholds, classify, first_event_final
from crosscheck.engines.drake.model import Model, model, new_context
from crosscheck.engines.drake.options import APPROXIMATIONS, Options, engine_name
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["APPROXIMATIONS", "ROW_BYTES", "RUNAWAY_SPEED", "Health", "Options", "raw_run", "simulate", "sweep"]

#: Bytes per record row: the raw row (state, force, acceleration: 21 doubles), the Record's 25 columns and
#: the classifier's temporaries; as the rigid engine's (measured there at 980, 1.5 x margin), whose rows are alike.
ROW_BYTES = 1536

#: A run whose generalised velocities exceed this (scaled, l omega or omega) is stopped and its remaining rows
#: are NaN: the classifier already calls a tip speed of 1e3 DIVERGED, and nothing after it is read.
RUNAWAY_SPEED = 1e6


@dataclass(frozen=True)
class Health:
    """Drake's statistics of one run (integers, kept per run by sweeps as ``solver_<field>``).

    contact_rows: rows with a rod-plane contact pair; steps: plant steps (discrete) or integrator steps
    (continuous); derivative_evaluations, error_shrinkages: the continuous integrator's (0 for discrete);
    failed: 1 when Drake raised and the run was cut short, or the run ran away (``RUNAWAY_SPEED``);
    message: the first line of Drake's error ("" otherwise; not a sweep column).
    """

    contact_rows: int
    steps: int
    derivative_evaluations: int
    error_shrinkages: int
    failed: int
    message: str = ""


@dataclass
class Raw:
    """A run's rows in SI: x (n + 1, 10) states [q, v] (the last one is the state after the last row's step,
    NaN for continuous), vdot (n, 5), force (n, 3) on the rod [N], active (n,); ``computed``: the rows computed
    (n, or fewer when the run stopped once its first event was judged: the rows after it are NaN)."""

    x: np.ndarray
    vdot: np.ndarray
    force: np.ndarray
    active: np.ndarray
    health: Health
    computed: int | None = None


def _read_pairs(results, rod_body, k: int, pairs: list) -> None:
    """Append (k, the rod is body B, Drake's force on body B [N, world]) for each point pair of row k's contact
    results: only copies here (the results are Drake's cache, recomputed in place at the next state); the forces are
    summed after the run (``_contact_rows``)."""
    for i in range(results.num_point_pair_contacts()):  # one pair for a capsule on a half-space
        info = results.point_pair_contact_info(i)
        pairs.append((k, info.bodyB_index() == rod_body, info.contact_force()))


def _contact_rows(pairs: list, force: np.ndarray, active: np.ndarray) -> None:
    """Rows of ``active`` (False on entry) and ``force`` (zeros on entry) from ``_read_pairs``: a pair exists, and
    the sum of its forces on the rod, 0 + f or 0 + (-f) pair by pair in order (np.add.at), the IEEE values of
    0 + f and 0 - f."""
    if pairs:
        k, on_b, f = zip(*pairs)
        f = np.array(f)
        f[~np.array(on_b, bool)] *= -1.0
        np.add.at(force, np.array(k), f)
        active[np.array(k)] = True


#: Discrete steps between two checks of their speeds (``_discrete_rows``).
CHUNK = 64


def _runaway(row: np.ndarray, bound: tuple) -> bool:
    """Not every generalised velocity of the state row [q, v] below its bound in magnitude (so also a NaN one).

    On Python floats, whose abs and < are the IEEE operations numpy's are: a numpy expression per row cost as much as
    Drake's own force-free step."""
    a, b, c, d, e = row.tolist()[5:]
    A, B, C, D, E = bound
    return not (abs(a) < A and abs(b) < B and abs(c) < C and abs(d) < D and abs(e) < E)


def _first_line(e: Exception) -> str:
    return (str(e).splitlines() or [""])[0]


def _discrete_steps(m: Model, pc, x: np.ndarray, pairs: list, start: int, stop: int) -> tuple[int, str | None]:
    """Steps start .. stop - 1 of a discrete plant from x[start] (already in ``pc``): each row's contact pairs
    (``_read_pairs``) and x[k + 1].  Returns (stop, None), or (k, Drake's message) when Drake raised in step k.  The
    step is computed once: the contact results read at x_k are cached with it, and the discrete update reuses them."""
    plant, rod_body = m.plant, m.rod_body
    results = plant.get_contact_results_output_port()
    k = start
    try:
        for k in range(start, stop):
            _read_pairs(results.Eval(pc), rod_body, k, pairs)
            x[k + 1] = plant.EvalUniquePeriodicDiscreteUpdate(pc).value(0)
            pc.SetDiscreteState(0, x[k + 1])
    except RuntimeError as e:
        return k, _first_line(e)
    return stop, None


def _discrete_rows(
    m: Model, pc, x: np.ndarray, pairs: list, n: int, bound: np.ndarray, judged=None
) -> tuple[int, str | None]:
    """Every step of a discrete plant from x[0] (already in ``pc``), as ``_discrete_steps``.

    Returns (n, None), or (k, why) for the first step k that ran away (x[k + 1] beyond ``bound``) or in which Drake
    raised.  The speeds are checked ``CHUNK`` steps at a time, in one numpy pass: the steps taken after the one that
    ran away, at most CHUNK - 1, are discarded with it (``raw_run``), and a step is a function of its state only, so
    the rows before it are those of a run checked at every step."""
    k, check = 0, FIRST_CHECK
    while k < n:
        start = k
        k, message = _discrete_steps(m, pc, x, pairs, start, min(n, start + CHUNK))
        ok = (np.abs(x[start + 1 : k + 1, 5:]) < bound).all(axis=1)
        if not ok.all():
            return start + int(np.argmin(ok)), "runaway speed"
        if message is not None:
            return k, message
        if judged is not None and k >= check and k < n:
            if judged(x, pairs, k):
                return k, STOPPED
            check *= 2
    return n, None


def _continuous_rows(
    m: Model, sim, pc, x: np.ndarray, vdot: np.ndarray, pairs: list, n: int, dt: float, bound: tuple, judged=None
) -> tuple[int, str | None]:
    """Every row of a continuous plant: ``sim`` advanced to t_k = k dt, then row k of x, vdot and contact pairs there.

    Returns (n, None), or (k, why) when x[k] ran away (beyond ``bound``) or Drake raised on the way to or at row k."""
    plant, rod_body = m.plant, m.rod_body
    results, accel = plant.get_contact_results_output_port(), plant.get_generalized_acceleration_output_port()
    k, check = 0, FIRST_CHECK
    try:
        sim.Initialize()
        for k in range(n):
            if k:
                sim.AdvanceTo(k * dt)
            x[k] = plant.GetPositionsAndVelocities(pc)
            _read_pairs(results.Eval(pc), rod_body, k, pairs)
            vdot[k] = accel.Eval(pc)
            if _runaway(x[k], bound):
                return k, "runaway speed"
            if judged is not None and k + 1 == check and k + 1 < n:
                if judged(x, pairs, k + 1, vdot):
                    return k + 1, STOPPED
                check *= 2
    except RuntimeError as e:
        return k, _first_line(e)
    return n, None


#: ``_discrete_rows`` and ``_continuous_rows``'s reason for a run stopped once its first event was judged (not a failure).
STOPPED = "first event judged"


def raw_run(m: Model, x0: np.ndarray, n: int, dt: float, speed_scale: np.ndarray, judged=None) -> Raw:
    """Run ``n`` rows of ``dt`` seconds from the state x0 = [q, v] (SI) in a fresh context of ``m``; ``speed_scale``:
    the SI value of a scaled generalised velocity of 1 (l omega for X', Y', Z', omega for psi', theta').

    ``judged(raw)``, if given, is asked at ``FIRST_CHECK`` rows and then at twice as many each time whether the
    rows so far (a ``Raw`` of them) settle the run's first event; the run stops there if so, its later rows NaN.
    """

    def ask(x, pairs, k, vdot=None):
        force, active = np.zeros((k, 3)), np.zeros(k, bool)
        _contact_rows(pairs, force, active)
        vd = (x[1 : k + 1, 5:] - x[:k, 5:]) / dt if vdot is None else vdot[:k]
        return judged(Raw(x=x[: k + 1], vdot=vd, force=force, active=active, health=None, computed=k))

    plant, opts = m.plant, m.options
    x = np.full((n + 1, 10), np.nan)
    vdot = np.full((n, 5), np.nan)
    force = np.zeros((n, 3))
    active = np.zeros(n, bool)
    bound = tuple((RUNAWAY_SPEED * np.asarray(speed_scale, float)).tolist())
    ctx = new_context(m)
    pc = plant.GetMyMutableContextFromRoot(ctx)
    plant.SetPositionsAndVelocities(pc, x0)
    evaluations = shrinkages = 0
    pairs: list = []
    if opts.discrete:
        x[0] = x0
        k, message = _discrete_rows(m, pc, x, pairs, n, np.array(bound), None if judged is None else ask)
        _contact_rows(pairs, force, active)
        if (
            message is not None
        ):  # rows k.. not computed (stopped, failed or ran away): row k's contact and step are not known
            force[k:], x[k + 1 :], active[k:] = np.nan, np.nan, False
        steps = k
        vdot[:] = (x[1:, 5:] - x[:-1, 5:]) / dt
    else:
        sim = Simulator(m.diagram, ctx)
        integrator = ResetIntegratorFromFlags(sim, opts.integrator, dt)
        integrator.set_target_accuracy(opts.accuracy)
        k, message = _continuous_rows(m, sim, pc, x, vdot, pairs, n, dt, bound, None if judged is None else ask)
        _contact_rows(pairs, force, active)
        if message is not None:
            x[k:], vdot[k:], force[k:], active[k:] = np.nan, np.nan, np.nan, False
        steps, evaluations = integrator.get_num_steps_taken(), integrator.get_num_derivative_evaluations()
        shrinkages = integrator.get_num_step_shrinkages_from_error_control()
    stopped = message == STOPPED
    health = Health(
        contact_rows=int(active.sum()),
        steps=int(steps),
        derivative_evaluations=int(evaluations),
        error_shrinkages=int(shrinkages),
        failed=int(message is not None and not stopped),
        message="" if stopped else message or "",
    )
    return Raw(x=x, vdot=vdot, force=force, active=active, health=health, computed=k if stopped else n)


def record(rod: Rod, raw: Raw, opts: Options) -> Record:
    """The scaled, world-frame ``Record`` of a run (the shared conversion ``crosscheck.engines.adapter.record_from_chain``
    with the plant's generalised accelerations: tip_acc = J v' + J' v)."""
    n = len(raw.active)
    return record_from_chain(
        rod,
        raw.x[:n, :5],
        raw.x[:n, 5:],
        raw.force,
        raw.active,
        timestep=opts.timestep,
        radius=opts.radius,
        vdot=raw.vdot,
        computed=raw.computed,
    )


#: The largest alpha the continuous plant runs: its stiffest mode (the rod's rotation, inertia I0 = m l^2 / alpha)
#: sets its error-controlled step, so its time grows with alpha (measured on one loaded core at horizon 0.5: 18 s at
#: 3, 37 s at 10, 98 s at 30; the audit's: 37 s at 100, more than 120 s at 1000, every other engine under 2 s).
CONTINUOUS_ALPHA_MAX = 100.0


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
    """Run one slipping state in Drake and classify its first event.

    Args:
      rod: physical rod (``Rod.scaled(alpha)`` for the paper's units).
      state: the paper's scaled slipping state (the capsule starts touching the plane, z_A = r).
      mu: friction coefficient >= 0.
      horizon: scaled time, > 0; ceil(horizon / timestep) rows.
      thresholds: outcome criteria (``Thresholds()`` by default).
      until_event: stop the run once its first event is judged (``first_event_final``): the outcome and event
        time are the whole run's, the record's later rows NaN (time too), and Drake's statistics count the
        steps taken.  Sweeps use it: they keep only the first event.
      **options: the fields of ``crosscheck.engines.drake.options.Options`` (approximation, timestep,
        radius, stiffness, dissipation, relaxation_time, stiction_tolerance, integrator, accuracy,
        near_rigid_threshold); an unknown or bad one raises ``ValueError`` naming it.

    Returns:
      ``crosscheck.engines.Run``, engine ``drake_<approximation>``, with ``Health`` in ``solver``.
    """
    mu, horizon, opts = run_inputs(state, mu, horizon, options, Options)
    if opts.approximation == "continuous" and rod.alpha > CONTINUOUS_ALPHA_MAX:
        raise ValueError(
            f"alpha must be at most {CONTINUOUS_ALPHA_MAX:g} for drake_continuous (its error-controlled steps shrink "
            f"as 1/alpha: 37 s at alpha 100 for a horizon of 0.5, more than 120 s at 1000); got {rod.alpha:g}"
        )
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES)  # the record holds every row: refuse before allocating
    m = model(rod, mu, opts)
    q0, v0 = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    l, w = rod.length, rod.omega

    rules = dict(
        mu=mu,
        alpha=rod.alpha,
        timestep=opts.timestep,
        friction_timeconst=opts.friction_time,
        contact_time=opts.contact_time,
        radius=opts.radius,
        thresholds=th,
    )

    def judged(raw: Raw) -> bool:
        return first_event_final(classify(record(rod, raw, opts), **rules), raw.computed, th, opts.timestep)

    raw = raw_run(
        m,
        np.concatenate((q0, v0)),
        n,
        opts.timestep / w,
        np.array([l * w, l * w, l * w, w, w]),
        judged if until_event else None,
    )
    rec = record(rod, raw, opts)
    c = classify(rec, **rules)
    run = Run.from_classification(
        opts.name, c, rec, state=state, mu=mu, alpha=rod.alpha, options=opts, thresholds=th, horizon=horizon, nstep=n
    )
    return replace(run, solver=raw.health)


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
    """Every state through ``simulate`` (``sweep_by_simulate`` with the registered engine of the options' approximation).

    Each run stops once its first event is judged (``simulate``'s ``until_event``): a sweep keeps the first event
    only, and the rows after it cost as much as those before (measured over the full report's Drake maps: the
    first event and its look-ahead need 13-49 % of the horizon on average).
    The diagram of each (rod, mu, options) is built once and reused (``model.model``); ``workers`` > 1 runs
    chunks of states in forked processes, each with its own diagrams.
    """
    from crosscheck.engines import get

    name = engine_name(Options.from_kwargs(options).approximation)
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
