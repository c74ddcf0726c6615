"""Steps per second of the DART engine against DART's own bare stepping loop, measured in the same run.

Baselines (same rod, states, mu, timestep, settings, the engine's own scene built per run as the engine
builds it): ``World.step`` alone, and with the reads a record row needs (``getPositions``,
``getVelocities``, ``getLastCollisionResult``).  The engine's time includes everything ``simulate`` does (the fresh scene, the scaled
``Record``, the classifier); the sweep stops each run once its first event is judged, as the report's do.
Best of ``--repeat`` (other processes share the 2 cores).

    python benchmarks/bench_dart.py [--states 8] [--horizon 2.0] [--repeat 3] [--timestep 1e-3]
"""

from __future__ import annotations

import argparse

import numpy as np
from timing import best_of  # benchmarks/timing.py (the script's directory is on sys.path)

from crosscheck import Rod, SlipState, engines
from crosscheck.coordinates import to_generalized
from crosscheck.engines import n_steps
from crosscheck.engines.dart.model import World
from crosscheck.engines.dart.options import Options


def bare(rod: Rod, state: SlipState, mu: float, opts: Options, nstep: int, reads: bool) -> None:
    """``nstep`` DART steps from ``state`` in a scene built as the engine builds it, with (or without) a row's reads."""
    w = World(rod, mu, opts)
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    skel, world = w.skeleton, w.world
    skel.setPositions(q)
    skel.setVelocities(v)
    for _ in range(nstep):
        world.step()
        if reads:
            skel.getPositions(), skel.getVelocities(), world.getLastCollisionResult().getNumContacts()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--states", type=int, default=8)
    ap.add_argument("--horizon", type=float, default=2.0, help="scaled time per state")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--timestep", type=float, default=Options().timestep)
    args = ap.parse_args()
    rod, mu = Rod.scaled(3.0), 0.5
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
    for name in ("dart",):
        spec = engines.get(name)
        opts = spec.options(timestep=args.timestep)
        nstep = n_steps(args.horizon, opts.timestep)
        total = len(states) * nstep
        t_step = best_of(args.repeat, lambda: [bare(rod, s, mu, opts, nstep, False) for s in states])
        t_reads = best_of(args.repeat, lambda: [bare(rod, s, mu, opts, nstep, True) for s in states])
        runs = []
        t_engine = best_of(
            args.repeat,
            lambda: runs.append(
                [spec.simulate(rod, s, mu, horizon=args.horizon, timestep=opts.timestep) for s in states]
            ),
        )
        contact = np.mean([r.solver.contact_steps / r.nstep for r in runs[-1]])
        sweeps = []
        t_sweep = best_of(
            args.repeat,
            lambda: sweeps.append(
                spec.sweep(rod, states, mu, horizon=args.horizon, progress=False, workers=1, timestep=opts.timestep)
            ),
        )
        print(
            f"{spec.label}: {len(states)} states x {nstep} steps (timestep {opts.timestep:g}, mu {mu:g}, "
            f"contact in {contact:.0%} of the steps), best of {args.repeat}"
        )
        print(f"  step alone:              {total / t_step:9.0f} steps/s  ({1e6 * t_step / total:.1f} us/step)")
        print(f"  step + the row reads:    {total / t_reads:9.0f} steps/s  ({1e6 * t_reads / total:.1f} us/step)")
        print(
            f"  engine simulate:         {total / t_engine:9.0f} steps/s  ({1e6 * t_engine / total:.1f} us/step)  "
            f"bare / engine {t_step / t_engine:.2f}, reads / engine {t_reads / t_engine:.2f}; "
            f"{t_engine / len(states):.3f} s per run to horizon {args.horizon:g}"
        )
        print(
            f"  engine sweep (stops at the first event): {t_sweep:.2f} s, {t_sweep / t_step:.2f} x the bare loop over "
            f"the whole horizon; {t_sweep / len(states):.3f} s per run"
        )


if __name__ == "__main__":
    main()
