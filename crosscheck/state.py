"""The paper's scaled slipping state (section 2.1, eq. polareqs_varphi)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from crosscheck.tolerances import THETA_MARGIN
from crosscheck.checks import AZIMUTH, ETA, FINITE, NONNEGATIVE, NUMBERS, RATE, THETA, VARPHI, Interval, check

__all__ = ["SlipState", "real", "real_scalar", "same_shape", "MIN_TIMESTEP", "check_timestep", "check_timestep_within"]

#: The polar angles a run may start from: ``THETA_MARGIN`` (1e-6) inside (0, pi/2), where the theory's runs stop.
THETA_START = Interval(
    THETA_MARGIN.atol, math.pi / 2 - THETA_MARGIN.atol, lo_open=False, hi_open=False, text="[1e-06, pi/2 - 1e-06]"
)

#: The smallest scaled timestep of any engine: the longest horizon (``crosscheck.checks.HORIZON_MAX`` = 1e4)
#: resolves times only to 1e4 x 2.2e-16 ~ 2e-12, so a smaller step is lost in the rounding of the time it
#: advances (and a denormal one, 5e-324, overflows the count of steps in a window).
MIN_TIMESTEP = 1e-12


def real(name: str, value, interval: Interval = FINITE) -> np.ndarray:
    """``check`` for values that must be real numbers: a complex number (whose imaginary part ``float`` would drop),
    a bool, bytes or an object array is refused with one line naming ``name``, as a value out of range is."""
    if value is None or type(value) in NUMBERS:  # None: check's message; a plain float or int is real
        return check(name, value, interval)
    x = np.asarray(value) if not isinstance(value, (str, bytes, bytearray)) else None
    if isinstance(value, (bool, np.bool_, bytes, bytearray)) or (
        x is not None and (x.dtype.kind in "cbSUVO" and x.size) and not (x.dtype.kind == "U" and x.ndim == 0)
    ):
        raise ValueError(f"{name} must be a real number in {interval}; got {value!r}"[:300])
    return check(name, value, interval)


def real_scalar(name: str, value, interval: Interval = FINITE) -> float:
    """``real`` for one number (a list or an array of several is refused, naming ``name``)."""
    x = real(name, value, interval)
    if x.ndim:
        raise ValueError(f"{name} must be one number in {interval}; got an array of shape {x.shape}")
    return float(x)


def check_timestep(value) -> float:
    """A timestep: one real number > 0 and at least ``MIN_TIMESTEP`` (ValueError naming timestep)."""
    dt = real_scalar("timestep", value, Interval(0.0, np.inf, lo_open=True, hi_open=True, text="(0, inf)"))
    if dt < MIN_TIMESTEP:
        raise ValueError(
            f"timestep must be at least {MIN_TIMESTEP:g} (below it a step is lost in the rounding of the time); got {dt!r}"
        )
    return dt


def check_timestep_within(timestep: float, horizon: float) -> None:
    """A run's (checked) timestep not past its (checked) horizon: a step past the horizon records nothing to judge
    (ValueError naming timestep and the horizon)."""
    if timestep > horizon:
        raise ValueError(f"timestep must be in (0, horizon = {horizon:g}]; got {timestep!r}")


def same_shape(**arrays) -> tuple:
    """The arrays broadcast together; ValueError naming them and their shapes when they do not broadcast."""
    try:
        return np.broadcast_arrays(*arrays.values())
    except ValueError:
        shapes = ", ".join(f"{k} {np.shape(v)}" for k, v in arrays.items())
        raise ValueError(
            f"{', '.join(arrays)} must have shapes that broadcast (equal, or 1 where they differ); got {shapes}"
        ) from None


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

    def check_start(self) -> "SlipState":
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
