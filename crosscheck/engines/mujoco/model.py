"""The MJCF rod model: compile ``models/rod.xml`` with a run's parameters, place a slipping state, read its sensors.

The model is ``models/rod.xml`` (shipped as ``crosscheck/_models/rod.xml``):
a capsule on five joints (slide X, Y, Z; hinge psi about world z; hinge theta
about body x) so that q = (X, Y, Z, psi, theta) is exactly the generalised
coordinate vector of ``crosscheck.coordinates``.  Run parameters are applied
with ``mujoco.MjSpec``; see ``build_model``.  The engine that runs it is
``crosscheck.engines.mujoco.engine``.

Geometry.  The capsule's end cap is centred on the tip A = (0, -l, 0) (body
frame), so the capsule touches the plane at C = A - r K, a radius below A.
A run starts with z_A = r + START_GAP: the capsule's lowest point a hair
above the plane.  With z_A = r exactly, MuJoCo's distance to the plane came
out between about -3.3e-16 l and +2.3e-16 l depending on the state, and
MuJoCo keeps a contact while dist < margin = 0, so whether the contact was
active in the first row was decided by that rounding (14 % of 400 random
states had it, with a first-row force of 2-26 m g from the elliptic cone's
coupling of a slipping contact), and 17 of the 300 starts of the quick
report's maps changed outcome when theta moved by 2 ulp.  Now no start has a
contact in the first row: the first step is force-free, and the contact
engages in the second whenever the tip's free acceleration points into the
plane, as it did for the other 86 % of starts.
tests/test_engine_mujoco.py checks it, and ``crosscheck.studies.rounding``
counts the starts that still hang on the last bit.
The tip velocity of the ``SlipState`` is given to A;
the contact point C then slips with v_A + r theta' (-sin psi, cos psi, 0),
which differs from v_A only when Theta != 0 (by r |Theta|).

Units.  Everything this module takes and returns is in the paper's scaled
units (section 2.1), except the compiled model itself, which is physical (SI).
"""

from __future__ import annotations

import importlib.resources
import os
from dataclasses import dataclass

import mujoco
import numpy as np

from crosscheck.checks import MU, check
from crosscheck.coordinates import to_generalized
from crosscheck.engines.kept import Kept
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = [
    "MODEL_FILE",
    "AXIAL_INERTIA",
    "axial_inertia",
    "ModelFileError",
    "model_path",
    "build_model",
    "model",
    "CACHE_SIZE",
    "initial_state",
    "SensorLayout",
    "record_from_sensordata",
]

#: The model file inside the package (a symlink to ``models/`` in the repository).
MODEL_FILE = "rod.xml"


class ModelFileError(ValueError):
    """The MuJoCo model file is missing or MuJoCo cannot read it; the message names the file."""


def model_path() -> str:
    """Path of ``rod.xml`` as shipped with the package (``crosscheck/_models/rod.xml``)."""
    return str(importlib.resources.files("crosscheck") / "_models" / MODEL_FILE)


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
#: MuJoCo refuses a moving body's mass or inertia below its mjMINVAL (1e-15); the axial inertia is held 10 times
#: above it, so that a 1 cm rod (I0 = 3e-5 kg m^2, 1e-12 I0 = 3e-17) compiles: its relative axial inertia is then
#: 3e-10, as negligible in the psi inertia as 1e-12.
MJ_MINVAL = 1e-15


def axial_inertia(inertia: float, relative: float = AXIAL_INERTIA) -> float:
    """The axial inertia [kg m^2] MuJoCo's model gives a rod of transverse inertia I0 = ``inertia``: ``relative`` I0,
    at least 10 MJ_MINVAL (``crosscheck.engines.mujoco.law`` mirrors it; MuJoCo Warp's model through Newton too)."""
    return max(relative * inertia, 10.0 * MJ_MINVAL)


def check_rod(rod: Rod, name: str = "MuJoCo") -> None:
    """ValueError unless the rod's mass and inertia are above 10 MJ_MINVAL, the least MuJoCo's compiler accepts of a
    moving body (``name``: the engine that compiles it)."""
    if min(rod.mass, rod.inertia) <= 10.0 * MJ_MINVAL:
        raise ValueError(
            f"rod must have a mass [kg] and an inertia I0 [kg m^2] above 1e-14 for {name} (MuJoCo's mjMINVAL is "
            f"1e-15); got mass {rod.mass:g}, inertia {rod.inertia:g}"
        )


def build_model(rod: Rod, mu: float, options) -> mujoco.MjModel:
    """Compile ``rod.xml`` with the parameters of one run.

    Args:
      rod: mass m, tip-to-centre length l, inertia I0 (alpha = m l^2 / I0) and g.
      mu: Coulomb friction coefficient, >= 0.
      options: scaled MuJoCo parameters (``crosscheck.engines.mujoco.options.Options``).

    Raises:
      ModelFileError: the model file is missing, malformed, or lacks one of the
        named elements (body "rod", geom "rod", site "tip", pair "floor_rod").
      ValueError: mu out of range.
    """
    mu = float(check("mu", mu, MU))
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
    spec.option.impratio = options.impratio
    spec.option.gravity = [0.0, 0.0, -rod.gravity]
    body.explicitinertial = True
    body.mass = rod.mass
    body.ipos = [0.0, 0.0, 0.0]
    body.inertia = [rod.inertia, axial_inertia(rod.inertia), rod.inertia]
    geom.fromto = [0.0, -l, 0.0, 0.0, l, 0.0]
    geom.size = [options.radius * l, 0.0, 0.0]
    site.pos = [0.0, -l, 0.0]
    pair.friction = [mu, mu, pair.friction[2], pair.friction[3], pair.friction[4]]
    pair.solref = [options.timeconst / w, options.dampratio]
    pair.solreffriction = (
        [0.0, 0.0] if options.friction_timeconst is None else [options.friction_timeconst / w, options.dampratio]
    )
    d0, dmax, width, mid, power = options.solimp
    pair.solimp = [d0, dmax, width * l, mid, power]
    # The keyframe is the viewer's start pose for the file's own parameters.
    for key in list(spec.keys):
        spec.delete(key)
    check_rod(rod)
    try:
        return spec.compile()
    except ValueError as e:
        raise ModelFileError(f"MuJoCo cannot compile {path}: {e}") from None


#: Compiled models kept by ``model`` (one per rod, mu, options and model file; a sweep over a grid of mu compiles one per mu).
CACHE_SIZE = 64

_kept = Kept(CACHE_SIZE)


def model(rod: Rod, mu: float, options) -> mujoco.MjModel:
    """``build_model`` once per (rod, mu, options, model file as it is on disk), kept for the next run of the same
    setting (the last ``CACHE_SIZE``).  Compiling took 1.3 ms, a fifth of a short ``simulate`` (the ladder's and the
    interventions' thousands of single runs).  The model is shared: read it, never change it (``build_model`` gives
    one of your own)."""
    mu = float(check("mu", mu, MU))
    path = options.model_file or model_path()
    try:
        st = os.stat(path)
        stamp = (st.st_mtime_ns, st.st_size, st.st_ino)  # an edited or replaced file compiles anew
    except OSError:
        return build_model(rod, mu, options)  # build_model says what is wrong with the file
    return _kept.get((rod, mu, options, path, stamp), lambda: build_model(rod, mu, options))


#: How far above the plane the capsule starts (scaled, l): positive, so that no contact is active in the first row
#: whatever the rounding of MuJoCo's distance (within about 3.3e-16 l of 0 at dist = 0: the module docstring).  1e-12 is
#: 3000 times that rounding, and 1e-5 of the 1e-7 l a tip with b = -1 falls in one default step (b dt^2 / 2, dt = 3e-4):
#: the contact engages in the second row whenever the tip's free acceleration points into the plane, as before.
START_GAP = 1e-12


def initial_state(
    model: mujoco.MjModel, rod: Rod, state: SlipState, radius: float, *, data: mujoco.MjData | None = None
) -> np.ndarray:
    """Full physics state (mjSTATE_FULLPHYSICS) of ``state`` with the capsule touching the plane.

    The tip A is put at (0, 0, r + START_GAP) so the capsule's lowest point
    C = A - r K is just above the plane and no contact is active in the first
    row (the module docstring); velocities from
    ``crosscheck.coordinates.to_generalized``.  Returns an (nstate,) array.
    ``data``: an ``MjData`` of ``model`` to reuse (its state is overwritten).
    """
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, radius + START_GAP))
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
    def from_model(cls, model: mujoco.MjModel) -> SensorLayout:
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


#: Rows of sensordata transposed per copy in ``_columns``: 512 rows x 28 columns (112 KiB) stay in the L2 cache while
#: they are read and written (blocks of 512 rows: 91 us for a 3-state chunk of 3334 rows, one copy of the whole: 132 us).
COPY_ROWS = 512


def _columns(sd: np.ndarray) -> np.ndarray:
    """(nsensordata, ...) contiguous copy of ``sd`` (..., nsensordata): each sensor a contiguous array of its own.

    The record reads 24 of the 28 columns, most of them twice or more, and a column read straight from the rows of
    ``sd`` (a stride of 224 bytes) touches a cache line per row: 10 us for a product of two columns of a 3-state chunk
    against 1.7 us contiguous.  The copy costs about nine such strided reads.
    """
    nsd = sd.shape[-1]
    rows = sd.reshape(-1, nsd)
    cols = np.empty((nsd, len(rows)))
    for a in range(0, len(rows), COPY_ROWS):
        cols[:, a : a + COPY_ROWS] = rows[a : a + COPY_ROWS].T
    return cols.reshape((nsd,) + sd.shape[:-1])


def record_from_sensordata(sensordata: np.ndarray, layout: SensorLayout, rod: Rod, radius: float) -> Record:
    """Scaled, world-frame ``Record`` from raw ``sensordata`` of shape (..., N, nsensordata).

    ``radius`` is the scaled capsule radius r / l used for the run.
    """
    sd = _columns(np.asarray(sensordata, dtype=float))
    l, w, g = rod.length, rod.omega, rod.gravity
    fs = rod.force_scale
    shape = sd.shape[1:]

    def vector(s: slice, scale: float) -> np.ndarray:
        out = np.empty(shape + (3,))
        for i in range(3):
            out[..., i] = sd[s.start + i] / scale
        return out

    # Contact frame -> world: the rows of MuJoCo's contact frame are (normal, tangent, normal x tangent).
    # Component by component on the sensor columns (no (..., 3) temporaries: this runs on every row of a sweep).
    f0, f1, f2 = sd[layout.force]
    n0, n1, n2 = sd[layout.normal]
    t0, t1, t2 = sd[layout.tangent]
    force = np.empty(shape + (3,))
    for i, (n_i, t_i, b_i) in enumerate(
        ((n0, t0, n1 * t2 - n2 * t1), (n1, t1, n2 * t0 - n0 * t2), (n2, t2, n0 * t1 - n1 * t0))
    ):
        force[..., i] = (f0 * n_i + f1 * t_i + f2 * b_i) / fs
    psi, theta = sd[layout.psi].copy(), sd[layout.theta].copy()  # copies: a record kept does not keep every column
    Psi, Theta = sd[layout.psi_dot] / w, sd[layout.theta_dot] / w
    tip_pos = vector(layout.tip_pos, l)
    tip_vel = vector(layout.tip_vel, l * w)
    tip_acc = vector(layout.tip_acc, g)
    tip_acc[..., 2] -= 1.0
    # velocity of the material point at C = A - r K: v_A + Omega x (-r K), Omega = theta' i + psi' K
    slip = np.zeros(shape + (3,))
    slip[..., 0] = tip_vel[..., 0] + -radius * Theta * np.sin(psi)
    slip[..., 1] = tip_vel[..., 1] + radius * Theta * np.cos(psi)
    return Record(
        t=sd[layout.clock] * w,
        tip_pos=tip_pos,
        tip_vel=tip_vel,
        tip_acc=tip_acc,
        force=force,
        normal_force=f0 / fs,
        active=sd[layout.found] > 0,
        gap=tip_pos[..., 2] - radius,
        slip_vel=slip,
        psi=psi,
        theta=theta,
        Psi=Psi,
        Theta=Theta,
    )
