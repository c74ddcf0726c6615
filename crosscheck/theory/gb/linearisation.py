"""The desingularised slipping flow near the GB manifold: eq. f, its Jacobian, K = B A, and the type of a GB point.

Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painleve
paradox*, section 4 (eqs. f, matA, matB, K).  Scaled units throughout;
x = (eta, varphi, psi, Psi, theta, Theta) (eq. x, ``crosscheck.theory.slipping.X_STATE``).

* ``f``, ``jacobian``: the desingularised vector field of eq. f (time s with
  eta p ds = dt) and its analytic Jacobian, vectorised over (..., 6) states.
* ``matrix_A``, ``matrix_B``, ``K``: J = A B on the GB manifold (eqs. matA,
  matB) and K = B A in closed form (eq. K).
* ``gb_type``, ``eigen``, ``quadrant``: node / saddle / focus from K's
  eigenvalues; eigenvectors e+- in the (p, b) plane (Theorem 4.1).
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

from crosscheck.checks import ALPHA, ETA, MU, THETA, check
from crosscheck.theory.slipping import X_STATE

__all__ = [
    "f",
    "jacobian",
    "matrix_A",
    "matrix_B",
    "K",
    "K_from_AB",
    "GBType",
    "gb_type",
    "eigen",
    "linear_orbits",
    "Quadrant",
    "quadrant",
]


# --------------------------------------------------------------------------
# Coefficients and their partial derivatives (Appendix A, eqs. b, p)
# --------------------------------------------------------------------------


def _terms(varphi, Psi, theta, Theta, mu, alpha):
    """b, p, Q1, Q2, A1, A2, d1, d2, c1, c2 and their partials in (varphi, Psi, theta, Theta).

    Returns a dict name -> (value, d/dvarphi, d/dPsi, d/dtheta, d/dTheta).
    """
    st, ct = np.sin(theta), np.cos(theta)
    sp, cp = np.sin(varphi), np.cos(varphi)
    zero = np.zeros(np.broadcast(varphi, Psi, theta, Theta, mu, alpha).shape)
    W = Psi**2 * ct**2 + Theta**2
    W_Psi, W_Theta, W_theta = 2 * Psi * ct**2, 2 * Theta, -2 * Psi**2 * ct * st
    g = mu * ct * sp - st  # p = 1 + alpha + alpha st g
    g_theta, g_varphi = -mu * st * sp - ct, mu * ct * cp
    out = {
        "b": (W * st - 1, zero, W_Psi * st, W_theta * st + W * ct, W_Theta * st),
        "p": (1 + alpha + alpha * st * g, alpha * st * g_varphi, zero, alpha * (ct * g + st * g_theta), zero),
        "Q1": (
            alpha * ct * sp * g - (1 + alpha) * mu,
            alpha * ct * (cp * g + sp * g_varphi),
            zero,
            alpha * sp * (-st * g + ct * g_theta),
            zero,
        ),
        "Q2": (
            alpha * ct * cp * g,
            alpha * ct * (-sp * g + cp * g_varphi),
            zero,
            alpha * cp * (-st * g + ct * g_theta),
            zero,
        ),
        "A1": (W * ct * sp, W * ct * cp, W_Psi * ct * sp, (W_theta * ct - W * st) * sp, W_Theta * ct * sp),
        "A2": (W * ct * cp, -W * ct * sp, W_Psi * ct * cp, (W_theta * ct - W * st) * cp, W_Theta * ct * cp),
        "d1": (-alpha * mu * cp / ct, alpha * mu * sp / ct, zero, -alpha * mu * cp * st / ct**2, zero),
        "d2": (
            -alpha * mu * st * sp - alpha * ct,
            -alpha * mu * st * cp,
            zero,
            -alpha * mu * ct * sp + alpha * st,
            zero,
        ),
        "c1": (2 * Psi * Theta * st / ct, zero, 2 * Theta * st / ct, 2 * Psi * Theta / ct**2, 2 * Psi * st / ct),
        "c2": (-(Psi**2) * st * ct, zero, -2 * Psi * st * ct, -(Psi**2) * np.cos(2 * theta), zero),
    }
    return {k: tuple(np.broadcast_to(v, zero.shape) for v in vals) for k, vals in out.items()}


def _split(x):
    x = check("x", x)
    if x.shape[-1:] != (6,):
        raise ValueError(f"x must have shape (..., 6) ordered as {X_STATE}; got {x.shape}")
    return np.moveaxis(x, -1, 0)


def f(x, mu, alpha) -> np.ndarray:
    """Desingularised slipping vector field f(x), eq. f.

    Args:
      x: (..., 6) states ordered as ``X_STATE`` = (eta, varphi, psi, Psi, theta, Theta), scaled.
      mu, alpha: friction coefficient and m l^2 / I0 (broadcast against x[..., 0]).

    Returns:
      (..., 6) dx/ds, where eta p ds = dt (F_z = -b/p substituted, eq. FZ).
    """
    eta, varphi, _, Psi, theta, Theta = _split(x)
    mu, alpha = check("mu", mu, MU), check("alpha", alpha, ALPHA)
    c = {k: v[0] for k, v in _terms(varphi, Psi, theta, Theta, mu, alpha).items()}
    b, p = c["b"], c["p"]
    out = (
        eta * (-c["Q1"] * b + c["A1"] * p),
        -c["Q2"] * b + (c["A2"] - eta * Psi) * p,
        eta * p * Psi,
        eta * (-c["d1"] * b + c["c1"] * p),
        eta * p * Theta,
        eta * (-c["d2"] * b + c["c2"] * p),
    )
    return np.stack(np.broadcast_arrays(*out), axis=-1)


def jacobian(x, mu, alpha) -> np.ndarray:
    """Analytic Jacobian df/dx of eq. f, shape (..., 6, 6); rows f_i, columns x_j in ``X_STATE`` order.

    Valid everywhere (not only on the GB manifold, where it reduces to eq.
    gatheredish = A B).
    """
    eta, varphi, _, Psi, theta, Theta = _split(x)
    mu, alpha = check("mu", mu, MU), check("alpha", alpha, ALPHA)
    T = _terms(varphi, Psi, theta, Theta, mu, alpha)
    b, p = T["b"], T["p"]
    shape = b[0].shape
    J = np.zeros(shape + (6, 6))
    # columns of the partials in _terms: (varphi, Psi, theta, Theta) -> x indices (1, 3, 4, 5)
    cols = (1, 3, 4, 5)

    def mixed(X, Y):
        """Partials of -X b + Y p (k = 1..4 in _terms order)."""
        return [-X[k] * b[0] - X[0] * b[k] + Y[k] * p[0] + Y[0] * p[k] for k in range(1, 5)]

    rows = {
        0: (eta, mixed(T["Q1"], T["A1"]), -T["Q1"][0] * b[0] + T["A1"][0] * p[0]),
        3: (eta, mixed(T["d1"], T["c1"]), -T["d1"][0] * b[0] + T["c1"][0] * p[0]),
        5: (eta, mixed(T["d2"], T["c2"]), -T["d2"][0] * b[0] + T["c2"][0] * p[0]),
    }
    for i, (scale, dk, value) in rows.items():
        J[..., i, 0] = value  # d/deta of eta * (...)
        for j, d in zip(cols, dk):
            J[..., i, j] = scale * d
    # f_varphi = -Q2 b + (A2 - eta Psi) p
    A2m = (T["A2"][0] - eta * Psi, T["A2"][1], T["A2"][2] - eta, T["A2"][3], T["A2"][4])
    for j, d in zip(cols, mixed(T["Q2"], A2m)):
        J[..., 1, j] = d
    J[..., 1, 0] = -Psi * p[0]
    # f_psi = eta p Psi, f_theta = eta p Theta
    for i, v, vcol in ((2, Psi, 3), (4, Theta, 5)):
        J[..., i, 0] = p[0] * v
        for j, k in zip(cols, range(1, 5)):
            J[..., i, j] = eta * p[k] * v
        J[..., i, vcol] += eta * p[0]
    return J


# --------------------------------------------------------------------------
# J = A B and K = B A (eqs. matA, matB, K)
# --------------------------------------------------------------------------


def matrix_A(x, mu, alpha) -> np.ndarray:
    """A = d f / d(p, b), eq. matA, shape (..., 6, 2): f written as a function of (p, b) and x."""
    eta, varphi, _, Psi, theta, Theta = _split(x)
    mu, alpha = check("mu", mu, MU), check("alpha", alpha, ALPHA)
    c = {k: v[0] for k, v in _terms(varphi, Psi, theta, Theta, mu, alpha).items()}
    col_p = (eta * c["A1"], c["A2"] - eta * Psi, eta * Psi, eta * c["c1"], eta * Theta, eta * c["c2"])
    col_b = (-eta * c["Q1"], -c["Q2"], 0 * eta, -eta * c["d1"], 0 * eta, -eta * c["d2"])
    cp = np.stack(np.broadcast_arrays(*col_p), axis=-1)
    cb = np.stack(np.broadcast_arrays(*col_b), axis=-1)
    return np.stack([cp, cb], axis=-1)


def matrix_B(x, mu, alpha) -> np.ndarray:
    """B = d(p, b) / dx, eq. matB, shape (..., 2, 6)."""
    eta, varphi, _, Psi, theta, Theta = _split(x)
    mu, alpha = check("mu", mu, MU), check("alpha", alpha, ALPHA)
    T = _terms(varphi, Psi, theta, Theta, mu, alpha)
    out = np.zeros(T["b"][0].shape + (2, 6))
    for row, name in enumerate(("p", "b")):
        for j, k in zip((1, 3, 4, 5), range(1, 5)):
            out[..., row, j] = T[name][k]
    return out


def K_from_AB(x, mu, alpha) -> np.ndarray:
    """K = B A computed from the coefficients (eq. BA), shape (..., 2, 2)."""
    return matrix_B(x, mu, alpha) @ matrix_A(x, mu, alpha)


def K(theta, varphi, Psi, Theta, eta, mu, alpha) -> np.ndarray:
    """The matrix K of eq. K (closed form on b = p = 0), shape (..., 2, 2).

    K is the Jacobian of (p, b)' = K (p, b) near the GB manifold (eq. p3a3),
    in the desingularised time s.  The closed form uses b = p = 0, so it equals
    B A (``K_from_AB``) only on the GB manifold.
    """
    theta = check("theta", theta, THETA)
    varphi, Psi, Theta = (check(n, v) for n, v in (("varphi", varphi), ("Psi", Psi), ("Theta", Theta)))
    eta, mu, alpha = check("eta", eta, ETA), check("mu", mu, MU), check("alpha", alpha, ALPHA)
    st, ct, cp = np.sin(theta), np.cos(theta), np.cos(varphi)
    tan = st / ct
    m = alpha * mu * ct**2 * cp**2
    s = alpha * mu * st * ct * cp
    K11 = m + eta * (Theta * (tan - (1 + alpha) / tan) - Psi * s)
    K12 = (1 + alpha) * m
    K21 = eta * Theta / tan
    K22 = eta * (2 * Psi * s - 2 * Theta * tan)
    K11, K12, K21, K22 = np.broadcast_arrays(K11, K12, K21, K22)
    return np.stack([np.stack([K11, K12], -1), np.stack([K21, K22], -1)], -2)


# --------------------------------------------------------------------------
# Classification and eigenvectors (section 4, Theorem 4.1)
# --------------------------------------------------------------------------


class GBType(IntEnum):
    """Type of a GB point as an equilibrium of eq. f in the (p, b) plane, from K's eigenvalues."""

    STABLE_NODE = 0
    SADDLE = 1
    UNSTABLE_NODE = 2
    STABLE_FOCUS = 3
    UNSTABLE_FOCUS = 4
    DEGENERATE = 5  # a zero eigenvalue (det K = 0) or a centre (trace 0, complex pair)


def gb_type(K, *, atol: float = 0.0):
    """GBType of each 2x2 matrix in K (shape (..., 2, 2)), from trace and determinant.

    det < 0: saddle.  det > 0 with real eigenvalues: node (stable if trace < 0);
    complex eigenvalues ((K11 - K22)^2 + 4 K12 K21 < 0): focus.  |det| <= atol
    (or a complex pair with |trace| <= atol): DEGENERATE.  Nodes include the
    repeated-eigenvalue (improper) nodes.  Returns a ``GBType`` for one matrix,
    an int8 array otherwise.
    """
    K = check("K", K)
    if K.shape[-2:] != (2, 2):
        raise ValueError(f"K must have shape (..., 2, 2); got {K.shape}")
    tr = K[..., 0, 0] + K[..., 1, 1]
    det = K[..., 0, 0] * K[..., 1, 1] - K[..., 0, 1] * K[..., 1, 0]
    disc = (K[..., 0, 0] - K[..., 1, 1]) ** 2 + 4 * K[..., 0, 1] * K[..., 1, 0]
    out = np.select(
        [np.abs(det) <= atol, det < 0, (disc < 0) & (np.abs(tr) <= atol), disc < 0, tr < 0],
        [
            GBType.DEGENERATE,
            GBType.SADDLE,
            GBType.DEGENERATE,
            np.where(tr < 0, GBType.STABLE_FOCUS, GBType.UNSTABLE_FOCUS),
            GBType.STABLE_NODE,
        ],
        GBType.UNSTABLE_NODE,
    ).astype(np.int8)
    return GBType(int(out)) if out.ndim == 0 else out


def eigen(K) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (lambda_+, lambda_-) and unit eigenvectors e_+- of K in the (p, b) plane.

    Args:
      K: (..., 2, 2).

    Returns:
      lam: (..., 2) complex, lam[..., 0] = lambda_+ (larger real part, then
        larger imaginary part), lam[..., 1] = lambda_-.
      vec: (..., 2, 2) complex, vec[..., :, i] the eigenvector of lam[..., i]
        as (p, b) components, unit length, sign fixed so that its b component
        is >= 0 (a direction, as the paper's (K12 / (lambda - K11), 1)).

    The eigenvector is (K12, lambda - K11) or (lambda - K22, K21), whichever is
    longer, so that triangular K (the planar case, K12 = 0) is handled.
    """
    K = np.asarray(check("K", K), dtype=complex)
    a, bb, c, d = K[..., 0, 0], K[..., 0, 1], K[..., 1, 0], K[..., 1, 1]
    tr = a + d
    root = np.sqrt((a - d) ** 2 + 4 * bb * c + 0j)
    lam = np.stack([(tr + root) / 2, (tr - root) / 2], axis=-1)
    swap = (lam[..., 0].real < lam[..., 1].real) | (
        (lam[..., 0].real == lam[..., 1].real) & (lam[..., 0].imag < lam[..., 1].imag)
    )
    lam = np.where(swap[..., None], lam[..., ::-1], lam)
    vecs = []
    for i in range(2):
        l_ = lam[..., i]
        v1 = np.stack([bb, l_ - a], axis=-1)
        v2 = np.stack([l_ - d, c], axis=-1)
        n1, n2 = np.linalg.norm(v1, axis=-1), np.linalg.norm(v2, axis=-1)
        v = np.where((n1 >= n2)[..., None], v1, v2)
        n = np.maximum(n1, n2)
        with np.errstate(invalid="ignore", divide="ignore"):
            v = v / n[..., None]
        # b component >= 0 (for real vectors); if b = 0, p component > 0
        flip = (v[..., 1].real < 0) | ((v[..., 1].real == 0) & (v[..., 0].real < 0))
        vecs.append(np.where(flip[..., None], -v, v))
    return lam, np.stack(vecs, axis=-1)


class Quadrant(IntEnum):
    """Where a real eigen-direction lies in the (p, b) plane (Theorem 4.1, Figs. 12-13)."""

    I_III = 1  # first and third quadrants (p b > 0)
    II_IV = 2  # second and fourth quadrants (p b < 0)
    P_AXIS = 3
    B_AXIS = 4
    COMPLEX = 5


def quadrant(v, *, atol: float = 0.0):
    """Quadrant pair of direction(s) v = (p, b), shape (..., 2); |component| <= atol counts as on an axis."""
    v = np.asarray(v)
    complex_ = np.any(np.abs(np.imag(v)) > 0, axis=-1) if np.iscomplexobj(v) else np.zeros(v.shape[:-1], bool)
    pv, bv = np.real(v[..., 0]), np.real(v[..., 1])
    out = np.select(
        [complex_, np.abs(pv) <= atol, np.abs(bv) <= atol, pv * bv > 0],
        [Quadrant.COMPLEX, Quadrant.B_AXIS, Quadrant.P_AXIS, Quadrant.I_III],
        Quadrant.II_IV,
    ).astype(np.int8)
    return Quadrant(int(out)) if out.ndim == 0 else out


def linear_orbits(K, *, n_orbits: int, n_s: int, span: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
    """Orbits of the linearised flow (p, b)' = K (p, b) (desingularised time s) from ``n_orbits`` starts on the unit circle.

    s runs over [-span, span] / max |lambda| (``n_s`` samples, forward and backward), the time scale of the
    faster eigenvalue, so every type of point shows its whole local picture.

    Returns:
      (s (n_s,), y (n_orbits, n_s, 2)): y[j] = expm(K s) (cos a_j, sin a_j), a_j = 2 pi j / n_orbits.
    """
    from scipy.linalg import expm

    K = np.asarray(check("K", K), dtype=float)
    lam, _ = eigen(K)
    scale = 1.0 / max(float(np.max(np.abs(lam))), 1e-12)
    s = np.linspace(-span * scale, span * scale, n_s)
    Phi = expm(K[None, :, :] * s[:, None, None])  # one batched call: (n_s, 2, 2)
    starts = [np.array([np.cos(a), np.sin(a)]) for a in np.linspace(0, 2 * np.pi, n_orbits, endpoint=False)]
    return s, np.stack([Phi @ y0 for y0 in starts])
