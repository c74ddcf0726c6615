"""Analytic reference: the paper's equations of motion, vectorised with numpy.

Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painleve
paradox* (``shared/reference/painleve-geometry.tex``).  Every function cites
the equation label it implements.  All functions broadcast their arguments
with numpy's rules.

Frames and units.  World frame (I, J, K) with K up and gravity along -K; the
body rotation is Rz(psi) Rx(theta) (eq. rotmatrix) and the tip A sits at
(0, -l, 0) in the body frame.  ``tip_acceleration`` and
``rotational_acceleration`` work in physical units of a ``Rod``; everything
else is in the paper's scaled units (lengths in l, forces in m g, time in
1/omega with omega^2 = g/l, alpha = m l^2 / I0).
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

from crosscheck.checks import ALPHA, BOUNDED, FINITE, MU, THETA, check, real, same_shape
from crosscheck.rod import Rod
from crosscheck.theory.critical import (
    CriticalValues,
    Mechanism,
    critical_values,
    kinematic_case,
    mechanism,
    mu_P_star,
    theta_pm,
    varphi_pm,
)

__all__ = [
    "Mode",
    "mode",
    "tip_acceleration",
    "rod_factors",
    "tip_acceleration_of",
    "rotational_acceleration",
    "b",
    "p",
    "normal_force",
    "b_rounding",
    "p_rounding",
    "boundary",
    "Q1",
    "Q2",
    "A1",
    "A2",
    "d1",
    "d2",
    "c1",
    "c2",
    "SCALED_STATE",
    "scaled_rhs",
    "CriticalValues",
    "Mechanism",
    "critical_values",
    "kinematic_case",
    "mechanism",
    "mu_P_star",
    "theta_pm",
    "varphi_pm",
]


# --------------------------------------------------------------------------
# Physical units: eqs. rotode and linode2
# --------------------------------------------------------------------------


def _force_components(force) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    f = check("force", force)
    if f.shape[-1:] != (3,):
        raise ValueError(f"force must have shape (..., 3) (Fx, Fy, Fz in the world frame); got {f.shape}")
    return f[..., 0], f[..., 1], f[..., 2]


def tip_acceleration(rod: Rod, psi, theta, psi_dot, theta_dot, force) -> np.ndarray:
    """Acceleration (x'', y'', z'') of the tip A, eq. linode2.

    Args:
      rod: the rod, in physical units (m, l, I0, g).
      psi: azimuthal angle [rad].
      theta: polar angle [rad], in (0, pi/2).
      psi_dot, theta_dot: angular rates [rad/s].
      force: contact force (Fx, Fy, Fz) [N] applied at A, world frame, shape (..., 3).

    Returns:
      (..., 3) array of tip accelerations [m/s^2], world frame, gravity included.
    """
    theta = check("theta", theta, THETA)
    psi, psi_dot, theta_dot = (check(n, v) for n, v in (("psi", psi), ("psi_dot", psi_dot), ("theta_dot", theta_dot)))
    return tip_acceleration_of(rod_factors(rod), psi, theta, psi_dot, theta_dot, _force_components(force))


def rod_factors(rod: Rod) -> tuple[float, float, float, float, float]:
    """(m, k = m l^2 / I0, r = I0 / (m l^2), h = I0 / (m l), g / l) of eq. linode2, in the rod's own floats."""
    m, l, i0, g = rod.mass, rod.length, rod.inertia, rod.gravity
    return m, m * l**2 / i0, i0 / (m * l**2), i0 / (m * l), g / l


def tip_acceleration_of(factors, psi, theta, psi_dot, theta_dot, force_components) -> np.ndarray:
    """``tip_acceleration`` from ``rod_factors`` (each a float, or an array of one rod's factors per state, for many rods in
    one call: the same arithmetic state by state) and the force's (Fx, Fy, Fz), arguments unchecked."""
    m, k, r, h, g_over_l = factors
    fx, fy, fz = force_components
    s, c = np.sin(theta), np.cos(theta)
    sp, cp = np.sin(psi), np.cos(psi)
    # h: the paper's I0/(m l) factor in front of the velocity terms
    xdd = k * (
        (-(sp**2) * c**2 + r + 1) * fx / m
        + (c**2 * sp * cp) * fy / m
        + (s * c * sp) * fz / m
        + h * (-(psi_dot**2) * c**3 * sp - theta_dot**2 * c * sp)
    )
    ydd = k * (
        (sp * cp * c**2) * fx / m
        + (-(cp**2) * c**2 + r + 1) * fy / m
        - (s * c * cp) * fz / m
        + h * (psi_dot**2 * c**3 * cp + theta_dot**2 * c * cp)
    )
    zdd = k * (
        (sp * s * c) * fx / m
        - (c * cp * s) * fy / m
        + (c**2 + r) * fz / m
        + h * (psi_dot**2 * c**2 * s + theta_dot**2 * s - g_over_l)
    )
    return np.stack(np.broadcast_arrays(xdd, ydd, zdd), axis=-1)


def rotational_acceleration(rod: Rod, psi, theta, psi_dot, theta_dot, force) -> np.ndarray:
    """Angular accelerations (theta'', psi'') [rad/s^2], eq. rotode.

    Arguments as in ``tip_acceleration``.  Returns an (..., 2) array.
    """
    theta = check("theta", theta, THETA)
    psi, psi_dot, theta_dot = (check(n, v) for n, v in (("psi", psi), ("psi_dot", psi_dot), ("theta_dot", theta_dot)))
    fx, fy, fz = _force_components(force)
    lr = rod.length / rod.inertia
    s, c = np.sin(theta), np.cos(theta)
    sp, cp = np.sin(psi), np.cos(psi)
    theta_dd = -lr * (sp * s * fx - cp * s * fy + c * fz) - psi_dot**2 * s * c
    psi_dd = lr / c * (cp * fx + sp * fy) + 2 * psi_dot * theta_dot * np.tan(theta)
    return np.stack(np.broadcast_arrays(theta_dd, psi_dd), axis=-1)


# --------------------------------------------------------------------------
# Scaled units: eqs. b, p, FZ and Appendix A
# --------------------------------------------------------------------------


def _b(Psi, Theta, theta):
    return (Psi**2 * np.cos(theta) ** 2 + Theta**2) * np.sin(theta) - 1.0


def _p(theta, varphi, mu, alpha):
    s = np.sin(theta)
    return 1.0 + alpha + alpha * s * (mu * np.cos(theta) * np.sin(varphi) - s)


def b(Psi, Theta, theta):
    """Scaled vertical free acceleration of the tip, eq. b.

    b = (Psi^2 cos^2 theta + Theta^2) sin theta - 1; in physical units
    l psi_dot^2 sin theta cos^2 theta + l theta_dot^2 sin theta - g, divided by g.
    """
    return _b(
        *same_shape(
            Psi=real("Psi", Psi, BOUNDED), Theta=real("Theta", Theta, BOUNDED), theta=real("theta", theta, THETA)
        )
    )


def p(theta, varphi, mu, alpha):
    """Scaled vertical tip acceleration per unit normal force while slipping, eq. p.

    p = 1 + alpha + alpha sin theta (mu cos theta sin varphi - sin theta).
    A paradox needs p < 0.
    """
    return _p(
        *same_shape(
            theta=real("theta", theta, THETA),
            varphi=real("varphi", varphi, BOUNDED),
            mu=real("mu", mu, MU),
            alpha=real("alpha", alpha, ALPHA),
        )
    )


#: Rounding operations in eqs. b and p: each term carries at most ~4 roundings (sin, cos,
#: products, sums), and the sum's error is bounded by that many ulps of the sum of |terms|.
_ROUNDINGS = 8


def b_rounding(Psi, Theta, theta):
    """Bound of the floating-point error of ``b``: 8 eps (|Psi^2 cos^2 theta sin theta| + Theta^2 sin theta + 1).

    A computed |b| at or below it has no meaningful sign: the state is on b = 0.
    """
    Psi, Theta, theta = check("Psi", Psi, BOUNDED), check("Theta", Theta, BOUNDED), check("theta", theta, THETA)
    s = np.sin(theta)
    return _ROUNDINGS * np.finfo(float).eps * ((Psi**2 * np.cos(theta) ** 2 + Theta**2) * s + 1.0)


def p_rounding(theta, varphi, mu, alpha):
    """Bound of the floating-point error of ``p``: 8 eps (1 + alpha + alpha sin^2 theta + alpha mu |sin theta cos theta sin varphi|).

    At mu = mu_P, theta = theta_P, varphi = -pi/2, where p = 0 exactly, ``p``
    computes -8.9e-16 and this bound is 2.7e-15.
    """
    theta, varphi, mu, alpha = (
        check("theta", theta, THETA),
        check("varphi", varphi),
        check("mu", mu, MU),
        check("alpha", alpha, ALPHA),
    )
    s, c = np.sin(theta), np.cos(theta)
    return (
        _ROUNDINGS * np.finfo(float).eps * (1.0 + alpha + alpha * s * s + alpha * mu * np.abs(s * c * np.sin(varphi)))
    )


def boundary(b, p, b_tol, p_tol) -> str:
    """Which mode boundary (b, p) lies on within the rounding bounds: "", "b = 0", "p = 0" or "b = p = 0" (scalars)."""
    on_b, on_p = abs(float(b)) <= float(b_tol), abs(float(p)) <= float(p_tol)
    return {(True, True): "b = p = 0", (True, False): "b = 0", (False, True): "p = 0"}.get((on_b, on_p), "")


def normal_force(Psi, Theta, theta, varphi, mu, alpha):
    """Scaled normal force F_z = -b / p that keeps the slipping tip on the plane, eq. FZ.

    Infinite where p = 0 (numpy's division semantics); meaningful only where
    ``mode`` is SLIP.
    """
    bb = b(Psi, Theta, theta)
    pp = p(theta, varphi, mu, alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        return -bb / pp


def Q1(theta, varphi, mu, alpha):
    """Appendix A, eq. polareqs_varphi_terms: coefficient of F_z in eta'."""
    ct = np.cos(theta)
    return alpha * ct * np.sin(varphi) * (mu * ct * np.sin(varphi) - np.sin(theta)) - (1 + alpha) * mu


def Q2(theta, varphi, mu, alpha):
    """Appendix A: coefficient of F_z in eta varphi'."""
    ct = np.cos(theta)
    return alpha * ct * np.cos(varphi) * (mu * ct * np.sin(varphi) - np.sin(theta))


def A1(Psi, Theta, theta, varphi):
    """Appendix A: free part of eta'."""
    ct = np.cos(theta)
    return (Psi**2 * ct**2 + Theta**2) * ct * np.sin(varphi)


def A2(Psi, Theta, theta, varphi):
    """Appendix A: free part of eta varphi' (before the -eta Psi term)."""
    ct = np.cos(theta)
    return (Psi**2 * ct**2 + Theta**2) * ct * np.cos(varphi)


def d1(theta, varphi, mu, alpha):
    """Appendix A: coefficient of F_z in Psi'."""
    return -alpha * mu * np.cos(varphi) / np.cos(theta)


def d2(theta, varphi, mu, alpha):
    """Appendix A: coefficient of F_z in Theta'."""
    return -alpha * mu * np.sin(theta) * np.sin(varphi) - alpha * np.cos(theta)


def c1(Psi, Theta, theta):
    """Appendix A: free part of Psi'."""
    return 2 * Psi * Theta * np.tan(theta)


def c2(Psi, Theta, theta):
    """Appendix A: free part of Theta'."""
    return -(Psi**2) * np.sin(theta) * np.cos(theta)


#: Order of the components of the scaled 10-state of eq. polareqs_varphi.
SCALED_STATE = ("x", "y", "z", "psi", "theta", "eta", "varphi", "w", "Psi", "Theta")


def scaled_rhs(state, F_z, mu, alpha) -> np.ndarray:
    """Right-hand side of the scaled first-order system, eq. polareqs_varphi.

    Args:
      state: (..., 10) array ordered as ``SCALED_STATE``:
        (x, y, z, psi, theta, eta, varphi, w, Psi, Theta), scaled units.
      F_z: scaled normal force (F_x, F_y follow from Coulomb's law, eq. friction).
        Pass ``normal_force(...)`` for the slipping motion, 0 for free flight.
      mu, alpha: friction coefficient and alpha = m l^2 / I0.

    Returns:
      (..., 10) array of time derivatives in scaled time.  The varphi
      component divides by eta and is undefined at eta = 0.
    """
    y = check("state", state)
    if y.shape[-1:] != (10,):
        raise ValueError(f"state must have shape (..., 10) ordered as {SCALED_STATE}; got {y.shape}")
    mu = check("mu", mu, MU)
    alpha = check("alpha", alpha, ALPHA)
    F_z = check("F_z", F_z, FINITE)
    _, _, _, psi, theta, eta, varphi, w, Psi, Theta = np.moveaxis(y, -1, 0)
    check("theta", theta, THETA)
    with np.errstate(divide="ignore", invalid="ignore"):
        dvarphi = (Q2(theta, varphi, mu, alpha) * F_z + A2(Psi, Theta, theta, varphi)) / eta - Psi
    out = (
        eta * np.cos(psi + varphi),
        eta * np.sin(psi + varphi),
        w,
        Psi,
        Theta,
        Q1(theta, varphi, mu, alpha) * F_z + A1(Psi, Theta, theta, varphi),
        dvarphi,
        _p(theta, varphi, mu, alpha) * F_z + _b(Psi, Theta, theta),
        d1(theta, varphi, mu, alpha) * F_z + c1(Psi, Theta, theta),
        d2(theta, varphi, mu, alpha) * F_z + c2(Psi, Theta, theta),
    )
    return np.stack(np.broadcast_arrays(*out), axis=-1)


# --------------------------------------------------------------------------
# Contact modes: section 3.1
# --------------------------------------------------------------------------


class Mode(IntEnum):
    """The four modes of the LCP 0 <= F_z  perp  w' = p F_z + b >= 0 (section 3.1)."""

    SLIP = 0
    LIFTOFF = 1
    INCONSISTENT = 2
    INDETERMINATE = 3


def mode(b, p):
    """Contact mode from the signs of b and p (section 3.1, eq. comp).

    Off the boundaries this is the paper's table: b<0,p>0 SLIP; b>0,p>0 LIFTOFF;
    b<0,p<0 INCONSISTENT; b>0,p<0 INDETERMINATE.  On the boundaries the mode is
    read off the solution set of the LCP 0 <= F_z perp p F_z + b >= 0, so that
    every (b, p) gets exactly one mode:

    * no solution (b < 0, p <= 0)                          -> INCONSISTENT
    * more than one solution (b > 0, p < 0; or b = p = 0)  -> INDETERMINATE
    * a unique solution with w' > 0 (b > 0, p >= 0)        -> LIFTOFF
    * a unique solution with w' = 0 (b <= 0, p > 0; b = 0, p < 0) -> SLIP

    Returns a ``Mode`` for scalar input and an int8 array of ``Mode`` values
    otherwise.  NaN raises ``ValueError``.
    """
    bb = check("b", b)
    pp = check("p", p)
    bb, pp = np.broadcast_arrays(bb, pp)
    out = np.select(
        [
            (bb < 0) & (pp <= 0),
            ((bb > 0) & (pp < 0)) | ((bb == 0) & (pp == 0)),
            (bb > 0) & (pp >= 0),
        ],
        [Mode.INCONSISTENT, Mode.INDETERMINATE, Mode.LIFTOFF],
        default=Mode.SLIP,
    ).astype(np.int8)
    if out.ndim == 0:
        return Mode(int(out))
    return out
