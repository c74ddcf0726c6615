"""The rigid engine: a Moreau / Stewart-Trinkle time-stepper on Pinocchio's constraint solvers with the exact Coulomb cone.

The rod is the 5-joint model of ``crosscheck.engines.pinocchio.model`` (the
same one whose M, C, g, Jacobians and Delassus operator are checked against
the paper); the contact is Pinocchio's ``PointContactConstraintModel``
between the plane (the universe, world axes: two tangential rows, then the
normal) and the tip A, with ``setFriction(mu)``.  One step of length dt from
(q_k, v_k):

    v_free = v_k + dt M^-1 (-C v_k - g)                    (aba with tau = 0)
    u      = J v_free + dt dJ v_k + (gap_k / dt) n         (the contact velocity at the end of the step)
    lambda = the impulse of the nonlinear complementarity problem (NCP) on
             the exact Coulomb cone: u + G lambda = u+, lambda in K_mu,
             u+ + mu |u+_t| n in K_mu*, lambda . (u+ + mu |u+_t| n) = 0
    v_k+1  = v_free + M^-1 J^T lambda,   q_k+1 = q_k + dt v_k+1   (semi-implicit Euler)

with G = J M^-1 J^T the Delassus operator (Pinocchio's
``ConstraintCholeskyDecomposition``) and the NCP solved by Pinocchio's
``PGSConstraintSolver`` (default) or ``ADMMConstraintSolver`` with
``solve_ncp = True``.  Why each term:

* ``dt dJ v_k``: the contact velocity at the end of the step is
  J(q_k+1) v_k+1 ~ J v_k+1 + dt dJ v.  Without it the step enforces J a = 0
  instead of the tip acceleration a_A = J a + dJ v = 0, and misses the
  centripetal term of eq. b: the normal impulse / dt would not be -b/p and
  the lift-off decision would not be b > 0 (MuJoCo's active contact misses
  this term, as ``crosscheck.engines.mujoco.studies.contact`` measures).  With it the
  impulse of a slipping step is exactly eq. FZ with the friction direction
  of the end-of-step slip, and lift-off happens iff b > 0.
* ``gap_k / dt``: the next gap gap_k + dt u+_n stays non-negative (to first
  order); a tip above the plane may still fall freely onto it.
* ``solve_ncp = True``: the convex relaxation (``solve_ncp = False``, the
  cone complementarity problem of Anitescu and of Drake's SAP) replaces the
  normal velocity by u_n + mu |u_t| in the complementarity and launches a
  slipping tip off the plane at w = mu |u_t| in one step: wrong for this
  problem (tests/test_engine_pinocchio.py checks that it happens and that we
  do not do it).

Contact activation.  The contact enters the NCP when the tip's height is at
most ``Options.contact_gap`` (default 10 dt^2 in units of l).  Each position
step raises a slipping tip by about sin theta (dt Theta)^2 / 2 (the arc of
the rod's rotation), so a threshold near machine zero would drop the contact
every step and make the tip hop; 10 dt^2 covers |Theta| up to ~4.5.  A tip
inside the band but lifting off is not held: the gap term lets the NCP
return lambda = 0 when the free motion keeps the gap positive.

Solver health is data: each step records the solver's iterations and
complementarity; a step that misses ``Options.tolerance`` is solved again
with ten times the iterations, up to ``Options.max_iterations_limit``, then
once more warm-started from the sticking impulse -G^-1 u if that lies in
the cone, and the steps that still miss it are counted in ``Run.solver``.
Why the sticking guess: at a jam (p < 0 for the current slip, b < 0) the
step's NCP has no slipping solution and its one solution is the stuck tip
with a tangential impulse (the impact without collision of
``crosscheck.theory.impact.darboux_keller``); from a cold start PGS cycles there at large mu (at
mu = 6 it missed the tolerance after 11002 iterations with a
complementarity of O(1) m g dt, i.e. a wrong impulse) while from the
sticking guess it confirms the solution in a few iterations.  Why only
last: just before p = 0 the step's NCP has both the slipping solution and
the sticking one (the discrete problem is not unique there); the sticking
guess taken at the first miss made the engine jam up to 0.015 early at
mu = 1.7 and stopped its jam time converging with dt, while the slipping
solution continues the analytic flow (to which PGS converges given the
iterations).

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
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.base import (
    STATE_KEYS,
    Run,
    SweepResult,
    check_states,
    n_steps_within_memory,
    sweep_mu_workers,
    run_inputs,
    summaries,
    sweep_by_simulate,
)
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.pinocchio.model import TIP_FRAME, build_model
from crosscheck.engines.pinocchio.options import SOLVERS, Options
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["NAME", "Options", "Stepper", "SOLVERS", "simulate", "sweep"]

#: The engine's registry name.
NAME = "pinocchio"

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

#: Bytes per record row (the raw row, the Record's columns and the classifier's temporaries): the peak
#: resident memory of a 2e5-step run grew by 980 bytes per row; 1.5 x that as a margin.
ROW_BYTES = 1536


@dataclass
class StepInfo:
    """What one step did: the impulse (world axes, physical), whether the contact was in the NCP, solver health,
    and the tip's position, velocity and classical acceleration at the step's start (world axes, physical; the
    acceleration with qdd = (v_next - v) / dt), which a record row needs."""

    impulse: np.ndarray
    active: bool
    iterations: int
    complementarity: float
    converged: bool
    tip_pos: np.ndarray
    tip_vel: np.ndarray
    tip_acc: np.ndarray


class Stepper:
    """The rod, its contact and a constraint solver, built once and stepped many times (physical units inside)."""

    def __init__(self, rod: Rod, mu: float, options: Options):
        self.rod, self.mu, self.options = rod, float(mu), options
        self.model = build_model(rod)
        self.data = self.model.createData()
        frame = self.model.frames[self.model.getFrameId(TIP_FRAME)]
        self.tip = self.model.getFrameId(TIP_FRAME)
        contact = pin.PointContactConstraintModel(self.model, 0, pin.SE3.Identity(), frame.parentJoint, frame.placement)
        contact.setFriction(self.mu)
        self.constraint = pin.ConstraintModel(contact)
        self.models = pin.StdVec_ConstraintModel()
        self.models.append(self.constraint)
        self.datas = pin.StdVec_ConstraintData()
        self.datas.append(self.constraint.createData())
        self.cholesky = pin.ConstraintCholeskyDecomposition(self.model, self.data, self.models, self.datas)
        if options.solver == "admm":
            self.solver, self.settings, self.result = (
                pin.ADMMConstraintSolver(3),
                pin.ADMMSolverSettings(),
                pin.ADMMSolverResult(),
            )
        else:  # "pgs", and the steps "auto" and "closed_form" hand to PGS
            self.solver, self.settings, self.result = (
                pin.PGSConstraintSolver(3),
                pin.PGSSolverSettings(),
                pin.PGSSolverResult(),
            )
        s = self.settings
        s.solve_ncp = bool(options.ncp)
        self.dt = options.timestep / rod.omega
        s.absolute_complementarity_tol = s.absolute_feasibility_tol = options.tolerance * rod.force_scale * self.dt
        s.relative_complementarity_tol = s.relative_feasibility_tol = 0.0
        self.zeros = np.zeros(self.model.nv)

    def step(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, StepInfo]:
        """One step from (q, v) [physical]; returns (q_next, v_next, StepInfo)."""
        model, data, dt = self.model, self.data, self.dt
        a_free = pin.aba(model, data, q, v, self.zeros)
        v_free = v + dt * a_free
        # tip kinematics at (q, v): height, Jacobian, dJ v (classical acceleration with qdd = 0)
        pin.forwardKinematics(model, data, q, v, self.zeros)
        pin.updateFramePlacement(model, data, self.tip)
        pos = data.oMf[self.tip].translation.copy()
        gap = pos[2]
        active = gap <= self.options.gap * self.rod.length
        if not active:
            pin.forwardKinematics(model, data, q, v, a_free)
            vel = pin.getFrameVelocity(model, data, self.tip, _LWA).linear
            acc = pin.getFrameClassicalAcceleration(model, data, self.tip, _LWA).linear
            return q + dt * v_free, v_free, StepInfo(np.zeros(3), False, 0, 0.0, True, pos, vel, acc)
        dJv = pin.getFrameClassicalAcceleration(model, data, self.tip, _LWA).linear
        pin.computeJointJacobians(model, data, q)
        pin.crba(model, data, q)
        self.constraint.calc(model, data, self.datas[0])
        J = pin.getConstraintsJacobian(model, data, self.models, self.datas)
        self.cholesky.compute(model, data, self.models, self.datas, 0.0)
        G = self.cholesky.getDelassusOperatorCholeskyExpression()
        u = J @ v_free + dt * dJv
        u[2] += gap / dt
        cap, iterations, stick_tried = self.options.max_iterations, 0, False
        while True:
            self.settings.max_iterations = cap
            self.solver.solve(G, u, self.models, self.datas, self.settings, self.result)
            iterations += self.result.iterations
            if self.result.converged:
                break
            if cap < self.options.max_iterations_limit:
                cap = min(10 * cap, self.options.max_iterations_limit)
                continue
            if stick_tried:
                break
            stick_tried = True
            lam = -np.linalg.solve(G.matrix(), u)  # the sticking impulse (module docstring)
            if not (lam[2] > 0.0 and math.hypot(lam[0], lam[1]) <= self.mu * lam[2]):
                break
            self.result.setConstraintImpulseGuess(lam)
        lam = np.array(self.result.retrieveConstraintImpulses())
        pin.cholesky.decompose(
            model, data
        )  # M = U D U^T of the crba above: M^-1 J^T lambda in O(nv) (a numpy solve costs 25x more)
        v_next = v_free + pin.cholesky.solve(model, data, J.T @ lam)
        # the row's tip kinematics from this step's J (the contact frame is the world's) and dJ v: no more Pinocchio calls
        info = StepInfo(
            lam,
            True,
            iterations,
            float(self.result.complementarity),
            bool(self.result.converged),
            pos,
            J @ v,
            dJv + J @ ((v_next - v) / dt),
        )
        return q + dt * v_next, v_next, info


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
