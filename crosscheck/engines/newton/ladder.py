"""Newton's models in between, for its engines' ladders (``crosscheck.studies.ladder``): MuJoCo's models and MuJoCo in C
for MuJoCo Warp, the compliant rod and the penalty law at a fine step for Featherstone.

* ``newton_mujoco`` is MuJoCo's model in float32 (``crosscheck.engines.newton.model``), so its ladder is MuJoCo's
  (the capsule point, the compliant rod with MuJoCo's matched law, MuJoCo's law in continuous time without and with
  its feed-forward: the rungs the ``mujoco`` engine declares, at MuJoCo Warp's contact settings), then MuJoCo in C at
  the same settings and timestep (``mujoco_c``: discretisation, in float64), then MuJoCo Warp itself: a start whose
  outcome first turns to MuJoCo Warp's there differs from MuJoCo in C by float32 alone ("float32").
* ``newton_featherstone``'s penalty contact pushes with F_n = ke delta + kd min(delta', 0) (the damping only while the
  capsule approaches the plane) and its friction is min(mu F_n, kf |u|) opposite the slip u (Newton's
  ``eval_body_contact``): in scaled units F_n = stiffness delta + damping delta', the compliant rod's Kelvin-Voigt law
  delta / eps^2 + (xi / eps) delta' with eps = 1 / sqrt(stiffness), xi = damping / sqrt(stiffness) (2 at the
  defaults), with exact Coulomb friction (``compliant``: compliance).  The next rung is the penalty law itself in
  nearly continuous time (``penalty_fine``: Featherstone at 1/16 of the run's timestep, every other setting the
  run's): it adds the friction's regularisation (a stuck tip creeps at up to mu F_n / kf) and the damping's one
  side (friction law); Featherstone at the run's timestep is the last rung (discretisation).

Scaled units (section 2.1).
"""

from __future__ import annotations

import math

from crosscheck import engines
from crosscheck.engines.spec import resolve

__all__ = [
    "mujoco_options",
    "mujoco_rung",
    "compliant_mujoco",
    "spring_law",
    "law",
    "mujoco_c",
    "compliant",
    "penalty_fine",
    "FINE",
]

#: MuJoCo's options that MuJoCo Warp through Newton sets the same way (``crosscheck.engines.newton.model``).
SHARED = ("timestep", "radius", "timeconst", "dampratio", "solimp", "impratio", "solver_tolerance")

#: The penalty law's fine step: the run's timestep over this.
FINE = 16


def mujoco_options(options) -> dict:
    """MuJoCo's options (``crosscheck.engines.mujoco.options.Options`` fields) of MuJoCo Warp's run ``options``."""
    return {k: getattr(options, k) for k in SHARED}


def mujoco_rung(cause: str):
    """The rung the ``mujoco`` engine declares for ``cause``, run at MuJoCo Warp's settings (module docstring)."""

    def rung(rod, state, mu, *, horizon, thresholds, options):
        spec = engines.get("mujoco")
        fn = resolve(spec.ladder[cause])
        return fn(
            rod, state, mu, horizon=horizon, thresholds=thresholds, options=spec.options(**mujoco_options(options))
        )

    rung.__name__ = rung.__qualname__ = f"mujoco_{cause.replace(' ', '_').replace('-', '_')}"
    return rung


compliant_mujoco = mujoco_rung("compliance")
spring_law = mujoco_rung("friction law")
law = mujoco_rung("feed-forward")


def mujoco_c(rod, state, mu, *, horizon, thresholds, options):
    """MuJoCo in C (the ``mujoco`` engine, float64) at MuJoCo Warp's settings and timestep."""
    return engines.get("mujoco").simulate(
        rod, state, mu, horizon=horizon, thresholds=thresholds, **mujoco_options(options)
    )


def compliant(rod, state, mu, *, horizon, thresholds, options):
    """The compliant rod at C with the penalty contact's normal law and parameters (module docstring), rows at the run's
    timestep."""
    k = options.stiffness
    return engines.get("compliant").simulate(
        rod,
        state,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        eps=1.0 / math.sqrt(k),
        xi=options.damping / math.sqrt(k),
        law="kelvin-voigt",
        radius=options.radius,
        timestep=options.timestep,
    )


def penalty_fine(rod, state, mu, *, horizon, thresholds, options):
    """The same Newton solver at 1/``FINE`` of the run's timestep, every other setting the run's: its contact law in
    nearly continuous time."""
    given = {k: getattr(options, k) for k in options.__dataclass_fields__}
    return engines.get(f"newton_{options.solver}").simulate(
        rod, state, mu, horizon=horizon, thresholds=thresholds, **{**given, "timestep": options.timestep / FINE}
    )
