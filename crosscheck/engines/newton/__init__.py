"""Newton (PyPI newton, on NVIDIA Warp): the rod of ``models/rod.xml`` under four of Newton's solvers, many worlds at once.

One module (``engine``) runs every solver; each registered engine has a module of its own (``mujoco_warp``, ``xpbd``,
``featherstone``, ``semi_implicit``) whose ``Options`` class fixes its solver (``Options.solver``):

* ``newton_mujoco``: ``SolverMuJoCo``, MuJoCo Warp in float32 with the ``mujoco`` engine's contact (elliptic cone,
  solref, solimp, Newton's method): the same model as MuJoCo in C, so the two are compared at the same settings;
* ``newton_xpbd``: ``SolverXPBD``, position-based dynamics: the contact a position projection within the step;
* ``newton_featherstone``: ``SolverFeatherstone``, reduced coordinates with Newton's penalty contact (a spring-damper
  normal force and friction regularised by a viscous slope);
* ``newton_semi_implicit``: ``SolverSemiImplicit``, the same penalty contact in maximal coordinates, its D6 joint a
  penalty spring (the rod's own axis locked by a torsion spring: ``options.SemiImplicitOptions``).

The rod is one body on a D6 joint with the five coordinates of ``models/rod.xml`` (no axial spin:
``crosscheck.engines.newton.model``).  Warp compiles every solver's kernels at their first use and caches them on
disk (``~/.cache/warp``); ``crosscheck.engines.newton.model.compile_seconds`` says how long a process spent on them.
``options`` holds the scaled ``Options`` (importing it imports no warp); ``model`` the Newton model, ``engine`` the
runs.  The engines are declared whether or not Newton is installed: where it is not, ``crosscheck engines`` lists
them as not installed with their pip line (``pip install crosscheck[newton]``), a run of one is refused in one line,
and the report skips their sections (``EngineSpec.unavailable``).
"""

from __future__ import annotations

from crosscheck.engines.newton.options import LABELS as _LABELS
from crosscheck.engines.spec import EngineSpec, Execution, Ladder, ReportPlan

__all__ = ["ENGINES"]


_TAGS = {
    # MuJoCo's soft, convex contact (as the mujoco engine's tags)
    "mujoco": {"compliant", "relaxed", "time_stepping", "batched"},
    # a position projection of a non-penetration constraint within the step: no force build-up time
    "xpbd": {"rigid", "time_stepping", "batched"},
    # a penalty spring-damper
    "featherstone": {"compliant", "time_stepping", "batched"},
    "semi_implicit": {"compliant", "time_stepping", "batched"},
}

#: Report settings by cost, in CPU seconds (the 2 cores were shared ~10-fold while measuring, so wall times were 10-15
#: x these).  On CPU a MuJoCo Warp step costs ~7 ms of CPU whatever its iteration cap (its solver converges in < 4
#: iterations: 100/50, 10/10 and 4/4 give the same record) and about as much at 4 worlds as at 64: its cost is its kernel
#: launches, so a map of n x n starts, one block of worlds, costs its step count, and a single ``simulate`` (the contact
#: and IC sections call it per start) costs as much as a map.  Featherstone's quick sections at timestep 1e-3 and 6 x 6
#: maps took 220 s (maps), 211 s (rounding), 67 s (contact), 27 s (IC) of wall time on the shared cores.  Hence: quick
#: at timestep 3e-3 (667 steps to horizon 2) on 4 x 4 maps and 3 x 3 convergence grids over (6e-3, 3e-3); full at
#: 2e-3 on 8 x 8 maps and 4 x 4 convergence grids over (4e-3, 2e-3, 1e-3).  The semi-implicit solver, at the same plan
#: (its joint spring is stable to 6e-3: ``options.SemiImplicitOptions``), took 29 s (maps), 25 (rounding), 28
#: (convergence), 11 (contact), 9 (IC), 9 (impact), 11 (Psi), 13 (lift-off) of wall time in the quick report.
_MAPS = {"quick": {"timestep": 3e-3}, "full": {"timestep": 2e-3}}
_CONVERGENCE = {
    "quick": [{"timestep": dt} for dt in (6e-3, 3e-3)],
    "full": [{"timestep": dt} for dt in (4e-3, 2e-3, 1e-3)],
}
#: MuJoCo Warp's full report at the quick report's timestep, 3e-3, and its convergence over the quick report's
#: (6e-3, 3e-3) (its 4 x 4 grid): at 2e-3 its maps, convergence over (4e-3, 2e-3, 1e-3) and one ladder start with its
#: interventions took 46, 58 and 105 s of section time in the full report (~7 ms of CPU a step whatever the worlds: a
#: setting costs its step count), and 31, 34 and 62 s at 3e-3 with (6e-3, 3e-3, 1.5e-3).  Its interventions still
#: take a quarter step (``crosscheck.engines.newton.interventions``).
_MAPS_MUJOCO = {"quick": {"timestep": 3e-3}, "full": {"timestep": 3e-3}}
_CONVERGENCE_MUJOCO = {
    "quick": [{"timestep": dt} for dt in (6e-3, 3e-3)],
    "full": [{"timestep": dt} for dt in (6e-3, 3e-3)],
}


_MODULES = {"mujoco": "mujoco_warp", "xpbd": "xpbd", "featherstone": "featherstone", "semi_implicit": "semi_implicit"}

#: Each solver's models in between (crosscheck.studies.ladder, ``crosscheck.engines.newton.ladder``) and the
#: interventions on the solver itself that test each cause (``crosscheck.engines.newton.interventions``).  The ladder and
#: interventions sections run one start at a time (``EngineSpec.first_event``), as many as ``_LADDER_STATES`` says,
#: so their cost is their runs' steps (``_LADDER_STATES`` gives a start's, measured).  Their grids are
#: the maps' (no grid of their own); a finer step than a sixteenth of the run's is never taken, and on MuJoCo Warp
#: none finer than a quarter (``crosscheck.engines.newton.interventions``).
_L, _I = "crosscheck.engines.newton.ladder:", "crosscheck.engines.newton.interventions:"
_LADDERS = {
    # MuJoCo's ladder at MuJoCo Warp's settings, then MuJoCo in C (float64), then MuJoCo Warp (float32)
    "mujoco": Ladder(
        rungs={
            "geometry": "capsule",
            "compliance": _L + "compliant_mujoco",
            "friction law": _L + "spring_law",
            "feed-forward": _L + "law",
            "discretisation": _L + "mujoco_c",
            "float32": "engine",
        },
        interventions={
            "geometry": _I + "geometry",
            "compliance": _I + "mujoco_compliance",
            "friction law": _I + "mujoco_friction_law",
            "feed-forward": _I + "mujoco_feed_forward",
            "discretisation": _I + "mujoco_discretisation",
            "float32": _I + "float32",
        },
    ),
    # the capsule's contact point, then XPBD's projection of it
    "xpbd": Ladder(
        rungs={"geometry": "capsule", "position projection": "engine"},
        interventions={"geometry": _I + "geometry", "position projection": _I + "position_projection"},
    ),
    # the compliant rod with the penalty normal law, the penalty law at a fine step, the solver itself (Featherstone in
    # reduced coordinates, the semi-implicit solver in maximal ones: the same penalty contact)
    "featherstone": Ladder(
        rungs={
            "geometry": "capsule",
            "compliance": _L + "compliant",
            "friction law": _L + "penalty_fine",
            "discretisation": "engine",
        },
        interventions={
            "geometry": _I + "geometry",
            "compliance": _I + "penalty_compliance",
            "friction law": _I + "friction_regularisation",
            "discretisation": _I + "discretisation",
        },
    ),
}
_LADDERS["semi_implicit"] = _LADDERS["featherstone"]


#: Starts the ladder (and so the interventions) runs, by cost: a start costs 105 s of section time in MuJoCo Warp's
#: ladder and interventions at timestep 2e-3 (~15 runs, each its full step count at ~7 ms of CPU a step, a quarter
#: step the finest), 13 s in Featherstone's, 9 s in the semi-implicit solver's and 6 s in XPBD's (measured in the full
#: report); so
#: MuJoCo Warp, Featherstone and the semi-implicit solver ladder 1 start in either report, XPBD 1 (quick) and 2 (full).
_LADDER_STATES = {
    "mujoco": {"quick": 1, "full": 1},
    "featherstone": {"quick": 1, "full": 1},
    "semi_implicit": {"quick": 1, "full": 1},
    "xpbd": {"quick": 1, "full": 2},
}


def _engine(solver: str, order: int) -> EngineSpec:
    return EngineSpec(
        name=f"newton_{solver}",
        engine=f"crosscheck.engines.newton.{_MODULES[solver]}",
        label=_LABELS[solver],
        libraries=("newton", "warp-lang", "mujoco-warp") if solver == "mujoco" else ("newton", "warp-lang"),
        install="crosscheck[newton]",
        tags=_TAGS[solver],
        ladder=_LADDERS[solver],
        # no event-tolerance profile (validation): not measured (validate does not judge these engines' events)
        report=ReportPlan(
            maps=_MAPS_MUJOCO if solver == "mujoco" else _MAPS,
            convergence=_CONVERGENCE_MUJOCO if solver == "mujoco" else _CONVERGENCE,
            maps_n={"quick": 4, "full": 8},
            convergence_n={"quick": 3, "full": 4},
            order=order,
            ladder=True,
            ladder_states=_LADDER_STATES[solver],
            sections="crosscheck.engines.newton.sections:sections" if solver == "mujoco" else None,
        ),
        execution=Execution(
            sweep_chunk=256,
            preload="crosscheck.engines.newton.engine:preload",
            provenance="crosscheck.engines.newton.engine:provenance",
        ),
    )


ENGINES = tuple(_engine(s, 80 + i) for i, s in enumerate(_LABELS))
