"""The impact without collision's structure (crosscheck.theory.impact.darboux_keller): slip then stick, Poisson's impulse, and the
limit p -> 0- on the boundary p = 0 (the Genot-Brogliato point of Glocker's rod), against closed forms, an independent march in
impulse, the rigid engine as dt -> 0 and the compliant rod as eps -> 0."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from crosscheck import Rod, SlipState
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.pinocchio.studies.rigid import order, planar_impasse
from crosscheck.theory import analytic
from crosscheck.theory.critical import theta_12
from crosscheck.theory.impact.darboux_keller import P_TOLERANCE, delassus, impact, turning_rate
from crosscheck.theory.slipping import slip_until_event
from crosscheck.tolerances import CLOSED_FORM, GB_REACHED

ALPHA = 3.0
#: Glocker's rod at the Genot-Brogliato point P+: alpha = 3, mu = 5/3, theta(0) = 31 deg, planar, slip 30/sqrt(10); b = p = 0 at theta = pi/4.
GLOCKER = (
    SlipState(theta=math.radians(31.0), varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=30.0 / math.sqrt(10.0)),
    5.0 / 3.0,
)
#: The independent march's step in P and what it leaves: RK4, but the slip direction turns at a rate ~ 1/|u_t| as the slip
#: stops, so the last steps set the error (measured over the nine states below: 2.2e-5 at h = 1e-4, 2.1e-6 at h = 2.5e-5).
MARCH_STEP, MARCH_ERROR = 1e-4, 5e-5


def _rod_frame_delassus(theta, alpha):
    s, c = math.sin(theta), math.cos(theta)
    return np.array([[1 + alpha, 0, 0], [0, 1 + alpha * s * s, -alpha * s * c], [0, -alpha * s * c, 1 + alpha * c * c]])


def _random_impasses(n, seed, *, alphas=(1e-2, 1e3)):
    """States with p <= 0 for their slip direction over alpha log-uniform: mu just above the direction's threshold, or well above it."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        alpha = float(np.exp(rng.uniform(*np.log(alphas))))
        theta, varphi = rng.uniform(0.05, 1.5), -rng.uniform(0.05, math.pi - 0.05)
        s, c = math.sin(theta), math.cos(theta)
        mu_0 = (1 + alpha * c * c) / (alpha * c * s * -math.sin(varphi))  # p = 0 for this direction (eq. p)
        mu = mu_0 * float(rng.choice([1.0 + 1e-9, rng.uniform(1.0, 3.0)]))
        if mu > 1000:
            continue
        state = SlipState(
            theta=theta,
            varphi=varphi,
            Theta=rng.uniform(-3, 3),
            Psi=rng.uniform(-3, 3),
            eta=rng.uniform(0.05, 5),
            psi=rng.uniform(-3, 3),
        )
        out.append((state, mu, alpha))
    return out


def test_a_stopped_slip_sticks_wherever_an_impulse_starts():
    """G_tn is an eigenvector of G_tt (eigenvalue g = 1 + alpha s^2) so |f_s| = |G_tn|/g < G_nn/|G_tn| <= mu where p <= 0 (the
    (j, n) block's determinant is 1 + alpha > 0): at 400 states over alpha in [0.01, 1000], including mu at the threshold; the
    first 40 impulses integrated."""
    for n, (state, mu, alpha) in enumerate(_random_impasses(400, 11)):
        G = delassus(state, alpha)
        psi = state.psi
        R = np.array(
            [[math.cos(psi), -math.sin(psi), 0], [math.sin(psi), math.cos(psi), 0], [0, 0, 1]]
        )  # rod frame (i, j, n) -> world
        np.testing.assert_allclose(R.T @ G @ R, _rod_frame_delassus(state.theta, alpha), atol=1e-12 * (1 + alpha))
        f_s = -np.linalg.solve(G[:2, :2], G[:2, 2])
        assert np.linalg.norm(f_s) < mu * (1 - 1e-9)
        if n < 40:
            assert [ph.name for ph in impact(state, mu, alpha).phases] == ["slip", "stick"]


def _march(state, mu, alpha, h=MARCH_STEP):
    """The impulse by an independent fixed-step RK4 march in P of du/dP = G (f, 1) (slip), then the stick in closed form."""
    rod = Rod.scaled(alpha)
    G = delassus(state, alpha)
    q, v = to_generalized(rod, state)
    from crosscheck.coordinates import tip_velocity

    u = tip_velocity(rod, q, v)
    y = np.array([u[0], u[1], u[2], 0.0, 0.0])

    def rhs(y):
        f = -mu * y[:2] / np.linalg.norm(y[:2])
        return np.concatenate([G @ np.array([f[0], f[1], 1.0]), f])

    P = 0.0
    while True:
        d_speed = float(y[:2] @ rhs(y)[:2]) / np.linalg.norm(y[:2])
        if np.linalg.norm(y[:2]) <= -d_speed * h:  # the slip stops within this step: finish it at the current direction
            dP = np.linalg.norm(y[:2]) / -d_speed
            y = y + dP * rhs(y)
            P += dP
            break
        k1 = rhs(y)
        k2 = rhs(y + h / 2 * k1)
        k3 = rhs(y + h / 2 * k2)
        k4 = rhs(y + h * k3)
        y, P = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), P + h
    f_s = -np.linalg.solve(G[:2, :2], G[:2, 2])
    S = G[2, 2] + G[2, :2] @ f_s
    P_c = P + max(0.0, -y[2]) / S
    L = np.array([y[3] + f_s[0] * (P_c - P), y[4] + f_s[1] * (P_c - P), P_c])
    return P, P_c, L


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_impulse_agrees_with_an_independent_march_in_impulse(seed):
    for state, mu, alpha in _random_impasses(3, 100 + seed, alphas=(0.5, 20.0)):
        r = impact(state, mu, alpha)
        P_s, P_c, L = _march(state, mu, alpha)
        assert abs(r.phases[0].P_end - P_s) < MARCH_ERROR * (1 + P_s)
        assert abs(r.compression_impulse - P_c) < MARCH_ERROR * (1 + P_c)
        np.testing.assert_allclose(r.tangential_impulse, L[:2], atol=MARCH_ERROR * (1 + P_c))


@pytest.mark.parametrize("e", [0.25, 0.5, 0.8])
@pytest.mark.parametrize("where", ["planar", "3d"])
def test_poisson_restitution_after_a_stopped_slip(e, where):
    """Poisson: P_f = (1 + e) P_c, the restitution phase sticks and throws the tip off at w = S e P_c, and it gives back
    S (e P_c)^2 / 2 of the energy the plastic impact loses (the work of the normal impulse on u_n while stuck)."""
    state, mu = (
        (planar_impasse(1.4, 0.5, ALPHA), 1.4)
        if where == "planar"
        else (SlipState(theta=0.9, varphi=-1.2, Theta=0.3, Psi=0.8, eta=1.0), 2.0)
    )
    r0, r = impact(state, mu, ALPHA), impact(state, mu, ALPHA, restitution=e)
    G = delassus(state, ALPHA)
    S = G[2, 2] - G[2, :2] @ np.linalg.solve(G[:2, :2], G[:2, 2])
    assert [ph.name for ph in r.phases] == ["slip", "stick"] and r.phases[1].P_end == r.normal_impulse
    assert r.compression_impulse == r0.compression_impulse
    assert CLOSED_FORM.ok(r.normal_impulse, (1 + e) * r0.compression_impulse)
    assert CLOSED_FORM.ok(r.w, S * e * r0.compression_impulse)
    assert CLOSED_FORM.ok(r.energy_lost, r0.energy_lost - 0.5 * S * (e * r0.compression_impulse) ** 2)
    assert r.energy_lost >= 0.0 and r.eta == 0.0


def test_the_slip_angle_turns_towards_minus_pi_half_and_p_never_rises():
    """dp/dP = -k <= 0 in the paper's domain: k from the rod-frame formula equals the Delassus form, and is (1 + alpha) alpha mu c^2
    cos^2 varphi / eta (the paper's K_12 / eta) on p = 0."""
    rng = np.random.default_rng(4)
    for _ in range(200):
        theta, varphi, mu, eta = (
            rng.uniform(0.05, 1.5),
            -rng.uniform(0.0, math.pi - 1e-3),
            rng.uniform(0.1, 10),
            rng.uniform(0.1, 5),
        )
        state = SlipState(theta=theta, varphi=varphi, Theta=0.0, Psi=0.0, eta=eta, psi=rng.uniform(-3, 3))
        G = delassus(state, ALPHA)
        u_t = eta * np.array([math.cos(state.psi + varphi), math.sin(state.psi + varphi)])
        s, c = math.sin(theta), math.cos(theta)
        k = mu * ALPHA**2 * s * c * c * math.cos(varphi) ** 2 * (s - mu * c * math.sin(varphi)) / eta
        assert turning_rate(G, u_t, mu) == pytest.approx(k, rel=1e-10, abs=1e-13) and k >= 0.0
    theta = 1.0
    s, c = math.sin(theta), math.cos(theta)
    mu = 2.0
    varphi = -math.pi / 2 - math.acos((1 + ALPHA * c * c) / (ALPHA * mu * s * c))  # eq. varphistar: p = 0
    state = SlipState(theta=theta, varphi=varphi, Theta=0.0, Psi=0.0, eta=1.3)
    assert abs(analytic.p(theta, varphi, mu, ALPHA)) <= P_TOLERANCE
    u_t = 1.3 * np.array([math.cos(varphi), math.sin(varphi)])
    assert turning_rate(delassus(state, ALPHA), u_t, mu) == pytest.approx(
        (1 + ALPHA) * ALPHA * mu * c * c * math.cos(varphi) ** 2 / 1.3, rel=1e-12
    )


# ------------------------------------------------------------------------------------------------ the boundary p = 0 ---


def _at_P_plus(theta_shift=0.0):
    """Glocker's rod placed at P+ itself (theta_1 = pi/4, b = 0, its arrival slip speed), or moved in theta into the inconsistent region."""
    mu = GLOCKER[1]
    th1 = float(theta_12(mu, ALPHA)[0])
    return SlipState(
        theta=th1 + theta_shift, varphi=-math.pi / 2, Theta=math.sqrt(1 / math.sin(th1)), Psi=0.0, eta=2.9513890040207
    ), mu


def test_at_the_planar_gb_point_the_tip_slides_along_p_0_until_its_slip_stops():
    """The limit on the planar section: P_c = P_s = eta / (mu (1 + alpha s^2) - alpha s c), L_t = mu P_s along the rod, the tip
    stuck and on the plane, Theta_after = Theta + alpha P_s (mu s - c) (eq. rotode integrated in impulse)."""
    state, mu = _at_P_plus()
    assert (
        abs(analytic.p(state.theta, state.varphi, mu, ALPHA)) <= P_TOLERANCE
        and abs(analytic.b(0.0, state.Theta, state.theta)) < 1e-15
    )
    s, c = math.sin(state.theta), math.cos(state.theta)
    P_s = state.eta / (mu * (1 + ALPHA * s * s) - ALPHA * s * c)
    r = impact(state, mu, ALPHA)
    assert [ph.name for ph in r.phases] == ["slip", "stick"]
    assert CLOSED_FORM.ok(r.phases[0].P_end, P_s) and r.compression_impulse == r.normal_impulse == r.phases[0].P_end
    assert CLOSED_FORM.ok(r.Theta, state.Theta + ALPHA * P_s * (mu * s - c))
    assert r.eta == 0.0 and abs(r.w) < 1e-14 and abs(r.Psi) < 1e-13  # u_n: the rounding of p along the slip, integrated
    np.testing.assert_allclose(r.tangential_impulse, [0.0, mu * P_s], atol=1e-12)


def test_the_boundary_impulse_is_the_limit_from_inside_the_inconsistent_region():
    """Impulses from p_0 = -delta (theta moved into (theta_1, theta_2)) tend to the boundary's at first order in delta, planar and 3-D."""
    planar, mu = _at_P_plus()
    r = impact(planar, mu, ALPHA)
    errs = []
    for shift in (1e-4, 1e-5, 1e-6):
        inside, _ = _at_P_plus(shift)
        assert analytic.p(inside.theta, inside.varphi, mu, ALPHA) < -P_TOLERANCE
        ri = impact(inside, mu, ALPHA)
        errs.append(max(abs(ri.Theta - r.Theta), abs(ri.normal_impulse - r.normal_impulse)))
    assert order([1e-4, 1e-5, 1e-6], errs) == pytest.approx(1.0, abs=0.05) and errs[-1] < 1e-5
    # 3-D: varphi off -pi/2, the direction turns (k > 0) and compresses the tip before the slip stops
    theta, mu3 = 1.0, 2.0
    s, c = math.sin(theta), math.cos(theta)
    varphi = -math.pi / 2 - math.acos((1 + ALPHA * c * c) / (ALPHA * mu3 * s * c))
    on = SlipState(theta=theta, varphi=varphi, Theta=0.4, Psi=0.7, eta=1.3)
    r3 = impact(on, mu3, ALPHA)
    assert r3.compression_impulse > r3.phases[0].P_end  # compressed: u_n < 0 at the stop
    errs = []
    for d in (1e-3, 1e-4, 1e-5):
        ri = impact(dataclasses.replace(on, varphi=varphi + d), mu3, ALPHA)  # towards -pi/2: deeper into p < 0
        errs.append(max(abs(ri.Theta - r3.Theta), abs(ri.Psi - r3.Psi), abs(ri.normal_impulse - r3.normal_impulse)))
    assert order([1e-3, 1e-4, 1e-5], errs) == pytest.approx(1.0, abs=0.05)


def test_a_gb_arrival_of_the_slipping_flow_gets_the_limit_when_told_and_is_refused_otherwise():
    """The flow stops Glocker's rod within GB_REACHED of b = p = 0 with p > 0 to rounding (8.6e-12): without ``boundary`` that
    state could still slip and gets no impulse; with it, the limit at P+ to the distance of the GB ball."""
    state, mu = GLOCKER
    a = slip_until_event(state, mu, ALPHA, t_max=5.0)
    assert a.outcome.name == "GB" and a.time == pytest.approx(2.5758, abs=1e-4) and P_TOLERANCE < a.p < GB_REACHED.atol
    with pytest.raises(ValueError, match=r"p must be <= 1e-12 .*: it can slip"):
        impact(a.state, mu, ALPHA)
    r, at = impact(a.state, mu, ALPHA, boundary=True), impact(_at_P_plus()[0], mu, ALPHA)
    assert (
        abs(r.Theta - at.Theta) < 10 * GB_REACHED.atol
        and abs(r.normal_impulse - at.normal_impulse) < 10 * GB_REACHED.atol
    )
    assert r.eta == 0.0 and abs(r.w) < 1e-14
    far = dataclasses.replace(a.state, theta=a.state.theta + 1e-5)
    with pytest.raises(
        ValueError, match=r"p must be in \[-1e-07, 1e-07\] for an impact on the boundary p = 0; got p = "
    ):
        impact(far, mu, ALPHA, boundary=True)


#: Timesteps at which the rigid engine is run through Glocker's GB point (at 1e-3 it lifts off before P+: too coarse).
GB_TIMESTEPS = (3e-4, 1e-4, 3e-5)


def test_rigid_engine_through_the_gb_point_converges_to_the_limit_impulse():
    """The time-stepper jams at P+ and its state one row later tends to the limit at first order (its slip right after is the
    flight's O(dt) tangential drift; the tip leaves the plane: stuck with b > 0 after the impulse)."""
    state, mu = GLOCKER
    a = slip_until_event(state, mu, ALPHA, t_max=5.0)
    r = impact(a.state, mu, ALPHA, boundary=True)
    rod = Rod.scaled(ALPHA)
    errs = []
    for dt in GB_TIMESTEPS:
        run = get("pinocchio").simulate(rod, state, mu, horizon=a.time + 0.01, timestep=dt)
        assert run.outcome.name == "JAM" and abs(run.event_time - a.time) <= dt
        R, k = run.record, int(round(run.event_time / dt)) + 1
        errs.append(max(abs(R.Theta[k] - r.Theta), abs(R.Psi[k] - r.Psi), abs(R.eta[k] - r.eta)))
        assert R.gap[k + 5] > 0.0 and np.all(R.normal_force[k + 1 : k + 6] == 0.0)
    assert order(GB_TIMESTEPS, errs) == pytest.approx(1.0, abs=0.1) and errs[-1] < 5 * GB_TIMESTEPS[-1], errs


def test_compliant_rod_through_the_gb_point_converges_to_the_limit_impulse():
    """Kelvin-Voigt, xi = 1, eps -> 0: the post-contact state tends to the limit at P+ (slowly: measured order ~0.28 in eps), not
    to the Darboux-Keller impulse of p > 0 states that leaves the tip slipping."""
    from crosscheck.engines.compliant.studies import limit as cl

    state, mu = GLOCKER
    a = slip_until_event(state, mu, ALPHA, t_max=5.0)
    r = impact(a.state, mu, ALPHA, boundary=True)
    eps = (1e-5, 1e-6, 1e-7)
    errs = [cl.post_errors(cl.limit_run(state, mu, ALPHA, eps=x, xi=1.0, horizon=a.time + 0.3), r)["max"] for x in eps]
    assert all(x > y for x, y in zip(errs, errs[1:])), errs
    assert 0.2 < order(eps, errs) < 0.4 and errs[-1] < 0.02, errs
