"""DART changed in the way each cause of its ladder names: the interventions that should remove a disagreement of it.

* geometry: a thinner capsule (r / 4, r / 16; the contact offset stays);
* discretisation: the timestep divided by 4 and 16.

Scaled units (section 2.1).  ``crosscheck.studies.interventions`` runs them.
"""

from __future__ import annotations

from crosscheck.engines.spec import Intervention

__all__ = ["geometry", "discretisation"]


def geometry(o):
    return tuple(
        Intervention(f"capsule radius {o.radius:g} -> {o.radius / k:g}", {"radius": o.radius / k}) for k in (4, 16)
    )


def discretisation(o):
    return tuple(
        Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}) for k in (4, 16)
    )
