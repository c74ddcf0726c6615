"""The engine "mujoco_law": the rod under MuJoCo's contact law, integrated in continuous time (no timestep).

MuJoCo's model with the time discretisation removed: the generalised
accelerations are qacc = M^-1 (qfrc_smooth + J^T f) with f MuJoCo's
instantaneous contact force (``crosscheck.engines.mujoco.law``), and
y = (q, v) is integrated by scipy's DOP853 (rtol 1e-10 by default).  The
right-hand side is smooth inside each phase; the phases end at events,
located by the integrator and followed by a restart:

* contact start / end: the capsule's distance to the plane crosses 0
  (MuJoCo has the contact while dist < 0; the force jumps there, since
  aref = -B v is not 0 when the capsule arrives with a normal velocity);
* |dist| = width: the impedance d(dist) stops growing (solimp saturates),
  a kink of the force in the state;
* sliding on dist = 0: a slipping capsule that touches the plane with no
  normal speed meets a force that pushes it off (MuJoCo's elliptic cone
  raises f_n to carry the friction aref_t = -B v_t asks for) while gravity
  pulls it back; the motion is then Filippov's sliding mode on
  dist = dist' = 0 with the fraction lambda in [0, 1] of the law's force that
  holds dist'' = 0 (MuJoCo realises it as a chatter of contact and free
  steps).  It ends when lambda reaches 0 (lift-off) or 1 (the capsule sinks in).

The run starts as the MuJoCo engine's (``initial_state``: tip at z = r, the
capsule touching the plane with no normal speed) in the phase the motion
enters: free flight when the free dist'' >= 0 (eq. b's lift-off at C),
contact when the law's force still lets the capsule sink, sliding otherwise
(the usual start of a slipping rod).  The ``Options.timestep`` is only the spacing of the recorded
rows (t_k = k timestep, k = 0 .. ceil(horizon / timestep) - 1, as the MuJoCo
engine's rows), which the one classifier reads exactly as it reads MuJoCo's
(same friction time constant, not rigid).

Limits.  The contact is the A end cap's: once theta leaves (0, pi/2) (the
classifier's exit) MuJoCo's capsule can touch with its other end, which this
engine does not model.  Hops slower than ``GRAZING_SPEED`` are averaged into
the sliding mode.

Units: physical inside (the rod's SI, as MuJoCo's), scaled at the interface.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import MU, POSITIVE, Interval, check
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.base import Run, SweepResult, n_steps_within_memory, sweep_by_simulate
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.mujoco.law import Parameters, accelerations, contact_frame, smooth_accelerations
from crosscheck.engines.mujoco.options import Options
from crosscheck.engines.options import options_from_kwargs
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState, check_timestep_within

__all__ = ["NAME", "Trajectory", "integrate", "record", "simulate", "sweep", "RTOL", "ROW_BYTES"]

#: The engine's registry name.
NAME = "mujoco_law"
#: How messages name this engine.
LABEL = "MuJoCo's law in continuous time"

#: DOP853's relative tolerance; atol is RTOL times the state's scale (l, l omega, 1 rad, omega).
RTOL = 1e-10
RELATIVE_TOLERANCE = Interval(1e-13, 1e-3, lo_open=False, hi_open=False)

#: Bytes per recorded row (the Record's 25 doubles and the dense-output evaluation, 2x margin).
ROW_BYTES = 512

#: Most integrator restarts (contact events and impedance kinks) in one run: a chattering contact
#: that starts and ends more often than this is refused rather than integrated forever.
MAX_SEGMENTS = 100_000


class Trajectory:
    """The integrated run: state and contact force at the record times, and the events.

    Attributes: t (n,) physical times [s]; q, v, qacc (n, 5) physical; force (n, 3)
    contact frame [N]; frames (n, 3, 3) contact frames (rows n, t1, t2); active (n,) contact exists; events: list of
    (time [s], kind) with kinds "contact_start", "contact_end", "slide_start",
    "slide_end" (into contact), "lift_off" (from sliding), "impedance_saturates",
    "impedance_unsaturates"; nfev: right-hand-side evaluations.
    """

    def __init__(self, t, q, v, qacc, force, frames, active, events, nfev):
        self.t, self.q, self.v, self.qacc, self.force, self.frames, self.active = t, q, v, qacc, force, frames, active
        self.events, self.nfev = events, nfev


def _dist(rod: Rod, y, radius: float) -> float:
    return y[2] - rod.length * math.sin(y[4]) - radius


def _dist_acceleration(rod: Rod, y, qacc) -> float:
    """d^2 dist / dt^2 = Z'' - l cos(theta) theta'' + l sin(theta) theta'^2 (the dJ/dt v term included)."""
    return qacc[2] - rod.length * (math.cos(y[4]) * qacc[4] - math.sin(y[4]) * y[9] * y[9])


class _Phases:
    """The three right-hand sides: free flight, contact, and sliding on dist = 0 (see ``integrate``)."""

    def __init__(self, rod: Rod, mu: float, options: Options, tau: float, radius: float, feed_forward: bool = True):
        self.rod, self.mu, self.options, self.tau, self.radius = rod, mu, options, tau, radius
        self.parameters = Parameters.of(
            rod, options, feed_forward=feed_forward
        )  # the same at every evaluation: converted once

    def _accelerations(self, y, contact: bool):
        return accelerations(self.rod, y[:5], y[5:], self.mu, self.options, contact=contact, parameters=self.parameters)

    def evaluate(self, y, phase: str):
        """(qacc, contact-frame force [N], frame, lambda): lambda is the sliding mode's force fraction (1 in contact, 0 free)."""
        rod = self.rod
        if phase == "free":  # no contact problem to build: its qacc_smooth and frame alone, the same numbers
            return smooth_accelerations(rod, y[:5], y[5:]), np.zeros(3), contact_frame(y[3]), 0.0
        qacc, f, pb = self._accelerations(y, True)
        if phase != "slide":
            return qacc, f, pb.frame, float(phase == "contact")
        # Filippov: the force fraction lambda that keeps dist'' = -(2/tau) dist' - dist/tau^2 (0 on the exact solution,
        # and it pulls the integrator's drift back to dist = dist' = 0 over the time constant)
        free = _dist_acceleration(rod, y, pb.qacc_smooth)
        push = _dist_acceleration(rod, y, qacc) - free
        vn = y[7] - rod.length * math.cos(y[4]) * y[9]
        target = -2.0 / self.tau * vn - _dist(rod, y, self.radius) / self.tau**2
        lam = (target - free) / push if push > 0 else 0.0
        return pb.qacc_smooth + lam * (qacc - pb.qacc_smooth), lam * f, pb.frame, lam

    def rhs(self, phase: str):
        def rhs(t, y):
            return np.concatenate((y[5:], self.evaluate(y, phase)[0]))

        return rhs

    def grazing_phase(self, y) -> str:
        """The phase a state on dist = 0 with dist' = 0 enters: free if it falls off the plane's side by itself
        (free dist'' >= 0), contact if the contact law still lets it sink (dist'' <= 0 under the force), else sliding."""
        qacc, _, pb = self._accelerations(y, True)
        free = _dist_acceleration(self.rod, y, pb.qacc_smooth)
        if free >= 0:
            return "free"
        return "contact" if _dist_acceleration(self.rod, y, qacc) <= 0 else "slide"


#: Normal speed of the contact point [l omega] below which an arrival at, or departure from, dist = 0 enters the
#: sliding mode (when the law's force would push the capsule off while gravity pulls it back) instead of one more
#: hop.  A hopping capsule's hops shrink only algebraically (the contact's damping acts at second order in the hop
#: speed v: v -> v - c v^2, measured from 1e-3 to 3.5e-5 over 200 hops), so the exact sequence never ends; the
#: sliding mode is its average.  At 1e-4 a hop lasts ~2v/|dist''_free| ~ 4e-4 (one MuJoCo step at the default
#: timestep 3e-4, below which MuJoCo cannot resolve hops either) and rises ~1e-8 l; the sliding mode then pulls
#: dist, dist' back to 0 over the time constant (an excursion <= GRAZING_SPEED tau ~ 6e-6 l).
GRAZING_SPEED = 1e-4


def integrate(
    rod: Rod, q0, v0, mu: float, options: Options, *, times, rtol: float = RTOL, feed_forward: bool = True
) -> Trajectory:
    """Integrate MuJoCo's continuous-time dynamics from (q0, v0) [physical] and sample at ``times`` [s] (increasing, from 0).

    Phases: "free" (dist > 0, no force), "contact" (dist < 0, the law's force
    f) and "slide": on dist = 0 with dist' = 0 the law's force can push the
    capsule out (MuJoCo's elliptic cone raises f_n to carry the friction that
    aref_t = -B v_t asks for) while gravity pulls it back.  Then neither side
    can be followed and the motion is Filippov's sliding mode on the
    codimension-2 set dist = dist' = 0: the force is lambda f, lambda in [0, 1]
    the fraction that holds dist'' = 0.  MuJoCo's time-stepper realises it as
    a chatter of contact and free steps with a contact fraction -> lambda as
    dt -> 0.  Sliding ends when lambda reaches 0 (lift-off) or 1 (the capsule
    sinks in: contact).  ``feed_forward`` False: the law without its normal row's feed-forward
    (``crosscheck.engines.mujoco.law.contact_problem``).
    """
    par = Parameters.of(rod, options)
    width = par.solimp[2]
    l, w = rod.length, rod.omega
    scale = np.array([l, l, l, 1.0, 1.0, l * w, l * w, l * w, w, w])
    atol = rtol * scale
    times = np.asarray(times, dtype=float)
    t_end = float(times[-1])
    n = len(times)
    Q, V, QA, F = np.empty((n, 5)), np.empty((n, 5)), np.empty((n, 5)), np.zeros((n, 3))
    frames = np.empty((n, 3, 3))
    active = np.zeros(n, bool)
    events: list = []
    nfev = 0
    phases = _Phases(rod, mu, options, par.timeconst, par.radius, feed_forward)
    grazing = GRAZING_SPEED * l * w
    # the distance an event function must leave its start by: rounding of dist at a restart is ~1e-17 l
    nudge = 1e-14 * l

    def dist(t, y):
        return _dist(rod, y, par.radius)

    def normal_speed(y):
        return y[7] - l * math.cos(y[4]) * y[9]

    def fill(j, yj, phase):
        Q[j], V[j] = yj[:5], yj[5:]
        QA[j], F[j], frames[j], lam = phases.evaluate(yj, phase)
        active[j] = lam > 0

    y = np.concatenate((np.asarray(q0, float), np.asarray(v0, float)))
    t = 0.0
    d0 = dist(t, y)
    if d0 < -nudge:
        phase = "contact"
    elif d0 > nudge:
        phase = "free"
    else:
        vn = normal_speed(y)
        phase = "contact" if vn < -grazing else "free" if vn > grazing else phases.grazing_phase(y)
    saturated = abs(d0) >= width
    k = 0  # next record row
    for _ in range(MAX_SEGMENTS):
        start = dist(t, y)
        ev_list = _phase_events(phase, dist, start, phases, nudge=nudge, width=width, saturated=saturated)
        sol = solve_ivp(
            phases.rhs(phase), (t, t_end), y, method="DOP853", rtol=rtol, atol=atol, dense_output=True, events=ev_list
        )
        nfev += sol.nfev
        if sol.status < 0:
            raise RuntimeError(f"mujoco_law integration failed at t = {t * w:g} (scaled): {sol.message}")
        hits = [(te[0], i) for i, te in enumerate(sol.t_events) if len(te)] if sol.status == 1 else []
        t_stop, which = min(hits) if hits else (t_end, -1)
        # rows in [t, t_stop) belong to this segment (all the rest when it reached t_end)
        stop = int(np.searchsorted(times, t_stop, side="left")) if hits else n
        for j in range(k, stop):
            fill(j, sol.sol(times[j]), phase)
        k = stop
        if not hits:
            break
        y = sol.y_events[which][0]
        t = t_stop
        vn = normal_speed(y)
        phase, kind, saturated = _next_phase(phase, which, y, vn, phases, grazing=grazing, saturated=saturated)
        events.append((t, kind))
        if t >= t_end:
            break
    else:
        raise RuntimeError(
            f"mujoco_law: more than {MAX_SEGMENTS} contact events before t = {t * w:g} (scaled); the contact chatters"
        )
    for j in range(k, n):  # an event exactly at the end: the remaining rows are its state
        fill(j, y, phase)
    return Trajectory(times, Q, V, QA, F, frames, active, events, nfev)


def _phase_events(phase: str, dist, start: float, phases: _Phases, *, nudge: float, width: float, saturated: bool):
    """The terminal events that end ``phase`` (``integrate``'s phases) begun at dist = ``start`` [m]: the contact's
    end and its impedance's (un)saturation at dist = -width, the free flight's contact, the slide's lift-off
    (lambda = 0) and sink (lambda = 1).  ``dist(t, y)``: the capsule's distance; ``nudge`` [m]: how far an event
    function must leave its start."""
    if phase == "contact":
        top = max(start, 0.0) + nudge
        ev_end = lambda t, y, top=top: dist(t, y) - top  # noqa: E731
        ev_end.terminal, ev_end.direction = True, 1.0
        # the impedance saturates at dist = -width; the edge is nudged so the function starts on its side
        edge = max(-width, start + nudge) if saturated else min(-width, start - nudge)
        ev_sat = lambda t, y, edge=edge: edge - dist(t, y)  # noqa: E731
        ev_sat.terminal, ev_sat.direction = True, (-1.0 if saturated else 1.0)
        return [ev_end, ev_sat]
    elif phase == "free":
        bottom = min(start, 0.0) - nudge
        ev_start = lambda t, y, bottom=bottom: dist(t, y) - bottom  # noqa: E731
        ev_start.terminal, ev_start.direction = True, -1.0
        return [ev_start]
    else:
        ev_lift = lambda t, y: phases.evaluate(y, "slide")[3]  # noqa: E731
        ev_lift.terminal, ev_lift.direction = True, -1.0
        ev_sink = lambda t, y: phases.evaluate(y, "slide")[3] - 1.0  # noqa: E731
        ev_sink.terminal, ev_sink.direction = True, 1.0
        return [ev_lift, ev_sink]


def _next_phase(phase: str, which: int, y, vn: float, phases: _Phases, *, grazing: float, saturated: bool):
    """The phase after event ``which`` (its index in ``_phase_events``) of ``phase`` at the state y with normal speed
    vn [m/s]: returns (phase, the event's kind, whether the impedance is saturated)."""
    if phase == "contact" and which == 1:
        kind, saturated = ("impedance_unsaturates" if saturated else "impedance_saturates"), not saturated
    elif phase == "contact":  # dist' >= 0 here: the capsule leaves, unless the hop is small enough to average
        phase = "slide" if vn <= grazing and phases.grazing_phase(y) == "slide" else "free"
        kind = "contact_end" if phase == "free" else "slide_start"
    elif phase == "free":  # dist' <= 0 here: the capsule sinks in, unless the hop is small enough to average
        phase = "slide" if vn >= -grazing and phases.grazing_phase(y) == "slide" else "contact"
        kind = "contact_start" if phase == "contact" else "slide_start"
        saturated = False
    else:
        phase = "free" if which == 0 else "contact"
        kind = "lift_off" if which == 0 else "slide_end"
        saturated = False
    return phase, kind, saturated


def record(rod: Rod, traj: Trajectory, options: Options) -> Record:
    """The scaled, world-frame ``Record`` of a trajectory, field by field as the MuJoCo engine fills it."""
    l, w, g = rod.length, rod.omega, rod.gravity
    q, v = traj.q, traj.v
    psi, theta = q[:, 3], q[:, 4]
    sp, cp, st, ct = np.sin(psi), np.cos(psi), np.sin(theta), np.cos(theta)
    dpsi, dth = v[:, 3], v[:, 4]
    tip = np.stack((q[:, 0] + l * ct * sp, q[:, 1] - l * ct * cp, q[:, 2] - l * st), -1)
    tip_vel = np.stack(
        (
            v[:, 0] + l * (-st * sp * dth + ct * cp * dpsi),
            v[:, 1] + l * (st * cp * dth + ct * sp * dpsi),
            v[:, 2] - l * ct * dth,
        ),
        -1,
    )
    force = np.einsum("nij,ni->nj", traj.frames, traj.force)  # contact frame -> world [N]
    # tip acceleration: the second derivative of eq. tipfromcentre, A = S + l (ct sp, -ct cp, -st)
    a_psi, a_th = traj.qacc[:, 3], traj.qacc[:, 4]
    rate2 = dth * dth + dpsi * dpsi
    acc = np.stack(
        (
            traj.qacc[:, 0] + l * (-st * sp * a_th + ct * cp * a_psi - ct * sp * rate2 - 2 * st * cp * dth * dpsi),
            traj.qacc[:, 1] + l * (st * cp * a_th + ct * sp * a_psi + ct * cp * rate2 - 2 * st * sp * dth * dpsi),
            traj.qacc[:, 2] - l * ct * a_th + l * st * dth * dth,
        ),
        -1,
    )
    radius = options.radius
    Theta = dth / w
    slip = np.zeros((len(traj.t), 3))
    slip[:, 0] = tip_vel[:, 0] / (l * w) - radius * Theta * sp
    slip[:, 1] = tip_vel[:, 1] / (l * w) + radius * Theta * cp
    tip_acc = acc / g
    return Record(
        t=traj.t * w,
        tip_pos=tip / l,
        tip_vel=tip_vel / (l * w),
        tip_acc=tip_acc,
        force=force / rod.force_scale,
        normal_force=traj.force[:, 0] / rod.force_scale,
        active=traj.active.copy(),
        gap=tip[:, 2] / l - radius,
        slip_vel=slip,
        psi=psi.copy(),
        theta=theta.copy(),
        Psi=dpsi / w,
        Theta=Theta,
    )


def simulate(
    rod: Rod,
    state: SlipState,
    mu: float,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    rtol: float = RTOL,
    feed_forward: bool = True,
    **options,
) -> Run:
    """Run one slipping state under MuJoCo's contact law in continuous time and classify it.

    Args:
      rod: physical rod (``Rod.scaled(alpha)`` for the paper's units).
      state: the paper's scaled slipping state (tip at z = r, as MuJoCo's start).
      mu: friction coefficient >= 0.
      horizon: scaled time, > 0.
      thresholds: outcome criteria (``Thresholds()`` by default).
      rtol: DOP853's relative tolerance (default 1e-10).
      feed_forward: False for MuJoCo's law without its normal row's feed-forward of the rigid force (its solref
        spring-damper alone under MuJoCo's friction: ``crosscheck.engines.mujoco.law.contact_problem``).
      **options: the MuJoCo engine's scaled ``Options`` (timestep: record
        spacing only; radius, timeconst, dampratio, friction_timeconst,
        solimp; solver_tolerance is ignored: the law is solved exactly;
        model_file is refused: the law is rod.xml's).

    Returns:
      ``crosscheck.engines.Run`` (engine "mujoco_law").
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    horizon = float(check("horizon", horizon, POSITIVE))
    opts = options_from_kwargs(Options, options, LABEL)  # the options are MuJoCo's; the message names this engine
    if opts.model_file is not None:
        raise ValueError(
            f"model_file must be None for the mujoco_law engine (its law is rod.xml's); got {opts.model_file!r}"
        )
    check_timestep_within(opts.timestep, horizon)  # one step past the horizon records nothing to judge
    mu = float(check("mu", mu, MU))
    rtol = float(check("rtol", rtol, RELATIVE_TOLERANCE))
    if not isinstance(feed_forward, bool):
        raise ValueError(f"feed_forward must be True or False; got {feed_forward!r}")
    th = thresholds or Thresholds()
    nstep = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES, what="records")
    times = np.arange(nstep) * (opts.timestep / rod.omega)
    q0, v0 = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    traj = integrate(rod, q0, v0, mu, opts, times=times, rtol=rtol, feed_forward=feed_forward)
    rec = record(rod, traj, opts)
    c = classify(
        rec,
        mu=mu,
        alpha=rod.alpha,
        timestep=opts.timestep,
        friction_timeconst=opts.friction_time,
        contact_time=opts.contact_time,
        radius=opts.radius,
        thresholds=th,
    )
    return Run.from_classification(
        NAME, c, rec, state=state, mu=mu, alpha=rod.alpha, options=opts, thresholds=th, horizon=horizon, nstep=nstep
    )


def sweep(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    progress: bool | None = None,
    **options,
) -> SweepResult:
    """Every state through ``simulate`` (``sweep_by_simulate``)."""
    return sweep_by_simulate(
        get(NAME), rod, states, mu, horizon=horizon, thresholds=thresholds, progress=progress, **options
    )
