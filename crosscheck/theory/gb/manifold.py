"""The GB manifold b = p = 0 at fixed Psi as closed curves, the zeros of det K on it, and the formulas of sections 4.2-4.4.

Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painleve
paradox*, sections 3.5 and 4.2-4.4 (eqs. detK, detK0, B, Psiquartic,
Psiquarticeps, ghastly, pdotarg).  Scaled units throughout.

* ``gb_manifold``: the closed curves b = p = 0 at fixed Psi, as arrays
  (``GBCurve``), and ``det_K_zeros`` along them.
* ``det_K``, ``detK0_coefficients``, ``b0_coefficients``, ``psi_quartic``,
  ``psi_quartic_eps``, ``ghastly``, ``p_dot_on_p0``: section 4.2-4.4 formulas.

Two misprints of the paper are implemented corrected (tests show both forms):
eq. detK prints the prefactor eta alpha cos^2 theta cos^2 varphi; expanding
K11 K22 - K12 K21 of eq. K gives eta alpha mu cos^2 theta cos^2 varphi (the
coefficient E of eq. detK0coeffs, which has the mu, agrees with the latter).
Eq. pdotarg's left side is finite only as p dp/dt (the derivative in the time
tau with dt = p dtau): dp/dt itself is unbounded at p = 0 since F_z = -b/p.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crosscheck.checks import ALPHA, ETA, MU, RATE, THETA, check, integer
from crosscheck.theory.critical import Psi_L, theta_12, varphi_pm
from crosscheck.theory.gb.linearisation import K, gb_type

#: The most samples per theta interval of ``gb_manifold`` (each curve then has up to 4e5 points).
MAX_SAMPLES = 100_000

__all__ = [
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

# --------------------------------------------------------------------------
# det K and the conics of section 4.2 (eqs. detK, detK0, B, Psiquartic)
# --------------------------------------------------------------------------


def det_K(theta, varphi, Psi, Theta, eta, mu, alpha):
    """det K, eq. detK with its prefactor corrected to eta alpha mu cos^2 theta cos^2 varphi.

    Equal to K11 K22 - K12 K21 of eq. K for all arguments (an identity).
    """
    return _det_K(theta, varphi, Psi, Theta, eta, mu, alpha, printed=False)


def det_K_as_printed(theta, varphi, Psi, Theta, eta, mu, alpha):
    """Eq. detK exactly as printed (prefactor eta alpha cos^2 theta cos^2 varphi, no mu): differs unless mu = 1."""
    return _det_K(theta, varphi, Psi, Theta, eta, mu, alpha, printed=True)


def _det_K(theta, varphi, Psi, Theta, eta, mu, alpha, *, printed):
    theta = check("theta", theta, THETA)
    varphi, Psi, Theta = (check(n, v) for n, v in (("varphi", varphi), ("Psi", Psi), ("Theta", Theta)))
    eta, mu, alpha = check("eta", eta, ETA), check("mu", mu, MU), check("alpha", alpha, ALPHA)
    st, ct, cp = np.sin(theta), np.cos(theta), np.cos(varphi)
    tan, cot = st / ct, ct / st
    s = alpha * mu * st * ct * cp
    pre = eta * alpha * (1.0 if printed else mu) * ct**2 * cp**2
    return pre * (Theta * (-2 * tan - (1 + alpha) * cot) + 2 * Psi * s) + eta**2 * (
        Theta**2 * (2 * (1 + alpha) - 2 * tan**2)
        + Theta * Psi * s * (4 * tan - 2 * (1 + alpha) * cot)
        - 2 * Psi**2 * s**2
    )


def detK0_coefficients(theta, varphi, eta, mu, alpha):
    """(A, B, Gamma, Delta, E) of eq. detK0coeffs: det K = 0 iff A Psi^2 + B Psi Theta + Gamma Psi = Delta Theta^2 + E Theta.

    Precisely, det K = (eta cos^5 theta / sin theta) (A Psi^2 + B Psi Theta +
    Gamma Psi - Delta Theta^2 - E Theta) (``detK0_residual``), so the conic is
    det K = 0 for eta > 0 and theta in (0, pi/2).
    """
    theta = check("theta", theta, THETA)
    varphi = check("varphi", varphi)
    eta, mu, alpha = check("eta", eta, ETA), check("mu", mu, MU), check("alpha", alpha, ALPHA)
    t, cp = np.tan(theta), np.cos(varphi)
    A = -2 * eta * alpha**2 * mu**2 * t**3 * cp**2
    B = 2 * eta * alpha * mu * cp * t * (1 + t**2) * (2 * t**2 - (1 + alpha))
    Gamma = 2 * alpha**2 * mu**2 * cp**3 * t**2
    Delta = 2 * eta * t * (1 + t**2) ** 2 * (t**2 - (1 + alpha))
    E = alpha * mu * cp**2 * (1 + t**2) * (2 * t**2 + (1 + alpha))
    return A, B, Gamma, Delta, E


def detK0_residual(theta, varphi, Psi, Theta, eta, mu, alpha):
    """A Psi^2 + B Psi Theta + Gamma Psi - Delta Theta^2 - E Theta (eq. detK0 as a residual)."""
    A, B, Gamma, Delta, E = detK0_coefficients(theta, varphi, eta, mu, alpha)
    return A * Psi**2 + B * Psi * Theta + Gamma * Psi - Delta * Theta**2 - E * Theta


def b0_coefficients(theta):
    """(M, N) of eq. Bcoeffs: b = 0 iff M Psi^2 + Theta^2 = N (eq. B), an ellipse in (Psi, Theta)."""
    t = np.tan(check("theta", theta, THETA))
    return 1 / (1 + t**2), np.sqrt(1 + t**2) / t


def psi_quartic(theta, varphi, eta, mu, alpha) -> np.ndarray:
    """Coefficients (C4, C3, C2, C1, C0) of eq. Psiquartic, stacked on the last axis (highest first, as np.roots).

    The quartic eliminates Theta between the conic det K = 0 (eq. detK0) and
    the ellipse b = 0 (eq. B); evaluate it on p = 0 (theta = theta_+-(varphi)).
    """
    A, B, G, D, E = detK0_coefficients(theta, varphi, eta, mu, alpha)
    M, N = b0_coefficients(theta)
    C4 = (A + M * D) ** 2 + M * B**2
    C3 = 2 * (A * G + M * (G * D - E * B))
    C2 = G**2 - 2 * D * N * (A + M * D) - N * B**2 + M * E**2
    C1 = 2 * N * (E * B - G * D)
    C0 = N * (N * D**2 - E**2)
    return np.stack(np.broadcast_arrays(C4, C3, C2, C1, C0), axis=-1)


def psi_quartic_roots(theta, varphi, eta, mu, alpha, *, imag_tol: float = 1e-9):
    """Real zeros of det K on the GB manifold above one (theta, varphi) on p = 0 (scalars).

    Solves eq. Psiquartic, then recovers Theta from eq. detK0 (linear in Theta
    once Theta^2 = N - M Psi^2 is substituted) and keeps the roots that lie on
    the ellipse b = 0 (squaring can add spurious roots).

    Returns:
      (Psi, Theta): two 1-D arrays (possibly empty) of the zeros of det K.
    """
    coeffs = psi_quartic(theta, varphi, eta, mu, alpha)
    roots = np.roots(coeffs)
    real = roots[np.abs(roots.imag) <= imag_tol * np.maximum(1, np.abs(roots))].real
    A, B, G, D, E = detK0_coefficients(theta, varphi, eta, mu, alpha)
    M, N = b0_coefficients(theta)
    Psi_out, Theta_out = [], []
    for Psi in np.sort(real):
        denom = E - B * Psi
        Theta = ((A + M * D) * Psi**2 + G * Psi - D * N) / denom
        if abs(Theta**2 - (N - M * Psi**2)) <= 1e-6 * N:
            Psi_out.append(Psi)
            Theta_out.append(Theta)
    return np.array(Psi_out), np.array(Theta_out)


def psi_quartic_eps(mu_hat, varphi_hat, alpha) -> np.ndarray:
    """Leading-order coefficients (C4, C3, C2, C1, C0) of eq. Psiquarticeps, near mu = mu_P.

    mu = mu_P (1 + eps^2 mu_hat), varphi = -pi/2 + eps varphi_hat (eq. mupperturb).
    """
    mu_hat, varphi_hat = check("mu_hat", mu_hat, MU), check("varphi_hat", varphi_hat)
    a = check("alpha", alpha, ALPHA)
    C4 = (1 + a) ** 2 * (2 * (2 + a) * mu_hat - varphi_hat**2)
    C2 = -((1 + a) ** 1.5) * (2 + a) ** 1.5 * (4 * (2 + a) * mu_hat - (3 + a) * varphi_hat**2)
    C0 = (1 + a) * (2 + a) ** 4 * (2 * mu_hat - varphi_hat**2)
    z = 0 * C4
    return np.stack(np.broadcast_arrays(C4, z, C2, z, C0), axis=-1)


def ghastly(theta, eta, alpha, *, sign=+1):
    """Right side of eq. ghastly: the value of alpha mu cos^2 varphi where det K = 0 at Psi = 0.

    sign = +1 for Theta > 0, -1 for Theta < 0:
    +- 2 eta tan^(1/2) theta (1 + tan^2 theta)^(5/4) [(1 + alpha) - tan^2 theta] / [(1 + alpha) + 2 tan^2 theta].
    """
    t = np.tan(check("theta", theta, THETA))
    eta, alpha = check("eta", eta, ETA), check("alpha", alpha, ALPHA)
    return sign * 2 * eta * np.sqrt(t) * (1 + t**2) ** 1.25 * ((1 + alpha) - t**2) / ((1 + alpha) + 2 * t**2)


def p_dot_on_p0(theta, varphi, Psi, Theta, eta, mu, alpha):
    """Eq. pdotarg: (1 + alpha) alpha mu cos^2 theta cos^2 varphi b / eta on p = 0.

    This is the limit of p dp/dt (real time) as p -> 0, i.e. dp/dtau with
    dt = p dtau; dp/dt itself is unbounded there (F_z = -b/p).  Its sign is
    that of b: a slipping (b < 0) trajectory crosses into p < 0 unless
    varphi = -pi/2 or theta = pi/2.
    """
    theta = check("theta", theta, THETA)
    varphi, Psi, Theta = (check(n, v) for n, v in (("varphi", varphi), ("Psi", Psi), ("Theta", Theta)))
    eta, mu, alpha = check("eta", eta, ETA), check("mu", mu, MU), check("alpha", alpha, ALPHA)
    b = (Psi**2 * np.cos(theta) ** 2 + Theta**2) * np.sin(theta) - 1
    with np.errstate(divide="ignore", invalid="ignore"):
        return (1 + alpha) * alpha * mu * np.cos(theta) ** 2 * np.cos(varphi) ** 2 * b / eta


# --------------------------------------------------------------------------
# The GB manifold at fixed Psi (section 3.5, Fig. GBs_bif3)
# --------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class GBCurve:
    """One closed curve of the GB manifold b = p = 0 at fixed Psi, projected to (theta, varphi, Theta).

    Attributes:
      mu, alpha, Psi: parameters.
      theta, varphi, Theta: (n,) samples in order along the closed curve (the
        last sample equals the first).
      crosses_zero: whether Theta changes sign along the curve (it then passes
        through Theta = 0 where b = 0 touches Theta = 0, at the edges of the
        theta gap of ``gb_theta_gap``); otherwise Theta has one sign.
    """

    mu: float
    alpha: float
    Psi: float
    theta: np.ndarray
    varphi: np.ndarray
    Theta: np.ndarray
    crosses_zero: bool

    @property
    def sign(self) -> int:
        """+1 / -1 for a curve in Theta > 0 / Theta < 0; 0 if it crosses Theta = 0."""
        return 0 if self.crosses_zero else int(np.sign(np.median(self.Theta)))

    def x(self, eta) -> np.ndarray:
        """(n, 6) states on the curve ordered as ``X_STATE`` (psi = 0)."""
        eta = np.broadcast_to(np.asarray(eta, float), self.theta.shape)
        zero = np.zeros_like(self.theta)
        return np.stack([eta, self.varphi, zero, zero + self.Psi, self.theta, self.Theta], axis=-1)

    def K(self, eta) -> np.ndarray:
        """(n, 2, 2) K of eq. K along the curve."""
        return K(self.theta, self.varphi, self.Psi, self.Theta, eta, self.mu, self.alpha)

    def types(self, eta) -> np.ndarray:
        """(n,) ``GBType`` values along the curve."""
        return np.atleast_1d(gb_type(self.K(eta)))


def gb_theta_gap(Psi) -> tuple[float, float] | None:
    """The theta interval where b = 0 has no real Theta: Psi^2 sin theta cos^2 theta > 1.

    Empty (None) for |Psi| <= Psi_L (eq. psil); otherwise the two roots in
    (0, pi/2) of Psi^2 s (1 - s^2) = 1, s = sin theta, around theta_L.
    """
    Psi = float(check("Psi", Psi, RATE))
    if abs(Psi) <= Psi_L:
        return None
    roots = np.roots([Psi**2, 0.0, -(Psi**2), 1.0])
    s = np.sort(roots[(np.abs(roots.imag) < 1e-12) & (roots.real > 0) & (roots.real < 1)].real)
    return float(np.arcsin(s[0])), float(np.arcsin(s[-1]))


def _spaced(lo, hi, n):
    # cosine spacing: varphi_+- and Theta have square-root ends at theta_1,2 and at the gap
    u = np.linspace(0.0, 1.0, n)
    return lo + (hi - lo) * 0.5 * (1 - np.cos(np.pi * u))


def gb_manifold(mu, Psi, alpha, *, n: int = 201) -> list[GBCurve]:
    """The closed curves of the GB manifold b = p = 0 for fixed Psi (section 3.5, Fig. GBs_bif3).

    Parameterised by theta along p = 0: varphi = varphi_-+(theta) (eq.
    varphistar) for theta in [theta_1, theta_2] (eq. theta12), and Theta =
    +- sqrt(1/sin theta - Psi^2 cos^2 theta) from b = 0.  Topology as |Psi| grows:

    * |Psi| < Psi_L (and in mechanism II up to Psi_1): two curves, one in
      Theta > 0 and one in Theta < 0.
    * mechanism III (mu > mu_L) with Psi_L < |Psi| < Psi_1: the theta gap of
      ``gb_theta_gap`` lies inside (theta_1, theta_2): two curves, each
      crossing Theta = 0.
    * Psi_1 < |Psi| < Psi_2: one curve crossing Theta = 0.
    * |Psi| > Psi_2, or mu < mu_P: empty.  At mu = mu_P the manifold is the two
      points theta_P, varphi = -pi/2, Theta = +-sqrt(csc theta_P) (returned as
      curves of one sample each).

    Args:
      mu, Psi, alpha: parameters (Psi is the azimuthal rate, fixed).
      n: samples per theta interval and branch (each curve has about 2n or 4n).

    Returns:
      A list of ``GBCurve``, ordered by theta then by Theta sign (+ first).
    """
    mu = float(check("mu", mu, MU))
    alpha = float(check("alpha", alpha, ALPHA))
    Psi = float(check("Psi", Psi, RATE))
    n = integer("n", n, 2, MAX_SAMPLES)
    th1, th2 = (float(t) for t in theta_12(mu, alpha))
    if math.isnan(th1):
        return []
    gap = gb_theta_gap(Psi)
    intervals = [(th1, th2)]
    if gap is not None:
        ga, gb_ = gap
        intervals = [(lo, hi) for lo, hi in ((th1, min(th2, ga)), (max(th1, gb_), th2)) if lo <= hi]
    curves = []

    def Theta_of(theta):
        return np.sqrt(np.maximum(1 / np.sin(theta) - Psi**2 * np.cos(theta) ** 2, 0.0))

    for lo, hi in intervals:
        if lo == hi:  # a single point of p = 0 (mu = mu_P) or a tangency with the gap
            th = np.array([lo])
            vp = np.array([-math.pi / 2]) if lo in (th1, th2) else varphi_pm(th, mu, alpha)[0]
            Th = Theta_of(th)
            for sgn in (+1, -1):
                curves.append(GBCurve(mu, alpha, Psi, th, vp, sgn * Th, bool(Th[0] == 0)))
            continue
        th = _spaced(lo, hi, n)
        v_minus, v_plus = varphi_pm(th, mu, alpha)
        # varphi_-+ meet at -pi/2 exactly where theta = theta_1,2; rounding of the arccos argument
        # can leave NaN there, which is the tangency value -pi/2
        v_minus = np.where(np.isnan(v_minus), -math.pi / 2, v_minus)
        v_plus = np.where(np.isnan(v_plus), -math.pi / 2, v_plus)
        loop_th = np.concatenate([th, th[::-1][1:]])
        loop_vp = np.concatenate([v_minus, v_plus[::-1][1:]])
        edge_gap = gap is not None and (lo > th1 or hi < th2)
        if not edge_gap:
            Th = Theta_of(loop_th)
            for sgn in (+1, -1):
                curves.append(GBCurve(mu, alpha, Psi, loop_th, loop_vp, sgn * Th, False))
        else:
            # Theta = 0 at the gap edge: the Theta > 0 and Theta < 0 halves join into one closed curve.
            # Start the loop at the gap edge so that both halves begin and end there.
            if hi < th2:  # interval [theta_1, gap_lo]: loop from the edge on the varphi_- branch
                half_th = np.concatenate([th[::-1], th[1:]])
                half_vp = np.concatenate([v_minus[::-1], v_plus[1:]])
            else:  # interval [gap_hi, theta_2]
                half_th = np.concatenate([th, th[::-1][1:]])
                half_vp = np.concatenate([v_minus, v_plus[::-1][1:]])
            Th = Theta_of(half_th)
            Th[0] = Th[-1] = 0.0  # exactly on the gap edge (the cubic's root leaves ~1e-8 from the sqrt)
            curves.append(
                GBCurve(
                    mu,
                    alpha,
                    Psi,
                    np.concatenate([half_th, half_th[::-1][1:]]),
                    np.concatenate([half_vp, half_vp[::-1][1:]]),
                    np.concatenate([Th, -Th[::-1][1:]]),
                    True,
                )
            )
    return curves


def det_K_zeros(curve: GBCurve, eta, *, iterations: int = 60) -> np.ndarray:
    """Points of ``curve`` where det K = 0 (a zero eigenvalue), refined by bisection in theta.

    Sign changes of det K between consecutive samples are bisected along the
    p = 0 branch they lie on (varphi = varphi_-(theta) or varphi_+(theta),
    Theta with the sign of the samples).

    Returns:
      (m, 3) array of (theta, varphi, Theta).
    """
    eta = float(check("eta", eta, ETA))
    iterations = integer("iterations", iterations, 1, 200)  # 60 halvings already reach the resolution of theta
    d = det_K(curve.theta, curve.varphi, curve.Psi, curve.Theta, eta, curve.mu, curve.alpha)
    out = []
    for i in np.nonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0)[0]:
        minus = curve.varphi[i] + curve.varphi[i + 1] < -math.pi  # both samples on the varphi_- side
        sgn = 1.0 if curve.Theta[i] + curve.Theta[i + 1] > 0 else -1.0

        def point(th):
            vm, vp = varphi_pm(th, curve.mu, curve.alpha)
            vp_ = vm if minus else vp
            vp_ = -math.pi / 2 if math.isnan(vp_) else float(vp_)
            Th = sgn * math.sqrt(max(1 / math.sin(th) - curve.Psi**2 * math.cos(th) ** 2, 0.0))
            return th, vp_, Th

        def g(th):
            t, v, T = point(th)
            return float(det_K(t, v, curve.Psi, T, eta, curve.mu, curve.alpha))

        a, b = sorted((float(curve.theta[i]), float(curve.theta[i + 1])))
        ga = g(a)
        for _ in range(iterations):
            m = 0.5 * (a + b)
            gm = g(m)
            if (gm > 0) == (ga > 0):
                a, ga = m, gm
            else:
                b = m
        out.append(point(0.5 * (a + b)))
    return np.array(out).reshape(-1, 3)
