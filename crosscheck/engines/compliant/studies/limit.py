"""The compliant rod run towards eps -> 0 beside the rigid impact without collision: the runs, the fits and the three studies.

The asymptotics it is measured against (growth rates, the fast problem, restitution, the indeterminate boundary,
the GB point's rates) are ``crosscheck.theory.compliant_limit``, whose docstring derives them.  Scaled units (section 2.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crosscheck.coordinates import tip_velocity, to_generalized
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic
from crosscheck.theory.compliant_limit import fast_limit, growth_rates, indeterminate_boundary, time_corrections
from crosscheck.theory.impact.darboux_keller import Impact, impact
from crosscheck.theory.slipping import slip_until_event

__all__ = [
    "slope_bound",
    "LimitRun",
    "limit_run",
    "impact_tip_velocity",
    "post_errors",
    "jam_state_past",
    "inconsistent_study",
    "indeterminate_study",
    "jam_study",
    "fit_log_slope",
    "fit_power",
]


def fit_log_slope(eps, t_over_eps) -> tuple[float, float]:
    """Least-squares (slope, intercept) of t/eps against ln(1/eps): the slope estimates 1/lambda."""
    x = np.log(1.0 / np.asarray(eps, float))
    slope, intercept = np.polyfit(x, np.asarray(t_over_eps, float), 1)
    return float(slope), float(intercept)


def slope_bound(eps, corrections, tolerance) -> float:
    """How far the least-squares slope of t_stop/eps against ln(1/eps) may lie from 1/lambda.

    Each point may depart from the leading law by its correction plus the
    correction's allowance (``tolerance.allowance``); a least-squares slope
    moves by sum_i |w_i| d_i for departures d_i, w_i = (x_i - mean x) /
    sum (x - mean x)^2 with x = ln(1/eps).
    """
    x = np.log(1.0 / np.asarray(eps, float))
    w = (x - x.mean()) / np.sum((x - x.mean()) ** 2)
    c = np.abs(np.asarray(corrections, float))
    return float(np.sum(np.abs(w) * (c + tolerance.allowance(c))))


def fit_power(eps, err) -> float:
    """Least-squares slope of ln|err| against ln(eps): the observed order of convergence."""
    return float(np.polyfit(np.log(np.asarray(eps, float)), np.log(np.abs(np.asarray(err, float))), 1)[0])


# ------------------------------------------------------------------------------------------- the compliant runs ---


@dataclass(frozen=True, eq=False)
class LimitRun:
    """One compliant run through its impulsive phase (``limit_run``).

    Attributes:
      eps, xi: the law's parameters.
      t_stop: the first slip stop of the contact point (NaN if none).
      t_end: the first contact end (the law's push returning to 0; NaN if none before the horizon).
      kinds: the event kinds in order.
      post: the paper's variables at t_end (``Trajectory.state_at``), with the tip velocity u (3,) [l omega].
      seconds: wall time of the run.
    """

    eps: float
    xi: float
    t_stop: float
    t_end: float
    kinds: tuple
    post: dict | None
    seconds: float

    @property
    def outcome(self) -> str:
        """ "impact" (the slip stopped before the contact ended), "liftoff" (the contact ended while slipping) or "open"."""
        if math.isfinite(self.t_stop) and (not math.isfinite(self.t_end) or self.t_stop <= self.t_end):
            return "impact"
        return "liftoff" if math.isfinite(self.t_end) else "open"

    def as_dict(self) -> dict:
        post = (
            None
            if self.post is None
            else {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in self.post.items()}
        )
        return {
            "eps": self.eps,
            "xi": self.xi,
            "t_stop": self.t_stop,
            "t_end": self.t_end,
            "kinds": list(self.kinds),
            "post": post,
            "outcome": self.outcome,
            "seconds": self.seconds,
        }


def _tip_velocity_of(d: dict) -> np.ndarray:
    beta = d["psi"] + d["varphi"]
    return np.array([d["eta"] * math.cos(beta), d["eta"] * math.sin(beta), d["w"]])


def limit_run(
    state: SlipState,
    mu: float,
    alpha: float,
    *,
    eps: float,
    xi: float,
    horizon: float,
    gap: float = 0.0,
    gap_rate: float = 0.0,
    stop_at=("contact_end",),
) -> LimitRun:
    """The compliant rod (``crosscheck.engines.compliant.integrate``, Kelvin-Voigt) from ``state`` until its first contact end (or ``horizon``)."""
    import time

    from crosscheck.engines.compliant import integrate

    t0 = time.perf_counter()
    tr = integrate(
        Rod.scaled(alpha), state, mu, horizon=horizon, eps=eps, xi=xi, gap=gap, gap_rate=gap_rate, stop_at=set(stop_at)
    )
    seconds = time.perf_counter() - t0
    end = next((e for e in tr.events if e.kind == "contact_end"), None)
    post = None
    if end is not None:
        post = dict(tr.state_at(end.time))
        post["u"] = _tip_velocity_of(post)
    return LimitRun(
        eps=float(eps),
        xi=float(xi),
        t_stop=float(tr.slip_stop_time),
        t_end=math.nan if end is None else float(end.time),
        kinds=tuple(e.kind for e in tr.events),
        post=post,
        seconds=seconds,
    )


def impact_tip_velocity(imp: Impact) -> np.ndarray:
    """The tip velocity (world x, y, z) [l omega] after an ``Impact``."""
    rod = Rod.scaled(imp.alpha)
    q, _ = to_generalized(rod, imp.state)
    return tip_velocity(rod, q, imp.v_after)


def post_errors(run: LimitRun, imp: Impact) -> dict:
    """|compliant - rigid| after the impulse: Theta, Psi, the tip velocity (slip speed and direction, and w) and their maximum."""
    if run.post is None:
        return {"Theta": math.nan, "Psi": math.nan, "u": math.nan, "w": math.nan, "max": math.nan}
    du = run.post["u"] - impact_tip_velocity(imp)
    e = {
        "Theta": abs(run.post["Theta"] - imp.Theta),
        "Psi": abs(run.post["Psi"] - imp.Psi),
        "u": float(np.linalg.norm(du[:2])),
        "w": abs(du[2]),
    }
    e["max"] = max(e.values())
    return e


def jam_state_past(state: SlipState, mu: float, alpha: float, *, depth: float = 1e-9) -> SlipState:
    """``state`` (at or near p = 0) moved in theta to eq. p = -depth: the limit p -> 0- of the rigid impulse (``crosscheck.theory.impact.darboux_keller``
    needs p <= 0; at a GB point the slipping flow stops at a distance 1e-7 from b = p = 0)."""

    def p_of(th):
        return float(analytic.p(th, state.varphi, mu, alpha))

    th = state.theta
    for _ in range(20):
        h = 1e-7
        dp = (p_of(th + h) - p_of(th - h)) / (2 * h)
        step = (p_of(th) + depth) / dp
        th -= step
        if abs(step) < 1e-15:
            break
    return SlipState(theta=th, varphi=state.varphi, Theta=state.Theta, Psi=state.Psi, eta=state.eta, psi=state.psi)


# ---------------------------------------------------------------------------------------------------- studies ---


def inconsistent_study(state: SlipState, mu: float, alpha: float, *, xi: float, eps_values) -> dict:
    """Slip-stop times and post-event states of the compliant rod from an inconsistent start (p < 0, b < 0) as eps -> 0.

    Returns a JSON-able dict: the fast limit, the derived coefficient 1/lambda
    and offset, C1 and C2 (``time_corrections``), per eps the measured t_stop/eps,
    the prediction, the post-event errors against the limit impact, the
    fitted slope of t_stop/eps against ln(1/eps), the observed order of the
    post-event error and that of the impulse's end time t_end (the error's
    derived scale: the O(1) dynamics drift over the time the compliant
    impulse lags the rigid one).
    """
    fast = fast_limit(state, mu, alpha, xi=xi)
    C1, C2 = time_corrections(fast)
    rows = []
    for eps in eps_values:
        r = limit_run(
            state,
            mu,
            alpha,
            eps=eps,
            xi=xi,
            horizon=min(5.0, eps * (fast.coefficient * math.log(1 / eps) + abs(fast.offset) + 100.0)),
        )
        T = r.t_stop / eps
        rows.append(
            {
                **r.as_dict(),
                "T": T,
                "predicted": fast.coefficient * math.log(1 / eps) + fast.offset,
                "correction": C1 * eps * T + C2 * eps * T * T,
                "errors": post_errors(r, fast.impact),
            }
        )
    eps_a = np.array([x["eps"] for x in rows])
    slope, intercept = fit_log_slope(eps_a, [x["T"] for x in rows])
    errs = [x["errors"]["max"] for x in rows]
    # the impulse ends at t_end = O(eps ln(1/eps)) after the rigid one: the O(1) dynamics drift by that much
    t_end = [x["t_end"] for x in rows]
    return {
        "state": state.as_dict(),
        "mu": mu,
        "alpha": alpha,
        "xi": xi,
        "fast": fast.as_dict(),
        "C1": C1,
        "C2": C2,
        "rows": rows,
        "slope": slope,
        "intercept": intercept,
        "post_order": fit_power(eps_a, errs) if len(rows) > 1 else math.nan,
        "t_end_order": fit_power(eps_a, t_end) if len(rows) > 1 else math.nan,
    }


def indeterminate_study(
    state: SlipState, mu: float, alpha: float, *, xi: float, eps: float, D0: float, offsets, horizon: float = 1.0
) -> dict:
    """Starts a relative distance ``offsets`` (in gap rate) from ``indeterminate_boundary``: positive offsets move outwards (predicted
    lift-off), negative inwards (predicted impact)."""
    gap, rate = indeterminate_boundary(state, mu, alpha, xi=xi, eps=eps, D0=D0)
    p, b = (
        float(analytic.p(state.theta, state.varphi, mu, alpha)),
        float(analytic.b(state.Psi, state.Theta, state.theta)),
    )
    lam, lam2 = growth_rates(p, xi)
    scale = abs(rate)
    rows = []
    for off in offsets:
        gr = rate + off * scale
        r = limit_run(
            state,
            mu,
            alpha,
            eps=eps,
            xi=xi,
            horizon=horizon,
            gap=gap,
            gap_rate=gr,
            stop_at=("contact_end", "slip_stop"),
        )
        rows.append({"offset": off, "gap_rate": gr, "predicted": "liftoff" if off > 0 else "impact", **r.as_dict()})
    return {
        "state": state.as_dict(),
        "mu": mu,
        "alpha": alpha,
        "xi": xi,
        "eps": eps,
        "D0": D0,
        "p": p,
        "b": b,
        "lambda": lam,
        "lambda_2": lam2,
        "gap": gap,
        "gap_rate_boundary": rate,
        "rows": rows,
    }


def jam_study(
    state: SlipState, mu: float, alpha: float, *, xi: float, eps_values, t_max: float = 2.0, after: float = 0.3
) -> dict:
    """A state that slips into p = 0 with b < 0 (Corollary 4.2) or into a GB point: the compliant slip stop against the rigid jam time
    and the post-event state against the limit impact, as eps -> 0.

    The rigid reference: ``slip_until_event`` to its JAM (or GB) at t_jam,
    then at a Corollary jam the fast limit from the jam state (the impact
    with the restitution the law implies there, ``fast_limit``); at a GB point
    (b = p = 0, where the impulse path keeps u_n = 0 while slipping and the
    fast problem has no growth) the plastic impact (e = 0) at p -> 0-.
    """
    r = slip_until_event(state, mu, alpha, t_max=t_max)
    if r.outcome not in (Outcome.JAM, Outcome.GB):
        raise ValueError(
            f"state must slip into a jam or a GB point; its first event is {r.outcome.name} at t = {r.time:.6g}"
        )
    jam = jam_state_past(r.state, mu, alpha)
    if r.outcome == Outcome.JAM:
        fast = fast_limit(
            r.state if float(analytic.p(r.state.theta, r.state.varphi, mu, alpha)) <= 1e-12 else jam, mu, alpha, xi=xi
        )
        imp, e, fd = fast.impact, fast.restitution, fast.as_dict()
    else:
        imp, e, fd = impact(jam, mu, alpha, restitution=0.0), 0.0, None
    rows = []
    for eps in eps_values:
        run = limit_run(state, mu, alpha, eps=eps, xi=xi, horizon=r.time + after)
        rows.append({**run.as_dict(), "lag": run.t_stop - r.time, "errors": post_errors(run, imp)})
    eps_a = np.array([x["eps"] for x in rows])
    lag = np.array([x["lag"] for x in rows])
    err = np.array([x["errors"]["max"] for x in rows])
    ok = np.isfinite(lag) & (lag != 0)
    return {
        "state": state.as_dict(),
        "mu": mu,
        "alpha": alpha,
        "xi": xi,
        "event": r.outcome.name,
        "t_jam": r.time,
        "jam_state": r.state.as_dict(),
        "b": r.b,
        "p": r.p,
        "restitution": e,
        "fast": fd,
        "iwc": {
            "Theta": imp.Theta,
            "Psi": imp.Psi,
            "eta": imp.eta,
            "varphi": imp.varphi,
            "w": imp.w,
            "u": impact_tip_velocity(imp).tolist(),
        },
        "rows": rows,
        "lag_order": fit_power(eps_a[ok], lag[ok]) if ok.sum() > 1 else math.nan,
        "post_order": fit_power(eps_a[np.isfinite(err)], err[np.isfinite(err)])
        if np.isfinite(err).sum() > 1
        else math.nan,
    }
