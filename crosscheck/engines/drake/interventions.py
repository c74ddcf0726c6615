"""Drake changed in the way each cause of its ladder names: the interventions that should remove a disagreement of that cause.

Each function takes the run's ``Options`` and returns ``Intervention`` s,
weakest first (``crosscheck.studies.interventions`` runs them):

* geometry: a thinner capsule (r / 4, r / 16);
* compliance: a stiffer point contact (stiffness x 10, x 100, and x 1000 at a tenth
  of the timestep), toward the rigid limit the compliant rod reaches as
  eps = 1 / sqrt(S) -> 0.  The strongest step shortens the timestep with it: at
  x 1000 the contact's time 1 / sqrt(S) is a thirtieth of the default step, and a
  step that long cannot follow the force building up (the continuous plant's
  rows and its error control are both set by the timestep).  Where the theory's
  slip from the start passes close to p = 0 (its least eq. p, p_min < 1), one
  more: the strongest made as far into the rigid limit at that closest approach
  as it is at p = 1.  There the contact follows the rod's normal motion in
  1 / (S p)^(1/2), not 1 / S^(1/2) (``crosscheck.theory.jam_lag.contact_time_at``),
  so the stiffness is divided by p_min and the timestep multiplied by
  p_min^(1/2) (the same steps per contact time).  Measured on the full report:
  from theta 0.904, varphi -1.9, Theta 0.625, Psi 0, mu 1.4 (p_min 0.003, the
  theory lifts off at 0.079) TAMSI and the continuous plant still jam at
  x 1000 and a tenth of the step, and lift off at 0.06 at that closest
  approach; a thinner capsule joined to it removes jams that each leaves alone;
* friction law: a smaller stiction tolerance (/ 10, / 100): Drake's friction
  is Coulomb's regularised below that slip speed (the continuous plant and
  TAMSI; SAP, Similar and Lagged regularise by their own relaxation, which
  this does not touch, so it should not confirm there);
* discretisation: the timestep divided by 4 and 16 (a time-stepping approximation only);
* relaxation: the same step solved without the convex relaxation: Drake's
  TAMSI at the same timestep, stiffness and capsule.

Scaled units (section 2.1).
"""

from __future__ import annotations

from crosscheck.engines.spec import Intervention
from crosscheck.theory.jam_lag import contact_time_at

__all__ = ["geometry", "compliance", "friction_law", "discretisation", "relaxation"]


def geometry(o):
    return tuple(
        Intervention(f"capsule radius {o.radius:g} -> {o.radius / k:g}", {"radius": o.radius / k}) for k in (4, 16)
    )


def compliance(o, p_min: float | None = None):
    stiffer = tuple(
        Intervention(f"point stiffness {o.stiffness:g} -> {o.stiffness * k:g}", {"stiffness": o.stiffness * k})
        for k in (10, 100)
    )
    stiffest, step = o.stiffness * 1000, o.timestep / 10
    out = (
        *stiffer,
        Intervention(
            f"point stiffness {o.stiffness:g} -> {stiffest:g}, timestep {o.timestep:g} -> {step:g}",
            {"stiffness": stiffest, "timestep": step},
        ),
    )
    slower = 1.0 if p_min is None else contact_time_at(p_min)
    if slower > 1.0:
        # one text for every start (the values are in the options), so that the report counts this step as one
        out += (
            Intervention(
                f"point stiffness {stiffest:g} / p_min, timestep {step:g} x p_min^(1/2) (at the theory's least p, "
                f"0 < p_min < 1)",
                {"stiffness": stiffest * slower**2, "timestep": step / slower},
            ),
        )
    return out


def friction_law(o):
    return tuple(
        Intervention(
            f"stiction tolerance {o.stiction_tolerance:g} -> {o.stiction_tolerance / k:g}",
            {"stiction_tolerance": o.stiction_tolerance / k},
        )
        for k in (10, 100)
    )


def discretisation(o):
    return tuple(
        Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}) for k in (4, 16)
    )


def relaxation(o):
    # SAP's dissipation is a relaxation time, TAMSI's Hunt & Crossley's: each takes its own default (the same damping ratio)
    return (
        Intervention(
            f"approximation {o.approximation} -> tamsi (no convex relaxation)",
            {
                "approximation": "tamsi",
                "relaxation_time": None,
                "dissipation": None if o.approximation == "sap" else o.dissipation,
            },
        ),
    )
