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
      model_file: path of an alternative MJCF file with the same element
        names (default: the packaged ``rod.xml``).
    """

    timestep: float = 3e-4
    radius: float = 0.01
    timeconst: float = 0.06
    dampratio: float = 1.0
    friction_timeconst: float | None = None
    solimp: tuple[float, float, float, float, float] = (0.9, 0.95, 0.001, 0.5, 2.0)
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


def initial_state(model: mujoco.MjModel, rod: Rod, state: SlipState, radius: float) -> np.ndarray:
    """Full physics state (mjSTATE_FULLPHYSICS) of ``state`` with the capsule touching the plane.

    The tip A is put at (0, 0, r) so the capsule's lowest point C = A - r K is
    on the plane (dist = 0, no contact yet); velocities from
    ``crosscheck.coordinates.to_generalized``.  Returns an (nstate,) array.
    """
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, radius))
    data = mujoco.MjData(model)
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
      window: W, the averaging window (scaled time).  0.02 is ~6 ms for a 1 m
        rod: long enough to hold many spike-flight cycles at the default
        timestep (a cycle is ~10-100 steps), short against the O(1) time scale
        on which the rigid slipping state changes.  Never fewer than
        ``window_steps`` steps.
      window_steps: lower bound of W in steps, so that at coarse timesteps a
        window still averages several spikes.
      jam_force: JAM needs a window-mean normal force >= this [m g].  The
        rigid slipping force -b/p is O(1) except next to p = 0; chatter
        averages to it, so a mean of 4 m g is an impulsive force.
      jam_ratio: ... and >= this multiple of the window-mean rigid force
        max(0, -b/p) evaluated on MuJoCo's own states (taken as 0 where
        p <= 0: no slipping solution exists there): the force is not what
        slipping with Coulomb friction needs.
      jam_slip_loss: ... and the slip speed eta of the contact point falls by
        at least this fraction of its value within the window: the abrupt loss
        of slip speed of an impact without collision.  A rigid slipping rod
        loses speed at |eta'| = |Q1 F_z + A1| = O(1), i.e. a fraction
        O(W / eta) = O(0.02) per window.
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

    window: float = 0.02
    window_steps: int = 10
    jam_force: float = 4.0
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


def _window_mean(x: np.ndarray, w: int) -> np.ndarray:
    """Mean of x[..., k:k+w] for every k with a full window (NaN for the last w - 1 rows)."""
    c = np.concatenate([np.zeros(x.shape[:-1] + (1,)), np.cumsum(x, axis=-1)], axis=-1)
    out = np.full(x.shape, np.nan)
    n = x.shape[-1]
    if w <= n:
        out[..., : n - w + 1] = (c[..., w:] - c[..., : n - w + 1]) / w
    return out


def _consecutive(mask: np.ndarray, k: int) -> np.ndarray:
    """True at row i when mask[i:i+k] are all True."""
    m = mask.astype(float)
    return _window_mean(m, k) > 1.0 - 1e-12


class Classification(NamedTuple):
    """What ``classify`` returns; each field has the batch shape of the record.

    outcome: int8 ``Outcome`` values.
    event_time: scaled time of the first event (NaN for SLIP).
    exit_time: scaled time at which theta left (0, pi/2), the paper's domain
      (the rod lies flat or stands up; NaN if never).  Events are looked for
      only before it (a run that leaves first is SLIP, like the analytic
      ``slip_until_event``), except DIVERGED, which is never dropped.
    """

    outcome: np.ndarray
    event_time: np.ndarray
    exit_time: np.ndarray


def classify(record: Record, *, mu: float, alpha: float, timestep: float, thresholds: Thresholds | None = None) -> Classification:
    """Outcome and event time of recorded runs (the one classifier of ``simulate`` and the sweeps).

    Args:
      record: a ``Record`` with N rows, optionally batched (B, N).
      mu, alpha: friction coefficient and m l^2 / I0 of the run.
      timestep: scaled timestep omega dt (sets the window length in rows).
      thresholds: criteria (``Thresholds()`` by default; see there for why).

    Returns:
      ``Classification(outcome, event_time, exit_time)``.  The first event
      wins; on a tie DIVERGED > JAM > LIFTOFF > STICK.  A window that would
      reach past the end of the record (or past the domain exit) is not
      judged, so an event in the last W of the horizon can be missed.
    """
    th = thresholds or Thresholds()
    w = th.window_rows(timestep)
    t = record.t
    n = t.shape[-1]
    rows = np.arange(n)
    Fn = np.nan_to_num(record.normal_force, nan=0.0)
    eta = record.eta

    # DIVERGED: non-finite values, runaway speed, or a stopped clock (MuJoCo warning).
    finite = np.ones(t.shape, bool)
    for x in (record.tip_pos, record.tip_vel, record.tip_acc, record.force):
        finite &= np.isfinite(x).all(axis=-1)
    finite &= np.isfinite(t) & np.isfinite(record.Psi) & np.isfinite(record.Theta) & np.isfinite(record.theta)
    speed = np.linalg.norm(np.nan_to_num(record.tip_vel, nan=np.inf), axis=-1)
    stalled = np.zeros(t.shape, bool)
    stalled[..., 1:] = np.diff(t, axis=-1) <= 0.0
    bad = ~finite | (speed > th.diverged_speed) | stalled
    has_div, k_div = _first(bad)

    # Domain: theta in (0, pi/2).  Start rows of windows must end before the exit.
    with np.errstate(invalid="ignore"):
        inside = (record.theta > 0.0) & (record.theta < math.pi / 2)
    has_exit, k_exit = _first(~inside & finite)
    end = np.where(has_exit, k_exit, n)[..., None]

    # Rigid slipping force on MuJoCo's own states: max(0, -b/p) where p > 0.  Where
    # p <= 0 no slipping solution supplies a bounded force, so it counts as 0:
    # any impulsive force there is unexplained by slipping.
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        s, c = np.sin(record.theta), np.cos(record.theta)
        b = (record.Psi**2 * c**2 + record.Theta**2) * s - 1.0
        p = 1.0 + alpha + alpha * s * (mu * c * np.sin(record.varphi) - s)
        rigid = np.where(p > 0, np.maximum(0.0, -b / p), 0.0)
        Fbar = _window_mean(Fn, w)
        rigid_bar = _window_mean(rigid, w)
        eta_end = np.full(eta.shape, np.nan)
        eta_end[..., : n - w + 1] = eta[..., w - 1 :]
        loss = (eta - eta_end) / eta
        jam = (Fbar >= th.jam_force) & (Fbar >= th.jam_ratio * rigid_bar) & (loss >= th.jam_slip_loss)
    has_jam, k_jam = _first(jam & (rows + w <= end))

    # LIFTOFF: lift_steps force-free rows in a row with the tip accelerating upwards (b > 0).
    with np.errstate(invalid="ignore"):
        free_up = (Fn <= 0.0) & (record.tip_acc[..., 2] > 0.0)
    has_lift, k_lift = _first(_consecutive(free_up, th.lift_steps) & (rows + th.lift_steps <= end))

    # STICK: slip speed below stick_speed with some normal force in the last window.
    pushed = np.concatenate([np.zeros(Fn.shape[:-1] + (w - 1,)), (Fn > 0).astype(float)], axis=-1)
    touched = _window_mean(pushed, w)[..., :n] > 0
    with np.errstate(invalid="ignore"):
        slow = eta < th.stick_speed
    has_stick, k_stick = _first(slow & touched & (rows < end))

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

    return Classification(
        outcome=outcome,
        event_time=time_at(best_k, best_k != big),
        exit_time=time_at(k_exit, has_exit),
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
      record: the time series (``Record``, N rows).
      state, mu, alpha: the run's start and parameters.
      options, thresholds: MuJoCo parameters and outcome criteria used.
      horizon: scaled time simulated; nstep: steps taken.
    """

    outcome: Outcome
    event_time: float
    exit_time: float
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
    cls = classify(record, mu=mu, alpha=rod.alpha, timestep=opts.timestep, thresholds=th)
    return MujocoRun(
        outcome=Outcome(int(cls.outcome)),
        event_time=float(cls.event_time),
        exit_time=float(cls.exit_time),
        record=record,
        state=state,
        mu=mu,
        alpha=rod.alpha,
        options=opts,
        thresholds=th,
        horizon=horizon,
        nstep=nstep,
    )
