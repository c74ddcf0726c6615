"""The thin adapter: an engine written in SI units joins crosscheck by one function ``run(problem) -> Rows``.

An outside engine never sees the paper's scaled variables, ``Record`` or the classifier.  It receives a
``Problem``: the rod in SI units and its start, and returns ``Rows``: the rod's motion and the contact force per
row.  ``Adapted`` turns that function into what ``EngineSpec(engine=...)`` names (``Options``, ``simulate``,
``sweep``); crosscheck makes the ``Record``, classifies it and returns the ``Run``::

    import numpy as np
    from crosscheck.engines import adapter

    def run(p: adapter.Problem) -> adapter.Rows:
        q, v = np.empty((p.steps + 1, 5)), np.empty((p.steps + 1, 5))
        force, point = np.zeros((p.steps, 3)), np.full((p.steps, 3), np.nan)
        q[0], v[0] = p.q0, p.v0
        for k in range(p.steps):
            ...  # step your engine from (q[k], v[k]) over p.timestep; fill force[k], point[k], q[k + 1], v[k + 1]
        return adapter.Rows(q=q, v=v, force=force, point=point)

    ENGINE = adapter.Adapted(name="my_engine", run=run)

The rod (section 2 of the paper; ``models/rod.xml`` is the same rod for MuJoCo's viewer).  A uniform slender rod of
mass m and half-length l (``Problem.length``: the distance from the contact tip A to the centre of mass S), moment of
inertia I0 about S about any axis normal to the rod, zero about its axis; a capsule of radius r around the segment
from A to the other tip B.  Gravity g along -z of the world frame; the rough plane is z = 0 with friction coefficient
mu (Coulomb: |F_t| <= mu F_n).  The capsule's end cap is centred on A, so it touches the plane at C = A - r K (K = +z).

Coordinates (SI, world frame).  Chain (the 5 joints of ``models/rod.xml``): q = (x, y, z, psi, theta) [m, m, m,
rad, rad], (x, y, z) the centre of mass S, the body rotation Rz(psi) Rx(theta); v = dq/dt [m/s, rad/s].  The rod's
axis is the body y axis and A is at (0, -l, 0) in the body frame, so A = S + l (cos theta sin psi,
-cos theta cos psi, -sin theta).  Free body: pose = (x, y, z, qw, qx, qy, qz) (S and the unit quaternion of the same
rotation), twist = (vx, vy, vz, wx, wy, wz) (S's velocity and the angular velocity, both in the world frame).  A
free body's spin about its own axis has no counterpart in the chain and is dropped (its axial inertia is zero).

``Problem`` (input; all SI): mass [kg], length l [m], inertia I0 [kg m^2], radius r [m], mu [-], gravity g [m/s^2],
q0, v0 (5,) and pose0 (7,), twist0 (6,) (the same start both ways: the capsule touching the plane at C with
z_A = r, slipping), timestep [s], horizon [s], steps = ceil(horizon / timestep), and options (the engine's
``Options``, with its own fields as it declared them).

``Rows`` (output), k = 0 .. steps - 1 the rows, row k at time k timestep:
  q, v: (steps + 1, 5) chain states, row 0 the start and row k + 1 the state after step k; or pose (steps + 1, 7)
    and twist (steps + 1, 6) for a free body.  The tip's acceleration of row k is (v_A[k + 1] - v_A[k]) / timestep.
  force: (steps, 3) [N], the contact force of the plane on the rod during step k, world frame (an impulse / timestep
    for a time-stepper); zeros where there is no contact.
  point: (steps, 3) [m], where that force acts, world frame; NaN in the rows with no contact.  A row has a contact
    where ``point`` is finite.
  vdot: optional (steps, 5) chain accelerations [m/s^2, rad/s^2] at row k (gravity included); when given, the tip's
    acceleration comes from it (J v' + J' v) instead of the difference, and q, v may have ``steps`` rows.
  solver: optional, any frozen dataclass of integer statistics (``Run.solver``).
A run that fails leaves NaN in the rows after it: the classifier calls it DIVERGED.

``Options`` is the base of an adapted engine's options (scaled units, like every engine's): ``timestep`` omega dt,
``radius`` r / l; ``contact_time`` (the scaled time over which a compliant normal force builds up, 0 for an
impulse-based contact) and ``friction_time`` (0 unless friction builds up too) are properties to override, and a
contact whose normal force is a spring adds ``spring_time`` (its eps, the time whose square divides the penetration:
a jam is then allowed the lag ``crosscheck.theory.jam_lag`` gives it).  A subclass adds its own fields.  ``record_from_chain`` is the shared conversion into the ``Record``, which Drake and
Bullet use too.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from crosscheck.checks import Interval
from crosscheck.coordinates import tip_position, tip_velocity, to_generalized
from crosscheck.engines.base import (
    Run,
    SweepResult,
    n_steps_within_memory,
    options_from_kwargs,
    run_inputs,
    sweep_by_simulate,
)
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.record import Record, row_times
from crosscheck.rod import Rod
from crosscheck.state import SlipState, check_timestep, real_scalar

__all__ = [
    "Options",
    "Problem",
    "Rows",
    "Adapted",
    "record_from_chain",
    "tip_acceleration",
    "chain_from_free",
    "free_from_chain",
]

#: The capsule radius r / l an adapted engine takes: [0, 0.5) (0: the rod touches at its tip A; below half its length).
RADIUS = Interval(0.0, 0.5, lo_open=False, hi_open=True)

#: Bytes per row kept while a run is converted (states, forces, the Record and the classifier's temporaries).
ROW_BYTES = 1536


@dataclass(frozen=True, kw_only=True)
class Options:
    """Base options of an adapted engine (scaled units).  timestep: omega dt (> 0); radius: capsule radius r / l.
    A subclass sets the class attribute ``LABEL``, how messages name the engine (its label)."""

    timestep: float = 1e-3
    radius: float = 0.01

    def __post_init__(self) -> None:
        object.__setattr__(self, "timestep", check_timestep(self.timestep))
        object.__setattr__(self, "radius", real_scalar("radius", self.radius, RADIUS))

    @classmethod
    def from_kwargs(cls, options: dict[str, Any]):
        return options_from_kwargs(cls, options, getattr(cls, "LABEL", cls.__name__))

    @property
    def contact_time(self) -> float:
        """Scaled time over which the normal force builds up (0: an impulse within the step)."""
        return 0.0

    @property
    def friction_time(self) -> float:
        """Scaled friction time constant (0: friction follows the normal force at once)."""
        return 0.0


def free_from_chain(q, v) -> tuple[np.ndarray, np.ndarray]:
    """(pose (..., 7), twist (..., 6)) of chain states (q, v) (..., 5): the same rigid motion as a free body."""
    q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    psi, theta = q[..., 3], q[..., 4]
    ch, sh, cp, sp = np.cos(theta / 2), np.sin(theta / 2), np.cos(psi / 2), np.sin(psi / 2)
    quat = np.stack((cp * ch, cp * sh, sp * sh, sp * ch), -1)  # Rz(psi) Rx(theta) = qz(psi) qx(theta)
    # angular velocity: psi' K + theta' Rz(psi) i
    w = np.stack((v[..., 4] * np.cos(psi), v[..., 4] * np.sin(psi), v[..., 3]), -1)
    return np.concatenate((q[..., :3], quat), -1), np.concatenate((v[..., :3], w), -1)


def chain_from_free(pose, twist) -> tuple[np.ndarray, np.ndarray]:
    """Chain (q, v) (..., 5) of free-body states: psi, theta from the rod's axis, their rates from the angular velocity
    (its spin about the axis dropped)."""
    pose, twist = np.asarray(pose, dtype=float), np.asarray(twist, dtype=float)
    qw, qx, qy, qz = np.moveaxis(pose[..., 3:7] / np.linalg.norm(pose[..., 3:7], axis=-1, keepdims=True), -1, 0)
    # the rod's axis d = R e_y = (-sin psi cos theta, cos psi cos theta, sin theta)
    dx, dy, dz = 2 * (qx * qy - qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qw * qx)
    theta = np.arcsin(np.clip(dz, -1.0, 1.0))
    psi = np.arctan2(-dx, dy)
    wx, wy, wz = np.moveaxis(twist[..., 3:6], -1, 0)
    # omega = theta' e1 + psi' K + s d with e1 = Rz(psi) i, e2 = Rz(psi) j, d = cos theta e2 + sin theta K
    cp, sp = np.cos(psi), np.sin(psi)
    spin = (-sp * wx + cp * wy) / np.cos(theta)
    dtheta, dpsi = cp * wx + sp * wy, wz - spin * np.sin(theta)
    q = np.concatenate((pose[..., :3], np.stack((psi, theta), -1)), -1)
    v = np.concatenate((twist[..., :3], np.stack((dpsi, dtheta), -1)), -1)
    return q, v


def tip_acceleration(rod: Rod, q: np.ndarray, v: np.ndarray, vdot: np.ndarray) -> np.ndarray:
    """Acceleration of the tip A [m/s^2, world] from chain (q, v, v') (N, 5): J v' + J' v, the second derivative of
    eq. tipfromcentre (gravity included in v': a free rod's is b g along z)."""
    l = rod.length
    psi, theta = q[:, 3], q[:, 4]
    sp, cp, st, ct = np.sin(psi), np.cos(psi), np.sin(theta), np.cos(theta)
    dpsi, dth = v[:, 3], v[:, 4]
    a_psi, a_th = vdot[:, 3], vdot[:, 4]
    rate2 = dth * dth + dpsi * dpsi
    return np.stack(
        (
            vdot[:, 0] + l * (-st * sp * a_th + ct * cp * a_psi - ct * sp * rate2 - 2 * st * cp * dth * dpsi),
            vdot[:, 1] + l * (st * cp * a_th + ct * sp * a_psi + ct * cp * rate2 - 2 * st * sp * dth * dpsi),
            vdot[:, 2] - l * ct * a_th + l * st * dth * dth,
        ),
        -1,
    )


def record_from_chain(
    rod: Rod,
    q: np.ndarray,
    v: np.ndarray,
    force: np.ndarray,
    active: np.ndarray,
    *,
    timestep: float,
    radius: float,
    vdot: np.ndarray | None = None,
    computed: int | None = None,
) -> Record:
    """The scaled, world-frame ``Record`` of n rows from chain states in SI (the one conversion every chain engine uses).

    q, v: (n + 1, 5) states (row k + 1 after step k), or (n, 5) with ``vdot``; force: (n, 3) [N] on the rod, world;
    active: (n,) rows with a contact; timestep: omega dt (scaled); radius: r / l; vdot: (n, 5) chain accelerations
    (tip_acc = J v' + J' v) or None (tip_acc = (v_A,k+1 - v_A,k) / dt); computed: rows computed (later ones NaN).
    The contact point's gap and slip are those of the capsule's lowest point C = A - r K.
    """
    n = len(active)
    L, w, g = rod.length, rod.omega, rod.gravity
    if vdot is None:
        pos = tip_position(rod, q)  # (n + 1, 3) [m]
        vel = tip_velocity(rod, q, v)  # [m/s]
        acc = (vel[1 : n + 1] - vel[:n]) / (timestep / w * g)  # [g], gravity included
    else:
        q, v = q[:n], v[:n]
        pos, vel = tip_position(rod, q), tip_velocity(rod, q, v)
        acc = tip_acceleration(rod, q, v, vdot) / g
    psi, theta = np.ascontiguousarray(q[:n, 3]), np.ascontiguousarray(q[:n, 4])
    Psi, Theta = v[:n, 3] / w, v[:n, 4] / w
    tip_pos, tip_vel = pos[:n] / L, vel[:n] / (L * w)
    force = np.asarray(force, dtype=float) / rod.force_scale
    # the material point of the capsule at C = A - r K: v_A + Omega x (-r K), Omega = theta' i + psi' K
    r = radius
    slip = np.zeros((n, 3))
    slip[:, 0] = tip_vel[:, 0] - r * Theta * np.sin(psi)
    slip[:, 1] = tip_vel[:, 1] + r * Theta * np.cos(psi)
    return Record(
        t=row_times(n, timestep, computed),
        tip_pos=tip_pos,
        tip_vel=tip_vel,
        tip_acc=acc,
        force=force,
        normal_force=force[:, 2].copy(),
        active=np.asarray(active, dtype=bool).copy(),
        gap=tip_pos[:, 2] - r,
        slip_vel=slip,
        psi=psi,
        theta=theta,
        Psi=Psi,
        Theta=Theta,
    )


@dataclass(frozen=True, kw_only=True)
class Problem:
    """One run for an SI engine (module docstring: the rod, the coordinates, the units)."""

    mass: float
    length: float
    inertia: float
    radius: float
    mu: float
    gravity: float
    q0: np.ndarray
    v0: np.ndarray
    timestep: float
    horizon: float
    steps: int
    options: Any

    @property
    def pose0(self) -> np.ndarray:
        """The start as a free body's pose (x, y, z, qw, qx, qy, qz) [m, -]."""
        return free_from_chain(self.q0, self.v0)[0]

    @property
    def twist0(self) -> np.ndarray:
        """The start as a free body's twist (vx, vy, vz, wx, wy, wz) [m/s, rad/s], world frame."""
        return free_from_chain(self.q0, self.v0)[1]


@dataclass(frozen=True, kw_only=True)
class Rows:
    """What an SI engine returns (module docstring): chain (q, v) or free-body (pose, twist), force, point, vdot."""

    force: np.ndarray
    point: np.ndarray
    q: np.ndarray | None = None
    v: np.ndarray | None = None
    pose: np.ndarray | None = None
    twist: np.ndarray | None = None
    vdot: np.ndarray | None = None
    solver: Any = None

    def chain(self) -> tuple[np.ndarray, np.ndarray]:
        """(q, v) as chain coordinates."""
        if self.q is not None and self.v is not None:
            return np.asarray(self.q, dtype=float), np.asarray(self.v, dtype=float)
        if self.pose is not None and self.twist is not None:
            return chain_from_free(self.pose, self.twist)
        raise ValueError("Rows needs q and v (chain) or pose and twist (free body)")


def _checked(name: str, rows: Rows, steps: int) -> tuple[np.ndarray, ...]:
    """(q, v, force, point) of an engine's rows, their shapes checked (one ValueError line naming the wrong one)."""
    q, v = rows.chain()
    force, point = np.asarray(rows.force, dtype=float), np.asarray(rows.point, dtype=float)
    states = (steps,) if rows.vdot is not None else ()
    for what, x, want in (("force", force, [(steps, 3)]), ("point", point, [(steps, 3)])):
        if x.shape not in want:
            raise ValueError(f"engine {name!r} returned {what} of shape {x.shape}; it must be {want[0]}")
    for what, x in (("q", q), ("v", v)):
        if x.shape not in [(steps + 1, 5)] + [(s, 5) for s in states]:
            raise ValueError(f"engine {name!r} returned {what} of shape {x.shape}; it must be ({steps + 1}, 5)")
    if rows.vdot is not None and np.shape(rows.vdot) != (steps, 5):
        raise ValueError(f"engine {name!r} returned vdot of shape {np.shape(rows.vdot)}; it must be ({steps}, 5)")
    return q, v, force, point


@dataclass(frozen=True)
class Adapted:
    """An SI engine as crosscheck runs it: what ``EngineSpec(engine=...)`` names.

    name: the engine's registry name (the ``Run.engine`` of its runs); run: ``run(Problem) -> Rows``, module-level so
    that sweeps can run it in worker processes; Options: its options, a subclass of ``adapter.Options``.
    """

    name: str
    run: Callable[[Problem], Rows]
    Options: type = Options

    def problem(self, rod: Rod, state: SlipState, mu: float, horizon: float, opts) -> Problem:
        """The SI ``Problem`` of a scaled run: the capsule touching the plane (z_A = r) with the state's velocities."""
        q0, v0 = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
        w = rod.omega
        return Problem(
            mass=rod.mass,
            length=rod.length,
            inertia=rod.inertia,
            radius=opts.radius * rod.length,
            mu=mu,
            gravity=rod.gravity,
            q0=q0,
            v0=v0,
            timestep=opts.timestep / w,
            horizon=horizon / w,
            steps=n_steps_within_memory(horizon, opts.timestep, ROW_BYTES),
            options=opts,
        )

    def simulate(
        self, rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds | None = None, **options
    ) -> Run:
        """One run: the engine's ``run`` on the SI problem, its rows as a ``Record``, classified (``Engine.simulate``)."""
        mu, horizon, opts = run_inputs(state, mu, horizon, options, self.Options)
        th = thresholds or Thresholds()
        p = self.problem(rod, state, mu, horizon, opts)
        rows = self.run(p)
        q, v, force, point = _checked(self.name, rows, p.steps)
        active = np.isfinite(point).all(axis=-1)
        record = record_from_chain(rod, q, v, force, active, timestep=opts.timestep, radius=opts.radius, vdot=rows.vdot)
        c = classify(
            record,
            mu=mu,
            alpha=rod.alpha,
            timestep=opts.timestep,
            friction_timeconst=opts.friction_time,
            rigid=opts.contact_time == 0.0,
            contact_time=opts.contact_time,
            radius=opts.radius,
            thresholds=th,
        )
        run = Run.from_classification(
            self.name,
            c,
            record,
            state=state,
            mu=mu,
            alpha=rod.alpha,
            options=opts,
            thresholds=th,
            horizon=horizon,
            nstep=p.steps,
        )
        return replace(run, solver=rows.solver) if rows.solver is not None else run

    def sweep(
        self,
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
        """Every state through ``simulate`` (``sweep_by_simulate``), on ``workers`` processes."""
        return sweep_by_simulate(
            self, rod, states, mu, horizon=horizon, thresholds=thresholds, progress=progress, workers=workers, **options
        )
