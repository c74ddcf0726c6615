"""The Kelvin-Voigt contact equivalent to MuJoCo's soft normal row: the compliant rod's (eps, xi) for a MuJoCo run.

MuJoCo-equivalent Kelvin-Voigt parameters (rung 3).  MuJoCo's Computation
chapter prescribes for a constraint with violation r (the contact's signed
distance, < 0 in penetration) and velocity v = r' the reference acceleration

    aref = -B v - k r,   B = 2 / (dmax timeconst),   k = d(r) K,   K = 1 / (dmax^2 timeconst^2 dampratio^2),

with the impedance d(r) of solimp = (d0, dmax, width, midpoint, power)
(``impedance``), and the solver's constraint force, with the regulariser
R = (1 - d)/d A_nn, is f = (d / A_nn)(aref - a0) for an isolated normal row
(A_nn: the row's Delassus entry, a0: its free acceleration).  The gap then
obeys

    r'' = (1 - d) a0 - d B r' - d^2 K r          (an acceleration law),

while the Kelvin-Voigt law of ``crosscheck.engines.compliant`` is a force law,
F_n = -r / eps^2 - (xi / eps) r', so that r'' = a0 + A_nn F_n.  Matching the
stiffness and damping of the two (the coefficients of r and r') gives

    A_nn / eps^2 = d^2 K   ->   eps = (dmax / d) timeconst dampratio sqrt(A_nn),
    A_nn xi / eps = d B    ->   xi  = 2 dampratio / sqrt(A_nn),

i.e. the same natural frequency d / (dmax timeconst dampratio) and the same
damping ratio (dampratio) of the gap.  In the paper's scaled units (timeconst
in 1/omega, width in l, force in m g) the normal Delassus entry of the rod is
the frictionless eq. p,

    A_nn = p(mu = 0) = 1 + alpha cos^2 theta,

the same at C as at A: a force along the normal K applied at C = A - r K has
the moment of the same force at A (r K x K = 0).  The impedance is taken at
the operating penetration, MuJoCo's static balance of the normal row under
the start's free normal acceleration a0 = b (eq. b; the same at C as at A,
z_C = z_A - r): 0 = (1 - d) b - d^2 K r, i.e. |r| = (1 - d(r)) |b| / (d(r)^2 K),
solved for r (``operating_penetration``).  Limits of the match:

* it holds for the normal row alone.  While the rod slips, friction couples
  into the normal row and the gap's acceleration per unit normal force
  becomes eq. p, not A_nn: the Kelvin-Voigt gap then rings at sqrt(p)/eps,
  slower as p -> 0 (the compliant Painleve regime), while MuJoCo's
  regulariser R stays scaled by A_nn.  That difference is rung 4's business;
* MuJoCo's force also has the feed-forward term -d a0 / A_nn (the
  impedance blends the free acceleration out), which a spring-damper has
  not.  It is the largest difference: MuJoCo delivers the fraction d (~0.9)
  of the rigid normal force at once, at zero penetration, while the spring
  builds its force over ~ eps / sqrt(A_nn) ~ timeconst (and the static
  penetrations differ by the factor (1 - d)/d ~ 0.1, MuJoCo's being the
  smaller).  The match is of the spring and damper about a penetration,
  not of the force's response to the free acceleration; that response is
  part of MuJoCo's law, rung 4;
* d(r) varies with the penetration (from d0 at r = 0 to dmax at r >= width):
  the match uses its value at the operating penetration, so eps is right to
  within the spread of dmax / d over the run (at most dmax / d0 - 1, 5.6 %
  for MuJoCo's default solimp);
* it is evaluated at the start state (theta sets A_nn): a rod that rotates
  far changes A_nn by up to the factor 1 + alpha.

All quantities are in the paper's scaled units (section 2.1).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields

from crosscheck.checks import ALPHA, POSITIVE, check
from crosscheck.engines.mujoco.law import impedance
from crosscheck.state import SlipState

__all__ = ["operating_penetration", "KelvinVoigtMatch", "mujoco_equivalent"]


def _stiffness(timeconst: float, dampratio: float, dmax: float) -> tuple[float, float]:
    """MuJoCo's (B, K) of solref (timeconst, dampratio): B = 2/(dmax tc), K = 1/(dmax^2 tc^2 dampratio^2); k = d(r) K."""
    return 2.0 / (dmax * timeconst), 1.0 / (dmax * dmax * timeconst * timeconst * dampratio * dampratio)


def operating_penetration(b: float, *, timeconst: float, dampratio: float, solimp: Sequence[float]) -> float:
    """MuJoCo's static penetration |r| of an isolated normal row under the free normal acceleration b (< 0).

    Solves |r| = (1 - d(r)) |b| / (d(r)^2 K) (module docstring) by bisection:
    the right side falls with |r| (d grows with |r|) and the left rises, so
    the root is unique.  Returns 0 for b >= 0 (nothing presses the contact).
    """
    if b >= 0.0:
        return 0.0
    _, K = _stiffness(timeconst, dampratio, float(solimp[1]))

    def excess(r):
        d = float(impedance(solimp, r))
        return r - (1.0 - d) * (-b) / (d * d * K)

    lo, hi = 0.0, 1.0
    while excess(hi) < 0.0:  # an upper bracket: |r| = 1 is far beyond any width, unless b is huge
        hi *= 2.0
    for _ in range(200):  # bisection to the last bit (excess is monotone, a few evaluations each)
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        lo, hi = (mid, hi) if excess(mid) < 0.0 else (lo, mid)
    return hi


@dataclass(frozen=True)
class KelvinVoigtMatch:
    """MuJoCo's normal row matched by a Kelvin-Voigt contact at the start state (module docstring).

    Attributes:
      eps, xi: the Kelvin-Voigt compliance and damping of ``crosscheck.engines.compliant``
        (F_n = -gap/eps^2 - (xi/eps) gap' in m g, gap in l, time in 1/omega).
      A_nn: the normal Delassus entry 1 + alpha cos^2 theta (frictionless eq. p).
      b: eq. b at the start (the free normal acceleration a0).
      penetration: the operating penetration |r| (scaled by l).
      d: the impedance at it; B, K: MuJoCo's solref damping and stiffness
        (MuJoCo's k = d K); frequency: the gap's natural frequency
        d / (dmax timeconst dampratio) (scaled), the same for both laws.
      timeconst, dampratio, solimp: the MuJoCo options matched.
    """

    eps: float
    xi: float
    A_nn: float
    b: float
    penetration: float
    d: float
    B: float
    K: float
    frequency: float
    timeconst: float
    dampratio: float
    solimp: tuple

    def as_dict(self) -> dict:
        return {
            f.name: (list(getattr(self, f.name)) if f.name == "solimp" else getattr(self, f.name)) for f in fields(self)
        }


def mujoco_equivalent(
    state: SlipState, alpha: float, *, timeconst: float, dampratio: float, solimp: Sequence[float]
) -> KelvinVoigtMatch:
    """Kelvin-Voigt (eps, xi) with MuJoCo's normal stiffness and damping at ``state`` (module docstring).

    eps = (dmax / d) timeconst dampratio sqrt(A_nn), xi = 2 dampratio / sqrt(A_nn),
    A_nn = 1 + alpha cos^2 theta, d = ``impedance`` at ``operating_penetration``.
    """
    alpha = float(check("alpha", alpha, ALPHA))
    timeconst = float(check("timeconst", timeconst, POSITIVE))
    dampratio = float(check("dampratio", dampratio, POSITIVE))
    solimp = tuple(float(v) for v in solimp)
    st, ct = math.sin(state.theta), math.cos(state.theta)
    b = (state.Psi**2 * ct * ct + state.Theta**2) * st - 1.0  # eq. b
    A_nn = 1.0 + alpha * ct * ct
    dmax = solimp[1]
    B, K = _stiffness(timeconst, dampratio, dmax)
    pen = operating_penetration(b, timeconst=timeconst, dampratio=dampratio, solimp=solimp)
    d = float(impedance(solimp, pen))
    eps = (dmax / d) * timeconst * dampratio * math.sqrt(A_nn)
    xi = 2.0 * dampratio / math.sqrt(A_nn)
    return KelvinVoigtMatch(
        eps=eps,
        xi=xi,
        A_nn=A_nn,
        b=b,
        penetration=pen,
        d=d,
        B=B,
        K=K,
        frequency=d / (dmax * timeconst * dampratio),
        timeconst=timeconst,
        dampratio=dampratio,
        solimp=solimp,
    )
