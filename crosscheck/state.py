"""The paper's scaled slipping state (section 2.1, eq. polareqs_varphi)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from crosscheck.checks import (  # the validators' home is crosscheck.checks; importable from here as before
    AZIMUTH,
    ETA,
    FINITE,
    MIN_TIMESTEP,
    NONNEGATIVE,
    RATE,
    THETA,
    VARPHI,
    Interval,
    check,
    check_timestep,
    check_timestep_within,
    real,
    real_scalar,
    same_shape,
)
from crosscheck.tolerances import THETA_MARGIN

__all__ = ["SlipState", "real", "real_scalar", "same_shape", "MIN_TIMESTEP", "check_timestep", "check_timestep_within"]

#: The polar angles a run may start from: ``THETA_MARGIN`` (1e-6) inside (0, pi/2), where the theory's runs stop.
THETA_START = Interval(
    THETA_MARGIN.atol, math.pi / 2 - THETA_MARGIN.atol, lo_open=False, hi_open=False, text="[1e-06, pi/2 - 1e-06]"
)


@dataclass(frozen=True)
class SlipState:
    """A state of the rod slipping with its tip A on the plane, in scaled units.

    Attributes:
      theta: polar angle of the rod to the horizontal [rad], in (0, pi/2).
      varphi: relative slip angle beta - psi [rad], in (-pi, 0].
      Theta: theta_dot / omega, scaled polar rate.
      Psi: psi_dot / omega, scaled azimuthal rate.
      eta: tip speed / (l omega), scaled slip speed, >= 0.
      psi: azimuthal angle [rad] (cyclic; default 0).

    The tip is on the plane (z = 0) with zero normal velocity (w = 0).
    """

    theta: float
    varphi: float
    Theta: float
    Psi: float
    eta: float
    psi: float = 0.0

    def __post_init__(self) -> None:
        # Any finite rate: a state the slipping flow reaches may spin fast (Psi ~ 1/cos theta near theta =
        # pi/2); the start of a run is held to the narrower ranges of ``check_start``.
        limits = {"theta": THETA, "varphi": VARPHI, "Theta": FINITE, "Psi": FINITE, "eta": NONNEGATIVE, "psi": FINITE}
        for name, interval in limits.items():
            object.__setattr__(self, name, real_scalar(name, getattr(self, name), interval))

    def check_start(self) -> SlipState:
        """This state, if it may start a run: theta at least ``THETA_MARGIN`` from 0 and pi/2 (where every run stops:
        a start nearer the vertical made the compliant rod crawl for minutes and MuJoCo's law meet a singular
        matrix), rates and azimuth within ``crosscheck.checks``'s ranges (ValueError otherwise)."""
        for name, interval in (("theta", THETA_START), ("Theta", RATE), ("Psi", RATE), ("eta", ETA), ("psi", AZIMUTH)):
            check(name, getattr(self, name), interval)
        return self

    @property
    def beta(self) -> float:
        """Slip angle (heading) beta = psi + varphi [rad] of the tip velocity."""
        return self.psi + self.varphi

    def as_dict(self) -> dict[str, float]:
        return asdict(self)
