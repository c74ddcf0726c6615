"""What happened to a slipping rod by the end of a run: shared by every engine."""

from __future__ import annotations

from enum import IntEnum

__all__ = ["Outcome"]


class Outcome(IntEnum):
    """First event of a slipping trajectory (analytic integration or simulation).

    SLIP: still slipping at the end of the horizon.
    LIFTOFF: the tip leaves the plane (analytic: b reaches 0 with p > 0).
    STICK: the tip speed reaches 0 while in contact.
    JAM: a paradox-like event, the "impact without collision" of the paper's
      conclusion (analytic: p reaches 0 with b < 0; an engine: an impulsive
      normal force with an abrupt loss of slip speed).
    DIVERGED: the run produced NaN/inf or the engine reported instability.
    GB: (analytic only) b and p reach 0 together, a point of the GB manifold
      such as P+ of the planar problem.
    LAUNCH: (engines only) a contact step throws the tip off the plane while
      the theory's free acceleration b is negative, so that the rigid rod
      would have stayed on it: the "gliding" of a convex or regularised
      contact step (Castro et al. 2023), or a soft contact's hop long and
      fast enough to be a flight.  Never an outcome of the theory; always a
      disagreement with it.
    """

    SLIP = 0
    LIFTOFF = 1
    STICK = 2
    JAM = 3
    DIVERGED = 4
    GB = 5
    LAUNCH = 6

    def __str__(self) -> str:
        # the name, as print(run.outcome) should read ("JAM", not IntEnum's "3"); the int values stay (arrays, Parquet)
        return self.name

    def __format__(self, spec: str) -> str:
        # f"{outcome}" reads as str(); a numeric spec ("{:d}") formats the value
        return self.name if not spec else int.__format__(int(self), spec)
