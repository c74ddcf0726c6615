"""The GB manifold b = p = 0, the matrix K and the desingularised slipping flow (sections 3.5-5 of the paper).

One name space for the GB analysis, made of two modules:

* ``crosscheck.theory.gb.linearisation``: the desingularised vector field of eq. f
  and its Jacobian, J = A B and K = B A on the manifold (eqs. matA, matB, K),
  the type of a GB point (node / saddle / focus) and its eigenvectors in the
  (p, b) plane (Theorem 4.1).
* ``crosscheck.theory.gb.manifold``: the manifold at fixed Psi as closed curves, the
  zeros of det K along them and the formulas of sections 4.2-4.4 (eqs. detK,
  detK0, B, Psiquartic, Psiquarticeps, ghastly, pdotarg).

``slip_until_event`` and the rest of ``crosscheck.theory.slipping`` are re-exported
here, as the paper treats the slipping flow and its GB points together.
"""

from crosscheck.theory.gb.linearisation import (
    GBType,
    K,
    K_from_AB,
    Quadrant,
    eigen,
    f,
    gb_type,
    jacobian,
    linear_orbits,
    matrix_A,
    matrix_B,
    quadrant,
)
from crosscheck.theory.gb.manifold import (
    GBCurve,
    b0_coefficients,
    det_K,
    det_K_as_printed,
    det_K_zeros,
    detK0_coefficients,
    detK0_residual,
    gb_manifold,
    gb_theta_gap,
    ghastly,
    p_dot_on_p0,
    psi_quartic,
    psi_quartic_eps,
    psi_quartic_roots,
)
from crosscheck.theory.slipping import X_STATE, SlipResult, slip_outcomes, slip_rhs, slip_until_event

__all__ = [
    "X_STATE",
    "SlipResult",
    "slip_outcomes",
    "slip_rhs",
    "slip_until_event",
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
    "det_K",
    "det_K_as_printed",
    "detK0_coefficients",
    "detK0_residual",
    "b0_coefficients",
    "psi_quartic",
    "psi_quartic_roots",
    "psi_quartic_eps",
    "ghastly",
    "p_dot_on_p0",
    "GBCurve",
    "gb_manifold",
    "gb_theta_gap",
    "det_K_zeros",
]
