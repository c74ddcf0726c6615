"""DART's run parameters in the paper's scaled units (importing this does not import dartpy)."""

from __future__ import annotations

from dataclasses import dataclass

from crosscheck.checks import CAPSULE_RADIUS, check_timestep, real_scalar
from crosscheck.engines.options import EngineOptions

__all__ = ["Options", "RADIUS"]

#: The capsule radius r / l (as MuJoCo's, Bullet's and PhysX's).
RADIUS = CAPSULE_RADIUS


@dataclass(frozen=True)
class Options(EngineOptions):
    """DART parameters of a run, in the paper's scaled units.

    Attributes:
      timestep: omega dt (default 1e-3, as Bullet's, PhysX's and the rigid engine's: the same rigid contact in
        four time-steppers differs by the contact model, not the discretisation).
      radius: capsule radius r / l (default 0.01, as ``models/rod.xml``).

    Fixed, not options (``crosscheck.engines.dart.model``): DART's default constraint solver,
    ``BoxedLcpConstraintSolver`` with the Dantzig pivoting solver (and its PGS fallback where Dantzig fails:
    dartpy 6.20 exposes ``PgsBoxedLcpSolver`` without a constructor, so PGS cannot be chosen as the primary
    solver and is not a second registered engine); friction mu on both shapes (DART combines them by the
    minimum), restitution 0; the Bullet collision detector (DART's default, FCL, has no capsule: it puts a
    sphere of radius 0.1 in its place); no joint damping, friction, limits or springs.
    """

    timestep: float = 1e-3
    radius: float = 0.01

    def __post_init__(self) -> None:
        object.__setattr__(self, "timestep", check_timestep(self.timestep))
        object.__setattr__(self, "radius", real_scalar("radius", self.radius, RADIUS))

    LABEL = "DART"

    @property
    def contact_time(self) -> float:
        """0: DART's contact is an impulse within the step (a velocity-level LCP), no force build-up time."""
        return 0.0

    @property
    def friction_time(self) -> float:
        """0: DART's friction rows have no position error, so a stuck contact does not creep."""
        return 0.0
