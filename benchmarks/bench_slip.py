"""Time crosscheck.theory.gb.slip_until_event on random slipping states.

Baseline, measured in the same run: a real-time ``solve_ivp`` (DOP853, same
tolerances) of eq. polareqs_varphi through ``analytic.scaled_rhs`` with
F_z = normal_force and a terminal event on b, from the same states, to the
same horizon.  (The baseline is singular at p = 0; it is only a cost yardstick.)
Target: one run ~ms, i.e. cheaper than the baseline.

    python benchmarks/bench_slip.py [--n 200] [--mu 1.4]
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck import SlipState
from crosscheck.theory import analytic
from crosscheck.theory.gb import slip_until_event
from crosscheck.tolerances import SLIP_INTEGRATION


def slipping_states(rng, n, mu, alpha):
    out = []
    while len(out) < n:
        th, ph = rng.uniform(0.2, 1.4), rng.uniform(-3.1, 0.0)
        Th, Ps, eta = rng.uniform(-1.5, 1.5), rng.uniform(-2, 2), rng.uniform(0.1, 3)
        if analytic._b(Ps, Th, th) < 0 < analytic._p(th, ph, mu, alpha):
            out.append(SlipState(theta=th, varphi=ph, Theta=Th, Psi=Ps, eta=eta))
    return out


def baseline(state, mu, alpha, t_end):
    y0 = np.array([0, 0, 0, state.psi, state.theta, state.eta, state.varphi, 0, state.Psi, state.Theta], float)

    def rhs(t, y):
        y = y.copy()
        y[4] = min(max(y[4], 1e-6), np.pi / 2 - 1e-6)
        fz = -analytic._b(y[8], y[9], y[4]) / analytic._p(y[4], y[6], mu, alpha)
        return analytic.scaled_rhs(y, fz, mu, alpha)

    ev = lambda t, y: analytic._b(y[8], y[9], y[4])  # noqa: E731
    ev.terminal, ev.direction = True, 1
    solve_ivp(
        rhs,
        (0, max(t_end, 1e-9)),
        y0,
        method="DOP853",
        rtol=SLIP_INTEGRATION.rtol,
        atol=SLIP_INTEGRATION.atol,
        events=[ev],
    )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--mu", type=float, default=1.4)
    ap.add_argument("--alpha", type=float, default=3.0)
    args = ap.parse_args()
    states = slipping_states(np.random.default_rng(0), args.n, args.mu, args.alpha)
    times, base, reasons = [], [], Counter()
    for s in states:
        t0 = time.perf_counter()
        r = slip_until_event(s, args.mu, args.alpha, t_max=10.0)
        times.append(time.perf_counter() - t0)
        reasons[f"{r.outcome.name}/{r.reason}"] += 1
        t0 = time.perf_counter()
        baseline(s, args.mu, args.alpha, r.time)
        base.append(time.perf_counter() - t0)
    times, base = np.array(times) * 1e3, np.array(base) * 1e3
    print(
        f"slip_until_event: median {np.median(times):.2f} ms, p90 {np.percentile(times, 90):.2f} ms, max {times.max():.2f} ms"
    )
    print(f"real-time baseline to the same time: median {np.median(base):.2f} ms")
    print(f"ratio (median) slip_until_event / baseline: {np.median(times) / np.median(base):.2f}")
    print("outcomes:", dict(reasons))


if __name__ == "__main__":
    main()
