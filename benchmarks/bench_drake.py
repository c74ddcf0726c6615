"""Cost of the Drake engines at the report maps' horizon 2.0, per approximation: seconds per run, and microseconds per step against Drake's bare loop over the same steps.

Starts: every ``--every``-th cell of the three quick outcome maps of
``crosscheck.report.sections.engine_maps`` (10 x 10 each: (Psi, mu) at theta
1.0, and (theta, Theta) at Psi 0 and 1.7, mu 1.4; varphi -1.9, eta 1) that
slips at t = 0 (b < 0 < p), as the map section runs them.  Each engine runs
them with its quick-map options (``EngineSpec.report.maps["quick"]``) or with
``--timestep``, on one core, after a warm-up run that builds the diagram (kept
for the runs that follow: one per rod, mu and options).  Reported per engine:
the median and max seconds per run, microseconds per row (a row is one plant
step for the discrete approximations, one record interval for the
continuous plant) through the engine and through Drake's bare
``Simulator.AdvanceTo`` over the same steps (``bench_drake_bare.bare_advance``:
nothing read between steps), their ratio bare / engine, and the estimated time
of the quick map section (300 starts x the mean seconds per slipping start x
the slipping fraction).  Each start is timed through the engine and bare in
turn, ``--repeat`` times, keeping each one's least CPU time
(``time.process_time``: other processes share the 2 cores).

    python benchmarks/bench_drake.py [--every 3] [--engines drake_sap,drake_continuous] [--timestep 1e-3] [--repeat 1]
"""

from __future__ import annotations

import argparse

import numpy as np
from bench_drake_bare import bare_advance, cpu_time

from crosscheck import Rod, SlipState
from crosscheck.coordinates import to_generalized
from crosscheck.engines.drake import ENGINES
from crosscheck.engines.drake.model import model


def map_starts(every: int) -> list[tuple[SlipState, float]]:
    """Slipping starts (b < 0 < p) on every ``every``-th cell of the three quick maps, with their mu."""

    def centres(lo, hi, n=10):
        return lo + (np.arange(n) + 0.5) * (hi - lo) / n

    starts = []
    for Psi in centres(0.0, 3.0):
        for mu in centres(0.0, 3.0):
            starts.append((dict(theta=1.0, varphi=-1.9, Theta=0.0, Psi=Psi, eta=1.0), mu))
    for Psi in (0.0, 1.7):
        for theta in centres(0.2, 1.5):
            for Theta in centres(-1.5, 1.5):
                starts.append((dict(theta=theta, varphi=-1.9, Theta=Theta, Psi=Psi, eta=1.0), 1.4))
    alpha = 3.0
    out = []
    for kw, mu in starts[::every]:
        s, c = np.sin(kw["theta"]), np.cos(kw["theta"])
        b = (kw["Psi"] ** 2 * c * c + kw["Theta"] ** 2) * s - 1.0
        p = 1 + alpha + alpha * s * (mu * c * np.sin(kw["varphi"]) - s)
        if b < 0 < p:
            out.append((SlipState(**kw), float(mu)))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--every", type=int, default=3)
    ap.add_argument("--engines", default=",".join(s.name for s in ENGINES))
    ap.add_argument("--timestep", type=float, default=None)
    ap.add_argument("--horizon", type=float, default=2.0)
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    rod = Rod.scaled(3.0)
    starts = map_starts(args.every)
    n_cells = 300 // args.every
    slipping = len(starts) / n_cells
    specs = {s.name: s for s in ENGINES}
    print(f"{len(starts)} slipping starts of {n_cells} cells (fraction {slipping:.2f}), horizon {args.horizon}")
    for name in args.engines.split(","):
        spec = specs[name]
        opts = dict(spec.report.maps["quick"])
        if args.timestep is not None:
            opts["timestep"] = args.timestep
        o = spec.options(**opts)
        dt = o.timestep / rod.omega
        cases = []  # (start, mu, model, x0, steps the engine made); the first run builds the diagram
        for s, mu in starts:
            run = spec.simulate(rod, s, mu, horizon=args.horizon, **opts)
            done = run.solver.steps if o.discrete else int(np.isfinite(run.record.theta).sum())
            cases.append(
                (
                    s,
                    mu,
                    model(rod, mu, o),
                    np.concatenate(to_generalized(rod, s, tip=(0.0, 0.0, o.radius))),
                    done,
                    run.nstep,
                )
            )
        secs, bare = np.full(len(cases), np.inf), np.full(len(cases), np.inf)
        for _ in range(args.repeat):
            for i, (s, mu, m, x0, done, _) in enumerate(cases):
                secs[i] = min(secs[i], cpu_time(lambda: spec.simulate(rod, s, mu, horizon=args.horizon, **opts)))
                bare[i] = min(bare[i], cpu_time(lambda: bare_advance(m, x0, done, dt)))
        steps = sum(c[4] for c in cases)
        print(
            f"{name:18s} {opts}: run median {np.median(secs):.3f} s, max {secs.max():.3f} s; engine {1e6 * secs.sum() / steps:6.1f} us/step, "
            f"bare {1e6 * bare.sum() / steps:6.1f}, bare / engine {bare.sum() / secs.sum():.2f}; quick map section ~{300 * slipping * secs.mean():.1f} s"
        )


if __name__ == "__main__":
    main()
