"""The rod of ``models/rod.xml`` in Newton: one model of B worlds (one start each), stepped together, in SI units.

Each world holds the rod and its own ground plane:

* the rod is one body on a D6 joint to the world with linear axes world x, y, z and angular axes world z, then the
  z-turned x (Newton turns the second angular axis by the first: rotation Rz(psi) Rx(theta), ``compute_2d_rotational
  _dofs``), so its five joint coordinates are exactly q = (X, Y, Z, psi, theta) of ``crosscheck.coordinates`` with the
  body origin at the centre of mass S.  That is the five-joint chain of ``models/rod.xml`` as one joint: no axial spin
  (a free body's friction torque at radius r spins the capsule's tiny axial inertia up to hundreds of rad/s);
* mass m, inertia diag(I0, a I0, I0) about S with the rod along body y, a = ``Options.axial_inertia`` (rod.xml's 1e-12 by
  default; Newton's inertia check, which
  would raise the axial moment to 1e-6 I0 + 1e-6 kg m^2, is told to accept it), kept as given (``lock_inertia``);
* a capsule along body y with its end caps centred on A = (0, -l, 0) and B = (0, l, 0), radius r l, no density (no
  mass of its own), no torsional or rolling friction, no restitution, margin and gap 0 (a contact exists only while
  the capsule penetrates, as the ``mujoco`` engine's pair);
* its own plane z = 0 with the same material: every Newton and MuJoCo rule that combines two shapes' friction
  (mean, max, product's root) then gives the run's mu, set per world (``Batch.run``'s ``mu``).

MuJoCo Warp (``SolverMuJoCo``) gets the ``mujoco`` engine's settings: Euler, Newton's method, elliptic cone, the
iterations and tolerance of rod.xml, condim 3, solref (timeconst, dampratio) and solimp on both geoms (equal, so
MuJoCo's mixing of the two keeps them), impratio; its own collision (``use_mujoco_contacts``).  The other solvers
collide through Newton's ``CollisionPipeline``; the penalty solvers read ke, kd, kf from the shapes.

Everything here is physical (SI, from the ``Rod``); ``Batch.run`` returns raw float64 copies of Warp's float32
states and ``crosscheck.engines.newton.engine`` scales them.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from crosscheck.engines.mujoco.model import axial_inertia, check_rod
from crosscheck.engines.newton.options import init_warp

wp = init_warp()
import newton  # noqa: E402  (after warp's configuration)
from newton._src.solvers.mujoco.constants import SOLREF_MODE_RAW  # noqa: E402  (not re-exported by newton)

from crosscheck.rod import Rod  # noqa: E402

__all__ = ["Batch", "Raw", "batch", "compile_seconds"]

#: CPU seconds spent in each solver's first step of this process (Warp compiles or loads its kernels then):
#: solver -> seconds.  The report's provenance names it; no per-step cost includes it.
_FIRST_STEP: dict[str, float] = {}


def compile_seconds() -> dict[str, float]:
    """CPU seconds of each solver's first step in this process (kernel compilation or cache loads), by solver."""
    return dict(_FIRST_STEP)


@dataclass(frozen=True)
class Raw:
    """B rollouts of n steps in physical units (Warp's float32 states as float64).

    q, v: (B, n + 1, 5) generalized positions (X, Y, Z, psi, theta) and velocities after k steps [m, rad, m/s, rad/s];
      psi unwrapped over the run.
    spin: (B, n + 1) angular velocity about the rod's own axis [rad/s] (0 for a solver that holds the D6 joint
      exactly; XPBD's projection leaves some).
    """

    q: np.ndarray
    v: np.ndarray
    spin: np.ndarray


def _world(rod: Rod, options) -> newton.ModelBuilder:
    """One world's builder: the rod on its D6 joint, its capsule, its plane (module docstring)."""
    l, m, g, r = rod.length, rod.mass, rod.gravity, options.radius * rod.length
    w = rod.omega
    one = newton.ModelBuilder(gravity=(0.0, 0.0, -g))
    if options.solver == "mujoco":
        newton.solvers.SolverMuJoCo.register_custom_attributes(one)
    cfg = newton.ModelBuilder.ShapeConfig(
        mu=1.0,
        density=0.0,
        margin=0.0,
        gap=0.0,
        restitution=0.0,
        mu_torsional=0.0,
        mu_rolling=0.0,
        ke=options.stiffness * m * g / l,
        kd=options.damping * m * g / (l * w),
        kf=options.friction_gain * m * g / (l * w),
    )
    I0 = rod.inertia
    axial = options.axial_inertia * I0
    if options.solver == "mujoco":  # MuJoCo compiles the model: its mjMINVAL floor, as the mujoco engine's
        check_rod(rod, "MuJoCo Warp")
        axial = axial_inertia(I0, options.axial_inertia)
    body = one.add_link(mass=m, inertia=wp.mat33(I0, 0.0, 0.0, 0.0, axial, 0.0, 0.0, 0.0, I0), lock_inertia=True)
    along_y = wp.quat_from_axis_angle(wp.vec3(1.0, 0.0, 0.0), -math.pi / 2)  # the capsule's z axis onto body y
    one.add_shape_capsule(body, xform=wp.transform(wp.vec3(0.0, 0.0, 0.0), along_y), radius=r, half_height=l, cfg=cfg)
    axis = newton.ModelBuilder.JointDofConfig
    joint = one.add_joint_d6(
        -1,
        body,
        linear_axes=[axis(axis=(1.0, 0.0, 0.0)), axis(axis=(0.0, 1.0, 0.0)), axis(axis=(0.0, 0.0, 1.0))],
        angular_axes=[axis(axis=(0.0, 0.0, 1.0)), axis(axis=(1.0, 0.0, 0.0))],
    )
    one.add_articulation([joint])
    one.add_ground_plane(cfg=cfg)
    return one


def _mujoco_contact(model, rod: Rod, options) -> None:
    """solref, solimp and condim of every geom (both of each world's pair equal: MuJoCo's mixing keeps them)."""
    n = model.shape_count
    tc = options.timeconst / rod.omega
    model.mujoco.solref.assign(np.tile(np.array([tc, options.dampratio], dtype=np.float32), (n, 1)))
    d0, dmax, width, mid, power = options.solimp
    imp = np.array([d0, dmax, width * rod.length, mid, power], dtype=np.float32)
    model.mujoco.geom_solimp.assign(np.tile(imp, (n, 1)))
    model.mujoco.condim.assign(np.full(n, 3, dtype=np.int32))
    # solref as given (MuJoCo's "raw" solref), not derived from the shapes' ke, kd nor MJCF's default
    model.mujoco.solref_mode.assign(np.full(n, SOLREF_MODE_RAW, dtype=np.int32))


def _solver(model, rod: Rod, options):
    """The Newton solver of ``options.solver`` on ``model``."""
    S = newton.solvers
    if options.solver == "mujoco":
        return S.SolverMuJoCo(
            model,
            separate_worlds=True,
            solver="newton",
            integrator="euler",
            cone="elliptic",
            iterations=options.solver_iterations,
            ls_iterations=options.ls_iterations,
            tolerance=options.solver_tolerance,
            impratio=options.impratio,
            use_mujoco_contacts=True,
            disable_contacts=False,
            use_mujoco_cpu=options.mujoco_cpu,
            # MuJoCo in C keeps its float64 data from step to step, not reloaded from Newton's float32 state
            # (``Batch.run`` loads each start through ``reset``)
            **({"update_data_interval": 0} if options.mujoco_cpu else {}),
        )
    if options.solver == "xpbd":
        return S.SolverXPBD(
            model, iterations=options.solver_iterations, rigid_contact_relaxation=options.contact_relaxation
        )
    if options.solver == "featherstone":
        return S.SolverFeatherstone(model)
    return S.SolverSemiImplicit(
        model,
        angular_damping=0.0,  # Newton's default 0.05 drags every rotation: not the rod's
        joint_attach_ke=options.joint_stiffness * rod.mass * rod.gravity * rod.length,
        joint_attach_kd=options.joint_damping * rod.mass * rod.gravity * rod.length / rod.omega,
    )


class Batch:
    """One Newton model of B worlds of the rod (module docstring), its solver, states and collision pipeline."""

    def __init__(self, rod: Rod, options, size: int) -> None:
        self.rod, self.options, self.size = rod, options, size
        self.device = wp.get_device(options.device)  # Options refused a CUDA device that is not here
        top = newton.ModelBuilder(gravity=(0.0, 0.0, -rod.gravity))
        if options.solver == "mujoco":
            newton.solvers.SolverMuJoCo.register_custom_attributes(top)
        top.inertia_relative_tolerance = 0.0  # keep rod.xml's axial moment 1e-12 I0 (module docstring)
        top.inertia_absolute_tolerance = 1e-30
        top.replicate(_world(rod, options), copy_count=size)
        self.model = top.finalize(device=self.device)
        if options.solver == "mujoco":
            _mujoco_contact(self.model, rod, options)
        with warnings.catch_warnings():
            # Newton's notes about itself, not about the run: MuJoCo Warp 4.0 beside its declared ~=3.17 (the one
            # installed with our mujoco 4.0; provenance names both versions) and its own use of deprecated calls
            warnings.filterwarnings("ignore", message="MuJoCo dependency version mismatch")
            warnings.filterwarnings("ignore", category=DeprecationWarning)
            warnings.filterwarnings("ignore", message="SolverMuJoCo update_data_interval is deprecated")
            self.solver = _solver(self.model, rod, options)
        self.states = (self.model.state(), self.model.state())
        self.control = self.model.control()
        self.pipeline = None
        if options.solver != "mujoco":
            self.pipeline = newton.CollisionPipeline(self.model)
            self.contacts = self.pipeline.contacts()
        else:
            self.contacts = None
        self.shape_world = self.model.shape_world.numpy().copy()
        self.dt = options.timestep / rod.omega

    def _set_mu(self, mu: np.ndarray) -> None:
        self.model.shape_material_mu.assign(np.asarray(mu, dtype=np.float32)[self.shape_world])
        self.solver.notify_model_changed(newton.ModelFlags.SHAPE_PROPERTIES)
        if self.options.mujoco_cpu:  # (Newton 1.8 passes a shape's changed friction to MuJoCo Warp only: set C's own)
            self.solver.mj_model.geom_friction[:, 0] = float(np.asarray(mu).ravel()[0])

    def _step(self, k: int) -> None:
        s_in, s_out = self.states[k % 2], self.states[(k + 1) % 2]
        s_in.clear_forces()
        if self.pipeline is not None:
            self.pipeline.collide(s_in, self.contacts)
        self.solver.step(s_in, s_out, self.control, self.contacts, self.dt)

    def run(self, q0: np.ndarray, v0: np.ndarray, mu: np.ndarray, n: int) -> Raw:
        """n steps of every world from (q0, v0) (each (B, 5), SI) at friction ``mu`` (B,); ``Raw``."""
        B = self.size
        self._set_mu(mu)
        s0 = self.states[0]
        q0, v0 = (np.asarray(x, dtype=np.float32).ravel() for x in (q0, v0))
        if self.options.mujoco_cpu:
            # MuJoCo in C's data is loaded from the state only by ``reset``, which sets the model's defaults: the start
            self.model.joint_q.assign(q0)
            self.model.joint_qd.assign(v0)
        self.solver.reset(s0)  # MuJoCo Warp's warm start and applied forces zeroed: no run carries into the next
        s0.joint_q.assign(q0)
        s0.joint_qd.assign(v0)
        newton.eval_fk(self.model, s0.joint_q, s0.joint_qd, s0)
        body_q = np.empty((n + 1, B, 7), dtype=np.float32)
        body_qd = np.empty((n + 1, B, 6), dtype=np.float32)
        body_q[0], body_qd[0] = s0.body_q.numpy(), s0.body_qd.numpy()
        for k in range(n):
            if k == 0 and self.options.solver not in _FIRST_STEP:
                t0 = time.process_time()
                self._step(0)
                wp.synchronize()
                _FIRST_STEP[self.options.solver] = time.process_time() - t0
            else:
                self._step(k)
            s = self.states[(k + 1) % 2]
            body_q[k + 1], body_qd[k + 1] = s.body_q.numpy(), s.body_qd.numpy()
        return _generalized(body_q, body_qd)


def _generalized(body_q: np.ndarray, body_qd: np.ndarray) -> Raw:
    """(q, v, spin) of the rod from Newton's body poses (x, y, z, quaternion x y z w) and twists (v_S, omega), world."""
    bq, bqd = body_q.astype(float), body_qd.astype(float)
    x, y, z, w = np.moveaxis(bq[..., 3:7], -1, 0)
    # the rod's axis j = R e_y (rotation Rz(psi) Rx(theta): j = (-sin psi cos theta, cos psi cos theta, sin theta))
    jx, jy, jz = 2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)
    theta = np.arcsin(np.clip(jz, -1.0, 1.0))
    psi = np.unwrap(np.arctan2(-jx, jy), axis=0)
    omega = bqd[..., 3:6]
    # omega = Psi e_z + Theta i with i = R e_x = (cos psi, sin psi, 0), plus any spin along j
    # (i is normal to e_z and to j; e_z and j are not normal to each other, so the spin comes from j's horizontal part)
    Theta = omega[..., 0] * np.cos(psi) + omega[..., 1] * np.sin(psi)
    rest_x, rest_y = omega[..., 0] - Theta * np.cos(psi), omega[..., 1] - Theta * np.sin(psi)
    spin = (rest_x * jx + rest_y * jy) / (jx * jx + jy * jy)
    Psi = omega[..., 2] - spin * jz
    q = np.stack((bq[..., 0], bq[..., 1], bq[..., 2], psi, theta), -1)
    v = np.stack((bqd[..., 0], bqd[..., 1], bqd[..., 2], Psi, Theta), -1)
    return Raw(q=np.moveaxis(q, 0, 1), v=np.moveaxis(v, 0, 1), spin=np.moveaxis(spin, 0, 1))


_CACHE: dict = {}


def batch(rod: Rod, options, size: int) -> Batch:
    """The process's ``Batch`` of (rod, options, size), built once (a model, a solver and their kernels' first load)."""
    key = (rod, options, size)
    if key not in _CACHE:
        if len(_CACHE) >= 8:  # a few models at a time: each holds B worlds' buffers
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = Batch(rod, options, size)
    return _CACHE[key]
