"""Drake through the engine against Drake's own bare ``Simulator.AdvanceTo`` loop over the same steps, per approximation, in the same run.

For each approximation at the quick maps' options, from the same slipping
starts (every ``--every``-th of a theta grid at Psi 0 and 1.7, mu 1.4,
varphi -1.9, eta 1) to the maps' horizon 2.0, three timings of the same steps:

* bare: ``bare_advance``, Drake alone on the engine's own plant and context
  (``crosscheck.engines.drake.model``), nothing read between steps: one
  ``AdvanceTo`` over a discrete plant's steps; for the continuous plant one
  ``AdvanceTo`` per record row with the engine's integrator and accuracy
  (the engine's rows are where its integrator must land, so these are its steps);
* raw: the engine's step loop (``engine.raw_run``: the contact results and the
  state read every step or row), without the record and the classifier;
* engine: ``crosscheck.engines.get(name).simulate``, the whole run.

A run that the engine stops early (a runaway or Drake's error) is advanced by
bare over the steps the engine took.  Reported: microseconds per step (a plant
step, or a record row of the continuous plant) and bare / engine.  The three
are timed in turn start by start, ``--repeat`` times, and each start keeps
its least CPU time in each (``time.process_time``: other processes share the
2 cores, and wall time counts their turns too).  The bare and engine states after the same steps are
compared bit for bit ("same states").

    python benchmarks/bench_drake_bare.py [--every 4] [--repeat 5] [--engines drake_sap,drake_tamsi]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator

from crosscheck import Rod, SlipState, engines
from crosscheck.coordinates import to_generalized
from crosscheck.engines.drake.engine import raw_run
from crosscheck.engines.drake.model import Model, model, new_context

HORIZON = 2.0
ALL = "drake_sap,drake_similar,drake_lagged,drake_tamsi,drake_continuous"


def bare_advance(m: Model, x0: np.ndarray, rows: int, dt: float) -> np.ndarray:
    """Drake alone over the engine's steps of ``rows`` record rows of ``dt`` seconds from x0 = [q, v] (SI), in a fresh
    context of ``m`` as the engine's; returns the last row's state (discrete: the state after the last step)."""
    ctx = new_context(m)
    pc = m.plant.GetMyMutableContextFromRoot(ctx)
    m.plant.SetPositionsAndVelocities(pc, x0)
    sim = Simulator(m.diagram, ctx)
    if m.options.discrete:
        sim.Initialize()
        sim.AdvanceTo(rows * dt)
    else:
        integrator = ResetIntegratorFromFlags(sim, m.options.integrator, dt)
        integrator.set_target_accuracy(m.options.accuracy)
        sim.Initialize()
        for k in range(1, rows):  # the engine's rows 1 .. rows - 1
            sim.AdvanceTo(k * dt)
    return m.plant.GetPositionsAndVelocities(pc)


def cpu_time(f) -> float:
    t = time.process_time()
    f()
    return time.process_time() - t


def compare(
    rod: Rod, spec, cases: list[tuple[SlipState, float]], *, horizon: float, repeat: int, options: dict | None = None
) -> dict:
    """Bare, raw and engine CPU seconds of one approximation over ``cases`` (start, mu), each a sum over the starts of
    the least of ``repeat`` timings, with the steps timed and whether bare and engine reach the same states."""
    given = dict(spec.report.maps["quick"] if options is None else options)
    opts = spec.options(**given)
    l, w = rod.length, rod.omega
    dt, scale = opts.timestep / w, np.array([l * w, l * w, l * w, w, w])
    n = spec.simulate(rod, cases[0][0], cases[0][1], horizon=horizon, **given).nstep  # the engine's rows
    runs = []  # (model, x0, rows the engine made) per case; the engine's first runs build the diagrams
    same = True
    for s, mu in cases:
        m = model(rod, mu, opts)
        x0 = np.concatenate(to_generalized(rod, s, tip=(0.0, 0.0, opts.radius)))
        raw = raw_run(m, x0, n, dt, scale)
        spec.simulate(rod, s, mu, horizon=horizon, **given)
        done = raw.health.steps if opts.discrete else int(np.isfinite(raw.x[:n, 0]).sum())
        runs.append((m, x0, done))
        last = raw.x[done] if opts.discrete else raw.x[done - 1]
        same &= bool(np.array_equal(bare_advance(m, x0, done, dt), last))
    timed = {
        "bare": lambda i: bare_advance(runs[i][0], runs[i][1], runs[i][2], dt),
        "raw": lambda i: raw_run(runs[i][0], runs[i][1], n, dt, scale),
        "engine": lambda i: spec.simulate(rod, cases[i][0], cases[i][1], horizon=horizon, **given),
    }
    # start by start, the three in turn: the load of the shared cores changes within a second, and each start's least
    # time over the repeats is the one least disturbed
    least = {k: np.full(len(cases), np.inf) for k in timed}
    for _ in range(repeat):
        for i in range(len(cases)):
            for k, f in timed.items():
                least[k][i] = min(least[k][i], cpu_time(lambda: f(i)))
    best = {k: float(v.sum()) for k, v in least.items()}
    return {**best, "steps": sum(done for _, _, done in runs), "runs": len(runs), "same": same, "options": given}


def _starts(every: int) -> list[SlipState]:
    thetas = np.linspace(0.2, 1.5, 12)
    states = [SlipState(theta=t, varphi=-1.9, Theta=0.0, Psi=P, eta=1.0) for P in (0.0, 1.7) for t in thetas]
    return states[::every]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--every", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--engines", default=ALL)
    args = ap.parse_args()
    rod, mu = Rod.scaled(3.0), 1.4
    cases = [(s, mu) for s in _starts(args.every)]
    for name in args.engines.split(","):
        r = compare(rod, engines.get(name), cases, horizon=HORIZON, repeat=args.repeat)
        us = 1e6 / r["steps"]
        print(
            f"{name:16s} {r['runs']} runs, {r['steps']} steps: bare {r['bare'] * us:6.1f} us/step, raw {r['raw'] * us:6.1f}, "
            f"engine {r['engine'] * us:6.1f};  bare / engine {r['bare'] / r['engine']:.2f}; same states: {'yes' if r['same'] else 'NO'}"
        )


if __name__ == "__main__":
    main()
