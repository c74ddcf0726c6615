"""The rod pivoting about its stuck tip (crosscheck.theory.sticking) and the hybrid model through it (crosscheck.theory.impact.continuation):
closed forms against eq. linode2 and eq. rotode, invariants, the modes at rest, and stick -> slip, slip -> stick and rest -> lift-off
against the rigid engine as dt -> 0."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck import Outcome, Rod, SlipState
from crosscheck.engines import get
from crosscheck.engines.pinocchio.studies.rigid import order
from crosscheck.theory import analytic
from crosscheck.theory.impact.continuation import StickSegment, run
from crosscheck.theory.impact.darboux_keller import delassus
from crosscheck.theory.sticking import SLIP_ONSET_SPEED, at_rest, stick_force, stick_rates, stick_until_event
from crosscheck.tolerances import CLOSED_FORM

ALPHA = 3.0
TIMESTEPS = (1e-3, 3e-4, 1e-4)
#: A resting rod that pivots, then slips outwards (varphi = -pi/2) when its friction ratio reaches mu = 0.3 at t = 0.1744.
STICK_THEN_SLIP = (SlipState(theta=1.2, varphi=-math.pi / 2, Theta=-0.3, Psi=0.5, eta=0.0, psi=0.4), 0.3)
#: The same rod slipping slowly at mu = 0.6: its slip stops at t = 0.038 and it sticks (until t = 1.11).
SLIP_THEN_STICK = (SlipState(theta=1.2, varphi=-math.pi / 2, Theta=-0.3, Psi=0.5, eta=0.05, psi=0.4), 0.6)
#: IC1 (the paper's example of an impact without collision): after the impulse the tip is at rest with b > 0.
IC1 = (SlipState(theta=1.1067, varphi=-1.8913, Theta=0.9, Psi=-0.1027, eta=2.1307), 1.4)


def _world(F, psi):
    i, j = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
    return np.array([*(F[0] * i + F[1] * j), F[2]])


def _random_rest_states(n, seed):
    rng = np.random.default_rng(seed)
    return [
        SlipState(
            theta=rng.uniform(0.05, 1.5),
            varphi=-math.pi / 2,
            Theta=rng.uniform(-2, 2),
            Psi=rng.uniform(-2, 2),
            eta=0.0,
            psi=rng.uniform(-3, 3),
        )
        for _ in range(n)
    ]


def test_the_sticking_force_holds_the_tip_and_gives_the_pivot_equations():
    """stick_force keeps the tip's acceleration (eq. linode2) at 0; with it eq. rotode is stick_rates."""
    rod = Rod.scaled(ALPHA)
    for s in _random_rest_states(50, 1):
        F = _world(stick_force(s.theta, s.Psi, s.Theta, ALPHA), s.psi)
        a = analytic.tip_acceleration(rod, s.psi, s.theta, s.Psi, s.Theta, F)
        assert np.max(np.abs(a)) < 1e-13 * (1 + s.Psi**2 + s.Theta**2)
        theta_dd, psi_dd = analytic.rotational_acceleration(rod, s.psi, s.theta, s.Psi, s.Theta, F)
        Psi_dot, Theta_dot = stick_rates(s.theta, s.Psi, s.Theta, ALPHA)
        assert CLOSED_FORM.ok(Theta_dot, theta_dd) and CLOSED_FORM.ok(Psi_dot, psi_dd)


def test_the_pivoting_rod_keeps_its_energy_and_vertical_momentum():
    s, mu = STICK_THEN_SLIP
    k = stick_until_event(s, mu, ALPHA, t_max=5.0)

    def energy(psi, theta, Psi, Theta):
        return (1 + ALPHA) / (2 * ALPHA) * (Theta**2 + math.cos(theta) ** 2 * Psi**2) + math.sin(theta)

    E = [energy(*y) for y in k.y]
    Lz = [y[2] * math.cos(y[1]) ** 2 for y in k.y]
    assert np.ptp(E) < 1e-9 and np.ptp(Lz) < 1e-9  # DOP853 at rtol 1e-11 over ~20 steps


def test_a_stick_ends_in_slip_before_the_normal_force_vanishes():
    """Where F_n = 0, F_j = -c / ((1 + alpha) s) != 0: the friction ratio diverges first.  At every cone exit of random sticking
    starts (mu up to 1000) F_n > 0 and |F_j| = mu F_n."""
    for th in np.linspace(0.05, 1.5, 30):
        s = math.sin(th)
        W = (1 + ALPHA * s * s) / ((1 + ALPHA) * s)  # F_n = 0
        _, F_j, F_n = stick_force(th, 0.0, math.sqrt(W), ALPHA)
        assert abs(F_n) < 1e-12 and CLOSED_FORM.ok(F_j, -math.cos(th) / ((1 + ALPHA) * s))
    rng = np.random.default_rng(3)
    ends = 0
    for s in _random_rest_states(200, 2):
        mu = float(np.exp(rng.uniform(np.log(0.1), np.log(1000))))
        if at_rest(s, mu, ALPHA).mode != "stick":
            continue
        k = stick_until_event(s, mu, ALPHA, t_max=3.0)
        if k.reason == "cone":
            ends += 1
            assert (
                k.force[2] > 0
                and abs(abs(k.force[1]) - mu * k.force[2]) < 1e-9
                and k.varphi == math.copysign(math.pi / 2, -k.force[1])
            )
    assert ends > 20


def test_a_slip_from_rest_is_consistent():
    """Where sticking would leave the cone or pull and b <= 0, the slip at varphi = -+pi/2 has a_n = 0, no lateral acceleration,
    its friction on the cone's edge opposite the slip, F_n >= 0 and a non-negative acceleration along the slip (eq. linode2)."""
    rod = Rod.scaled(ALPHA)
    seen = set()
    for s in _random_rest_states(300, 5):
        mu = 0.5
        r = at_rest(s, mu, ALPHA)
        seen.add(r.mode)
        if r.mode == "liftoff":
            assert r.b > 0
        if r.mode != "slip":
            continue
        u_hat = np.array([math.cos(s.psi + r.varphi), math.sin(s.psi + r.varphi)])
        a = analytic.tip_acceleration(rod, s.psi, s.theta, s.Psi, s.Theta, _world(r.force, s.psi))
        scale = 1 + s.Psi**2 + s.Theta**2
        assert abs(a[2]) < 1e-12 * scale and abs(a[0] * u_hat[1] - a[1] * u_hat[0]) < 1e-12 * scale
        assert a[:2] @ u_hat >= -1e-12 * scale and r.force[2] >= 0
        assert CLOSED_FORM.ok(np.hypot(*_world(r.force, s.psi)[:2]), mu * r.force[2])
        assert _world(r.force, s.psi)[:2] @ u_hat <= 0
    assert seen == {"stick", "slip", "liftoff"}


def _engine_errors(state, mu, T):
    """At the engine's row nearest T, per timestep: max |engine - hybrid| over theta, Theta, Psi, eta (the hybrid run to that row's time)."""
    rod = Rod.scaled(ALPHA)
    errs = []
    for dt in TIMESTEPS:
        R = get("pinocchio").simulate(rod, state, mu, horizon=T + 2 * dt, timestep=dt).record
        k = int(round(T / dt))
        h = run(state, mu, ALPHA, horizon=float(R.t[k]))
        last = h.segments[-1]
        ref = last.stick.state if isinstance(last, StickSegment) else last.slip.state
        errs.append(
            max(
                abs(R.theta[k] - ref.theta),
                abs(R.Theta[k] - ref.Theta),
                abs(R.Psi[k] - ref.Psi),
                abs(R.eta[k] - ref.eta),
            )
        )
    return errs


def test_stick_then_slip_against_the_rigid_engine():
    """The pivoting rod (at t = 0.1, stuck) and its slip after the cone exit (at t_slip + 0.4, slipping outwards) tend to the
    engine's at first order in dt; the engine's friction reaches the cone within a step or two of the analytic exit."""
    state, mu = STICK_THEN_SLIP
    h = run(state, mu, ALPHA, horizon=1.0)
    kinds = [type(x).__name__ for x in h.segments]
    assert kinds[:3] == ["Segment", "StickSegment", "Segment"] and h.segments[1].stick.reason == "cone"
    t_slip = h.segments[1].t1
    assert t_slip == pytest.approx(0.1744, abs=1e-4) and h.segments[2].start.varphi == -math.pi / 2
    assert h.segments[2].start.eta == SLIP_ONSET_SPEED
    for T in (0.1, t_slip + 0.4):
        errs = _engine_errors(state, mu, T)
        assert order(TIMESTEPS, errs) == pytest.approx(1.0, abs=0.15) and errs[-1] < 0.5 * TIMESTEPS[-1], (T, errs)
    for dt in TIMESTEPS:
        R = get("pinocchio").simulate(Rod.scaled(ALPHA), state, mu, horizon=t_slip + 0.05, timestep=dt).record
        on_cone = np.hypot(R.force[:, 0], R.force[:, 1]) >= mu * R.force[:, 2] * (1 - 1e-9)
        assert abs(R.t[np.argmax(on_cone)] - t_slip) <= 2 * dt


def test_slip_then_stick_against_the_rigid_engine():
    """The slipping flow's STICK (eta -> 0) hands the rod to the pivot: at t = 0.6 both agree with the engine at first order."""
    state, mu = SLIP_THEN_STICK
    h = run(state, mu, ALPHA, horizon=0.6)
    assert h.segments[0].slip.outcome == Outcome.STICK and h.segments[0].t1 == pytest.approx(0.038, abs=1e-3)
    assert isinstance(h.segments[1], StickSegment) and (h.outcome, h.reason) == (Outcome.STICK, "stick: t_max")
    errs = _engine_errors(state, mu, 0.6)
    assert order(TIMESTEPS, errs) == pytest.approx(1.0, abs=0.15) and errs[-1] < 0.5 * TIMESTEPS[-1], errs


def test_rest_with_b_positive_lifts_off_as_the_rigid_engine_does():
    """IC1's impact without collision leaves the tip at rest with b > 0: sticking would need F_n < 0 and the hybrid model lifts off
    at the jam.  The engine, at every timestep: after its jam the tip leaves the plane (no contact force, the gap growing), and the
    rates of the row after the jam approach the impulse's.  Its jam comes early here (by 2.3e-4 at dt = 1e-5, 1.7e-4 at 1e-6: the
    time-stepper's slow jam-time convergence near p = 0, RIGID_COROLLARY_STOP), so the rates are held to shrinking, not to an order."""
    state, mu = IC1
    h = run(state, mu, ALPHA, horizon=0.1)
    imp = h.impacts[0]
    at = SlipState(theta=h.segments[0].slip.state.theta, varphi=-math.pi / 2, Theta=imp.Theta, Psi=imp.Psi, eta=0.0)
    rest = at_rest(at, mu, ALPHA)
    assert rest.mode == "liftoff" and rest.b > 0 and stick_force(at.theta, at.Psi, at.Theta, ALPHA)[2] < 0
    assert h.outcome == Outcome.LIFTOFF and h.time == pytest.approx(0.000434, abs=1e-6)
    errs = []
    for dt in (1e-4, 3e-5, 1e-5):
        run_ = get("pinocchio").simulate(Rod.scaled(ALPHA), state, mu, horizon=h.time + 40 * dt, timestep=dt)
        R, k = run_.record, int(round(run_.event_time / dt)) + 1
        assert run_.outcome == Outcome.JAM and 0.0 <= run_.event_time <= h.time
        assert np.all(R.normal_force[k + 1 :] == 0.0) and np.all(np.diff(R.gap[k + 1 :]) > 0)
        errs.append(max(abs(R.Theta[k] - imp.Theta), abs(R.Psi[k] - imp.Psi)))
    assert errs[0] > errs[1] > errs[2] and errs[-1] < 1e-3, errs


def test_a_resting_start_with_b_positive_lifts_off_at_once():
    state = SlipState(theta=0.8, varphi=-math.pi / 2, Theta=2.0, Psi=0.0, eta=0.0)
    h = run(state, 1.0, ALPHA, horizon=1.0)
    assert (h.outcome, h.time) == (Outcome.LIFTOFF, 0.0)
    r = get("pinocchio").simulate(Rod.scaled(ALPHA), state, 1.0, horizon=0.01, timestep=1e-4)
    assert r.outcome == Outcome.LIFTOFF and r.event_time <= 1e-4


def test_the_delassus_matrix_in_the_rod_frame_is_the_closed_form():
    """G in (i, j, n) as the module docstring writes it (the ground of F_i = 0 and of the onset directions)."""
    for s in _random_rest_states(20, 7):
        c, sn = math.cos(s.psi), math.sin(s.psi)
        R = np.array([[c, -sn, 0], [sn, c, 0], [0, 0, 1]])
        st, ct = math.sin(s.theta), math.cos(s.theta)
        want = np.array(
            [[1 + ALPHA, 0, 0], [0, 1 + ALPHA * st * st, -ALPHA * st * ct], [0, -ALPHA * st * ct, 1 + ALPHA * ct * ct]]
        )
        np.testing.assert_allclose(R.T @ delassus(s, ALPHA) @ R, want, atol=1e-13)


def test_at_most_one_slip_direction_from_rest():
    """p_+ p_- (sigma_- + sigma_+) = -2 mu (1 + alpha) B (B = -b): both directions cannot be consistent; and where sticking fails
    with b <= 0, exactly one is, at 2000 random rest states over alpha and mu in [0.01, 100]."""
    from crosscheck.theory.sticking import _onset

    rng = np.random.default_rng(8)
    slips = 0
    for _ in range(2000):
        th, Psi, Theta = rng.uniform(0.02, 1.55), rng.uniform(-3, 3), rng.uniform(-3, 3)
        mu, alpha = (float(np.exp(rng.uniform(np.log(0.01), np.log(100)))) for _ in range(2))
        s, c = math.sin(th), math.cos(th)
        W = Psi**2 * c * c + Theta**2
        B = 1 - s * W
        p_plus, p_minus = 1 + alpha * c * c + alpha * mu * s * c, 1 + alpha * c * c - alpha * mu * s * c
        if B > 0 and p_minus > 0:
            (_, sig_m), (_, sig_p) = _onset(th, Psi, Theta, mu, alpha, -1.0), _onset(th, Psi, Theta, mu, alpha, 1.0)
            assert CLOSED_FORM.ok(p_plus * p_minus * (sig_m + sig_p) / B, -2 * mu * (1 + alpha)) and sig_m + sig_p < 0
        r = at_rest(SlipState(theta=th, varphi=-math.pi / 2, Theta=Theta, Psi=Psi, eta=0.0), mu, alpha)
        assert r.mode != "inconsistent"
        slips += r.mode == "slip"
    assert slips > 200


def test_the_slip_onset_speed_moves_the_motion_by_its_own_size(monkeypatch):
    """The slipping flow starts at eta = SLIP_ONSET_SPEED, not 0: the state 0.4 after the onset moves by < SLIP_ONSET_SPEED when it is
    made ten times smaller (measured 9.0e-8): far below the engines' O(dt) errors."""
    import crosscheck.theory.impact.continuation as continuation

    state, mu = STICK_THEN_SLIP
    T = run(state, mu, ALPHA, horizon=1.0).segments[1].t1 + 0.4
    ends = []
    for eta0 in (SLIP_ONSET_SPEED, 0.1 * SLIP_ONSET_SPEED):
        monkeypatch.setattr(continuation, "SLIP_ONSET_SPEED", eta0)
        ends.append(run(state, mu, ALPHA, horizon=T).segments[-1].slip.state)
    a, b = ends
    assert (
        max(abs(a.theta - b.theta), abs(a.Theta - b.Theta), abs(a.Psi - b.Psi), abs(a.eta - b.eta)) < SLIP_ONSET_SPEED
    )
