"""The compliant rod as a contact engine: its ``Options`` and one run's ``Record`` at a fixed timestep, classified.

``simulate`` integrates the event-driven model (``crosscheck.engines.compliant.integrate``)
and samples it by the solver's dense output at t_k = k timestep, filling the
``Record`` every engine fills (scaled units, world frame): the tip A's
position, velocity and acceleration (gravity included), the contact force at
C and its normal part, whether the contact is active (a contact mode: the law
pushes), the gap and slip velocity of C, and the angles and rates.

Classifier settings (``crosscheck.engines.classifier.classify``):

* ``rigid=False``: the force builds up over the law's time scale eps (the
  contact oscillates at ~ sqrt(G_nn)/eps with G_nn in [1, 1 + alpha]), so a
  lift-off is judged over ``lift_steps`` force-free rows and a jam over a
  window, as for MuJoCo's soft contact;
* ``friction_timeconst=0``: the stick phase is exact (C's slip speed is
  held at 0 to the solver's tolerance, no creep), so the STICK threshold is
  the classifier's floor ``stick_speed`` (1e-2).  That floor does not fit
  an exact stick perfectly: it calls the run stuck when eta falls below
  1e-2, i.e. ~1e-2 / |eta'| early (|eta'| = O(mu F_z)), and would call a
  slow slip that swings round through small eta a STICK.  The classifier is
  shared, so we do not bend it; the trajectory's own ``slip_stop`` event
  (``integrate``) gives the exact stop time.
* JAM does not fit this model at eps >= 1e-3.  The compliant rod's impact
  without collision is not one impulsive window: from the rigid jam time
  (p = 0) the normal force grows over a time that shrinks slowly with eps
  (measured on one jamming state at mu = 1.6: the slip stops 0.026 after
  the rigid jam at eps = 1e-2, 0.0054 at eps = 1e-3: slope 0.69 from these
  two points; the report's compliant_limit section fits the lag), to
  peaks of 9-190 m g, and the slip stops.  Over the classifier's 0.05
  window the mean force (3.6 m g) stays below jam_ratio x the slipping
  force -b/p_eff (4.4 m g: large because p_eff ~ 0.2 there), so the run is
  classified STICK at the end of the impulse (0.031 against the rigid
  0.025).  The jam is visible in the trajectory instead: the first
  ``slip_stop`` event with its normal force (``Trajectory.after_slip_stop``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields

import numpy as np

from crosscheck.checks import HORIZON, check, check_timestep, check_timestep_within
from crosscheck.coordinates import tip_position, tip_velocity
from crosscheck.engines import get
from crosscheck.engines.base import Run, SweepResult, n_steps_within_memory, sweep_by_simulate
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.compliant import laws as _laws
from crosscheck.engines.compliant.model import FREE, SLIP, STICK, q_from_y
from crosscheck.engines.compliant.tolerances import COMPLIANT_INTEGRATION
from crosscheck.engines.compliant.trajectory import ATOL, METHODS, RADIUS, RTOL, integrate
from crosscheck.engines.options import EngineOptions
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["Options", "SolverStats", "simulate", "sweep", "record_of", "NAME"]

#: The engine's registry name.
NAME = "compliant"

#: Bytes per record row (13 fields, ~25 float64 columns, plus the classifier's temporaries): 1.5 x 25 x 8 x 4 copies.
ROW_BYTES = 1200


@dataclass(frozen=True)
class Options(EngineOptions):
    """Parameters of the compliant rod, in the paper's scaled units.

    Attributes:
      eps: the normal law's small parameter (stiffness 1/eps^2, damping
        xi/eps; the resting penetration is eps^2 F_z), > 0 (default 1e-2).
      xi: damping, >= 0 (default 1: near critical, xi_c = 2/sqrt(G_nn) in [1, 2] for alpha = 3).
      radius: capsule radius r / l in [0, 0.5) (default 0: contact at the tip A).
      law: the normal law's name (``crosscheck.engines.compliant.laws``).
      timestep: scaled time between record rows (default 1e-3); the
        integration itself is adaptive (dense output).
      method: "Radau" (default) or "BDF".
      rtol, atol: solver tolerances (``COMPLIANT_INTEGRATION``).
    """

    eps: float = 1e-2
    xi: float = 1.0
    radius: float = 0.0
    law: str = "kelvin-voigt"
    timestep: float = 1e-3
    method: str = "Radau"
    rtol: float = COMPLIANT_INTEGRATION.rtol
    atol: float = COMPLIANT_INTEGRATION.atol

    def __post_init__(self) -> None:
        object.__setattr__(self, "eps", float(check("eps", self.eps, _laws.EPS)))
        object.__setattr__(self, "xi", float(check("xi", self.xi, _laws.XI)))
        object.__setattr__(self, "radius", float(check("radius", self.radius, RADIUS)))
        _laws.get(self.law)
        object.__setattr__(self, "timestep", check_timestep(self.timestep))  # the floor every engine has (1e-12)
        object.__setattr__(self, "rtol", float(check("rtol", self.rtol, RTOL)))
        object.__setattr__(self, "atol", float(check("atol", self.atol, ATOL)))
        if self.method not in METHODS:
            raise ValueError(f"method must be one of {', '.join(METHODS)}; got {self.method!r}")

    LABEL = NAME  # the registry's label of this engine is its name

    @property
    def contact_time(self) -> float:
        """Time over which the normal force builds up: the law's time scale eps."""
        return self.eps

    @property
    def spring_time(self) -> float:
        """eps of the normal law delta / eps^2 (Kelvin-Voigt or Hunt & Crossley): the time through which a jam lags the
        rigid one by s* (eps^4 / (k |b|))^(1/5) (``crosscheck.theory.jam_lag``)."""
        return self.eps

    @property
    def friction_time(self) -> float:
        """The stick phase is exact (no creep): 0."""
        return 0.0


@dataclass(frozen=True)
class SolverStats:
    """Per-run statistics of the event-driven integration (``Run.solver``; scalars, so a sweep stacks them).

    steps: solver steps; nfev, njev: right-hand side and Jacobian evaluations;
    segments: mode segments; events: mode switches; slip_stops, stick_breaks,
    contact_ends: how many of each; slip_stop_time: the first slip stop (NaN if
    none); end_time: where the integration ended (the horizon, or a domain exit).
    """

    steps: int
    nfev: int
    njev: int
    segments: int
    events: int
    slip_stops: int
    stick_breaks: int
    contact_ends: int
    slip_stop_time: float
    end_time: float

    @classmethod
    def of(cls, traj) -> SolverStats:
        kinds = [e.kind for e in traj.events]
        return cls(
            steps=len(traj.t),
            nfev=int(traj.nfev),
            njev=int(traj.njev),
            segments=len(traj.segments),
            events=len(kinds),
            slip_stops=kinds.count("slip_stop"),
            stick_breaks=kinds.count("stick_break"),
            contact_ends=kinds.count("contact_end"),
            slip_stop_time=float(traj.slip_stop_time),
            end_time=float(traj.segments[-1].t1),
        )


def record_of(traj, times: np.ndarray) -> Record:
    """The ``Record`` of a ``Trajectory`` at ``times`` (scaled, world frame) by the segments' dense output.

    At a time shared by two segments (a mode switch) the later segment is used.
    """
    dyn = traj.dynamics
    n = len(times)
    Y = np.empty((n, 10))
    modes = np.zeros(n, dtype=int)
    dirs: list = [None] * n
    segs = traj.segments
    k0 = 0
    for j, seg in enumerate(segs):
        last = j == len(segs) - 1
        k1 = n if last else int(np.searchsorted(times, seg.t1, side="left"))
        if k1 > k0:
            tt = np.minimum(times[k0:k1], seg.t1)
            Y[k0:k1] = np.asarray(seg.sol(tt)).T
            modes[k0:k1] = seg.mode
            for k in range(k0, k1):
                dirs[k] = seg.direction
        k0 = max(k0, k1)
    force = np.zeros((n, 3))
    acc = np.empty((n, 3))
    slip = np.zeros((n, 3))
    for k in range(n):
        T = dyn.terms(
            Y[k]
        )  # once for the force, the tip's acceleration and the slip (``Dynamics.slip`` is J_t q' of the same terms)
        F = dyn.force(Y[k], int(modes[k]), dirs[k], T) if modes[k] != FREE else np.zeros(3)
        force[k] = F
        acc[k] = dyn.tip_acceleration(Y[k], F, T)
        slip[k, :2] = T[2][:2] @ T[4]
    rod = Rod.scaled(dyn.alpha)
    q, v = q_from_y(Y, dyn.radius)
    return Record(
        t=np.asarray(times, float),
        tip_pos=tip_position(rod, q),
        tip_vel=tip_velocity(rod, q, v),
        tip_acc=acc,
        force=force,
        normal_force=force[:, 2].copy(),
        active=np.isin(modes, (SLIP, STICK)),
        gap=Y[:, 2].copy(),
        slip_vel=slip,
        psi=Y[:, 3].copy(),
        theta=Y[:, 4].copy(),
        Psi=Y[:, 8].copy(),
        Theta=Y[:, 9].copy(),
    )


def simulate(
    rod: Rod,
    state: SlipState,
    mu: float,
    *,
    horizon: float,
    eps: float = Options.eps,
    xi: float = Options.xi,
    radius: float = 0.0,
    law: str = "kelvin-voigt",
    thresholds: Thresholds | None = None,
    **options,
) -> Run:
    """Run one slipping state with the compliant rod and classify its first event.

    The capsule starts touching the plane (z_A = r, the gap of C zero) with
    the velocities of ``state``, exactly as the MuJoCo engine's
    ``initial_state``; ``ceil(horizon / timestep)`` record rows at
    t_k = k timestep.  ``Run.solver`` holds the ``SolverStats`` (for the
    events and the dense output themselves, call ``integrate``).  Options:
    see ``Options``.
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    horizon = float(check("horizon", horizon, HORIZON))
    opts = Options.from_kwargs(dict(options, eps=eps, xi=xi, radius=radius, law=law))
    check_timestep_within(opts.timestep, horizon)
    th = thresholds or Thresholds()
    n = n_steps_within_memory(horizon, opts.timestep, ROW_BYTES)
    times = opts.timestep * np.arange(n)
    # integrate past the last row by one timestep so that every row lies inside the dense output
    traj = integrate(
        rod,
        state,
        mu,
        horizon=max(horizon, times[-1] + opts.timestep),
        eps=opts.eps,
        xi=opts.xi,
        radius=opts.radius,
        law=opts.law,
        method=opts.method,
        rtol=opts.rtol,
        atol=opts.atol,
    )
    end = traj.segments[-1].t1
    if end < times[-1]:
        # the run stopped early (theta left the domain): rows past the end are the last state, the classifier's exit rule sees theta
        times = np.minimum(times, end)
    record = record_of(traj, times)
    if end < opts.timestep * (n - 1):
        # rows past a domain exit hold the exit state with theta on the boundary it reached (0 or pi/2), so the
        # classifier's exit rule sees the exit; the clock keeps its fixed step
        past = opts.timestep * np.arange(n) > end
        theta = np.where(past, np.where(record.theta[-1] < 0.75, 0.0, 0.5 * np.pi), record.theta)
        record = Record(
            **{f.name: getattr(record, f.name) for f in fields(Record)}
            | {"t": opts.timestep * np.arange(n), "theta": theta}
        )
    c = classify(
        record,
        mu=float(mu),
        alpha=rod.alpha,
        timestep=opts.timestep,
        friction_timeconst=opts.friction_time,
        rigid=False,
        contact_time=opts.contact_time,
        radius=opts.radius,
        thresholds=th,
    )
    return Run.from_classification(
        NAME,
        c,
        record,
        state=state,
        mu=float(mu),
        alpha=rod.alpha,
        options=opts,
        thresholds=th,
        horizon=horizon,
        nstep=n,
        solver=SolverStats.of(traj),
    )


def sweep(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    progress: bool | None = None,
    workers: int = 1,
    **options,
) -> SweepResult:
    """Every state through ``simulate`` (``sweep_by_simulate``; ``workers`` forked processes)."""
    return sweep_by_simulate(
        get(NAME),
        rod,
        states,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        progress=progress,
        workers=workers,
        **options,
    )
