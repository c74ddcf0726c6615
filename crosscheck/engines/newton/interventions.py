"""Newton's solvers changed in the way each cause of their ladders names: the interventions that should remove a
disagreement of it.  Every one changes a setting of the Newton solver itself.

MuJoCo Warp (``newton_mujoco``):

* geometry: a thinner capsule (r / 4, r / 16);
* compliance, friction law, feed-forward: the ``mujoco`` engine's own interventions (``crosscheck.engines.mujoco
  .interventions``) where MuJoCo Warp through Newton has the setting (time constant, impedance, impratio; not MuJoCo's
  separate friction time constant, which Newton's SolverMuJoCo does not set, nor a step below a quarter of the run's:
  compliance's strongest, the time constant at a hundredth with the step at a sixteenth, is left out);
* discretisation: the timestep divided by 4 (a MuJoCo Warp step costs ~7 ms of CPU whatever its worlds: a run to
  horizon 2 at a sixteenth of the quick report's step, 10667 steps, costs ~75 CPU seconds);
* float32: Newton's ``SolverMuJoCo(use_mujoco_cpu=True)`` (``Options.mujoco_cpu``): the same converted model stepped
  by MuJoCo in C in float64.

XPBD (``newton_xpbd``), position projection, two families: the projection converged within the step (iterations
2 -> 8 and 32 with the contact relaxation 0.8 -> 1, the full correction), and the projection's step (the timestep
divided by 4 and 16).

Featherstone and the semi-implicit solver (``newton_featherstone``, ``newton_semi_implicit``), penalty contact:

* compliance: a stiffer contact spring (stiffness x 10 at the run's timestep, x 100 at a quarter of it; the damping
  kept critical, 2 sqrt(stiffness)), omega_n dt kept below 1 (Featherstone's explicit contact force);
* friction law: the friction's regularisation shrunk, the slope kf x 10 at the run's timestep, then x 4 and x 16
  with the timestep divided by as much (kf dt kept: a stuck tip's creep speed mu F_n / kf down 4 and 16 times, the
  explicit friction no closer to overshooting).  Why the step with it: the friction is explicit, and once kf dt
  exceeds the tip's effective mass the slope overshoots to the Coulomb bound every step, so a stuck tip chatters at a
  speed the step sets, not kf: from theta 1, varphi -1.9, Psi 0.375, mu 1.125 at timestep 3e-3 (kf dt = 3 at the
  default) Featherstone's tip slips at a mean 0.035 l omega after the stick at kf 1e3, 0.014 at 1e4, and the same
  0.014 at 1e5 (mu F_n / kf = 5.5e-4, 6e-5, 6e-6).  The discretisation's own interventions (the step alone) tell
  the two apart;
* discretisation: the timestep divided by 4 and 16.

Scaled units (section 2.1).  ``crosscheck.studies.interventions`` runs them.
"""

from __future__ import annotations

import math

from crosscheck import engines
from crosscheck.engines.newton.ladder import SHARED, mujoco_options
from crosscheck.engines.spec import Intervention

__all__ = [
    "geometry",
    "mujoco_compliance",
    "mujoco_friction_law",
    "mujoco_feed_forward",
    "mujoco_discretisation",
    "float32",
    "position_projection",
    "penalty_compliance",
    "friction_regularisation",
    "discretisation",
]


def geometry(o):
    return tuple(
        Intervention(f"capsule radius {o.radius:g} -> {o.radius / k:g}", {"radius": o.radius / k}) for k in (4, 16)
    )


#: The shortest timestep an intervention on MuJoCo Warp takes, as a fraction of the run's (cost: module docstring).
MIN_STEP = 1 / 4


def _mujoco(cause: str, o, *, p_min=None) -> tuple:
    """The ``mujoco`` engine's interventions for ``cause`` at MuJoCo Warp's settings, those Newton's SolverMuJoCo has
    and whose step is at least ``MIN_STEP`` of the run's."""
    spec = engines.get("mujoco")
    ivs = spec.interventions_for(cause, spec.options(**mujoco_options(o)), p_min=p_min)
    return tuple(
        iv
        for iv in ivs
        if set(iv.options) <= set(SHARED) and iv.options.get("timestep", o.timestep) >= MIN_STEP * o.timestep
    )


def mujoco_compliance(o, *, p_min=None):
    return _mujoco("compliance", o, p_min=p_min)


def mujoco_friction_law(o, *, p_min=None):
    return _mujoco("friction law", o, p_min=p_min)


def mujoco_feed_forward(o, *, p_min=None):
    return _mujoco("feed-forward", o, p_min=p_min)


def mujoco_discretisation(o):
    return (Intervention(f"timestep {o.timestep:g} -> {o.timestep / 4:g}", {"timestep": o.timestep / 4}),)


def float32(o):
    return (Intervention("MuJoCo Warp (float32) -> MuJoCo in C (float64), same model", {"mujoco_cpu": True}),)


def position_projection(o):
    converged = tuple(
        Intervention(
            f"iterations {o.solver_iterations} -> {n}, contact relaxation {o.contact_relaxation:g} -> 1",
            {"iterations": n, "contact_relaxation": 1.0},
            "iterations",
        )
        for n in (8, 32)
    )
    finer = tuple(
        Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}, "timestep")
        for k in (4, 16)
    )
    return converged + finer


def penalty_compliance(o):
    out = []
    for k, dt in ((10, o.timestep), (100, o.timestep / 4)):
        s = o.stiffness * k
        text = f"stiffness {o.stiffness:g} -> {s:g} (damping {2 * math.sqrt(s):.3g})"
        options = {"stiffness": s, "damping": 2 * math.sqrt(s)}
        if dt != o.timestep:
            text += f", timestep {o.timestep:g} -> {dt:g}"
            options["timestep"] = dt
        out.append(Intervention(text, options))
    return tuple(out)


def friction_regularisation(o):
    kf = o.friction_gain
    out = [Intervention(f"friction slope kf {kf:g} -> {kf * 10:g}", {"friction_gain": kf * 10}, "slope")]
    for k in (4, 16):
        out.append(
            Intervention(
                f"friction slope kf {kf:g} -> {kf * k:g}, timestep {o.timestep:g} -> {o.timestep / k:g} (kf dt kept)",
                {"friction_gain": kf * k, "timestep": o.timestep / k},
                "slope with the step",
            )
        )
    return tuple(out)


def discretisation(o):
    return tuple(
        Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}) for k in (4, 16)
    )
