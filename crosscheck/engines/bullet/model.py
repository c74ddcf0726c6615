"""The rod of ``models/rod.xml`` in pybullet: one DIRECT client per process, its world built per (rod, mu, options), one rollout.

The rod is a ``createMultiBody`` with a fixed, massless base at the origin
and a chain of five links, each on one joint, all frames at the centre of
mass S (no offsets):

    link 0  prismatic along world x   X
    link 1  prismatic along world y   Y
    link 2  prismatic along world z   Z
    link 3  revolute about world z    psi
    link 4  revolute about body x     theta  (mass m, inertia diag(I0, 0, I0), the capsule)

so that Bullet's joint positions and velocities are exactly q = (X, Y, Z, psi,
theta) and v of ``crosscheck.coordinates`` (body rotation Rz(psi) Rx(theta)).
Links 0-3 have no mass.  A free base would be wrong: its third rotation
(about the rod's axis) has the capsule's tiny axial inertia, and the friction
torque at radius r spins it up to hundreds of rad/s; the chain has no such
degree of freedom, like ``models/rod.xml``.  The axial inertia is 0 (eq.
inertia); Bullet accepts it, since no joint turns about the rod's axis.

The capsule lies along body y with its end caps centred on A = (0, -l, 0) and
B = (0, l, 0) (``GEOM_CAPSULE``, height 2 l between the cap centres, radius
r l), so it touches the plane z = 0 (``GEOM_PLANE`` on a static body) at
C = A - r K.  Free dynamics: one Bullet step is v' = v + dt a(q, v),
q' = q + dt v' with a the rod's exact acceleration (eqs. rotode, linode2;
measured to 1.6e-13 relative over random states, tests/test_engine_bullet.py).

Settings, each because Bullet's default is wrong for this problem (friction,
and the others), and the reset between runs: ``docs/bullet_model.md``.

Solver analytics (``reportSolverAnalytics``) are on: ``stepSimulation``
then returns the sweeps PGS took and its last residual, which
``crosscheck.engines.bullet.engine.BulletHealth`` reports.

Everything here is physical (SI, from the ``Rod``); ``rollout`` returns raw
physical arrays and ``crosscheck.engines.bullet.engine`` scales them.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from crosscheck.coordinates import tip_position, tip_velocity
from crosscheck.engines.classifier import FIRST_CHECK
from crosscheck.rod import Rod
from crosscheck.stderr_fd import silenced


def _import_pybullet():
    """``import pybullet`` without the build-time line its C code writes to stderr (once per process, so once per worker)."""
    with silenced():
        import pybullet
    return pybullet


pb = _import_pybullet()

__all__ = ["World", "world", "JOINTS"]

#: The five joints in the order of ``crosscheck.coordinates.GENERALIZED``.
JOINTS = (0, 1, 2, 3, 4)

#: The rod's link (the capsule, the mass and the inertia).
ROD_LINK = 4

#: Bullet's joint velocity clamp, lifted out of reach (see the module docstring).
NO_CLAMP = 1e30


@dataclass(frozen=True)
class Raw:
    """One rollout in physical units: states 0..n and what each step's contact did.

    q, v: (n + 1, 5) joint positions and velocities after k steps.
    force: (n, 3) contact force on the rod of step k -> k+1 [N], world frame (the impulse / dt).
    points: (n,) number of Bullet contact points in that step.
    distance: (n,) the smallest distance Bullet gave its points at the step's collision detection [m]
      (negative: penetration; NaN without a point).
    iterations: (n,) PGS sweeps the step's solve took (Bullet's solver analytics; at most ``solver_iterations``).
    residual: (n,) the solve's last residual, the largest squared velocity change of a row in its last sweep [(m/s)^2]
      (0: a sweep changed nothing, the fixed point).
    computed: the steps taken (n, or fewer when the rollout stopped once its first event was judged: the later
      states and forces are NaN, their points 0).
    """

    q: np.ndarray
    v: np.ndarray
    force: np.ndarray
    points: np.ndarray
    distance: np.ndarray
    iterations: np.ndarray
    residual: np.ndarray
    computed: int | None = None


class World:
    """A pybullet world holding the plane and the rod of one (rod, mu, options), and its rollouts."""

    def __init__(self, client: int, rod: Rod, mu: float, options) -> None:
        self.client, self.rod, self.mu, self.options = client, rod, float(mu), options
        self.key = (rod, self.mu, options)
        self.dt = options.timestep / rod.omega
        c = client
        l = rod.length
        pb.resetSimulation(physicsClientId=c)
        pb.setGravity(0.0, 0.0, -rod.gravity, physicsClientId=c)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=self.dt,
            numSubSteps=0,
            numSolverIterations=options.solver_iterations,
            solverResidualThreshold=(options.solver_tolerance * l * rod.omega) ** 2,
            enableConeFriction=int(options.cone),
            contactERP=options.contact_erp,
            contactSlop=0.0,
            contactBreakingThreshold=options.contact_margin * l,
            restitutionVelocityThreshold=0.0,
            globalCFM=0.0,
            reportSolverAnalytics=1,
            physicsClientId=c,
        )
        self.ground = pb.createMultiBody(
            0.0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=c), physicsClientId=c
        )
        capsule = pb.createCollisionShape(
            pb.GEOM_CAPSULE,
            radius=options.radius * l,
            height=2.0 * l,
            collisionFrameOrientation=pb.getQuaternionFromEuler([math.pi / 2, 0.0, 0.0]),
            physicsClientId=c,
        )
        zero, ident = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]
        self.body = pb.createMultiBody(
            baseMass=0.0,
            baseCollisionShapeIndex=-1,
            baseVisualShapeIndex=-1,
            basePosition=zero,
            baseOrientation=ident,
            linkMasses=[0.0, 0.0, 0.0, 0.0, rod.mass],
            linkCollisionShapeIndices=[-1, -1, -1, -1, capsule],
            linkVisualShapeIndices=[-1] * 5,
            linkPositions=[zero] * 5,
            linkOrientations=[ident] * 5,
            linkInertialFramePositions=[zero] * 5,
            linkInertialFrameOrientations=[ident] * 5,
            linkParentIndices=[0, 1, 2, 3, 4],  # createMultiBody numbers the base 0 and link i as i + 1
            linkJointTypes=[pb.JOINT_PRISMATIC] * 3 + [pb.JOINT_REVOLUTE] * 2,
            linkJointAxis=[[1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1], [1, 0, 0]],
            physicsClientId=c,
        )
        if self.body < 0 or self.ground < 0:
            raise RuntimeError("pybullet could not create the rod or the plane")
        pb.changeDynamics(
            self.ground,
            -1,
            lateralFriction=1.0,
            restitution=0.0,
            rollingFriction=0.0,
            spinningFriction=0.0,
            physicsClientId=c,
        )
        pb.changeDynamics(
            self.body,
            -1,
            linearDamping=0.0,
            angularDamping=0.0,
            maxJointVelocity=NO_CLAMP,
            activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING,
            physicsClientId=c,
        )
        for j in JOINTS:
            pb.changeDynamics(self.body, j, jointDamping=0.0, physicsClientId=c)
        pb.changeDynamics(
            self.body,
            ROD_LINK,
            localInertiaDiagonal=[rod.inertia, 0.0, rod.inertia],
            lateralFriction=self.mu,
            restitution=0.0,
            rollingFriction=0.0,
            spinningFriction=0.0,
            physicsClientId=c,
        )
        pb.setJointMotorControlArray(self.body, list(JOINTS), pb.VELOCITY_CONTROL, forces=[0.0] * 5, physicsClientId=c)

    def set_state(self, q: np.ndarray, v: np.ndarray) -> None:
        """Put the rod at (q, v) [physical] with no contact point left from before (module docstring)."""
        c, body = self.client, self.body
        far = 1e3 * self.rod.length + 10.0 * self.options.contact_margin * self.rod.length
        for j in JOINTS:
            pb.resetJointState(body, j, far if j == 2 else 0.0, 0.0, physicsClientId=c)
        pb.performCollisionDetection(physicsClientId=c)
        if pb.getContactPoints(body, self.ground, physicsClientId=c):
            raise RuntimeError("Bullet kept a contact point of the previous run after the rod was lifted off the plane")
        for j in JOINTS:
            pb.resetJointState(body, j, float(q[j]), float(v[j]), physicsClientId=c)

    def rollout(self, q0: np.ndarray, v0: np.ndarray, nstep: int, judged=None) -> Raw:
        """``nstep`` Bullet steps from (q0, v0) [physical]: the states and each step's contact.

        ``judged(raw)``, if given, is asked after ``FIRST_CHECK`` steps and then after twice as many each time whether
        the steps so far (a ``Raw`` of them) settle the run's first event; the rollout stops there if so.
        """
        self.set_state(q0, v0)
        c, body, ground = self.client, self.body, self.ground
        joints = list(JOINTS)
        q = np.empty((nstep + 1, 5))
        v = np.empty((nstep + 1, 5))
        force = np.zeros((nstep, 3))
        points = np.zeros(nstep, np.int64)
        distance = np.full(nstep, np.nan)
        iterations = np.zeros(nstep, np.int64)
        residual = np.zeros(nstep)
        step, states, contacts = pb.stepSimulation, pb.getJointStates, pb.getContactPoints
        s = states(body, joints, physicsClientId=c)
        q[0] = [x[0] for x in s]
        v[0] = [x[1] for x in s]
        along_slip = self.options.friction_axes == "slip"
        turn = 0.0
        check = FIRST_CHECK
        for k in range(nstep):
            if judged is not None and k == check:
                if judged(
                    Raw(
                        q=q[: k + 1],
                        v=v[: k + 1],
                        force=force[:k],
                        points=points[:k],
                        distance=distance[:k],
                        iterations=iterations[:k],
                        residual=residual[:k],
                        computed=k,
                    )
                ):
                    q[k + 1 :], v[k + 1 :], force[k:] = np.nan, np.nan, np.nan
                    return Raw(
                        q=q,
                        v=v,
                        force=force,
                        points=points,
                        distance=distance,
                        iterations=iterations,
                        residual=residual,
                        computed=k,
                    )
                check *= 2
            if along_slip:
                turn, about = self._turn_to_slip(q[k], v[k])
            for island in step(physicsClientId=c) or ():  # the solver's analytics (reportSolverAnalytics): one island
                iterations[k] = max(iterations[k], island["numIterationsUsed"])
                residual[k] = max(residual[k], island["remainingResidual"])
            s = states(body, joints, physicsClientId=c)
            q[k + 1] = [x[0] for x in s]
            v[k + 1] = [x[1] for x in s]
            if along_slip:
                q[k + 1], v[k + 1] = _turned(q[k + 1], v[k + 1], -turn, about)
            cps = contacts(body, ground, physicsClientId=c)
            if cps:
                # on the rod (body A): normal force along the plane's normal (from B to A), the two friction forces
                # along their directions; each is the step's impulse / dt (pybullet's getContactPoints)
                fx = fy = fz = 0.0
                dmin = math.inf
                for cp in cps:
                    n, fn, f1, d1, f2, d2 = cp[7], cp[9], cp[10], cp[11], cp[12], cp[13]
                    fx += fn * n[0] + f1 * d1[0] + f2 * d2[0]
                    fy += fn * n[1] + f1 * d1[1] + f2 * d2[1]
                    fz += fn * n[2] + f1 * d1[2] + f2 * d2[2]
                    dmin = min(dmin, cp[8])
                if along_slip:  # back to the world's axes
                    cg, sg = math.cos(turn), math.sin(turn)
                    fx, fy = cg * fx + sg * fy, -sg * fx + cg * fy
                force[k] = fx, fy, fz
                points[k] = len(cps)
                distance[k] = dmin
        return Raw(q=q, v=v, force=force, points=points, distance=distance, iterations=iterations, residual=residual)

    def _turn_to_slip(self, q: np.ndarray, v: np.ndarray) -> tuple[float, np.ndarray]:
        """Set the rod at (q, v) turned about the vertical through the tip A by the angle that brings the slip of its
        contact point C = A - r K along world +x (``Options.friction_axes`` "slip"); return the angle and A (x, y)."""
        rod, psi = self.rod, q[3]
        u = tip_velocity(rod, q, v)[:2] + self.options.radius * rod.length * v[4] * np.array(
            (-math.sin(psi), math.cos(psi))
        )
        turn = -math.atan2(u[1], u[0]) if u[0] or u[1] else 0.0
        about = tip_position(rod, q)[:2]
        qt, vt = _turned(q, v, turn, about)
        for j in JOINTS:
            pb.resetJointState(self.body, j, float(qt[j]), float(vt[j]), physicsClientId=self.client)
        return turn, about


def _turned(q: np.ndarray, v: np.ndarray, angle: float, about: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) turned by ``angle`` about the vertical through ``about`` (x, y) [m]: psi + angle, S and its velocity turned."""
    c, s = math.cos(angle), math.sin(angle)
    q, v = q.copy(), v.copy()
    x, y = q[0] - about[0], q[1] - about[1]
    q[0], q[1], q[3] = about[0] + c * x - s * y, about[1] + s * x + c * y, q[3] + angle
    v[0], v[1] = c * v[0] - s * v[1], s * v[0] + c * v[1]
    return q, v


_world: World | None = None
_client: tuple[int, int] | None = None  # (pid, client id)


def world(rod: Rod, mu: float, options) -> World:
    """The process's world for (rod, mu, options): the cached one, or rebuilt in the process's one DIRECT client.

    The client is per process (``sweep``'s forked workers connect their own: a client is not shared
    across a fork).
    """
    global _world, _client
    pid = os.getpid()
    if _client is None or _client[0] != pid:
        _client = (pid, pb.connect(pb.DIRECT))
        if _client[1] < 0:
            raise RuntimeError("pybullet could not connect a DIRECT physics client")
        _world = None
    key = (rod, float(mu), options)
    if _world is None or _world.key != key:
        _world = None
        _world = World(_client[1], rod, mu, options)
    return _world
