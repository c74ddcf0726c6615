"""slip_until_event: the desingularised slipping flow (eq. f) run to its first event."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from crosscheck import Outcome, SlipState
from crosscheck.theory import analytic
from crosscheck.theory.critical import mu_C, mu_P, theta_12
from crosscheck.theory.slipping import X_STATE, slip_outcomes, slip_until_event
from crosscheck.tolerances import EVENT_TIME, GB_REACHED

ALPHA = 3.0
HALF_PI = math.pi / 2


def real_time_run(state: SlipState, mu, alpha, *, t_max=20.0, event="b"):
    """Reference: eq. polareqs_varphi in real time with F_z = normal_force, stopped at b = 0 or eta = 0.

    Regular as long as p stays away from 0, which the cases below do (p > 0.5).
    """
    y0 = np.array([0, 0, 0, state.psi, state.theta, state.eta, state.varphi, 0, state.Psi, state.Theta], float)

    def rhs(t, y):
        fz = analytic.normal_force(y[8], y[9], y[4], y[6], mu, alpha)
        return analytic.scaled_rhs(y, fz, mu, alpha)

    g = {"b": lambda t, y: analytic.b(y[8], y[9], y[4]), "eta": lambda t, y: y[5]}[event]
    g.terminal, g.direction = True, (+1 if event == "b" else -1)
    sol = solve_ivp(rhs, (0, t_max), y0, method="DOP853", rtol=1e-11, atol=1e-13, events=[g])
    assert sol.status == 1, "reference run found no event"
    return sol.t_events[0][0], sol.y_events[0][0]


# (name, state, mu): p stays > 0.5 along these, so the real-time problem is regular
LIFTOFF_CASES = [
    ("planar", SlipState(theta=0.5, varphi=-HALF_PI, Theta=1.3, Psi=0.0, eta=1.0), 0.5),
    ("spinning", SlipState(theta=0.6, varphi=-0.5, Theta=0.5, Psi=1.4, eta=1.0), 0.3),
    ("oblique", SlipState(theta=0.8, varphi=-1.2, Theta=1.0, Psi=0.8, eta=1.0), 0.5),
]
STICK_CASES = [
    ("planar", SlipState(theta=0.5, varphi=-HALF_PI, Theta=0.0, Psi=0.0, eta=0.3), 1.0),
    ("spinning", SlipState(theta=0.7, varphi=-2.0, Theta=0.2, Psi=0.3, eta=0.3), 1.0),
]


@pytest.mark.parametrize("name, state, mu", LIFTOFF_CASES, ids=[c[0] for c in LIFTOFF_CASES])
def test_liftoff_time_and_state_match_real_time_integration(name, state, mu):
    r = slip_until_event(state, mu, ALPHA, t_max=20.0)
    assert r.outcome is Outcome.LIFTOFF and r.reason == "b=0"
    t_ref, y_ref = real_time_run(state, mu, ALPHA)
    assert EVENT_TIME.ok(r.time, t_ref), (r.time, t_ref)
    # same state at the event: (psi, theta, eta, varphi, Psi, Theta) of SCALED_STATE
    got = [r.state.psi, r.state.theta, r.state.eta, r.state.varphi, r.state.Psi, r.state.Theta]
    assert EVENT_TIME.ok(got, y_ref[[3, 4, 5, 6, 8, 9]])
    assert abs(r.b) <= 1e-12 and r.p > 0.5


@pytest.mark.parametrize("name, state, mu", STICK_CASES, ids=[c[0] for c in STICK_CASES])
def test_stick_time_matches_real_time_integration(name, state, mu):
    r = slip_until_event(state, mu, ALPHA, t_max=20.0)
    assert r.outcome is Outcome.STICK and r.state.eta == 0.0
    t_ref, y_ref = real_time_run(state, mu, ALPHA, event="eta")
    assert EVENT_TIME.ok(r.time, t_ref), (r.time, t_ref)
    assert EVENT_TIME.ok([r.state.theta, r.state.Theta, r.state.Psi], y_ref[[4, 9, 8]])


def test_planar_problem_is_an_invariant_manifold():
    # remark rem:3d22d: Psi = 0, varphi = -pi/2 stays so (up to cos(-pi/2) = 6e-17 rounding)
    th1 = float(theta_12(1.4, ALPHA)[0])
    state = SlipState(theta=th1 - 0.05, varphi=-HALF_PI, Theta=0.9, Psi=0.0, eta=1.0)
    r = slip_until_event(state, 1.4, ALPHA, t_max=20.0)
    assert len(r.t) > 3
    x = dict(zip(X_STATE, r.x.T))
    assert np.max(np.abs(x["varphi"] + HALF_PI)) < 1e-12
    assert np.max(np.abs(x["Psi"])) < 1e-12
    assert np.all(np.diff(r.t) > 0)  # p > 0 while slipping: s and t run the same way


def _near_P_plus(mu, omegas, *, r=1e-2):
    """Planar slipping starts at (p, b) = r (cos omega, sin omega) from P+ = (theta_1, sqrt(csc theta_1)).

    (p, b) -> (theta, Theta) by the linearisation p = p_theta dtheta, b = b_theta dtheta + b_Theta dTheta
    (eqs. p, b at varphi = -pi/2, Psi = 0); omega in (-pi/2, 0) is the slipping quadrant p > 0 > b.
    """
    th1 = float(theta_12(mu, ALPHA)[0])
    Th = math.sqrt(1 / math.sin(th1))
    p_th = ALPHA * (-mu * math.cos(2 * th1) - math.sin(2 * th1))
    b_th, b_Th = Th**2 * math.cos(th1), 2 * Th * math.sin(th1)
    out = []
    for w in omegas:
        dth = r * math.cos(w) / p_th
        out.append(
            SlipState(
                theta=th1 + dth, varphi=-HALF_PI, Theta=Th + (r * math.sin(w) - b_th * dth) / b_Th, Psi=0.0, eta=1.0
            )
        )
    return out


def _strong_direction(mu):
    """Angle in the (p, b) plane of e_1 = (3 tan^2 theta_1 - (1 + alpha), 1), eq. evecK2D, taken in p > 0."""
    th1 = float(theta_12(mu, ALPHA)[0])
    e11 = 3 * math.tan(th1) ** 2 - (1 + ALPHA)
    return math.atan2(-1.0, -e11)


@pytest.mark.parametrize("mu", [1.40, 1.50])
def test_or_theorem_planar_lift_off_before_P_plus_below_mu_C(mu):
    # Or (2012) Theorem 1 / Genot-Brogliato: for mu in (mu_P, mu_C] slipping near P+ ends in lift-off.
    # e_1 (weak) lies in the first quadrant: every slipping orbit turns towards it and crosses b = 0.
    # (Starts within ~0.3 rad of the strong b-axis come within GB_REACHED of P+ first: a resolution limit.)
    assert mu_P(ALPHA) < mu <= mu_C(ALPHA)
    omegas = np.random.default_rng(1).uniform(-HALF_PI + 0.35, -0.02, size=8)
    outcomes, times = slip_outcomes(_near_P_plus(mu, omegas), mu, ALPHA, t_max=10.0)
    assert np.all(outcomes == Outcome.LIFTOFF), outcomes
    assert np.all(times > 0)


@pytest.mark.parametrize("mu", [1.6, 1.7, 2.5])
def test_or_theorem_planar_P_plus_reached_in_finite_time_above_mu_C(mu):
    # mu > mu_C: e_1 (now strong) lies in the fourth quadrant and is the separatrix: slipping orbits
    # between the -b axis (weak e_2) and e_1 reach P+ in finite time; those between e_1 and +p lift off.
    assert mu > mu_C(ALPHA)
    w_strong = _strong_direction(mu)
    assert -HALF_PI < w_strong < 0
    rng = np.random.default_rng(2)
    th1 = float(theta_12(mu, ALPHA)[0])
    for s in _near_P_plus(mu, rng.uniform(-HALF_PI + 0.02, w_strong - 0.05, size=6)):
        r = slip_until_event(s, mu, ALPHA, t_max=10.0)
        assert r.outcome is Outcome.GB, r
        assert 0 < r.time < 0.01  # finite (and short: the start is 1e-2 from P+)
        # on the disc's edge up to the event root finder (brentq, xtol 4 eps in s)
        assert math.hypot(r.p, r.b) == pytest.approx(GB_REACHED.atol, rel=1e-6)
        assert abs(r.state.theta - th1) < 1e-6 and abs(r.state.Theta - math.sqrt(1 / math.sin(th1))) < 1e-6
    outcomes, _ = slip_outcomes(_near_P_plus(mu, rng.uniform(w_strong + 0.05, -0.02, size=6)), mu, ALPHA)
    assert np.all(outcomes == Outcome.LIFTOFF), outcomes


def test_jam_away_from_planar_section():
    # eq. pdotarg: on p = 0 with b < 0 and varphi != -pi/2, p decreases, so a start just
    # outside the Painleve region with the rod at rest in Theta reaches p = 0 (inconsistency).
    mu, varphi = 1.4, -1.8
    theta_minus = float(analytic.theta_pm(varphi, mu, ALPHA)[0])
    state = SlipState(theta=theta_minus - 0.01, varphi=varphi, Theta=0.0, Psi=0.0, eta=1.0)
    assert analytic.p(state.theta, varphi, mu, ALPHA) > 0
    r = slip_until_event(state, mu, ALPHA, t_max=10.0)
    assert r.outcome is Outcome.JAM and r.reason == "p=0"
    assert abs(r.p) < 1e-10 and r.b < -0.5 and 0 < r.time < 1.0


@pytest.mark.parametrize(
    "state, mu, outcome",
    [
        (SlipState(theta=0.6, varphi=-1.0, Theta=2.0, Psi=0.0, eta=1.0), 0.5, Outcome.LIFTOFF),  # b > 0, p > 0
        (SlipState(theta=1.0, varphi=-HALF_PI, Theta=0.0, Psi=0.0, eta=1.0), 1.4, Outcome.JAM),  # b < 0, p < 0
        (SlipState(theta=1.0, varphi=-HALF_PI, Theta=1.5, Psi=0.0, eta=1.0), 1.4, Outcome.LIFTOFF),  # b, -p > 0
        # at rest, held by friction: |F_j| / F_n = 0.715 <= mu (at mu 0.5 it slips: test_a_start_at_rest_...)
        (SlipState(theta=0.6, varphi=-1.0, Theta=0.0, Psi=0.0, eta=0.0), 0.8, Outcome.STICK),
    ],
    ids=["liftoff-mode", "inconsistent", "indeterminate", "eta=0"],
)
def test_start_outside_slipping_returns_at_once(state, mu, outcome):
    r = slip_until_event(state, mu, ALPHA)
    assert (r.outcome, r.time, r.reason, r.state) == (outcome, 0.0, "start", state)


def test_start_on_gb_point_is_gb_at_time_zero():
    th1 = float(theta_12(1.7, ALPHA)[0])
    state = SlipState(theta=th1, varphi=-HALF_PI, Theta=math.sqrt(1 / math.sin(th1)), Psi=0.0, eta=1.0)
    r = slip_until_event(state, 1.7, ALPHA)
    assert (r.outcome, r.time) == (Outcome.GB, 0.0)


def test_horizon_gives_slip_at_t_max():
    state = SlipState(theta=0.5, varphi=-HALF_PI, Theta=0.0, Psi=0.0, eta=0.3)  # sticks at t = 1.04
    r = slip_until_event(state, 1.0, ALPHA, t_max=0.5)
    assert (r.outcome, r.reason, r.time) == (Outcome.SLIP, "t_max", 0.5)
    assert r.t[-1] == pytest.approx(0.5, abs=1e-12)


def test_leaving_varphi_range_stops_with_slip_on_the_boundary():
    # a spinning rod falling flat: its relative slip angle sweeps down to -pi
    state = SlipState(theta=0.6, varphi=-1.0, Theta=0.0, Psi=1.5, eta=1.0)
    r = slip_until_event(state, 0.8, ALPHA, t_max=20.0)
    assert (r.outcome, r.reason) == (Outcome.SLIP, "varphi=-pi")
    assert -math.pi < r.state.varphi < -math.pi + 1e-9


@pytest.mark.parametrize(
    "kw, message",
    [
        ({"mu": -1.0}, "mu must be in [0, 1000]; got -1.0"),
        ({"alpha": 0.0}, "alpha must be in [0.001, 1000]; got 0.0"),
        ({"t_max": 0.0}, "t_max must be in (0, 10000]; got 0.0"),
    ],
)
def test_bad_input_raises(kw, message):
    args = {"mu": 1.0, "alpha": 3.0, "t_max": 1.0} | kw
    state = SlipState(theta=0.5, varphi=-1.0, Theta=0.0, Psi=0.0, eta=1.0)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
        slip_until_event(state, args["mu"], args["alpha"], t_max=args["t_max"])


def test_a_start_on_b_0_with_b_decreasing_is_integrated():
    """b = 0 exactly (computed 0.0) with p > 0 and b decreasing: the start rule lifts off only for b > 0, so the run slips
    (the tip stays on the plane: b < 0 at once) until theta reaches 0.  A rule b >= 0 would call it LIFTOFF at t = 0."""
    state = SlipState(theta=0.2, varphi=-1.0, Theta=-2.2435439705234983, Psi=0.0, eta=1.0)
    assert (
        analytic.b(state.Psi, state.Theta, state.theta) == 0.0 and analytic.p(state.theta, state.varphi, 1.0, 3.0) > 0
    )
    r = slip_until_event(state, 1.0, 3.0)
    assert (r.outcome, r.reason) == (Outcome.SLIP, "theta=0") and r.time == pytest.approx(0.0887, abs=1e-4)
    assert r.t.size > 2 and np.all(r.x[1:, 0] > 0)  # integrated, not decided at the start
