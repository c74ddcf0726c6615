"""The analytic reference of the dynamics-terms validation, in the paper's scaled units.

M, C, g of the rod from eqs. rotode and linode (``reference_terms``), scaled by q = L q_s and t = t_s / omega
(``scaled_matrices``), and for a chunk of states the tip accelerations of eq. linode2 and the Delassus matrix
(``reference_chunk``); each state's scale factors are its own rod's floats (``Units``).  Pinocchio's side and the
comparison: ``dynamics_terms``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from crosscheck.rod import Rod
from crosscheck.theory import analytic

__all__ = ["reference_terms", "scaled_matrices", "scale_factors", "Units", "units_of", "per_state", "reference_chunk"]


class Rods(NamedTuple):
    """The rods of N states as (N,) arrays, with the names of ``Rod``'s attributes that ``reference_terms`` reads."""

    mass: np.ndarray
    inertia: np.ndarray
    gravity: np.ndarray


def reference_terms(rod: Rod, q, v) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C, g of the rod written from eqs. rotode and linode (physical units).

    Eq. linode is m (X'', Y'', Z'') = F - m g e_z; eq. rotode multiplied by
    I0 cos^2 theta (psi) and I0 (theta) is
      I0 cos^2 theta psi'' - 2 I0 sin theta cos theta psi' theta' = l cos theta (cos psi F_x + sin psi F_y),
      I0 theta'' + I0 sin theta cos theta psi'^2 = -l (sin psi sin theta F_x - cos psi sin theta F_y + cos theta F_z),
    whose right-hand sides are J^T F.  So M = diag(m, m, m, I0 cos^2 theta, I0),
    g = (0, 0, m g, 0, 0), and C is the Christoffel matrix of M (the only C
    linear in v with C v as above and M' - 2C skew-symmetric):
    C[psi, psi] = -I0 s c theta', C[psi, theta] = -I0 s c psi', C[theta, psi] = I0 s c psi'.

    q, v: (N, 5); ``rod`` may also hold one rod per state, its mass, inertia and gravity as (N,) arrays.
    Returns M (N, 5, 5), C (N, 5, 5), g (N, 5).
    """
    q = np.asarray(q, float)
    v = np.asarray(v, float)
    n = q.shape[0]
    theta = q[:, 4]
    psi_dot, theta_dot = v[:, 3], v[:, 4]
    i0 = rod.inertia
    sc = np.sin(theta) * np.cos(theta)
    M = np.zeros((n, 5, 5))
    for j in range(3):
        M[:, j, j] = rod.mass
    M[:, 3, 3] = i0 * np.cos(theta) ** 2
    M[:, 4, 4] = i0
    C = np.zeros((n, 5, 5))
    C[:, 3, 3] = -i0 * sc * theta_dot
    C[:, 3, 4] = -i0 * sc * psi_dot
    C[:, 4, 3] = i0 * sc * psi_dot
    g = np.zeros((n, 5))
    g[:, 2] = rod.mass * rod.gravity
    return M, C, g


def scale_factors(rod: Rod) -> tuple:
    """(L (5,), L L^T (5, 5), m l^2, m l^2 omega, m g l) of ``scaled_matrices``, each as the rod's own floats give it."""
    L = np.array([rod.length] * 3 + [1.0, 1.0])
    ml2 = rod.mass * rod.length**2
    return L, L[:, None] * L[None, :], ml2, ml2 * rod.omega, rod.mass * rod.gravity * rod.length


def scaled_matrices(rod: Rod, M, C, g) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C and a generalised force (g or C v + g) in the paper's scaled units.

    With q = L q_s, L = diag(l, l, l, 1, 1), and t = t_s / omega:
    M_s = L M L / (m l^2), C_s = L C L / (m l^2 omega), g_s = L g / (m g l).
    """
    L, outer, ml2, ml2_omega, mgl = scale_factors(rod)
    return M * outer / ml2, C * outer / ml2_omega, g * L / mgl


def units_of(s: dict, rods: list[Rod]) -> Units:
    """Each state's ``Units``.  Each rod's scale factors in its own floats (Python's l**2 and numpy's differ in the
    last bit now and then), spread to its states; every product with them is then the one a rod at a time would form."""
    of, l, ones = s["rod"], s["l"], np.ones(len(s["rod"]))
    return Units(
        mass=s["m"],
        gravity=s["g"],
        force_scale=per_state(of, rods, lambda r: r.force_scale),
        L=np.stack((l, l, l, ones, ones), axis=-1),
        ml2=per_state(of, rods, lambda r: r.mass * r.length**2),
        ml2_omega=per_state(of, rods, lambda r: r.mass * r.length**2 * r.omega),
        mgl=per_state(of, rods, lambda r: r.mass * r.gravity * r.length),
    )


def per_state(rod_of_state: np.ndarray, rods: list[Rod], value) -> np.ndarray:
    """``value(rod)`` of each state's rod, (N,): computed once per rod with the rod's own floats, as ``Rod`` gives it."""
    return np.array([value(rod) for rod in rods])[rod_of_state]


class Units(NamedTuple):
    """Per-state factors of the scaled units, ``scale_factors``' of each state's rod ((N,) arrays; L (N, 5))."""

    mass: np.ndarray
    gravity: np.ndarray  # accelerations in units of g = l omega^2
    force_scale: np.ndarray  # m g
    L: np.ndarray  # q = L q_s
    ml2: np.ndarray
    ml2_omega: np.ndarray
    mgl: np.ndarray

    def at(self, states: slice) -> Units:
        """The factors of ``states`` only."""
        return Units(*(x[states] for x in self))

    def outer(self) -> np.ndarray:
        """L L^T (N, 5, 5), entry by entry as ``scale_factors`` forms it for one rod."""
        return self.L[:, :, None] * self.L[:, None, :]


def reference_chunk(q, v, lo, s, rates_rad, F, units: Units, outer, factors) -> dict:
    """The reference's quantities of one chunk of states in scaled units.

    ``lo``: its first state; ``s``, ``rates_rad`` (psi', theta' [rad/s]) and F (N, 3) [N] of all states; ``units``,
    ``outer`` and ``factors`` (``analytic.rod_factors`` of each state's rod) the chunk's.
    """
    k = q.shape[0]
    now = slice(lo, lo + k)
    ref_M, ref_C, ref_g = reference_terms(Rods(mass=units.mass, inertia=s["I0"][now], gravity=units.gravity), q, v)
    for x, by, over in (
        (ref_M, outer, units.ml2[:, None, None]),
        (ref_C, outer, units.ml2_omega[:, None, None]),
        (ref_g, units.L, units.mgl[:, None]),
    ):
        x *= by
        x /= over
    # eq. linode2 at six (rates, force) pairs per state: (rates, F), (rates, 0), and at rest with 0 and with
    # the unit forces m g e_j, whose differences are the columns of G (G does not depend on the rates; at
    # rest the difference does not cancel large velocity terms).  One call for the chunk, each state with its
    # rod's factors; the six pairs broadcast against the states' angles.
    zero = np.zeros(k)
    psi_dot, theta_dot = (np.stack((x[now], x[now], zero, zero, zero, zero)) for x in rates_rad)
    forces = np.zeros((6, k, 3))
    forces[0] = F[now]
    for j in range(3):
        forces[3 + j, :, j] = units.force_scale
    ref = analytic.tip_acceleration_of(
        factors, s["psi"][now], s["theta"][now], psi_dot, theta_dot, (forces[..., 0], forces[..., 1], forces[..., 2])
    )
    ref /= units.gravity[:, None]
    ref_G = np.stack([ref[3 + j] - ref[2] for j in range(3)], axis=-1)
    return {
        "tip acc, aba": ref[0],
        "tip acc, G F + free": ref[0],
        "Delassus G": ref_G,
        "free tip acc": ref[1],
        "M (crba)": ref_M,
        "C (Coriolis matrix)": ref_C,
        "g (gravity)": ref_g,
    }
