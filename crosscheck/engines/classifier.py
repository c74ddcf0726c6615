"""The one event classifier: what happened first in a recorded run of any engine, and when.

A rigid rod slipping with Coulomb friction ends its slip in one of the
paper's events: LIFTOFF (b reaches 0 with p > 0), STICK (eta reaches 0), JAM
(p reaches 0 with b < 0, Corollary 4.2), or it keeps slipping (SLIP).  An
engine's record (``crosscheck.engines.Record``) shows these events through
forces and velocities, and a soft contact shows them blurred: while a tip
slips on MuJoCo's soft elliptic contact it alternates between short normal
force spikes (several m g) and short flights (the contact chatters), and only
the normal impulse averaged over a window matches the rigid F_z = -b/p
(eq. FZ).  Every criterion therefore looks at windows or at signs that the
chatter cannot fake; the numbers are in ``Thresholds`` (``crosscheck.engines.thresholds``) with where they come
from.

JAM is judged against the engine's own friction.  An engine's friction is not
always anti-parallel to the slip (MuJoCo's is skewed by 7-34 degrees off the
planar section), so while it slips its window-mean normal force is
-b/p_eff, with p_eff the vertical tip acceleration per unit normal force of
the engine's actual contact force (eq. linode2):

    p_eff = 1 + alpha - alpha sin^2 theta - alpha sin theta cos theta (F_t . e) / F_z,

e = (-sin psi, cos psi) the rod's horizontal direction; p_eff equals eq. p
when F_t = -mu F_z u/|u|.  A rule that compared the force with -b/p instead
fires on ordinary slipping off the planar section (window means 3-7 x -b/p
but 1.0-1.6 x -b/p_eff, measured at high mu eta).  Below mu_P no friction
direction makes p_eff vanish (p_eff >= min over varphi of eq. p > 0), so this
rule cannot mistake a mere direction change for a jam.

A compliant contact (force built up over a contact time tau_c > 0: the
compliant rod's eps, Drake's 1/sqrt(stiffness), MuJoCo's solref time
constant) resolves an impact without collision in a time O(tau_c), not in a
step, and ends it in a slip stop that a fixed window misses.  ``classify``
therefore also judges the first slip stop itself when it is given
``contact_time`` (``stop_jam_rows``): over the last jam_contact_times tau_c
before it, the contact slipped at the engine's own p_eff <= jam_p_eff (read
at the capsule's contact point, r below the tip: the friction's arm is
sin theta + r) under jam_ratio times the slipping force.  As tau_c -> 0 this
tends to the rigid rule.  The derivation from
``crosscheck.theory.compliant_limit`` and the measurements behind the
contact point are in ``docs/classifier.md``.

Each rule is one function of ``crosscheck.engines.classifier_rules``
(``diverged_rows``, ``window_jam_rows``, ``impulse_jam_rows``,
``liftoff_rows``, ``launch_rows``, ``stick_rows``, ``stop_jam_rows``) over the
series ``rows_of`` computes once; ``first_event`` takes the earliest.

All quantities are in the paper's scaled units (section 2.1).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from crosscheck.checks import NONNEGATIVE, check
from crosscheck.engines.classifier_rules import (
    diverged_rows,
    first_row,
    held_at_rest,
    impulse_jam_rows,
    launch_rows,
    liftoff_rows,
    rows_of,
    stick_rows,
    stop_jam_rows,
    window_jam_rows,
    window_sum,
)
from crosscheck.engines.record import Record
from crosscheck.engines.thresholds import Thresholds
from crosscheck.outcome import Outcome

__all__ = ["Thresholds", "Classification", "classify", "window_sum"]


class Classification(NamedTuple):
    """What ``classify`` returns; each field has the batch shape of the record.

    outcome: int8 ``Outcome`` values.
    event_time: scaled time of the first event (NaN for SLIP).
    event_row: its row (-1 for SLIP).
    exit_time: scaled time at which theta left (0, pi/2), the paper's domain
      (the rod lies flat or stands up; NaN if never).  Events are looked for
      only before it (a run that leaves first is SLIP, like the analytic
      ``slip_until_event``), except DIVERGED, which is never dropped.
    diverged_time: scaled time of the first diverged row (NaN if none), also
      when another event came first and is the outcome: a divergence is
      always reported.
    jam_p_eff: the engine's own p at the JAM: window p_eff, or eq. p of the
      row for a rigid contact's one-row impulse (NaN if the outcome is not JAM).
    jam_impulse: the normal impulse of the JAM [m g / omega]: over the window,
      or of the one row (NaN if the outcome is not JAM).
    max_normal_force: largest normal force of one row [m g] (the spikes).
    max_window_force: largest window-mean normal force [m g].
    active_fraction: fraction of rows in which the engine had a contact.
    max_gap: largest height of the contact point above the plane [l].
    """

    outcome: np.ndarray
    event_time: np.ndarray
    event_row: np.ndarray
    exit_time: np.ndarray
    diverged_time: np.ndarray
    jam_p_eff: np.ndarray
    jam_impulse: np.ndarray
    max_normal_force: np.ndarray
    max_window_force: np.ndarray
    active_fraction: np.ndarray
    max_gap: np.ndarray


#: Rows after which an engine that may stop a run once its first event is judged first classifies the rows so far;
#: then after twice as many each time, so the checks cost at most about two classifications of the rows computed.
FIRST_CHECK = 128


def first_event_final(c: Classification, rows: int, thresholds: Thresholds, timestep: float) -> bool:
    """Whether the first event ``classify`` found on a run's first ``rows`` rows is the first event of the whole run.

    Every rule judges a row from the rows before it and at most a window (``Thresholds.window_rows``) plus one
    row after it, and a rule whose rows reach past the record is not judged.  An event whose look-ahead ends
    inside the rows is therefore judged exactly as on any longer record that begins with them, and an earlier
    event would have been judged too: nothing the run does later can change the first event.
    """
    k = int(c.event_row)
    return k >= 0 and k + thresholds.window_rows(timestep) + max(2, thresholds.lift_steps) <= rows


def _at(x: np.ndarray, k: np.ndarray, has: np.ndarray) -> np.ndarray:
    """x at row k of each run where ``has``, NaN elsewhere."""
    idx = np.where(has, k, 0)
    xk = np.take_along_axis(x, np.asarray(idx)[..., None], axis=-1)[..., 0]
    return np.where(has, xk, np.nan)


def first_event(found: list[tuple[Outcome, np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """(outcome, row) of the earliest of ``found``'s events, (outcome, has, first row) each; on a tie the earlier
    in ``found`` wins; SLIP and the largest int64 where none happened."""
    has0 = found[0][1]
    big = np.iinfo(np.int64).max
    best_k = np.full(has0.shape, big, dtype=np.int64)
    outcome = np.full(has0.shape, int(Outcome.SLIP), dtype=np.int8)
    for oc, has, k in found:
        better = has & (k < best_k)
        best_k = np.where(better, k, best_k)
        outcome = np.where(better, np.int8(oc), outcome)
    return outcome, best_k


def _jam_rows(R: Record, s, th: Thresholds, *, mu, alpha: float, w: int, rigid: bool):
    """(jam, p_eff, sF): the rows the window rule judges a JAM, with its p_eff and summed force; for a ``rigid``
    engine also the rows of one step's impulse (``impulse_jam_rows``), with their own p_eff and force."""
    jam, p_eff, sF = window_jam_rows(s, th, alpha=alpha, w=w)
    if rigid:
        impulse, p_row = impulse_jam_rows(R, s, th, mu=mu, alpha=alpha)
        jam |= impulse
        p_eff = np.where(impulse, p_row, p_eff)
        sF = np.where(impulse, s.Fn, sF)
    return jam, p_eff, sF


def _classification(R: Record, s, outcome, best_k, diverged, k_jam, p_eff, sF, *, timestep: float, w: int):
    """The ``Classification`` of the runs: the first event's ``outcome`` at row ``best_k`` (the largest int64 where
    none), ``diverged`` = (has, first row) of the divergence, the JAM's row, p_eff and summed force, and the force,
    activity and gap summaries of the computed rows."""
    found_event = best_k != np.iinfo(np.int64).max
    has_div, k_div = diverged
    Fn, t, computed, n = s.Fn, R.t, s.computed, s.n
    with np.errstate(invalid="ignore"):
        return Classification(
            outcome=outcome,
            event_time=_at(t, best_k, found_event),
            event_row=np.where(found_event, best_k, -1),
            exit_time=_at(t, s.k_exit, s.has_exit),
            diverged_time=_at(t, k_div, has_div),
            jam_p_eff=_at(p_eff, k_jam, outcome == Outcome.JAM),
            jam_impulse=_at(sF * timestep, k_jam, outcome == Outcome.JAM),
            # fmax skips NaN as nanmax does, without nanmax's RuntimeWarning for a run with no finite row (diverged at once)
            max_normal_force=np.fmax.reduce(np.where(np.isfinite(Fn), Fn, np.nan), axis=-1) if n else np.nan,
            max_window_force=np.fmax.reduce(window_sum(Fn, w) / w, axis=-1)
            if n >= w
            else np.full(has_div.shape, np.nan),
            active_fraction=(np.asarray(R.active, dtype=bool) & computed).sum(axis=-1)
            / np.maximum(computed.sum(axis=-1), 1),
            max_gap=np.max(np.where(computed, R.gap, -np.inf), axis=-1),
        )


def classify(
    record: Record,
    *,
    mu,
    alpha: float,
    timestep: float,
    friction_timeconst: float = 0.0,
    rigid: bool = False,
    contact_time: float | None = None,
    radius: float = 0.0,
    thresholds: Thresholds | None = None,
) -> Classification:
    """Outcome and event time of recorded runs, for every engine.

    Args:
      record: a ``Record`` with rows at a uniform ``timestep`` (batch axes allowed).
      mu: friction coefficient, a scalar or one per run (the batch shape).
      alpha: the rod's m l^2 / I0.
      timestep: scaled time between rows (sets the window length in rows).
      friction_timeconst: scaled friction time constant of the run (the
        STICK threshold grows with it; 0 for a rigid contact).
      rigid: the engine resolves contact by impulses within a step (no force
        build-up time).  Its lift-off is decided exactly in one step (the
        impulse is 0 iff b >= 0), so LIFTOFF needs one force-free upward row,
        not lift_steps.  A JAM can then also be one row's impulse
        (``impulse_jam_rows``).
      contact_time: scaled time over which the engine's normal force builds
        up (``Options.contact_time``); with a value > 0 (and not ``rigid``)
        the first slip stop is also judged as a compliant JAM (module
        docstring; ``stop_jam_rows``).  None or 0: the window rule only.
      radius: the capsule radius r [l] of the engine's rod (0: it touches at the tip), the friction's extra moment arm
        in the slip stop's p_eff (module docstring).
      thresholds: criteria (``Thresholds()`` by default; see there for why).

    Returns:
      ``Classification``.  The first event wins; on a tie DIVERGED > JAM >
      LAUNCH > LIFTOFF > STICK.  A window that would reach past the end of the record
      (or past the domain exit) is not judged, so an event in the last W of
      the horizon can be missed.
    """
    th = thresholds or Thresholds()
    r = float(check("radius", radius, NONNEGATIVE))
    w = th.window_rows(timestep)
    stick_speed = th.stick_floor(timestep=timestep, friction_timeconst=friction_timeconst, rigid=rigid)
    if contact_time is not None and not rigid:
        check("contact_time", contact_time, NONNEGATIVE)
    R = record
    mu = np.asarray(mu, dtype=float)[..., None]  # broadcast over rows

    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        s = rows_of(R)
        has_div, k_div = first_row(diverged_rows(R, s, th))
        jam, p_eff, sF = _jam_rows(R, s, th, mu=mu, alpha=alpha, w=w, rigid=rigid)
        has_jam, k_jam = first_row(jam)
        has_lift, k_lift = first_row(liftoff_rows(R, s, th, rigid=rigid))
        has_launch, k_launch = first_row(launch_rows(R, s, th, w=w, timestep=timestep))
        held = held_at_rest(R, mu[..., 0], alpha, stick_speed)  # a start at rest sticks only if friction holds it
        has_stick, k_stick = first_row(stick_rows(s, w=w, stick_speed=stick_speed) & held)
        if contact_time and not rigid:
            m = th.stop_rows(float(contact_time), timestep)
            stop_jam = stop_jam_rows(
                s,
                th,
                has_stick=has_stick,
                k_stick=k_stick,
                m=m,
                stick_speed=stick_speed,
                alpha=alpha,
                radius=r,
                p_eff=p_eff,
                sF=sF,
            )
            if stop_jam.any():
                has_jam, k_jam = first_row(jam | stop_jam)

    outcome, best_k = first_event(
        [  # precedence on ties: earlier in the list wins
            (Outcome.DIVERGED, has_div, k_div),
            (Outcome.JAM, has_jam, k_jam),
            (Outcome.LAUNCH, has_launch, k_launch),
            (Outcome.LIFTOFF, has_lift, k_lift),
            (Outcome.STICK, has_stick, k_stick),
        ]
    )
    return _classification(R, s, outcome, best_k, (has_div, k_div), k_jam, p_eff, sF, timestep=timestep, w=w)
