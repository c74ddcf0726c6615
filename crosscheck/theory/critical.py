"""Critical values of section 3 of the paper and the kinematic cases of section 3.4.

All in scaled units; alpha = m l^2 / I0 (3 for a uniform rod).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from enum import IntEnum

import numpy as np

from crosscheck.checks import ALPHA, MU, RATE, THETA, check

__all__ = [
    "CriticalValues",
    "Mechanism",
    "critical_values",
    "mu_P",
    "mu_C",
    "mu_L",
    "theta_P",
    "theta_L",
    "Psi_L",
    "Psi_P",
    "theta_12",
    "Psi_on_b0",
    "mu_P_star",
    "p_min",
    "theta_pm",
    "varphi_pm",
    "kinematic_case",
    "mechanism",
]

# theta_L and Psi_L do not depend on mu or alpha (eqs. thetal, psil).
theta_L = math.asin(1.0 / math.sqrt(3.0))
Psi_L = math.sqrt(3.0 * math.sqrt(3.0) / 2.0)


def mu_P(alpha):
    """Painleve's critical friction 2 sqrt(alpha + 1) / alpha, eq. mup2D."""
    alpha = check("alpha", alpha, ALPHA)
    return 2.0 * np.sqrt(alpha + 1.0) / alpha


def mu_C(alpha):
    """Genot-Brogliato's critical friction (2/sqrt 3) mu_P, eq. muC."""
    return 2.0 / math.sqrt(3.0) * mu_P(alpha)


def mu_L(alpha):
    """Friction at which theta_1 = theta_L and Psi_1 = Psi_L: (2 alpha + 3) / (alpha sqrt 2), eq. mul."""
    alpha = check("alpha", alpha, ALPHA)
    return (2.0 * alpha + 3.0) / (alpha * math.sqrt(2.0))


def theta_P(alpha):
    """arctan sqrt(1 + alpha), eq. thetap: where p = 0 bounds varphi."""
    alpha = check("alpha", alpha, ALPHA)
    return np.arctan(np.sqrt(1.0 + alpha))


def Psi_P(alpha):
    """((2 + alpha)^3 / (1 + alpha))^(1/4), eq. psip: Psi_1 = Psi_2 at mu = mu_P."""
    alpha = check("alpha", alpha, ALPHA)
    return ((2.0 + alpha) ** 3 / (1.0 + alpha)) ** 0.25


def mu_P_star(varphi, alpha):
    """2 sqrt(alpha + 1) / (alpha |sin varphi|), eq. mup: p < 0 somewhere iff mu > mu_P*."""
    varphi = check("varphi", varphi)
    alpha = check("alpha", alpha, ALPHA)
    with np.errstate(divide="ignore"):
        return 2.0 * np.sqrt(alpha + 1.0) / (alpha * np.abs(np.sin(varphi)))


def p_min(mu, alpha):
    """Smallest value of eq. p over all theta and varphi: 1 + alpha/2 - (alpha/2) sqrt(1 + mu^2).

    At varphi = -pi/2, p = 1 + alpha cos^2 theta - (alpha mu / 2) sin 2 theta =
    1 + alpha/2 + (alpha/2)(cos 2 theta - mu sin 2 theta), whose minimum over
    theta is the expression above; |sin varphi| = 1 there, so no other varphi
    goes lower.  It is 0 exactly at mu = mu_P and negative above.
    """
    mu = check("mu", mu, MU)
    alpha = check("alpha", alpha, ALPHA)
    return 1.0 + 0.5 * alpha - 0.5 * alpha * np.sqrt(1.0 + mu**2)


def _sqrt_discriminant(d, scale):
    # At mu = mu_P the discriminant is zero analytically but rounding can make it
    # -1e-16 * scale.  Treat |d| below a few ulps of its terms as zero so that the
    # double root theta_1 = theta_2 = theta_P is found; below that, NaN (no root).
    tiny = 16 * np.finfo(float).eps * scale
    d = np.where((d < 0) & (d > -tiny), 0.0, d)
    with np.errstate(invalid="ignore"):
        return np.sqrt(d)


def theta_pm(varphi, mu, alpha):
    """Roots (theta_-, theta_+) of p(theta, varphi) = 0 for fixed varphi, eq. thetastar.

    Returns a pair of arrays; NaN where mu < mu_P*(varphi) (no root).
    """
    varphi = check("varphi", varphi)
    mu = check("mu", mu, MU)
    alpha = check("alpha", alpha, ALPHA)
    a = mu * alpha * np.sin(varphi)
    root = _sqrt_discriminant(a**2 - 4.0 * (alpha + 1.0), 4.0 * (alpha + 1.0))
    return np.arctan(-0.5 * a - 0.5 * root), np.arctan(-0.5 * a + 0.5 * root)


def varphi_pm(theta, mu, alpha):
    """Roots (varphi_-, varphi_+) of p(theta, varphi) = 0 for fixed theta, eq. varphistar.

    varphi_-+ = -pi/2 -+ arccos((1 + alpha cos^2 theta) / (alpha mu sin theta cos theta)).
    NaN where the arccos argument exceeds 1 (p > 0 for every varphi).
    """
    theta = check("theta", theta, THETA)
    mu = check("mu", mu, MU)
    alpha = check("alpha", alpha, ALPHA)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # mu -> 0: arg -> inf, no root (NaN)
        arg = (1.0 + alpha * np.cos(theta) ** 2) / (alpha * mu * np.sin(theta) * np.cos(theta))
        # same rounding guard as theta_pm: arg = 1 + O(eps) is the tangency point
        arg = np.where((arg > 1) & (arg < 1 + 16 * np.finfo(float).eps), 1.0, arg)
        acos = np.arccos(arg)
    return -np.pi / 2 - acos, -np.pi / 2 + acos


def theta_12(mu, alpha):
    """(theta_1, theta_2) = theta_-+(-pi/2), eq. theta12; NaN for mu < mu_P."""
    return theta_pm(-np.pi / 2, mu, alpha)


def Psi_on_b0(theta):
    """|Psi| at which b = 0 when Theta = 0: (1 + tan^2)^(3/4) / tan^(1/2), eqs. psi1, psi2."""
    t = np.tan(theta)
    return (1.0 + t**2) ** 0.75 / np.sqrt(t)


@dataclass(frozen=True)
class CriticalValues:
    """Every critical value of section 3 for one (mu, alpha).

    ``theta_1, theta_2, Psi_1, Psi_2, varphi_1, varphi_2`` exist only when
    mu >= mu_P (p < 0 somewhere; at mu = mu_P they meet at theta_P, Psi_P,
    -pi/2) and are NaN otherwise.
    """

    mu: float
    alpha: float
    mu_P: float
    mu_C: float
    mu_L: float
    theta_P: float
    theta_L: float
    Psi_L: float
    Psi_P: float
    theta_1: float
    theta_2: float
    Psi_1: float
    Psi_2: float
    varphi_1: float
    varphi_2: float

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


def critical_values(mu: float, alpha: float) -> CriticalValues:
    """All critical values for friction ``mu`` >= 0 and ``alpha`` > 0 (scalars)."""
    from crosscheck.checks import real_scalar

    mu = real_scalar("mu", mu, MU)  # one value: a list or an array is refused in one line, not by float()
    alpha = real_scalar("alpha", alpha, ALPHA)
    th1, th2 = (float(t) for t in theta_12(mu, alpha))
    thP = float(theta_P(alpha))
    vp1, vp2 = (float(v) for v in varphi_pm(thP, mu, alpha))
    if math.isnan(th1):
        vp1 = vp2 = math.nan
    return CriticalValues(
        mu=mu,
        alpha=alpha,
        mu_P=float(mu_P(alpha)),
        mu_C=float(mu_C(alpha)),
        mu_L=float(mu_L(alpha)),
        theta_P=thP,
        theta_L=theta_L,
        Psi_L=Psi_L,
        Psi_P=float(Psi_P(alpha)),
        theta_1=th1,
        theta_2=th2,
        Psi_1=float(Psi_on_b0(th1)),
        Psi_2=float(Psi_on_b0(th2)),
        varphi_1=vp1,
        varphi_2=vp2,
    )


class Mechanism(IntEnum):
    """How the GB manifold deforms as |Psi| grows, section 3.4 (Fig. mechanisms)."""

    I = 1
    II = 2  # mu_P < mu <= mu_L
    III = 3  # mu > mu_L


def mechanism(mu, alpha):
    """Mechanism I, II or III of section 3.4 for friction ``mu`` and ``alpha``.

    Boundaries: mu = mu_P belongs to I (p >= 0 everywhere, no paradox) and
    mu = mu_L to II (the paper's conclusion writes (mu_P, mu_L]).
    Returns a ``Mechanism`` for scalars, an int8 array otherwise.
    """
    mu = check("mu", mu, MU)
    alpha = check("alpha", alpha, ALPHA)
    out = np.select([mu <= mu_P(alpha), mu <= mu_L(alpha)], [Mechanism.I, Mechanism.II], Mechanism.III).astype(np.int8)
    return Mechanism(int(out)) if out.ndim == 0 else out


def kinematic_case(mu, Psi, alpha):
    """Kinematic case 1..7 of section 3.4 (Figs. mechanisms and muPsicases).

    I:   |Psi| < Psi_L -> 1;  else 2.
    II:  |Psi| < Psi_L -> 3;  < Psi_1 -> 4;  < Psi_2 -> 6;  else 7.
    III: |Psi| < Psi_L -> 3;  < Psi_1 -> 5;  < Psi_2 -> 6;  else 7.
    A |Psi| on a threshold belongs to the case above it (lift-off at Theta = 0
    is possible for |Psi| >= Psi_L, the paper's wording).  Returns an int for
    scalars, an int8 array otherwise.
    """
    mu = check("mu", mu, MU)
    Psi = check("Psi", Psi, RATE)
    alpha = check("alpha", alpha, ALPHA)
    mech = np.asarray(mechanism(mu, alpha))
    th1, th2 = theta_12(mu, alpha)
    with np.errstate(invalid="ignore"):
        psi1, psi2 = Psi_on_b0(th1), Psi_on_b0(th2)
        a = np.abs(Psi)
        paradox = np.select([a < Psi_L, a < psi1, a < psi2], [3, 0, 6], 7)
        paradox = np.where(paradox == 0, np.where(mech == Mechanism.II, 4, 5), paradox)
    out = np.where(mech == Mechanism.I, np.where(a < Psi_L, 1, 2), paradox).astype(np.int8)
    return int(out) if out.ndim == 0 else out
