"""PhysX (PyPI sapien, SAPIEN 3 on CPU): the capsule rod of ``models/rod.xml`` as a PhysX 5 articulation, TGS or PGS.

``options``: the run parameters (imports no SAPIEN); ``model``: the PhysX scene (the five-joint chain, the
capsule, the plane, every setting PhysX's defaults get wrong) and one rollout; ``engine``: ``simulate`` and
``sweep``; ``chain``: the record of a chain rollout in SI.  Two registered names, one per solver:
``physx_tgs`` (PhysX 5's default, temporal Gauss-Seidel) and ``physx_pgs`` (projected Gauss-Seidel).
Importing this package does not import SAPIEN.

Its friction is a pyramid where PGS solves it, and no setting of PhysX through SAPIEN changes that.  PhysX's patch
friction puts two perpendicular 1D friction constraints on each contact patch; PGS processes the two axes separately
(each clamped on its own: a square pyramid), TGS works with their combined impulse (PhysX 5.6's documentation of
``PxFrictionType``).  SAPIEN 3.0.3 ships PhysX 5.3.1 and its ``PhysxSceneConfig`` has no friction type (its settings:
gravity, bounce_threshold, enable_pcm, enable_tgs, enable_ccd, enable_enhanced_determinism,
enable_friction_every_iteration, cpu_workers), and PhysX 5 deprecates every friction type but the patch's.  So the
ladder has no "pyramid cone" rung for PhysX: the one switch that changes the cone, PGS to TGS, changes the solver with
it (the two are the two registered engines, compared on the same maps).
"""

from crosscheck.engines.physx.options import LABELS as _LABELS
from crosscheck.engines.spec import EngineSpec, Execution, Ladder, ReportPlan

__all__ = ["ENGINES"]


#: Report settings by cost (python benchmarks/bench_physx.py): a step costs ~60-90 us with the record (a fresh
#: scene per run, ~2 ms), ~3 x Bullet's, so a run to horizon 2 at the default timestep 1e-3 takes ~0.15 s, cut to
#: about half by stopping at the first event.  Each of the two solvers gets 12 x 12 maps in the full report, as
#: each of Drake's approximations, and convergence in the timestep on 6 x 6 (theta, Theta) grids.  Measured: the quick report's sections of both solvers (maps, contact, onset, IC, rounding, convergence, ladder,
#: interventions) took 95 s of section time at 6 x 6 maps and 4 x 4 convergence grids (2 cores shared by other jobs;
#: rounding and maps the largest); the quick grids are therefore 4 x 4 maps and 3 x 3 convergence grids, which the
#: quick report (and tests/test_report.py, which runs it) can afford for three engines more.
_PLAN = dict(
    maps={"quick": {"timestep": 1e-3}, "full": {"timestep": 1e-3}},
    convergence={
        "quick": [{"timestep": dt} for dt in (4e-3, 2e-3, 1e-3)],
        "full": [{"timestep": dt} for dt in (4e-3, 2e-3, 1e-3, 5e-4)],
    },
    maps_n={"quick": 4, "full": 12},
    convergence_n={"quick": 3, "full": 6},
    ladder=True,
)

#: Its models in between (crosscheck.studies.ladder): the capsule's contact point, then PhysX itself.
_LADDER = {"geometry": "capsule", "discretisation": "engine"}

ENGINES = tuple(
    EngineSpec(
        name=f"physx_{s}",
        engine=f"crosscheck.engines.physx.{'engine' if s == 'tgs' else 'pgs'}",
        label=_LABELS[s],
        libraries=("sapien",),
        install="crosscheck[physx]",
        defaults={"solver": s},
        tags={"rigid", "time_stepping"},
        # no event-tolerance profile (validation): not measured (validate does not judge its events)
        execution=Execution(
            one_core={"workers": 1}, solver_columns=("contact_steps", "max_points"), stops_at_event=True
        ),
        ladder=Ladder(rungs=_LADDER, interventions={c: f"crosscheck.engines.physx.interventions:{c}" for c in _LADDER}),
        report=ReportPlan(**_PLAN, order=60 + i),
    )
    for i, s in enumerate(("tgs", "pgs"))
)
