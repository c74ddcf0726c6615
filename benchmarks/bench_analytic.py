"""Time crosscheck.theory.analytic.b, p and mode on a 10^6-point grid.

Baseline, measured in the same run: the bare numpy expressions of eqs. b and
p on the same arrays (no input checks, no broadcasting helpers).  Target:
each of b and p within 2x of its bare expression.

    python benchmarks/bench_analytic.py [--n 1000000] [--repeat 7]
"""

from __future__ import annotations

import argparse
import timeit

import numpy as np

from crosscheck.theory import analytic


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    n = args.n
    theta = rng.uniform(1e-3, np.pi / 2 - 1e-3, n)
    varphi = rng.uniform(-np.pi, 0, n)
    Psi = rng.normal(0, 2, n)
    Theta = rng.normal(0, 1, n)
    mu, alpha = 1.4, 3.0

    def bare_b():
        return (Psi**2 * np.cos(theta) ** 2 + Theta**2) * np.sin(theta) - 1.0

    def bare_p():
        s = np.sin(theta)
        return 1.0 + alpha + alpha * s * (mu * np.cos(theta) * np.sin(varphi) - s)

    bb, pp = bare_b(), bare_p()
    assert np.array_equal(analytic.b(Psi, Theta, theta), bb) and np.array_equal(
        analytic.p(theta, varphi, mu, alpha), pp
    )

    def best(f):
        return min(timeit.repeat(f, number=1, repeat=args.repeat))

    rows = [
        ("b", best(lambda: analytic.b(Psi, Theta, theta)), best(bare_b)),
        ("p", best(lambda: analytic.p(theta, varphi, mu, alpha)), best(bare_p)),
        (
            "mode",
            best(lambda: analytic.mode(bb, pp)),
            best(lambda: np.where(pp > 0, np.where(bb <= 0, 0, 1), np.where(bb < 0, 2, 3))),
        ),
    ]
    print(f"{n} points, best of {args.repeat}")
    print(f"{'function':<8} {'crosscheck [ms]':>16} {'bare numpy [ms]':>16} {'ratio':>7}")
    for name, t, t0 in rows:
        print(f"{name:<8} {t * 1e3:>16.2f} {t0 * 1e3:>16.2f} {t / t0:>7.2f}")
    print("baseline for mode: a two-level np.where on the signs (no boundary rules, no checks)")


if __name__ == "__main__":
    main()
