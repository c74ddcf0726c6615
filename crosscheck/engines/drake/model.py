"""The rod as a Drake ``MultibodyPlant``: the chain of ``models/rod.xml``, a capsule on a half-space, built once per run setting.

Chain.  Four massless bodies and the rod, joined by prismatic X, Y, Z (world
axes), revolute psi about world z and revolute theta about the body x axis,
in that order, so the rod's rotation is Rz(psi) Rx(theta) (eq. rotmatrix)
and Drake's q = (X, Y, Z, psi, theta), v = q' are exactly the generalised
coordinates of ``crosscheck.coordinates``.  A free body would be wrong: the
friction at the capsule's surface has a lever r about the rod's own axis,
whose inertia is tiny, and spins it up to hundreds of rad/s.

Rod.  Mass m at the rod body's origin S, inertia diag(I0, AXIAL_INERTIA I0, I0)
about S with the rod along body y (eq. inertia; the axial moment only enters
the psi inertia I0 cos^2 + eps sin^2 theta).  The tip A is at (0, -l, 0).

Contact.  A capsule of radius r l and length 2 l along body y (Drake's capsule
lies along its own z axis: it is rotated by Rx(pi/2)), so its end cap is
centred on A and it touches the plane at C = A - r K; a ``HalfSpace`` on the
world body with its boundary z = 0.  Point contact (``ContactModel.kPoint``),
the material on each geometry's proximity properties: friction (mu, mu) on
both (Drake combines two frictions as 2 mu1 mu2 / (mu1 + mu2) = mu), point
stiffness 2 k on both (combined k1 k2 / (k1 + k2) = k), Hunt & Crossley
dissipation d on both (combined: the stiffness-weighted mean, d), and SAP's
relaxation time tau_d / 2 on both (combined: the sum, tau_d)
(multibody/plant/contact_properties.cc of Drake v1.51.1).
``penetration_allowance`` only sets defaults for missing properties, so it
changes nothing here.

Discrete plants use ``use_sampled_output_ports = False``: the contact results
and accelerations read at a state are those of the step that starts there
(computed once and cached with the step; ``DiscreteUpdateManager``).

Units.  Everything this module takes and returns is in the paper's scaled
units except the plant, which is in SI (``Rod``'s m, l, I0, g).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
from pydrake.geometry import AddContactMaterial, Capsule, HalfSpace, ProximityProperties
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.plant import (
    AddMultibodyPlant,
    CoulombFriction,
    DiscreteContactApproximation,
    MultibodyPlantConfig,
)
from pydrake.multibody.tree import (
    PrismaticJoint,
    RevoluteJoint,
    SpatialInertia,
    UnitInertia,
)
from pydrake.systems.framework import DiagramBuilder

from crosscheck.checks import MU, check
from crosscheck.engines.drake.options import Options
from crosscheck.engines.kept import Kept
from crosscheck.rod import Rod

__all__ = ["AXIAL_INERTIA", "CACHE_SIZE", "JOINTS", "Model", "build_model", "model", "new_context", "tip_kinematics"]

#: Axial inertia of the slender rod relative to I0 (eq. inertia has 0): as MuJoCo's model, 1e-12.  Drake
#: accepts 0 too (the triangle inequality holds with equality), but then the psi inertia I0 cos^2 theta has
#: no floor; with 1e-12 it changes the psi inertia by a relative 1e-12 tan^2 theta.
AXIAL_INERTIA = 1e-12

#: Joint names in the order of q.
JOINTS = ("X", "Y", "Z", "psi", "theta")

#: Built diagrams kept (one per rod, mu and plant-relevant options; a sweep over a grid of mu builds one per mu).
CACHE_SIZE = 64


@dataclass(frozen=True, eq=False)
class Model:
    """A built diagram (plant and scene graph) of one run setting; contexts are made per run.

    Attributes: diagram, plant; context: a default context never evaluated, cloned by each run
    (``new_context``); rod_body (the rod's BodyIndex, to orient contact forces); options, mu.
    """

    diagram: object
    plant: object
    context: object
    rod_body: object
    options: Options
    mu: float


def _material(mu: float, k: float, d: float, tau: float) -> ProximityProperties:
    props = ProximityProperties()
    AddContactMaterial(dissipation=d, point_stiffness=k, friction=CoulombFriction(mu, mu), properties=props)
    props.AddProperty("material", "relaxation_time", tau)
    return props


def build_model(rod: Rod, mu: float, options: Options) -> Model:
    """Build the rod's diagram for one run setting (SI inside; see the module docstring).

    Raises ValueError for mu out of range, or an approximation the installed Drake no longer has.
    """
    mu = float(check("mu", mu, MU))
    if options.approximation == "tamsi" and not hasattr(DiscreteContactApproximation, "kTamsi"):
        import pydrake

        raise ValueError(
            f"approximation 'tamsi' is not available in the installed Drake {getattr(pydrake, '__version__', '?')} "
            "(deprecated for removal after 2026-09-01)"
        )
    l, m, w, g = rod.length, rod.mass, rod.omega, rod.gravity
    config = MultibodyPlantConfig(
        time_step=options.timestep / w if options.discrete else 0.0,
        contact_model="point",
        discrete_contact_approximation=options.approximation if options.discrete else "sap",
        stiction_tolerance=options.stiction_tolerance * l * w,
        sap_near_rigid_threshold=options.near_rigid_threshold,
        use_sampled_output_ports=False,
    )
    drake_log = logging.getLogger("drake")
    level = drake_log.level
    # The first context logs that rigid half spaces take no part in deformable contact (there is none here), and
    # the plant TAMSI's deprecation: neither concerns a run, so they are not printed once per diagram.
    drake_log.setLevel(logging.ERROR)
    try:
        builder = DiagramBuilder()
        plant, _ = AddMultibodyPlant(config, builder)
        links = [plant.AddRigidBody(f"{name}_link", SpatialInertia.Zero()) for name in JOINTS[:-1]]
        unit = UnitInertia(rod.inertia / m, AXIAL_INERTIA * rod.inertia / m, rod.inertia / m)
        body = plant.AddRigidBody("rod", SpatialInertia(m, np.zeros(3), unit))
        chain = [plant.world_body(), *links, body]
        axes = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
        for i, (name, axis) in enumerate(zip(JOINTS, axes)):
            kind = PrismaticJoint if i < 3 else RevoluteJoint
            plant.AddJoint(kind(name, chain[i].body_frame(), chain[i + 1].body_frame(), axis))
        k = options.stiffness * rod.force_scale / l
        d = options.hunt_crossley / (l * w)
        tau = options.relaxation / w
        capsule = RigidTransform(RotationMatrix.MakeXRotation(math.pi / 2), [0.0, 0.0, 0.0])
        plant.RegisterCollisionGeometry(
            body, capsule, Capsule(options.radius * l, 2.0 * l), "rod", _material(mu, 2 * k, d, tau / 2)
        )
        plant.RegisterCollisionGeometry(
            plant.world_body(), RigidTransform(), HalfSpace(), "plane", _material(mu, 2 * k, d, tau / 2)
        )
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -g])
        plant.Finalize()
        diagram = builder.Build()
        context = diagram.CreateDefaultContext()
    finally:
        drake_log.setLevel(level)
    return Model(diagram=diagram, plant=plant, context=context, rod_body=body.index(), options=options, mu=mu)


def new_context(m: Model):
    """A fresh context of ``m``'s diagram (a clone of its never-evaluated default context): a run's numbers do
    not depend on the runs before it."""
    return m.context.Clone()


_kept = Kept(CACHE_SIZE)


def model(rod: Rod, mu: float, options: Options) -> Model:
    """``build_model`` once per (rod, mu, options), kept for the next run of the same setting (the last ``CACHE_SIZE``)."""
    return _kept.get((rod, float(mu), options), lambda: build_model(rod, mu, options))


def tip_kinematics(
    rod: Rod, q: np.ndarray, v: np.ndarray, vdot: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position, velocity and acceleration of the tip A [physical, world] from (q, v, v') of shape (N, 5).

    A = S + l (cos theta sin psi, -cos theta cos psi, -sin theta) (eq. tipfromcentre) and its first two
    time derivatives; the acceleration is J v' + J' v, gravity included in v' (a free rod's is b g along z).
    """
    l = rod.length
    psi, theta = q[:, 3], q[:, 4]
    sp, cp, st, ct = np.sin(psi), np.cos(psi), np.sin(theta), np.cos(theta)
    dpsi, dth = v[:, 3], v[:, 4]
    a_psi, a_th = vdot[:, 3], vdot[:, 4]
    pos = np.stack((q[:, 0] + l * ct * sp, q[:, 1] - l * ct * cp, q[:, 2] - l * st), -1)
    vel = np.stack(
        (
            v[:, 0] + l * (-st * sp * dth + ct * cp * dpsi),
            v[:, 1] + l * (st * cp * dth + ct * sp * dpsi),
            v[:, 2] - l * ct * dth,
        ),
        -1,
    )
    rate2 = dth * dth + dpsi * dpsi
    acc = np.stack(
        (
            vdot[:, 0] + l * (-st * sp * a_th + ct * cp * a_psi - ct * sp * rate2 - 2 * st * cp * dth * dpsi),
            vdot[:, 1] + l * (st * cp * a_th + ct * sp * a_psi + ct * cp * rate2 - 2 * st * sp * dth * dpsi),
            vdot[:, 2] - l * ct * a_th + l * st * dth * dth,
        ),
        -1,
    )
    return pos, vel, acc
