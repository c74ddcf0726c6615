"""The classifier's rules: for each event, the rows of a recorded run where its rule sees it (``classifier``).

``rows_of`` computes once what every rule reads from a ``Record`` (the slip speed, the normal force, eq. p and b
along the run, the rows before the domain exit); each rule is one function of those series: ``diverged_rows``,
``window_jam_rows``, ``impulse_jam_rows``, ``liftoff_rows``, ``launch_rows``, ``stick_rows`` (with
``held_at_rest``) and ``stop_jam_rows``.  The reasons and numbers behind each rule: ``crosscheck.engines.classifier``
and ``crosscheck.engines.thresholds``.  Scaled units (section 2.1).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from crosscheck.engines.record import Record
from crosscheck.engines.thresholds import Thresholds
from crosscheck.theory.sticking import stick_force

__all__ = [
    "Rows",
    "rows_of",
    "first_row",
    "window_sum",
    "window_count",
    "held_at_rest",
    "diverged_rows",
    "window_jam_rows",
    "impulse_jam_rows",
    "liftoff_rows",
    "launch_rows",
    "stick_rows",
    "stop_jam_rows",
]


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


def first_row(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def window_count(mask: np.ndarray, w: int) -> np.ndarray:
    """Number of True in mask[..., k:k+w] for each k with a full window: n - w + 1 values (n >= w).

    Integer prefix sums: the counts ``window_sum`` gives exactly, at a third of the cost of a float cumsum.
    """
    n = mask.shape[-1]
    c = np.zeros(mask.shape[:-1] + (n + 1,), dtype=np.int64)
    np.cumsum(mask, axis=-1, out=c[..., 1:])
    return c[..., w:] - c[..., : n - w + 1]


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
    has_exit, k_exit = first_row(~((theta > 0.0) & (theta < math.pi / 2)) & computed)
    has_cut, k_cut = first_row(~computed)
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
        run[..., : n - lift_steps + 1] = window_count(free_up, lift_steps) == lift_steps
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
        ahead_free[..., : n - w] = window_count(in_contact, w)[..., 1:] == 0
        ahead_down[..., : n - w] = window_count(falling, w)[..., 1:] == w
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
