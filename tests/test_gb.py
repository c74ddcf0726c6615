"""crosscheck.theory.gb: eq. f and its Jacobian, K, the GB manifold and the claims of sections 4-5."""

import math

import numpy as np
import pytest

from crosscheck import Outcome, SlipState
from crosscheck.theory import analytic, gb
from crosscheck.theory.critical import Psi_L, critical_values, mu_C, mu_P, theta_12, theta_pm
from crosscheck.theory.gb import GBType, Quadrant
from crosscheck.tolerances import CLOSED_FORM, FINITE_DIFFERENCE, GB_IDENTITY

ALPHA = 3.0
HALF_PI = math.pi / 2

# (mu, Psi) across mechanisms II and III and kinematic cases 3-6 (Fig. GBs_bif3); eta varies K only
MANIFOLD_CASES = [(1.4, 0.0), (1.4, 1.78), (1.4, 2.4789), (1.7, 1.062), (6.0, 0.0), (6.0, 1.8997), (6.0, 10.0024)]
ETAS = (0.5, 1.0, 10.0)


def gb_points(mu, Psi, *, n=41):
    """(m, 6) states on the GB manifold (eta column set later) from every curve."""
    curves = gb.gb_manifold(mu, Psi, ALPHA, n=n)
    assert curves, (mu, Psi)
    return np.concatenate([c.x(1.0) for c in curves])


def with_eta(x, eta):
    x = x.copy()
    x[:, 0] = eta
    return x


def random_gb_points(rng, n):
    return np.column_stack(
        [
            rng.uniform(0.2, 3, n),
            rng.uniform(-3, 0, n),
            rng.uniform(-1, 1, n),
            rng.uniform(-2, 2, n),
            rng.uniform(0.2, 1.4, n),
            rng.uniform(-2, 2, n),
        ]
    )


# ------------------------------------------------------------- f, J, A, B, K ---


def test_f_is_the_real_time_field_times_eta_p():
    # eq. f: f = eta p * (d/dt of eq. polareqs_varphi with F_z = -b/p), away from p = 0
    rng = np.random.default_rng(0)
    x = random_gb_points(rng, 20)
    eta, varphi, psi, Psi, theta, Theta = x.T
    b, p = analytic.b(Psi, Theta, theta), analytic.p(theta, varphi, 1.4, ALPHA)
    keep = np.abs(p) > 0.1
    y10 = np.column_stack([0 * eta, 0 * eta, 0 * eta, psi, theta, eta, varphi, 0 * eta, Psi, Theta])[keep]
    rt = analytic.scaled_rhs(y10, (-b / p)[keep], 1.4, ALPHA)
    want = (eta * p)[keep, None] * rt[:, [5, 6, 3, 8, 4, 9]]  # (eta, varphi, psi, Psi, theta, Theta)
    got = gb.f(x, 1.4, ALPHA)[keep]
    assert CLOSED_FORM.ok(got, want), np.max(np.abs(got - want))
    assert CLOSED_FORM.ok(got, [gb.slip_rhs(xi, 1.4, ALPHA) for xi in x[keep]])


@pytest.mark.parametrize("mu", [0.5, 1.4, 6.0])
def test_jacobian_matches_finite_differences(mu):
    rng = np.random.default_rng(int(mu * 10))
    x = random_gb_points(rng, 25)
    J = gb.jacobian(x, mu, ALPHA)
    h = 1e-6
    for j in range(6):
        e = np.zeros(6)
        e[j] = h
        fd = (gb.f(x + e, mu, ALPHA) - gb.f(x - e, mu, ALPHA)) / (2 * h)
        assert FINITE_DIFFERENCE.ok(J[:, :, j], fd), (j, np.max(np.abs(J[:, :, j] - fd)))


@pytest.mark.parametrize("mu, Psi", MANIFOLD_CASES, ids=str)
def test_K_closed_form_is_B_A_and_J_is_A_B_on_the_manifold(mu, Psi):
    for eta in ETAS:
        x = with_eta(gb_points(mu, Psi), eta)
        theta, varphi, Theta = x[:, 4], x[:, 1], x[:, 5]
        assert GB_IDENTITY.ok(gb.K(theta, varphi, Psi, Theta, eta, mu, ALPHA), gb.K_from_AB(x, mu, ALPHA))
        assert GB_IDENTITY.ok(gb.jacobian(x, mu, ALPHA), gb.matrix_A(x, mu, ALPHA) @ gb.matrix_B(x, mu, ALPHA))


def test_K_closed_form_needs_the_manifold():
    # off b = p = 0 the closed form drops terms: B A differs (so the test above can fail)
    x = np.array([[1.0, -1.8, 0.0, 0.3, 0.8, 0.5]])
    Kc = gb.K(0.8, -1.8, 0.3, 0.5, 1.0, 1.4, ALPHA)
    assert not GB_IDENTITY.ok(Kc, gb.K_from_AB(x, 1.4, ALPHA)[0])


@pytest.mark.parametrize("mu, Psi", MANIFOLD_CASES, ids=str)
def test_lemma_eigenvalues_of_J_are_those_of_K_and_four_zeros(mu, Psi):
    x = with_eta(gb_points(mu, Psi, n=11), 1.0)
    lamJ = np.linalg.eigvals(gb.jacobian(x, mu, ALPHA))
    lamK = np.linalg.eigvals(gb.K(x[:, 4], x[:, 1], Psi, x[:, 5], 1.0, mu, ALPHA))
    for lj, lk, J in zip(lamJ, lamK, gb.jacobian(x, mu, ALPHA)):
        scale = np.linalg.norm(J)
        order = np.argsort(np.abs(lj))
        zeros, rest = lj[order[:4]], lj[order[4:]]
        assert np.all(np.abs(zeros) <= 1e-9 * scale), zeros
        rest = rest[np.lexsort((rest.imag, rest.real))]
        lk = lk[np.lexsort((lk.imag, lk.real))]
        assert np.allclose(rest, lk, rtol=1e-8, atol=1e-9 * scale), (rest, lk)


def test_K_symmetry_eq_group():
    rng = np.random.default_rng(3)
    theta, varphi, Psi, Theta, eta = (
        rng.uniform(0.2, 1.4, 30),
        rng.uniform(-3, 0, 30),
        rng.normal(size=30),
        rng.normal(size=30),
        2.0,
    )
    assert CLOSED_FORM.ok(
        gb.K(theta, varphi, Psi, Theta, eta, 1.7, ALPHA), gb.K(theta, -math.pi - varphi, -Psi, Theta, eta, 1.7, ALPHA)
    )


# ------------------------------------------------------------------- det K ---


def test_det_K_identity_and_the_printed_prefactor():
    rng = np.random.default_rng(4)
    args = (
        rng.uniform(0.2, 1.4, 50),
        rng.uniform(-3, 0, 50),
        rng.normal(size=50),
        rng.normal(size=50),
        rng.uniform(0.1, 5, 50),
    )
    for mu in (1.0, 1.4, 6.0):
        Km = gb.K(*args, mu, ALPHA)
        want = Km[..., 0, 0] * Km[..., 1, 1] - Km[..., 0, 1] * Km[..., 1, 0]
        assert CLOSED_FORM.ok(gb.det_K(*args, mu, ALPHA), want)
        # eq. detK as printed lacks mu in its first prefactor: right only at mu = 1
        assert CLOSED_FORM.ok(gb.det_K_as_printed(*args, mu, ALPHA), want) == (mu == 1.0)


def test_det_K_is_a_multiple_of_the_conic_eq_detK0():
    # det K = (eta cos^5 theta / sin theta) (A Psi^2 + B Psi Theta + Gamma Psi - Delta Theta^2 - E Theta)
    rng = np.random.default_rng(5)
    theta, varphi, Psi, Theta, eta = (
        rng.uniform(0.2, 1.4, 50),
        rng.uniform(-3, 0, 50),
        rng.normal(size=50),
        rng.normal(size=50),
        rng.uniform(0.1, 5, 50),
    )
    for mu in (1.4, 6.0):
        factor = eta * np.cos(theta) ** 5 / np.sin(theta)
        got = factor * gb.detK0_residual(theta, varphi, Psi, Theta, eta, mu, ALPHA)
        assert CLOSED_FORM.ok(got, gb.det_K(theta, varphi, Psi, Theta, eta, mu, ALPHA))


def test_b0_ellipse_eq_B():
    rng = np.random.default_rng(6)
    theta, Psi, Theta = rng.uniform(0.2, 1.4, 40), rng.normal(size=40), rng.normal(size=40)
    M, N = gb.b0_coefficients(theta)
    # b = 0  <=>  M Psi^2 + Theta^2 = N, indeed b = (M Psi^2 + Theta^2 - N) sin theta
    assert CLOSED_FORM.ok(analytic.b(Psi, Theta, theta), (M * Psi**2 + Theta**2 - N) * np.sin(theta))


@pytest.mark.parametrize(
    "mu, Psi, eta", [(1.7, 1.062, 10.0), (1.4, 1.78, 1.0), (6.0, 1.8997, 1.0), (1.4, 0.0, 1.0)], ids=str
)
def test_quartic_roots_are_the_det_K_zeros_along_the_manifold(mu, Psi, eta):
    # zeros of det K found by bisection along each GB curve are roots of eq. Psiquartic at their (theta, varphi)
    found = 0
    for curve in gb.gb_manifold(mu, Psi, ALPHA, n=201):
        for theta, varphi, Theta in gb.det_K_zeros(curve, eta):
            Psis, Thetas = gb.psi_quartic_roots(theta, varphi, eta, mu, ALPHA)
            k = np.argmin(np.abs(Psis - Psi))
            assert abs(Psis[k] - Psi) < 1e-6 and abs(Thetas[k] - Theta) < 1e-6, (Psis, Thetas, Psi, Theta)
            found += 1
    assert found >= 2


# Fig. 16 setting: alpha = 3, eta = 1, mu = mu_P (1 + eps^2 mu_hat), varphi = -pi/2 + eps varphi_hat
def _quartic_root_errors(eps, mu_hat=1.0, varphi_hat=0.8):
    mu = float(mu_P(ALPHA)) * (1 + eps**2 * mu_hat)
    varphi = -HALF_PI + eps * varphi_hat
    want = np.sort(np.roots(gb.psi_quartic_eps(mu_hat, varphi_hat, ALPHA)).real)
    errs = []
    for theta in theta_pm(varphi, mu, ALPHA):
        got = np.roots(gb.psi_quartic(float(theta), varphi, 1.0, mu, ALPHA))
        assert np.all(np.abs(got.imag) < 1e-9)
        errs.append(np.sort(got.real) - want)
    return np.array(errs)  # (2 branches theta_-+, 4 roots)


def test_quartic_asymptotics_near_mu_P_converge_at_first_order():
    eps = np.array([0.02, 0.01, 0.005, 0.0025])
    err = np.array([np.max(np.abs(_quartic_root_errors(e))) for e in eps])
    rates = np.log2(err[:-1] / err[1:])
    assert np.all(np.abs(rates - 1.0) < 0.05), (err, rates)  # O(eps): theta_+- = theta_P +- eps theta_hat
    assert err[-1] < 0.01


@pytest.mark.parametrize("mu, eta", [(1.4, 1.0), (1.7, 1.0), (1.7, 10.0), (6.0, 1.0)], ids=str)
def test_ghastly_locates_the_zeros_of_det_K_at_Psi_0(mu, eta):
    count = 0
    for curve in gb.gb_manifold(mu, 0.0, ALPHA, n=201):
        for theta, varphi, Theta in gb.det_K_zeros(curve, eta):
            lhs = ALPHA * mu * math.cos(varphi) ** 2
            rhs = gb.ghastly(theta, eta, ALPHA, sign=np.sign(Theta))
            assert abs(lhs - rhs) < 1e-8 * abs(lhs), (theta, varphi, Theta, lhs, rhs)
            count += 1
    assert count >= 2


# ------------------------------------------------- classification, eigenvectors ---


@pytest.mark.parametrize(
    "Km, want",
    [
        ([[-1, 0], [0, -2]], GBType.STABLE_NODE),
        ([[1, 0], [0, 2]], GBType.UNSTABLE_NODE),
        ([[1, 0], [0, -2]], GBType.SADDLE),
        ([[-1, -2], [2, -1]], GBType.STABLE_FOCUS),
        ([[1, -2], [2, 1]], GBType.UNSTABLE_FOCUS),
        ([[0, 1], [0, -1]], GBType.DEGENERATE),
        ([[0, -1], [1, 0]], GBType.DEGENERATE),
        ([[-1, 0], [1, -1]], GBType.STABLE_NODE),
    ],
    ids=["snode", "unode", "saddle", "sfocus", "ufocus", "zero-eig", "centre", "jordan"],
)
def test_classify_known_matrices(Km, want):
    assert gb.gb_type(np.array(Km, float)) is want


def _planar(mu, which):
    """K at P+- / Q+- of the planar problem (varphi = -pi/2, Psi = 0), eta = 1."""
    th1, th2 = (float(t) for t in theta_12(mu, ALPHA))
    theta = th1 if which[0] == "P" else th2
    Theta = math.sqrt(1 / math.sin(theta)) * (1 if which[1] == "+" else -1)
    return theta, Theta, gb.K(theta, -HALF_PI, 0.0, Theta, 1.0, mu, ALPHA)


@pytest.mark.parametrize("mu", [1.4, 1.5, 1.7, 6.0])
@pytest.mark.parametrize("which", ["P+", "P-", "Q+", "Q-"])
def test_planar_eigenpairs_are_eqs_evalK2D_evecK2D(mu, which):
    theta, Theta, Km = _planar(mu, which)
    t = math.tan(theta)
    lam1, lam2 = Theta * (t - (1 + ALPHA) / t), -2 * Theta * t
    e1, e2 = np.array([3 * t**2 - (1 + ALPHA), 1.0]), np.array([0.0, 1.0])
    lam, vec = gb.eigen(Km)
    assert np.all(lam.imag == 0)
    for want_l, want_e in ((lam1, e1), (lam2, e2)):
        i = int(np.argmin(np.abs(lam.real - want_l)))
        assert CLOSED_FORM.ok(lam[i].real, want_l)
        v = vec[:, i].real
        assert abs(v[0] * want_e[1] - v[1] * want_e[0]) <= 1e-12 * np.linalg.norm(want_e)  # parallel


def test_lambda1_vanishes_at_mu_P_and_e11_at_mu_C():
    theta_P = float(theta_12(float(mu_P(ALPHA)), ALPHA)[0])
    t = math.tan(theta_P)
    assert abs(t - (1 + ALPHA) / t) < 1e-14  # lambda_1 / (eta Theta)
    theta_1 = float(theta_12(float(mu_C(ALPHA)), ALPHA)[0])
    assert abs(3 * math.tan(theta_1) ** 2 - (1 + ALPHA)) < 1e-13
    # and nowhere else nearby: the sign of e_11 flips across mu_C, lambda_1 < 0 above mu_P
    for mu, sign in ((1.5, +1), (1.6, -1)):
        assert np.sign(3 * math.tan(float(theta_12(mu, ALPHA)[0])) ** 2 - (1 + ALPHA)) == sign


@pytest.mark.parametrize("mu", [1.4, 1.5, 1.6, 1.7, 6.0])
def test_planar_P_plus_stable_node_Q_saddles_and_e1_quadrants(mu):
    assert gb.gb_type(_planar(mu, "P+")[2]) is GBType.STABLE_NODE
    assert gb.gb_type(_planar(mu, "P-")[2]) is GBType.UNSTABLE_NODE
    assert gb.gb_type(_planar(mu, "Q+")[2]) is GBType.SADDLE
    assert gb.gb_type(_planar(mu, "Q-")[2]) is GBType.SADDLE
    theta, _, Km = _planar(mu, "P+")
    lam, vec = gb.eigen(Km)
    lam1 = _planar(mu, "P+")[1] * (math.tan(theta) - (1 + ALPHA) / math.tan(theta))
    i1 = int(np.argmin(np.abs(lam.real - lam1)))
    want = Quadrant.I_III if mu < mu_C(ALPHA) else Quadrant.II_IV
    assert gb.quadrant(vec[:, i1]) is want
    # e_2's p component is K12 ~ cos^2(-pi/2) ~ 1e-32 in floating point: an axis up to rounding
    assert gb.quadrant(vec[:, 1 - i1], atol=1e-12) is Quadrant.B_AXIS
    assert gb.quadrant(vec[:, i1], atol=1e-12) is want


def _off_planar_points(sign):
    """GB samples with sign * Theta > 1e-4 and |cos varphi| > 1e-3, over several (mu, Psi, eta).

    Away from Theta = 0 (K21 = eta Theta cot theta -> 0) and varphi = -pi/2 (K12 -> 0), where the
    eigenvectors approach the axes and the quadrant statements degenerate.
    """
    out = []
    for mu, Psi in MANIFOLD_CASES:
        for c in gb.gb_manifold(mu, Psi, ALPHA, n=41):
            keep = (sign * c.Theta > 1e-4) & (np.abs(np.cos(c.varphi)) > 1e-3)
            for eta in ETAS:
                out.append(
                    np.column_stack(
                        [
                            c.theta[keep],
                            c.varphi[keep],
                            0 * c.theta[keep] + Psi,
                            c.Theta[keep],
                            0 * c.theta[keep] + eta,
                            0 * c.theta[keep] + mu,
                        ]
                    )
                )
    return np.concatenate(out)


def test_theorem_4_1_Theta_positive_eigenvectors_in_different_quadrants():
    pts = _off_planar_points(+1)
    theta, varphi, Psi, Theta, eta, mu = pts.T
    Km = gb.K(theta, varphi, Psi, Theta, eta, mu, ALPHA)
    lam, vec = gb.eigen(Km)
    assert np.all(lam.imag == 0)
    # eq. offdiagonals: product of the first components with e = (., 1) equals -K12/K21 < 0
    first = vec[..., 0, :].real / vec[..., 1, :].real
    product = first[:, 0] * first[:, 1]
    want = -Km[:, 0, 1] / Km[:, 1, 0]
    assert np.all(want < 0)
    assert np.allclose(product, want, rtol=1e-9, atol=0)
    # Theorem 4.1 (1): e_- (stable / strong / weakly unstable) in quadrants II-IV, e_+ in I-III
    assert np.all(gb.quadrant(vec[:, :, 1]) == Quadrant.II_IV)
    assert np.all(gb.quadrant(vec[:, :, 0]) == Quadrant.I_III)
    types = set(gb.gb_type(Km).tolist())
    assert types <= {GBType.STABLE_NODE, GBType.SADDLE, GBType.UNSTABLE_NODE}
    assert {GBType.STABLE_NODE, GBType.SADDLE, GBType.UNSTABLE_NODE} <= types  # all three are realised


def test_theorem_4_1_Theta_negative_no_stable_node_or_focus():
    pts = _off_planar_points(-1)
    theta, varphi, Psi, Theta, eta, mu = pts.T
    types = gb.gb_type(gb.K(theta, varphi, Psi, Theta, eta, mu, ALPHA))
    assert len(types) > 1000
    assert not np.any((types == GBType.STABLE_NODE) | (types == GBType.STABLE_FOCUS))
    assert np.any(types == GBType.UNSTABLE_FOCUS)  # the paper's numerical unstable foci at Psi != 0


# --------------------------------------------------------------- the manifold ---


@pytest.mark.parametrize(
    "mu, Psi, want",
    [
        (1.4, 0.0, [(False, 1), (False, -1)]),  # case 3: Theta > 0 and Theta < 0 loops
        (1.4, 1.78, [(False, 1), (False, -1)]),  # case 4 (Psi_L < Psi < Psi_1, mechanism II)
        (1.4, 2.4789, [(True, 0)]),  # case 6: one loop through Theta = 0
        (1.4, 3.1, []),  # case 7: |Psi| > Psi_2 = 3.0097
        (6.0, 0.0, [(False, 1), (False, -1)]),
        (6.0, -1.8997, [(True, 0), (True, 0)]),  # case 5 (mechanism III): two loops, each through Theta = 0
        (6.0, 10.0024, [(True, 0)]),
        (6.0, 18.0, []),  # Psi_2 = 17.8171
        (1.3, 0.0, []),  # mu < mu_P: no paradox, no manifold
    ],
    ids=str,
)
def test_manifold_topology_across_Psi_L_Psi_1_Psi_2(mu, Psi, want):
    curves = gb.gb_manifold(mu, Psi, ALPHA, n=201)
    assert [(c.crosses_zero, c.sign) for c in curves] == want
    for c in curves:
        assert np.max(np.abs(analytic.b(Psi, c.Theta, c.theta))) < 1e-12
        assert np.max(np.abs(analytic.p(c.theta, c.varphi, mu, ALPHA))) < 1e-12
        ends = np.array([c.theta[0] - c.theta[-1], c.varphi[0] - c.varphi[-1], c.Theta[0] - c.Theta[-1]])
        assert np.all(ends == 0)  # closed
        steps = np.hypot(np.hypot(np.diff(c.theta), np.diff(c.varphi)), np.diff(c.Theta))
        assert steps.max() < 0.1  # connected samples (no jump between branches)


def test_manifold_thresholds_are_the_critical_values():
    cv = critical_values(1.4, ALPHA)
    assert cv.Psi_1 == pytest.approx(1.9480, abs=1e-4) and cv.Psi_2 == pytest.approx(3.0097, abs=1e-4)
    below = lambda P: [(c.crosses_zero, c.sign) for c in gb.gb_manifold(1.4, P, ALPHA, n=51)]  # noqa: E731
    assert below(Psi_L * 0.999) == below(cv.Psi_1 * 0.999) == [(False, 1), (False, -1)]
    assert below(cv.Psi_1 * 1.001) == below(cv.Psi_2 * 0.999) == [(True, 0)]
    assert below(cv.Psi_2 * 1.001) == []
    assert gb.gb_theta_gap(Psi_L * 0.999) is None
    ga, gb_ = gb.gb_theta_gap(cv.Psi_1)
    assert ga == pytest.approx(cv.theta_1, abs=1e-12) or gb_ == pytest.approx(cv.theta_1, abs=1e-12)


@pytest.mark.parametrize(
    "mu, theta, varphi",
    [
        (1.4, 0.9702, -HALF_PI),
        (1.4, 1.0094, -1.7832),
        (1.4, 1.0953, -1.8793),
        (1.4, 1.1872, -1.7978),
        (1.4, 1.2209, -HALF_PI),
        (1.7, 0.7692, -HALF_PI),
        (1.7, 0.8517, -1.9969),
        (1.7, 1.0227, -2.2143),
        (1.7, 1.2562, -2.1107),
        (1.7, 1.3333, -HALF_PI),
    ],
    ids=str,
)
def test_printed_GB_points_of_figs_8_9_lie_on_p_0(mu, theta, varphi):
    # to printed precision: |p| <= |grad p| * 5e-5 (half a unit in the 4th decimal of theta and varphi)
    p_theta = ALPHA * (
        math.cos(theta) * (mu * math.cos(theta) * math.sin(varphi) - math.sin(theta))
        + math.sin(theta) * (-mu * math.sin(theta) * math.sin(varphi) - math.cos(theta))
    )
    p_varphi = ALPHA * mu * math.sin(theta) * math.cos(theta) * math.cos(varphi)
    assert abs(analytic.p(theta, varphi, mu, ALPHA)) <= 5e-5 * (abs(p_theta) + abs(p_varphi))


def test_fig_9d_prints_varphi_with_the_wrong_sign():
    # Fig. 13(d) prints (1.2562, 2.1107): outside (-pi, 0] and far from p = 0; -2.1107 is on it
    assert analytic._p(1.2562, 2.1107, 1.7, ALPHA) > 2.5
    assert abs(analytic.p(1.2562, -2.1107, 1.7, ALPHA)) < 1e-4


@pytest.mark.parametrize("mu, theta, varphi", [(1.4, 1.0953, -1.8793), (1.7, 1.0227, -2.2143)], ids=str)
def test_figs_8c_9c_are_the_zero_eigenvalue_points(mu, theta, varphi):
    # panels (c): "lambda_+ passes through zero", eta = 1, Psi = 0, Theta = sqrt(csc theta)
    curve = gb.gb_manifold(mu, 0.0, ALPHA, n=201)[0]
    zeros = gb.det_K_zeros(curve, 1.0)
    k = np.argmin(np.abs(zeros[:, 0] - theta) + np.abs(zeros[:, 1] - varphi))
    assert abs(zeros[k, 0] - theta) < 5e-5 and abs(zeros[k, 1] - varphi) < 5e-5, zeros


# ------------------------------------------------- section 4 claims on the flow ---


@pytest.mark.parametrize("mu, varphi", [(1.4, -1.8), (1.7, -2.2), (6.0, -0.7)], ids=str)
def test_pdotarg_is_the_limit_of_p_dp_dt(mu, varphi):
    # eq. pdotarg vs the derivative of p along the real-time flow (F_z = normal_force) at p = delta -> 0
    theta0 = float(theta_pm(varphi, mu, ALPHA)[0])  # p(theta0, varphi) = 0
    Psi, Theta, eta = 0.4, 0.3, 1.3
    want = float(gb.p_dot_on_p0(theta0, varphi, Psi, Theta, eta, mu, ALPHA))
    errs = []
    for dtheta in (1e-3, 1e-4, 1e-5):
        theta = theta0 - dtheta  # p > 0 just below theta_-
        pp = float(analytic.p(theta, varphi, mu, ALPHA))
        y = np.array([0, 0, 0, 0, theta, eta, varphi, 0, Psi, Theta], float)
        fz = float(analytic.normal_force(Psi, Theta, theta, varphi, mu, ALPHA))
        dy = analytic.scaled_rhs(y, fz, mu, ALPHA)
        x = np.array([eta, varphi, 0, Psi, theta, Theta])
        grad_p = gb.matrix_B(x, mu, ALPHA)[0]  # dp/dx in X_STATE order
        dp_dt = grad_p[1] * dy[6] + grad_p[4] * dy[4]
        errs.append(abs(pp * dp_dt - want))
    assert errs[-1] < 1e-4 * abs(want) and errs[0] > 5 * errs[-1]  # converges as p -> 0
    assert np.sign(want) == np.sign(analytic.b(Psi, Theta, theta0)) == -1  # sign(p') = sign(b)


@pytest.mark.parametrize("mu", [1.34, 1.4, 1.7, 6.0])
def test_corollary_4_2_open_set_reaches_p_0_with_b_negative(mu):
    # for mu > mu_P pick varphi with mu > mu_P*(varphi) and start just outside p < 0 (Theta = Psi = 0, b = -1)
    assert mu > mu_P(ALPHA)
    varphi = -HALF_PI - 0.5 * math.acos(float(mu_P(ALPHA)) / mu)
    t_minus, t_plus = (float(t) for t in theta_pm(varphi, mu, ALPHA))
    width = t_plus - t_minus
    start = SlipState(theta=t_minus - 0.01 * width, varphi=varphi, Theta=0.0, Psi=0.0, eta=1.0)
    r = gb.slip_until_event(start, mu, ALPHA)
    assert r.outcome is Outcome.JAM and r.b < -0.5 and 0 < r.time < 1
    rng = np.random.default_rng(42)
    x0 = np.array([start.theta, start.varphi, start.Theta, start.Psi, start.eta])
    scale = np.array([1e-3 * width, 1e-3, 1e-3, 1e-3, 1e-3])
    directions = np.concatenate([np.eye(5), -np.eye(5), rng.normal(size=(10, 5))])
    for d in directions:
        x = x0 + scale * d / np.linalg.norm(d)
        s = SlipState(theta=x[0], varphi=x[1], Theta=x[2], Psi=x[3], eta=x[4])
        assert gb.slip_until_event(s, mu, ALPHA).outcome is Outcome.JAM, d


def test_fig_13_initial_conditions_straddle_the_separatrix():
    # both start slipping near the GB manifold (b < 0 < p); one reaches p = 0, the other lifts off
    md1 = SlipState(theta=1.1067, eta=2.1307, varphi=-1.8913, Psi=-0.1027, Theta=0.9)
    md2 = SlipState(theta=1.1031, eta=2.0, varphi=-1.9233, Psi=0.0, Theta=0.9)
    for s in (md1, md2):
        assert analytic.b(s.Psi, s.Theta, s.theta) < 0 < analytic.p(s.theta, s.varphi, 1.4, ALPHA) < 0.03
    r1, r2 = (gb.slip_until_event(s, 1.4, ALPHA) for s in (md1, md2))
    assert (r1.outcome, r2.outcome) == (Outcome.JAM, Outcome.LIFTOFF)
    assert r1.b < 0 and r2.p > 0 and max(r1.time, r2.time) < 0.05
