"""The rigid engine: the rod as a Pinocchio multibody model, stepped by a Moreau / Stewart-Trinkle scheme on Pinocchio's NCP solvers.

``model``: the rod's chain (PX, PY, PZ, RZ, RX), its M, C, g, Jacobians and
Delassus operator (equal to the analytic terms to 1e-14, ``crosscheck.engines.pinocchio.studies.dynamics_terms``);
``options``: the run parameters; ``stepper``: the exact-cone time-stepper and the engine's ``simulate`` and
``sweep``; ``closed_form``, ``ncp`` and ``batch``: the same step for a batch of states in numpy, with the terms
and the one-contact NCP in closed form (the default for sweeps of 16 states or more).
"""

from crosscheck.engines.pinocchio import tolerances as pinocchio_tol
from crosscheck.engines.spec import EngineSpec, Execution, ReportPlan, Validation

__all__ = ["ENGINES"]


ENGINES = (
    EngineSpec(
        name="pinocchio",
        engine="crosscheck.engines.pinocchio.stepper",
        label="Pinocchio",
        libraries=("pin",),
        tags={"rigid", "time_stepping"},
        validation=Validation(
            tolerances={
                "liftoff_onset": pinocchio_tol.RIGID_LIFTOFF_ONSET,
                "event_disagreement": pinocchio_tol.RIGID_EVENT_DISAGREEMENT,
                "event_time": pinocchio_tol.RIGID_EVENT_TIME,
                "no_jam_below_mu_P": pinocchio_tol.RIGID_NO_JAM_BELOW_MU_P,
                "corollary_stop": pinocchio_tol.RIGID_COROLLARY_STOP,
            },
            checks="crosscheck.engines.pinocchio.studies.rigid:checks",
            dynamics="crosscheck.engines.pinocchio.studies.dynamics_terms",
        ),
        # A chunk is one closed-form batch, whose step costs ~0.3 ms of numpy calls almost whatever its size: 128 states
        # step at ~2.3e5 steps/s on one core, 32 at ~0.9e5
        # (benchmarks/bench_pinocchio_engine.py).
        execution=Execution(
            one_core={"workers": 1},
            solver_columns=("contact_steps", "unconverged_steps", "max_iterations"),
            sweep_chunk=128,
        ),
        # the quick report at a coarser timestep (its cost is the NCP's), drawn beside MuJoCo's maps
        report=ReportPlan(
            slug="rigid",
            maps={"quick": {"timestep": 3e-3}, "full": {"timestep": 1e-3}},
            beside="mujoco_maps",
            convergence={
                "quick": [{"timestep": dt} for dt in (1e-2, 3e-3, 1e-3)],
                "full": [{"timestep": dt} for dt in (3e-3, 1e-3, 3e-4)],
            },
            convergence_n={"quick": 5, "full": 14},
            # MuJoCo's and Bullet's 24 x 24 grids: the theory's boundary probes of each map paid once for the three
            maps_n={"quick": 10, "full": 24},
            sections="crosscheck.engines.pinocchio.sections:sections",
            order=20,
        ),
    ),
)
