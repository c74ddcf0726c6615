"""Bullet's run parameters in the paper's scaled units (importing this does not import pybullet)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crosscheck.checks import CAPSULE_RADIUS, NONNEGATIVE, POSITIVE, UNIT, check_timestep, real_scalar
from crosscheck.engines.options import EngineOptions

__all__ = ["Options", "RADIUS", "MU_MAX", "FRICTION_AXES"]

#: The capsule radius r / l (as MuJoCo's: at r >= l/2 the end cap reaches the centre of mass).
RADIUS = CAPSULE_RADIUS

#: Bullet clamps the combined friction coefficient (the product of the two bodies' frictions) to
#: [-10, 10] (``btManifoldResult::calculateCombinedFriction``, MAX_FRICTION): a larger mu would be run
#: silently at 10, so ``simulate`` refuses it.
MU_MAX = 10.0

#: Where the friction rows lie (``Options.friction_axes``).
FRICTION_AXES = ("world", "slip")

#: Largest ``solver_iterations`` accepted: Bullet's PGS costs ~1 us per iteration and contact step, so
#: 1e5 iterations is already 0.1 s per step.
MAX_ITERATIONS = 100_000


@dataclass(frozen=True)
class Options(EngineOptions):
    """Bullet parameters of a run, in the paper's scaled units.

    Attributes:
      timestep: omega dt (default 1e-3, ~3.2e-4 s for a 1 m rod).  Why 1e-3: it is the rigid engine's
        (Pinocchio's) default, so the two time-steppers of the same rigid contact differ by their
        contact models rather than their discretisation; a run to horizon 2 costs 0.04-0.06 s at it
        (``benchmarks/bench_bullet.py``) and the quick report's three 10 x 10 maps took 7.2 s.  An
        event comes O(dt) late or early (first-order semi-implicit Euler, like the rigid engine).
      radius: capsule radius r / l (default 0.01, as ``models/rod.xml``).
      solver_iterations: Bullet's ``numSolverIterations``, the cap on the PGS sweeps per step
        (default 50, pybullet's).  On one slipping contact PGS reaches ``solver_tolerance`` in ~36
        sweeps (the records at 50 and at 1000 are identical bit for bit); a step that reaches the cap
        first is counted in ``Run.solver.unconverged_steps``.  More sweeps do not cure the steps that
        miss it at mu >= 1: PGS may cycle there (``crosscheck.engines.bullet.engine``'s docstring).
      solver_tolerance: PGS stops when no row's velocity changes by more than this in a sweep
        (scaled velocity l omega; Bullet's ``solverResidualThreshold`` is its square in (m/s)^2).
        Default 1e-13: at the fixed point of its sweep PGS still moves the O(1-10) velocities by
        rounding, ~1e-15 (measured: 4.8e-20 left after 50 sweeps on a slip, where 0 never came);
        1e-13 stops there, ~36 sweeps on a slipping contact, and leaves the force 1e-13 / dt = 1e-10
        m g from the fixed point at dt = 1e-3.  pybullet's own default, 1e-7 (m/s)^2, stops at
        ~3e-4 m/s (1e-4 l omega for a 1 m rod), a force error of 0.1 m g at dt = 1e-3.
      contact_erp: Bullet's ``contactERP``, the fraction of a penetration removed per step by the
        normal row's position error (default 0.08, pybullet's).  It acts only on penetration, which
        the speculative contact (see ``contact_margin``) prevents except when a landing tip crosses
        the whole margin in one step; it sets no build-up time of the force (module docstring of
        ``crosscheck.engines.bullet.engine``).
      contact_margin: Bullet's ``contactBreakingThreshold`` / l (default 0.02, Bullet's 0.02 m for a
        1 m rod).  A rod-plane contact point exists (and enters the step as a unilateral row whose
        gap may close within the step) while the capsule is closer to the plane than this.
      cone: True (default) solves friction on Bullet's cone (``enableConeFriction``: the two
        tangential rows clipped together to a disk of radius mu F_n); False on two independent rows
        (a square pyramid, |F_t| up to sqrt(2) mu F_n), kept to show the difference.
      friction_axes: "world" (default, Bullet's: its multibody solver puts the friction rows along
        world x and y, and its friction then opposes diag(D)^-1 u, not the slip u:
        ``crosscheck.engines.bullet.law``) or "slip": before each step the whole state is turned
        about the vertical through the tip so that the contact point's slip lies along world x,
        and turned back after it (an exact symmetry of rod, plane and gravity), so that Bullet's
        unchanged solver has its first friction row along the slip: Coulomb's direction.
    """

    timestep: float = 1e-3
    radius: float = 0.01
    solver_iterations: int = 50
    solver_tolerance: float = 1e-13
    contact_erp: float = 0.08
    contact_margin: float = 0.02
    cone: bool = True
    friction_axes: str = "world"

    def __post_init__(self) -> None:
        object.__setattr__(self, "timestep", check_timestep(self.timestep))
        object.__setattr__(self, "radius", real_scalar("radius", self.radius, RADIUS))
        n = self.solver_iterations
        if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and 1 <= n <= MAX_ITERATIONS):
            raise ValueError(f"solver_iterations must be an integer in [1, {MAX_ITERATIONS}]; got {n!r}")
        object.__setattr__(self, "solver_iterations", int(n))
        object.__setattr__(
            self, "solver_tolerance", real_scalar("solver_tolerance", self.solver_tolerance, NONNEGATIVE)
        )
        object.__setattr__(self, "contact_erp", real_scalar("contact_erp", self.contact_erp, UNIT))
        object.__setattr__(self, "contact_margin", real_scalar("contact_margin", self.contact_margin, POSITIVE))
        if not isinstance(self.cone, (bool, np.bool_)):
            raise ValueError(f"cone must be True or False; got {self.cone!r}")
        object.__setattr__(self, "cone", bool(self.cone))
        if self.friction_axes not in FRICTION_AXES:
            raise ValueError(f"friction_axes must be one of {', '.join(FRICTION_AXES)}; got {self.friction_axes!r}")

    LABEL = "Bullet"

    @property
    def contact_time(self) -> float:
        """0: Bullet's contact is an impulse within the step, with no force build-up time.

        The normal row is a velocity-level unilateral constraint (the contact velocity at the end of
        the step may not close more than the gap), solved by PGS with the friction rows: the force
        that stops a slipping tip acts in the step it is needed, and is zero in the step after the
        free motion would lift the tip.  contact_erp only removes penetration, which the speculative
        row prevents (``contact_margin``); it is no spring.
        """
        return 0.0

    @property
    def friction_time(self) -> float:
        """0: the friction rows have no position error (no friction anchors), so a stuck contact does not creep."""
        return 0.0
