"""Cost of the compliant rod (crosscheck.engines.compliant.integrate) per state against the rigid flow, and its solver choices.

Three measurements on the same random slipping states (b < 0 < p, seeded),
each run to the rigid flow's first event (``crosscheck.theory.slipping.slip_until_event``,
t_max = 2), in the same run so that the machine's load cancels in the ratios
(CPU time of this process; the rigid runs the best of 3, as benchmarks/timing.py's
best_of, the compliant runs once each: they take 0.1-0.5 s):

1. cost per state of ``integrate`` at a few eps against ``slip_until_event``
   (the ratio of medians);
2. Radau against BDF at the default tolerances (``COMPLIANT_INTEGRATION``)
   and BDF at 100x tighter ones: wall time and the largest error of the slow
   variables at the end against a Radau run at rtol 1e-11 / atol 1e-13;
3. the analytic Jacobian (``Dynamics.jac``) against scipy's own
   finite-difference Jacobian of the whole right-hand side.

    python benchmarks/bench_compliant.py [--n 12] [--mu 0.5] [--eps 1e-1 1e-2 1e-3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.integrate

from crosscheck.theory import analytic
from crosscheck.engines.compliant import integrate
from crosscheck.engines.compliant import trajectory as _trajectory
from crosscheck.rod import Rod
from crosscheck.theory.slipping import slip_until_event
from crosscheck.state import SlipState

KEYS = ("eta", "varphi", "Psi", "theta", "Theta")


def slipping_states(rng: np.random.Generator, n: int, mu: float, alpha: float) -> list[SlipState]:
    """n slipping states (b < 0 < p, eq. b and eq. p) in the paper's ranges."""
    out = []
    while len(out) < n:
        th, ph = rng.uniform(0.2, 1.4), rng.uniform(-3.1, 0.0)
        Th, Ps, eta = rng.uniform(-1.5, 1.5), rng.uniform(-2, 2), rng.uniform(0.1, 3)
        if analytic.b(Ps, Th, th) < 0 < analytic.p(th, ph, mu, alpha):
            out.append(SlipState(theta=th, varphi=ph, Theta=Th, Psi=Ps, eta=eta))
    return out


def _timed(f):
    """(f(), the CPU time it took [s]): process time, which the other processes on the shared cores do not inflate
    as much as wall time (measured: wall-time ratios moved 2x between two runs, CPU-time ratios by ~20 %)."""
    t = time.process_time()
    out = f()
    return out, time.process_time() - t


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=12)
    ap.add_argument("--mu", type=float, default=0.5)
    ap.add_argument("--alpha", type=float, default=3.0)
    ap.add_argument("--eps", type=float, nargs="+", default=[1e-1, 1e-2, 1e-3])
    args = ap.parse_args()
    rod = Rod.scaled(args.alpha)
    states = slipping_states(np.random.default_rng(0), args.n, args.mu, args.alpha)
    horizons = []
    rigid = []
    for s in states:
        r, _ = _timed(lambda: slip_until_event(s, args.mu, args.alpha, t_max=2.0))
        rigid.append(min(_timed(lambda: slip_until_event(s, args.mu, args.alpha, t_max=2.0))[1] for _ in range(3)))
        horizons.append(max(r.time, 1e-3))
    rigid = np.array(rigid) * 1e3
    print(f"{len(states)} slipping states, mu = {args.mu}, horizons (rigid first event, <= 2): median {np.median(horizons):.3f}")
    print(f"slip_until_event: median {np.median(rigid):.2f} ms per state")

    # 1. cost per state at each eps
    for eps in args.eps:
        cost, steps = [], []
        for s, h in zip(states, horizons):
            tr, dt = _timed(lambda: integrate(rod, s, args.mu, horizon=h, eps=eps, xi=1.0))
            cost.append(dt)
            steps.append(len(tr.t))
        cost = np.array(cost) * 1e3
        print(f"integrate eps={eps:g}: median {np.median(cost):.1f} ms (max {cost.max():.1f}), median steps {np.median(steps):.0f}; "
              f"ratio to slip_until_event (medians): {np.median(cost) / np.median(rigid):.0f}")

    # 2. Radau against BDF, and 3. analytic against finite-difference Jacobian, at the middle eps
    eps = args.eps[len(args.eps) // 2]
    refs = [integrate(rod, s, args.mu, horizon=h, eps=eps, xi=1.0, rtol=1e-11, atol=1e-13) for s, h in zip(states, horizons)]

    def err(tr, ref, h):
        a, b = tr.state_at(h), ref.state_at(h)
        return max(abs(a[k] - b[k]) for k in KEYS)

    def run(label, **kw):
        costs, errs = [], []
        for s, h, ref in zip(states, horizons, refs):
            tr, dt = _timed(lambda: integrate(rod, s, args.mu, horizon=h, eps=eps, xi=1.0, **kw))
            costs.append(dt)
            errs.append(err(tr, ref, h))
        costs = np.array(costs) * 1e3
        print(f"  {label}: median {np.median(costs):.1f} ms, total {costs.sum():.0f} ms; error of the slow variables: "
              f"median {np.median(errs):.1e}, largest {max(errs):.1e}")
        return costs.sum()

    print(f"solver choices at eps = {eps:g} (errors against Radau at rtol 1e-11, atol 1e-13):")
    radau = run("Radau, analytic Jacobian")
    bdf = run("BDF, analytic Jacobian", method="BDF")
    bdf_tight = run("BDF, analytic Jacobian, rtol 1e-10, atol 1e-12", method="BDF", rtol=1e-10, atol=1e-12)
    original = _trajectory.solve_ivp

    def without_jacobian(*a, **kw):
        kw["jac"] = None
        return original(*a, **kw)

    _trajectory.solve_ivp = without_jacobian
    try:
        fd = run("Radau, scipy's finite-difference Jacobian")
    finally:
        _trajectory.solve_ivp = original
    print(f"  BDF / Radau time: {bdf / radau:.2f} at the same tolerances, {bdf_tight / radau:.2f} at 100x tighter ones; "
          f"finite-difference / analytic Jacobian time: {fd / radau:.2f}")
    assert scipy.integrate.solve_ivp is original


if __name__ == "__main__":
    main()
