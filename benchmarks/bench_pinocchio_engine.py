"""Steps per second of the rigid engine (``crosscheck.engines.get("pinocchio")``) against a bare loop of the same Pinocchio calls, measured in the same run.

Baseline (same rod, states, mu, horizon, timestep, solver settings): a Python
loop that makes exactly the Pinocchio calls one PGS engine step needs (aba,
forward kinematics and the tip's dJ v, joint Jacobians, crba, the contact
constraint's Jacobian, the Delassus Cholesky, the PGS solve, the impulse,
M^-1 J^T lambda, semi-implicit Euler) and nothing else: no record, no
classification, no retry of a missed tolerance.  The engine's time includes
everything ``simulate`` / ``sweep`` does (the scaled ``Record`` of every
row, the solver-health bookkeeping, the classifier).  Best of ``--repeat``
(other processes share the 2 cores), so compare the ratios of one run.

Timed, on one core unless said:
* ``simulate`` with PGS, one state after another (the engine as it was);
* ``sweep`` with ``solver="closed_form"`` (``crosscheck.engines.pinocchio.batch``):
  all states stepped together, the NCP in closed form; its steps/s grows
  with the batch (a step's numpy calls cost about the same for 1 or 100
  states), so it is timed at ``--states``, at the report's sweep chunk for
  this engine (``crosscheck.studies.agreement_store.store_chunk``: its
  ``EngineSpec.sweep_chunk``, 128) and at the default chunk of the other
  engines (32 states, ``STORE_CHUNK``);
* ``sweep`` with PGS on one and on two processes (its parallel efficiency).

The ratio engine / bare is bare time over engine time (> 1: faster than the
bare PGS loop).  Target of the closed form: >= 1e5 steps/s on one core.
Each line gives steps/s by wall clock and by this process's CPU time (both
best of ``--repeat``): on a shared machine the CPU time is the steadier.

    python benchmarks/bench_pinocchio_engine.py [--states 128] [--horizon 1.0] [--repeat 3] [--mu 0.5]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pinocchio as pin

from crosscheck import Rod, SlipState
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get, n_steps
from crosscheck.engines.pinocchio.model import TIP_FRAME, build_model
from crosscheck.engines.pinocchio.stepper import Options
from crosscheck.studies.agreement_store import STORE_CHUNK, store_chunk

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def bare(rod: Rod, state: SlipState, mu: float, opts: Options, nstep: int) -> None:
    """The engine's Pinocchio calls for ``nstep`` steps, without anything else."""
    model = build_model(rod)
    data = model.createData()
    tip = model.getFrameId(TIP_FRAME)
    frame = model.frames[tip]
    contact = pin.PointContactConstraintModel(model, 0, pin.SE3.Identity(), frame.parentJoint, frame.placement)
    contact.setFriction(mu)
    models = pin.StdVec_ConstraintModel()
    models.append(pin.ConstraintModel(contact))
    datas = pin.StdVec_ConstraintData()
    datas.append(models[0].createData())
    chol = pin.ConstraintCholeskyDecomposition(model, data, models, datas)
    solver, settings, result = pin.PGSConstraintSolver(3), pin.PGSSolverSettings(), pin.PGSSolverResult()
    settings.solve_ncp = True
    dt = opts.timestep / rod.omega
    settings.absolute_complementarity_tol = settings.absolute_feasibility_tol = opts.tolerance * rod.force_scale * dt
    settings.relative_complementarity_tol = settings.relative_feasibility_tol = 0.0
    settings.max_iterations = opts.max_iterations
    zeros = np.zeros(model.nv)
    q, v = to_generalized(rod, state)
    for _ in range(nstep):
        v_free = v + dt * pin.aba(model, data, q, v, zeros)
        pin.forwardKinematics(model, data, q, v, zeros)
        pin.updateFramePlacement(model, data, tip)
        gap = data.oMf[tip].translation[2]
        dJv = pin.getFrameClassicalAcceleration(model, data, tip, LWA).linear
        pin.computeJointJacobians(model, data, q)
        pin.crba(model, data, q)
        models[0].calc(model, data, datas[0])
        J = pin.getConstraintsJacobian(model, data, models, datas)
        chol.compute(model, data, models, datas, 0.0)
        u = J @ v_free + dt * dJv
        u[2] += gap / dt
        solver.solve(chol.getDelassusOperatorCholeskyExpression(), u, models, datas, settings, result)
        lam = np.array(result.retrieveConstraintImpulses())
        pin.cholesky.decompose(model, data)
        v = v_free + pin.cholesky.solve(model, data, J.T @ lam)
        q = q + dt * v


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--states", type=int, default=128)
    ap.add_argument("--horizon", type=float, default=1.0, help="scaled time per state")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument(
        "--mu", type=float, default=0.5, help="friction (0.5: below mu_P, every step an ordinary slip, stick or flight)"
    )
    args = ap.parse_args()

    rod = Rod.scaled(3.0)
    mu = args.mu
    rng = np.random.default_rng(0)
    states = [
        SlipState(
            theta=rng.uniform(0.2, 1.3),
            varphi=-rng.uniform(0.1, 3.0),
            Theta=0.7 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.2, 3),
        )
        for _ in range(args.states)
    ]
    opts = Options()
    nstep = n_steps(args.horizon, opts.timestep)
    engine = get("pinocchio")
    few = states[
        :8
    ]  # the PGS loops take ~30 us a step: 8 states keep them short; their steps/s does not depend on the count

    def rates(n_states: int, f) -> tuple[float, float]:
        """(wall, CPU) steps/s of ``f``, each the best of ``--repeat``."""
        wall, cpu = [], []
        for _ in range(args.repeat):
            t, c = time.perf_counter(), time.process_time()
            f()
            wall.append(time.perf_counter() - t)
            cpu.append(time.process_time() - c)
        return n_states * nstep / min(wall), n_states * nstep / min(cpu)

    report_chunk = store_chunk(engine)
    sizes = sorted({STORE_CHUNK, report_chunk, len(states)})
    runs = {
        "bare loop of the Pinocchio calls (PGS)": rates(len(few), lambda: [bare(rod, s, mu, opts, nstep) for s in few]),
        "engine simulate, PGS": rates(
            len(few), lambda: [engine.simulate(rod, s, mu, horizon=args.horizon, solver="pgs") for s in few]
        ),
        **{
            f"engine sweep, closed form, {n} states{' (report chunk)' if n == report_chunk else ''}": rates(
                n,
                lambda n=n: engine.sweep(
                    rod,
                    [states[i % len(states)] for i in range(n)],
                    mu,
                    horizon=args.horizon,
                    progress=False,
                    workers=1,
                    solver="closed_form",
                ),
            )
            for n in sizes
        },
        "engine sweep, PGS, 1 process": rates(
            len(few), lambda: engine.sweep(rod, few, mu, horizon=args.horizon, progress=False, workers=1, solver="pgs")
        ),
        "engine sweep, PGS, 2 processes": rates(
            len(few), lambda: engine.sweep(rod, few, mu, horizon=args.horizon, progress=False, workers=2, solver="pgs")
        ),
    }
    runs["engine sweep, PGS, 2 processes"] = (
        runs["engine sweep, PGS, 2 processes"][0],
        float("nan"),
    )  # the workers' CPU is not ours
    bare_wall, bare_cpu = runs["bare loop of the Pinocchio calls (PGS)"]
    print(f"timestep {opts.timestep:g}, mu {mu:g}, {nstep} steps per state, best of {args.repeat}")
    print(f"{'':52s} {'steps/s (wall)':>15s} {'ratio':>6s} {'steps/s (CPU)':>15s} {'ratio':>6s}")
    for name, (wall, cpu) in runs.items():
        print(f"{name:52s} {wall:15.0f} {wall / bare_wall:6.2f} {cpu:15.0f} {cpu / bare_cpu:6.2f}")
    w1, w2 = runs["engine sweep, PGS, 1 process"][0], runs["engine sweep, PGS, 2 processes"][0]
    print(f"PGS sweep parallel efficiency on 2 processes: {w2 / (2 * w1):.2f}")


if __name__ == "__main__":
    main()
