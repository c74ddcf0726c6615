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

from crosscheck.engines.drake.options import LABELS
from crosscheck.engines.spec import EngineSpec, Execution, Ladder, ReportPlan

__all__ = ["ENGINES"]

_TAGS = {
    "continuous": {"compliant", "continuous"},
    "sap": {"compliant", "relaxed", "time_stepping"},
    "similar": {"compliant", "relaxed", "time_stepping"},
    "lagged": {"compliant", "relaxed", "time_stepping"},
    "tamsi": {"compliant", "time_stepping"},
}


#: Report settings by cost (python benchmarks/bench_drake.py --every 3: 50 of the quick maps' slipping starts, one
#: core, while other jobs shared the 2 cores): the quick map section runs 3 maps of 10 x 10 starts at horizon 2, half
#: of which slip at t = 0 and are run, so a run must take <= ~0.13 s for the section to stay under ~20 s.  Measured
#: median (max) s/run and the section's estimate: SAP 0.067 (0.16), ~11 s and Similar 0.070 (0.17), ~12 s at timestep
#: 2e-3 (a force-free step costs ~25 us, a stuck SAP step ~170 us); Lagged 0.10 (0.18), ~16 s at 3e-3; TAMSI 0.12
#: (0.17), ~17 s at 1e-3; the continuous plant 0.14 (0.30), ~24 s at rows of 2e-3 with accuracy 1e-3 and stiction
#: tolerance 1e-3 (its integrator steps cost ~60 us and it takes 1-3 per row; the default accuracy 1e-6 and stiction
#: tolerance 1e-4 triple it). Re-measured after the engine's step loop stopped making numpy calls per step (the same
#: command with --repeat 2, CPU time, 2026-11-25): SAP 0.051 (0.13), Similar 0.052 (0.12), Lagged 0.076 (0.083),
#: TAMSI 0.062 (0.067), continuous 0.095 (0.17) s/run, 13-26 % below the engine before it in the same conditions;
#: Drake's bare Simulator.AdvanceTo over the same steps takes 0.49 (TAMSI) to 0.74 (continuous) of the engine's time.
#: Convergence: discrete approximations refine the timestep at stiffness 1e4, then stiffen (as MuJoCo's plan
#: refines timestep, then timeconst); the continuous plant stiffens at a fixed row spacing.  SAP and Similar glide off
#: a slipping tip at any of these settings (crosscheck.engines.drake.engine): their convergence section shows it
#: rather than a convergence to the theory.
_CONTINUOUS_QUICK = {"timestep": 2e-3, "accuracy": 1e-3, "stiction_tolerance": 1e-3}
_MAPS = {
    "continuous": {
        "quick": _CONTINUOUS_QUICK,
        "full": {"timestep": 1e-3, "accuracy": 1e-4, "stiction_tolerance": 1e-3},
    },
    "sap": {"quick": {"timestep": 2e-3}, "full": {"timestep": 1e-3}},
    "similar": {"quick": {"timestep": 2e-3}, "full": {"timestep": 1e-3}},
    "lagged": {"quick": {"timestep": 3e-3}, "full": {"timestep": 1e-3}},
    "tamsi": {"quick": {"timestep": 1e-3}, "full": {"timestep": 1e-3}},
}


def _discrete_convergence(quick: list, full: list) -> dict:
    return {
        "quick": [{"timestep": dt, "stiffness": k} for dt, k in quick],
        "full": [{"timestep": dt, "stiffness": k} for dt, k in full],
    }


_QUICK_STEPS = [(4e-3, 1e4), (2e-3, 1e4), (1e-3, 1e4), (1e-3, 1e5)]
_CONVERGENCE = {
    "continuous": {
        "quick": [{**_CONTINUOUS_QUICK, "stiffness": k} for k in (1e3, 1e4, 1e5)],
        "full": [
            {"timestep": 1e-3, "accuracy": 1e-4, "stiction_tolerance": 1e-3, "stiffness": k} for k in (1e3, 1e4, 1e5)
        ],
    },
    "sap": _discrete_convergence(_QUICK_STEPS, _QUICK_STEPS),
    "similar": _discrete_convergence(_QUICK_STEPS, _QUICK_STEPS),
    "lagged": _discrete_convergence(
        [(6e-3, 1e4), (3e-3, 1e4), (3e-3, 1e5)], [(6e-3, 1e4), (3e-3, 1e4), (1e-3, 1e4), (1e-3, 1e5)]
    ),
    "tamsi": _discrete_convergence(_QUICK_STEPS, _QUICK_STEPS),
}

#: Grid sizes by cost: a Drake run costs 2-4 x a MuJoCo run at the quick maps' options (table above) and 5 approximations
#: share the report's time, so each map is 6 x 6 (quick) and 12 x 12 (full) instead of 10 x 10 and 32 x 32, and each
#: convergence grid 4 x 4 and 6 x 6 in (theta, Theta) (MuJoCo's: 7 x 7 and 20 x 20), the full one over the quick one's
#: settings (timestep down to 1e-3, then a stiffer contact).  Measured in a full report (2 cores, shared): SAP's maps took
#: 47 s at 16 x 16 and its convergence 99 s at 8 x 8 over timesteps down to 3e-4, which would have put the five
#: approximations alone past 12 minutes.
_MAPS_N = {"quick": 6, "full": 12}
_CONVERGENCE_N = {"quick": 4, "full": 6}

#: The models between the theory and each approximation (``crosscheck.studies.ladder``; ``ladder`` here): the capsule's
#: contact point, the compliant rod with Drake's normal law, Drake's law in continuous time, the approximation itself.
_LADDER = {
    "geometry": "capsule",
    "compliance": "crosscheck.engines.drake.ladder:compliant",
    "friction law": "crosscheck.engines.drake.ladder:continuous",
    "discretisation": "engine",
}
#: The convex approximations' ladder: TAMSI's non-convex step at the same timestep first (discretisation), then the
#: approximation itself (its relaxation).
_LADDER_RELAXED = {**_LADDER, "discretisation": "crosscheck.engines.drake.ladder:tamsi", "relaxation": "engine"}
#: The continuous plant's own ladder: its regularised friction is its last difference (no discretisation).
_LADDER_CONTINUOUS = {
    "geometry": "capsule",
    "compliance": "crosscheck.engines.drake.ladder:compliant",
    "friction law": "engine",
}


#: Starts each approximation's ladder runs in the full report, by cost: a start costs 3.5 s of section time in
#: Lagged's ladder and interventions, 1.9 s in the continuous plant's and 0.9-1.1 s in SAP's, Similar's and TAMSI's
#: (measured in the full report), so each ladders what ~10-20 s buys.
_LADDER_STATES = {
    "lagged": {"quick": 3, "full": 6},
    "continuous": {"quick": 3, "full": 8},
    "sap": {"quick": 3, "full": 8},
    "similar": {"quick": 3, "full": 8},
    "tamsi": {"quick": 3, "full": 8},
}


def _ladder(a: str) -> Ladder:
    rungs = _LADDER_CONTINUOUS if a == "continuous" else _LADDER_RELAXED if "relaxed" in _TAGS[a] else _LADDER
    return Ladder(
        rungs=rungs,
        interventions={c: f"crosscheck.engines.drake.interventions:{c.replace(' ', '_')}" for c in rungs},
    )


ENGINES = tuple(
    EngineSpec(
        name=f"drake_{a}",
        engine="crosscheck.engines.drake.engine",
        label=LABELS[a],
        libraries=("drake",),
        install="crosscheck[drake]",
        defaults={"approximation": a},
        tags=_TAGS[a],
        # no event-tolerance profile (validation): not measured yet (validate does not judge these engines' events)
        execution=Execution(
            one_core={"workers": 1},
            solver_columns=("contact_rows", "steps", "derivative_evaluations", "error_shrinkages", "failed"),
            stops_at_event=True,
        ),
        ladder=_ladder(a),
        report=ReportPlan(
            slug=f"drake_{a}",
            maps=_MAPS[a],
            convergence=_CONVERGENCE[a],
            maps_n=_MAPS_N,
            convergence_n=_CONVERGENCE_N,
            ladder=True,
            ladder_states=_LADDER_STATES.get(a),
            order=40 + i,
        ),
    )
    for i, a in enumerate(("sap", "continuous", "similar", "lagged", "tamsi"))
)
