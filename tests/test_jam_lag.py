"""The slip stop of a spring contact after a Corollary 4.2 jam: Painleve I's pole and the comparison that uses it (the compliant rod's lag
against it: ``tests/test_compliant_limit.py``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from crosscheck import Rod, engines
from crosscheck.engines.compliant import integrate
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.studies.comparison import LAG_STEPS, LAG_TAU, comparison_window, event_lag, jam_lag, jam_scale
from crosscheck.theory import analytic
from crosscheck.theory.jam_lag import contact_time_at, inner_pole, inner_scale, jam_stiffness, spring_jam_lag
from crosscheck.theory.slipping import slip_until_event

ALPHA = 3.0


def test_the_inner_pole_is_painleve_one_tritronquee_pole():
    # q = 12^(3/5) y, s = 12^(1/5) x maps q'' = s + q^2/2 to y'' = 6 y^2 + x, whose tritronquee solution
    # (y ~ -sqrt(-x/6) as x -> -inf) has its first real pole at x = 2.3841687 (Joshi & Kitaev 2001)
    assert abs(inner_pole() / 12**0.2 - 2.3841687) < 1e-6


def test_jam_stiffness_is_minus_dp_dP_along_the_impulse():
    """k against a finite difference of eq. p along the slip direction's turn d varphi / dP (darboux_keller's rate)."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        theta, varphi, eta, mu = (
            rng.uniform(0.2, 1.4),
            rng.uniform(-3.0, -0.1),
            rng.uniform(0.2, 3.0),
            rng.uniform(0.5, 3.0),
        )
        s, c = math.sin(theta), math.cos(theta)
        turn = ALPHA * c * math.cos(varphi) * (mu * c * math.sin(varphi) - s) / eta  # d varphi / dP
        h = 1e-6
        dp = (analytic.p(theta, varphi + h * turn, mu, ALPHA) - analytic.p(theta, varphi - h * turn, mu, ALPHA)) / (
            2 * h
        )
        assert jam_stiffness(theta, varphi, eta, mu, ALPHA) == pytest.approx(-dp, rel=1e-6, abs=1e-9)


def test_no_inner_scale_without_a_corollary_jam():
    assert math.isnan(inner_scale(0.3, 1.0))  # b > 0: not a jam
    assert math.isnan(inner_scale(-0.3, 0.0))  # planar section: p does not move with the impulse
    assert inner_scale(-0.5, 2.0) == pytest.approx(1.0)
    assert spring_jam_lag(1e-3, math.nan) == 0.0 and spring_jam_lag(0.0, 1.0) == 0.0


def test_a_jam_gives_a_spring_contact_its_lag_and_mujoco_none():
    state = SlipState(theta=1.1208333333333333, varphi=-1.9, Theta=-0.375, Psi=0.0, eta=1.0)
    first = slip_until_event(state, 1.4, ALPHA, t_max=2.0)
    assert first.outcome == Outcome.JAM
    scale = jam_scale(first.x[-1], 1.4, ALPHA)
    drake = engines.get("drake_continuous").options(stiffness=1e7)
    lag = jam_lag(drake, scale)
    assert lag == pytest.approx(inner_pole() * scale * drake.contact_time**0.8) and lag > LAG_TAU * drake.contact_time
    _, window, _ = comparison_window(
        Outcome.JAM, first.time, 2.0, contact_time=drake.contact_time, timestep=drake.timestep, spring_jam=lag
    )
    assert window == lag
    # other events keep LAG_TAU contact times; MuJoCo's impedance feeds the rigid force forward: no spring lag
    _, window, _ = comparison_window(
        Outcome.LIFTOFF, first.time, 2.0, contact_time=drake.contact_time, timestep=drake.timestep, spring_jam=lag
    )
    assert (
        window
        == event_lag(drake.contact_time, drake.timestep)
        == max(LAG_TAU * drake.contact_time, LAG_STEPS * drake.timestep)
    )
    assert jam_lag(engines.get("mujoco").options(), scale) == 0.0
    assert np.array_equal(jam_lag(drake, np.array([scale, np.nan])), [lag, 0.0])


def test_the_maps_analytic_events_carry_each_jams_inner_scale_and_nan_elsewhere():
    """``analytic_events`` gives every JAM start its (k |b|)^(-1/5) at the theory's jam state (the lag the agreement study
    allows a spring contact there) and every other start NaN."""
    from crosscheck.studies.analytic_events import analytic_events

    theta = np.array([1.1208333333333333, 1.0125, 0.4, 1.2])
    points = {
        "theta": theta,
        "varphi": np.full(4, -1.9),
        "Theta": np.array([-0.375, -0.375, 0.3, 0.9]),
        "Psi": np.zeros(4),
        "eta": np.ones(4),
        "mu": np.array([1.4, 1.4, 0.5, 1.4]),
    }
    a = analytic_events(points, alpha=ALPHA, horizon=2.0)
    assert (a.outcome == Outcome.JAM).sum() >= 2 and (a.outcome != Outcome.JAM).any()
    for i in range(4):
        s = SlipState(theta=theta[i], varphi=-1.9, Theta=points["Theta"][i], Psi=0.0, eta=1.0)
        r = slip_until_event(s, points["mu"][i], ALPHA, t_max=2.0)
        if a.outcome[i] == Outcome.JAM:
            assert a.jam_scale[i] == jam_scale(r.x[-1], points["mu"][i], ALPHA) and np.isfinite(a.jam_scale[i])
        else:
            assert np.isnan(a.jam_scale[i])


@pytest.mark.parametrize("p", [1.0, 0.2])
def test_an_undamped_spring_contact_rings_with_period_two_pi_eps_over_root_p(p):
    """The compliant rod (xi = 0) slipping on the planar section from zero penetration at eq. p = p: its normal force
    oscillates about -b/p with period 2 pi eps / p^(1/2), the contact time eps over p^(1/2) of ``contact_time_at``.
    2 %: the slow state (eta, theta, so p) moves during the period, measured 0.5 % at p = 0.2 and eps = 1e-3."""
    mu, alpha, eps = 1.3, 3.0, 1e-3
    low = minimize_scalar(lambda t: analytic.p(t, -math.pi / 2, mu, alpha), bounds=(0.1, 1.5), method="bounded").x
    theta = brentq(lambda t: analytic.p(t, -math.pi / 2, mu, alpha) - p, 0.05, low)
    want = 2 * math.pi * eps * contact_time_at(p)
    tr = integrate(
        Rod.scaled(alpha),
        SlipState(theta=theta, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0),
        mu,
        horizon=3 * want,
        eps=eps,
        xi=0.0,
        max_step=eps / 20,
    )
    t = np.linspace(0.0, 3 * want, 20001)
    F = np.interp(t, tr.t, tr.normal_force)
    peaks = t[1:-1][(F[1:-1] > F[:-2]) & (F[1:-1] >= F[2:])]
    assert len(peaks) >= 2
    assert abs((peaks[1] - peaks[0]) / want - 1) < 0.02, (peaks[:3], want)
