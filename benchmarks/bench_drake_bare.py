"""Drake through the engine against Drake's own bare loop over the same steps, measured in the same run.

For each discrete approximation at the quick maps' options, from the same
slipping starts (every ``--every``-th of a theta grid at Psi 0 and 1.7, mu
1.4, varphi -1.9, eta 1), three timings of the same number of steps to the
maps' horizon 2.0:

* bare: ``Simulator.AdvanceTo(n dt)`` on the engine's own plant and context
  (``crosscheck.engines.drake.model``), nothing read between steps;
* stepped: the engine's step loop (``EvalUniquePeriodicDiscreteUpdate`` and the
  contact results read every step, as ``engine.raw_run``), without the record
  and the classifier;
* engine: ``crosscheck.engines.get(name).simulate``, the whole run.

The ratios bare / engine and stepped / engine say what the engine's reads and
its record cost on top of Drake's own stepping.  Each is the best of
``--repeat`` timings (other processes share the 2 cores).

    python benchmarks/bench_drake_bare.py [--every 4] [--repeat 2] [--engines drake_sap,drake_tamsi]
"""

from __future__ import annotations

import argparse

import numpy as np
from pydrake.systems.analysis import Simulator

from crosscheck import Rod, SlipState, engines
from crosscheck.coordinates import to_generalized
from crosscheck.engines.drake.engine import raw_run
from crosscheck.engines.drake.model import model, new_context
from timing import best_of

HORIZON = 2.0


def _starts(every: int) -> list[SlipState]:
    thetas = np.linspace(0.2, 1.5, 12)
    states = [SlipState(theta=t, varphi=-1.9, Theta=0.0, Psi=P, eta=1.0) for P in (0.0, 1.7) for t in thetas]
    return states[::every]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--every", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--engines", default="drake_sap,drake_similar,drake_lagged,drake_tamsi")
    args = ap.parse_args()
    rod, mu = Rod.scaled(3.0), 1.4
    states = _starts(args.every)
    for name in args.engines.split(","):
        spec = engines.get(name)
        given = dict(spec.report.maps["quick"])
        opts = spec.options(**given)
        n = int(round(HORIZON / opts.timestep))
        m = model(rod, mu, opts)
        l, w = rod.length, rod.omega
        dt = opts.timestep / w
        x0s = [np.concatenate(to_generalized(rod, s, tip=(0.0, 0.0, opts.radius))) for s in states]

        def bare():
            for x0 in x0s:
                ctx = new_context(m)
                m.plant.SetPositionsAndVelocities(m.plant.GetMyMutableContextFromRoot(ctx), x0)
                sim = Simulator(m.diagram, ctx)
                sim.Initialize()
                sim.AdvanceTo(n * dt)

        def stepped():
            for x0 in x0s:
                raw_run(m, x0, n, dt, np.array([l * w, l * w, l * w, w, w]))

        def engine():
            for s in states:
                spec.simulate(rod, s, mu, horizon=HORIZON, **given)

        engine()  # warm-up: the diagram is built once per setting
        t_bare, t_step, t_eng = best_of(args.repeat, bare), best_of(args.repeat, stepped), best_of(args.repeat, engine)
        us = 1e6 / (n * len(states))
        print(f"{name:16s} {len(states)} runs x {n} steps: bare {t_bare * us:6.1f} us/step, stepped {t_step * us:6.1f}, engine {t_eng * us:6.1f};"
              f"  bare / engine {t_bare / t_eng:.2f}, stepped / engine {t_step / t_eng:.2f}")


if __name__ == "__main__":
    main()
