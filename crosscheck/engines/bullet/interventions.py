"""Bullet changed in the way each cause of its ladder names: the interventions that should remove a disagreement of that cause.

* geometry: a thinner capsule (r / 4, r / 16; the contact margin stays);
* friction law: the friction rows along the slip (``Options.friction_axes`` "slip": the state turned about
  the vertical before each step so that Bullet's first friction row lies along the contact's slip), so that
  its friction opposes the slip as Coulomb's does, not diag(D)^-1 u (``crosscheck.engines.bullet.law``);
* discretisation: the timestep divided by 4 and 16.

Scaled units (section 2.1).  ``crosscheck.studies.interventions`` runs them.
"""

from __future__ import annotations

from crosscheck.engines.spec import Intervention

__all__ = ["geometry", "friction_law", "discretisation"]


def geometry(o):
    return tuple(
        Intervention(f"capsule radius {o.radius:g} -> {o.radius / k:g}", {"radius": o.radius / k}) for k in (4, 16)
    )


def friction_law(o):
    if o.friction_axes == "slip":  # already Coulomb's direction: nothing to change
        return ()
    return (Intervention("friction rows along world x, y -> along the slip", {"friction_axes": "slip"}),)


def discretisation(o):
    return tuple(
        Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}) for k in (4, 16)
    )
