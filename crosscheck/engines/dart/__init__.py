"""DART (PyPI dartpy): the capsule rod of ``models/rod.xml`` as a DART skeleton under its boxed-LCP contact solver.

``options``: the run parameters (imports no dartpy); ``model``: the DART world (the five-joint chain, the
capsule, the plane, the collision detector that has a capsule) and one rollout; ``console``: DART's C++ warnings
on stderr, captured and counted; ``engine``: ``simulate`` and ``sweep``.  One registered name, ``dart``: DART's
default ``BoxedLcpConstraintSolver`` with Dantzig's solver (dartpy 6.20 gives PGS no constructor, so it is not a
second engine).  Importing this package does not import dartpy.
"""

from crosscheck.engines.spec import EngineSpec, Execution, Ladder, ReportPlan

__all__ = ["ENGINES"]

#: Its models in between (crosscheck.studies.ladder, ``crosscheck.engines.dart.ladder``): the capsule's contact point,
#: DART's step with Coulomb's cone, with the pyramid, then DART itself (its friction bound fixed before the friction).
_LADDER = {
    "geometry": "capsule",
    "discretisation": "crosscheck.engines.dart.ladder:coulomb_step",
    "pyramid cone": "crosscheck.engines.dart.ladder:pyramid_step",
    "friction bound": "engine",
}

ENGINES = (
    EngineSpec(
        name="dart",
        engine="crosscheck.engines.dart.engine",
        label="DART",
        libraries=("dartpy",),
        install="crosscheck[dart]",
        tags={"rigid", "time_stepping"},
        # no event-tolerance profile (validation): not measured (validate does not judge its events)
        execution=Execution(
            one_core={"workers": 1}, solver_columns=("contact_steps", "max_points"), stops_at_event=True
        ),
        ladder=Ladder(
            rungs=_LADDER,
            interventions={c: f"crosscheck.engines.dart.interventions:{c.replace(' ', '_')}" for c in _LADDER},
        ),
        # Cost (python benchmarks/bench_dart.py, 2 cores shared): DART's bare step ~80 us, ~160 us with the record
        # and classifier, a run to horizon 2 at the default timestep ~0.3 s, twice PhysX's; so the grids are the
        # smallest the sections take: 4 x 4 maps (quick), 12 x 12 (full), convergence in the timestep on 3 x 3 and
        # 6 x 6 (theta, Theta) grids.  The quick report's DART sections took 82 s of section time at 6 x 6 and 4 x 4.
        report=ReportPlan(
            maps={"quick": {"timestep": 1e-3}, "full": {"timestep": 1e-3}},
            convergence={
                "quick": [{"timestep": dt} for dt in (4e-3, 2e-3, 1e-3)],
                "full": [{"timestep": dt} for dt in (4e-3, 2e-3, 1e-3, 5e-4)],
            },
            maps_n={"quick": 4, "full": 12},
            convergence_n={"quick": 3, "full": 6},
            ladder=True,
            order=70,
        ),
    ),
)
