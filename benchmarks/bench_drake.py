"""Cost of the Drake engines: microseconds per record row and seconds per run at the report maps' horizon 2.0, per approximation.

Starts: every ``--every``-th cell of the three quick outcome maps of
``crosscheck.report.sections.engine_maps`` (10 x 10 each: (Psi, mu) at theta
1.0, and (theta, Theta) at Psi 0 and 1.7, mu 1.4; varphi -1.9, eta 1) that
slips at t = 0 (b < 0 < p), as the map section runs them.  Each engine runs
them with its quick-map options (``EngineSpec.report.maps["quick"]``) or with
``--timestep``, on one core, after a warm-up run that builds the diagram (kept
for the runs that follow: one per rod, mu and options).  Reported per engine:
the median and max seconds per run, microseconds per row (a row is one plant
step for the discrete approximations, one record interval for the
continuous plant), and the estimated time of the quick map section
(300 starts x the mean seconds per slipping start x the slipping fraction).
Each run is timed once (best-of is over the whole set with ``--repeat``),
since other processes share the 2 cores.

    python benchmarks/bench_drake.py [--every 3] [--engines drake_sap,drake_continuous] [--timestep 1e-3] [--repeat 1]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from crosscheck import Rod, SlipState
from crosscheck.engines.drake import ENGINES


def map_starts(every: int) -> list[tuple[SlipState, float]]:
    """Slipping starts (b < 0 < p) on every ``every``-th cell of the three quick maps, with their mu."""
    centres = lambda lo, hi, n=10: lo + (np.arange(n) + 0.5) * (hi - lo) / n
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
        best = None
        for _ in range(args.repeat):
            secs, rows = [], 0
            for s, mu in starts:
                spec.simulate(rod, s, mu, horizon=min(args.horizon, 10 * opts.get("timestep", 1e-3)), **opts)  # builds the diagram
                t0 = time.perf_counter()
                run = spec.simulate(rod, s, mu, horizon=args.horizon, **opts)
                secs.append(time.perf_counter() - t0)
                rows += run.nstep
            if best is None or sum(secs) < sum(best[0]):
                best = (secs, rows)
        secs, rows = best
        secs = np.array(secs)
        print(f"{name:18s} {opts}: run median {np.median(secs):.3f} s, max {secs.max():.3f} s; {1e6 * secs.sum() / rows:6.1f} us/row; "
              f"quick map section ~{300 * slipping * secs.mean():.1f} s")


if __name__ == "__main__":
    main()
