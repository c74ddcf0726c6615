"""The rod of ``models/rod.xml`` in PhysX (SAPIEN 3 on CPU): the five-joint articulation on a plane, one rollout.

The scene is a ``PhysxCpuSystem`` alone in a ``sapien.Scene`` (``sapien.Scene()`` would add a render system,
which needs a rendering device this machine has not).  The plane is a static actor with a
``PhysxCollisionShapePlane`` turned so that its normal (PhysX's local +x) is world +z.  The rod is a
reduced-coordinate articulation with a fixed root at the origin and a chain of five links, each on one joint,
every frame at the centre of mass S:

    link 1  prismatic along world x   X
    link 2  prismatic along world y   Y
    link 3  prismatic along world z   Z
    link 4  revolute about world z    psi
    link 5  revolute about body x     theta  (mass m, inertia diag(I0, J, I0), the capsule)

PhysX turns a joint about or along its frame's x axis; each joint's frame is the same rotation in parent and
child (x onto the joint's axis), so the links stay aligned with the world until the two revolutes turn the
rod by Rz(psi) Rx(theta): the joint positions are exactly q = (X, Y, Z, psi, theta) of
``crosscheck.coordinates``.  The axial spin is locked by the chain (no joint turns about the rod's axis), as
in Bullet and MuJoCo: a free rigid body's tiny axial inertia spins up to 20-60 rad/s under the friction
torque at radius r within 0.2 s.  PhysX refuses a link of zero mass or a zero principal inertia (it puts 1 kg
and (1, 1, 1) in their place), so links 1-4 get ``CHAIN_MASS`` m and inertia ``CHAIN_MASS`` I0, and the
capsule an axial inertia J = ``CHAIN_MASS`` I0: a relative change of the rod's mass matrix of at most
4 ``CHAIN_MASS`` = 4e-7, ~3 float32 ulps.  The contact force is read from the momentum of the moving links,
F = M (v_k+1 - v_k) / dt - M g along each prismatic axis (M the masses each joint carries, read back from
PhysX), which is exact up to float32 rounding; PhysX's contact report gives normal impulses only.

The capsule (PhysX's lies along its local x, turned onto body y) has its end caps centred on A = (0, -l, 0)
and B = (0, l, 0), radius r l, so it touches the plane at C = A - r K.  Settings, each because PhysX's or
SAPIEN's default is wrong here (``crosscheck.engines.physx.options.Options`` for the ones that are options):
friction dynamic = mu and static = ``static_ratio`` mu (1: Coulomb's one coefficient) on both shapes (PhysX
averages the two shapes' coefficients), restitution 0;
link linear and angular damping 0 (0.05); joint friction 0 (SAPIEN's 0.05), damping and armature 0, no
drives; link velocity clamps (10 m/s, 50 rad/s) and joint velocity clamps (100) at 1e30; torsional patch
radius ``patch_radius`` l (0); rest offset 0; sleep, bounce threshold, contact offset, solver and
iterations from the options.

PhysX computes in float32: the state read back each step is float32 (relative rounding 6e-8), converted to
float64.  A fresh system per run: PhysX keeps contact manifolds and friction anchors between steps, so a
reused scene would carry one run's contact into the next.  Everything here is physical (SI, from the ``Rod``).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from crosscheck.engines.classifier import FIRST_CHECK
from crosscheck.engines.physx.chain import Raw
from crosscheck.rod import Rod

with warnings.catch_warnings():  # SAPIEN warns at import that it falls back to its own libvulkan (no renderer is used)
    warnings.simplefilter("ignore")
    import sapien
    import sapien.physx as px

__all__ = ["World", "CHAIN_MASS", "NO_CLAMP"]

#: The mass and inertia of links 1-4 and the capsule's axial inertia, relative to m and I0 (PhysX refuses 0).
CHAIN_MASS = 1e-7

#: PhysX's velocity clamps, put out of reach (float32 holds up to 3.4e38).
NO_CLAMP = 1e30

#: Each joint's axis and kind, in the order of ``crosscheck.coordinates.GENERALIZED``.
JOINTS = (("prismatic", "x"), ("prismatic", "y"), ("prismatic", "z"), ("revolute", "z"), ("revolute", "x"))


def _onto(axis: str):
    """The pose turning PhysX's local x onto world ``axis``."""
    half = math.sqrt(0.5)
    q = {"x": (1.0, 0.0, 0.0, 0.0), "y": (half, 0.0, 0.0, half), "z": (half, 0.0, -half, 0.0)}[axis]
    return sapien.Pose(q=list(q))


class World:
    """The plane and the rod of one (rod, mu, options) in a fresh PhysX CPU system."""

    def __init__(self, rod: Rod, mu: float, options) -> None:
        self.rod, self.options = rod, options
        l, w = rod.length, rod.omega
        self.dt = options.timestep / w
        config = px.PhysxSceneConfig()
        config.gravity = [0.0, 0.0, -rod.gravity]
        config.bounce_threshold = options.bounce_threshold * l * w
        config.enable_tgs = options.solver == "tgs"
        config.enable_pcm = True
        config.enable_ccd = False
        config.enable_enhanced_determinism = False
        config.enable_friction_every_iteration = options.friction_every_iteration
        px.set_scene_config(config)  # read when a system is made
        self.system = px.PhysxCpuSystem()
        self.system.timestep = self.dt
        self.scene = sapien.Scene([self.system])
        material = px.PhysxMaterial(static_friction=options.static_ratio * mu, dynamic_friction=mu, restitution=0.0)
        ground = px.PhysxRigidStaticComponent()
        ground.attach(self._shaped(px.PhysxCollisionShapePlane(material), "z"))
        self._add(ground)
        self.links = self._chain(rod, material, options)
        self.articulation = self.links[-1].articulation
        self.articulation.set_sleep_threshold(options.sleep_threshold * (l * w) ** 2)
        self.articulation.set_solver_position_iterations(options.position_iterations)
        self.articulation.set_solver_velocity_iterations(options.velocity_iterations)
        # the mass each prismatic joint carries (links 1-5, 2-5, 3-5), for the contact force from momentum
        masses = [float(k.mass) for k in self.links[1:]]
        self.carried = np.array([sum(masses[0:]), sum(masses[1:]), sum(masses[2:])])

    def _shaped(self, shape, axis: str):
        shape.local_pose = _onto(axis)
        shape.contact_offset = self.options.contact_offset * self.rod.length
        shape.rest_offset = 0.0
        shape.patch_radius = self.options.patch_radius * self.rod.length
        shape.min_patch_radius = 0.0
        return shape

    def _add(self, component) -> None:
        entity = sapien.Entity()
        entity.add_component(component)
        self.scene.add_entity(entity)

    def _chain(self, rod: Rod, material, options) -> list:
        root = px.PhysxArticulationLinkComponent(None)
        links = [root]
        for _ in JOINTS:
            links.append(px.PhysxArticulationLinkComponent(links[-1]))
        capsule = px.PhysxCollisionShapeCapsule(options.radius * rod.length, rod.length, material)
        links[-1].attach(self._shaped(capsule, "y"))
        entities = []
        for link in links:
            entity = sapien.Entity()
            entity.add_component(link)
            entities.append(entity)
        root.joint.type = "fixed"
        for link, (kind, axis) in zip(links[1:], JOINTS):
            j = link.joint
            j.type = kind
            j.pose_in_parent = j.pose_in_child = _onto(axis)
            j.limit = np.array([[-np.inf, np.inf]])  # a joint with limits [0, 0] (the default) is locked
            j.set_friction(0.0)
            j.set_drive_properties(0.0, 0.0, 0.0, "force")
            j.set_armature([0.0])
            j.max_velocity = NO_CLAMP
        small_m, small_i = CHAIN_MASS * rod.mass, CHAIN_MASS * rod.inertia
        for link in links[:-1]:
            link.set_mass(small_m)
            link.set_inertia([small_i] * 3)
        links[-1].set_mass(rod.mass)
        links[-1].set_inertia([rod.inertia, small_i, rod.inertia])
        for link in links:
            link.set_linear_damping(0.0)
            link.set_angular_damping(0.0)
            link.set_max_linear_velocity(NO_CLAMP)
            link.set_max_angular_velocity(NO_CLAMP)
        for entity in entities:
            self.scene.add_entity(entity)
        return links

    def rollout(self, q0: np.ndarray, v0: np.ndarray, nstep: int, judged=None) -> Raw:
        """``nstep`` PhysX steps from (q0, v0) [physical]: the states and each step's contact.

        ``judged(raw)``, if given, is asked after ``FIRST_CHECK`` steps and then after twice as many each time whether
        the steps so far settle the run's first event; the rollout stops there if so (later rows NaN).
        """
        art, system = self.articulation, self.system
        art.set_qpos(np.asarray(q0, np.float32))
        art.set_qvel(np.asarray(v0, np.float32))
        q = np.full((nstep + 1, 5), np.nan)
        v = np.full((nstep + 1, 5), np.nan)
        force = np.zeros((nstep, 3))
        points = np.zeros(nstep, np.int64)
        separation = np.full(nstep, np.nan)
        # row 0 is the start as given; PhysX holds it rounded to float32 (6e-8 relative), as every later row
        q[0], v[0] = q0, v0
        check = FIRST_CHECK
        for k in range(nstep):
            if judged is not None and k == check:
                self._forces(q, v, force, points, k)
                raw = Raw(q, v, force, points, separation, computed=k)
                if judged(raw.head(k)):
                    force[k:] = np.nan
                    return raw
                check *= 2
            system.step()
            q[k + 1], v[k + 1] = art.get_qpos(), art.get_qvel()
            least, n = math.inf, 0
            for contact in system.get_contacts():
                for p in contact.points:
                    n += 1
                    least = min(least, p.separation)
            if n:
                points[k], separation[k] = n, least
        self._forces(q, v, force, points, nstep)
        return Raw(q, v, force, points, separation)

    def _forces(self, q, v, force, points, k: int) -> None:
        """Steps 0..k-1's contact force from the momentum of the moving links (module docstring); 0 in a step
        without a contact point (PhysX applied no contact impulse there; the momentum would show float32 noise)."""
        gravity = np.array([0.0, 0.0, -self.rod.gravity])
        force[:k] = self.carried * (np.diff(v[: k + 1, :3], axis=0) / self.dt - gravity)
        force[:k][points[:k] == 0] = 0.0
