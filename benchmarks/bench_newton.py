"""Steps per second of the Newton engines' batched sweep against Newton's bare batched step loop, in the same run.

For each solver: one Newton model of B worlds (the engine's own ``Batch``: the rod's D6 joint, capsule and plane per
world), and

* bare: ``n`` calls of the solver's step on all B worlds (collision included where the solver needs Newton's
  pipeline), no readback: what Newton costs;
* sweep: ``crosscheck.engines.get(name).sweep`` of the same B starts over the same steps: the readback of every
  step's poses and twists, the scaled ``Record``, the classifier, the summaries.

World-steps per CPU second (and wall time) are B n / time, best of ``--repeat`` (other processes share the 2 cores).  The models and
kernels are built and loaded before any timing (the first step, which compiles or loads the kernels, is timed apart:
``crosscheck.engines.newton.model.compile_seconds``).  ``--cold`` instead runs each solver's first step in a fresh
process with an empty Warp kernel cache (a temporary ``WARP_CACHE_PATH``) and prints the CPU seconds of Warp's
compilation: what a fresh machine (CI) pays once.

    python benchmarks/bench_newton.py [--worlds 4 64 256] [--horizon 0.5] [--repeat 2] [--solvers mujoco xpbd featherstone]
    python benchmarks/bench_newton.py --cold
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np
from timing import best_of  # benchmarks/timing.py (the script's directory is on sys.path)

from crosscheck import Rod, engines
from crosscheck.coordinates import to_generalized
from crosscheck.engines import n_steps

SOLVERS = ("mujoco", "xpbd", "featherstone")


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def cold(solver: str) -> None:
    """Print the CPU seconds of one Newton solver's build and first step (run in a fresh process and cache)."""
    from crosscheck.engines.newton import model as newton_model
    from crosscheck.state import SlipState

    spec = engines.get(f"newton_{solver}")
    rod, opts = Rod.scaled(3.0), spec.options()
    c0, t0 = _cpu(), time.perf_counter()
    batch = newton_model.Batch(rod, opts, 4)
    c1 = _cpu()
    q0, v0 = to_generalized(rod, SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0), tip=(0, 0, 0.01))
    batch.run(np.tile(q0, (4, 1)), np.tile(v0, (4, 1)), np.full(4, 0.5), 1)
    c2, t2 = _cpu(), time.perf_counter()
    print(
        f"{solver:13s} cold: model and solver {c1 - c0:6.1f} CPU s, first step {c2 - c1:6.1f} CPU s, "
        f"total {c2 - c0:6.1f} CPU s ({t2 - t0:.0f} s wall)",
        flush=True,
    )


def cold_all(solvers) -> None:
    """Each solver's cold compile in a fresh process and an empty kernel cache of its own."""
    for solver in solvers:
        with tempfile.TemporaryDirectory() as cache:
            env = {**os.environ, "WARP_CACHE_PATH": cache}
            subprocess.run([sys.executable, __file__, "--cold-one", solver], env=env, check=True)


def best_cpu(repeat: int, f) -> float:
    """The least CPU time of ``repeat`` runs of ``f()`` [s]: Warp's CPU kernels run on the calling thread, so this is
    the work itself, whatever else shares the cores (wall times here were 10-15 x it on the shared machine)."""
    times = []
    for _ in range(repeat):
        c = _cpu()
        f()
        times.append(_cpu() - c)
    return min(times)


def bare(batch, n: int) -> None:
    """``n`` steps of every world of ``batch``, no readback."""
    import warp as wp

    for k in range(n):
        batch._step(k)
    wp.synchronize()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", type=int, nargs="+", default=[4, 64, 256])
    ap.add_argument("--horizon", type=float, default=0.5, help="scaled time per start")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--solvers", nargs="+", default=list(SOLVERS), choices=SOLVERS)
    ap.add_argument("--cold", action="store_true", help="each solver's kernel compile from an empty cache")
    ap.add_argument("--cold-one", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.cold_one:
        return cold(args.cold_one)
    if args.cold:
        return cold_all(args.solvers)

    import sys as _sys

    _sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
    from conftest import random_slip_states  # the tests' seeded slipping states

    from crosscheck.engines.newton import model as newton_model

    rod, mu = Rod.scaled(3.0), 0.5
    for solver in args.solvers:
        spec = engines.get(f"newton_{solver}")
        opts = spec.options()
        n = n_steps(args.horizon, opts.timestep)
        for B in args.worlds:
            states = random_slip_states(np.random.default_rng(0), B)
            q0, v0 = (np.array(x) for x in zip(*(to_generalized(rod, s, tip=(0, 0, opts.radius)) for s in states)))
            batch = newton_model.batch(rod, opts, B)
            batch.run(q0, v0, np.full(B, mu), 1)  # the model built and its kernels loaded before any timing
            t_bare, c_bare = best_of(args.repeat, lambda: bare(batch, n)), best_cpu(args.repeat, lambda: bare(batch, n))
            run = lambda: spec.sweep(rod, states, mu, horizon=args.horizon, progress=False)  # noqa: E731
            t_sweep, c_sweep = best_of(args.repeat, run), best_cpu(args.repeat, run)
            print(
                f"{spec.name:20s} B={B:4d} n={n:5d}: bare {B * n / c_bare:9.0f} world-steps per CPU s "
                f"({1e3 * c_bare / n:6.2f} CPU ms/step; wall {1e3 * t_bare / n:6.2f}), sweep {B * n / c_sweep:9.0f} "
                f"({1e3 * c_sweep / n:6.2f} CPU ms/step; wall {1e3 * t_sweep / n:6.2f}), sweep / bare CPU "
                f"{c_sweep / c_bare:5.2f}",
                flush=True,
            )
    print("first steps (kernel loads) of this process, CPU s:", newton_model.compile_seconds())


if __name__ == "__main__":
    main()
