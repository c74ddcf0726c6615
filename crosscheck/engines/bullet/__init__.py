"""Bullet (PyPI pybullet): the capsule rod of ``models/rod.xml`` on Bullet's Featherstone multibody and its PGS contact solver.

``options``: the run parameters (imports no pybullet); ``model``: the
pybullet world (the five-joint chain, the capsule, the plane, the settings
that Bullet's defaults get wrong) and one rollout; ``engine``: ``simulate``
and ``sweep``.  Importing this package does not import pybullet.
"""

from crosscheck.engines.spec import EngineSpec, ReportPlan

__all__ = ["ENGINES"]

ENGINES = (
    EngineSpec(
        name="bullet", module="crosscheck.engines.bullet.engine", label="Bullet", libraries=("pybullet",),
        one_core={"workers": 1}, solver_columns=("contact_steps", "max_points"),
        # An impulse-based rigid step: PGS on the velocity-level contact problem of each step (a unilateral
        # normal row that lets a gap close within the step, friction clipped to the cone), ERP only removing
        # penetration; no force build-up time and no creep (crosscheck.engines.bullet.engine's docstring).
        tags={"rigid", "time_stepping"},
        # Not measured yet: validate does not judge its events (no event-tolerance profile).
        tolerances=None,
        # ~30 us per step with the record (benchmarks/bench_bullet.py): a 10 x 10 map to horizon 2 at timestep
        # 2e-3 is ~3 s, so the quick report's three maps stay under 20 s; the full report at the default 1e-3.
        report=ReportPlan(maps={"quick": {"timestep": 2e-3}, "full": {"timestep": 1e-3}},
                          convergence={"quick": [{"timestep": dt} for dt in (1e-2, 3e-3, 1e-3)],
                                       "full": [{"timestep": dt} for dt in (3e-3, 1e-3, 3e-4)]},
                          order=50),
    ),
)
