"""MuJoCo's run parameters in the paper's scaled units (importing this does not import MuJoCo)."""

from __future__ import annotations

import os
from dataclasses import dataclass

from crosscheck.checks import CAPSULE_RADIUS, FINITE, NONNEGATIVE, POSITIVE, check_timestep, real, real_scalar
from crosscheck.engines.options import EngineOptions

__all__ = ["Options", "RADIUS"]

#: The capsule radius r / l (see Options.radius).
RADIUS = CAPSULE_RADIUS


@dataclass(frozen=True)
class Options(EngineOptions):
    """MuJoCo parameters of a run, in the paper's scaled units.

    Attributes:
      timestep: omega dt (default 3e-4, i.e. ~1e-4 s for a 1 m rod under
        g = 9.81 m/s^2).
      radius: capsule radius r / l (default 0.01).
      timeconst: normal contact time constant omega tau of solref (default
        0.06, ~0.02 s for a 1 m rod: MuJoCo's default).  Must be >= 2
        timestep, else MuJoCo would silently raise it ("refsafe").
      dampratio: damping ratio of solref (default 1, critical).
      friction_timeconst: time constant of the friction directions only
        (solreffriction on the contact pair); None uses ``timeconst``.
      solimp: MuJoCo impedance (d0, dmax, width / l, midpoint, power);
        default MuJoCo's (0.9, 0.95, 0.001 m for l = 1 m, 0.5, 2).
      impratio: MuJoCo's ratio of frictional to normal impedance (default 1,
        rod.xml's and MuJoCo's): the friction rows' regulariser is
        R_t = R_n / impratio, so impratio << 1 makes the friction soft and
        isotropic and removes most of its skew off the slip
        (``crosscheck.engines.mujoco.studies.friction_skew``).
      solver_tolerance: MuJoCo's solver tolerance (default 1e-10, as in
        rod.xml).  The Newton solver stops on it, so the contact force and the
        acceleration agree to ~5e-7 relative at 1e-10; 0 runs to
        ``iterations`` and gives ~1e-11 (used by the instantaneous check).
      model_file: path of an alternative MJCF file with the same element
        names (default: the packaged ``rod.xml``).
    """

    timestep: float = 3e-4
    radius: float = 0.01
    timeconst: float = 0.06
    dampratio: float = 1.0
    friction_timeconst: float | None = None
    solimp: tuple[float, float, float, float, float] = (0.9, 0.95, 0.001, 0.5, 2.0)
    impratio: float = 1.0
    solver_tolerance: float = 1e-10
    model_file: str | None = None

    def __post_init__(self) -> None:
        for name in ("timestep", "timeconst", "dampratio"):
            object.__setattr__(self, name, real_scalar(name, getattr(self, name), POSITIVE))
        check_timestep(self.timestep)
        # A slender rod's radius is a small fraction of l; at r >= l/2 the capsule's end cap reaches
        # the centre of mass and the contact point C is no longer "below the tip".
        object.__setattr__(self, "radius", real_scalar("radius", self.radius, RADIUS))
        if self.friction_timeconst is not None:
            object.__setattr__(
                self, "friction_timeconst", real_scalar("friction_timeconst", self.friction_timeconst, POSITIVE)
            )
        for name in ("timeconst", "friction_timeconst"):
            tc = getattr(self, name)
            if tc is not None and tc < 2 * self.timestep:
                if name == "timeconst" and tc == type(self).__dataclass_fields__["timeconst"].default:
                    # the default time constant: the option given was the timestep (the CLI has no --timeconst)
                    raise ValueError(
                        f"timestep must be at most timeconst / 2 = {tc / 2:g} (MuJoCo's refsafe, with its default "
                        f"contact time constant timeconst = {tc:g}); got {self.timestep!r}"
                    )
                raise ValueError(f"{name} must be >= 2 timestep = {2 * self.timestep:g} (MuJoCo's refsafe); got {tc!r}")
        solimp = real("solimp", self.solimp, FINITE)
        if solimp.shape != (5,):
            raise ValueError(f"solimp must have 5 numbers (d0, dmax, width, midpoint, power); got {self.solimp!r}")
        # MuJoCo's impedance d(r) (Computation chapter): d0, dmax in (0, 1), width > 0, the sigmoid's
        # midpoint in (0, 1) and power >= 1 (MuJoCo clamps the others silently).
        if not (0 < solimp[0] < 1 and 0 < solimp[1] < 1 and solimp[2] > 0 and 0 < solimp[3] < 1 and solimp[4] >= 1):
            raise ValueError(
                f"solimp must have d0, dmax in (0, 1), width > 0, midpoint in (0, 1) and power >= 1; got {tuple(solimp)!r}"
            )
        object.__setattr__(self, "solimp", tuple(float(x) for x in solimp))
        object.__setattr__(self, "impratio", real_scalar("impratio", self.impratio, POSITIVE))
        object.__setattr__(
            self, "solver_tolerance", real_scalar("solver_tolerance", self.solver_tolerance, NONNEGATIVE)
        )
        if self.model_file is not None:
            object.__setattr__(self, "model_file", os.fspath(self.model_file))

    LABEL = "MuJoCo"

    @property
    def contact_time(self) -> float:
        """Time over which the soft normal force builds up: the solref time constant."""
        return self.timeconst

    @property
    def friction_time(self) -> float:
        """Time constant of the friction directions (a stuck contact creeps at ~0.4 of it)."""
        return self.friction_timeconst if self.friction_timeconst is not None else self.timeconst
