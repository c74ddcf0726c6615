"""Slipping states that reach p = 0 with b < 0 (Corollary 4.2), built backwards from the jam.

The rigid rod jams where it slips into p = 0 with b < 0: no slipping solution
exists beyond (Corollary 4.2), and the paper's text recalls the classical way
out, impact without collision.  On the planar section varphi = -pi/2 the
crossing happens only at b = 0 (the GB manifold), so these jams are a 3-D
mechanism.  ``corollary_states`` picks points of p = 0 off the planar
section, runs the slipping flow (eq. f) backwards from them and keeps the
starts whose forward run (``slip_until_event``) jams where it was built to:
test states with a known analytic jam for every contact engine.

Scaled units (section 2.1).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import ALPHA, HORIZON, MU, check, integer
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.theory.critical import mu_P, theta_pm
from crosscheck.theory.slipping import slip_rhs, slip_until_event

__all__ = ["backward_from", "corollary_states"]


def backward_from(x_event: np.ndarray, mu: float, alpha: float, t_back: float):
    """Integrate the slipping flow (eq. f, with dt/ds = eta p) backwards from ``x_event`` for real time ``t_back``.

    Returns the state (eta, varphi, psi, Psi, theta, Theta) at t = -t_back, or
    None when the backward run meets b = 0, eta -> 0 or a domain boundary
    first (then the forward run would not slip all the way to the event).
    """

    def rhs(_, y):
        eta, varphi, theta = y[0], y[1], y[4]
        st, ct = math.sin(theta), math.cos(theta)
        p = 1.0 + alpha + alpha * st * (mu * ct * math.sin(varphi) - st)
        return np.append(-slip_rhs(y[:6], mu, alpha), eta * p)  # s reversed; y[6] = real time run backwards

    def event(fn):
        fn.terminal = True
        return fn

    def b_of(y):
        st, ct = math.sin(y[4]), math.cos(y[4])
        return (y[3] ** 2 * ct * ct + y[5] ** 2) * st - 1.0

    events = [
        event(lambda s, y: y[6] - t_back),
        event(lambda s, y: b_of(y)),
        event(lambda s, y: y[0] - 1e-3),
        event(lambda s, y: y[1]),
        event(lambda s, y: y[1] + math.pi),
        event(lambda s, y: y[4] - 1e-3),
        event(lambda s, y: math.pi / 2 - 1e-3 - y[4]),
    ]
    sol = solve_ivp(rhs, (0.0, 1e4), np.append(x_event, 0.0), method="DOP853", rtol=1e-10, atol=1e-12, events=events)
    if sol.status != 1 or not len(sol.t_events[0]) or any(len(te) for te in sol.t_events[1:]):
        return None
    return sol.y_events[0][0][:6]


def corollary_states(
    mu: float,
    n: int,
    rng: np.random.Generator,
    *,
    alpha: float = 3.0,
    horizon: float = 2.0,
    t_range: tuple[float, float] = (0.2, 1.5),
    min_offplane: float = 0.1,
    max_b: float = -0.1,
    max_tries: int = 20_000,
) -> tuple[list[SlipState], np.ndarray, np.ndarray]:
    """Slipping states the theory sends to p = 0 with b < 0 (Corollary 4.2), away from varphi = -pi/2.

    Built from the event backwards: a point of p = 0 (theta = theta_-+(varphi),
    eq. thetastar) with |varphi + pi/2| >= ``min_offplane`` (the 3-D mechanism:
    on varphi = -pi/2, p = 0 is crossed only at b = 0), Theta ~ U(-2, 2),
    Psi ~ U(-3, 3), eta ~ U(0.3, 3) and b <= ``max_b`` (clear of the GB
    manifold); by eq. pdotarg every such point is crossed from p > 0 into
    p < 0.  The slipping flow is run backwards for a time ~ U(t_range) (after
    the soft contact's build-up, before the horizon), and the start is kept
    when ``slip_until_event`` from it ends in JAM in ``t_range`` with the same
    conditions at its event.

    Returns:
      (states, analytic jam times (n,), varphi at the jam (n,)).

    Raises:
      ValueError: mu <= mu_P*(varphi) for every allowed varphi, or fewer than
        n states in ``max_tries`` attempts.
    """
    mu = float(check("mu", mu, MU))
    alpha = float(check("alpha", alpha, ALPHA))
    n = integer("n", n, 1, 100_000)
    horizon = float(check("horizon", horizon, HORIZON))
    if not isinstance(rng, np.random.Generator):
        raise ValueError(
            f"rng must be a numpy.random.Generator (numpy.random.default_rng(seed)); got {type(rng).__name__}"
        )
    ratio = 2.0 * math.sqrt(1.0 + alpha) / (alpha * mu)  # |sin varphi| must exceed this (eq. mup)
    half = math.acos(ratio) if ratio < 1 else 0.0
    if half <= min_offplane:
        raise ValueError(
            f"no p = 0 crossing with |varphi + pi/2| >= {min_offplane} at mu = {mu:g} (mu_P = {float(mu_P(alpha)):.4g})"
        )
    found, times, varphis = [], [], []
    for _ in range(max_tries):
        off = rng.uniform(min_offplane, half) * rng.choice((-1.0, 1.0))
        varphi = -math.pi / 2 + off
        theta = float(theta_pm(varphi, mu, alpha)[int(rng.integers(2))])
        Theta, Psi, eta = rng.uniform(-2, 2), rng.uniform(-3, 3), rng.uniform(0.3, 3.0)
        if (
            not (1e-3 < theta < math.pi / 2 - 1e-3)
            or (Psi**2 * math.cos(theta) ** 2 + Theta**2) * math.sin(theta) - 1 > max_b
        ):
            continue
        x0 = backward_from(np.array([eta, varphi, 0.0, Psi, theta, Theta]), mu, alpha, rng.uniform(*t_range))
        if x0 is None:
            continue
        s = SlipState(theta=x0[4], varphi=x0[1], Theta=x0[5], Psi=x0[3], eta=x0[0])
        r = slip_until_event(s, mu, alpha, t_max=horizon)
        if (
            r.outcome == Outcome.JAM
            and t_range[0] <= r.time <= t_range[1]
            and r.b <= max_b
            and abs(r.state.varphi + math.pi / 2) >= min_offplane
        ):
            found.append(s)
            times.append(r.time)
            varphis.append(r.state.varphi)
            if len(found) == n:
                return found, np.array(times), np.array(varphis)
    raise ValueError(f"found only {len(found)} of {n} Corollary 4.2 states at mu = {mu:g} in {max_tries} attempts")
