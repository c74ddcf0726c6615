"""The comparison rule every study uses to set an engine's outcome beside the theory's: what is rated, for how long, with what lag.

An analytic run is compared only up to its comparison time (its event, its
exit from the paper's domain, or the horizon); an engine event after that
time counts as SLIP (``comparison_labels``), allowing the engine up to
``LAG_TAU`` contact time constants and at least ``LAG_STEPS`` timesteps of
lag at an analytic event; the engine runs ``window_margin`` past the horizon
so that an event near its end is judged by whole classifier windows.

A STICK the classifier cannot tell from the theory's slip is read as that
slip (``stick_from``).  The classifier calls a contact stuck once its slip
speed eta falls below the engine's STICK floor (``Thresholds.stick_floor``:
10 timesteps for a rigid contact, the larger of 1e-2 and the friction time
otherwise), so an engine that followed a theory whose slip slows below that
floor (to eta ~ 1e-3 at its chart's edge varphi = -pi, say) would be called
STICK even though the theory slips on.  Where the theory SLIPs to its
comparison time and its eta falls below the floor at t_floor on the way, an
engine STICK from t_floor - lag on (the lag an event is allowed) is
compared as the SLIP it cannot be told from.  An earlier STICK, while the
theory's slip is still faster than the floor, stays a disagreement, as does
any other event; the theory's own outcome is never changed.

At a jam a spring contact is allowed the lag the theory gives it.  A
contact whose normal force is a spring of time eps (``Options.spring_time``:
the compliant rod, Drake's point contact) stops slipping
s* (eps^4 / (k |b|))^(1/5) after the rigid rod's Corollary 4.2 jam
(``crosscheck.theory.jam_lag``: the pole s* = 3.919 of Painleve I, k and b at
the theory's jam state), which shrinks as eps^(4/5), slower than LAG_TAU eps:
without it a stiffer contact, converging to the theory's jam at that rate,
would be judged farther from it.  MuJoCo's impedance feeds the rigid force
forward, so its contact is not a spring there (``spring_time`` None) and
keeps LAG_TAU tau.
Scaled units (section 2.1).
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.engines.classifier import Thresholds
from crosscheck.outcome import Outcome

__all__ = [
    "RATED",
    "EVENTS",
    "LAG_TAU",
    "LAG_STEPS",
    "window_margin",
    "comparison_labels",
    "comparison_window",
    "compared_label",
    "floor_time",
    "engine_floor",
    "event_lag",
    "stick_from",
    "run_stick_from",
    "jam_scale",
    "theory_jam_scale",
    "jam_lag",
    "event_lags",
    "run_comparison_window",
]

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


def comparison_labels(outcome: np.ndarray, event_time: np.ndarray, until: np.ndarray, stick_from=np.inf) -> np.ndarray:
    """An engine's outcome as compared: an event after the comparison time ``until`` counts as SLIP, and so does a
    STICK at or after ``stick_from`` (``stick_from``: where the classifier cannot tell it from the theory's slip).

    DIVERGED is kept whatever its time (a diverged run is never relabelled).
    """
    outcome, event_time = np.asarray(outcome), np.asarray(event_time)
    keep = (outcome == Outcome.DIVERGED) | (event_time <= np.asarray(until))
    keep &= ~((outcome == Outcome.STICK) & (event_time >= np.asarray(stick_from)))
    return np.where(keep, outcome, np.int8(Outcome.SLIP)).astype(np.int8)


def comparison_window(
    outcome: Outcome, time: float, horizon: float, *, contact_time: float, timestep: float, spring_jam: float = 0.0
) -> tuple[float, float, float]:
    """(until, lag, run_until) of one start whose analytic first event is ``outcome`` at ``time``: its comparison time (the event
    time for an event, the domain-exit time of a censored SLIP, the horizon otherwise), the lag an engine is allowed at an event
    (max(LAG_TAU contact_time, LAG_STEPS timestep), and at a JAM at least ``spring_jam``: ``jam_lag``), and how far an engine
    must run for its label: until + lag within the horizon."""
    until = min(time, horizon) if outcome == Outcome.SLIP else (time if outcome in EVENTS else horizon)
    lag = event_lag(contact_time, timestep, spring_jam if outcome == Outcome.JAM else 0.0) if outcome in EVENTS else 0.0
    return until, lag, max(min(until + lag, horizon), timestep)


def run_comparison_window(first, horizon: float, mu: float, alpha: float, options) -> tuple[float, float, float]:
    """``comparison_window`` of a theory run ``first`` (``slip_until_event``'s result) for an engine run at ``options``:
    its contact time, timestep and, at a jam, its spring lag (``jam_lag``)."""
    return comparison_window(
        Outcome(int(first.outcome)),
        float(first.time),
        horizon,
        contact_time=options.contact_time,
        timestep=options.timestep,
        spring_jam=jam_lag(options, theory_jam_scale(first, mu, alpha)),
    )


def event_lags(outcome, scale, options) -> np.ndarray:
    """``comparison_window``'s lag for many starts: per analytic ``outcome`` (int8 array) and jam ``scale`` (``jam_scale``,
    NaN where no jam), the lag an engine run at ``options`` is allowed; 0 where the theory has no event."""
    outcome = np.asarray(outcome)
    spring_jam = np.where(outcome == Outcome.JAM, jam_lag(options, scale), 0.0)
    return np.where(
        np.isin(outcome, EVENTS), event_lag(float(options.contact_time), float(options.timestep), spring_jam), 0.0
    )


def compared_label(outcome: Outcome, time: float, until: float, stick_from: float = math.inf) -> Outcome:
    """``comparison_labels`` of one run (a NaN time, no event, counts as never)."""
    t = time if math.isfinite(time) else math.inf
    return Outcome(
        int(
            comparison_labels(
                np.array([int(outcome)], np.int8), np.array([t]), np.array([until]), np.array([stick_from])
            )[0]
        )
    )


def floor_time(t, eta, floor: float) -> float:
    """The first time the theory's slip speed ``eta`` (samples at times ``t``) falls below ``floor``, linear between the
    samples; NaN if it never does."""
    eta = np.asarray(eta, float)
    below = np.flatnonzero(eta < floor)
    if not below.size:
        return math.nan
    k = int(below[0])
    if k == 0:
        return float(t[0])
    return float(np.interp(floor, [eta[k], eta[k - 1]], [t[k], t[k - 1]]))


def engine_floor(thresholds: Thresholds, options) -> float:
    """The STICK floor of a run at ``options`` (an engine's ``Options``): rigid when its contact time is 0, as the engines
    call ``classify``."""
    return thresholds.stick_floor(
        timestep=options.timestep, friction_timeconst=options.friction_time, rigid=options.contact_time == 0.0
    )


def event_lag(contact_time: float, timestep: float, spring_jam=0.0):
    """The lag an engine is allowed at an analytic event: LAG_TAU contact times, at least LAG_STEPS timesteps, and at a
    jam at least ``spring_jam`` (``jam_lag``; a scalar or an array of one per start)."""
    base = max(LAG_TAU * contact_time, LAG_STEPS * timestep)
    return np.maximum(base, spring_jam) if np.ndim(spring_jam) else max(base, float(spring_jam))


def jam_scale(x, mu: float, alpha: float) -> float:
    """(k |b|)^(-1/5) at the theory's jam state ``x`` (eq. f's state (eta, varphi, psi, Psi, theta, Theta)):
    ``crosscheck.theory.jam_lag.inner_scale``; NaN where b >= 0 or k <= 0."""
    from crosscheck.theory import analytic
    from crosscheck.theory.jam_lag import inner_scale, jam_stiffness

    eta, varphi, _psi, Psi, theta, Theta = (float(v) for v in x)
    return inner_scale(float(analytic.b(Psi, Theta, theta)), jam_stiffness(theta, varphi, eta, mu, alpha))


def theory_jam_scale(first, mu: float, alpha: float) -> float:
    """``jam_scale`` of a theory run (``slip_until_event``'s result) that JAMs, NaN for any other outcome."""
    return jam_scale(first.x[-1], mu, alpha) if int(first.outcome) == Outcome.JAM else math.nan


def jam_lag(options, scale):
    """The lag a run at ``options`` (an engine's ``Options``) is allowed at a theory jam of ``scale`` (``jam_scale``):
    ``crosscheck.theory.jam_lag.spring_jam_lag`` at its ``spring_time`` for a spring contact, 0 otherwise (module
    docstring).  ``scale``: a scalar or an array (NaN: no Corollary 4.2 jam, 0)."""
    from crosscheck.theory.jam_lag import spring_jam_lag

    eps = getattr(options, "spring_time", None)  # optional in the engine contract: only spring contacts declare it
    if np.ndim(scale):
        return np.array(
            [0.0 if eps is None else spring_jam_lag(float(eps), float(c)) for c in np.asarray(scale, float)]
        )
    return 0.0 if eps is None else spring_jam_lag(float(eps), float(scale))


def stick_from(outcome, until, t_floor, lag):
    """The time from which an engine STICK is read as the theory's SLIP (module docstring): t_floor - lag where the
    theory SLIPs to ``until`` and its slip speed falls below the engine's STICK floor at ``t_floor`` <= until; +inf
    elsewhere (a NaN t_floor: never below).  Scalars or arrays."""
    outcome, until, t_floor = np.asarray(outcome), np.asarray(until, float), np.asarray(t_floor, float)
    with np.errstate(invalid="ignore"):
        hit = (outcome == Outcome.SLIP) & (t_floor <= until)
    return np.where(hit, t_floor - np.asarray(lag, float), np.inf)


def run_stick_from(first, until: float, thresholds: Thresholds, options) -> float:
    """``stick_from`` of one theory run ``first`` (``slip_until_event``'s result, its ``x[:, 0]`` the slip speed) compared up
    to ``until`` with an engine run at ``options`` (its STICK floor and event lag)."""
    t_floor = floor_time(first.t, first.x[:, 0], engine_floor(thresholds, options))
    return float(stick_from(int(first.outcome), until, t_floor, event_lag(options.contact_time, options.timestep)))
