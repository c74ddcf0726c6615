"""Input validation shared by the Python API and the command line.

Every check raises ``ValueError`` whose message names the parameter and its
allowed range, e.g. ``theta must be in (0, pi/2); got 2.0``.  The CLI prints
the same message on one line, so the error text is part of the interface.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

__all__ = [
    "Interval",
    "check",
    "number",
    "integer",
    "THETA",
    "VARPHI",
    "MU",
    "ALPHA",
    "ETA",
    "RATE",
    "AZIMUTH",
    "UNIT",
    "HORIZON",
    "POSITIVE",
    "NONNEGATIVE",
    "FINITE",
    "BOUNDED",
    "CAPSULE_RADIUS",
    "CONTACT_RADIUS",
    "real",
    "real_scalar",
    "same_shape",
    "MIN_TIMESTEP",
    "check_timestep",
    "check_timestep_within",
    "writable_directory",
    "writable_file",
]


class Interval:
    """A real interval with open or closed ends, printed the way errors show it."""

    def __init__(self, lo: float, hi: float, *, lo_open: bool, hi_open: bool, text: str | None = None):
        self.lo, self.hi = lo, hi
        self.lo_open, self.hi_open = lo_open, hi_open
        self._text = text

    def __str__(self) -> str:
        if self._text:
            return self._text
        left = "(" if self.lo_open else "["
        right = ")" if self.hi_open else "]"
        return f"{left}{self.lo:g}, {self.hi:g}{right}"

    def contains(self, x: np.ndarray) -> np.ndarray:
        lo_ok = x > self.lo if self.lo_open else x >= self.lo
        hi_ok = x < self.hi if self.hi_open else x <= self.hi
        return lo_ok & hi_ok


# The paper's quantities are scaled to be of order one (its figures: mu <= 2, |Theta|, |Psi| <= 3,
# eta <= 10, alpha = 3).  The ranges below are a factor 30-300 wider than that and stop where the
# computation stops meaning anything:
# * rates (Theta, Psi, eta) at most 100: every engine calls a scaled tip speed above 1e3 a divergence
#   (``Thresholds.diverged_speed``), and a rate of 100 already moves the tip at ~140;
# * mu at most 1e3 and alpha in [1e-3, 1e3]: p (eq. p) is a sum of terms of size 1, alpha and
#   alpha mu, so beyond that its sign near p = 0 is lost to rounding (8 eps alpha mu ~ 2e-9 at the
#   bounds), and the critical angles of eqs. thetap-psi2 lose digits to cancellation;
# * psi at most 1e3 rad in magnitude: it enters through sin and cos, which lose ~log10|psi| digits;
# * horizons of the analytic runs at most 1e4 (scaled time, ~30 min for a 1 m rod): the events
#   of a slipping rod come within O(10), and past 1e4 the time itself has lost 4 of its digits.
MU_MAX = 1e3
ALPHA_MIN, ALPHA_MAX = 1e-3, 1e3
RATE_MAX = 100.0
PSI_MAX = 1e3
HORIZON_MAX = 1e4

THETA = Interval(0.0, math.pi / 2, lo_open=True, hi_open=True, text="(0, pi/2)")
VARPHI = Interval(-math.pi, 0.0, lo_open=True, hi_open=False, text="(-pi, 0]")
MU = Interval(0.0, MU_MAX, lo_open=False, hi_open=False)
ALPHA = Interval(ALPHA_MIN, ALPHA_MAX, lo_open=False, hi_open=False)
ETA = Interval(0.0, RATE_MAX, lo_open=False, hi_open=False)
RATE = Interval(-RATE_MAX, RATE_MAX, lo_open=False, hi_open=False)
AZIMUTH = Interval(-PSI_MAX, PSI_MAX, lo_open=False, hi_open=False)
UNIT = Interval(0.0, 1.0, lo_open=False, hi_open=False)
HORIZON = Interval(0.0, HORIZON_MAX, lo_open=True, hi_open=False)
POSITIVE = Interval(0.0, math.inf, lo_open=True, hi_open=True, text="(0, inf)")
NONNEGATIVE = Interval(0.0, math.inf, lo_open=False, hi_open=True, text="[0, inf)")
FINITE = Interval(-math.inf, math.inf, lo_open=True, hi_open=True, text="(-inf, inf)")
#: A capsule's radius r / l (MuJoCo's, Drake's, Bullet's rod): at r >= l/2 the end cap reaches the centre of mass.
CAPSULE_RADIUS = Interval(0.0, 0.5, lo_open=True, hi_open=True)
#: The contact point's distance r below the tip A, in units of l (the theory's capsule, the compliant rod): 0 is the
#: tip itself; a thicker capsule is no longer the paper's slender rod.
CONTACT_RADIUS = Interval(0.0, 0.5, lo_open=False, hi_open=True)
#: Values whose squares and products stay finite: arguments of the closed forms (eqs. b, p), which also
#: see states a flow reached (their rates are not held to the ranges of a start).
BOUNDED = Interval(-1e100, 1e100, lo_open=False, hi_open=False)


#: Exact types ``check`` tests as one Python float (bool, a subclass of int, is not one of them: ``real`` refuses it).
NUMBERS = frozenset((float, int, np.float64))


def check(name: str, value, interval: Interval = FINITE) -> np.ndarray:
    """Return ``value`` as a float array after checking it lies in ``interval``.

    NaN and infinities are rejected for every interval (an unbounded interval is
    open at infinity).  Arrays are accepted; the message quotes the first
    offending element.
    """
    if type(value) in NUMBERS:
        # one plain number, most calls (a state's component, each right-hand side of a flow): the same test without
        # numpy's array machinery, which cost 20 times as much; anything it refuses gets the general path's message
        try:
            v = float(value)
        except OverflowError:  # an int beyond any float
            raise ValueError(f"{name} must be in {interval}; got an integer of {len(str(abs(value)))} digits") from None
        if math.isfinite(v) and interval.contains(v):
            return np.asarray(v)
    if value is None:
        raise ValueError(f"{name} is required and must be in {interval}")
    if isinstance(value, str) and (not value.isascii() or "_" in value):
        # one rule for text everywhere (crosscheck.cli.options): float() would read "1_0" as 10, "٣" as 3, "１" as 1
        raise ValueError(
            f"{name} must be a number in {interval} written with ASCII digits (no underscores); got {value[:40]!r}"
        )
    try:
        x = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):  # OverflowError: an int beyond any float
        raise ValueError(f"{name} must be a number in {interval}; got {value!r}") from None
    bad = ~(np.isfinite(x) & interval.contains(x))
    if np.any(bad):
        first = x[bad].flat[0] if x.ndim else float(x)
        raise ValueError(f"{name} must be in {interval}; got {float(first)!r}")
    return x


def number(name: str, value, interval: Interval = FINITE) -> float:
    """``check`` for one scalar: also parses strings, so the CLI passes its raw text."""
    return float(check(name, value, interval))


def integer(name: str, value, lo: int, hi: int) -> int:
    """An integer in [lo, hi] from an int or the CLI's raw text ("1e3" and "2.5" are not integers); ValueError naming both."""
    if isinstance(value, str):
        text = value.strip()
        digits = text.lstrip("+-")
        # ASCII digits only ("²" and "٣" pass isdigit), and few of them (a 5000-digit string hits Python's int limit)
        v = int(text) if digits.isascii() and digits.isdigit() and len(digits) <= 30 else None
    else:
        v = int(value) if isinstance(value, (int, np.integer)) and not isinstance(value, bool) else None
    if v is None or not lo <= v <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}]; got {value!r}")
    return v


def writable_directory(name: str, value) -> Path:
    """``value`` as a directory this process can write, created if missing; ValueError naming ``name`` otherwise.

    Checked before any work starts, so that a long run never fails at its first write.
    """
    import tempfile

    if value is None or not str(value).strip():
        raise ValueError(f"{name} must be a writable directory path; got {value!r}")
    path = Path(value)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{name} must be a writable directory; got {str(path)!r}, which is a file")
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as e:  # a file created in it is the test: permission bits, ACLs, read-only mounts, /proc alike
        raise ValueError(
            f"{name} must be a writable directory; cannot write in {str(path)!r}: {e.strerror or e}"
        ) from None
    return path


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
    dt = real_scalar("timestep", value, POSITIVE)
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


def writable_file(name: str, value, *, suffixes: tuple[str, ...] = ()) -> Path:
    """``value`` as a file path this process can write (its directory created if missing, the file not touched);
    ValueError naming ``name`` otherwise: empty, a directory, a suffix not in ``suffixes`` (when given), a parent
    that is a file or that the file system refuses (/proc, read-only).  Checked before a run, not after it."""
    if value is None or not str(value).strip():
        raise ValueError(f"{name} must be a file path; got {value!r}")
    path = Path(value)
    shown = repr(str(value)) if len(str(value)) <= 80 else f"{str(value)[:60]!r}... ({len(str(value))} characters)"
    try:
        if path.is_dir():
            raise ValueError(f"{name} must be a file path; got {shown}, which is a directory")
        if suffixes and path.suffix.lower() not in suffixes:
            raise ValueError(f"{name} must be a file ending in {', '.join(suffixes)}; got {shown}")
        writable_directory(name, path.parent)
        if path.exists():
            if not os.access(path, os.W_OK):
                raise PermissionError(13, "Permission denied")
        else:  # the name itself (its length, its characters) as the file system takes it; nothing is left behind
            os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644))
            os.unlink(path)
    except ValueError as e:
        if str(e).startswith(f"{name} must be a file"):
            raise
        why = str(e).rsplit(": ", 1)[-1] if "cannot write in" in str(e) else "a file stands where its directory goes"
        raise ValueError(f"{name} must be a file path in a writable directory; cannot write {shown}: {why}") from None
    except OSError as e:
        raise ValueError(f"{name} must be a writable file path; cannot use {shown}: {e.strerror or e}") from None
    return path
