"""Steps per second of the MuJoCo engine's ``sweep`` against two baselines measured in the same run.

Baselines (same model, same states, same horizon and timestep):
  * bare rollout: ``mujoco.rollout.Rollout(nthread=2).rollout(...)`` with its own
    checks and output allocation (state and sensors), nothing else;
  * Python loop: ``mj_step`` in a Python loop that reads the contacts each step
    (``data.ncon``, ``mj_contactForce``) and the tip site, as a user without
    sensors would record the same series.

The sweep's time includes everything it does (compiling the model, initial
states, the scaled ``Record`` of every row, classification, summaries).  Each measurement is repeated, interleaved,
and the best is kept, since other processes share the 2 cores; the CPU time of the process (all its threads) is
printed beside the wall time, as it moves less with their load.  Target: sweep / bare >= 0.9 in wall time.

Measured (best of 7, this code and the code before it run in turn four times): 0.90-0.93 at 64 states (CPU time
0.92-0.94) against 0.85-0.88 before, 0.90-0.92 at 100 (a quick-report map) against 0.90-0.91; 1.11 at 1024 (best
of 3, a full-report map, where the bare rollout's own output of states and sensors is the larger).  What moved 64
states: a sweep's rollouts were chunks of 16 states, each one ``rollout`` call on both threads, read while the next
rolled out; every call ended at a barrier, its last state (~8 ms) on one thread while the other waited, five times
per sweep.  Now each thread runs its own single-threaded rollouts of 3-state chunks and takes the next one as it
finishes (``crosscheck.engines.mujoco.rollouts``): the threads wait on each other once, at the end.  What is left:
with both cores busy the wall time cannot fall below (rollout CPU + reading CPU) / 2, about 0.94 of the bare
rollout at 64 states, and the reading (Record, classifier, summaries: ~0.3 ms per chunk and ~0.4 ms per state of
3334 rows) is a little dearer in 3-state chunks than it was in 5-state blocks.  The reading thread's own CPU is
printed: 35-44 ms at 64 states while the rollouts run (records 13, classifier 21, summaries 3.5), against 33-36 ms
on an idle core (probably as the chunks come from the other core's cache, which the rollouts share).  Transposing the sensor columns before the record's
arithmetic (``crosscheck.engines.mujoco.model``) took 1.5 ms of it off; since, 0.91-0.95 in 17 runs at 64 and 100 states.

    python benchmarks/bench_mujoco.py [--states 64 100 1024] [--horizon 1.0] [--repeat 5] [--loop-states 4]
"""

from __future__ import annotations

import argparse
import time

import mujoco
import numpy as np
from mujoco import rollout

from crosscheck import Rod, SlipState
from crosscheck.engines import get, n_steps
from crosscheck.engines.mujoco.model import build_model, initial_state
from crosscheck.engines.mujoco.options import Options


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--states",
        type=int,
        nargs="+",
        default=[64, 100, 1024],
        help="batch sizes, each measured apart (100: a quick-report map, 1024: a full-report map)",
    )
    ap.add_argument("--horizon", type=float, default=1.0, help="scaled time per state")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--loop-states", type=int, default=4, help="states for the (slow) Python loop; 0 leaves it out")
    args = ap.parse_args()

    for n in args.states:
        measure(n, args)


def measure(n_states: int, args) -> None:
    """The three runs at one batch size, interleaved ``args.repeat`` times; prints the best of each."""
    rod = Rod(mass=1.0, length=1.0, inertia=1.0 / 3.0, gravity=9.81)
    mu = 0.8
    rng = np.random.default_rng(0)
    states = [
        SlipState(
            theta=rng.uniform(0.2, 1.3),
            varphi=-rng.uniform(0.1, 3.0),
            Theta=0.7 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.2, 3),
        )
        for _ in range(n_states)
    ]
    opts = Options()
    model = build_model(rod, mu, opts)
    nstep = n_steps(args.horizon, opts.timestep)
    x0 = np.stack([initial_state(model, rod, s, opts.radius) for s in states])
    total = n_states * nstep

    def bare() -> float:
        datas = [mujoco.MjData(model) for _ in range(2)]
        with rollout.Rollout(nthread=2) as pool:
            t0 = time.perf_counter()
            pool.rollout(model, datas, x0, nstep=nstep)
            return time.perf_counter() - t0

    reading = [
        np.inf
    ]  # CPU of this thread in a sweep: the records, the classifier, the summaries (the rollouts run in others)

    def swept() -> float:
        c0, t0 = time.thread_time(), time.perf_counter()
        get("mujoco").sweep(rod, states, mu, horizon=args.horizon, progress=False)
        wall = time.perf_counter() - t0
        reading[0] = min(reading[0], time.thread_time() - c0)
        return wall

    def loop() -> float:
        data = mujoco.MjData(model)
        force = np.zeros(6)
        tip = model.site("tip").id
        out = np.empty((nstep, 4))
        t0 = time.perf_counter()
        for x in x0[: args.loop_states]:
            mujoco.mj_setState(model, data, x, mujoco.mjtState.mjSTATE_FULLPHYSICS)
            for k in range(nstep):
                mujoco.mj_step(model, data)
                fn = 0.0
                for i in range(data.ncon):
                    mujoco.mj_contactForce(model, data, i, force)
                    fn += force[0]
                out[k, 0] = fn
                out[k, 1:] = data.site_xpos[tip]
        return (time.perf_counter() - t0) * n_states / args.loop_states

    runs = {"bare": bare, "sweep": swept, **({"loop": loop} if args.loop_states else {})}
    best = {k: np.inf for k in runs}
    cpu = {k: np.inf for k in runs}
    for _ in range(args.repeat):  # interleaved, so load from other processes hits all alike
        for k, f in runs.items():
            c = time.process_time()
            best[k] = min(best[k], f())
            cpu[k] = min(cpu[k], time.process_time() - c)
    rate = {k: total / v for k, v in best.items()}
    print(
        f"{n_states} states x {nstep} steps (horizon {args.horizon}, timestep {opts.timestep} scaled), mujoco {mujoco.__version__}, "
        f"best of {args.repeat}"
    )
    print(f"bare rollout (2 threads): {rate['bare']:12,.0f} steps/s   CPU {cpu['bare']:.3f} s")
    print(
        f"sweep (2 threads):        {rate['sweep']:12,.0f} steps/s   CPU {cpu['sweep']:.3f} s   ratio to bare rollout {rate['sweep'] / rate['bare']:.2f} "
        f"(target >= 0.9), in CPU time {cpu['bare'] / cpu['sweep']:.2f}"
    )
    print(
        f"  of which the reading thread (records, classifier, summaries): CPU {reading[0]:.3f} s; with both cores busy the "
        f"sweep's wall time cannot fall below (its CPU) / 2 = {cpu['sweep'] / 2:.3f} s, the bare rollout's {cpu['bare'] / 2:.3f} s"
    )
    if "loop" in rate:
        print(
            f"python mj_step loop:      {rate['loop']:12,.0f} steps/s   sweep / loop {rate['sweep'] / rate['loop']:.1f}x (1 thread, reads contacts)"
        )


if __name__ == "__main__":
    main()
