"""The compliant rod's mode switches: each mode's terminal events, and the mode and state after each event.

===============  ==========================================================
contact_start    free -> contact: the gap g of C crosses 0 downwards, or
                 (after a contact ended inside the plane) the law's push
                 crosses 0 upwards while g < 0.
contact_end      contact -> free: the push crosses 0 downwards (the law
                 would pull), or g crosses 0 upwards.
slip_stop        slip -> stick (or slip_restart): C's slip speed |s| falls
                 to ``SLIP_STOP.atol``.  The friction direction s/|s| is
                 singular at s = 0, so the stop is an event, never a
                 regularisation: the residual slip (1e-9) is removed by the
                 tangential impulse -G_tt^-1 s (kinetic energy change
                 -s.G_tt^-1 s/2 ~ 1e-18) and the stop time is the event time
                 plus the linear extrapolation |s| / |d|s|/dt|.
slip_restart     after a slip_stop whose stick force lies outside the cone
                 |F_t| <= mu F_n: the slip restarts at once in the direction
                 ``restart_direction``.
stick_break      stick -> slip: |F_t| reaches mu F_n; the slip restarts in
                 the direction of the tangential acceleration the cone
                 cannot cancel (``restart_direction``; friction is
                 continuous across the break).  C's residual slip of the
                 stick phase (the solver's error, ~atol) is removed first.
                 While |s| < ``SLIP_FLOOR.atol`` (half the slip-stop
                 speed) the friction direction is the current state's
                 self-consistent restart direction.  The floor lies strictly
                 below the slip-stop event: inside it the
                 friction direction does not turn with s, so one step may
                 carry a stopping slip through s = 0 to the far side unseen
                 by the event; there |s| rises inside the floor and falls
                 outside, and a floor at the event's speed would attract
                 from both sides, approached but never crossed (a solver
                 failure).  Below the event the far side's slip falls
                 through the event's speed where s/|s| is smooth.
domain_exit      theta leaves (0, pi/2) (M is singular at pi/2).
segments         more than ``MAX_SEGMENTS`` mode switches (a chatter): the
                 run ends there.
solver_failure   the solver failed (step size underflow): the run ends;
                 the event's ``reason`` is the solver's message with the
                 mode, C's slip speed and gap there.
===============  ==========================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from crosscheck.engines.compliant.model import FREE, MODES, SLIP, STICK, Dynamics, restart_direction
from crosscheck.engines.compliant.tolerances import SLIP_STOP
from crosscheck.tolerances import THETA_MARGIN

__all__ = [
    "EVENT_KINDS",
    "Event",
    "mode_events",
    "stick_holds",
    "remove_slip",
    "contact_mode",
    "slip_direction",
    "slip_rate",
    "switch",
]

#: Event kinds an ``Event`` may have (and ``stop_at`` may name).
EVENT_KINDS = (
    "contact_start",
    "contact_end",
    "slip_stop",
    "slip_restart",
    "stick_break",
    "domain_exit",
    "segments",
    "solver_failure",
)


@dataclass(frozen=True)
class Event:
    """A mode switch at scaled time ``time``: ``kind`` (``EVENT_KINDS``), the mode before and after it, and the
    state y (gap coordinates, ``crosscheck.engines.compliant.model``) and restart direction after it; ``reason`` says why a
    ``solver_failure`` happened (empty for the other kinds)."""

    time: float
    kind: str
    before: str
    after: str
    y: np.ndarray | None = field(default=None, repr=False, compare=False)
    direction: np.ndarray | None = field(default=None, repr=False, compare=False)
    reason: str = field(default="", compare=False)


def mode_events(dyn: Dynamics, mode: int, below: bool):
    """Terminal event functions of ``mode`` and the kind each one means."""
    margin = THETA_MARGIN.atol
    evs = []

    def add(fun, direction, kind):
        fun.terminal, fun.direction = True, direction
        evs.append((fun, kind))

    add(lambda t, y: y[4] - margin, -1, "domain_exit")
    add(lambda t, y: 0.5 * math.pi - margin - y[4], -1, "domain_exit")
    if mode == FREE:
        if below:
            # the law's push changes sign at delta = 0 too (delta (1 + (xi/eps) delta') and delta/eps^2 + (xi/eps) delta'
            # as C rises through the plane): only a push below the plane starts the contact ("above" takes the rest)
            add(lambda t, y: dyn.push(y) if y[2] < 0.0 else -1.0, +1, "contact_start")
            add(lambda t, y: y[2], +1, "above")
        else:
            add(lambda t, y: y[2], -1, "contact_start")
        return evs
    add(lambda t, y: dyn.push(y), -1, "contact_end")
    add(lambda t, y: y[2], +1, "contact_end")
    if mode == SLIP and dyn.mu > 0.0:
        add(lambda t, y: math.hypot(*dyn.slip(y)) - SLIP_STOP.atol, -1, "slip_stop")
    if mode == STICK:

        def cone(t, y):
            F = dyn.force(y, STICK)
            return dyn.mu * F[2] - math.hypot(F[0], F[1])

        add(cone, -1, "stick_break")
    return evs


def stick_holds(dyn: Dynamics, y) -> bool:
    """C at rest stays stuck: the stick force lies in the cone |F_t| <= mu F_n.

    As a contact closes F_n = 0 and the cone is a point; the test is then its
    limit F_n -> 0+ (the stick force per unit normal force,
    -G_tt^-1 (a_free_t / F_n + G_tn), in the cone of radius mu): C's free
    tangential acceleration must vanish (a rod at rest) and |G_tt^-1 G_tn| <= mu.
    """
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    Fn = dyn.push(y)
    if Fn > 0.0:
        Ft = -np.linalg.solve(G[:2, :2], a_free[:2] + G[:2, 2] * Fn)
        return math.hypot(Ft[0], Ft[1]) <= dyn.mu * Fn
    if math.hypot(a_free[0], a_free[1]) > 0.0:
        return False
    f = np.linalg.solve(G[:2, :2], G[:2, 2])
    return math.hypot(f[0], f[1]) <= dyn.mu


def remove_slip(dyn: Dynamics, y) -> np.ndarray:
    """y with C's residual tangential velocity s removed by the impulse -G_tt^-1 s (the least kinetic energy change)."""
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    s = J[:2] @ qd
    P = -np.linalg.solve(G[:2, :2], s)
    dq = MJt[:, :2] @ P
    y = y.copy()
    c = math.cos(y[4])
    y[5] += dq[0]
    y[6] += dq[1]
    y[8] += dq[3]
    y[9] += dq[4]
    y[7] += dq[2] - c * dq[4]
    return y


def contact_mode(dyn: Dynamics, y) -> tuple[int, np.ndarray | None, np.ndarray, list]:
    """The contact mode entered at y (slip, or stick if C is at rest and the cone holds); returns (mode, direction, y, extra events)."""
    s = dyn.slip(y)
    if dyn.mu == 0.0 or math.hypot(*s) > SLIP_STOP.atol:
        return SLIP, None, y, []
    y = remove_slip(dyn, y)
    if stick_holds(dyn, y):
        return STICK, None, y, []
    return SLIP, slip_direction(dyn, y), y, ["slip_restart"]


def slip_direction(dyn: Dynamics, y) -> np.ndarray:
    """The direction in which C at rest starts to slip (``restart_direction``); at F_n = 0 its limit F_n -> 0+:
    along C's free tangential acceleration if it has one, else the direction of the problem per unit normal force."""
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    Fn = dyn.push(y)
    if Fn > 0.0:
        return restart_direction(a_free[:2] + G[:2, 2] * Fn, G[:2, :2], dyn.mu * Fn)
    if math.hypot(a_free[0], a_free[1]) > 0.0:
        return restart_direction(a_free[:2], G[:2, :2], 0.0)
    return restart_direction(G[:2, 2], G[:2, :2], dyn.mu)


def slip_rate(dyn: Dynamics, y, mode: int) -> np.ndarray:
    """ds/dt of C's slip at y in ``mode`` (tangential acceleration of C)."""
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    F = dyn.force(y, mode)
    return a_free[:2] + G[:2] @ F


def switch(dyn: Dynamics, kind: str, t: float, y, mode: int, below: bool):
    """The mode after event ``kind`` at time t and state y (contact_start, contact_end, slip_stop or stick_break).

    Returns (mode, direction, y, below, events): the new mode, its restart direction (None but for a restarted
    slip), the state after the switch (C's residual slip removed where C comes to rest), whether C is below the
    plane, and the ``Event`` list of the switch (a slip_stop's time is extrapolated to |s| = 0).
    """
    before = MODES[mode]
    direction = None
    events: list[Event] = []
    if kind == "contact_start":
        mode, direction, y, extra = contact_mode(dyn, y)
        events.append(Event(t, kind, before, MODES[mode], y.copy(), direction))
        events += [Event(t, k, "stick", "slip", y.copy(), direction) for k in extra]
    elif kind == "contact_end":
        mode, below = FREE, y[2] < 0.0
        events.append(Event(t, kind, before, "free", y.copy()))
    elif kind == "slip_stop":
        # the stop itself: the event fired at |s| = SLIP_STOP.atol; add the time the slip still needs at its current rate
        rate = float(np.dot(dyn.slip(y), slip_rate(dyn, y, SLIP))) / max(math.hypot(*dyn.slip(y)), 1e-300)
        t_stop = t + (SLIP_STOP.atol / -rate if rate < 0.0 else 0.0)
        y = remove_slip(dyn, y)
        if stick_holds(dyn, y):
            mode = STICK
            events.append(Event(t_stop, kind, before, "stick", y.copy()))
        else:
            mode, direction = SLIP, slip_direction(dyn, y)
            events.append(Event(t_stop, kind, before, "slip", y.copy(), direction))
            events.append(Event(t_stop, "slip_restart", "stick", "slip", y.copy(), direction))
    elif kind == "stick_break":
        # the stick held C's slip at its value at the stop (0) up to the solver's error (~atol): remove that residual,
        # so the new slip grows from rest along the restart direction (a residual in another direction would turn
        # the friction direction s/|s| round while |s| ~ atol and chatter between slip stop and restart)
        y = remove_slip(dyn, y)
        mode, direction = SLIP, slip_direction(dyn, y)
        events.append(Event(t, kind, before, "slip", y.copy(), direction))
    return mode, direction, y, below, events
