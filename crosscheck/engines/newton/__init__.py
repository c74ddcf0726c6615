"""Newton (PyPI newton, on NVIDIA Warp): the rod of ``models/rod.xml`` under three of Newton's solvers, many worlds at once.

One module (``engine``) serves one registered engine per solver (``Options.solver``, fixed by each record's
``defaults``):

* ``newton_mujoco``: ``SolverMuJoCo``, MuJoCo Warp in float32 with the ``mujoco`` engine's contact (elliptic cone,
  solref, solimp, Newton's method): the same model as MuJoCo in C, so the two are compared at the same settings;
* ``newton_xpbd``: ``SolverXPBD``, position-based dynamics: the contact a position projection within the step;
* ``newton_featherstone``: ``SolverFeatherstone``, reduced coordinates with Newton's penalty contact (a spring-damper
  normal force and friction regularised by a viscous slope).

The rod is one body on a D6 joint with the five coordinates of ``models/rod.xml`` (no axial spin:
``crosscheck.engines.newton.model``).  Warp compiles every solver's kernels at their first use and caches them on
disk (``~/.cache/warp``); ``crosscheck.engines.newton.model.compile_seconds`` says how long a process spent on them.
``options`` holds the scaled ``Options`` (importing it imports no warp); ``model`` the Newton model, ``engine`` the
runs.  The engines are listed only where ``newton`` is installed (``pip install crosscheck[newton]``).
"""

from __future__ import annotations

import importlib.util

from crosscheck.engines.spec import EngineSpec, ReportPlan

__all__ = ["ENGINES", "AVAILABLE"]

#: Whether Newton, Warp and MuJoCo Warp are installed (the extra ``crosscheck[newton]``).
AVAILABLE = all(importlib.util.find_spec(m) is not None for m in ("newton", "warp", "mujoco_warp"))

_LABELS = {"mujoco": "Newton MuJoCo Warp", "xpbd": "Newton XPBD", "featherstone": "Newton Featherstone"}

_TAGS = {
    # MuJoCo's soft, convex contact (as the mujoco engine's tags)
    "mujoco": {"compliant", "relaxed", "time_stepping", "batched"},
    # a position projection of a non-penetration constraint within the step: no force build-up time
    "xpbd": {"rigid", "time_stepping", "batched"},
    # a penalty spring-damper
    "featherstone": {"compliant", "time_stepping", "batched"},
}

#: Report settings by cost (benchmarks/bench_newton.py): on CPU a MuJoCo Warp step of a block of worlds costs ~10-20 ms
#: whatever the block (its kernel launches), XPBD's and Featherstone's ~3-6 ms; a map of n x n starts is one block, so
#: its cost is the step count: horizon 2 at timestep 1e-3 is 2000 steps, 20-40 s for MuJoCo Warp.  The maps run at
#: 1e-3 in both reports; convergence at three timesteps on 4 x 4 starts (quick) and 6 x 6 (full).
_MAPS = {"quick": {"timestep": 1e-3}, "full": {"timestep": 1e-3}}
_CONVERGENCE = {
    "quick": [{"timestep": dt} for dt in (3e-3, 1e-3)],
    "full": [{"timestep": dt} for dt in (3e-3, 1e-3, 3e-4)],
}


#: Options each engine runs with beyond ``solver``.  XPBD: an axial moment of 1e-4 I0 (``Options.axial_inertia``): at
#: rod.xml's 1e-12 its contact projection turns the capsule about its own axis (4.6e3 omega within a horizon of 1 on
#: theta = 1, varphi = -1.9, mu = 0.5) and launches it; at 1e-6 the spin is 2.8 omega, at 1e-4 0.03 omega (iterations 2),
#: while the inertia about the vertical errs by 1e-4 tan^2 theta.
_DEFAULTS = {"mujoco": {}, "xpbd": {"axial_inertia": 1e-4}, "featherstone": {}}


def _engine(solver: str, order: int) -> EngineSpec:
    return EngineSpec(
        name=f"newton_{solver}",
        module="crosscheck.engines.newton.engine",
        label=_LABELS[solver],
        libraries=("newton", "warp-lang", "mujoco-warp") if solver == "mujoco" else ("newton", "warp-lang"),
        defaults={"solver": solver, **_DEFAULTS[solver]},
        tags=_TAGS[solver],
        # no event-tolerance profile: not measured (validate does not judge these engines' events)
        tolerances=None,
        report=ReportPlan(
            maps=_MAPS,
            convergence=_CONVERGENCE,
            maps_n={"quick": 6, "full": 12},
            convergence_n={"quick": 4, "full": 6},
            order=order,
        ),
        sweep_chunk=256,
    )


ENGINES = tuple(_engine(s, 60 + i) for i, s in enumerate(_LABELS)) if AVAILABLE else ()
