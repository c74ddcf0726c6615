"""The hybrid rigid model: slip until the first event, through an impact without collision at a jam, and on, up to a horizon.

The paper's slipping flow (``crosscheck.theory.slipping.slip_until_event``) stops
at its first event.  At a JAM (p reaches 0 with b < 0, Corollary 4.2) the
rigid model continues with the impulse of ``crosscheck.theory.impact.darboux_keller.impact``; the
post-impulse state then decides what follows:

* the tip leaves the plane (normal velocity w > 0, after a restitution
  e > 0, or b > 0 at the new state): LIFTOFF at the jam time;
* the tip is stuck (slip speed 0): STICK at the jam time (the sticking rod
  is beyond the slipping model);
* the tip still slips with b < 0 < p: the slipping flow starts again from
  the post-impulse state (a new segment);
* the new state leaves the paper's domain (varphi outside (-pi, 0]):
  SLIP, ended there.

Every other first event (LIFTOFF, STICK, GB, SLIP at the horizon or a
domain exit) ends the run.  Scaled units (section 2.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from crosscheck.theory import analytic
from crosscheck.checks import ALPHA, HORIZON, MU, UNIT, check, integer
from crosscheck.theory.impact.darboux_keller import Impact, impact
from crosscheck.outcome import Outcome
from crosscheck.theory.slipping import SlipResult, continue_slip
from crosscheck.state import SlipState

__all__ = ["Segment", "HybridResult", "run"]


@dataclass(frozen=True, eq=False)
class Segment:
    """One slipping segment from ``start`` (at time t0) to its first event (``slip``, a ``SlipResult`` in local time)."""

    t0: float
    start: SlipState
    slip: SlipResult = field(repr=False)
    impact: Impact | None = field(default=None, repr=False)

    @property
    def t1(self) -> float:
        return self.t0 + self.slip.time


@dataclass(frozen=True, eq=False)
class HybridResult:
    """The hybrid run: its segments, the final outcome and its time, and why it ended."""

    segments: tuple
    outcome: Outcome
    time: float
    reason: str

    @property
    def impacts(self) -> list[Impact]:
        return [s.impact for s in self.segments if s.impact is not None]

    def as_dict(self) -> dict:
        fin = lambda x: x if x is not None and math.isfinite(x) else None  # noqa: E731
        return {
            "outcome": self.outcome.name, "time": self.time, "reason": self.reason,
            "segments": [{"t0": s.t0, "t1": s.t1, "start": s.start.as_dict(), "event": s.slip.outcome.name, "reason": s.slip.reason,
                          "impact": None if s.impact is None else {
                              "normal_impulse": s.impact.normal_impulse, "tangential_impulse": s.impact.tangential_impulse.tolist(),
                              "phases": [(p.name, p.P_start, p.P_end) for p in s.impact.phases], "energy_lost": s.impact.energy_lost,
                              "after": {"Theta": s.impact.Theta, "Psi": s.impact.Psi, "eta": s.impact.eta, "varphi": fin(s.impact.varphi),
                                        "w": s.impact.w}}}
                         for s in self.segments],
        }


def run(state: SlipState, mu: float, alpha: float, *, horizon: float, restitution: float = 0.0, max_impacts: int = 8) -> HybridResult:
    """The hybrid rigid model from a slipping ``state`` up to ``horizon`` (scaled time).

    Raises ValueError for bad arguments (as ``slip_until_event`` and ``impact``).
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, HORIZON))
    restitution = float(check("restitution", restitution, UNIT))
    max_impacts = integer("max_impacts", max_impacts, 0, 1000)
    segments: list[Segment] = []
    t, s = 0.0, state
    for _ in range(max_impacts + 1):
        r = continue_slip(s, mu, alpha, t_max=horizon - t)
        if r.outcome != Outcome.JAM:
            segments.append(Segment(t, s, r))
            return HybridResult(tuple(segments), r.outcome, t + r.time, r.reason)
        imp = impact(r.state, mu, alpha, restitution=restitution)
        segments.append(Segment(t, s, r, imp))
        t += r.time
        if imp.w > 1e-12 * (1.0 + abs(imp.w)):
            return HybridResult(tuple(segments), Outcome.LIFTOFF, t, "impact: rebound (w > 0)")
        if imp.eta == 0.0:
            return HybridResult(tuple(segments), Outcome.STICK, t, "impact: stuck (slip stopped inside the cone)")
        if not (-math.pi < imp.varphi <= 0.0):
            return HybridResult(tuple(segments), Outcome.SLIP, t, "impact: varphi left (-pi, 0]")
        s = imp.after()
        b, p = float(analytic.b(s.Psi, s.Theta, s.theta)), float(analytic.p(s.theta, s.varphi, mu, alpha))
        if b > 0.0:
            return HybridResult(tuple(segments), Outcome.LIFTOFF, t, "impact: b > 0 after it")
        if horizon - t <= 0.0:
            return HybridResult(tuple(segments), Outcome.SLIP, t, "t_max")
        if p <= 0.0:
            continue  # still inconsistent: the next slip_until_event reports JAM at once
    return HybridResult(tuple(segments), Outcome.JAM, t, f"more than {max_impacts} impacts")
