"""DART's run parameters in the paper's scaled units (importing this does not import dartpy)."""

from __future__ import annotations

from dataclasses import dataclass

from crosscheck.checks import CAPSULE_RADIUS, check_timestep, real_scalar
from crosscheck.engines.options import EngineOptions

__all__ = ["Options", "RADIUS", "FRICTION_SOLVERS"]

#: The capsule radius r / l (as MuJoCo's, Bullet's and PhysX's).
RADIUS = CAPSULE_RADIUS


#: The boxed-LCP solvers of DART's constraint solver a run can take (``Options.friction_solver``): its default
#: Dantzig pivoting solver, and dartpy 6.20's ``NsgsFrictionSolver`` (non-smooth Gauss-Seidel) with its friction law
#: Box (the two rows boxed apart, a pyramid) or Coulomb (the cone).
FRICTION_SOLVERS = ("dantzig", "nsgs_box", "nsgs_coulomb")


@dataclass(frozen=True)
class Options(EngineOptions):
    """DART parameters of a run, in the paper's scaled units.

    Attributes:
      timestep: omega dt (default 1e-3, as Bullet's, PhysX's and the rigid engine's: the same rigid contact in
        four time-steppers differs by the contact model, not the discretisation).
      radius: capsule radius r / l (default 0.01, as ``models/rod.xml``).
      friction_solver: the step's boxed-LCP solver (``FRICTION_SOLVERS``): "dantzig" (default, DART's: each friction
        row boxed by mu times the normal impulse solved before the friction rows enter, a fixed square pyramid);
        "nsgs_box" (DART's NSGS friction solver, the rows boxed by mu times the normal impulse as it is solved: a
        pyramid whose size follows the normal force); "nsgs_coulomb" (the same solver with Coulomb's cone).  The
        last two are the interventions of the friction bound and the pyramid cone
        (``crosscheck.engines.dart.interventions``).

    Fixed, not options (``crosscheck.engines.dart.model``): DART's default constraint solver,
    ``BoxedLcpConstraintSolver``, by default with the Dantzig pivoting solver (and its PGS fallback where Dantzig fails:
    dartpy 6.20 exposes ``PgsBoxedLcpSolver`` without a constructor, so PGS cannot be chosen as the primary
    solver and is not a second registered engine); friction mu on both shapes (DART combines them by the
    minimum), restitution 0; the Bullet collision detector (DART's default, FCL, has no capsule: it puts a
    sphere of radius 0.1 in its place); no joint damping, friction, limits or springs.
    """

    timestep: float = 1e-3
    radius: float = 0.01
    friction_solver: str = "dantzig"

    def __post_init__(self) -> None:
        object.__setattr__(self, "timestep", check_timestep(self.timestep))
        object.__setattr__(self, "radius", real_scalar("radius", self.radius, RADIUS))
        if self.friction_solver not in FRICTION_SOLVERS:
            raise ValueError(
                f"friction_solver must be one of {', '.join(FRICTION_SOLVERS)}; got {self.friction_solver!r}"
            )

    LABEL = "DART"

    @property
    def contact_time(self) -> float:
        """0: DART's contact is an impulse within the step (a velocity-level LCP), no force build-up time."""
        return 0.0

    @property
    def friction_time(self) -> float:
        """0: DART's friction rows have no position error, so a stuck contact does not creep."""
        return 0.0
