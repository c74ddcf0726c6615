"""One contact's exact-cone NCP in closed form, vectorised over a batch: lift-off, stick, or slip along a root of h(phi).

The problem (``crosscheck.engines.pinocchio.stepper``, world axes: two
tangential rows t, then the normal n): find lambda in the Coulomb cone
K_mu = {|lambda_t| <= mu lambda_n} with u+ = u + G lambda, u+_n >= 0,
lambda_n u+_n = 0 and, when lambda_n > 0, either u+ = 0 inside the cone
(stick) or lambda = lambda_n (n - mu d) with u+_t = a d, a > 0 (slip along
the unit vector d, the friction opposing the end-of-step slip).  Its
candidates, each in closed form:

* u_n >= 0: lambda = 0.  It is what Pinocchio's PGS returns from its cold
  start: its first normal update is max(0, -u_n / G_nn) = 0, the cone then
  has radius 0, the iterate does not move and PGS stops on its proximal
  criterion.  (Where the discrete Painleve condition G_nn - mu g.d < 0 holds
  for some d, the NCP may also have solutions with lambda_n > 0; PGS does
  not see them and neither do we.)
* mu = 0: lambda = (0, 0, -u_n / G_nn).
* stick: lambda = -G^-1 u, a solution iff it lies in K_mu.
* slip: with d = (cos phi, sin phi), g = G_tn and A = G_tt, the normal row
  gives lambda_n = -u_n / D(phi), D = G_nn - mu g.d (the step's p in units of
  1 / m), and the tangential rows say that D u_t - u_n (g - mu A d) is
  parallel to d: h(phi) = (D u_t - u_n (g - mu A d)) x d = 0, a
  trigonometric polynomial of degree 2,
  h = a0 + a1 cos phi + b1 sin phi + a2 cos 2 phi + b2 sin 2 phi,
  with at most four roots.  A root is a solution iff D > 0 and a > 0.

``solve`` brackets every root of h on a grid of ``GRID`` angles (a pair of
roots inside one cell is caught by the bound |h| <= max|h''| delta^2 / 8 at
the nearer end of a cell where h' changes sign), skips the cells where D or
a D is negative beyond what the cell can hide, polishes each root by Newton
from the cell's secant point, and returns the solution where the NCP has
exactly one.  (PGS starts cold at every step: an impulse guess is used by
one solve only, measured.)  Where it has
several (just before p = 0 the stick and the slip; at a jam above mu_P two
slips), the discrete problem does not say which one the engine takes:
Pinocchio's PGS does, by where it converges from lambda = 0 (the module
docstring of the stepper), so those rows are returned unsolved for the
caller to hand to PGS, as are rows whose roots are too close to resolve.
"""

from __future__ import annotations

import numpy as np

__all__ = ["GRID", "solve", "h_coefficients"]

#: Angles of the grid that brackets the roots of h (cell width 2 pi / GRID).
GRID = 128

#: Newton steps per root from the cell's secant point: its error ~ (h''/h') delta^2 / 8 ~ 3e-4 (h''/h') falls to
#: ~1e-7, 1e-14, rounding (quadratic convergence); as many again for a root not yet at rounding (small h' against h''),
#: and a root still off after them is handed to PGS.
NEWTON_STEPS = 3

_PHI = 2.0 * np.pi * np.arange(GRID + 1) / GRID
_BASIS = np.stack((np.ones(GRID + 1), np.cos(_PHI), np.sin(_PHI), np.cos(2 * _PHI), np.sin(2 * _PHI)))
_DBASIS = np.stack((np.zeros(GRID + 1), -np.sin(_PHI), np.cos(_PHI), -2 * np.sin(2 * _PHI), 2 * np.cos(2 * _PHI)))
_SECOND = np.array([0.0, 1.0, 1.0, 4.0, 4.0])  # |d^2/dphi^2| of (1, cos, sin, cos 2, sin 2) <= these
_EPS = np.finfo(float).eps


def h_coefficients(G: np.ndarray, u: np.ndarray, mu: np.ndarray) -> np.ndarray:
    """Fourier coefficients (a0, a1, b1, a2, b2) of h(phi), D(phi) and a(phi) D(phi), (P, 3, 5), for P problems G (P, 3, 3),
    u (P, 3), mu (P,) (module docstring; a D = (D u_t - u_n (g - mu A d)) . d, the slip speed times D)."""
    ux, uy, un = u[:, 0], u[:, 1], u[:, 2]
    gx, gy, Gnn = G[:, 0, 2], G[:, 1, 2], G[:, 2, 2]
    a, b, e = G[:, 0, 0], G[:, 0, 1], G[:, 1, 1]
    out = np.zeros(
        (u.shape[0], 3, 5)
    )  # filled column by column: np.stack costs more than the arithmetic at these sizes
    # D (u_t x d) = G_nn (ux s - uy c) - mu (gx c + gy s)(ux s - uy c); -u_n (g x d); + u_n mu (A d x d),
    # A d x d = (a - e) c s - b (c^2 - s^2); products of c and s expanded into the second harmonics
    mgu_x, mgu_y = mu * (gx * ux - gy * uy), mu * (gx * uy + gy * ux)
    un_mu = un * mu
    out[:, 0, 0] = -0.5 * mu * (gy * ux - gx * uy)
    out[:, 0, 1] = un * gy - Gnn * uy
    out[:, 0, 2] = Gnn * ux - un * gx
    out[:, 0, 3] = 0.5 * mgu_y - un_mu * b
    out[:, 0, 4] = 0.5 * (un_mu * (a - e) - mgu_x)
    out[:, 1, 0] = Gnn
    out[:, 1, 1] = -mu * gx
    out[:, 1, 2] = -mu * gy
    # D (u_t . d) - u_n (g . d) + u_n mu (d . A d), d . A d = (a + e) / 2 + (a - e) / 2 cos 2 phi + b sin 2 phi
    out[:, 2, 0] = 0.5 * (un_mu * (a + e) - mu * (gx * ux + gy * uy))
    out[:, 2, 1] = out[:, 0, 2]
    out[:, 2, 2] = Gnn * uy - un * gy
    out[:, 2, 3] = out[:, 0, 4]
    out[:, 2, 4] = un_mu * b - 0.5 * mgu_y
    return out


def _complex(coef: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(a0, C1, C2) of coefficients (P, 5): h = a0 + Re(C1 z + C2 z^2), z = exp(i phi), C_k = a_k - i b_k."""
    return coef[:, 0], coef[:, 1] - 1j * coef[:, 2], coef[:, 3] - 1j * coef[:, 4]


def _h(a0: np.ndarray, C1: np.ndarray, C2: np.ndarray, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """h(phi) and h'(phi) = Re(i z (C1 + 2 C2 z)) of P problems, (P,) each (``_complex``; Horner's rule in z takes
    fewer numpy calls than the cos and sin of phi and 2 phi)."""
    z = np.exp(1j * phi)
    t = C2 * z
    return a0 + ((t + C1) * z).real, -((C1 + 2.0 * t) * z).imag


def _dh(coef: np.ndarray, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """h'(phi) and h''(phi) of P problems, (P,) each, for coefficients (P, 5)."""
    c1, s1 = np.cos(phi), np.sin(phi)
    c2, s2 = c1 * c1 - s1 * s1, 2.0 * s1 * c1
    a0, a1, b1, a2, b2 = coef.T
    return b1 * c1 - a1 * s1 + 2.0 * (b2 * c2 - a2 * s2), -(a1 * c1 + b1 * s1) - 4.0 * (a2 * c2 + b2 * s2)


def _curvature(coef: np.ndarray) -> np.ndarray:
    """A bound on |f''| of trigonometric polynomials of degree 2, (...,) for coefficients (..., 5)."""
    return np.abs(coef) @ _SECOND


def _hidden_pairs(coef: np.ndarray, H: np.ndarray, change: np.ndarray, bound: np.ndarray) -> np.ndarray:
    """Per problem, whether two roots of h may share one grid cell (no sign ``change`` at its ends).

    Then h has an extremum x* inside (h' changes sign) whose value has the other sign, so an end at distance e of x*
    lies within max|h''| e^2 / 2 of zero: both within max|h''| delta^2 / 2, the nearer within max|h''| delta^2 / 8 =
    ``bound``.  The bound is loose (a stuck tip, u_t ~ 0, meets it often), so such a
    cell's extremum is found by Newton on h' and the pair is hidden only if h there has crossed to the other side
    (or is too close to zero to tell).
    """
    hidden = np.zeros(len(coef), bool)
    aH = np.abs(H)
    lo, hi = np.minimum(aH[:, :-1], aH[:, 1:]), np.maximum(aH[:, :-1], aH[:, 1:])
    r, k = np.nonzero(~change & (lo <= bound[:, None]) & (hi <= 4.0 * bound[:, None]))
    if r.size == 0:
        return hidden
    c, lo, hi = coef[r], _PHI[k], _PHI[k + 1]
    dlo, dhi = np.einsum("pj,jp->p", c, _DBASIS[:, k]), np.einsum("pj,jp->p", c, _DBASIS[:, k + 1])
    turn = (dlo > 0) != (dhi > 0)  # an extremum inside
    c, lo, hi, dlo, dhi, r, k = c[turn], lo[turn], hi[turn], dlo[turn], dhi[turn], r[turn], k[turn]
    x = lo + (hi - lo) * dlo / (dlo - dhi)
    with np.errstate(divide="ignore", invalid="ignore"):
        # h at x is off h(x*) by ~h'' (x - x*)^2 / 2: two Newton steps (x - x* ~ 1e-7, then ~1e-14) are plenty
        for _ in range(2):
            dh, d2h = _dh(c, x)
            x = x - dh / d2h
    hx, _ = _h(*_complex(c), np.clip(x, lo, hi))
    unsure = ((hx > 0) != (H[r, k] > 0)) | (np.abs(hx) <= 64 * _EPS * np.abs(c).sum(axis=1))
    hidden[r[unsure]] = True
    return hidden


def _roots(coef: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The roots of h that may be solutions, as (row, phi) pairs, and per row whether a root pair may hide in one
    cell or a root did not converge; ``coef`` (P, 3, 5) from ``h_coefficients``."""
    F = coef @ _BASIS  # (P, 3, GRID + 1): h, D and a D on the grid; the last column repeats the first (phi = 2 pi)
    ch, H = coef[:, 0], F[:, 0]
    pos = H > 0
    change = pos[:, :-1] != pos[:, 1:]
    delta = 2 * np.pi / GRID
    bound = _curvature(coef) * (delta * delta / 2)  # (P, 3)
    hidden = _hidden_pairs(ch, H, change, bound[:, 0] / 4)
    row, k = np.nonzero(change)
    # a root in a cell where D or a D lies below -max|f''| delta^2 / 2 at an end is negative there (so it is no
    # solution): f at an interior point x* >= 0 would keep f >= -max|f''| delta^2 / 2 within delta of x*
    keep = ~(np.minimum(F[row, 1:, k], F[row, 1:, k + 1]) < -bound[row, 1:]).any(axis=1)
    row, k = row[keep], k[keep]
    lo, hi = _PHI[k], _PHI[k + 1]
    hlo, hhi = H[row, k], H[row, k + 1]
    c = ch[row]
    cz = _complex(c)
    phi = lo + (hi - lo) * hlo / (hlo - hhi)  # the secant point: within (h''/h') delta^2 / 8 of the root
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(NEWTON_STEPS):
            h, dh = _h(*cz, phi)
            phi = phi - h / dh
        tol = 64 * _EPS * np.abs(c).sum(axis=1)
        h, dh = _h(*cz, phi)
        slow = np.flatnonzero(np.abs(h) > tol)
        if slow.size:  # a root where h' is small against h'' (two roots a cell or so apart): Newton needs more steps
            cs = tuple(x[slow] for x in cz)
            ps = phi[slow]
            for _ in range(NEWTON_STEPS):
                hs, dhs = _h(*cs, ps)
                ps = ps - hs / dhs
            phi[slow] = ps
            h[slow] = _h(*cs, ps)[0]
    # a root that left its cell or whose h is above rounding is one Newton could not settle (a near-double root)
    bad = ~((phi >= lo) & (phi <= hi) & (np.abs(h) <= tol))
    hidden[row[bad]] = True
    return row, phi, hidden


def solve(G: np.ndarray, u: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The impulse of each of P problems where the NCP has one solution.

    Args:
      G: (P, 3, 3) Delassus operators (symmetric positive definite).
      u: (P, 3) contact velocities at the end of the step without impulse.
      mu: (P,) friction coefficients.

    Returns:
      (lambda (P, 3), solved (P,) bool, kind (P,) int8: 0 none, 1 stick, 2 slip, -1 unsolved).
      Where ``solved`` is False the problem has several solutions or could
      not be resolved (lambda is NaN there): the caller's PGS decides.
    """
    P = u.shape[0]
    lam = np.zeros((P, 3))
    kind = np.zeros(P, np.int8)
    push = u[:, 2] < 0.0
    frictionless = push & (mu == 0.0)
    if frictionless.any():
        lam[frictionless, 2] = -u[frictionless, 2] / G[frictionless, 2, 2]
        kind[frictionless] = 2
        push &= ~frictionless
    if push.all():
        idx = slice(None)  # the common case (the caller passes the pressed rows): no copies
        Gi, ui, mi = G, u, mu
    else:
        idx = np.flatnonzero(push)
        if idx.size == 0:
            return lam, np.ones(P, bool), kind
        Gi, ui, mi = G[idx], u[idx], mu[idx]
    n = len(ui)
    stick = -np.linalg.solve(Gi, ui[:, :, None])[:, :, 0]
    stick_ok = (stick[:, 2] > 0.0) & (np.hypot(stick[:, 0], stick[:, 1]) <= mi * stick[:, 2])
    row, phi, unresolved = _roots(h_coefficients(Gi, ui, mi))
    d = np.stack((np.cos(phi), np.sin(phi)), axis=1)
    Gr, ur, mr = Gi[row], ui[row], mi[row]
    D = Gr[:, 2, 2] - mr * (Gr[:, 0, 2] * d[:, 0] + Gr[:, 1, 2] * d[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        lam_n = -ur[:, 2] / D
    slip = np.column_stack((-mr * lam_n * d[:, 0], -mr * lam_n * d[:, 1], lam_n))
    u_plus = ur + np.einsum("pij,pj->pi", Gr, slip)
    slip_ok = (D > 0.0) & (np.einsum("pi,pi->p", u_plus[:, :2], d) > 0.0)
    n_slip = np.bincount(row[slip_ok], minlength=n)
    count = n_slip + stick_ok
    both = stick_ok & (n_slip == 1)
    if both.any():
        # a slip at the edge of the stick region (a -> 0) is the sticking impulse itself: one solution, not two
        ok_rows = row[slip_ok]
        close = np.linalg.norm(slip[slip_ok] - stick[ok_rows], axis=1) <= 1e-9 * np.linalg.norm(stick[ok_rows], axis=1)
        same = np.zeros(n, bool)
        same[ok_rows[close]] = True
        count[both & same] = 1
    one = (count == 1) & ~unresolved
    out = np.full((n, 3), np.nan)
    use_stick = one & stick_ok
    out[use_stick] = stick[use_stick]
    k = np.zeros(n, np.int8)
    k[use_stick] = 1
    pick = slip_ok & one[row] & ~stick_ok[row]
    out[row[pick]] = slip[pick]
    k[row[pick]] = 2
    k[~one] = -1
    lam[idx], kind[idx] = out, k
    return lam, kind >= 0, kind
