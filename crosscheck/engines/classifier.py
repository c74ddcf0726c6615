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

Each rule is one function (``diverged_rows``, ``window_jam_rows``,
``impulse_jam_rows``, ``liftoff_rows``, ``launch_rows``, ``stick_rows``,
``stop_jam_rows``) over the series ``rows_of`` computes once; ``first_event``
takes the earliest.

All quantities are in the paper's scaled units (section 2.1).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from crosscheck.checks import NONNEGATIVE, check
from crosscheck.engines.record import Record
from crosscheck.engines.thresholds import Thresholds
from crosscheck.outcome import Outcome
from crosscheck.theory.sticking import stick_force

__all__ = ["Thresholds", "Classification", "classify", "window_sum"]


def held_at_rest(record: Record, mu, alpha: float, stick_speed: float) -> np.ndarray:
    """The rows the STICK rule may judge: every row once the tip has slid (its slip speed reached ``stick_speed``),
    and the rows of a start at rest only if the friction can hold it there, |F_t| <= mu F_n with the stuck rod's
    forces at the first row (``crosscheck.theory.sticking.stick_force``, eq. linode2 at a = 0).  A start at rest
    that the friction cannot hold slides from its first step, however slowly: its first slow rows are not a STICK.
    (..., n) bool, ``mu`` a scalar or one per run."""
    eta = np.where(np.isfinite(record.eta), record.eta, 0.0)
    slid = np.logical_or.accumulate(eta >= stick_speed, axis=-1)
    _, F_j, F_n = stick_force(record.theta[..., 0], record.Psi[..., 0], record.Theta[..., 0], alpha)
    with np.errstate(invalid="ignore"):
        held = (F_n >= 0.0) & (np.abs(F_j) <= np.asarray(mu, dtype=float) * F_n)
    return slid | np.asarray(held)[..., None]


def _first(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(any, index of first True) along the last axis."""
    has = mask.any(axis=-1)
    return has, np.where(has, mask.argmax(axis=-1), -1)


def window_sum(x: np.ndarray, w: int) -> np.ndarray:
    """Sum of x[..., k:k+w] for each k with a full window; NaN for the last w - 1 rows."""
    n = x.shape[-1]
    c = np.zeros(x.shape[:-1] + (n + 1,))
    np.cumsum(x, axis=-1, out=c[..., 1:])
    out = np.full(x.shape, np.nan)
    if w <= n:
        out[..., : n - w + 1] = c[..., w:] - c[..., : n - w + 1]
    return out


def _window_count(mask: np.ndarray, w: int) -> np.ndarray:
    """Number of True in mask[..., k:k+w] for each k with a full window: n - w + 1 values (n >= w).

    Integer prefix sums: the counts ``window_sum`` gives exactly, at a third of the cost of a float cumsum.
    """
    n = mask.shape[-1]
    c = np.zeros(mask.shape[:-1] + (n + 1,), dtype=np.int64)
    np.cumsum(mask, axis=-1, out=c[..., 1:])
    return c[..., w:] - c[..., : n - w + 1]


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


class Rows(NamedTuple):
    """What every rule reads from a record, computed once; each field has the record's shape (..., n).

    computed: the rows a run computed (a run stopped once its first event is judged leaves NaN times after).
    end: (..., 1) the first row no rule may read: the domain exit, else the first row not computed, else n.
    st, ct: sin and cos theta.  b: eq. b.  eta: the slip speed.  Fn: the normal force.
    Fz: the force's z component where it presses (0 elsewhere); Fe: F_t . e on those rows (0 elsewhere).
    """

    n: int
    index: np.ndarray
    computed: np.ndarray
    has_exit: np.ndarray
    k_exit: np.ndarray
    end: np.ndarray
    st: np.ndarray
    ct: np.ndarray
    b: np.ndarray
    eta: np.ndarray
    Fn: np.ndarray
    Fz: np.ndarray
    Fe: np.ndarray


def rows_of(record: Record) -> Rows:
    """The shared series of ``record`` (call under ``np.errstate(invalid="ignore", divide="ignore", over="ignore")``)."""
    n = len(record)
    t, theta, psi = record.t, record.theta, record.psi
    computed = np.isfinite(t)
    # Domain: theta in (0, pi/2).  Windows must end before the exit (or the last computed row).
    has_exit, k_exit = _first(~((theta > 0.0) & (theta < math.pi / 2)) & computed)
    has_cut, k_cut = _first(~computed)
    end = np.where(has_exit, k_exit, np.where(has_cut, k_cut, n))[..., None]
    st, ct = np.sin(theta), np.cos(theta)
    b = (record.Psi * record.Psi * ct * ct + record.Theta * record.Theta) * st - 1.0  # eq. b
    F = record.force
    pressed = F[..., 2] > 0
    Fz = np.where(pressed, F[..., 2], 0.0)
    # F_t . e only on the pressed rows (0 elsewhere): sin and cos cost 20-30 cheap passes each
    Fe = np.zeros(Fz.shape)
    psi_p = psi[pressed]
    Fe[pressed] = -np.sin(psi_p) * F[..., 0][pressed] + np.cos(psi_p) * F[..., 1][pressed]
    return Rows(
        n=n,
        index=np.arange(n),
        computed=computed,
        has_exit=has_exit,
        k_exit=k_exit,
        end=end,
        st=st,
        ct=ct,
        b=b,
        eta=record.eta,
        Fn=record.normal_force,
        Fz=Fz,
        Fe=Fe,
    )


def diverged_rows(record: Record, s: Rows, th: Thresholds) -> np.ndarray:
    """DIVERGED: non-finite values (NaN fails every comparison), runaway speed, or a stopped clock (mujoco.rollout
    repeats the last row after a warning); only computed rows, but past the domain exit too."""
    vel, az = record.tip_vel, record.tip_acc[..., 2]
    speed2 = vel[..., 0] * vel[..., 0] + vel[..., 1] * vel[..., 1] + vel[..., 2] * vel[..., 2]
    bad = ~(speed2 <= th.diverged_speed**2) | ~(np.abs(az + 1.0) < 1e9) | ~(np.abs(s.Fn) < np.inf)
    bad |= ~(np.abs(record.theta) < np.inf)
    bad[..., 1:] |= ~(np.diff(record.t, axis=-1) > 0.0)
    return bad & s.computed


def window_jam_rows(s: Rows, th: Thresholds, *, alpha: float, w: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """JAM over a window: an impulsive window-mean force beyond what slipping with the engine's own friction needs
    (-b/p_eff), an abrupt loss of slip speed, at the engine's own p_eff ~ 0 (module docstring).

    Returns (rows, window p_eff, window normal impulse / timestep).
    """
    n, st, ct, eta = s.n, s.st, s.ct, s.eta
    sF = window_sum(s.Fz, w)
    p_eff = (window_sum(s.Fz * (1 + alpha - alpha * st * st), w) - alpha * window_sum(st * ct * s.Fe, w)) / sF
    Fbar = sF / w
    slipping_force = np.where(p_eff > 0, window_sum(np.maximum(0.0, -s.b), w) / w / p_eff, 0.0)
    eta_end = np.full(eta.shape, np.nan)
    if w <= n:
        eta_end[..., : n - w + 1] = eta[..., w - 1 :]
    jam = (
        (Fbar >= th.jam_force)
        & (Fbar >= th.jam_ratio * slipping_force)
        & (eta - eta_end >= th.jam_slip_loss * eta)
        & (p_eff <= th.jam_p_eff)
    )
    jam &= s.index + w <= s.end
    return jam, p_eff, sF


def impulse_jam_rows(
    record: Record, s: Rows, th: Thresholds, *, mu: np.ndarray, alpha: float
) -> tuple[np.ndarray, np.ndarray]:
    """JAM as one row's impulse, for a rigid contact (it resolves the impact without collision within a step): eq. p on
    the row's own state (a rigid contact's friction is exactly Coulomb's) at most jam_p_eff, the row's force beyond
    jam_ratio times the slipping force -b/p (and jam_force), and the slip speed falling by jam_slip_loss within
    lift_steps rows.  ``mu`` has a trailing axis of 1.  Returns (rows, eq. p of each row)."""
    n, st, ct, eta = s.n, s.st, s.ct, s.eta
    p_row = 1.0 + alpha + alpha * st * (mu * ct * np.sin(record.varphi) - st)
    after = np.full(eta.shape, np.nan)
    m = th.lift_steps
    if m < n:
        after[..., : n - m] = eta[..., m:]
    # Where p <= 0 no slipping force exists (Corollary 4.2's impasse): any impulse beyond jam_force is the IWC.
    need = th.jam_ratio * np.maximum(th.jam_force, np.where(p_row > 0, np.maximum(0.0, -s.b) / p_row, 0.0))
    impulse = (
        (s.Fn >= need) & (p_row <= th.jam_p_eff) & (eta - after >= th.jam_slip_loss * eta) & (s.index + m <= s.end)
    )
    return impulse, p_row


def liftoff_rows(record: Record, s: Rows, th: Thresholds, *, rigid: bool) -> np.ndarray:
    """LIFTOFF: lift_steps force-free rows in a row with the tip accelerating upwards (b > 0).  A rigid contact decides
    this exactly in one step (its impulse is 0 iff b >= 0): one row suffices."""
    n = s.n
    lift_steps = 1 if rigid else th.lift_steps
    free_up = (s.Fn <= 0.0) & (record.tip_acc[..., 2] > 0.0)
    run = np.zeros(free_up.shape, dtype=bool)
    if lift_steps <= n:
        run[..., : n - lift_steps + 1] = _window_count(free_up, lift_steps) == lift_steps
    return run & (s.index + lift_steps <= s.end)


def launch_rows(record: Record, s: Rows, th: Thresholds, *, w: int, timestep: float) -> np.ndarray:
    """LAUNCH: a contact row with b < 0 whose step leaves the contact point rising at launch_ratio eta (and fast enough
    to fly a window under b), followed by a window with no contact force and b < 0 throughout."""
    n, Fn, b, eta = s.n, s.Fn, s.b, s.eta
    vz = record.tip_vel[..., 2]  # C = A - r K moves vertically with A
    rising = np.full(vz.shape, -np.inf)
    rising[..., :-1] = vz[..., 1:]
    in_contact, falling = Fn > 0.0, b < 0.0
    pushed = in_contact & falling
    fast = (rising >= th.launch_ratio * eta) & (rising >= th.launch_speed) & (rising >= 0.5 * np.abs(b) * w * timestep)
    ahead_free = np.full(Fn.shape, False)
    ahead_down = np.full(Fn.shape, False)
    if w + 1 <= n:
        ahead_free[..., : n - w] = _window_count(in_contact, w)[..., 1:] == 0
        ahead_down[..., : n - w] = _window_count(falling, w)[..., 1:] == w
    return pushed & fast & ahead_free & ahead_down & (s.index + 1 + w <= s.end)


def stick_rows(s: Rows, *, w: int, stick_speed: float) -> np.ndarray:
    """STICK: slip speed below ``stick_speed`` (``Thresholds.stick_floor``) with some normal force in the last
    window (rows k < w - 1: the window is rows 0..k)."""
    n, Fn = s.n, s.Fn
    c = np.zeros(Fn.shape[:-1] + (n + 1,), dtype=np.int64)
    np.cumsum(Fn > 0.0, axis=-1, out=c[..., 1:])
    touched = c[..., 1:] > 0
    if w <= n:
        touched[..., w - 1 :] = c[..., w:] > c[..., : n - w + 1]
    return (s.eta < stick_speed) & touched & (s.index < s.end)


def stop_jam_rows(
    s: Rows,
    th: Thresholds,
    *,
    has_stick: np.ndarray,
    k_stick: np.ndarray,
    m: int,
    stick_speed: float,
    alpha: float,
    radius: float,
    p_eff: np.ndarray,
    sF: np.ndarray,
) -> np.ndarray:
    """Compliant JAM: the first slip stop (``k_stick``), judged on its ``m`` rows before it (jam_contact_times contact
    times, ``Thresholds.stop_rows``).

    The rigid rule's one row becomes that look-back: its loaded slipping rows (eta at or above the STICK threshold,
    F_z >= jam_force, so that F_t / F_z is a friction direction and not the noise of a grazing row) reach the
    engine's own p_eff <= jam_p_eff (read at the capsule's contact point, ``radius`` below the tip), their mean force
    is jam_ratio times the slipping force -b/p_eff of the row of least p_eff (0 where p_eff <= 0: no slipping
    solution) and jam_ratio jam_force, and the slip speed fell by jam_slip_loss over the look-back.  It keeps the
    stop's row, so it only relabels the stop.  Writes the JAM's p_eff and normal impulse / timestep into ``p_eff``
    and ``sF`` at its row; returns the rows.
    """
    st, ct, eta, b, Fn, Fz, Fe = s.st, s.ct, s.eta, s.b, s.Fn, s.Fz, s.Fe
    stop_jam = np.zeros(p_eff.shape, dtype=bool)
    for idx in zip(*np.nonzero(np.atleast_1d(has_stick))):
        idx = idx if has_stick.ndim else ()
        j = int(k_stick[idx])
        a = max(0, j - m)
        if j == a:
            continue
        loaded = (eta[idx][a:j] >= stick_speed) & (Fz[idx][a:j] >= th.jam_force)
        if not loaded.any():
            continue
        # the row's own p_eff (eq. linode2 with its force), only on the look-back: inf where it carries no load
        st_a, ct_a, Fz_a = st[idx][a:j], ct[idx][a:j], Fz[idx][a:j]
        p_row = np.where(
            Fz_a > 0.0,
            1.0
            + alpha
            - alpha * st_a * st_a
            - alpha * (st_a + radius) * ct_a * Fe[idx][a:j] / np.where(Fz_a > 0.0, Fz_a, 1.0),
            np.inf,
        )
        pr = np.where(loaded, p_row, np.inf)
        i = int(np.argmin(pr))
        p_min = float(pr[i])
        slipping_force = max(0.0, -float(b[idx][a + i])) / p_min if p_min > 0.0 else 0.0
        Fn_rows = np.where(Fn[idx][a:j] > 0.0, Fn[idx][a:j], 0.0)
        Fmean = float(Fn_rows.mean())
        e0 = float(eta[idx][a])
        if (
            p_min <= th.jam_p_eff
            and Fmean >= th.jam_ratio * max(th.jam_force, slipping_force)
            and e0 - float(eta[idx][j]) >= th.jam_slip_loss * e0
        ):
            stop_jam[idx + (j,)] = True
            p_eff[idx + (j,)] = p_min
            sF[idx + (j,)] = float(Fn_rows.sum())
    return stop_jam


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
        has_div, k_div = _first(diverged_rows(R, s, th))
        jam, p_eff, sF = _jam_rows(R, s, th, mu=mu, alpha=alpha, w=w, rigid=rigid)
        has_jam, k_jam = _first(jam)
        has_lift, k_lift = _first(liftoff_rows(R, s, th, rigid=rigid))
        has_launch, k_launch = _first(launch_rows(R, s, th, w=w, timestep=timestep))
        held = held_at_rest(R, mu[..., 0], alpha, stick_speed)  # a start at rest sticks only if friction holds it
        has_stick, k_stick = _first(stick_rows(s, w=w, stick_speed=stick_speed) & held)
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
                has_jam, k_jam = _first(jam | stop_jam)

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
