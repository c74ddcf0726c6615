"""States per second of ``crosscheck validate pinocchio`` beside the bare loop of its Pinocchio calls.

    python benchmarks/bench_pinocchio.py [--states N] [--repeat R]

The baseline, measured in the same run on the same states, is the bare Python
loop of the ten Pinocchio calls the validation makes per state (crba,
computeCoriolisMatrix, computeGeneralizedGravity, nonLinearEffects,
computeJointJacobiansTimeVariation, getFrameJacobian,
getFrameJacobianTimeVariation, aba, forwardKinematics,
getFrameClassicalAcceleration) with nothing stored and no reference.  The
ratio validation time / bare time is what the rest (conversions, the
analytic reference, the batched linear algebra, the error statistics and
mu_P) costs on top of Pinocchio.  Best of ``--repeat`` rounds, each running the bare loop and then the
validation, by wall clock and by this process's CPU time (the steadier of the two when other processes share the
cores).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import pinocchio as pin

from crosscheck.coordinates import paper_to_qv
from crosscheck.engines.pinocchio import model as pinrod
from crosscheck.engines.pinocchio.studies import dynamics_terms
from crosscheck.rod import Rod


def bare_inputs(n: int, seed: int):
    """(model, data, tip, q, v, tau) for n states of ``dynamics_terms.random_states`` on one rod."""
    s = dynamics_terms.random_states(n, np.random.default_rng(seed))
    rod = Rod(mass=s["m"][0], length=s["l"][0], inertia=s["I0"][0], gravity=s["g"][0])
    q, v = paper_to_qv(rod, s["theta"], s["varphi"], s["Theta"], s["Psi"], s["eta"], s["psi"])
    q, v = np.ascontiguousarray(q), np.ascontiguousarray(v)
    tau = np.ascontiguousarray(np.random.default_rng(seed + 1).standard_normal((n, 5)))
    e = pinrod.PinocchioRod(rod)
    return e.model, e.data, e.tip, q, v, tau


def bare_loop(model, data, tip, q, v, tau) -> None:
    lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for i in range(q.shape[0]):
        qi, vi = q[i], v[i]
        pin.crba(model, data, qi)
        pin.computeCoriolisMatrix(model, data, qi, vi)
        pin.computeGeneralizedGravity(model, data, qi)
        pin.nonLinearEffects(model, data, qi, vi)
        pin.computeJointJacobiansTimeVariation(model, data, qi, vi)
        pin.getFrameJacobian(model, data, tip, lwa)
        pin.getFrameJacobianTimeVariation(model, data, tip, lwa)
        a = pin.aba(model, data, qi, vi, tau[i])
        pin.forwardKinematics(model, data, qi, vi, a)
        pin.getFrameClassicalAcceleration(model, data, tip, lwa)


def best_of_wall_and_cpu(repeat: int, *fs) -> list[tuple[float, float]]:
    """(shortest wall-clock time, shortest CPU time of this process) [s] of each of ``fs`` over ``repeat`` rounds, each
    round running every one of them in turn: a machine that speeds up or slows down during the run moves them alike."""
    wall, cpu = [[] for _ in fs], [[] for _ in fs]
    for _ in range(repeat):
        for k, f in enumerate(fs):
            t, c = time.perf_counter(), time.process_time()
            f()
            wall[k].append(time.perf_counter() - t)
            cpu[k].append(time.process_time() - c)
    return [(min(w), min(c)) for w, c in zip(wall, cpu)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    n = args.states
    inputs = bare_inputs(n, args.seed)
    result = None

    def run():
        nonlocal result
        result = dynamics_terms.validate(n, np.random.default_rng(args.seed), progress=False)

    (t_bare, c_bare), (t_val, c_val) = best_of_wall_and_cpu(args.repeat, lambda: bare_loop(*inputs), run)
    print(f"pin {pin.__version__}, numpy {np.__version__}, {os.cpu_count()} cpus, {n} states, best of {args.repeat}")
    print(f"{'':28} {'wall':>24}  {'CPU of this process':>28}")
    print(
        f"{'bare Pinocchio loop':<28} {n / t_bare:>12,.0f} states/s  {t_bare:7.3f} s  {n / c_bare:>12,.0f} states/s  {c_bare:7.3f} s"
    )
    print(
        f"{'validate pinocchio':<28} {n / t_val:>12,.0f} states/s  {t_val:7.3f} s  {n / c_val:>12,.0f} states/s  {c_val:7.3f} s  "
        f"({'passed' if result.passed else 'FAILED'})"
    )
    print(
        f"ratio validate / bare time: {t_val / t_bare:.2f} (CPU {c_val / c_bare:.2f}); "
        f"bare / validate: {t_bare / t_val:.2f} (CPU {c_bare / c_val:.2f}) (target >= 0.7)"
    )


if __name__ == "__main__":
    main()
