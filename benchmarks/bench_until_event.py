"""A run stopped once its first event is judged against the whole run, for the engines whose sweeps stop so (Drake, Bullet).

From the same starts (a theta x Theta spread at Psi 0 and 1.7, mu 1.4, varphi -1.9, eta 1, and a line over Psi at
theta 1, Theta 0 with mu drawn from a seeded generator), each engine's ``simulate`` to the maps' horizon 2.0 with and
without ``until_event``, timed in turn by this process's CPU (other processes share the 2 cores).  Reported per engine:
the CPU of the stopped runs over the whole runs' (the baseline, measured in the same run), and how many starts differ
in outcome, event time, ``jam_p_eff`` or ``jam_impulse`` (0: ``first_event_final`` keeps the whole run's first event).

    python benchmarks/bench_until_event.py [--engines drake_sap,bullet] [--thetas 12] [--seed 1]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from crosscheck import Rod, SlipState, engines

ALL = "drake_sap,drake_similar,drake_lagged,drake_tamsi,drake_continuous,bullet"
FIELDS = ("outcome", "event_time", "jam_p_eff", "jam_impulse")


def starts(thetas: int, rng: np.random.Generator) -> list[tuple[SlipState, float]]:
    out = [
        (SlipState(theta=float(th), varphi=-1.9, Theta=Th, Psi=float(rng.choice([0.0, 1.7])), eta=1.0), 1.4)
        for th in np.linspace(0.3, 1.4, thetas)
        for Th in (-0.6, 0.0, 0.6)
    ]
    out += [
        (SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=float(p), eta=1.0), float(rng.uniform(0.3, 1.5)))
        for p in np.linspace(0, 1.9, 8)
    ]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--engines", default=ALL)
    ap.add_argument("--thetas", type=int, default=12)
    ap.add_argument("--horizon", type=float, default=2.0)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rod = Rod.scaled(3.0)
    runs = starts(a.thetas, np.random.default_rng(a.seed))
    print(f"{len(runs)} starts, horizon {a.horizon:g}")
    print(f"{'engine':<18} {'whole [s CPU]':>13} {'stopped [s CPU]':>15} {'stopped / whole':>15} {'differ':>6}")
    for name in a.engines.split(","):
        spec = engines.get(name)
        whole = stopped = 0.0
        differ = 0
        for state, mu in runs:
            t0 = time.process_time()
            w = spec.simulate(rod, state, mu, horizon=a.horizon)
            t1 = time.process_time()
            s = spec.simulate(rod, state, mu, horizon=a.horizon, until_event=True)
            t2 = time.process_time()
            whole, stopped = whole + t1 - t0, stopped + t2 - t1
            differ += not all(np.array_equal(getattr(w, f), getattr(s, f), equal_nan=True) for f in FIELDS)
        print(f"{name:<18} {whole:>13.2f} {stopped:>15.2f} {stopped / whole:>15.2f} {differ:>6d}")


if __name__ == "__main__":
    main()
