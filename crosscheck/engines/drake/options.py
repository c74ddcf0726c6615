"""Drake's run parameters in the paper's scaled units (importing this does not import pydrake).

Conversions to the SI values Drake is given (``crosscheck.engines.drake.model``),
for a rod of mass m, tip-to-centre length l, gravity g and omega = sqrt(g / l):

* ``timestep``: dt = timestep / omega;
* ``radius``: the capsule's radius r l;
* ``stiffness``: k = stiffness m g / l [N/m] (a scaled stiffness S means the
  rod's weight m g compresses the contact by l / S);
* ``dissipation``: Hunt & Crossley's d = dissipation / (l omega) [s/m]
  (Drake's force is k x (1 + d x')+, x the penetration, so the scaled
  dissipation multiplies a scaled penetration speed);
* ``relaxation_time``: SAP's tau_d = relaxation_time / omega [s];
* ``stiction_tolerance``: v_s = stiction_tolerance l omega [m/s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from crosscheck.checks import CAPSULE_RADIUS, Interval, check_timestep, real_scalar
from crosscheck.engines.options import EngineOptions

__all__ = [
    "ACCURACY",
    "APPROXIMATIONS",
    "CREEP_MARGIN",
    "DISCRETE",
    "DISSIPATION",
    "INTEGRATORS",
    "NEAR_RIGID_THRESHOLD",
    "RADIUS",
    "RELAXATION_TIME",
    "SAP_SIGMA",
    "STICTION_TOLERANCE",
    "STIFFNESS",
    "Options",
    "engine_name",
]

#: The contact approximations, each a registered engine ``drake_<approximation>``: "continuous" is a
#: continuous-time plant (time_step 0) with Hunt & Crossley point contact and Stribeck friction integrated
#: by an error-controlled integrator; the others are Drake's ``DiscreteContactApproximation`` of a
#: discrete plant (kSap, kSimilar, kLagged, kTamsi; TAMSI is deprecated in Drake for removal after
#: 2026-09-01, multibody/plant/multibody_plant.h of v1.51.1).
APPROXIMATIONS = ("continuous", "sap", "similar", "lagged", "tamsi")

#: The approximations of a discrete plant (a fixed time step equal to ``Options.timestep``).
DISCRETE = ("sap", "similar", "lagged", "tamsi")

#: Drake's error-controlled integration schemes (``pydrake.systems.analysis.GetIntegrationSchemes``
#: without the fixed-step explicit_euler, semi_explicit_euler and runge_kutta2, and without cenic,
#: which needs a discrete plant's contact problem).
INTEGRATORS = (
    "runge_kutta3",
    "runge_kutta5",
    "bogacki_shampine3",
    "radau1",
    "radau3",
    "implicit_euler",
    "velocity_implicit_euler",
)

# Ranges.  Each is where the number still means what its name says for the paper's rod (forces O(1) m g,
# speeds O(1) l omega, times O(1) / omega):
#: r / l: as MuJoCo's capsule (at r >= l/2 the end cap reaches the centre of mass).
RADIUS = CAPSULE_RADIUS
#: k l / (m g): at 1e2 the weight compresses the contact by 0.01 l, the default radius (a softer contact
#: sinks the tip A itself below the plane); at 1e10 the contact time 1/sqrt(k) is 1e-5, and the
#: continuous integrator needs ~1e5 steps per unit time.
STIFFNESS = Interval(1e2, 1e10, lo_open=False, hi_open=False)
#: d l omega: Hunt & Crossley's factor (1 + d x') doubles the force at a penetration speed 1/d; at 1e6
#: that is 1e-6 l omega, so the contact would no longer be elastic at any speed the rod reaches.
DISSIPATION = Interval(0.0, 1e6, lo_open=False, hi_open=False)
#: omega tau_d of SAP's linear Kelvin-Voigt damping: at 1 the damping acts over the rod's own time scale.
RELAXATION_TIME = Interval(0.0, 1.0, lo_open=False, hi_open=False)
#: v_s / (l omega): above 1e-2 a stuck contact creeps faster than the classifier's STICK speed
#: (``Thresholds.stick_speed``), so a stuck rod would read as slipping.
STICTION_TOLERANCE = Interval(0.0, 1e-2, lo_open=True, hi_open=False)
#: The continuous integrator's target accuracy (Drake's IntegratorBase: a relative local error norm).
ACCURACY = Interval(1e-12, 1e-1, lo_open=False, hi_open=False)
#: SAP's near-rigid threshold beta (Castro et al. 2022, section V.B): the contact's period is at least beta dt.
NEAR_RIGID_THRESHOLD = Interval(0.0, 10.0, lo_open=False, hi_open=False)

#: SAP's friction regularisation sigma: R_t = sigma w_t (multibody/plant/sap_driver.cc of v1.51.1, a
#: constant there).  A stuck SAP contact slips at v_t = R_t gamma_t ~ sigma a_t dt, a_t the tangential
#: acceleration friction cancels.
SAP_SIGMA = 1e-3

#: ``Options.friction_time`` is this multiple of the largest creep speed of a stuck contact, read as a
#: time at a tangential acceleration of 1 g (the classifier's STICK threshold is stick_creep x friction_time;
#: MuJoCo's friction_time is 2.5 x its measured creep).
CREEP_MARGIN = 2.5


#: How tables and messages name the engine of each approximation.
LABELS = {
    "continuous": "Drake continuous",
    "sap": "Drake SAP",
    "similar": "Drake Similar",
    "lagged": "Drake Lagged",
    "tamsi": "Drake TAMSI",
}


def engine_name(approximation: str) -> str:
    """The registered name of an approximation's engine: ``drake_<approximation>``."""
    return f"drake_{approximation}"


def _check_number(name: str, value, interval: Interval) -> float:
    return real_scalar(name, value, interval)


@dataclass(frozen=True)
class Options(EngineOptions):
    """Drake parameters of a run, in the paper's scaled units (module docstring: their SI values).

    Attributes:
      approximation: one of ``APPROXIMATIONS`` (default "sap"; each registered
        engine fixes it through its ``EngineSpec.defaults``).
      timestep: omega dt.  For a discrete approximation it is the plant's
        time step (one contact solve per row); for "continuous" it is only the
        spacing of the record's rows (the integrator chooses its own steps,
        at most this long).  Default 1e-3.
      radius: capsule radius r / l (default 0.01, as MuJoCo's).
      stiffness: point-contact stiffness k l / (m g) of the rod-plane pair
        (default 1e4: the weight compresses the contact by 1e-4 l, and the
        contact time 1/sqrt(k) is 0.01).  Both geometries get 2 k: Drake's
        combined stiffness is k1 k2 / (k1 + k2).
      dissipation: Hunt & Crossley dissipation d l omega (continuous, similar,
        lagged, tamsi; SAP ignores it).  None (default): 2 sqrt(stiffness),
        which damps the contact critically at the rod's static load: linearised
        at the weight's compression x0 = m g / k the damping coefficient is
        k x0 d = m g d, critical when it is 2 sqrt(k m).  Both geometries get
        it: Drake's combined dissipation is the stiffness-weighted mean.
      relaxation_time: SAP's Kelvin-Voigt relaxation time omega tau_d (SAP only).
        None (default): 2 / sqrt(stiffness), critical damping k tau_d =
        2 sqrt(k m).  Each geometry gets half: Drake adds the two.
      stiction_tolerance: the regularised friction's stiction speed
        v_s / (l omega) (continuous: Stribeck; similar, lagged, tamsi: Drake's
        regularisation; SAP sets its own).  Default 1e-4 (Drake's default
        1e-4 m/s is 3.2e-5 for a 1 m rod).
      integrator: the continuous plant's error-controlled scheme, one of
        ``INTEGRATORS`` (default "runge_kutta3", Drake's default).
      accuracy: its target accuracy (default 1e-6; continuous only).
      near_rigid_threshold: SAP's beta (default 1.0, Drake's).
    """

    approximation: str = "sap"
    timestep: float = 1e-3
    radius: float = 0.01
    stiffness: float = 1e4
    dissipation: float | None = None
    relaxation_time: float | None = None
    stiction_tolerance: float = 1e-4
    integrator: str = "runge_kutta3"
    accuracy: float = 1e-6
    near_rigid_threshold: float = 1.0

    def __post_init__(self) -> None:
        if self.approximation not in APPROXIMATIONS:
            raise ValueError(f"approximation must be one of {', '.join(APPROXIMATIONS)}; got {self.approximation!r}")
        if self.integrator not in INTEGRATORS:
            raise ValueError(f"integrator must be one of {', '.join(INTEGRATORS)}; got {self.integrator!r}")

        def set_(name, value):
            object.__setattr__(self, name, value)

        set_("timestep", check_timestep(self.timestep))
        set_("radius", _check_number("radius", self.radius, RADIUS))
        set_("stiffness", _check_number("stiffness", self.stiffness, STIFFNESS))
        if self.dissipation is not None:
            set_("dissipation", _check_number("dissipation", self.dissipation, DISSIPATION))
        if self.relaxation_time is not None:
            set_("relaxation_time", _check_number("relaxation_time", self.relaxation_time, RELAXATION_TIME))
        set_("stiction_tolerance", _check_number("stiction_tolerance", self.stiction_tolerance, STICTION_TOLERANCE))
        set_("accuracy", _check_number("accuracy", self.accuracy, ACCURACY))
        set_(
            "near_rigid_threshold",
            _check_number("near_rigid_threshold", self.near_rigid_threshold, NEAR_RIGID_THRESHOLD),
        )

    @classmethod
    def label_of(cls, options: dict[str, Any]) -> str:
        """The label of the engine of the options' approximation ("Drake SAP")."""
        approximation = options.get("approximation", cls.approximation)
        return (
            LABELS.get(approximation, engine_name(approximation))
            if isinstance(approximation, str)
            else engine_name(approximation)
        )

    @property
    def name(self) -> str:
        """The registered engine of this approximation (``drake_sap``, ...)."""
        return engine_name(self.approximation)

    @property
    def discrete(self) -> bool:
        """A discrete plant (time step ``timestep``) rather than a continuous one."""
        return self.approximation in DISCRETE

    @property
    def hunt_crossley(self) -> float:
        """The Hunt & Crossley dissipation d l omega in use (``dissipation`` or its default)."""
        return self.dissipation if self.dissipation is not None else 2.0 * math.sqrt(self.stiffness)

    @property
    def relaxation(self) -> float:
        """SAP's relaxation time omega tau_d in use (``relaxation_time`` or its default)."""
        return self.relaxation_time if self.relaxation_time is not None else 2.0 / math.sqrt(self.stiffness)

    @property
    def contact_time(self) -> float:
        """Time over which the normal force builds up: 1/omega_n of the contact spring with the rod's mass.

        sqrt(m / k) omega = 1 / sqrt(stiffness).  SAP caps the contact's frequency
        at 2 pi / (beta dt) (its near-rigid regularisation R_n >= beta^2 / (4 pi^2) w_n,
        multibody/contact_solvers/sap/sap_friction_cone_constraint.cc), so for SAP
        it is max(1 / sqrt(stiffness), beta timestep / (2 pi)).
        """
        t = 1.0 / math.sqrt(self.stiffness)
        if self.approximation == "sap":
            t = max(t, self.near_rigid_threshold * self.timestep / (2.0 * math.pi))
        return t

    @property
    def spring_time(self) -> float:
        """eps of the normal force as a spring delta / eps^2 (Hunt & Crossley or SAP's Kelvin-Voigt, damping aside): the
        contact time, through which a jam lags the rigid one by s* (eps^4 / (k |b|))^(1/5) (``crosscheck.theory.jam_lag``)."""
        return self.contact_time

    @property
    def friction_time(self) -> float:
        """The STICK threshold's friction time: CREEP_MARGIN x the creep speed of a stuck contact at 1 g.

        A stuck contact of a regularised friction law slips at most at v_s (Drake:
        "v_stiction is the slip velocity that we'd have when we are at edge of the
        friction cone", MultibodyPlant::set_stiction_tolerance), so CREEP_MARGIN x
        stiction_tolerance; SAP's own regularisation creeps at ~SAP_SIGMA a_t dt,
        so CREEP_MARGIN x SAP_SIGMA x timestep.  Both are far below the classifier's
        floor ``Thresholds.stick_speed`` = 1e-2 at the defaults.
        """
        if self.approximation == "sap":
            return CREEP_MARGIN * SAP_SIGMA * self.timestep
        return CREEP_MARGIN * self.stiction_tolerance
