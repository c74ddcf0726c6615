"""Event-driven integration of the compliant rod: contact start and end, slip stop, stick break, each a mode switch.

The rod of ``crosscheck.engines.compliant.model`` is integrated mode by mode (free,
slipping, stuck) with scipy's implicit Radau method and the analytic stiff
Jacobian of ``Dynamics.jac``; each mode's right-hand side is smooth, and a
mode ends at a terminal event where the next mode begins:

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

The choice of Radau or BDF and the cost per state, measured: ``docs/compliant_trajectory.md``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import CONTACT_RADIUS, HORIZON, MU, RATE, Interval, check
from crosscheck.coordinates import paper_to_qv, qv_to_paper
from crosscheck.engines.compliant import laws as _laws
from crosscheck.engines.compliant.model import (
    FREE,
    MODES,
    SLIP,
    STICK,
    Dynamics,
    q_from_y,
    restart_direction,
    y_from_qv,
)
from crosscheck.engines.compliant.tolerances import COMPLIANT_INTEGRATION, SLIP_FLOOR, SLIP_STOP
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.tolerances import THETA_MARGIN

__all__ = [
    "Event",
    "Segment",
    "Trajectory",
    "integrate",
    "start_state",
    "make_dynamics",
    "RADIUS",
    "GAP",
    "EVENT_KINDS",
    "METHODS",
]

#: Capsule radius r / l: 0 is the tip A itself; at r >= l/2 the end cap reaches the centre of mass.
RADIUS = CONTACT_RADIUS
#: Initial gap of the contact point [l]: a contact start has C on or in the plane, and a penetration
#: deeper than l (the tip-to-centre distance) is no contact of this rod.
GAP = Interval(-1.0, 0.0, lo_open=False, hi_open=False)
#: Solver tolerances: below 1e-13 relative scipy's Radau works under its own rounding floor (it raises
#: rtol to 100 ulp and warns); looser than 1e-2 no event of the study is located.
RTOL = Interval(1e-13, 1e-2, lo_open=False, hi_open=False)
ATOL = Interval(1e-16, 1e-2, lo_open=False, hi_open=False)
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
#: The stiff methods of ``solve_ivp`` this integrator accepts.
METHODS = ("Radau", "BDF")
#: At most this many mode segments per run: a stick-slip or contact chatter that switches more often is cut
#: off (reported as a "segments" event) rather than looping.
MAX_SEGMENTS = 20000


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


@dataclass(frozen=True, eq=False)
class Segment:
    """One mode's stretch [t0, t1] with its dense output (over y, the gap coordinates)."""

    t0: float
    t1: float
    mode: int
    direction: np.ndarray | None
    y0: np.ndarray = field(repr=False)
    sol: object = field(repr=False)
    nfev: int = 0
    njev: int = 0


@dataclass(frozen=True, eq=False)
class Trajectory:
    """The event-driven solution of ``integrate``.

    Attributes:
      t: (n,) scaled times of the solver's steps (segment ends repeated).
      q, v: (n, 5) generalised coordinates and velocities (``crosscheck.coordinates``), scaled units.
      mode: (n,) int mode code (0 free, 1 slip, 2 stick) of each row.
      normal_force: (n,) F_n [m g].
      events: list of ``Event`` in time order.
      slip_stop_time: the first time C's slip stops (NaN if never).
      segments: the modes' dense outputs.
      dynamics: the ``Dynamics`` (model and parameters).
      nfev, njev: right-hand side and Jacobian evaluations.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    mode: np.ndarray
    normal_force: np.ndarray
    events: list
    slip_stop_time: float
    segments: list = field(repr=False)
    dynamics: Dynamics = field(repr=False)
    nfev: int = 0
    njev: int = 0

    def _segment(self, t: float) -> Segment:
        """The segment holding time t; at a switch (t the end of one and the start of the next) the later one."""
        for seg in self.segments:
            if t < seg.t1:
                return seg
        return self.segments[-1]

    def y_at(self, t: float) -> tuple[np.ndarray, Segment]:
        """State y (gap coordinates) and its segment at time t (the later segment at a switch)."""
        seg = self._segment(float(t))
        return np.asarray(seg.sol(float(t))), seg

    def state_at(self, t: float) -> dict:
        """The paper's variables at time t: theta, varphi, Theta, Psi, eta, psi, x, y, z, w of the tip A
        (``crosscheck.coordinates.qv_to_paper``), plus gap and gap_rate of C, C's slip speed eta_C and
        angle varphi_C, the normal force and the mode's name."""
        y, seg = self.y_at(t)
        return self._state(y, seg.mode, seg.direction)

    def _state(self, y, mode, direction) -> dict:
        dyn = self.dynamics
        q, v = q_from_y(y, dyn.radius)
        d = {k: float(x) for k, x in qv_to_paper(Rod.scaled(dyn.alpha), q, v).items()}
        s = dyn.slip(y)
        F = dyn.force(y, mode, direction)
        d.update(
            gap=float(y[2]),
            gap_rate=float(y[7]),
            eta_C=float(math.hypot(*s)),
            varphi_C=float(np.angle(np.exp(1j * (math.atan2(s[1], s[0]) - q[3])))),
            normal_force=float(F[2]),
            tangential_force=float(math.hypot(F[0], F[1])),
            mode=MODES[mode],
        )
        return d

    def after_slip_stop(self) -> dict | None:
        """The state just after the first slip stop (None if the slip never stops).

        Keys: time, Theta, Psi, theta, eta_C (0 after the residual slip is removed), varphi_C (the restart
        direction's angle relative to psi if the slip restarts, NaN if C stays stuck), w (normal velocity of C,
        i.e. gap_rate), gap, normal_force, mode ("stick" or "slip").
        """
        ev = next((e for e in self.events if e.kind == "slip_stop"), None)
        if ev is None:
            return None
        mode = STICK if ev.after == "stick" else SLIP
        d = self._state(ev.y, mode, ev.direction)
        varphi = (
            float(np.angle(np.exp(1j * (math.atan2(ev.direction[1], ev.direction[0]) - ev.y[3]))))
            if mode == SLIP
            else math.nan
        )
        return {
            "time": ev.time,
            "Theta": d["Theta"],
            "Psi": d["Psi"],
            "theta": d["theta"],
            "eta_C": d["eta_C"],
            "varphi_C": varphi,
            "w": d["gap_rate"],
            "gap": d["gap"],
            "normal_force": d["normal_force"],
            "mode": d["mode"],
        }

    def energy(self) -> np.ndarray:
        """(n,) total mechanical energy at the rows (``Dynamics.energy``)."""
        ys = y_from_qv(self.q, self.v, self.dynamics.radius)
        return np.array([self.dynamics.energy(y) for y in ys])


def _check_stop(stop_at) -> frozenset:
    if stop_at is None:
        return frozenset()
    kinds = frozenset([stop_at] if isinstance(stop_at, str) else stop_at)
    bad = sorted(kinds - set(EVENT_KINDS))
    if bad:
        raise ValueError(f"stop_at must be event kinds, each one of {', '.join(EVENT_KINDS)}; got {bad[0]!r}")
    return kinds


def make_dynamics(alpha: float, mu: float, *, eps: float, xi: float, radius: float, law) -> Dynamics:
    """Checked ``Dynamics``: each bad parameter one ValueError naming it and its range."""
    mu = float(check("mu", mu, MU))
    eps = float(check("eps", eps, _laws.EPS))
    xi = float(check("xi", xi, _laws.XI))
    radius = float(check("radius", radius, RADIUS))
    law = _laws.get(law)
    return Dynamics(alpha=float(alpha), mu=mu, eps=eps, xi=xi, radius=radius, law=law, slip_floor=SLIP_FLOOR.atol)


def _events(dyn: Dynamics, mode: int, below: bool):
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


def _stick_holds(dyn: Dynamics, y) -> bool:
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


def _remove_slip(dyn: Dynamics, y) -> np.ndarray:
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


def _contact_mode(dyn: Dynamics, y) -> tuple[int, np.ndarray | None, np.ndarray, list]:
    """The contact mode entered at y (slip, or stick if C is at rest and the cone holds); returns (mode, direction, y, extra events)."""
    s = dyn.slip(y)
    if dyn.mu == 0.0 or math.hypot(*s) > SLIP_STOP.atol:
        return SLIP, None, y, []
    y = _remove_slip(dyn, y)
    if _stick_holds(dyn, y):
        return STICK, None, y, []
    return SLIP, _direction(dyn, y), y, ["slip_restart"]


def _direction(dyn: Dynamics, y) -> np.ndarray:
    """The direction in which C at rest starts to slip (``restart_direction``); at F_n = 0 its limit F_n -> 0+:
    along C's free tangential acceleration if it has one, else the direction of the problem per unit normal force."""
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    Fn = dyn.push(y)
    if Fn > 0.0:
        return restart_direction(a_free[:2] + G[:2, 2] * Fn, G[:2, :2], dyn.mu * Fn)
    if math.hypot(a_free[0], a_free[1]) > 0.0:
        return restart_direction(a_free[:2], G[:2, :2], 0.0)
    return restart_direction(G[:2, 2], G[:2, :2], dyn.mu)


def start_state(rod: Rod, state: SlipState, dyn: Dynamics, *, gap: float, gap_rate: float) -> np.ndarray:
    """The integrator's state y of ``state`` with C at height ``gap`` and normal velocity ``gap_rate``.

    The tip A is at (0, 0, r + gap), as the MuJoCo engine's ``initial_state``
    puts it at (0, 0, r) (``crosscheck.coordinates.to_generalized`` with
    tip = (0, 0, radius)); the velocities are the tip's of ``state`` plus
    the normal velocity gap_rate (C's normal velocity equals A's).
    """
    q0, v0 = paper_to_qv(
        Rod.scaled(rod.alpha),
        state.theta,
        state.varphi,
        state.Theta,
        state.Psi,
        state.eta,
        state.psi,
        tip=(0.0, 0.0, dyn.radius + gap),
        w=gap_rate,
    )
    return y_from_qv(q0, v0, dyn.radius)


def integrate(
    rod: Rod,
    state: SlipState,
    mu: float,
    *,
    horizon: float,
    eps: float,
    xi: float,
    radius: float = 0.0,
    law="kelvin-voigt",
    gap: float = 0.0,
    gap_rate: float = 0.0,
    stop_at=None,
    method: str = "Radau",
    rtol: float | None = None,
    atol: float | None = None,
    max_step: float = math.inf,
) -> Trajectory:
    """Integrate the compliant rod from ``state`` to ``horizon`` (or a ``stop_at`` event).

    Args:
      rod: the rod (only alpha = m l^2 / I0 matters: everything is scaled).
      state: ``SlipState`` of the tip A (its velocity; C's slip velocity is
        v_A + r Theta (-sin psi, cos psi, 0)); the capsule touches the plane,
        z_A = r + gap (as the MuJoCo engine's ``initial_state`` with
        tip = (0, 0, radius)).
      mu: Coulomb friction coefficient, >= 0.
      horizon: scaled end time, > 0.
      eps: the law's small parameter (stiffness 1/eps^2, damping xi/eps), > 0.
      xi: damping, >= 0.
      radius: capsule radius r / l in [0, 0.5) (0: the contact is the tip A).
      law: a name of ``crosscheck.engines.compliant.laws`` ("kelvin-voigt" default).
      gap: initial gap of C [l], <= 0 (initial penetration -gap).
      gap_rate: initial normal velocity of C [l omega].
      stop_at: event kinds (``EVENT_KINDS``) that end the run.
      method: "Radau" (default) or "BDF".
      rtol, atol: solver tolerances (default ``COMPLIANT_INTEGRATION``); atol
        applies to O(1) states and is scaled by eps on the gap (see there).
      max_step: the solver's largest step.

    Returns:
      ``Trajectory``.
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    horizon = float(check("horizon", horizon, HORIZON))
    dyn = make_dynamics(rod.alpha, mu, eps=eps, xi=xi, radius=radius, law=law)
    gap = float(check("gap", gap, GAP))
    gap_rate = float(check("gap_rate", gap_rate, RATE))
    stops = _check_stop(stop_at)
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}; got {method!r}")
    rtol = float(check("rtol", COMPLIANT_INTEGRATION.rtol if rtol is None else rtol, RTOL))
    atol = float(check("atol", COMPLIANT_INTEGRATION.atol if atol is None else atol, ATOL))
    e = dyn.eps
    atol_v = atol * np.array([1, 1, min(1.0, e), 1, 1, 1, 1, 1, 1, 1])

    y = start_state(rod, state, dyn, gap=gap, gap_rate=gap_rate)
    events: list[Event] = []
    # the first mode: contact if the law pushes, or if it is zero (C on the plane at rest) and C's free normal acceleration
    # is downwards (the rod sinks into the plane at once); free otherwise
    push = dyn.push(y) if y[2] <= 0.0 else -1.0
    a_n = dyn.terms(y)[6][2]
    direction = None
    if push > 0.0 or (push == 0.0 and y[2] <= 0.0 and (gap_rate < 0.0 or (gap_rate == 0.0 and a_n <= 0.0))):
        mode, direction, y, extra = _contact_mode(dyn, y)
        for kind in extra:
            events.append(Event(0.0, kind, "stick", "slip", y.copy(), direction))
    else:
        mode = FREE
    below = y[2] < 0.0

    t = 0.0
    segments: list[Segment] = []
    T, Y, MODE = [], [], []
    slip_stop_time = math.nan
    nfev = njev = 0
    stop = False
    while t < horizon and not stop:
        if len(segments) >= MAX_SEGMENTS:
            events.append(Event(t, "segments", MODES[mode], MODES[mode]))
            break
        evs = _events(dyn, mode, below)
        m, dcur = mode, direction
        sol = solve_ivp(
            lambda tt, yy: dyn.rhs(yy, m, dcur),
            (t, horizon),
            y,
            method=method,
            rtol=rtol,
            atol=atol_v,
            jac=lambda tt, yy: dyn.jac(yy, m, dcur),
            events=[f for f, _ in evs],
            dense_output=True,
            max_step=max_step,
        )
        nfev += sol.nfev
        njev += sol.njev
        seg_t, seg_y = sol.t, sol.y.T
        if sol.status == -1:
            segments.append(Segment(t, float(seg_t[-1]), mode, direction, y.copy(), sol.sol, sol.nfev, sol.njev))
            T.append(seg_t), Y.append(seg_y), MODE.append(np.full(len(seg_t), mode))
            y_end = seg_y[-1]
            reason = (
                f"{sol.message} (mode {MODES[mode]}, C's slip speed {math.hypot(*dyn.slip(y_end)):.3g}, gap {y_end[2]:.3g}, "
                f"last step {seg_t[-1] - seg_t[-2] if len(seg_t) > 1 else math.nan:.3g})"
            )
            events.append(
                Event(float(seg_t[-1]), "solver_failure", MODES[mode], MODES[mode], y_end.copy(), direction, reason)
            )
            break
        if sol.status == 0:
            segments.append(Segment(t, horizon, mode, direction, y.copy(), sol.sol, sol.nfev, sol.njev))
            T.append(seg_t), Y.append(seg_y), MODE.append(np.full(len(seg_t), mode))
            t = horizon
            break
        fired = [(sol.t_events[i][0], i) for i in range(len(evs)) if len(sol.t_events[i])]
        te, i = min(fired)
        ye = np.asarray(sol.y_events[i][0], dtype=float)
        kind = evs[i][1]
        segments.append(Segment(t, float(te), mode, direction, y.copy(), sol.sol, sol.nfev, sol.njev))
        keep = seg_t < te
        (
            T.append(np.append(seg_t[keep], te)),
            Y.append(np.vstack([seg_y[keep], ye])),
            MODE.append(np.full(keep.sum() + 1, mode)),
        )
        t, y = float(te), ye
        before = MODES[mode]
        direction = None
        n_events = len(events)
        if kind == "domain_exit":
            events.append(Event(t, kind, before, before))
            break
        if kind == "above":
            below = False
            continue
        if kind == "contact_start" and not below and y[7] > 0.0:
            # a graze: the root of C's height lies where C already rises (the dense output dipped below the plane by
            # rounding), the law cannot push it, and entering contact would end it at once, over and over
            continue
        if kind == "contact_start":
            mode, direction, y, extra = _contact_mode(dyn, y)
            events.append(Event(t, kind, before, MODES[mode], y.copy(), direction))
            events += [Event(t, k, "stick", "slip", y.copy(), direction) for k in extra]
        elif kind == "contact_end":
            mode, below = FREE, y[2] < 0.0
            events.append(Event(t, kind, before, "free", y.copy()))
        elif kind == "slip_stop":
            # the stop itself: the event fired at |s| = SLIP_STOP.atol; add the time the slip still needs at its current rate
            rate = float(np.dot(dyn.slip(y), _slip_rate(dyn, y, SLIP))) / max(math.hypot(*dyn.slip(y)), 1e-300)
            t_stop = t + (SLIP_STOP.atol / -rate if rate < 0.0 else 0.0)
            y = _remove_slip(dyn, y)
            if math.isnan(slip_stop_time):
                slip_stop_time = t_stop
            if _stick_holds(dyn, y):
                mode = STICK
                events.append(Event(t_stop, kind, before, "stick", y.copy()))
            else:
                mode, direction = SLIP, _direction(dyn, y)
                events.append(Event(t_stop, kind, before, "slip", y.copy(), direction))
                events.append(Event(t_stop, "slip_restart", "stick", "slip", y.copy(), direction))
        elif kind == "stick_break":
            # the stick held C's slip at its value at the stop (0) up to the solver's error (~atol): remove that residual,
            # so the new slip grows from rest along the restart direction (a residual in another direction would turn
            # the friction direction s/|s| round while |s| ~ atol and chatter between slip stop and restart)
            y = _remove_slip(dyn, y)
            mode, direction = SLIP, _direction(dyn, y)
            events.append(Event(t, kind, before, "slip", y.copy(), direction))
        if any(ev.kind in stops for ev in events[n_events:]):
            stop = True
    t_all = np.concatenate(T) if T else np.array([0.0])
    y_all = np.vstack(Y) if Y else y[None]
    mode_all = np.concatenate(MODE) if MODE else np.array([mode])
    q, v = q_from_y(y_all, dyn.radius)
    # F_n is the law's push in both contact modes (``Dynamics.force``'s third component), without the friction part
    Fn = np.array([dyn.push(yy) if mm != FREE else 0.0 for yy, mm in zip(y_all, mode_all)])
    return Trajectory(
        t=t_all,
        q=q,
        v=v,
        mode=mode_all,
        normal_force=Fn,
        events=events,
        slip_stop_time=slip_stop_time,
        segments=segments,
        dynamics=dyn,
        nfev=nfev,
        njev=njev,
    )


def _slip_rate(dyn: Dynamics, y, mode: int) -> np.ndarray:
    """ds/dt of C's slip at y in ``mode`` (tangential acceleration of C)."""
    Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
    F = dyn.force(y, mode)
    return a_free[:2] + G[:2] @ F
