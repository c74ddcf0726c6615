"""Input validation shared by the Python API and the command line.

Every check raises ``ValueError`` whose message names the parameter and its
allowed range, e.g. ``theta must be in (0, pi/2); got 2.0``.  The CLI prints
the same message on one line, so the error text is part of the interface.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Interval", "check", "number", "THETA", "VARPHI", "MU", "ALPHA", "ETA", "POSITIVE", "FINITE"]


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


THETA = Interval(0.0, math.pi / 2, lo_open=True, hi_open=True, text="(0, pi/2)")
VARPHI = Interval(-math.pi, 0.0, lo_open=True, hi_open=False, text="(-pi, 0]")
MU = Interval(0.0, math.inf, lo_open=False, hi_open=True, text="[0, inf)")
ALPHA = Interval(0.0, math.inf, lo_open=True, hi_open=True, text="(0, inf)")
ETA = Interval(0.0, math.inf, lo_open=False, hi_open=True, text="[0, inf)")
POSITIVE = Interval(0.0, math.inf, lo_open=True, hi_open=True, text="(0, inf)")
FINITE = Interval(-math.inf, math.inf, lo_open=True, hi_open=True, text="(-inf, inf)")


def check(name: str, value, interval: Interval = FINITE) -> np.ndarray:
    """Return ``value`` as a float array after checking it lies in ``interval``.

    NaN and infinities are rejected for every interval (an unbounded interval is
    open at infinity).  Arrays are accepted; the message quotes the first
    offending element.
    """
    if value is None:
        raise ValueError(f"{name} is required and must be in {interval}")
    try:
        x = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
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
        v = int(text) if text.lstrip("+-").isdigit() else None
    else:
        v = int(value) if isinstance(value, (int, np.integer)) and not isinstance(value, bool) else None
    if v is None or not lo <= v <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}]; got {value!r}")
    return v
