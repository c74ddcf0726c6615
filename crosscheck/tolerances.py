"""Every tolerance of the project, in one place, with where its number comes from.

A value ``got`` passes against ``want`` when
``|got - want| <= atol + rtol * |want|`` (numpy's ``isclose`` rule; scipy's
``_ivp`` error measure).  ``Tolerance.ratio`` gives the error in multiples of
the allowance, so reports can say "0.3 of tolerance" rather than "passed".

Sections: analytic reference, Pinocchio, MuJoCo, GB manifold.  Each engine's
section is edited only by that engine's module.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["Tolerance", "all_tolerances"]


@dataclass(frozen=True)
class Tolerance:
    atol: float
    rtol: float
    why: str

    def ratio(self, got, want) -> np.ndarray:
        """|got - want| / (atol + rtol |want|): <= 1 passes."""
        got, want = np.asarray(got, float), np.asarray(want, float)
        return np.abs(got - want) / (self.atol + self.rtol * np.abs(want))

    def ok(self, got, want) -> bool:
        r = self.ratio(got, want)
        return bool(np.all(np.isfinite(r) & (r <= 1.0)))

    def as_dict(self) -> dict:
        return asdict(self)


# ---------------------------------------------------------------- analytic ---
#: Closed forms evaluated two ways in double precision (a handful of
#: trig/sqrt operations each, condition numbers O(10) away from theta -> 0,
#: pi/2): 1e-12 relative is ~4500 ulp, ample for the rounding of ~20 flops
#: and tight enough to catch any wrong coefficient.
CLOSED_FORM = Tolerance(atol=1e-12, rtol=1e-12, why="double-precision rounding of closed forms (~20 flops)")

#: Identities that evaluate a function at a root computed by another closed
#: form, e.g. p(theta_+(varphi), varphi) = 0: p has terms of size 1 + alpha,
#: so the residual is rounding of O(alpha) numbers.
ROOT_RESIDUAL = Tolerance(atol=1e-12, rtol=0.0, why="rounding of O(1 + alpha) terms at a closed-form root")

#: Symbolic (sympy Lagrangian) vs numeric eq. linode2 at random states: the
#: issue's 1e-12 relative bound; atol covers accelerations that cancel to ~0
#: (scale g, m/s^2 -> 1e-12 g).
DERIVATION = Tolerance(atol=1e-11, rtol=1e-12, why="issue 2: independent derivation to 1e-12 relative")

#: Central finite differences with step h of a smooth function: truncation
#: O(h^2 f''') + rounding O(eps f / h); h = 1e-6 gives ~1e-8 relative.
FINITE_DIFFERENCE = Tolerance(atol=1e-7, rtol=1e-6, why="central differences, h = 1e-6: truncation + eps/h rounding")


# --------------------------------------------------------------- pinocchio ---


# ------------------------------------------------------------------ mujoco ---


# ---------------------------------------------------------------------- gb ---


def all_tolerances() -> dict[str, dict]:
    """Every named tolerance of this module, for reports' provenance blocks."""
    return {k: v.as_dict() for k, v in globals().items() if isinstance(v, Tolerance)}
