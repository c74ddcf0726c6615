"""CPU time of the compliant engine (``simulate``) per state against its bare ``solve_ivp``; the model's cost and solver choices.

The headline, on random slipping states (b < 0 < p, seeded) run over the
same horizon: ``crosscheck.engines.get("compliant").simulate`` (integration
with its mode-switch events, the sampled ``Record``, the classifier) against
the bare ``scipy.integrate.solve_ivp`` of the same right-hand side over the
same intervals: one call per mode segment of the engine's own trajectory,
from that segment's start state to its end, with the same method,
tolerances, analytic Jacobian and dense output, and nothing else (no events,
no record).  Both are timed in the same run, interleaved, by the CPU time of
this process (wall-time ratios moved 2x between two runs on the shared
cores, CPU-time ratios by ~20 %), the best of ``--repeat`` each; the ratio
bare / engine is the share of the engine's time that is the solver's.  Measured with the defaults: 0.70-0.72
(0.62-0.67 before the record read the force and the slip from one ``Dynamics.terms`` per row); most of the rest is
the record's second ``Dynamics.terms`` per row, inside ``Dynamics.tip_acceleration``, and the mode-switch events.

With ``--more``, three older measurements on states run to the rigid flow's first event
(``crosscheck.theory.slipping.slip_until_event``, t_max = 2):

1. cost per state of ``integrate`` at a few eps against ``slip_until_event``
   (the ratio of medians);
2. Radau against BDF at the default tolerances (``COMPLIANT_INTEGRATION``)
   and BDF at 100x tighter ones: time and the largest error of the slow
   variables at the end against a Radau run at rtol 1e-11 / atol 1e-13;
3. the analytic Jacobian (``Dynamics.jac``) against scipy's own
   finite-difference Jacobian of the whole right-hand side.

    python benchmarks/bench_compliant.py [--n 12] [--mu 0.5] [--horizon 0.5] [--repeat 3] [--more [--eps 1e-1 1e-2 1e-3]]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.integrate

from crosscheck.engines import get, n_steps
from crosscheck.engines.compliant import integrate
from crosscheck.engines.compliant import trajectory as _trajectory
from crosscheck.engines.compliant.run import Options
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic
from crosscheck.theory.slipping import slip_until_event

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


def bare_segments(traj, options: Options) -> None:
    """``solve_ivp`` of each mode segment of ``traj`` alone: its right-hand side, Jacobian, start state and interval,
    the engine's method and tolerances (``integrate`` scales atol by eps on the gap), dense output, no events."""
    dyn = traj.dynamics
    atol = options.atol * np.array([1, 1, min(1.0, dyn.eps), 1, 1, 1, 1, 1, 1, 1])
    for seg in traj.segments:
        if seg.t1 > seg.t0:
            m, d = seg.mode, seg.direction
            scipy.integrate.solve_ivp(
                lambda t, y: dyn.rhs(y, m, d),
                (seg.t0, seg.t1),
                seg.y0,
                method=options.method,
                rtol=options.rtol,
                atol=atol,
                jac=lambda t, y: dyn.jac(y, m, d),
                dense_output=True,
            )


def engine_overhead(rod: Rod, states: list[SlipState], mu: float, horizon: float, repeat: int) -> None:
    """The headline of the module docstring: ``simulate`` against the bare ``solve_ivp`` of its segments."""
    engine, options = get("compliant"), Options()
    # simulate integrates one timestep past its last record row, at (n_steps - 1) timestep
    end = max(horizon, n_steps(horizon, options.timestep) * options.timestep)
    trajs = [integrate(rod, s, mu, horizon=end, eps=options.eps, xi=options.xi) for s in states]
    t_engine = t_bare = np.inf
    for _ in range(repeat):  # interleaved, so the load of other processes hits both alike
        t_engine = min(t_engine, _timed(lambda: [engine.simulate(rod, s, mu, horizon=horizon) for s in states])[1])
        t_bare = min(t_bare, _timed(lambda: [bare_segments(tr, options) for tr in trajs])[1])
    segments = sum(len(tr.segments) for tr in trajs)
    print(
        f"{len(states)} slipping states, mu = {mu}, horizon {horizon} ({round(horizon / options.timestep)} record rows each), "
        f"eps = {options.eps:g}, {options.method}; {segments} mode segments; CPU time, best of {repeat}"
    )
    print(f"bare solve_ivp of the segments: {t_bare / len(states) * 1e3:7.1f} ms per state")
    print(
        f"compliant engine (simulate):    {t_engine / len(states) * 1e3:7.1f} ms per state   ratio bare / engine {t_bare / t_engine:.2f}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=12)
    ap.add_argument("--mu", type=float, default=0.5)
    ap.add_argument("--alpha", type=float, default=3.0)
    ap.add_argument("--horizon", type=float, default=0.5, help="scaled time per state of the engine measurement")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--more", action="store_true", help="also the rigid-flow cost and the solver choices (minutes)")
    ap.add_argument("--eps", type=float, nargs="+", default=[1e-1, 1e-2, 1e-3])
    args = ap.parse_args()
    rod = Rod.scaled(args.alpha)
    states = slipping_states(np.random.default_rng(0), args.n, args.mu, args.alpha)
    engine_overhead(rod, states, args.mu, args.horizon, args.repeat)
    if not args.more:
        return
    horizons = []
    rigid = []
    for s in states:
        r, _ = _timed(lambda: slip_until_event(s, args.mu, args.alpha, t_max=2.0))
        rigid.append(min(_timed(lambda: slip_until_event(s, args.mu, args.alpha, t_max=2.0))[1] for _ in range(3)))
        horizons.append(max(r.time, 1e-3))
    rigid = np.array(rigid) * 1e3
    print(
        f"{len(states)} slipping states, mu = {args.mu}, horizons (rigid first event, <= 2): median {np.median(horizons):.3f}"
    )
    print(f"slip_until_event: median {np.median(rigid):.2f} ms per state")

    # 1. cost per state at each eps
    for eps in args.eps:
        cost, steps = [], []
        for s, h in zip(states, horizons):
            tr, dt = _timed(lambda: integrate(rod, s, args.mu, horizon=h, eps=eps, xi=1.0))
            cost.append(dt)
            steps.append(len(tr.t))
        cost = np.array(cost) * 1e3
        print(
            f"integrate eps={eps:g}: median {np.median(cost):.1f} ms (max {cost.max():.1f}), median steps {np.median(steps):.0f}; "
            f"ratio to slip_until_event (medians): {np.median(cost) / np.median(rigid):.0f}"
        )

    # 2. Radau against BDF, and 3. analytic against finite-difference Jacobian, at the middle eps
    eps = args.eps[len(args.eps) // 2]
    refs = [
        integrate(rod, s, args.mu, horizon=h, eps=eps, xi=1.0, rtol=1e-11, atol=1e-13) for s, h in zip(states, horizons)
    ]

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
        print(
            f"  {label}: median {np.median(costs):.1f} ms, total {costs.sum():.0f} ms; error of the slow variables: "
            f"median {np.median(errs):.1e}, largest {max(errs):.1e}"
        )
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
    print(
        f"  BDF / Radau time: {bdf / radau:.2f} at the same tolerances, {bdf_tight / radau:.2f} at 100x tighter ones; "
        f"finite-difference / analytic Jacobian time: {fd / radau:.2f}"
    )
    assert scipy.integrate.solve_ivp is original


if __name__ == "__main__":
    main()
