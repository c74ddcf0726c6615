"""The batched Cholesky factor and forward substitution behind Pinocchio's Delassus matrix (crosscheck.engines.pinocchio.spd).

The bounds are the backward-error bounds of the two algorithms (Higham,
*Accuracy and Stability of Numerical Algorithms*, 2nd ed.): Cholesky gives
L L^T = M + dM with |dM| <= gamma_{n+1} |L| |L^T| entrywise (thm. 10.3), and a
triangular solve L w = b gives (L + dL) w = b with |dL| <= gamma_n |L| (thm. 8.5),
gamma_k = k eps / (1 - k eps).  The check itself forms L L^T or L w - b in floating
point, which adds at most gamma_{n+1} of the same magnitudes (thm. 3.5), so
each bound below is the sum of the two.  They hold for any positive definite matrix,
however ill-conditioned: the matrices here reach the condition number of the
rod's M at cos theta = 1e-3.
"""

from __future__ import annotations

import numpy as np

from crosscheck.engines.pinocchio import model as pinrod
from crosscheck.engines.pinocchio import spd
from crosscheck.rod import Rod

EPS = np.finfo(float).eps


def gamma(k: int) -> float:
    return k * EPS / (1 - k * EPS)


def random_spd(n_states: int, rng: np.random.Generator) -> np.ndarray:
    """SPD 5 x 5 matrices Q diag(d) Q^T with eigenvalues d log-uniform over up to six decades."""
    Q, _ = np.linalg.qr(rng.standard_normal((n_states, 5, 5)))
    d = 10.0 ** rng.uniform(-6, 0, (n_states, 5))
    M = (Q * d[:, None, :]) @ np.swapaxes(Q, 1, 2)
    return (M + np.swapaxes(M, 1, 2)) / 2  # exactly symmetric, as ``symmetrised`` makes Pinocchio's M


def dense(L: list) -> np.ndarray:
    n, N = len(L), L[0][0].shape[0]
    out = np.zeros((N, n, n))
    for i in range(n):
        for j in range(i + 1):
            out[:, i, j] = L[i][j]
    return out


def test_the_factor_reproduces_m_within_the_backward_error_bound_of_cholesky():
    M = random_spd(500, np.random.default_rng(11))
    L = dense(spd.cholesky_columns(M))
    absL = np.abs(L)
    assert (np.abs(L @ np.swapaxes(L, 1, 2) - M) <= (gamma(6) + gamma(6)) * absL @ np.swapaxes(absL, 1, 2)).all()
    assert (np.diagonal(L, axis1=1, axis2=2) > 0).all()


def test_the_forward_solve_is_backward_stable_for_every_state_and_right_hand_side():
    rng = np.random.default_rng(12)
    M = random_spd(500, rng)
    cols = spd.cholesky_columns(M)
    L = dense(cols)
    B = rng.standard_normal((5, 4, 500))
    W = spd.forward_solve(cols, B)
    w, b = W.transpose(2, 0, 1), B.transpose(2, 0, 1)  # (N, 5, 4)
    residual = np.abs(L @ w - b)
    assert (residual <= gamma(5) * np.abs(L) @ np.abs(w) + gamma(6) * (np.abs(L) @ np.abs(w) + np.abs(b))).all()


def test_a_matrix_that_is_not_positive_definite_gives_nan_in_its_own_state_only():
    M = random_spd(3, np.random.default_rng(13))
    M[1, 2, 2] = -1.0
    with np.errstate(invalid="ignore"):  # the square root of a negative pivot: NaN is the result asked for
        L = dense(spd.cholesky_columns(M))
    assert np.isnan(L[1, 2:, 2]).all()
    assert np.isfinite(L[[0, 2]]).all()


def test_pinocchios_delassus_matrix_is_symmetric_and_equals_j_minv_jt_by_lu():
    # The rod near the vertical (cos theta down to 1e-3): G through M^-1 carries M's condition number 1/cos^2 theta,
    # so the two routes may differ by a few eps / cos^2 theta relative to |G|.
    rod = Rod.scaled(3.0)
    theta = np.arccos(np.geomspace(1.0, 1e-3, 50) * 0.999)
    q = np.zeros((50, 5))
    q[:, 4] = theta
    v = np.random.default_rng(14).standard_normal((50, 5))
    terms = pinrod.engine(rod).terms(q, v)
    G = terms.delassus()
    assert (G == np.swapaxes(G, 1, 2)).all()  # W^T W: symmetric by construction
    lu = terms.J @ np.linalg.solve(terms.M, np.swapaxes(terms.J, 1, 2))
    kappa = 1.0 / np.cos(theta) ** 2
    assert (np.abs(G - lu).max(axis=(1, 2)) <= 50 * EPS * kappa * np.abs(lu).max(axis=(1, 2))).all()


def test_a_states_delassus_matrix_and_free_acceleration_do_not_depend_on_the_batch_it_is_in():
    # one numpy operation per entry acts on each state alone: a state gives the same bits alone, in any slice of a
    # batch and in the whole batch (chunked validations and sweeps then equal unchunked ones)
    rng = np.random.default_rng(15)
    n = 300
    q = np.zeros((n, 5))
    q[:, :3] = rng.standard_normal((n, 3))
    q[:, 3] = rng.uniform(-3, 3, n)
    q[:, 4] = rng.uniform(0.01, 1.55, n)
    v = rng.standard_normal((n, 5))
    rod_engine = pinrod.engine(Rod.scaled(3.0))
    whole = rod_engine.terms(q, v)
    for a, b in ((0, 1), (7, 8), (299, 300), (0, 2), (5, 64), (100, 300)):
        part = rod_engine.terms(q[a:b], v[a:b])
        assert np.array_equal(part.delassus(), whole.delassus()[a:b])
        assert np.array_equal(part.free_acceleration(), whole.free_acceleration()[a:b])
