"""numpy_rod: a crosscheck engine plugin (its entry point ``numpy_rod:ENGINES``, group ``crosscheck.engines``).

Only the declaration lives here, so that ``crosscheck engines`` lists the engine without importing it.
"""

from crosscheck.engines.spec import EngineSpec, Ladder, ReportPlan

__all__ = ["ENGINES"]

ENGINES = (
    EngineSpec(
        name="numpy_rod",
        engine="numpy_rod.engine:ENGINE",
        label="numpy penalty rod",
        libraries=("numpy",),
        tags={"compliant", "time_stepping"},
        # optional: the models between it and the theory (the theory on its capsule, then itself: what is left is its
        # compliance), and what tests that cause (a stiffer spring, its timestep shortened with it)
        ladder=Ladder(
            rungs={"geometry": "capsule", "compliance": "engine"},
            interventions={"compliance": "numpy_rod.interventions:compliance"},
        ),
        # optional: its report sections (6 x 6 outcome maps in the quick report, 12 x 12 in the full one)
        report=ReportPlan(
            maps={"quick": {"timestep": 1e-3}, "full": {"timestep": 5e-4}},
            maps_n={"quick": 6, "full": 12},
            ladder=True,
        ),
    ),
)
