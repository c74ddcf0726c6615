"""Many small symmetric positive definite systems at once: the Cholesky factor of each, one numpy operation per entry.

The joint-space inertia matrix M of the rod (5 x 5, symmetric positive definite
for theta in (0, pi/2): its condition number is 1/cos^2 theta in the natural
units diag(m, m, m, I0, I0), see ``crosscheck.engines.pinocchio.model``) is
factored as M = L L^T at N states together.  The arrays hold one entry of every
state's matrix each ("structure of arrays"), so each step of the factorisation
and of the triangular solves is one numpy operation over the N states.  On the
validation's chunks of 8192 states, G = J M^-1 J^T and J M^-1 (C v + g) cost
0.10 us per state this way against 0.51 through ``numpy.linalg.solve``, which
calls LAPACK once per state (measured; ``benchmarks/bench_pinocchio.py`` times
the whole validation).

Cholesky needs no pivoting for a symmetric positive definite matrix and is
backward stable (Higham, *Accuracy and Stability of Numerical Algorithms*,
thm. 10.3), as LU with partial pivoting is.  A matrix that is not positive
definite has no real factor: a square root of a negative number gives NaN,
which every comparison downstream counts as a failure, not as a number.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cholesky_columns", "forward_solve"]


def cholesky_columns(M: np.ndarray) -> list[list[np.ndarray]]:
    """The lower Cholesky factors L of M (N, n, n) as L[i][j], i >= j, each an (N,) array (M = L L^T per state).

    Only the lower triangle of M is read.  Entries above the diagonal are not returned.
    """
    n = M.shape[-1]
    L: list[list[np.ndarray]] = [[None] * n for _ in range(n)]  # type: ignore[list-item]
    for j in range(n):
        s = M[:, j, j].copy()
        for k in range(j):
            s -= L[j][k] * L[j][k]
        d = np.sqrt(s)
        L[j][j] = d
        for i in range(j + 1, n):
            t = M[:, i, j].copy()
            for k in range(j):
                t -= L[i][k] * L[j][k]
            L[i][j] = t / d
    return L


def forward_solve(L: list[list[np.ndarray]], B: np.ndarray) -> np.ndarray:
    """W with L W = B per state, for L from ``cholesky_columns`` and B (n, r, N): r right-hand sides of N states."""
    n = len(L)
    W = np.empty_like(B)
    for i in range(n):
        t = B[i].copy()
        for k in range(i):
            t -= L[i][k] * W[k]
        W[i] = t / L[i][i]
    return W
