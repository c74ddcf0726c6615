"""Event-driven integration of the compliant rod: contact start and end, slip stop, stick break, each a mode switch.

The rod of ``crosscheck.engines.compliant.model`` is integrated mode by mode (free,
slipping, stuck) with scipy's implicit Radau method and the analytic stiff
Jacobian of ``Dynamics.jac``; each mode's right-hand side is smooth, and a
mode ends at a terminal event where the next mode begins (the events and
what each one does: ``crosscheck.engines.compliant.switches``).

The choice of Radau or BDF and the cost per state, measured: ``docs/compliant_trajectory.md``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import CONTACT_RADIUS, HORIZON, MU, RATE, Interval, check
from crosscheck.coordinates import paper_to_qv, qv_to_paper
from crosscheck.engines.compliant import laws as _laws
from crosscheck.engines.compliant.model import FREE, MODES, SLIP, STICK, Dynamics, q_from_y, y_from_qv
from crosscheck.engines.compliant.switches import EVENT_KINDS, Event, contact_mode, mode_events, switch
from crosscheck.engines.compliant.tolerances import COMPLIANT_INTEGRATION, SLIP_FLOOR
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = [
    "Segment",
    "Trajectory",
    "integrate",
    "start_state",
    "make_dynamics",
    "RADIUS",
    "GAP",
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
#: The stiff methods of ``solve_ivp`` this integrator accepts.
METHODS = ("Radau", "BDF")
#: At most this many mode segments per run: a stick-slip or contact chatter that switches more often is cut
#: off (reported as a "segments" event) rather than looping.
MAX_SEGMENTS = 20000


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
    atol_v = atol * np.array([1, 1, min(1.0, dyn.eps), 1, 1, 1, 1, 1, 1, 1])
    y = start_state(rod, state, dyn, gap=gap, gap_rate=gap_rate)
    path = _Path()
    mode, direction, y = _first_mode(dyn, y, gap_rate, path.events)
    below = y[2] < 0.0
    t = 0.0
    while t < horizon:
        if len(path.segments) >= MAX_SEGMENTS:
            path.events.append(Event(t, "segments", MODES[mode], MODES[mode]))
            break
        evs = mode_events(dyn, mode, below)
        sol = _solve(
            dyn, mode, direction, evs, (t, horizon), y, method=method, rtol=rtol, atol=atol_v, max_step=max_step
        )
        if sol.status != 1:  # the horizon (0) or a solver failure (-1)
            t1 = horizon if sol.status == 0 else float(sol.t[-1])
            path.add(Segment(t, t1, mode, direction, y.copy(), sol.sol, sol.nfev, sol.njev), sol.t, sol.y.T)
            if sol.status == -1:
                path.events.append(_failure(dyn, sol, mode, direction))
            break
        te, i = min((sol.t_events[i][0], i) for i in range(len(evs)) if len(sol.t_events[i]))
        ye = np.asarray(sol.y_events[i][0], dtype=float)
        kind = evs[i][1]
        keep = sol.t < te
        seg = Segment(t, float(te), mode, direction, y.copy(), sol.sol, sol.nfev, sol.njev)
        path.add(seg, np.append(sol.t[keep], te), np.vstack([sol.y.T[keep], ye]))
        t, y = float(te), ye
        direction = None
        if kind == "domain_exit":
            path.events.append(Event(t, kind, MODES[mode], MODES[mode]))
            break
        if kind == "above":
            below = False
            continue
        if kind == "contact_start" and not below and y[7] > 0.0:
            # a graze: the root of C's height lies where C already rises (the dense output dipped below the plane by
            # rounding), the law cannot push it, and entering contact would end it at once, over and over
            continue
        mode, direction, y, below, new = switch(dyn, kind, t, y, mode, below)
        path.events += new
        if any(ev.kind in stops for ev in new):
            break
    return path.trajectory(dyn, y, mode)


class _Path:
    """The solution as it grows: the segments, their rows (times, states, modes) and the events."""

    def __init__(self):
        self.segments: list[Segment] = []
        self.events: list[Event] = []
        self.T, self.Y, self.MODE = [], [], []

    def add(self, segment: Segment, t: np.ndarray, y: np.ndarray) -> None:
        """Append ``segment`` with its rows t (n,) and y (n, 10)."""
        self.segments.append(segment)
        self.T.append(t)
        self.Y.append(y)
        self.MODE.append(np.full(len(t), segment.mode))

    def trajectory(self, dyn: Dynamics, y, mode: int) -> Trajectory:
        """The ``Trajectory`` of the rows so far (the state y in ``mode`` alone if there are none)."""
        t_all = np.concatenate(self.T) if self.T else np.array([0.0])
        y_all = np.vstack(self.Y) if self.Y else y[None]
        mode_all = np.concatenate(self.MODE) if self.MODE else np.array([mode])
        q, v = q_from_y(y_all, dyn.radius)
        # F_n is the law's push in both contact modes (``Dynamics.force``'s third component), without the friction part
        Fn = np.array([dyn.push(yy) if mm != FREE else 0.0 for yy, mm in zip(y_all, mode_all)])
        slip_stop = next((ev.time for ev in self.events if ev.kind == "slip_stop"), math.nan)
        return Trajectory(
            t=t_all,
            q=q,
            v=v,
            mode=mode_all,
            normal_force=Fn,
            events=self.events,
            slip_stop_time=slip_stop,
            segments=self.segments,
            dynamics=dyn,
            nfev=sum(seg.nfev for seg in self.segments),
            njev=sum(seg.njev for seg in self.segments),
        )


def _solve(dyn: Dynamics, mode: int, direction, evs, span, y, **options):
    """``solve_ivp``'s dense solution of ``mode`` from y over the time span, ending at the first of the events ``evs``
    (``mode_events``); ``options``: method, rtol, atol, max_step."""
    return solve_ivp(
        lambda tt, yy: dyn.rhs(yy, mode, direction),
        span,
        y,
        jac=lambda tt, yy: dyn.jac(yy, mode, direction),
        events=[f for f, _ in evs],
        dense_output=True,
        **options,
    )


def _first_mode(dyn: Dynamics, y, gap_rate: float, events: list) -> tuple[int, np.ndarray | None, np.ndarray]:
    """The first mode at the start y: contact if the law pushes, or if it is zero (C on the plane at rest) and C's
    free normal acceleration is downwards (the rod sinks into the plane at once); free otherwise.  Returns (mode,
    direction, y) and appends a slip restart at t = 0 to ``events``."""
    push = dyn.push(y) if y[2] <= 0.0 else -1.0
    a_n = dyn.terms(y)[6][2]
    if push > 0.0 or (push == 0.0 and y[2] <= 0.0 and (gap_rate < 0.0 or (gap_rate == 0.0 and a_n <= 0.0))):
        mode, direction, y, extra = contact_mode(dyn, y)
        events += [Event(0.0, kind, "stick", "slip", y.copy(), direction) for kind in extra]
        return mode, direction, y
    return FREE, None, y


def _failure(dyn: Dynamics, sol, mode: int, direction) -> Event:
    """The solver_failure event at the end of the failed solution ``sol``, its reason the solver's message with the
    mode, C's slip speed and gap there, and the last step."""
    seg_t, y_end = sol.t, sol.y[:, -1]
    reason = (
        f"{sol.message} (mode {MODES[mode]}, C's slip speed {math.hypot(*dyn.slip(y_end)):.3g}, gap {y_end[2]:.3g}, "
        f"last step {seg_t[-1] - seg_t[-2] if len(seg_t) > 1 else math.nan:.3g})"
    )
    return Event(float(seg_t[-1]), "solver_failure", MODES[mode], MODES[mode], y_end.copy(), direction, reason)
