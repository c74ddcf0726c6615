"""PhysX's run parameters in the paper's scaled units, every default PhysX gets wrong for a slipping rod set here.

Importing this does not import SAPIEN.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from crosscheck.checks import CAPSULE_RADIUS, NONNEGATIVE, POSITIVE, Interval, check_timestep, real_scalar
from crosscheck.engines.options import EngineOptions

__all__ = ["Options", "PgsOptions", "SOLVERS", "RADIUS", "MAX_ITERATIONS"]

#: PhysX's two rigid-body solvers (``PxSceneFlag`` / ``PxSolverType``): temporal Gauss-Seidel, PhysX 5's default, which
#: substeps the contact rows over its position iterations, and projected Gauss-Seidel, PhysX 4's default.
SOLVERS = ("tgs", "pgs")

#: The capsule radius r / l (as MuJoCo's and Bullet's).
#: How tables and messages name the engine of each solver.
LABELS = {"tgs": "PhysX TGS", "pgs": "PhysX PGS"}

RADIUS = CAPSULE_RADIUS

#: PhysX stores solver iteration counts in 8 bits (``PxArticulation::setSolverIterationCounts``: 1..255 position,
#: 0..255 velocity).
MAX_ITERATIONS = 255

#: The ratio of the static to the dynamic friction coefficient: Coulomb's law has one coefficient (1); PhysX keeps
#: two, and a static one above mu would hold a contact that Coulomb's law lets slip.
STATIC_RATIO = Interval(1.0, 100.0, lo_open=False, hi_open=False)

#: The bounce threshold's range [l omega]: PhysX keeps it in float32 and needs it positive.
BOUNCE = Interval(0.0, 1e30, lo_open=True, hi_open=False)


def _iterations(name: str, n, lo: int) -> int:
    if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and lo <= n <= MAX_ITERATIONS):
        raise ValueError(f"{name} must be an integer in [{lo}, {MAX_ITERATIONS}]; got {n!r}")
    return int(n)


@dataclass(frozen=True)
class Options(EngineOptions):
    """PhysX parameters of a run, in the paper's scaled units (lengths in l, velocities in l omega).

    Attributes:
      timestep: omega dt (default 1e-3, as Bullet's and the rigid engine's: the same rigid contact in three
        time-steppers differs by the contact model, not the discretisation).
      radius: capsule radius r / l (default 0.01, as ``models/rod.xml``).
      solver: "tgs" (PhysX 5's default) or "pgs"; each registered name fixes one (``physx_tgs``, ``physx_pgs``).
      position_iterations: the articulation's solver position iterations (default 10, SAPIEN's; PhysX's own is 4).
        On the slipping start theta = 1, varphi = -1.9, mu = 0.5 the normal force scatters step to step by
        0.07-0.3 m g about the rigid value at 4, 10 and 32 alike (float32 positions: module docstring of
        ``crosscheck.engines.physx.engine``), and a TGS step costs ~100 us at 10, ~170 us at 32.
      velocity_iterations: the velocity iterations after them (default 1, PhysX's and SAPIEN's).
      contact_offset: the shapes' contact offset / l (default 0.02, Bullet's margin; PhysX's default is 0.02 m,
        SAPIEN's 0.01 m, the capsule's radius for a 1 m rod): PhysX makes a contact (a speculative one, whose
        gap may close within the step) while the capsule is this close to the plane.  The rest offset is 0:
        the rows aim at touching, not at a skin.
      bounce_threshold: PhysX's bounce threshold [l omega] (default 1e6): a contact approaching faster than
        it is solved as an impact with the restitution coefficient (0 here) rather than as a resting contact
        with its position error; SAPIEN's 2 m/s is 0.64 l omega for a 1 m rod, within the speeds of a rod
        whose tip lands, so the same landing would be treated by one law or the other by its speed.
      sleep_threshold: the articulation's sleep threshold, a kinetic energy per unit mass [(l omega)^2]
        (default 0: PhysX's 5e-5 (m/s)^2 per kg, SAPIEN's 5e-3, would freeze a rod that slows down before it
        sticks).
      static_ratio: PhysX's static friction coefficient / mu (default 1: static = dynamic = mu, Coulomb's single
        coefficient; PhysX's materials take the two separately and average each over the two shapes).
      patch_radius: the torsional patch radius / l of PhysX's patch friction (default 0: the paper's point contact,
        no torsional friction; SAPIEN's default is 0 too, recorded here because patch friction would otherwise add a
        friction torque about the normal).
      friction_every_iteration: PhysX's ``eENABLE_FRICTION_EVERY_ITERATION`` (default True, SAPIEN's; PhysX's
        own default False solves friction only in the last position iterations).

    Fixed, not options (each PhysX default wrong here; ``crosscheck.engines.physx.model``): restitution 0; link and
    joint damping 0; joint friction 0 (SAPIEN's 0.05); the velocity clamps (10 m/s and 50 rad/s per link,
    100 per joint) out of reach.  PhysX's friction is its
    patch friction, one anchor pair per contact patch with two friction rows along two tangent axes, each
    clipped to mu times the normal impulse (SAPIEN 3.0 exposes no other friction model).
    """

    timestep: float = 1e-3
    radius: float = 0.01
    solver: str = "tgs"
    position_iterations: int = 10
    velocity_iterations: int = 1
    contact_offset: float = 0.02
    bounce_threshold: float = 1e6
    sleep_threshold: float = 0.0
    static_ratio: float = 1.0
    patch_radius: float = 0.0
    friction_every_iteration: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "timestep", check_timestep(self.timestep))
        object.__setattr__(self, "radius", real_scalar("radius", self.radius, RADIUS))
        if self.solver not in SOLVERS:
            raise ValueError(f"solver must be one of {', '.join(SOLVERS)}; got {self.solver!r}")
        object.__setattr__(self, "position_iterations", _iterations("position_iterations", self.position_iterations, 1))
        object.__setattr__(self, "velocity_iterations", _iterations("velocity_iterations", self.velocity_iterations, 0))
        object.__setattr__(self, "contact_offset", real_scalar("contact_offset", self.contact_offset, POSITIVE))
        object.__setattr__(self, "bounce_threshold", real_scalar("bounce_threshold", self.bounce_threshold, BOUNCE))
        object.__setattr__(self, "sleep_threshold", real_scalar("sleep_threshold", self.sleep_threshold, NONNEGATIVE))
        object.__setattr__(self, "static_ratio", real_scalar("static_ratio", self.static_ratio, STATIC_RATIO))
        object.__setattr__(self, "patch_radius", real_scalar("patch_radius", self.patch_radius, NONNEGATIVE))
        if not isinstance(self.friction_every_iteration, (bool, np.bool_)):
            raise ValueError(f"friction_every_iteration must be True or False; got {self.friction_every_iteration!r}")
        object.__setattr__(self, "friction_every_iteration", bool(self.friction_every_iteration))

    @classmethod
    def label_of(cls, options: dict[str, Any]) -> str:
        """The label of the engine of the options' solver ("PhysX TGS")."""
        solver = options.get("solver", cls.solver)
        return LABELS.get(solver, f"physx_{solver}") if isinstance(solver, str) else f"physx_{solver}"

    @property
    def contact_time(self) -> float:
        """0: an impulse within the step (a speculative rigid contact row), no force build-up time."""
        return 0.0

    @property
    def friction_excess(self) -> float:
        """The largest |F_t| / (mu F_n) PhysX's friction reaches: sqrt(2) for PGS, whose two patch-friction rows are
        clipped each to mu F_n (both saturate when the slip turns within the step: measured |F_t| = 1.414 mu F_n on the
        first steps from theta = 1, varphi = -1.9, Psi = 1.25, mu = 1.25, where PGS jams at once below mu_P), 1 for TGS
        (measured on the cone, |F_t| = mu F_n to 1e-4).  Read by the maps' check of no impact without collision."""
        return 2.0**0.5 if self.solver == "pgs" else 1.0

    @property
    def friction_time(self) -> float:
        """0: no creep time constant is declared (PhysX's friction anchors are its patch friction's, not a spring)."""
        return 0.0


@dataclass(frozen=True)
class PgsOptions(Options):
    """``Options`` of the registered ``physx_pgs``: the same fields, PGS by default (so that the options a study
    builds from the plan's settings alone, without the registry's defaults, name the solver that ran)."""

    solver: str = "pgs"
