"""The comparison rule every study uses to set an engine's outcome beside the theory's: what is rated, for how long, with what lag.

An analytic run is compared only up to its comparison time (its event, its
exit from the paper's domain, or the horizon); an engine event after that
time counts as SLIP (``comparison_labels``), allowing the engine up to
``LAG_TAU`` contact time constants and at least ``LAG_STEPS`` timesteps of
lag at an analytic event; the engine runs ``window_margin`` past the horizon
so that an event near its end is judged by whole classifier windows.
Scaled units (section 2.1).
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.engines.classifier import Thresholds
from crosscheck.outcome import Outcome

__all__ = ["RATED", "EVENTS", "LAG_TAU", "LAG_STEPS", "window_margin", "comparison_labels", "comparison_window", "compared_label"]

#: Outcomes an analytic run is compared on (GB and DIVERGED rows are counted, not rated).
RATED = (Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM)
EVENTS = (Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM)

#: An engine may meet an analytic event up to LAG_TAU contact time constants late (see ``_rate``).
LAG_TAU = 2.0

#: ... and at least LAG_STEPS timesteps late: the first row after the event, plus the O(dt) shift of a
#: first-order integrator (measured up to 1.3 dt at the rigid engine's lift-offs).  For MuJoCo
#: LAG_TAU tau is larger (tau >= 2 dt, MuJoCo's refsafe), so this only matters for rigid contacts.
LAG_STEPS = 3.0


def window_margin(thresholds: Thresholds, timestep: float) -> float:
    """How far past the horizon an engine runs: two classifier windows, so an event near the end is judged whole."""
    return 2.0 * thresholds.window_rows(timestep) * timestep


def comparison_labels(outcome: np.ndarray, event_time: np.ndarray, until: np.ndarray) -> np.ndarray:
    """An engine's outcome as compared: an event after the comparison time ``until`` counts as SLIP.

    DIVERGED is kept whatever its time (a diverged run is never relabelled).
    """
    outcome = np.asarray(outcome)
    keep = (outcome == Outcome.DIVERGED) | (np.asarray(event_time) <= np.asarray(until))
    return np.where(keep, outcome, np.int8(Outcome.SLIP)).astype(np.int8)


def comparison_window(outcome: Outcome, time: float, horizon: float, *, contact_time: float, timestep: float) -> tuple[float, float, float]:
    """(until, lag, run_until) of one start whose analytic first event is ``outcome`` at ``time``: its comparison time (the event
    time for an event, the domain-exit time of a censored SLIP, the horizon otherwise), the lag an engine is allowed at an event
    (max(LAG_TAU contact_time, LAG_STEPS timestep)), and how far an engine must run for its label: until + lag within the horizon."""
    until = min(time, horizon) if outcome == Outcome.SLIP else (time if outcome in EVENTS else horizon)
    lag = max(LAG_TAU * contact_time, LAG_STEPS * timestep) if outcome in EVENTS else 0.0
    return until, lag, max(min(until + lag, horizon), timestep)


def compared_label(outcome: Outcome, time: float, until: float) -> Outcome:
    """``comparison_labels`` of one run (a NaN time, no event, counts as never)."""
    t = time if math.isfinite(time) else math.inf
    return Outcome(int(comparison_labels(np.array([int(outcome)], np.int8), np.array([t]), np.array([until]))[0]))
