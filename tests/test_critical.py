"""Identities between the critical values of section 3 and the functions b, p they come from."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from crosscheck.checks import MU_MAX
from crosscheck.theory import analytic as an
from crosscheck.theory import critical as cr
from crosscheck.theory.analytic import Mode
from crosscheck.tolerances import CLOSED_FORM, FINITE_DIFFERENCE, ROOT_RESIDUAL

ALPHAS = [0.5, 1.0, 3.0, 7.0, 30.0]
# hypothesis runs derandomized: the same examples on every run (seeded, reproducible)
PROPERTY = settings(max_examples=200, derandomize=True, deadline=None)


@PROPERTY
@given(alpha=st.floats(0.2, 50), excess=st.floats(1e-3, 10), varphi=st.floats(-3.1, -0.05))
def test_p_vanishes_at_theta_pm(alpha, excess, varphi):
    mu = cr.mu_P_star(varphi, alpha) * (1 + excess)
    assume(mu <= MU_MAX)  # near varphi = -pi, mu_P* grows past the range mu is accepted in (crosscheck.checks)
    for th in cr.theta_pm(varphi, mu, alpha):
        assert 0 < th < math.pi / 2
        assert abs(an.p(th, varphi, mu, alpha)) <= ROOT_RESIDUAL.atol * (1 + alpha) * (1 + mu)


@PROPERTY
@given(alpha=st.floats(0.2, 50), excess=st.floats(1e-3, 10), u=st.floats(0.01, 0.99))
def test_p_vanishes_at_varphi_pm(alpha, excess, u):
    mu = cr.mu_P(alpha) * (1 + excess)
    th1, th2 = cr.theta_12(mu, alpha)
    theta = th1 + u * (th2 - th1)  # inside (theta_1, theta_2) both roots exist
    for vp in cr.varphi_pm(theta, mu, alpha):
        assert -math.pi < vp < 0
        assert abs(an.p(theta, vp, mu, alpha)) <= ROOT_RESIDUAL.atol * (1 + alpha) * (1 + mu)


def test_no_root_below_mu_P_star():
    # below mu_P*(varphi) p > 0 for every theta: theta_pm has no real root
    alpha, varphi = 3.0, -1.2
    mu = 0.999 * cr.mu_P_star(varphi, alpha)
    assert all(np.isnan(t) for t in cr.theta_pm(varphi, mu, alpha))
    theta = np.linspace(1e-3, math.pi / 2 - 1e-3, 2001)
    assert an.p(theta, varphi, mu, alpha).min() > 0


def test_lift_off_threshold_is_a_double_root_of_b():
    # At (theta_L, Psi_L, Theta = 0): b = 0 and db/dtheta = 0 (tangency of b = 0 to Theta = 0).
    assert an.b(cr.Psi_L, 0.0, cr.theta_L) == pytest.approx(0.0, abs=CLOSED_FORM.atol)
    h = 1e-6
    dbdtheta = (an.b(cr.Psi_L, 0.0, cr.theta_L + h) - an.b(cr.Psi_L, 0.0, cr.theta_L - h)) / (2 * h)
    assert abs(dbdtheta) <= FINITE_DIFFERENCE.atol
    # and it is a minimum of the threshold: any other theta needs a larger |Psi|
    theta = np.linspace(0.05, 1.5, 1000)
    assert np.all(an.b(cr.Psi_L, 0.0, theta) <= CLOSED_FORM.atol)


@pytest.mark.parametrize("alpha", ALPHAS, ids=str)
def test_Psi_1_equals_Psi_2_equals_Psi_P_at_mu_P(alpha):
    cv = cr.critical_values(cr.mu_P(alpha), alpha)
    assert cv.theta_1 == pytest.approx(cv.theta_P, abs=1e-7)  # double root: sqrt(rounding) ~ 1e-8
    assert cv.Psi_1 == pytest.approx(cv.Psi_P, rel=1e-7)
    assert cv.Psi_2 == pytest.approx(cv.Psi_P, rel=1e-7)
    assert cv.varphi_1 == pytest.approx(-math.pi / 2, abs=1e-7)


@pytest.mark.parametrize("alpha", ALPHAS, ids=str)
def test_Psi_1_equals_Psi_L_at_mu_L(alpha):
    cv = cr.critical_values(cr.mu_L(alpha), alpha)
    assert cv.theta_1 == pytest.approx(cr.theta_L, rel=CLOSED_FORM.rtol)
    assert cv.Psi_1 == pytest.approx(cr.Psi_L, rel=CLOSED_FORM.rtol)


@pytest.mark.parametrize("alpha", ALPHAS, ids=str)
def test_critical_values_nan_below_mu_P(alpha):
    cv = cr.critical_values(0.99 * cr.mu_P(alpha), alpha)
    for name in ("theta_1", "theta_2", "Psi_1", "Psi_2", "varphi_1", "varphi_2"):
        assert math.isnan(getattr(cv, name)), name
    assert not math.isnan(cv.Psi_L) and not math.isnan(cv.theta_P)


@PROPERTY
@given(alpha=st.floats(0.2, 50), excess=st.floats(1e-4, 20))
def test_ordering_of_critical_values(alpha, excess):
    cv = cr.critical_values(cr.mu_P(alpha) * (1 + excess), alpha)
    assert cv.theta_1 < cv.theta_P < cv.theta_2
    assert cv.theta_2 > cr.theta_L  # "theta_2 > theta_L for all alpha, mu" (sec. 3.4)
    assert cr.Psi_L <= cv.Psi_1 * (1 + 1e-12) and cv.Psi_1 < cv.Psi_2
    assert cv.varphi_1 < -math.pi / 2 < cv.varphi_2
    assert cv.mu_P < cv.mu_C


def test_region_p_negative_is_bounded_by_theta12_varphi12():
    # Fig. badregion: alpha = 3, mu = 1.4.  p < 0 exactly inside
    # theta in (theta_1, theta_2), varphi in (varphi_1, varphi_2), and both boxes are tight.
    mu, alpha = 1.4, 3.0
    cv = cr.critical_values(mu, alpha)
    theta, varphi = np.meshgrid(np.linspace(1e-4, math.pi / 2 - 1e-4, 1201), np.linspace(-math.pi + 1e-4, 0, 1201))
    neg = an.p(theta, varphi, mu, alpha) < 0
    assert neg.any()
    assert cv.theta_1 < theta[neg].min() and theta[neg].max() < cv.theta_2
    assert cv.varphi_1 < varphi[neg].min() and varphi[neg].max() < cv.varphi_2
    # tightness: just inside each bound p < 0, just outside p > 0 for every varphi (theta bounds)
    # or every theta (varphi bounds)
    d = 1e-6
    all_theta = np.linspace(1e-4, math.pi / 2 - 1e-4, 20001)
    all_varphi = np.linspace(-math.pi + 1e-4, 0, 20001)
    for th, inside in ((cv.theta_1, +d), (cv.theta_2, -d)):
        assert an.p(th + inside, -math.pi / 2, mu, alpha) < 0
        assert an.p(th - inside, all_varphi, mu, alpha).min() > 0
    for vp, inside in ((cv.varphi_1, +d), (cv.varphi_2, -d)):
        assert an.p(cv.theta_P, vp + inside, mu, alpha) < 0
        assert an.p(all_theta, vp - inside, mu, alpha).min() > 0


# --------------------------------------------------------------------------
# kinematic cases 1..7 against brute force: which modes exist at Theta = 0 on
# the planar section varphi = -pi/2 (Figs. psi1.6119, psi1.9483, psi3.0097)
# --------------------------------------------------------------------------

S, L, I, D = Mode.SLIP, Mode.LIFTOFF, Mode.INCONSISTENT, Mode.INDETERMINATE
MODES_AT_THETA_DOT_ZERO = {1: {S}, 2: {S, L}, 3: {S, I}, 4: {S, L, I}, 5: {S, D, I}, 6: {S, L, D, I}, 7: {S, L, D}}


def _modes_present(mu, Psi, alpha):
    theta = np.linspace(1e-4, math.pi / 2 - 1e-4, 200001)
    m = an.mode(an.b(Psi, 0.0, theta), an.p(theta, -math.pi / 2, mu, alpha))
    return {Mode(k) for k in np.unique(m)}


def _case_grid():
    alpha = 3.0
    cases = []
    for mu in (0.5, 1.2, 1.4, 1.7, 2.0, 2.5, 6.0):
        cv = cr.critical_values(mu, alpha)
        edges = (
            [0.0, cr.Psi_L]
            + ([] if math.isnan(cv.Psi_1) else [cv.Psi_1, cv.Psi_2])
            + [1.5 * max(cr.Psi_L, np.nan_to_num(cv.Psi_2))]
        )
        for lo, hi in zip(edges[:-1], edges[1:]):
            for Psi in (lo + 0.2 * (hi - lo), 0.5 * (lo + hi), lo + 0.8 * (hi - lo)):
                cases.append((mu, Psi, alpha))
    return cases


@pytest.mark.parametrize("mu, Psi, alpha", _case_grid(), ids=lambda v: f"{v:.3g}")
def test_kinematic_case_matches_the_modes_it_describes(mu, Psi, alpha):
    case = cr.kinematic_case(mu, Psi, alpha)
    assert _modes_present(mu, Psi, alpha) == MODES_AT_THETA_DOT_ZERO[case]
    assert cr.kinematic_case(mu, -Psi, alpha) == case  # symmetric in Psi


def test_kinematic_case_and_mechanism_vectorise():
    mu = np.array([1.0, 1.4, 1.4, 6.0])
    Psi = np.array([2.0, 1.7, 2.5, 1.9])
    got = cr.kinematic_case(mu, Psi, 3.0)
    assert got.dtype == np.int8 and got.tolist() == [2, 4, 6, 5]
    assert cr.mechanism(mu, 3.0).tolist() == [1, 2, 2, 3]
    assert cr.mechanism(cr.mu_P(3.0), 3.0) == cr.Mechanism.I  # documented boundary
    assert cr.mechanism(cr.mu_L(3.0), 3.0) == cr.Mechanism.II


# --------------------------------------------------------------------------
# mode(b, p)
# --------------------------------------------------------------------------


def test_mode_sign_rules_on_a_grid():
    b, p = np.meshgrid(np.linspace(-2, 2, 41), np.linspace(-2, 2, 41))
    m = an.mode(b, p)
    assert m.dtype == np.int8
    off = (b != 0) & (p != 0)
    want = np.where(
        p > 0, np.where(b < 0, Mode.SLIP, Mode.LIFTOFF), np.where(b < 0, Mode.INCONSISTENT, Mode.INDETERMINATE)
    )
    np.testing.assert_array_equal(m[off], want[off])


@pytest.mark.parametrize(
    "b, p, want",
    [
        (-1.0, 1.0, Mode.SLIP),
        (0.0, 1.0, Mode.SLIP),  # unique LCP solution F_z = 0, w' = 0
        (1.0, 1.0, Mode.LIFTOFF),
        (1.0, 0.0, Mode.LIFTOFF),  # w' = b > 0 whatever F_z: unique solution F_z = 0
        (-1.0, 0.0, Mode.INCONSISTENT),  # w' = b < 0 whatever F_z: no solution
        (0.0, 0.0, Mode.INDETERMINATE),  # every F_z >= 0 solves
        (-1.0, -1.0, Mode.INCONSISTENT),
        (1.0, -1.0, Mode.INDETERMINATE),
        (0.0, -1.0, Mode.SLIP),  # unique solution F_z = 0, w' = 0
    ],
)
def test_mode_boundaries_follow_the_lcp(b, p, want):
    got = an.mode(b, p)
    assert isinstance(got, Mode) and got is want
    # cross-check with the LCP 0 <= F perp pF + b >= 0 solved by enumeration
    sols = []
    if b >= 0:
        sols.append(0.0)  # F = 0 needs w' = b >= 0
    if p != 0 and -b / p > 0:
        sols.append(-b / p)
    if p == 0 and b == 0:
        sols.append(1.0)  # a continuum
    if not sols:
        assert want is Mode.INCONSISTENT
    elif len(sols) > 1:
        assert want is Mode.INDETERMINATE
    else:
        F = sols[0]
        assert want is (Mode.LIFTOFF if p * F + b > 0 else Mode.SLIP)


def test_mode_rejects_nan():
    with pytest.raises(ValueError, match=r"^b must be in \(-inf, inf\); got nan$"):
        an.mode(np.nan, 1.0)


@pytest.mark.parametrize("alpha", ALPHAS, ids=str)
def test_p_min_is_the_minimum_of_p_and_vanishes_at_mu_P(alpha):
    theta, varphi = np.meshgrid(np.linspace(1e-3, math.pi / 2 - 1e-3, 801), np.linspace(-math.pi + 1e-3, 0, 801))
    for mu in (0.0, 0.5, 1.3, 4.0):
        brute = an.p(theta, varphi, mu, alpha).min()
        assert cr.p_min(mu, alpha) <= brute <= cr.p_min(mu, alpha) + 1e-4 * (1 + alpha) * (1 + mu)
    assert cr.p_min(cr.mu_P(alpha), alpha) == pytest.approx(0.0, abs=ROOT_RESIDUAL.atol * (1 + alpha))
