"""The rod of ``models/rod.xml`` in DART (dartpy): the five-joint chain skeleton on a plane, one rollout.

The rod is a ``Skeleton`` of five body nodes, each on one joint from the world, every frame at the centre of
mass S:

    body 1  prismatic along world x   X
    body 2  prismatic along world y   Y
    body 3  prismatic along world z   Z
    body 4  revolute about world z    psi
    body 5  revolute about body x     theta  (mass m, inertia diag(I0, J, I0), the capsule)

so DART's generalised positions and velocities are exactly q = (X, Y, Z, psi, theta) and v of
``crosscheck.coordinates``.  The axial spin is locked by the chain (no joint turns about the rod's axis).
DART warns that a zero mass "can cause invalid physical behavior or segfault", so bodies 1-4 get
``CHAIN_MASS`` m and moments ``CHAIN_MASS`` I0, and the capsule an axial moment J = ``CHAIN_MASS`` I0: a
relative change of the mass matrix of at most 4e-12.  The capsule (DART's ``CapsuleShape`` lies along its
local z, turned onto body y) has cap centres A = (0, -l, 0) and B = (0, l, 0), radius r l; the plane is a
``PlaneShape`` (normal +z through the origin) on a welded ground skeleton.

Settings: DART's default constraint solver (``BoxedLcpConstraintSolver``, Dantzig's pivoting method on the
boxed LCP of the step, PGS as its fallback), whose contact has one normal row and two friction rows along world
x and y, each boxed by mu times the frictionless normal impulse (``crosscheck.engines.dart.engine``): a square
pyramid whose size does not follow the normal force.  dartpy 6.20 does not expose the friction directions, but
it has a second boxed-LCP solver, ``NsgsFrictionSolver``, with a friction law Box (the rows bounded by mu times the
normal impulse as solved: a pyramid that follows the normal force) or Coulomb (the cone): ``Options.friction_solver``
puts it in Dantzig's place, the interventions of the friction bound and the pyramid cone.  The collision detector is DART's Bullet one (``BulletCollisionDetector``): FCL, the default, has no
capsule and silently puts a sphere of radius 0.1 in its place, and ODE's misses the contact of a capsule that
starts exactly touching.  Friction mu and restitution 0 on both shapes.  The contact force is read from the
momentum of the moving bodies, F = M (v_k+1 - v_k) / dt - M g along each prismatic axis (M the masses each
joint carries): DART's own ``Skeleton.getConstraintForces`` departs from it by up to 3e-4 m g on a steady
slip, a fraction of the force's change per step.  A fresh world per run.  Everything here is physical (SI, from the ``Rod``).
"""

from __future__ import annotations

import dartpy as dart
import numpy as np

from crosscheck.engines.classifier import FIRST_CHECK
from crosscheck.engines.physx.chain import Raw
from crosscheck.rod import Rod

__all__ = ["World", "CHAIN_MASS"]

#: The mass and moments of bodies 1-4 and the capsule's axial moment, relative to m and I0 (DART warns at 0).
CHAIN_MASS = 1e-12

#: Each joint's kind and axis, in the order of ``crosscheck.coordinates.GENERALIZED``.
JOINTS = (("prismatic", (1, 0, 0)), ("prismatic", (0, 1, 0)), ("prismatic", (0, 0, 1)))
JOINTS += (("revolute", (0, 0, 1)), ("revolute", (1, 0, 0)))


def _surface(shape_node, mu: float) -> None:
    shape_node.createCollisionAspect()
    aspect = shape_node.createDynamicsAspect()
    aspect.setFrictionCoeff(mu)
    aspect.setRestitutionCoeff(0.0)


class World:
    """The plane and the rod of one (rod, mu, options) in a fresh DART world."""

    def __init__(self, rod: Rod, mu: float, options) -> None:
        D = dart.dynamics
        self.rod, self.options = rod, options
        self.dt = options.timestep / rod.omega
        self.world = dart.simulation.World()
        self.world.setGravity([0.0, 0.0, -rod.gravity])
        self.world.setTimeStep(self.dt)
        ground = D.Skeleton("ground")
        _, plane = ground.createWeldJointAndBodyNodePair()
        _surface(plane.createShapeNode(D.PlaneShape([0.0, 0.0, 1.0], 0.0)), mu)
        self.skeleton = D.Skeleton("rod")
        parent = None
        for kind, axis in JOINTS:
            if kind == "prismatic":
                props = D.PrismaticJointProperties()
                props.mAxis = np.array(axis, float)
                _, body = self.skeleton.createPrismaticJointAndBodyNodePair(parent, props)
            else:
                props = D.RevoluteJointProperties()
                props.mAxis = np.array(axis, float)
                _, body = self.skeleton.createRevoluteJointAndBodyNodePair(parent, props)
            small_i = CHAIN_MASS * rod.inertia
            body.setMass(CHAIN_MASS * rod.mass)
            body.setMomentOfInertia(small_i, small_i, small_i, 0.0, 0.0, 0.0)
            parent = body
        body.setMass(rod.mass)
        body.setMomentOfInertia(rod.inertia, CHAIN_MASS * rod.inertia, rod.inertia, 0.0, 0.0, 0.0)
        capsule = body.createShapeNode(D.CapsuleShape(options.radius * rod.length, 2.0 * rod.length))
        turn = dart.math.Isometry3()
        turn.set_rotation(np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]))  # local z onto body y
        capsule.setRelativeTransform(turn)
        _surface(capsule, mu)
        # the detector before the skeletons: FCL's group would otherwise be built first (and log its sphere)
        self.world.getConstraintSolver().setCollisionDetector(dart.collision.BulletCollisionDetector())
        if options.friction_solver != "dantzig":  # DART's NSGS friction solver in Dantzig's place, with its law
            nsgs = dart.constraint.NsgsFrictionSolver
            settings = nsgs.Options()
            settings.law = nsgs.Law.Coulomb if options.friction_solver == "nsgs_coulomb" else nsgs.Law.Box
            self.world.getConstraintSolver().setBoxedLcpSolver(nsgs(settings))
        self.world.addSkeleton(ground)
        self.world.addSkeleton(self.skeleton)
        masses = [self.skeleton.getBodyNode(i).getMass() for i in range(5)]
        self.carried = np.array([sum(masses[0:]), sum(masses[1:]), sum(masses[2:])])

    def rollout(self, q0: np.ndarray, v0: np.ndarray, nstep: int, judged=None) -> Raw:
        """``nstep`` DART steps from (q0, v0) [physical]: the states and each step's contact.

        ``judged(raw)``, if given, is asked after ``FIRST_CHECK`` steps and then after twice as many each time whether
        the steps so far settle the run's first event; the rollout stops there if so (later rows NaN).
        """
        skel, world = self.skeleton, self.world
        skel.setPositions(np.asarray(q0, float))
        skel.setVelocities(np.asarray(v0, float))
        q = np.full((nstep + 1, 5), np.nan)
        v = np.full((nstep + 1, 5), np.nan)
        force = np.zeros((nstep, 3))
        points = np.zeros(nstep, np.int64)
        separation = np.full(nstep, np.nan)
        q[0], v[0] = skel.getPositions(), skel.getVelocities()
        gravity = np.array([0.0, 0.0, -self.rod.gravity])
        check = FIRST_CHECK
        for k in range(nstep):
            if judged is not None and k == check:
                raw = Raw(q, v, force, points, separation, computed=k)
                if judged(raw.head(k)):
                    force[k:] = np.nan
                    return raw
                check *= 2
            world.step()
            q[k + 1], v[k + 1] = skel.getPositions(), skel.getVelocities()
            result = world.getLastCollisionResult()
            n = result.getNumContacts()
            if n:  # without a contact point DART applied no impulse: 0, not the momentum's rounding
                force[k] = self.carried * ((v[k + 1, :3] - v[k, :3]) / self.dt - gravity)
                points[k] = n
                separation[k] = -max(result.getContact(i).penetrationDepth for i in range(n))
        return Raw(q, v, force, points, separation)
