"""MuJoCo: the capsule rod of ``models/rod.xml`` stepped by MuJoCo, and MuJoCo's contact law in continuous time.

Two engines live here:

* ``mujoco``: MuJoCo itself (``engine``: the rollout; ``model``: the MJCF
  model, its start and sensors; ``warning_counts``: MuJoCo's warnings counted);
* ``mujoco_law``: MuJoCo's instantaneous contact law (``law``: reference
  acceleration from solref, impedance from solimp, the regulariser R, the
  elliptic cone) integrated with no time discretisation (``ode``).  It is the
  friction-law rung of MuJoCo's ladder.

MuJoCo-only studies and report sections live in ``crosscheck.studies.mujoco``
and ``crosscheck.report.sections``; they are declared here.
"""

from crosscheck.engines.mujoco import tolerances as mujoco_tol
from crosscheck.engines.spec import EngineSpec, Execution, Ladder, ReportPlan, Validation

__all__ = ["ENGINES"]


ENGINES = (
    EngineSpec(
        name="mujoco",
        engine="crosscheck.engines.mujoco.engine",
        label="MuJoCo",
        libraries=("mujoco",),
        tags={"compliant", "relaxed", "time_stepping", "batched"},
        execution=Execution(one_core={"nthread": 1}),
        validation=Validation(
            tolerances={
                "liftoff_onset": mujoco_tol.MUJOCO_LIFTOFF_ONSET,
                "event_disagreement": mujoco_tol.MUJOCO_EVENT_DISAGREEMENT,
                "event_time": mujoco_tol.MUJOCO_EVENT_TIME,
                "no_jam_below_mu_P": mujoco_tol.MUJOCO_NO_JAM_BELOW_MU_P,
                "corollary_stop": mujoco_tol.MUJOCO_COROLLARY_STOP,
            },
            checks="crosscheck.engines.mujoco.studies.contact:checks",
        ),
        # the models between the theory and MuJoCo: its capsule's contact point, the compliant rod with MuJoCo's matched
        # Kelvin-Voigt law, MuJoCo's own law in continuous time without and with its normal force's feed-forward, MuJoCo
        # itself (crosscheck.studies.ladder runs them; crosscheck.engines.mujoco.studies.ladder says why in this order)
        ladder=Ladder(
            rungs={
                "geometry": "capsule",
                "compliance": "crosscheck.engines.mujoco.studies.ladder:compliant",
                "friction law": "crosscheck.engines.mujoco.studies.ladder:spring_law",
                "feed-forward": "crosscheck.engines.mujoco.studies.ladder:mujoco_law",
                "discretisation": "engine",
            },
            interventions={
                c: f"crosscheck.engines.mujoco.interventions:{c.replace(' ', '_').replace('-', '_')}"
                for c in ("geometry", "compliance", "friction law", "feed-forward", "discretisation")
            },
        ),
        report=ReportPlan(
            maps={"quick": {"timestep": 3e-4, "timeconst": 0.06}, "full": {"timestep": 3e-4, "timeconst": 0.06}},
            convergence={
                "quick": [
                    {"timestep": dt, "timeconst": tc}
                    for dt, tc in ((3e-3, 0.06), (1e-3, 0.06), (3e-4, 0.06), (3e-4, 0.02))
                ],
                "full": [
                    {"timestep": dt, "timeconst": tc}
                    for dt, tc in ((3e-3, 0.06), (1e-3, 0.06), (3e-4, 0.06), (3e-4, 0.02), (1e-4, 0.02), (1e-4, 0.006))
                ],
            },
            # the full report's convergence on 14 x 14 (theta, Theta) starts (the section's default 20 x 20 took 66 s of
            # section time at these six settings, the two at timestep 1e-4 the most)
            convergence_n={"quick": 7, "full": 14},
            # 24 x 24 full maps, as the rigid engine's and Bullet's: the theory's boundary probes of a grid (three
            # random directions at four radii per start, an integration each) cost 62 s of the 98 s its 32 x 32 maps
            # took in the full report, and three engines on one grid pay them once
            maps_n={"quick": 10, "full": 24},
            sections="crosscheck.engines.mujoco.sections:sections",
            onset=False,
            order=10,
            ladder=True,
            # a start costs ~0.8 s of section time, ladder and interventions (full report, measured: 174 s for its 210
            # disagreements): the quick report ladders 8 of its maps' disagreements, the full report an even spread
            # of 30 (~25 s)
            ladder_states={"quick": 8, "full": 30},
        ),
    ),
    EngineSpec(
        name="mujoco_law",
        engine="crosscheck.engines.mujoco.ode",
        label="MuJoCo's law in continuous time",
        libraries=("mujoco",),
        tags={"compliant", "relaxed", "continuous"},
    ),
)
