"""eq. linode2, eq. rotode and the scaled system against an independent derivation.

The reference here is a sympy Lagrangian in q = (X, Y, Z, psi, theta) built
from the rotation matrix Rz(psi) Rx(theta) (not from the paper's tip formula),
with the contact force entering as generalised force J_A^T F.
"""

import functools
import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from crosscheck.rod import Rod
from crosscheck.theory import analytic as an
from crosscheck.tolerances import DERIVATION


@functools.cache
def lagrangian_model():
    """Lambdified M(q), h(q, v) (= C v + g) and tip kinematics from a Lagrangian."""
    X, Y, Z, psi, th = sp.symbols("X Y Z psi theta", real=True)
    dX, dY, dZ, dpsi, dth = sp.symbols("dX dY dZ dpsi dtheta", real=True)
    m, l, I0, g = sp.symbols("m l I0 g", positive=True)
    q = sp.Matrix([X, Y, Z, psi, th])
    v = sp.Matrix([dX, dY, dZ, dpsi, dth])
    Rz = sp.Matrix([[sp.cos(psi), -sp.sin(psi), 0], [sp.sin(psi), sp.cos(psi), 0], [0, 0, 1]])
    Rx = sp.Matrix([[1, 0, 0], [0, sp.cos(th), -sp.sin(th)], [0, sp.sin(th), sp.cos(th)]])
    R = Rz * Rx
    tip = sp.Matrix([X, Y, Z]) + R * sp.Matrix([0, -l, 0])
    # body angular velocity from R^T dR/dt (skew), independent of eq. angvel
    Rdot = sum((R.diff(qi) * vi for qi, vi in zip(q, v)), sp.zeros(3, 3))
    W = sp.simplify(R.T * Rdot)
    omega_body = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
    inertia = sp.diag(I0, 0, I0)
    T = sp.Rational(1, 2) * m * (dX**2 + dY**2 + dZ**2) + sp.Rational(1, 2) * (omega_body.T * inertia * omega_body)[0]
    V = m * g * Z
    M = sp.hessian(T, v)
    dT_dv = sp.Matrix([T.diff(vi) for vi in v])
    # d/dt(dT/dv) = M qdd + (d(dT/dv)/dq) v ; Lagrange: M qdd + h = J^T F
    h = dT_dv.jacobian(q) * v - sp.Matrix([T.diff(qi) for qi in q]) + sp.Matrix([V.diff(qi) for qi in q])
    J = tip.jacobian(q)
    Jdot_v = (J * v).jacobian(q) * v
    args = (X, Y, Z, psi, th, dX, dY, dZ, dpsi, dth, m, l, I0, g)
    return tuple(sp.lambdify(args, sp.simplify(e), "numpy") for e in (M, h, J, Jdot_v, tip))


def random_cases(rng: np.random.Generator, n: int):
    for k in range(n):
        rod = Rod(
            mass=rng.uniform(0.1, 10),
            length=rng.uniform(0.05, 3),
            inertia=rng.uniform(0.01, 5),
            gravity=rng.uniform(1, 30),
        )
        if k % 4 == 0:
            theta = rng.uniform(1e-6, 1e-2)  # rod nearly flat
        elif k % 4 == 1:
            theta = math.pi / 2 - rng.uniform(1e-3, 1e-2)  # |cos theta| ~ 1e-2
        else:
            theta = rng.uniform(0, math.pi / 2)
        q = np.array([*rng.normal(size=3), rng.uniform(-math.pi, math.pi), theta])
        v = rng.normal(size=5) * 3
        F = rng.normal(size=3) * rod.mass * rod.gravity
        yield rod, q, v, F


def reference_accelerations(rod, q, v, F):
    M, h, J, Jdot_v, _ = lagrangian_model()
    args = (*q, *v, rod.mass, rod.length, rod.inertia, rod.gravity)
    Jm = np.array(J(*args), float)
    qdd = np.linalg.solve(np.array(M(*args), float), Jm.T @ F - np.array(h(*args), float).ravel())
    return qdd, Jm @ qdd + np.array(Jdot_v(*args), float).ravel()


def test_tip_acceleration_matches_lagrangian_derivation():
    # required: <= 1e-12 relative to the size of the acceleration, at 200 seeded states
    # including theta ~ 1e-6..1e-2 and |cos theta| ~ 1e-3..1e-2 (measured: 1.2e-15)
    rng = np.random.default_rng(20261121)
    for rod, q, v, F in random_cases(rng, 200):
        _, want = reference_accelerations(rod, q, v, F)
        got = an.tip_acceleration(rod, q[3], q[4], v[3], v[4], F)
        assert np.max(np.abs(got - want)) <= DERIVATION.rtol * np.linalg.norm(want), (rod, q, v, F, got, want)


def test_rotational_acceleration_matches_lagrangian_derivation():
    # eq. rotode, componentwise relative (measured: 5.6e-15, psi'' near cos theta ~ 1e-2 included)
    rng = np.random.default_rng(7)
    for rod, q, v, F in random_cases(rng, 200):
        qdd, _ = reference_accelerations(rod, q, v, F)
        got = an.rotational_acceleration(rod, q[3], q[4], v[3], v[4], F)
        np.testing.assert_allclose(got, qdd[[4, 3]], rtol=DERIVATION.rtol, atol=0)


def test_tip_acceleration_broadcasts():
    rod = Rod.uniform(2.0, 0.5)
    theta = np.linspace(0.1, 1.4, 7)[:, None]
    force = np.zeros((1, 4, 3))
    got = an.tip_acceleration(rod, 0.3, theta, 1.0, -2.0, force)
    assert got.shape == (7, 4, 3)
    np.testing.assert_array_equal(got[3, 2], an.tip_acceleration(rod, 0.3, theta[3, 0], 1.0, -2.0, [0, 0, 0]))


# --------------------------------------------------------------------------
# scaled system (eq. polareqs_varphi + Appendix A) vs dimensional equations
# --------------------------------------------------------------------------


def test_scaled_system_equals_scaled_dimensional_equations():
    rng = np.random.default_rng(11)
    for _ in range(300):
        rod = Rod(
            mass=rng.uniform(0.1, 10),
            length=rng.uniform(0.05, 3),
            inertia=rng.uniform(0.01, 5),
            gravity=rng.uniform(1, 30),
        )
        mu = rng.uniform(0, 5)
        theta = rng.uniform(0.01, math.pi / 2 - 0.01)
        varphi = rng.uniform(-math.pi, 0)
        psi = rng.uniform(-math.pi, math.pi)
        Theta, Psi = rng.normal(size=2) * 2
        eta = rng.uniform(0.1, 5)
        Fz = rng.uniform(-2, 5)  # scaled normal force, any value: the identity is linear in F_z
        om, l, g = rod.omega, rod.length, rod.gravity
        beta = psi + varphi
        F = rod.mass * g * Fz * np.array([-mu * math.cos(beta), -mu * math.sin(beta), 1.0])  # eq. friction
        acc = an.tip_acceleration(rod, psi, theta, Psi * om, Theta * om, F)
        rot = an.rotational_acceleration(rod, psi, theta, Psi * om, Theta * om, F)
        eta_phys = eta * l * om
        want = {
            "eta": (math.cos(beta) * acc[0] + math.sin(beta) * acc[1]) / g,
            "varphi": ((-math.sin(beta) * acc[0] + math.cos(beta) * acc[1]) / eta_phys - Psi * om) / om,
            "w": acc[2] / g,
            "Psi": rot[1] / om**2,
            "Theta": rot[0] / om**2,
        }
        state = np.array([0.3, -0.2, 0.0, psi, theta, eta, varphi, 0.0, Psi, Theta])
        rhs = dict(zip(an.SCALED_STATE, an.scaled_rhs(state, Fz, mu, rod.alpha)))
        for k, w in want.items():
            assert rhs[k] == pytest.approx(
                w, rel=1e-10, abs=1e-10 * (1 + abs(Fz) * (1 + mu) * (1 + rod.alpha) + Psi**2 + Theta**2)
            ), k
        assert rhs["x"] == pytest.approx(eta * math.cos(beta), rel=1e-14)
        assert rhs["w"] == pytest.approx(
            an.p(theta, varphi, mu, rod.alpha) * Fz + an.b(Psi, Theta, theta), rel=1e-12, abs=1e-12
        )


def _slipping_rhs(mu, alpha):
    def f(t, y):
        Fz = an.normal_force(y[8], y[9], y[4], y[6], mu, alpha)
        return an.scaled_rhs(y, Fz, mu, alpha)

    return f


@pytest.mark.parametrize("theta0, Theta0", [(0.5, 0.3), (0.9, -0.2), (1.3, 0.0)])
def test_planar_problem_is_invariant(theta0, Theta0):
    # Remark 2.1: {Psi = 0} and {varphi = -pi/2} is invariant under the slipping flow (mu < mu_P so p > 0).
    mu, alpha = 0.5, 3.0
    y0 = np.array([0, 0, 0, 0.0, theta0, 1.5, -math.pi / 2, 0, 0.0, Theta0])
    sol = solve_ivp(_slipping_rhs(mu, alpha), (0, 0.5), y0, rtol=1e-10, atol=1e-12)
    assert sol.success
    assert np.max(np.abs(sol.y[8])) <= 1e-14  # Psi: d1 F_z with cos(-pi/2) = 6e-17
    assert np.max(np.abs(sol.y[6] + math.pi / 2)) <= 1e-14
    # off the manifold the same flow leaves it: the test can fail
    y1 = y0.copy()
    y1[6] += 0.1
    sol = solve_ivp(_slipping_rhs(mu, alpha), (0, 0.5), y1, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(sol.y[8])) > 1e-3
