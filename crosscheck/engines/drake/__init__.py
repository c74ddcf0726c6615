"""Drake: the rod as a ``MultibodyPlant`` (the chain of ``models/rod.xml``, a capsule on a half-space) under Drake's contact approximations.

One module (``engine``) serves five registered engines, one per contact
approximation (``Options.approximation``, fixed by each record's ``defaults``):

* ``drake_continuous``: a continuous plant (time_step 0), point contact with
  Hunt & Crossley dissipation and Stribeck friction, error-controlled integrator;
* ``drake_sap``: discrete SAP, a convex relaxation of compliant contact (linear
  Kelvin-Voigt dissipation, its own friction regularisation);
* ``drake_similar``, ``drake_lagged``: the convex approximations of Hunt &
  Crossley contact with regularised friction;
* ``drake_tamsi``: the non-convex TAMSI (deprecated in Drake for removal after
  2026-09-01; refused with a ValueError by a Drake that no longer has it).

``options`` holds the scaled ``Options`` (importing it does not import
pydrake), ``model`` the diagram and ``engine`` the runs.  Importing this
package does not import pydrake either.
"""

from crosscheck.engines.spec import EngineSpec, ReportPlan

__all__ = ["ENGINES"]

_TAGS = {
    "continuous": {"compliant", "continuous"},
    "sap": {"compliant", "relaxed", "time_stepping"},
    "similar": {"compliant", "relaxed", "time_stepping"},
    "lagged": {"compliant", "relaxed", "time_stepping"},
    "tamsi": {"compliant", "time_stepping"},
}

_LABELS = {"continuous": "Drake continuous", "sap": "Drake SAP", "similar": "Drake Similar", "lagged": "Drake Lagged",
           "tamsi": "Drake TAMSI"}

#: Report settings by cost (benchmarks/bench_drake.py; one core): the quick map section is 3 maps of 10 x 10 starts
#: at horizon 2, i.e. <= 300 runs, so a run must take <= ~65 ms for the section to stay under ~20 s.
#: Discrete approximations vary the timestep with the stiffness held, then stiffen at the finest timestep (as
#: MuJoCo's plan varies timestep, then timeconst); the continuous plant varies the stiffness, stiffer towards the
#: rigid theory, at a fixed row spacing.
_MAPS = {
    "continuous": {"quick": {"timestep": 1e-3}, "full": {"timestep": 3e-4}},
    "sap": {"quick": {"timestep": 1e-3}, "full": {"timestep": 3e-4}},
    "similar": {"quick": {"timestep": 1e-3}, "full": {"timestep": 3e-4}},
    "lagged": {"quick": {"timestep": 3e-3}, "full": {"timestep": 1e-3}},
    "tamsi": {"quick": {"timestep": 1e-3}, "full": {"timestep": 3e-4}},
}


def _discrete_convergence(quick: list, full: list) -> dict:
    return {"quick": [{"timestep": dt, "stiffness": k} for dt, k in quick], "full": [{"timestep": dt, "stiffness": k} for dt, k in full]}


_CONVERGENCE = {
    "continuous": {"quick": [{"timestep": 1e-3, "stiffness": k} for k in (1e3, 1e4, 1e5)],
                   "full": [{"timestep": 1e-3, "stiffness": k} for k in (1e3, 1e4, 1e5, 1e6)]},
    "sap": _discrete_convergence([(3e-3, 1e4), (1e-3, 1e4), (3e-4, 1e4), (3e-4, 1e5)],
                                 [(3e-3, 1e4), (1e-3, 1e4), (3e-4, 1e4), (3e-4, 1e5), (1e-4, 1e5), (1e-4, 1e6)]),
    "similar": _discrete_convergence([(3e-3, 1e4), (1e-3, 1e4), (3e-4, 1e4), (3e-4, 1e5)],
                                     [(3e-3, 1e4), (1e-3, 1e4), (3e-4, 1e4), (3e-4, 1e5), (1e-4, 1e5), (1e-4, 1e6)]),
    "lagged": _discrete_convergence([(3e-3, 1e4), (1e-3, 1e4), (1e-3, 1e5)],
                                    [(3e-3, 1e4), (1e-3, 1e4), (3e-4, 1e4), (3e-4, 1e5), (1e-4, 1e6)]),
    "tamsi": _discrete_convergence([(3e-3, 1e4), (1e-3, 1e4), (3e-4, 1e4), (3e-4, 1e5)],
                                   [(3e-3, 1e4), (1e-3, 1e4), (3e-4, 1e4), (3e-4, 1e5), (1e-4, 1e5), (1e-4, 1e6)]),
}

ENGINES = tuple(
    EngineSpec(
        name=f"drake_{a}", module="crosscheck.engines.drake.engine", label=_LABELS[a], slug=f"drake_{a}", libraries=("drake",),
        defaults={"approximation": a}, one_core={"workers": 1},
        solver_columns=("contact_rows", "steps", "derivative_evaluations", "error_shrinkages", "failed"),
        tags=_TAGS[a],
        # no event-tolerance profile: not measured yet (validate does not judge these engines' events)
        tolerances=None,
        report=ReportPlan(maps=_MAPS[a], convergence=_CONVERGENCE[a], order=40 + i),
    )
    for i, a in enumerate(("sap", "continuous", "similar", "lagged", "tamsi"))
)
