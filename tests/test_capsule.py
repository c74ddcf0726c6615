"""The rigid rod with its contact at the capsule point C: closed forms against Pinocchio, r = 0 against crosscheck.theory.slipping."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import brentq

from crosscheck.coordinates import to_generalized
from crosscheck.engines.pinocchio import model as pinrod
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic, capsule, gb, slipping
from crosscheck.tolerances import (
    CAPSULE_JAM_CONVERGENCE,
    CAPSULE_JAM_FORCE_LAW,
    CAPSULE_PIN_DYNAMICS,
    CAPSULE_PIN_SLIP,
    CAPSULE_PIN_VELOCITY,
    CAPSULE_REDUCTION_TIME,
    CLOSED_FORM,
)

RADII = (0.0, 0.01, 0.1, 0.3)
_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_K_CROSS = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])  # [K]x: K x w = _K_CROSS @ w


def _random_state(rng: np.random.Generator) -> SlipState:
    return SlipState(
        theta=rng.uniform(0.05, 1.5),
        varphi=-rng.uniform(0.0, 0.999 * math.pi),
        Theta=rng.uniform(-5, 5),
        Psi=rng.uniform(-5, 5),
        eta=rng.uniform(0.2, 3.0),
        psi=rng.uniform(-3, 3),
    )


def _pinocchio_at_C(rod: Rod, state: SlipState, mu: float, r: float) -> dict:
    """Pinocchio's b, p_C, C's slip velocity and the slipping accelerations, with the contact frame moved to C."""
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, r))
    eng = pinrod.engine(rod)
    model, data = eng.model, eng.data
    J6 = pin.computeFrameJacobian(model, data, q, eng.tip, _LWA)
    JC = J6[:3] + r * _K_CROSS @ J6[3:]  # v_C = v_A + omega x (-r K) = v_A + r K x omega
    terms = eng.terms(q[None], v[None])
    G = JC @ np.linalg.solve(terms.M[0], JC.T)
    uC = JC @ v
    beta = math.atan2(uC[1], uC[0])
    d = np.array([-mu * math.cos(beta), -mu * math.sin(beta), 1.0])
    b = terms.free_acceleration()[0, 2] / rod.gravity
    p = rod.mass * G[2] @ d
    # slipping: F_z from Pinocchio's own b and p_C, then aba with tau = J_C^T F
    Fz = -b / p
    a = pin.aba(model, data, q, v, JC.T @ (Fz * d))
    pin.forwardKinematics(model, data, q, v, a)
    aA = pin.getFrameClassicalAcceleration(model, data, eng.tip, _LWA).linear
    psi, Psi, Theta = q[3], v[3], v[4]
    i_h, j_h = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
    duC = aA[:2] + r * a[4] * j_h - r * Theta * Psi * i_h  # d/dt (v_A + r Theta j), dj/dt = -Psi i
    eta_C = math.hypot(uC[0], uC[1])
    unit = uC[:2] / eta_C
    rates = np.array([duC @ unit, (unit[0] * duC[1] - unit[1] * duC[0]) / eta_C - Psi, a[3], a[4]])
    return {"b": b, "p": p, "u": uC[:2], "Fz": Fz, "rates": rates, "v1": 1.0 + np.abs(v).sum(), "eta_C": eta_C}


def test_p_reduces_to_eq_p_at_r_zero():
    rng = np.random.default_rng(10)
    theta, varphi = rng.uniform(1e-3, 1.57, 500), rng.uniform(-math.pi, 0.0, 500)
    mu, alpha = rng.uniform(0, 5, 500), rng.uniform(0.5, 20, 500)
    assert CLOSED_FORM.ok(capsule.p(theta, varphi, mu, alpha, 0.0), analytic.p(theta, varphi, mu, alpha))
    x = np.array([1.3, -1.1, 0.4, 0.7, 0.8, -0.6])
    # the one slipping field at r = 0 is eq. f with the Appendix A coefficients (crosscheck.theory.gb.f, written independently)
    assert CLOSED_FORM.ok(slipping.slip_rhs(x, 1.5, 3.0, radius=0.0), gb.f(x, 1.5, 3.0))


@pytest.mark.parametrize("r", RADII, ids=lambda r: f"r={r}")
def test_closed_forms_against_pinocchio_at_C(r):
    rng = np.random.default_rng(int(1000 * r) + 1)
    n = 0
    for _ in range(40):
        alpha, mu = 10 ** rng.uniform(math.log10(0.5), math.log10(20)), rng.uniform(0, 5)
        state = _random_state(rng)
        eta_C, varphi_C = capsule.contact_slip(state, radius=r)
        if eta_C < 0.05:  # the slip direction of a nearly stuck C is rounding: not a test of p_C
            continue
        n += 1
        rod = Rod.scaled(alpha)
        pin_C = _pinocchio_at_C(rod, state, mu, r)
        u = eta_C * np.array([math.cos(varphi_C + state.psi), math.sin(varphi_C + state.psi)])
        assert CAPSULE_PIN_VELOCITY.ok(u / pin_C["v1"], pin_C["u"] / pin_C["v1"])
        scale = (1 + alpha) * (1 + mu) * (1 + r) * (1 + pin_C["v1"] / eta_C)
        assert CAPSULE_PIN_SLIP.ok(capsule.p(state.theta, varphi_C, mu, alpha, r) / scale, pin_C["p"] / scale)
        assert CAPSULE_PIN_SLIP.ok(
            capsule.b(state.Psi, state.Theta, state.theta) / pin_C["v1"] ** 2, pin_C["b"] / pin_C["v1"] ** 2
        )
        # the slipping field at C in real time: f / (eta_C p_C)
        x = [eta_C, varphi_C, state.psi, state.Psi, state.theta, state.Theta]
        f = slipping.slip_rhs(x, mu, alpha, radius=r)
        p_C = capsule.p(state.theta, varphi_C, mu, alpha, r)
        got = np.array([f[0], f[1], f[3], f[5]]) / (eta_C * p_C)
        # F_z = -b/p_C carries p_C's rounding ~ eps (1 + alpha)(1 + mu) relative to |p_C|: its term scale grows as 1/|p_C|
        force = abs(pin_C["Fz"]) * (1 + (1 + alpha) * (1 + mu) / abs(p_C))
        scale = (1 + alpha) * (1 + force) * pin_C["v1"] ** 2 / math.cos(state.theta) ** 2 * (1 + 1 / eta_C)
        assert CAPSULE_PIN_DYNAMICS.ok(got / scale, pin_C["rates"] / scale)
    assert n >= 30


def test_r_zero_reproduces_slipping():
    rng = np.random.default_rng(20)
    outcomes = set()
    for _ in range(60):
        state = SlipState(
            theta=rng.uniform(0.1, 1.45),
            varphi=-rng.uniform(0.05, 3.1),
            Theta=rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.05, 2),
            psi=rng.uniform(-3, 3),
        )
        mu = rng.uniform(0, 2)
        want = slipping.slip_until_event(state, mu, 3.0)
        got = capsule.slip_until_event(state, mu, 3.0, radius=0.0)
        assert (got.outcome, got.reason) == (want.outcome, want.reason)
        assert CAPSULE_REDUCTION_TIME.ok(got.time, want.time)
        outcomes.add(want.outcome)
    assert {Outcome.JAM, Outcome.LIFTOFF, Outcome.STICK} <= outcomes  # the sample exercises the events


def _near_boundary(delta: float, eta: float) -> SlipState:
    """theta = 0.9, Psi = 0, b = -1e-3 (Theta from eq. b) and p = delta at A (eq. p, varphi on the branch above -pi/2)."""
    theta, mu, alpha = 0.9, 1.6, 3.0
    Theta = math.sqrt((1 - 1e-3) / math.sin(theta))
    varphi = brentq(lambda ph: analytic.p(theta, ph, mu, alpha) - delta, -math.pi / 2, -0.01)
    return SlipState(theta=theta, varphi=varphi, Theta=Theta, Psi=0.0, eta=eta)


def _first_order_shift(state: SlipState, mu, alpha, r):
    """p_C - p_A to first order in r: alpha mu r cos theta (sin varphi + sin theta Theta cos^2 varphi / eta).

    The lever (sin theta + r) adds alpha mu r cos theta sin varphi; C's slip v_A + r Theta j turns the slip
    angle by r Theta cos varphi / eta, which moves eq. p by alpha mu sin theta cos theta cos varphi times that.
    """
    s, c = math.sin(state.theta), math.cos(state.theta)
    return alpha * mu * r * c * (math.sin(state.varphi) + s * state.Theta * math.cos(state.varphi) ** 2 / state.eta)


@pytest.mark.parametrize(
    "delta, eta, at_A, at_C",
    [(0.003, 1.0, Outcome.LIFTOFF, Outcome.JAM), (-0.003, 0.1, Outcome.JAM, Outcome.LIFTOFF)],
    ids=["slips-at-A-jams-at-C", "jams-at-A-lifts-at-C"],
)
def test_radius_changes_the_outcome_near_p_zero(delta, eta, at_A, at_C):
    mu, alpha, r = 1.6, 3.0, 0.01
    state = _near_boundary(delta, eta)
    # the shift of p by the capsule, against its first-order closed form: the remainder is O(r^2)
    shift = [capsule.p(state.theta, capsule.contact_slip(state, radius=x)[1], mu, alpha, x) - delta for x in (r, r / 2)]
    rem = [s - _first_order_shift(state, mu, alpha, x) for s, x in zip(shift, (r, r / 2))]
    assert 3.0 < rem[0] / rem[1] < 5.0  # halving r quarters the remainder
    assert math.copysign(1.0, shift[0]) != math.copysign(1.0, delta) and abs(shift[0]) > abs(delta)  # p changes sign
    assert slipping.slip_until_event(state, mu, alpha).outcome is at_A
    assert capsule.slip_until_event(state, mu, alpha, radius=0.0).outcome is at_A
    got = capsule.slip_until_event(state, mu, alpha, radius=r)
    assert got.outcome is at_C
    if at_C is Outcome.JAM:
        assert got.time == 0.0 and got.p < 0  # inconsistent from the start at C
    else:
        assert got.time > 0.0 and got.reason == "b=0"


def test_jam_time_converges_with_the_integrator_tolerance():
    state = SlipState(
        theta=0.558491807212282,
        varphi=-2.1265159074397824,
        Theta=0.926342075423221,
        Psi=-0.31659380758977446,
        eta=1.4916615350187519,
    )
    kw = dict(mu=1.6, alpha=3.0, radius=0.01)
    ref = capsule.slip_until_event(state, rtol=1e-13, atol=1e-15, **kw)
    assert ref.outcome is Outcome.JAM and ref.reason == "p=0" and ref.time > 0.2
    for rtol in (1e-6, 1e-8, 1e-10):
        got = capsule.slip_until_event(state, rtol=rtol, atol=rtol / 100, **kw)
        assert got.outcome is Outcome.JAM
        assert abs(got.time - ref.time) <= CAPSULE_JAM_CONVERGENCE.rtol * rtol * ref.time


@pytest.mark.parametrize("radius", [-0.01, 0.5, 1.0, math.nan])
def test_bad_radius(radius):
    state = SlipState(theta=0.8, varphi=-1.0, Theta=0.1, Psi=0.2, eta=1.0)
    with pytest.raises(ValueError, match=r"^radius must be in \[0, 0\.5\); got"):
        capsule.slip_until_event(state, 1.0, 3.0, radius=radius)
    with pytest.raises(ValueError, match=r"^radius must be in \[0, 0\.5\)"):
        capsule.p(0.8, -1.0, 1.0, 3.0, radius)


def test_start_rules_judged_at_C():
    r, Theta = 0.02, 1.0
    # A slips straight across the rod's plane (varphi = -pi/2) at exactly r Theta: C's material point is at rest
    stuck = SlipState(theta=0.7, varphi=-math.pi / 2, Theta=Theta, Psi=0.3, eta=r * Theta)
    assert capsule.contact_slip(stuck, radius=r)[0] < 1e-15
    got = capsule.slip_until_event(stuck, 0.5, 3.0, radius=r)
    assert (got.outcome, got.time, got.reason) == (Outcome.STICK, 0.0, "start")
    at_A = slipping.slip_until_event(stuck, 0.5, 3.0)
    assert at_A.time > 0.0  # the tip itself slips at r Theta
    # a slow A slipping near the rod's plane: r Theta turns C's slip across it, varphi_C in (0, pi/2)
    varphi, eta = -0.3, 0.5 * r * Theta
    across = SlipState(theta=0.7, varphi=varphi, Theta=Theta, Psi=0.3, eta=eta)
    eta_C, varphi_C = capsule.contact_slip(across, radius=r)
    u_i, u_j = eta * math.cos(varphi), eta * math.sin(varphi) + r * Theta  # v_C = v_A + r Theta j
    assert (
        CLOSED_FORM.ok([eta_C, varphi_C], [math.hypot(u_i, u_j), math.atan2(u_j, u_i)]) and 0 < varphi_C < math.pi / 2
    )
    got = capsule.slip_until_event(across, 0.5, 3.0, radius=r)
    assert (got.outcome, got.time, got.reason) == (Outcome.SLIP, 0.0, "varphi=0")
    # and tip_slip inverts contact_slip
    eta_A, varphi_A = capsule.tip_slip(eta_C, varphi_C, Theta, radius=r)
    assert CLOSED_FORM.ok([eta_A, varphi_A], [across.eta, across.varphi])


def test_normal_force_along_a_run_is_eq_FZ_at_C():
    state = SlipState(
        theta=0.558491807212282,
        varphi=-2.1265159074397824,
        Theta=0.926342075423221,
        Psi=-0.31659380758977446,
        eta=1.4916615350187519,
    )
    got = capsule.slip_until_event(state, 1.6, 3.0, radius=0.01)
    x = got.x
    with np.errstate(divide="ignore"):  # p_C = 0 at the JAM itself
        want = -capsule.b(x[:, 3], x[:, 5], x[:, 4]) / capsule.p(x[:, 4], x[:, 1], 1.6, 3.0, 0.01)
    np.testing.assert_array_equal(got.normal_force, want)
    assert np.all(want[:-1] > 0) and want[-2] > 10 * want[0]  # it grows without bound towards the JAM (p_C -> 0+)
    assert math.isclose(got.p, 0.0, abs_tol=1e-9) and got.b < 0
    # F_z ~ (t_jam - t)^(-1/2): p_C dp_C/dt = (dp_C/ds) / eta_C = -k at the jam, so F_z sqrt(t_jam - t) -> -b / sqrt(2 k)
    eta_C, varphi_C, theta = got.state.eta, got.state.varphi, got.state.theta
    dp_dvarphi = 3.0 * 1.6 * math.cos(theta) * (math.sin(theta) + 0.01) * math.cos(varphi_C)  # d p_C / d varphi_C
    k = (
        -dp_dvarphi * slipping.slip_rhs(x[-1], 1.6, 3.0, radius=0.01)[1] / eta_C
    )  # d theta/ds = eta_C p_C Theta = 0 there
    limit = -got.b / math.sqrt(2 * k)
    lag = got.time - got.t[:-1]
    near = lag < 5e-3
    assert near.sum() >= 3
    c = (want[:-1][near] * np.sqrt(lag[near]) / limit - 1) / np.sqrt(lag[near])  # the next order's coefficient
    assert CAPSULE_JAM_FORCE_LAW.ok(c, c[-1])
