"""The hybrid rigid model: slip, impact without collision, stick, and on, through every mode change, up to a horizon.

The paper's slipping flow (``crosscheck.theory.slipping.slip_until_event``)
stops at its first event.  The rigid model continues from there:

* JAM (p reaches 0 with b < 0, Corollary 4.2): the impulse of
  ``crosscheck.theory.impact.darboux_keller.impact``;
* GB (the flow reaches b = p = 0, the Genot-Brogliato point): the same
  impulse on the boundary, its limit p -> 0- (``impact(..., boundary=True)``);
* after an impulse the tip is at rest (the slip always stops within it) or,
  with a restitution e > 0, thrown off (normal velocity w > 0): LIFTOFF;
* STICK (the slip speed reaches 0) and a tip at rest after an impulse: the
  mode at rest (``crosscheck.theory.sticking.at_rest``): the rod sticks and
  pivots about its tip (``stick_until_event``) until the friction leaves the
  cone; lifts off (b > 0 where sticking would need a pull: LIFTOFF); or
  slips again in the direction the theory gives (varphi = -pi/2, a new
  slipping segment; varphi = +pi/2, towards the centre, is outside the
  paper's domain (-pi, 0]: SLIP, ended there);
* LIFTOFF, SLIP (the horizon or a domain exit) end the run.

Scaled units (section 2.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from crosscheck.checks import ALPHA, HORIZON, MU, UNIT, check, integer
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.theory.impact.darboux_keller import Impact, impact
from crosscheck.theory.slipping import SlipResult, continue_slip
from crosscheck.theory.sticking import SLIP_ONSET_SPEED, StickResult, at_rest, stick_until_event

__all__ = ["Segment", "StickSegment", "HybridResult", "run", "MAX_MODES"]

#: The most mode changes (slip, stick) a run may make before it is called off (a guard: each change is an event of the model).
MAX_MODES = 64
#: The slipping flow's desingularised horizon: a slip from rest starts at eta = SLIP_ONSET_SPEED, where s runs ~ 1/sqrt(eta) per unit t.
_S_MAX = 1e8


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
class StickSegment:
    """The rod pivoting about its stuck tip from ``start`` (at time t0) until ``stick`` ends (a ``StickResult`` in local time)."""

    t0: float
    start: SlipState
    stick: StickResult = field(repr=False)

    @property
    def t1(self) -> float:
        return self.t0 + self.stick.time


def _fin(x):
    return x if x is not None and math.isfinite(x) else None


def _segment_dict(s) -> dict:
    if isinstance(s, StickSegment):
        r = s.stick
        start = {**s.start.as_dict(), "eta": 0.0, "varphi": None}  # a tip at rest has no slip direction
        return {
            "mode": "stick",
            "t0": s.t0,
            "t1": s.t1,
            "start": start,
            "event": r.outcome.name,
            "reason": r.reason,
            "slip_varphi": _fin(r.varphi),
            "force": list(r.force),
            "end": r.state.as_dict(),
        }
    return {
        "mode": "slip",
        "t0": s.t0,
        "t1": s.t1,
        "start": s.start.as_dict(),
        "event": s.slip.outcome.name,
        "reason": s.slip.reason,
        "impact": None
        if s.impact is None
        else {
            "normal_impulse": s.impact.normal_impulse,
            "tangential_impulse": s.impact.tangential_impulse.tolist(),
            "phases": [(p.name, p.P_start, p.P_end) for p in s.impact.phases],
            "energy_lost": s.impact.energy_lost,
            "after": {
                "Theta": s.impact.Theta,
                "Psi": s.impact.Psi,
                "eta": s.impact.eta,
                "varphi": _fin(s.impact.varphi),
                "w": s.impact.w,
            },
        },
    }


@dataclass(frozen=True, eq=False)
class HybridResult:
    """The hybrid run: its segments (``Segment`` while slipping, ``StickSegment`` while stuck), the final outcome and its time, and why it ended."""

    segments: tuple
    outcome: Outcome
    time: float
    reason: str

    @property
    def impacts(self) -> list[Impact]:
        return [s.impact for s in self.segments if isinstance(s, Segment) and s.impact is not None]

    def as_dict(self) -> dict:
        return {
            "outcome": self.outcome.name,
            "time": self.time,
            "reason": self.reason,
            "segments": [_segment_dict(s) for s in self.segments],
        }


def run(
    state: SlipState, mu: float, alpha: float, *, horizon: float, restitution: float = 0.0, max_impacts: int = 8
) -> HybridResult:
    """The hybrid rigid model from a slipping (or, with eta = 0, resting) ``state`` up to ``horizon`` (scaled time).

    At most ``max_impacts`` impacts without collision: the next jam ends the run (JAM, "more than ... impacts").
    Raises ValueError for bad arguments (as ``slip_until_event`` and ``impact``).
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, HORIZON))
    restitution = float(check("restitution", restitution, UNIT))
    max_impacts = integer("max_impacts", max_impacts, 0, 1000)
    segments: list = []
    t, s, from_rest = 0.0, state, False
    for _ in range(MAX_MODES):
        r = continue_slip(s, mu, alpha, t_max=horizon - t, **({"s_max": _S_MAX} if from_rest else {}))
        if r.outcome in (Outcome.JAM, Outcome.GB):
            if sum(isinstance(x, Segment) and x.impact is not None for x in segments) >= max_impacts:
                segments.append(Segment(t, s, r))
                return HybridResult(tuple(segments), Outcome.JAM, t + r.time, f"more than {max_impacts} impacts")
            imp = impact(r.state, mu, alpha, restitution=restitution, boundary=r.outcome is Outcome.GB)
            segments.append(Segment(t, s, r, imp))
            t += r.time
            if imp.w > 1e-12 * (1.0 + abs(imp.w)):
                return HybridResult(tuple(segments), Outcome.LIFTOFF, t, "impact: rebound (w > 0)")
            at = SlipState(
                theta=r.state.theta, varphi=r.state.varphi, Theta=imp.Theta, Psi=imp.Psi, eta=0.0, psi=r.state.psi
            )
            why = "impact"
        elif r.outcome is Outcome.STICK:
            segments.append(Segment(t, s, r))
            t += r.time
            at, why = r.state, "slip stopped"
        else:
            segments.append(Segment(t, s, r))
            return HybridResult(tuple(segments), r.outcome, t + r.time, r.reason)
        # the tip at rest: stick, lift off or slip again
        rest = at_rest(at, mu, alpha)
        if rest.mode == "liftoff":
            return HybridResult(
                tuple(segments), Outcome.LIFTOFF, t, f"{why}: at rest with b > 0 (sticking would need F_n < 0)"
            )
        if rest.mode == "inconsistent":
            return HybridResult(tuple(segments), Outcome.JAM, t, f"{why}: at rest with no consistent mode")
        varphi = rest.varphi
        if rest.mode == "stick":
            if horizon - t <= 0.0:
                return HybridResult(tuple(segments), Outcome.STICK, t, "t_max")
            k = stick_until_event(at, mu, alpha, t_max=horizon - t)
            segments.append(StickSegment(t, at, k))
            t += k.time
            if k.reason != "cone":
                return HybridResult(tuple(segments), k.outcome, t, f"stick: {k.reason}")
            at, varphi = k.state, k.varphi
        if not -math.pi < varphi <= 0.0:
            return HybridResult(
                tuple(segments), Outcome.SLIP, t, "slip from rest towards the centre: varphi = pi/2 is outside (-pi, 0]"
            )
        if horizon - t <= 0.0:
            return HybridResult(tuple(segments), Outcome.SLIP, t, "t_max")
        s = SlipState(theta=at.theta, varphi=varphi, Theta=at.Theta, Psi=at.Psi, eta=SLIP_ONSET_SPEED, psi=at.psi)
        from_rest = True
    return HybridResult(tuple(segments), Outcome.JAM, t, f"more than {MAX_MODES} mode changes")
