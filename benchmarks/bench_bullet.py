"""Steps per second of the Bullet engine (``crosscheck.engines.get("bullet")``) against bare pybullet loops, measured in the same run.

Baselines (same rod, states, mu, timestep, settings, the engine's own world):
``stepSimulation`` alone, and ``stepSimulation`` with the two reads a record
row needs (``getJointStates``, ``getContactPoints``).  The engine's time
includes everything ``simulate`` does (the reset that clears Bullet's contact
points, the scaled ``Record``, the classifier).  Also the seconds per run at
horizon 2 (the report maps' horizon), and the sweep on one and two
processes.  Best of ``--repeat`` (other processes share the 2 cores).

    python benchmarks/bench_bullet.py [--states 8] [--horizon 2.0] [--repeat 3] [--timestep 1e-3]
"""

from __future__ import annotations

import argparse

import numpy as np
import pybullet as pb
from timing import best_of  # benchmarks/timing.py (the script's directory is on sys.path)

from crosscheck import Rod, SlipState, engines
from crosscheck.coordinates import to_generalized
from crosscheck.engines import n_steps
from crosscheck.engines.bullet import ENGINES
from crosscheck.engines.bullet.model import JOINTS, world
from crosscheck.engines.bullet.options import Options


def bare(rod: Rod, state: SlipState, mu: float, opts: Options, nstep: int, reads: bool) -> None:
    """``nstep`` Bullet steps from ``state`` in the engine's world, with (or without) the reads of a record row."""
    w = world(rod, mu, opts)
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    w.set_state(q, v)
    c, body, ground, joints = w.client, w.body, w.ground, list(JOINTS)
    for _ in range(nstep):
        pb.stepSimulation(physicsClientId=c)
        if reads:
            pb.getJointStates(body, joints, physicsClientId=c)
            pb.getContactPoints(body, ground, physicsClientId=c)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--states", type=int, default=8)
    ap.add_argument("--horizon", type=float, default=2.0, help="scaled time per state")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--timestep", type=float, default=Options().timestep)
    args = ap.parse_args()

    spec = ENGINES[0]
    if (
        "bullet" not in engines.names()
    ):  # until the package is in crosscheck.engines.BUILTIN (the sweep needs the registry)
        engines.register(spec)
    rod = Rod.scaled(3.0)
    mu = 0.5
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
    opts = Options(timestep=args.timestep)
    nstep = n_steps(args.horizon, opts.timestep)
    total = len(states) * nstep

    t_step = best_of(args.repeat, lambda: [bare(rod, s, mu, opts, nstep, False) for s in states])
    t_reads = best_of(args.repeat, lambda: [bare(rod, s, mu, opts, nstep, True) for s in states])
    runs = []
    t_engine = best_of(
        args.repeat,
        lambda: runs.append([spec.simulate(rod, s, mu, horizon=args.horizon, timestep=opts.timestep) for s in states]),
    )
    contact = np.mean([r.solver.contact_steps / r.nstep for r in runs[-1]])
    t_sweep1 = best_of(
        args.repeat,
        lambda: spec.sweep(rod, states, mu, horizon=args.horizon, progress=False, workers=1, timestep=opts.timestep),
    )
    t_sweep2 = best_of(
        args.repeat,
        lambda: spec.sweep(rod, states, mu, horizon=args.horizon, progress=False, workers=2, timestep=opts.timestep),
    )
    print(
        f"{len(states)} states x {nstep} steps (timestep {opts.timestep:g}, mu {mu:g}, contact in {contact:.0%} of the steps), best of {args.repeat}"
    )
    print(f"stepSimulation alone:            {total / t_step:10.0f} steps/s  ({1e6 * t_step / total:.1f} us/step)")
    print(f"stepSimulation + the row reads:  {total / t_reads:10.0f} steps/s  ({1e6 * t_reads / total:.1f} us/step)")
    print(
        f"engine simulate:                 {total / t_engine:10.0f} steps/s  ({1e6 * t_engine / total:.1f} us/step)  "
        f"ratio to the reads loop {t_reads / t_engine:.2f};  {t_engine / len(states):.3f} s per run to horizon {args.horizon:g}"
    )
    print(f"engine sweep, 1 process:         {total / t_sweep1:10.0f} steps/s")
    print(
        f"engine sweep, 2 processes:       {total / t_sweep2:10.0f} steps/s  parallel efficiency {t_sweep1 / (2 * t_sweep2):.2f}"
    )


if __name__ == "__main__":
    main()
