"""Drake's models in between, for its ladder (``crosscheck.studies.ladder``): the compliant rod with Drake's normal law, and Drake's continuous plant.

Scaled units (section 2.1).  Drake's point contact pushes with F_n = S delta (1 + D delta')
(Hunt & Crossley: stiffness S m g / l, dissipation D / (l omega); continuous, Similar,
Lagged, TAMSI) or F_n = S (delta + tau_d delta') (SAP's linear Kelvin-Voigt law, relaxation
time tau_d / omega).  The compliant rod's laws (``crosscheck.engines.compliant.laws``) are
delta / eps^2 (1 + (xi / eps) delta') and delta / eps^2 + (xi / eps) delta', so the same
contact is eps = 1 / sqrt(S) with xi = D / sqrt(S) (Hunt & Crossley) or xi = tau_d sqrt(S)
(Kelvin-Voigt); at Drake's defaults (D = 2 sqrt(S), tau_d = 2 / sqrt(S)) xi = 2 either way.
The compliant rod has exact Coulomb friction with a stick phase; Drake's friction is
regularised (a stiction tolerance, or SAP's and Similar's convex relaxation), so the rung
after it, friction law, is Drake's own law in continuous time: its continuous plant with the
same stiffness, Hunt & Crossley dissipation and capsule (for SAP, whose dissipation is a
relaxation time, the continuous plant's default dissipation 2 sqrt(S), the same damping ratio).
The convex approximations (SAP, Similar, Lagged) have one more rung before themselves: TAMSI, Drake's
non-convex step, at the same timestep and contact, so that what the time step does and what the convex
relaxation of the step's contact problem does are two causes ("discretisation", "relaxation").
"""

from __future__ import annotations

import math

from crosscheck import engines

__all__ = ["compliant", "continuous", "tamsi"]


def compliant(rod, state, mu, *, horizon, thresholds, options):
    """The compliant rod at C with Drake's normal law and parameters (module docstring), records at Drake's row spacing."""
    S = options.stiffness
    if options.approximation == "sap":
        law, xi = "kelvin-voigt", options.relaxation * math.sqrt(S)
    else:
        law, xi = "hunt-crossley", options.hunt_crossley / math.sqrt(S)
    return engines.get("compliant").simulate(
        rod,
        state,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        eps=1.0 / math.sqrt(S),
        xi=xi,
        law=law,
        radius=options.radius,
        timestep=options.timestep,
    )


def continuous(rod, state, mu, *, horizon, thresholds, options):
    """Drake's continuous point contact at the same stiffness, dissipation and capsule, rows at the run's timestep; stopped
    once its first event is judged (the ladder reads the outcome and event time only)."""
    dissipation = None if options.approximation == "sap" else options.hunt_crossley
    return engines.get("drake_continuous").simulate(
        rod,
        state,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        timestep=options.timestep,
        stiffness=options.stiffness,
        dissipation=dissipation,
        radius=options.radius,
        until_event=True,
    )


def tamsi(rod, state, mu, *, horizon, thresholds, options):
    """Drake's non-convex TAMSI step at the run's timestep, stiffness, dissipation and capsule: the step without the relaxation;
    stopped once its first event is judged, as ``continuous``."""
    dissipation = None if options.approximation == "sap" else options.hunt_crossley
    return engines.get("drake_tamsi").simulate(
        rod,
        state,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        timestep=options.timestep,
        stiffness=options.stiffness,
        dissipation=dissipation,
        radius=options.radius,
        until_event=True,
    )
