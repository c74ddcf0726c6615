"""DART changed in the way each cause of its ladder names: the interventions that should remove a disagreement of it.

* geometry: a thinner capsule (r / 4, r / 16; the contact offset stays);
* discretisation: the timestep divided by 4 and 16;
* pyramid cone: Coulomb's cone in place of the pyramid (``Options.friction_solver`` "nsgs_coulomb": DART's NSGS
  friction solver with its Coulomb law).  dartpy has no cone for the Dantzig step, so this also lets the friction's
  bound follow the normal impulse (the friction bound's change): a disagreement that the friction bound's own
  intervention removes too is counted as removed by another cause;
* friction bound: the friction rows bounded by mu times the normal impulse as it is solved, the pyramid kept
  (``friction_solver`` "nsgs_box": DART's NSGS friction solver with its Box law).

Scaled units (section 2.1).  ``crosscheck.studies.interventions`` runs them.
"""

from __future__ import annotations

from crosscheck.engines.spec import Intervention

__all__ = ["geometry", "discretisation", "pyramid_cone", "friction_bound"]


def geometry(o):
    return tuple(
        Intervention(f"capsule radius {o.radius:g} -> {o.radius / k:g}", {"radius": o.radius / k}) for k in (4, 16)
    )


def discretisation(o):
    return tuple(
        Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}) for k in (4, 16)
    )


def pyramid_cone(o):
    return (Intervention("friction pyramid (Dantzig) -> Coulomb cone (NSGS)", {"friction_solver": "nsgs_coulomb"}),)


def friction_bound(o):
    return (
        Intervention(
            "friction bound mu F_n0 (Dantzig) -> mu F_n (NSGS, pyramid kept)", {"friction_solver": "nsgs_box"}
        ),
    )
