"""MuJoCo changed in the way each cause of its ladder names: the interventions that should remove a disagreement of that cause.

Each function takes the run's ``Options`` and returns ``Intervention`` s,
weakest first (``crosscheck.studies.interventions`` runs them):

* geometry: a thinner capsule (MuJoCo needs r > 0: r / 4, r / 16);
* compliance: a stiffer contact toward the rigid limit, the time constant of
  solref down to a third and a tenth (never below MuJoCo's 2 dt), the last
  with the impedance raised to d0 = dmax = 0.99 (the fraction of the rigid
  force MuJoCo feeds forward at once);
* friction law: a shorter friction time constant (``friction_timeconst``): the
  skew of MuJoCo's friction is the angle between u and u + a_t / B with
  B = 2 / (dmax tau_f) (``crosscheck.engines.mujoco.studies.friction_skew``),
  so tau_f -> 0 makes its friction oppose the slip as Coulomb's does;
* discretisation: the timestep divided by 4 and 16 at the same contact.

Scaled units (section 2.1).
"""

from __future__ import annotations

from crosscheck.engines.spec import Intervention

__all__ = ["geometry", "compliance", "friction_law", "discretisation"]


def geometry(o):
    return tuple(Intervention(f"capsule radius {o.radius:g} -> {o.radius / k:g}", {"radius": o.radius / k}) for k in (4, 16))


def compliance(o):
    floor = 2 * o.timestep
    tc3, tc10 = max(floor, o.timeconst / 3), max(floor, o.timeconst / 10)
    d0, dmax, width, mid, power = o.solimp
    stiff = (max(d0, 0.99), max(dmax, 0.99), width, mid, power)
    return (Intervention(f"time constant {o.timeconst:g} -> {tc3:g}", {"timeconst": tc3}),
            Intervention(f"time constant {o.timeconst:g} -> {tc10:g}, impedance {dmax:g} -> {stiff[1]:g}", {"timeconst": tc10, "solimp": stiff}))


def friction_law(o):
    now = o.timeconst if o.friction_timeconst is None else o.friction_timeconst
    steps = [max(2 * o.timestep, now / k) for k in (6, 30)]
    return tuple(Intervention(f"friction time constant {now:g} -> {tf:g}", {"friction_timeconst": tf}) for tf in steps)


def discretisation(o):
    return tuple(Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}) for k in (4, 16))
