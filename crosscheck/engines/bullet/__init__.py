"""Bullet (PyPI pybullet): the capsule rod of ``models/rod.xml`` on Bullet's Featherstone multibody and its PGS contact solver.

``options``: the run parameters (imports no pybullet); ``model``: the
pybullet world (the five-joint chain, the capsule, the plane, the settings
that Bullet's defaults get wrong) and one rollout; ``engine``: ``simulate``
and ``sweep``.  Importing this package does not import pybullet.
"""

from crosscheck.engines.spec import EngineSpec, Execution, Ladder, ReportPlan

__all__ = ["ENGINES"]


ENGINES = (
    EngineSpec(
        name="bullet",
        engine="crosscheck.engines.bullet.engine",
        label="Bullet",
        libraries=("pybullet",),
        install="crosscheck[bullet]",
        execution=Execution(
            one_core={"workers": 1},
            solver_columns=("contact_steps", "unconverged_steps", "max_iterations", "max_points"),
            stops_at_event=True,
        ),
        # An impulse-based rigid step: PGS on the velocity-level contact problem of each step (a unilateral
        # normal row that lets a gap close within the step, friction clipped to the cone), ERP only removing
        # penetration; no force build-up time and no creep (crosscheck.engines.bullet.engine's docstring).
        tags={"rigid", "time_stepping"},
        # No event-tolerance profile: validate does not judge its events.  Not for want of runs but of a settled
        # engine: at mu >= 1 Bullet's PGS misses its tolerance in 15-27 % of the contact steps (cycling between two
        # impulses in part of them), which a profile would freeze as "measured" (engine.py's docstring).
        # its models in between (crosscheck.studies.ladder): the capsule's contact point, then Bullet's friction law in
        # continuous time (the capsule whose friction opposes diag(D)^-1 u in world axes rather than the slip u: Bullet's
        # fixed friction rows, crosscheck.engines.bullet.law), then Bullet itself (its PGS step)
        ladder=Ladder(
            rungs={
                "geometry": "capsule",
                "friction law": "crosscheck.engines.bullet.law:friction_law",
                "discretisation": "engine",
            },
            interventions={
                c: f"crosscheck.engines.bullet.interventions:{c.replace(' ', '_')}"
                for c in ("geometry", "friction law", "discretisation")
            },
        ),
        # ~28 us per step with the record (benchmarks/bench_bullet.py).  The quick report's three 10 x 10 maps took 7.2 s
        # at the default timestep 1e-3 (the agreement study stops each run after its analytic event), so both reports
        # use it.  Drawn beside the rigid engine's maps: the same rigid Coulomb contact in another time-stepper.
        # Convergence over the timestep on 5 x 5 (quick, ~4 s) and 14 x 14 (full, ~2 min) starts of its grid.
        report=ReportPlan(
            maps={"quick": {"timestep": 1e-3}, "full": {"timestep": 1e-3}},
            beside="rigid_maps",
            convergence={
                "quick": [{"timestep": dt} for dt in (1e-2, 3e-3, 1e-3)],
                "full": [{"timestep": dt} for dt in (3e-3, 1e-3, 3e-4)],
            },
            convergence_n={"quick": 5, "full": 10},  # (14 x 14 took 21-25 s of section time in the full report)
            # 24 x 24 full maps, as MuJoCo's and the rigid engine's: its 32 x 32 took 90 s in the full report beside five
            # Drake engines
            maps_n={"quick": 10, "full": 24},
            ladder=True,
            order=50,
            sections="crosscheck.engines.bullet.sections:sections",
        ),
    ),
)
