"""Pinocchio's rod (crosscheck.engines.pinocchio.model) against the paper, state by state.

Real Pinocchio, seeded random rods and states.  Allowances are atol * scale
with the tolerances and term scales of the Pinocchio section of
crosscheck.tolerances (quantities that go through M^-1 carry the condition
number 1/cos^2 theta of M; aba carries 1/cos theta; see there for why).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from crosscheck import tolerances as tol
from crosscheck.coordinates import GENERALIZED, paper_to_qv, tip_position
from crosscheck.engines.pinocchio import model as pinrod
from crosscheck.engines.pinocchio import tolerances as pinocchio_tol
from crosscheck.engines.pinocchio.studies.dynamics_reference import scaled_matrices
from crosscheck.rod import Rod
from crosscheck.theory import analytic
from crosscheck.theory.critical import mu_P

EPS = np.finfo(float).eps

#: Random physical rods (m, l, I0, g): arbitrary units, alpha from 0.5 to 20.
RODS = {
    "uniform": Rod.uniform(mass=1.0, length=0.5, gravity=9.81),
    "heavy-short": Rod(mass=7.3, length=0.13, inertia=7.3 * 0.13**2 / 17.0, gravity=3.7),
    "light-long": Rod(mass=0.21, length=4.2, inertia=0.21 * 4.2**2 / 0.6, gravity=19.0),
    "scaled-alpha-3": Rod.scaled(3.0),
}


def random_states(rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    """Scaled states: thirds with theta uniform, theta in [1e-8, 1e-1] (near 0) and cos theta in [3e-3, 3e-2] (~1e-2)."""
    third = n // 3
    theta = np.concatenate(
        (
            rng.uniform(1e-3, math.pi / 2 - 1e-3, n - 2 * third),
            10.0 ** rng.uniform(-8, -1, third),
            np.arccos(10.0 ** rng.uniform(-2.5, -1.5, third)),
        )
    )
    return {
        "theta": theta,
        "varphi": -math.pi * rng.uniform(0, 1, n),
        "Theta": rng.uniform(-5, 5, n),
        "Psi": rng.uniform(-5, 5, n),
        "eta": rng.uniform(0, 3, n),
        "psi": rng.uniform(-math.pi, math.pi, n),
        "F": rng.standard_normal((n, 3)),
        "mu": rng.uniform(0, 5, n),
    }


def assert_within(got, want, tolerance, scale, what: str) -> None:
    """|got - want| <= tolerance.atol * scale + tolerance.rtol * |want| entry by entry."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    scale = np.asarray(scale, float)
    scale = scale.reshape(scale.shape + (1,) * (want.ndim - scale.ndim))
    allowed = tolerance.atol * scale + tolerance.rtol * np.abs(want)
    ratio = np.abs(got - want) / allowed
    worst = np.unravel_index(np.argmax(ratio), ratio.shape)
    assert ratio.max() <= 1.0, (
        f"{what}: error {ratio.max():.3g} x allowance at {worst}: got {got[worst]!r}, want {want[worst]!r}"
    )


# --------------------------------------------------------------------------
# The model itself
# --------------------------------------------------------------------------


@pytest.mark.parametrize("name", RODS, ids=str)
def test_model_is_the_chain_of_single_axis_joints_with_the_singular_inertia(name):
    rod = RODS[name]
    model = pinrod.build_model(rod)
    assert (model.nq, model.nv, model.njoints) == (5, 5, 6)
    assert tuple(model.names[1:]) == GENERALIZED
    assert [model.joints[i].shortname() for i in range(1, 6)] == [
        "JointModelPX",
        "JointModelPY",
        "JointModelPZ",
        "JointModelRZ",
        "JointModelRX",
    ]
    body = model.inertias[5]
    assert body.mass == rod.mass
    np.testing.assert_array_equal(body.lever, np.zeros(3))
    # Taken as it is, no regularisation: exactly diag(I0, 0, I0) about S.
    np.testing.assert_array_equal(body.inertia, np.diag([rod.inertia, 0.0, rod.inertia]))
    assert all(model.inertias[i].mass == 0.0 for i in range(1, 5))
    frame = model.frames[model.getFrameId(pinrod.TIP_FRAME)]
    assert frame.parentJoint == 5
    np.testing.assert_array_equal(frame.placement.translation, [0.0, -rod.length, 0.0])
    np.testing.assert_array_equal(frame.placement.rotation, np.eye(3))
    np.testing.assert_array_equal(model.gravity.linear, [0.0, 0.0, -rod.gravity])


def test_tip_frame_is_at_A_of_eq_tipfromcentre():
    rng = np.random.default_rng(1)
    rod = RODS["heavy-short"]
    q = np.column_stack(
        (rng.uniform(-2, 2, (200, 3)), rng.uniform(-math.pi, math.pi, 200), rng.uniform(0, math.pi / 2, 200))
    )
    got = pinrod.engine(rod).tip_position(q)
    assert_within(
        got, tip_position(rod, q), pinocchio_tol.PIN_MATRICES, rod.length + np.abs(q[:, :3]).sum(1), "tip position"
    )


def test_body_rotation_is_Rz_psi_Rx_theta_eq_rotmatrix():
    rod = RODS["uniform"]
    e = pinrod.engine(rod)
    psi, theta = 0.7, 1.1
    pin.forwardKinematics(e.model, e.data, np.array([0.1, 0.2, 0.3, psi, theta]))
    cp, sp, c, s = math.cos(psi), math.sin(psi), math.cos(theta), math.sin(theta)
    Rz = np.array([[cp, -sp, 0], [sp, cp, 0], [0, 0, 1]])
    Rx = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    np.testing.assert_allclose(e.data.oMi[5].rotation, Rz @ Rx, rtol=0, atol=4 * EPS)


# --------------------------------------------------------------------------
# Tip accelerations: eq. linode2 by two independent routes
# --------------------------------------------------------------------------


def _tip_case(rod, rng, n=600):
    s = random_states(rng, n)
    om = rod.omega
    args = (s["psi"], s["theta"], s["Psi"] * om, s["Theta"] * om, s["F"] * rod.force_scale)
    want = analytic.tip_acceleration(rod, *args) / rod.gravity
    # Term scale in units of g: force terms (1 + alpha)|F|_1, velocity terms (with the linear velocity
    # of S at eta = 0, |v_s|_1 <= 2 (|Psi| + |Theta|)), gravity 1.
    V = (1 + 3 * (np.abs(s["Psi"]) + np.abs(s["Theta"]))) ** 2
    A = (1 + rod.alpha) * np.abs(s["F"]).sum(1) + V
    return s, args, want, A


@pytest.mark.parametrize("name", RODS, ids=str)
def test_tip_acceleration_by_aba_equals_eq_linode2(name):
    rod = RODS[name]
    s, args, want, A = _tip_case(rod, np.random.default_rng(10))
    got = pinrod.tip_acceleration(rod, *args, route="aba") / rod.gravity
    cos = np.cos(s["theta"])
    assert_within(got, want, pinocchio_tol.PIN_TIP_ACCELERATION, A / cos, "aba route")
    # The required bound itself: 1e-12 of the term scale, met everywhere here (cos theta >= 3e-3).
    assert_within(got, want, tol.Tolerance(1e-12, 0.0, "required 1e-12 of the term scale"), A, "aba route, 1e-12")


@pytest.mark.parametrize("name", RODS, ids=str)
def test_tip_acceleration_by_delassus_equals_eq_linode2(name):
    rod = RODS[name]
    s, args, want, A = _tip_case(rod, np.random.default_rng(11))
    got = pinrod.tip_acceleration(rod, *args, route="delassus") / rod.gravity
    cos = np.cos(s["theta"])
    assert_within(got, want, pinocchio_tol.PIN_THROUGH_MINV, A / cos**2, "G F + free")
    # 1e-12 of the term scale holds where the condition number 1/cos^2 theta of M allows it.
    ok = cos >= 0.02
    assert ok.sum() > 300
    assert_within(
        got[ok],
        want[ok],
        tol.Tolerance(1e-12, 0.0, "required 1e-12 of the term scale"),
        A[ok],
        "G F + free, 1e-12, cos >= 0.02",
    )


@pytest.mark.parametrize("route", pinrod.ROUTES, ids=str)
@pytest.mark.parametrize(
    "shapes",
    [((), (3,)), ((7,), (3,)), ((7,), (7, 3)), ((2, 1), (4, 3)), ((), (5, 3))],
    ids=["scalar", "array-one-force", "array-forces", "broadcast-2d", "scalar-state-many-forces"],
)
def test_tip_acceleration_broadcasts_like_the_reference(route, shapes):
    state_shape, force_shape = shapes
    rng = np.random.default_rng(12)
    rod = RODS["light-long"]
    psi, theta, pd, td = (rng.uniform(0.1, 1.4, state_shape) for _ in range(4))
    F = rng.standard_normal(force_shape)
    want = analytic.tip_acceleration(rod, psi, theta, pd, td, F)
    got = pinrod.tip_acceleration(rod, psi, theta, pd, td, F, route=route)
    assert got.shape == want.shape
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * rod.gravity * (1 + rod.alpha) * (1 + np.abs(F).sum()))


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"theta": 2.0}, "theta must be in (0, pi/2); got 2.0"),
        ({"theta": 0.0}, "theta must be in (0, pi/2); got 0.0"),
        ({"force": [1.0, 2.0]}, "force must have shape (..., 3) (Fx, Fy, Fz in the world frame); got (2,)"),
        ({"psi_dot": float("nan")}, "psi_dot must be in (-inf, inf); got nan"),
        ({"route": "crba"}, "route must be one of delassus, aba; got 'crba'"),
    ],
    ids=["theta-too-big", "theta-zero", "force-shape", "nan-rate", "bad-route"],
)
def test_bad_input_raises_the_reference_messages(kwargs, message):
    args = {"psi": 0.1, "theta": 0.5, "psi_dot": 1.0, "theta_dot": 1.0, "force": [0.0, 0.0, 1.0]} | kwargs
    with pytest.raises(ValueError) as err:
        pinrod.tip_acceleration(RODS["uniform"], **args)
    assert str(err.value) == message
    ref_args = {k: v for k, v in args.items() if k != "route"}
    if "route" not in kwargs:  # the reference raises the very same message
        with pytest.raises(ValueError, match=None) as ref_err:
            analytic.tip_acceleration(RODS["uniform"], **ref_args)
        assert str(ref_err.value) == message


# --------------------------------------------------------------------------
# M, C, g against eqs. rotode and linode written out as matrices
# --------------------------------------------------------------------------


def reference_matrices(rod: Rod, q, v):
    """Eqs. linode (m X'' = F_x, ..., m Z'' = F_z - m g) and rotode times I0 cos^2 theta, I0 (see crosscheck.engines.pinocchio.studies.dynamics_reference.reference_terms)."""
    m, i0, g = rod.mass, rod.inertia, rod.gravity
    _, _, _, psi, theta = q
    _, _, _, psi_dot, theta_dot = v
    s, c = math.sin(theta), math.cos(theta)
    M = np.array(
        [
            [m, 0, 0, 0, 0],
            [0, m, 0, 0, 0],
            [0, 0, m, 0, 0],
            [0, 0, 0, i0 * c**2, 0],
            [0, 0, 0, 0, i0],
        ],
        dtype=float,
    )
    C = np.array(
        [
            [0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0],
            [0, 0, 0, -i0 * s * c * theta_dot, -i0 * s * c * psi_dot],
            [0, 0, 0, i0 * s * c * psi_dot, 0],
        ],
        dtype=float,
    )
    gravity = np.array([0, 0, m * g, 0, 0], dtype=float)
    return M, C, gravity


@pytest.mark.parametrize("name", RODS, ids=str)
def test_M_C_g_equal_eqs_rotode_linode_entry_by_entry(name):
    rod = RODS[name]
    s = random_states(np.random.default_rng(20), 300)
    q, v = paper_to_qv(rod, s["theta"], s["varphi"], s["Theta"], s["Psi"], s["eta"], s["psi"])
    terms = pinrod.engine(rod).terms(q, v)
    want = [reference_matrices(rod, qi, vi) for qi, vi in zip(q, v)]
    got_M, got_C, got_g = scaled_matrices(rod, terms.M, terms.C, terms.g)
    want_M, want_C, want_g = scaled_matrices(rod, *(np.array(x) for x in zip(*want)))
    rates = 1 + np.abs(v * np.array([1, 1, 1, rod.length, rod.length]) / (rod.length * rod.omega)).sum(1)
    assert_within(got_M, want_M, pinocchio_tol.PIN_MATRICES, 1.0, "M")
    assert_within(got_C, want_C, pinocchio_tol.PIN_MATRICES, rates, "C")
    assert_within(got_g, want_g, pinocchio_tol.PIN_MATRICES, 1.0, "g")
    # The equations themselves: M a + C v + g = J^T F reproduces eq. rotode.
    F = s["F"] * rod.force_scale
    generalized_force = np.einsum("nij,ni->nj", terms.J, F) - np.array([w[1] @ vi + w[2] for w, vi in zip(want, v)])
    a = np.linalg.solve(np.array([w[0] for w in want]), generalized_force[..., None])[..., 0]
    rot = analytic.rotational_acceleration(rod, s["psi"], s["theta"], v[:, 3], v[:, 4], F)
    np.testing.assert_allclose(a[:, [4, 3]], rot, rtol=1e-9, atol=1e-9 * rod.omega**2)


# --------------------------------------------------------------------------
# Identities
# --------------------------------------------------------------------------


def _fd_step() -> float:
    # Balances rounding eps f / h against truncation h^2 f''' / 6 for f''' ~ f.
    return (3 * EPS) ** (1 / 3)


@pytest.mark.parametrize("name", RODS, ids=str)
def test_coriolis_identities(name):
    rod = RODS[name]
    e = pinrod.engine(rod)
    s = random_states(np.random.default_rng(30), 120)
    q, v = paper_to_qv(rod, s["theta"], s["varphi"], s["Theta"], s["Psi"], s["eta"], s["psi"])
    terms = e.terms(q, v)
    # C(q, 0) = 0 exactly, and nonLinearEffects(q, 0) = g exactly.
    at_rest = e.terms(q, np.zeros_like(v))
    np.testing.assert_array_equal(at_rest.C, 0.0)
    np.testing.assert_array_equal(at_rest.nle, at_rest.g)
    # C v + g = nonLinearEffects (RNEA), in scaled units.
    Cv_g = scaled_matrices(rod, terms.M, terms.C, np.einsum("nij,nj->ni", terms.C, v) + terms.g)[2]
    nle = scaled_matrices(rod, terms.M, terms.C, terms.nle)[2]
    rates = 1 + np.abs(v * np.array([1, 1, 1, rod.length, rod.length]) / (rod.length * rod.omega)).sum(1)
    assert_within(Cv_g, nle, pinocchio_tol.PIN_MATRICES, rates**2, "C v + g vs nle")
    # M' - 2C is skew-symmetric, with M' = dM/dt along v by central differences.
    h = _fd_step()
    Mdot = (e.mass_matrix(q + h * v) - e.mass_matrix(q - h * v)) / (2 * h)
    N = Mdot - 2 * terms.C
    # Bound: rounding of M entries eps (m + I0) / h, truncation h^2/6 |d^3 M/dt^3| <= h^2/6 * 4 I0 |theta'|^3
    # (only M_psipsi = I0 cos^2 theta varies); C's own rounding eps (m + I0)|v| is far below.
    fd_bound = EPS * (rod.mass + rod.inertia) / h + h**2 / 6 * 4 * rod.inertia * np.abs(v[:, 4]) ** 3
    assert_within(N + np.swapaxes(N, 1, 2), 0.0 * N, pinocchio_tol.PIN_FINITE_DIFFERENCE, 2 * fd_bound, "M' - 2C skew")
    assert_within(
        Mdot, terms.C + np.swapaxes(terms.C, 1, 2), pinocchio_tol.PIN_FINITE_DIFFERENCE, fd_bound, "M' = C + C^T"
    )
    # The check has teeth: a C with the same C v but the psi row lumped into C[psi, psi] is not skew.
    wrong = terms.C.copy()
    wrong[:, 3, 3] = 2 * terms.C[:, 3, 3]
    wrong[:, 3, 4] = 0.0
    Nw = Mdot - 2 * wrong
    np.testing.assert_allclose(
        np.einsum("nij,nj->ni", wrong, v),
        np.einsum("nij,nj->ni", terms.C, v),
        rtol=0,
        atol=1e-12 * rod.inertia * (np.abs(v[:, 3:]).sum(1) ** 2).max(),
    )
    assert np.abs(Nw + np.swapaxes(Nw, 1, 2)).max() > 1e3 * pinocchio_tol.PIN_FINITE_DIFFERENCE.atol * fd_bound.max()


@pytest.mark.parametrize("name", RODS, ids=str)
def test_tip_jacobian_and_its_time_variation_against_finite_differences(name):
    rod = RODS[name]
    e = pinrod.engine(rod)
    s = random_states(np.random.default_rng(40), 90)
    q, v = paper_to_qv(rod, s["theta"], s["varphi"], s["Theta"], s["Psi"], s["eta"], s["psi"], tip=(0.5, -1.5, 0.0))
    terms = e.terms(q, v)
    h = _fd_step()
    l = rod.length
    # J: columns by central differences of Pinocchio's tip position.  Rounding of positions
    # eps (|S| + l); truncation h^2/6 |d^3 tip/dq^3| <= h^2/6 l (angles) and 0 (translations).
    fd_J = np.empty_like(terms.J)
    for j in range(5):
        dq = np.zeros(5)
        dq[j] = h
        fd_J[:, :, j] = (e.tip_position(q + dq) - e.tip_position(q - dq)) / (2 * h)
    bound_J = 2 * EPS * (np.abs(q[:, :3]).sum(1) + l) / h + h**2 / 6 * l
    assert_within(fd_J, terms.J, pinocchio_tol.PIN_FINITE_DIFFERENCE, bound_J, "J vs finite differences")
    # dJ: J along q + t v, so dJ = d/dt J(q + t v).  J entries are l times products of sines and
    # cosines of psi, theta: rounding eps l, third time derivative <= l (|psi'| + |theta'|)^3.
    fd_dJ = (e.jacobian(q + h * v) - e.jacobian(q - h * v)) / (2 * h)
    w = np.abs(v[:, 3]) + np.abs(v[:, 4])
    bound_dJ = 2 * EPS * l / h + h**2 / 6 * l * w**3
    assert_within(fd_dJ, terms.dJ, pinocchio_tol.PIN_FINITE_DIFFERENCE, bound_dJ, "dJ vs finite differences")
    # The tip velocity J v is the derivative of eq. tipfromcentre: slip heading beta = psi + varphi, speed eta.
    tip_v = np.einsum("nij,nj->ni", terms.J, v) / (l * rod.omega)
    np.testing.assert_allclose(
        tip_v[:, 0], s["eta"] * np.cos(s["psi"] + s["varphi"]), rtol=0, atol=1e-12 * (1 + np.abs(v).sum(1).max())
    )
    np.testing.assert_allclose(
        tip_v[:, 1], s["eta"] * np.sin(s["psi"] + s["varphi"]), rtol=0, atol=1e-12 * (1 + np.abs(v).sum(1).max())
    )
    np.testing.assert_allclose(tip_v[:, 2], 0.0, rtol=0, atol=1e-12 * (1 + np.abs(v).sum(1).max()))


def test_aba_is_the_inverse_of_rnea_with_the_singular_inertia():
    # No regularisation is needed: aba and rnea are mutual inverses at |cos theta| = 1e-3 too.
    rod = RODS["uniform"]
    e = pinrod.engine(rod)
    rng = np.random.default_rng(50)
    for theta in (1e-6, 0.7, math.acos(1e-3)):
        q = np.array([0.3, -0.1, 0.2, rng.uniform(-3, 3), theta])
        v, tau = rng.standard_normal(5), rng.standard_normal(5)
        a = pin.aba(e.model, e.data, q, v, tau).copy()
        back = pin.rnea(e.model, e.data, q, v, a)
        np.testing.assert_allclose(back, tau, rtol=0, atol=1e-13 * (1 + np.abs(tau).max()))


# --------------------------------------------------------------------------
# b, p, normal force, mode, mu_P
# --------------------------------------------------------------------------


def test_b_equals_eq_b():
    rng = np.random.default_rng(60)
    s = random_states(rng, 900)
    got = pinrod.b(s["Psi"], s["Theta"], s["theta"])
    V = (
        3 + 3 * (np.abs(s["Psi"]) + np.abs(s["Theta"]))
    ) ** 2  # (1 + |v_s|_1)^2 at eta = 1: |v_s|_1 <= 2 + 3(|Psi| + |Theta|)
    assert_within(got, analytic.b(s["Psi"], s["Theta"], s["theta"]), pinocchio_tol.PIN_SLIP, V, "b")


def test_p_equals_eq_p():
    rng = np.random.default_rng(61)
    s = random_states(rng, 900)
    alpha = rng.choice([0.5, 1.0, 3.0, 7.0, 20.0], 900)
    got = pinrod.p(s["theta"], s["varphi"], s["mu"], alpha)
    assert_within(
        got,
        analytic.p(s["theta"], s["varphi"], s["mu"], alpha),
        pinocchio_tol.PIN_SLIP,
        (1 + alpha) * (1 + s["mu"]),
        "p",
    )
    assert got.shape == (900,) and np.ndim(pinrod.p(0.5, -1.0, 1.0, 3.0)) == 0


@pytest.mark.parametrize("name", RODS, ids=str)
def test_b_and_p_of_physical_rods_do_not_depend_on_m_l_I0_g_or_psi(name):
    # slip_coefficients scales Pinocchio's physical free acceleration and Delassus row to the paper's
    # units: the result must be eqs. b and p with alpha = m l^2 / I0, whatever psi.
    rod = RODS[name]
    s = random_states(np.random.default_rng(62), 300)
    q, v = paper_to_qv(rod, s["theta"], s["varphi"], s["Theta"], s["Psi"], s["eta"], s["psi"])
    bb, pp = pinrod.slip_coefficients(rod, pinrod.engine(rod).terms(q, v), s["psi"] + s["varphi"], s["mu"])
    V = (1 + 2 * s["eta"] + 3 * (np.abs(s["Psi"]) + np.abs(s["Theta"]))) ** 2
    assert_within(bb, analytic.b(s["Psi"], s["Theta"], s["theta"]), pinocchio_tol.PIN_SLIP, V, "b")
    assert_within(
        pp,
        analytic.p(s["theta"], s["varphi"], s["mu"], rod.alpha),
        pinocchio_tol.PIN_SLIP,
        (1 + rod.alpha) * (1 + s["mu"]),
        "p",
    )


def test_normal_force_equals_eq_FZ():
    rng = np.random.default_rng(63)
    s = random_states(rng, 300)
    got = pinrod.normal_force(s["Psi"], s["Theta"], s["theta"], s["varphi"], s["mu"], 3.0)
    want = analytic.normal_force(s["Psi"], s["Theta"], s["theta"], s["varphi"], s["mu"], 3.0)
    # -b/p: relative errors of b and p add, each <= PIN_SLIP.atol * scale / |.|
    pp = np.abs(analytic.p(s["theta"], s["varphi"], s["mu"], 3.0))
    bb = np.abs(analytic.b(s["Psi"], s["Theta"], s["theta"]))
    V = (3 + 3 * (np.abs(s["Psi"]) + np.abs(s["Theta"]))) ** 2
    allowed = pinocchio_tol.PIN_SLIP.atol * (V / pp + bb * 4 * (1 + s["mu"]) / pp**2)
    assert np.all(np.abs(got - want) <= allowed)


def test_mode_agrees_on_10000_random_states():
    rng = np.random.default_rng(64)
    n = 10_000
    theta = rng.uniform(1e-6, math.pi / 2 - 1e-6, n)
    varphi = -math.pi * rng.uniform(0, 1, n)
    Theta, Psi = rng.uniform(-4, 4, (2, n))
    mu = rng.uniform(0, 5, n)
    alpha = rng.choice([0.5, 1.0, 3.0, 10.0], n)
    want_b, want_p = analytic.b(Psi, Theta, theta), analytic.p(theta, varphi, mu, alpha)
    got = pinrod.mode(pinrod.b(Psi, Theta, theta), pinrod.p(theta, varphi, mu, alpha))
    want = analytic.mode(want_b, want_p)
    # No state of this seed lies on a mode boundary (within the allowance of b or p), so every mode must match.
    V = (3 + 3 * (np.abs(Psi) + np.abs(Theta))) ** 2
    assert not np.any(
        (np.abs(want_b) <= pinocchio_tol.PIN_SLIP.atol * V)
        | (np.abs(want_p) <= pinocchio_tol.PIN_SLIP.atol * (1 + alpha) * (1 + mu))
    )
    np.testing.assert_array_equal(got, want)
    assert set(np.unique(want)) == {int(m) for m in analytic.Mode}  # all four modes are exercised


@pytest.mark.parametrize("alpha", [0.5, 1.0, 3.0, 10.0, 20.0], ids=lambda a: f"alpha={a}")
def test_mu_P_from_pinocchio_p_alone_equals_eq_mup2D(alpha):
    got = pinrod.mu_P(alpha)
    want = 2 * math.sqrt(1 + alpha) / alpha
    assert abs(got - want) <= pinocchio_tol.PIN_MU_P.atol
    assert got == pytest.approx(float(mu_P(alpha)), abs=pinocchio_tol.PIN_MU_P.atol)


def test_mu_P_searches_the_modules_own_p_to_the_last_bit():
    """mu_P evaluates p without ``p``'s per-call checks: the same Brent search over ``p`` itself lands on the same float,
    and that float is where min over theta of p crosses 0 (p > 0 everywhere just below it, < 0 somewhere just above)."""
    from scipy.optimize import minimize_scalar

    alpha = 3.0

    def ratio(theta):
        p0, p1 = (float(pinrod.p(theta, -math.pi / 2, mu, alpha)) for mu in (0.0, 1.0))
        return p0 / (p0 - p1) if p0 > p1 else math.inf

    got = pinrod.mu_P(alpha)
    assert got == float(
        minimize_scalar(ratio, bounds=(0.0, math.pi / 2), method="bounded", options={"xatol": 1e-10}).fun
    )

    def min_p(mu):
        return float(
            minimize_scalar(
                lambda theta: float(pinrod.p(theta, -math.pi / 2, mu, alpha)),
                bounds=(0.0, math.pi / 2),
                method="bounded",
                options={"xatol": 1e-10},
            ).fun
        )

    # 1e-9 relative: the required accuracy of mu_P (PIN_MU_P); min p moves by ~|dp/dmu| 1e-9 ~ 1e-9, far above rounding
    assert min_p(got * (1 - 1e-9)) > 0.0 > min_p(got * (1 + 1e-9))


def test_terms_are_computed_once_and_shared_read_only():
    """G and the free acceleration are computed once per RodTerms and handed out read-only: a caller cannot change another's."""
    rod = Rod.uniform(2.0, 0.7)
    q, v = paper_to_qv(rod, np.array([0.4, 1.2]), -1.0, 0.3, -0.8, 1.5, 0.2)
    terms = pinrod.engine(rod).terms(q, v)
    for method in (terms.delassus, terms.free_acceleration):
        assert method() is method()
        with pytest.raises(ValueError, match="read-only"):
            method()[...] = 0.0
    # and G is J M^-1 J^T of the terms' own matrices, within the rounding of a solve through M (PIN_THROUGH_MINV:
    # ~90 eps of the term scale times cond(M) = 1/cos^2 theta)
    G = terms.J @ np.linalg.solve(terms.M, np.swapaxes(terms.J, 1, 2))
    allowance = pinocchio_tol.PIN_THROUGH_MINV.atol * np.abs(G).max() / math.cos(1.2) ** 2
    np.testing.assert_allclose(terms.delassus(), G, rtol=0, atol=allowance)
