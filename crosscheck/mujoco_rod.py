"""The rod in MuJoCo: build the model, run one slipping state, classify what happened.

The model is ``models/rod.xml`` (shipped as ``crosscheck/_models/rod.xml``):
a capsule on five joints (slide X, Y, Z; hinge psi about world z; hinge theta
about body x) so that q = (X, Y, Z, psi, theta) is exactly the generalised
coordinate vector of ``crosscheck.coordinates``.  Run parameters are applied
with ``mujoco.MjSpec``; see ``build_model``.

Geometry.  The capsule's end cap is centred on the tip A = (0, -l, 0) (body
frame), so the capsule touches the plane at C = A - r K, a radius below A.
A run starts with z_A = r: the capsule touches the plane with zero
penetration, and because MuJoCo keeps a contact only while dist < margin = 0,
the contact is not yet active at t = 0.  The tip velocity of the ``SlipState``
is given to A; the contact point C then slips with v_A + r theta' (-sin psi,
cos psi, 0), which differs from v_A only when Theta != 0 (by r |Theta|).

Units.  Everything this module takes and returns is in the paper's scaled units
(section 2.1): time in 1/omega, lengths in l, velocities in l omega,
accelerations in g, forces in m g; so are all the options (``timestep`` is
omega dt, ``radius`` is r / l, ...).  ``Rod`` supplies m, l, I0, g.
"""

from __future__ import annotations

import importlib.resources
import math
import os
from dataclasses import dataclass, field, fields
from typing import Any, NamedTuple

import mujoco
import numpy as np

from crosscheck.checks import ETA as NONNEGATIVE
from crosscheck.checks import FINITE, MU, POSITIVE, check
from crosscheck.coordinates import to_generalized
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = [
    "MODEL_FILE",
    "ModelFileError",
    "Options",
    "Thresholds",
    "SensorLayout",
    "Record",
    "MujocoRun",
    "model_path",
    "build_model",
    "initial_state",
    "record_from_sensordata",
    "Classification",
    "classify",
    "n_steps",
    "simulate",
    "capsule_tip_acceleration",
]

#: The model file inside the package (a symlink to ``models/`` in the repository).
MODEL_FILE = "rod.xml"


class ModelFileError(ValueError):
    """The MuJoCo model file is missing or MuJoCo cannot read it; the message names the file."""


def model_path() -> str:
    """Path of ``rod.xml`` as shipped with the package (``crosscheck/_models/rod.xml``)."""
    return str(importlib.resources.files("crosscheck") / "_models" / MODEL_FILE)


# --------------------------------------------------------------------------
# Options
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class Options:
    """MuJoCo parameters of a run, in the paper's scaled units.

    Attributes:
      timestep: omega dt (default 3e-4, i.e. ~1e-4 s for a 1 m rod under
        g = 9.81 m/s^2).
      radius: capsule radius r / l (default 0.01).
      timeconst: normal contact time constant omega tau of solref (default
        0.06, ~0.02 s for a 1 m rod: MuJoCo's default).  Must be >= 2
        timestep, else MuJoCo would silently raise it ("refsafe").
      dampratio: damping ratio of solref (default 1, critical).
      friction_timeconst: time constant of the friction directions only
        (solreffriction on the contact pair); None uses ``timeconst``.
      solimp: MuJoCo impedance (d0, dmax, width / l, midpoint, power);
        default MuJoCo's (0.9, 0.95, 0.001 m for l = 1 m, 0.5, 2).
      solver_tolerance: MuJoCo's solver tolerance (default 1e-10, as in
        rod.xml).  The Newton solver stops on it, so the contact force and the
        acceleration agree to ~5e-7 relative at 1e-10; 0 runs to
        ``iterations`` and gives ~1e-11 (used by the instantaneous check).
      model_file: path of an alternative MJCF file with the same element
        names (default: the packaged ``rod.xml``).
    """

    timestep: float = 3e-4
    radius: float = 0.01
    timeconst: float = 0.06
    dampratio: float = 1.0
    friction_timeconst: float | None = None
    solimp: tuple[float, float, float, float, float] = (0.9, 0.95, 0.001, 0.5, 2.0)
    solver_tolerance: float = 1e-10
    model_file: str | None = None

    def __post_init__(self) -> None:
        for name in ("timestep", "radius", "timeconst", "dampratio"):
            object.__setattr__(self, name, float(check(name, getattr(self, name), POSITIVE)))
        if self.friction_timeconst is not None:
            object.__setattr__(self, "friction_timeconst", float(check("friction_timeconst", self.friction_timeconst, POSITIVE)))
        for name in ("timeconst", "friction_timeconst"):
            tc = getattr(self, name)
            if tc is not None and tc < 2 * self.timestep:
                raise ValueError(f"{name} must be >= 2 timestep = {2 * self.timestep:g} (MuJoCo's refsafe); got {tc!r}")
        solimp = check("solimp", self.solimp, FINITE)
        if solimp.shape != (5,):
            raise ValueError(f"solimp must have 5 numbers (d0, dmax, width, midpoint, power); got {self.solimp!r}")
        if not (0 < solimp[0] < 1 and 0 < solimp[1] < 1 and solimp[2] > 0):
            raise ValueError(f"solimp must have 0 < d0, dmax < 1 and width > 0; got {tuple(solimp)!r}")
        object.__setattr__(self, "solimp", tuple(float(x) for x in solimp))
        object.__setattr__(self, "solver_tolerance", float(check("solver_tolerance", self.solver_tolerance, NONNEGATIVE)))
        if self.model_file is not None:
            object.__setattr__(self, "model_file", os.fspath(self.model_file))

    @classmethod
    def from_kwargs(cls, options: dict[str, Any]) -> "Options":
        """``Options(**options)`` with an error naming any unknown option."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(options) - known)
        if unknown:
            raise ValueError(f"unknown MuJoCo option {unknown[0]!r}; known options: {', '.join(sorted(known))}")
        return cls(**options)


# --------------------------------------------------------------------------
# Model
# --------------------------------------------------------------------------


def _load_spec(path: str) -> mujoco.MjSpec:
    if not os.path.isfile(path):
        raise ModelFileError(f"MuJoCo model file not found: {path}")
    try:
        spec = mujoco.MjSpec.from_file(path)
    except ValueError as e:
        raise ModelFileError(f"malformed MuJoCo model file {path}: {e}") from None
    return spec


#: Axial inertia of the slender rod relative to I0 (eq. inertia has 0; MuJoCo
#: needs > 0).  It only enters the psi inertia I0 cos^2 + eps sin^2.
AXIAL_INERTIA = 1e-12


def build_model(rod: Rod, mu: float, options: Options | None = None) -> mujoco.MjModel:
    """Compile ``rod.xml`` with the parameters of one run.

    Args:
      rod: mass m, tip-to-centre length l, inertia I0 (alpha = m l^2 / I0) and g.
      mu: Coulomb friction coefficient, >= 0.
      options: scaled MuJoCo parameters (``Options``; defaults if None).

    Raises:
      ModelFileError: the model file is missing, malformed, or lacks one of the
        named elements (body "rod", geom "rod", site "tip", pair "floor_rod").
      ValueError: mu out of range.
    """
    mu = float(check("mu", mu, MU))
    options = options or Options()
    path = options.model_file or model_path()
    spec = _load_spec(path)
    l, w = rod.length, rod.omega
    try:
        body, geom, site, pair = spec.body("rod"), spec.geom("rod"), spec.site("tip"), spec.pair("floor_rod")
    except (KeyError, ValueError):
        body = geom = site = pair = None
    if body is None or geom is None or site is None or pair is None:
        raise ModelFileError(f"MuJoCo model file {path} lacks body 'rod', geom 'rod', site 'tip' or pair 'floor_rod'")
    spec.option.timestep = options.timestep / w
    spec.option.tolerance = options.solver_tolerance
    spec.option.gravity = [0.0, 0.0, -rod.gravity]
    body.explicitinertial = True
    body.mass = rod.mass
    body.ipos = [0.0, 0.0, 0.0]
    body.inertia = [rod.inertia, AXIAL_INERTIA * rod.inertia, rod.inertia]
    geom.fromto = [0.0, -l, 0.0, 0.0, l, 0.0]
    geom.size = [options.radius * l, 0.0, 0.0]
    site.pos = [0.0, -l, 0.0]
    pair.friction = [mu, mu, pair.friction[2], pair.friction[3], pair.friction[4]]
    pair.solref = [options.timeconst / w, options.dampratio]
    pair.solreffriction = [0.0, 0.0] if options.friction_timeconst is None else [options.friction_timeconst / w, options.dampratio]
    d0, dmax, width, mid, power = options.solimp
    pair.solimp = [d0, dmax, width * l, mid, power]
    # The keyframe is the viewer's start pose for the file's own parameters.
    for key in list(spec.keys):
        spec.delete(key)
    try:
        return spec.compile()
    except ValueError as e:
        raise ModelFileError(f"MuJoCo cannot compile {path}: {e}") from None


def initial_state(model: mujoco.MjModel, rod: Rod, state: SlipState, radius: float, *, data: mujoco.MjData | None = None) -> np.ndarray:
    """Full physics state (mjSTATE_FULLPHYSICS) of ``state`` with the capsule touching the plane.

    The tip A is put at (0, 0, r) so the capsule's lowest point C = A - r K is
    on the plane (dist = 0, no contact yet); velocities from
    ``crosscheck.coordinates.to_generalized``.  Returns an (nstate,) array.
    ``data``: an ``MjData`` of ``model`` to reuse (its state is overwritten).
    """
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, radius))
    if data is None:
        data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    data.qpos[:] = q
    data.qvel[:] = v
    out = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(model, data, out, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    return out


# --------------------------------------------------------------------------
# Sensors -> record (scaled, world frame)
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class SensorLayout:
    """Where each named sensor of ``rod.xml`` sits in ``MjData.sensordata``.

    Built from the compiled model by name (``SensorLayout.from_model``), so a
    reordered or extended sensor list in the XML still reads correctly.  The
    contact sensor's fields follow its ``data`` attribute in MuJoCo's fixed
    order: found, force (3, contact frame), dist, normal (3, world), tangent
    (3, world), linvel (3, contact frame).
    """

    found: int
    force: slice
    dist: int
    normal: slice
    tangent: slice
    linvel: slice
    tip_pos: slice
    tip_vel: slice
    tip_acc: slice
    psi: int
    theta: int
    psi_dot: int
    theta_dot: int
    clock: int

    @classmethod
    def from_model(cls, model: mujoco.MjModel) -> "SensorLayout":
        def adr(name: str, dim: int) -> int:
            try:
                s = model.sensor(name)
            except KeyError:
                raise ModelFileError(f"MuJoCo model lacks the sensor {name!r}") from None
            if int(s.dim[0]) != dim:
                raise ModelFileError(f"sensor {name!r} has dimension {int(s.dim[0])}, expected {dim}")
            return int(s.adr[0])

        c = adr("contact", 14)
        three = {k: slice(adr(k, 3), adr(k, 3) + 3) for k in ("tip_pos", "tip_vel", "tip_acc")}
        return cls(
            found=c,
            force=slice(c + 1, c + 4),
            dist=c + 4,
            normal=slice(c + 5, c + 8),
            tangent=slice(c + 8, c + 11),
            linvel=slice(c + 11, c + 14),
            psi=adr("psi_pos", 1),
            theta=adr("theta_pos", 1),
            psi_dot=adr("psi_vel", 1),
            theta_dot=adr("theta_vel", 1),
            clock=adr("clock", 1),
            **three,
        )


@dataclass(frozen=True, eq=False)
class Record:
    """Time series of one run (or a batch: a leading (B,) axis), scaled units, world frame.

    Row k is what MuJoCo's sensors computed at the start of step k, i.e. at
    the state of time t[k] = k timestep (``mujoco.rollout`` copies
    ``sensordata`` after ``mj_step``, whose sensors were evaluated before the
    integration).

    Attributes (N rows; vectors have a trailing axis of 3):
      t: scaled time omega t.
      tip_pos: tip A / l.
      tip_vel: velocity of A / (l omega).
      tip_acc: acceleration of A / g (gravity included: MuJoCo's framelinacc
        reports a - g like an accelerometer, and g is added back).
      force: contact force on the rod / (m g), world frame.
      normal_force: its component along the contact normal (+z), / (m g).
      active: MuJoCo has a floor-rod contact (dist < 0) in this row.
      gap: height of the capsule's lowest point C = A - r K above the plane / l.
      slip_vel: horizontal velocity of the rod's material point at C / (l omega),
        v_A + r theta' (-sin psi, cos psi, 0) (z component 0).
      psi, theta: angles [rad]; Psi, Theta: rates / omega.
    """

    t: np.ndarray
    tip_pos: np.ndarray
    tip_vel: np.ndarray
    tip_acc: np.ndarray
    force: np.ndarray
    normal_force: np.ndarray
    active: np.ndarray
    gap: np.ndarray
    slip_vel: np.ndarray
    psi: np.ndarray
    theta: np.ndarray
    Psi: np.ndarray
    Theta: np.ndarray

    @property
    def eta(self) -> np.ndarray:
        """Scaled slip speed of the contact point C, |slip_vel|."""
        return np.hypot(self.slip_vel[..., 0], self.slip_vel[..., 1])

    @property
    def varphi(self) -> np.ndarray:
        """Relative slip angle beta - psi of C's velocity, wrapped to (-pi, pi]."""
        beta = np.arctan2(self.slip_vel[..., 1], self.slip_vel[..., 0])
        return np.angle(np.exp(1j * (beta - self.psi)))


def record_from_sensordata(sensordata: np.ndarray, layout: SensorLayout, rod: Rod, radius: float) -> Record:
    """Scaled, world-frame ``Record`` from raw ``sensordata`` of shape (..., N, nsensordata).

    ``radius`` is the scaled capsule radius r / l used for the run.
    """
    sd = np.asarray(sensordata, dtype=float)
    l, w, g = rod.length, rod.omega, rod.gravity
    f_c = sd[..., layout.force]
    normal = sd[..., layout.normal]
    tangent = sd[..., layout.tangent]
    bitangent = np.cross(normal, tangent)
    # contact frame -> world: rows of MuJoCo's contact frame are (normal, tangent, normal x tangent)
    force = (f_c[..., 0:1] * normal + f_c[..., 1:2] * tangent + f_c[..., 2:3] * bitangent) / rod.force_scale
    psi, theta = sd[..., layout.psi], sd[..., layout.theta]
    Psi, Theta = sd[..., layout.psi_dot] / w, sd[..., layout.theta_dot] / w
    tip_pos = sd[..., layout.tip_pos] / l
    tip_vel = sd[..., layout.tip_vel] / (l * w)
    tip_acc = sd[..., layout.tip_acc] / g
    tip_acc[..., 2] -= 1.0
    # velocity of the material point at C = A - r K: v_A + Omega x (-r K), Omega = theta' i + psi' K
    slip = tip_vel.copy()
    slip[..., 0] += -radius * Theta * np.sin(psi)
    slip[..., 1] += radius * Theta * np.cos(psi)
    slip[..., 2] = 0.0
    return Record(
        t=sd[..., layout.clock] * w,
        tip_pos=tip_pos,
        tip_vel=tip_vel,
        tip_acc=tip_acc,
        force=force,
        normal_force=f_c[..., 0] / rod.force_scale,
        active=sd[..., layout.found] > 0,
        gap=tip_pos[..., 2] - radius,
        slip_vel=slip,
        psi=psi,
        theta=theta,
        Psi=Psi,
        Theta=Theta,
    )


# --------------------------------------------------------------------------
# Outcome of a recorded run: the one classifier of simulate and the sweeps
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class Thresholds:
    """Quantitative criteria of ``classify``, in the paper's scaled units.

    MuJoCo's soft elliptic contact does not slip the way a rigid Coulomb
    contact does: while the tip slips it alternates between short normal-force
    spikes (several m g) and short flights (the contact chatters), and only
    the normal impulse averaged over a window matches the rigid F_z = -b/p
    (eq. FZ).  Every criterion therefore looks at windows or at signs that the
    chatter cannot fake.

    Attributes:
      window: W, the averaging window (scaled time).  A slipping soft
        contact cycles spike -> flight -> landing; measured cycle lengths are
        ~0.1 (timestep 3e-3, i.e. dt = 1e-3 s for a 1 m rod), ~0.04 (3e-4) and
        ~0.01 (3e-5).  W = 0.05 (16 ms for a 1 m rod) averages over whole
        cycles at the default timestep and finer, and is still short against
        the O(1) time on which the rigid slipping state changes.  W is never
        fewer than ``window_steps`` rows, which covers coarse timesteps
        (40 x 3e-3 = 0.12 > one cycle).  With W = 0.02 and 10 rows, landings of
        the chatter at dt = 1e-3 s were classified as jams below mu_P.
      window_steps: lower bound of W in rows (see ``window``).
      jam_force: JAM needs a window-mean normal force >= this [m g].  One
        m g, the weight: a slipping rod's window-mean force is the rigid
        -b/p = O(1) (below 1 unless b < -1 or p < 1), so this floor only
        rules out small forces whose ratio to a near-zero rigid force is big.
      jam_ratio: ... and >= this multiple of the window-mean rigid force
        max(0, -b/p) evaluated on MuJoCo's own states (taken as 0 where
        p <= 0: no slipping solution exists there): the force is not what
        slipping with Coulomb friction needs.
      jam_slip_loss: ... and the slip speed eta of the contact point falls by
        at least this fraction of its value within the window: the abrupt loss
        of slip speed of an impact without collision.  A rigid slipping rod
        loses speed at |eta'| = |Q1 F_z + A1| = O(1), i.e. a fraction
        O(W / eta) = O(0.05 / eta) per window.
      lift_steps: LIFTOFF needs this many consecutive rows with zero normal
        force and upward tip acceleration.  During a force-free row MuJoCo's
        tip acceleration is exactly the free acceleration b of eq. b, so an
        upward acceleration there is the paper's lift-off condition b > 0;
        chatter flights of a slipping tip have b < 0 and never qualify.  More
        than one row, because the first row after an inactive start is free
        even when the semi-implicit Euler step then closes the gap.
      stick_speed: STICK when the contact point's slip speed eta falls below
        this while the rod is in contact (some normal force in the last
        window).  MuJoCo's soft friction lets a stuck contact creep, so exact
        zero is never reached; the event time is late by at most
        stick_speed / |eta'| with |eta'| = O(mu F_z).
      diverged_speed: DIVERGED when the scaled tip speed exceeds this (energy
        is bounded: a slipping rod of the paper's ranges never exceeds O(10)),
        when any value is not finite, or when MuJoCo's clock stops advancing
        (``mujoco.rollout`` stops stepping after a MuJoCo warning and repeats
        the last row).
    """

    window: float = 0.05
    window_steps: int = 40
    jam_force: float = 1.0
    jam_ratio: float = 3.0
    jam_slip_loss: float = 0.2
    lift_steps: int = 3
    stick_speed: float = 1e-2
    diverged_speed: float = 1e3

    def window_rows(self, timestep: float) -> int:
        """Window length in rows for scaled timestep ``timestep``."""
        return max(int(self.window_steps), int(math.ceil(self.window / timestep - 1e-9)))


def _first(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(any, index of first True) along the last axis."""
    has = mask.any(axis=-1)
    return has, np.where(has, mask.argmax(axis=-1), -1)


def _window_sum(x: np.ndarray, w: int) -> np.ndarray:
    """Sum of x[..., k:k+w] for each k with a full window; NaN for the last w - 1 rows."""
    n = x.shape[-1]
    c = np.zeros(x.shape[:-1] + (n + 1,))
    np.cumsum(x, axis=-1, out=c[..., 1:])
    out = np.full(x.shape, np.nan)
    if w <= n:
        out[..., : n - w + 1] = c[..., w:] - c[..., : n - w + 1]
    return out


class Classification(NamedTuple):
    """What ``classify`` returns; each field has the batch shape of the sensordata.

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
    max_normal_force: largest normal force of one row [m g] (the spikes).
    max_window_force: largest window-mean normal force [m g] (JAM's statistic).
    active_fraction: fraction of rows in which MuJoCo had a contact.
    max_gap: largest height of the capsule's lowest point [l].
    """

    outcome: np.ndarray
    event_time: np.ndarray
    event_row: np.ndarray
    exit_time: np.ndarray
    diverged_time: np.ndarray
    max_normal_force: np.ndarray
    max_window_force: np.ndarray
    active_fraction: np.ndarray
    max_gap: np.ndarray


def classify(sensordata: np.ndarray, layout: SensorLayout, *, rod: Rod, mu, radius: float, timestep: float,
             thresholds: Thresholds | None = None) -> Classification:
    """Outcome and event time of recorded runs: the one classifier of ``simulate`` and the sweeps.

    Works on MuJoCo's raw sensor rows, so a sweep never builds full records.

    Args:
      sensordata: (..., N, nsensordata) rows as ``mujoco.rollout`` records them.
      layout: ``SensorLayout`` of the model.
      rod: the rod (scales and alpha).
      mu: friction coefficient, a scalar or one per run (the batch shape).
      radius: scaled capsule radius r / l.
      timestep: scaled timestep omega dt (sets the window length in rows).
      thresholds: criteria (``Thresholds()`` by default; see there for why).

    Returns:
      ``Classification``.  The first event wins; on a tie DIVERGED > JAM >
      LIFTOFF > STICK.  A window that would reach past the end of the record
      (or past the domain exit) is not judged, so an event in the last W of
      the horizon can be missed.
    """
    th = thresholds or Thresholds()
    w = th.window_rows(timestep)
    sd = np.asarray(sensordata, dtype=float)
    n = sd.shape[-2]
    rows = np.arange(n)
    cols = (layout.found, layout.force.start, layout.tip_pos.start + 2, layout.tip_vel.start, layout.tip_vel.start + 1,
            layout.tip_vel.start + 2, layout.tip_acc.start + 2, layout.psi, layout.theta, layout.psi_dot, layout.theta_dot, layout.clock)
    # one strided gather per column, then everything runs on contiguous (..., N) arrays
    X = np.empty((len(cols),) + sd.shape[:-1])
    for j, c in enumerate(cols):
        X[j] = sd[..., c]
    found, fn, z, vx, vy, vz, az, psi, theta, psi_dot, theta_dot, clock = X
    l, om, g = rod.length, rod.omega, rod.gravity
    alpha = rod.alpha
    mu = np.asarray(mu, dtype=float)[..., None]  # broadcast over rows
    lw = l * om
    t = clock * om
    Fn = fn / rod.force_scale
    Theta, Psi = theta_dot / om, psi_dot / om

    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        # DIVERGED: non-finite values (NaN fails every comparison), runaway speed,
        # or a stopped clock (mujoco.rollout repeats the last row after a warning).
        speed2 = (vx * vx + vy * vy + vz * vz) / (lw * lw)
        bad = ~(speed2 <= th.diverged_speed**2) | ~(np.abs(az) < 1e9 * g) | ~(np.abs(Fn) < np.inf) | ~(np.abs(theta) < np.inf)
        bad[..., 1:] |= ~(np.diff(clock, axis=-1) > 0.0)
        has_div, k_div = _first(bad)

        # Domain: theta in (0, pi/2).  Windows must end before the exit.
        has_exit, k_exit = _first(~((theta > 0.0) & (theta < math.pi / 2)))
        end = np.where(has_exit, k_exit, n)[..., None]

        # Slip velocity of the contact point C = A - r K: v_A + r theta' (-sin psi, cos psi).
        sp, cp = np.sin(psi), np.cos(psi)
        ux = vx / lw - radius * Theta * sp
        uy = vy / lw + radius * Theta * cp
        eta = np.hypot(ux, uy)
        sin_varphi = (uy * cp - ux * sp) / eta

        # Rigid slipping force on MuJoCo's own states, eqs. b, p, FZ: max(0, -b/p) where
        # p > 0.  Where p <= 0 no slipping solution supplies a bounded force, so it counts
        # as 0: any impulsive force there is unexplained by slipping.
        st, ct = np.sin(theta), np.cos(theta)
        b = (Psi * Psi * ct * ct + Theta * Theta) * st - 1.0
        p = 1.0 + alpha + alpha * st * (mu * ct * sin_varphi - st)
        rigid = np.where(p > 0.0, np.maximum(0.0, -b / p), 0.0)

        # JAM: impulsive window-mean force, beyond the rigid one, with an abrupt loss of slip speed.
        Fbar = _window_sum(Fn, w) / w
        rigid_bar = _window_sum(rigid, w) / w
        eta_end = np.full(eta.shape, np.nan)
        if w <= n:
            eta_end[..., : n - w + 1] = eta[..., w - 1 :]
        jam = (Fbar >= th.jam_force) & (Fbar >= th.jam_ratio * rigid_bar) & (eta - eta_end >= th.jam_slip_loss * eta)
        has_jam, k_jam = _first(jam & (rows + w <= end))

        # LIFTOFF: lift_steps force-free rows in a row with the tip accelerating upwards (b > 0).
        free_up = (Fn <= 0.0) & (az > g)  # framelinacc = a - g, so a_z > 0 <=> az > g
        run = _window_sum(free_up.astype(float), th.lift_steps) >= th.lift_steps - 0.5
        has_lift, k_lift = _first(run & (rows + th.lift_steps <= end))

        # STICK: slip speed below stick_speed with some normal force in the last window.
        c = np.zeros(Fn.shape[:-1] + (n + 1,))
        np.cumsum(Fn > 0.0, axis=-1, out=c[..., 1:])
        touched = (c[..., 1:] - c[..., np.maximum(rows - w + 1, 0)]) > 0.0
        has_stick, k_stick = _first((eta < th.stick_speed) & touched & (rows < end))

    big = np.iinfo(np.int64).max
    order = [  # precedence on ties: earlier in the list wins
        (Outcome.DIVERGED, has_div, k_div),
        (Outcome.JAM, has_jam, k_jam),
        (Outcome.LIFTOFF, has_lift, k_lift),
        (Outcome.STICK, has_stick, k_stick),
    ]
    best_k = np.full(has_div.shape, big, dtype=np.int64)
    outcome = np.full(has_div.shape, int(Outcome.SLIP), dtype=np.int8)
    for oc, has, k in order:
        better = has & (k < best_k)
        best_k = np.where(better, k, best_k)
        outcome = np.where(better, np.int8(oc), outcome)

    def time_at(k, has):
        idx = np.where(has, k, 0)
        tk = np.take_along_axis(t, np.asarray(idx)[..., None], axis=-1)[..., 0]
        return np.where(has, tk, np.nan)

    found_event = best_k != big
    with np.errstate(invalid="ignore"):
        return Classification(
            outcome=outcome,
            event_time=time_at(best_k, found_event),
            event_row=np.where(found_event, best_k, -1),
            exit_time=time_at(k_exit, has_exit),
            diverged_time=time_at(k_div, has_div),
            max_normal_force=np.nanmax(np.where(np.isfinite(Fn), Fn, np.nan), axis=-1) if n else np.nan,
            max_window_force=np.nanmax(Fbar, axis=-1) if n >= w else np.full(has_div.shape, np.nan),
            active_fraction=(found > 0).mean(axis=-1),
            max_gap=np.max(z / l - radius, axis=-1),
        )


# --------------------------------------------------------------------------
# One run
# --------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class MujocoRun:
    """Result of ``simulate``: the record, what happened first and when.

    Attributes:
      outcome: ``Outcome`` (SLIP, LIFTOFF, STICK, JAM or DIVERGED), decided by
        ``classify`` with ``thresholds``.
      event_time: scaled time of that event (NaN for SLIP).
      exit_time: scaled time theta left (0, pi/2) (NaN if never); see
        ``Classification``.
      diverged_time: scaled time the run diverged (NaN if never), even when
        another event came first.
      record: the time series (``Record``, N rows).
      state, mu, alpha: the run's start and parameters.
      options, thresholds: MuJoCo parameters and outcome criteria used.
      horizon: scaled time simulated; nstep: steps taken.
    """

    outcome: Outcome
    event_time: float
    exit_time: float
    diverged_time: float
    record: Record = field(repr=False)
    state: SlipState
    mu: float
    alpha: float
    options: Options
    thresholds: Thresholds
    horizon: float
    nstep: int


def n_steps(horizon: float, timestep: float) -> int:
    """Steps needed to cover ``horizon`` (both scaled): ceil(horizon / timestep), at least 1."""
    return max(1, int(math.ceil(horizon / timestep - 1e-9)))


def simulate(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds | None = None, **options) -> MujocoRun:
    """Run one slipping state in MuJoCo and classify its first event.

    The capsule starts touching the plane with no penetration and no contact
    (z_A = r), with the velocities of ``state`` (``crosscheck.coordinates``);
    MuJoCo steps ``ceil(horizon / timestep)`` times through ``mujoco.rollout``
    (the same path as ``crosscheck.mujoco_sweep.sweep``, so a state gives the
    same numbers either way).

    Args:
      rod: physical rod (``Rod.scaled(alpha)`` for the paper's units).
      state: the paper's scaled slipping state.
      mu: friction coefficient >= 0.
      horizon: scaled time to simulate, > 0.
      thresholds: outcome criteria (``Thresholds()`` by default).
      **options: scaled MuJoCo parameters, the fields of ``Options``:
        timestep, radius, timeconst, dampratio, friction_timeconst, solimp,
        model_file.  An unknown name raises ``ValueError`` naming it.

    Returns:
      ``MujocoRun`` with the record, outcome and event time.
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    horizon = float(check("horizon", horizon, POSITIVE))
    opts = Options.from_kwargs(options)
    mu = float(check("mu", mu, MU))
    th = thresholds or Thresholds()
    model = build_model(rod, mu, opts)
    layout = SensorLayout.from_model(model)
    x0 = initial_state(model, rod, state, opts.radius)
    nstep = n_steps(horizon, opts.timestep)
    from mujoco import rollout  # the rollout module imports its extension lazily

    _, sensordata = rollout.rollout(model, mujoco.MjData(model), x0[None], nstep=nstep)
    record = record_from_sensordata(sensordata[0], layout, rod, opts.radius)
    cls = classify(sensordata[0], layout, rod=rod, mu=mu, radius=opts.radius, timestep=opts.timestep, thresholds=th)
    return MujocoRun(
        outcome=Outcome(int(cls.outcome)),
        event_time=float(cls.event_time),
        exit_time=float(cls.exit_time),
        diverged_time=float(cls.diverged_time),
        record=record,
        state=state,
        mu=mu,
        alpha=rod.alpha,
        options=opts,
        thresholds=th,
        horizon=horizon,
        nstep=nstep,
    )


# --------------------------------------------------------------------------
# The analytic tip acceleration with the force at the capsule's contact point
# --------------------------------------------------------------------------


def capsule_tip_acceleration(rod: Rod, psi, theta, psi_dot, theta_dot, force, offset) -> np.ndarray:
    """Tip acceleration of eq. linode2 when the force acts a distance ``offset`` below A.

    The capsule touches the plane at P = A - offset K (offset = r for the lowest
    point of the cap; MuJoCo applies the force midway into the penetration,
    offset = r + dist / 2 with dist < 0).  Moving the force from A to P adds the
    torque (-offset K) x F = offset (F_y, -F_x, 0); its component on the theta
    axis i = (cos psi, sin psi, 0) is offset (F_y cos psi - F_x sin psi), its
    component on the psi axis K is 0, and the rest is carried by the joints
    (the rod has no axial rotation).  The extra theta'' = that torque / I0
    moves A by d(A - S)/d theta = l (-sin theta sin psi, sin theta cos psi,
    -cos theta).

    Args: as ``crosscheck.analytic.tip_acceleration`` (physical units, force
      (..., 3) world frame [N]), plus offset [m], broadcasting.

    Returns:
      (..., 3) tip accelerations [m/s^2], world frame, gravity included.
    """
    from crosscheck.analytic import tip_acceleration

    a = tip_acceleration(rod, psi, theta, psi_dot, theta_dot, force)
    f = np.asarray(force, dtype=float)
    psi, theta, offset = (np.asarray(x, dtype=float) for x in (psi, theta, offset))
    extra = offset * (f[..., 1] * np.cos(psi) - f[..., 0] * np.sin(psi)) / rod.inertia
    l = rod.length
    lever = np.stack(np.broadcast_arrays(-l * np.sin(theta) * np.sin(psi), l * np.sin(theta) * np.cos(psi), -l * np.cos(theta)), -1)
    return a + extra[..., None] * lever
