"""The slender rod of the paper (section 2.1) in physical or scaled units."""

from __future__ import annotations

import math
from dataclasses import dataclass

from crosscheck.checks import ALPHA, Interval, real_scalar

#: Each physical parameter (SI units) in [1e-100, 1e100]: products of two stay finite in double precision.
PHYSICAL = Interval(1e-100, 1e100, lo_open=False, hi_open=False)

__all__ = ["Rod"]


@dataclass(frozen=True)
class Rod:
    """A slender rigid rod AB touching the plane at its tip A.

    Attributes:
      mass: m [kg].
      length: l [m], the distance from the contact tip A to the centre of mass S
        (half the rod's length for a uniform rod).
      inertia: I0 [kg m^2], the moment of inertia about S about any axis normal
        to the rod (eq. inertia); m l^2 / 3 for a uniform rod.  The axial moment
        is zero (slender rod).
      gravity: g [m/s^2], acting along -z of the world frame.
    """

    mass: float = 1.0
    length: float = 1.0
    inertia: float = 1.0 / 3.0
    gravity: float = 9.81

    def __post_init__(self) -> None:
        for name in ("mass", "length", "inertia", "gravity"):
            object.__setattr__(self, name, real_scalar(name, getattr(self, name), PHYSICAL))
        # alpha = m l^2 / I0 in logarithms: the product may overflow or underflow where the ratio does not
        log_alpha = math.log(self.mass) + 2.0 * math.log(self.length) - math.log(self.inertia)
        if not math.log(ALPHA.lo) <= log_alpha <= math.log(ALPHA.hi):
            raise ValueError(
                f"alpha = mass length^2 / inertia must be in {ALPHA}; got mass={self.mass:g}, length={self.length:g}, "
                f"inertia={self.inertia:g} (alpha = 10^{log_alpha / math.log(10):.4g})"
            )

    @classmethod
    def scaled(cls, alpha: float = 3.0) -> Rod:
        """The rod in the paper's scaled units: m = l = g = 1, I0 = 1/alpha."""
        alpha = real_scalar("alpha", alpha, ALPHA)
        return cls(mass=1.0, length=1.0, inertia=1.0 / alpha, gravity=1.0)

    @classmethod
    def uniform(cls, mass: float, length: float, gravity: float = 9.81) -> Rod:
        """A uniform rod (alpha = 3) with tip-to-centre distance ``length``."""
        mass, length = real_scalar("mass", mass, PHYSICAL), real_scalar("length", length, PHYSICAL)
        inertia = mass * length**2 / 3.0
        if not PHYSICAL.lo <= inertia <= PHYSICAL.hi:  # name what the caller gave, not the inertia derived from it
            raise ValueError(
                f"mass and length must give a uniform rod's inertia m l^2 / 3 in [{PHYSICAL.lo:g}, {PHYSICAL.hi:g}] "
                f"kg m^2; got mass {mass!r}, length {length!r} (m l^2 / 3 = {inertia:.3g})"
            )
        return cls(mass=mass, length=length, inertia=inertia, gravity=gravity)

    def describe(self) -> str:
        """The rod in one phrase: the scaled rod by its alpha, a physical one by its mass, tip-to-centre length,
        inertia and gravity (SI units) and alpha."""
        if self.mass == 1.0 and self.length == 1.0 and self.gravity == 1.0:
            return f"scaled rod (m = l = g = 1), alpha {self.alpha:g}"
        return (
            f"rod of mass {self.mass:g} kg, length {self.length:g} m (tip to centre), inertia {self.inertia:g} kg m^2, "
            f"gravity {self.gravity:g} m/s^2 (alpha {self.alpha:g})"
        )

    @property
    def alpha(self) -> float:
        """alpha = m l^2 / I0 (dimensionless); 3 for a uniform rod."""
        return self.mass * self.length**2 / self.inertia

    @property
    def omega(self) -> float:
        """omega = sqrt(g / l) [1/s], the inverse time scale of the scaling."""
        return math.sqrt(self.gravity / self.length)

    @property
    def time_scale(self) -> float:
        """1/omega [s]: one unit of the paper's scaled time in seconds."""
        return 1.0 / self.omega

    @property
    def force_scale(self) -> float:
        """m g [N]: one unit of the paper's scaled force in newtons."""
        return self.mass * self.gravity
