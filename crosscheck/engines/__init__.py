"""The registry: the one place that knows which contact engines exist.

    from crosscheck import engines
    engines.names()                                   # ['compliant', 'mujoco', 'mujoco_law', 'pinocchio', ...]
    run = engines.get("mujoco").simulate(rod, state, mu, horizon=1.0, timestep=3e-4)

Each engine is a subpackage (``crosscheck/engines/<name>/``) that declares
itself in ``ENGINES``, a tuple of ``crosscheck.engines.spec.EngineSpec``: its
names, label, libraries, options, tags, tolerance profile, ladder and report
sections.  ``BUILTIN`` lists those subpackages; everything else in the
harness (studies, sweeps, tolerances, findings, provenance, the report's
engine sections) reads ``specs()`` and never names an engine.  An engine's
library is imported only when it runs, so listing the engines is cheap.

The shared pieces are the ``Record`` every engine fills, the one classifier
(``classify``) and the ``Run`` / ``SweepResult`` they return.  ``register``
adds an engine defined elsewhere (a test, a user's script); every study,
``--engine`` option and generated report section then accepts it.
"""

from __future__ import annotations

import importlib

from crosscheck.engines.base import SERIES, SUMMARY, Engine, Run, SweepResult, n_steps, sweep_by_simulate
from crosscheck.engines.classifier import Classification, Thresholds, classify
from crosscheck.engines.record import Record
from crosscheck.engines.spec import TAGS, EngineSpec, ReportPlan

__all__ = [
    "DEFAULT",
    "names",
    "get",
    "specs",
    "libraries",
    "register",
    "unregister",
    "labels",
    "Engine",
    "EngineSpec",
    "ReportPlan",
    "TAGS",
    "Run",
    "SweepResult",
    "Record",
    "Thresholds",
    "Classification",
    "classify",
    "n_steps",
    "sweep_by_simulate",
    "SERIES",
    "SUMMARY",
]

#: The engine subpackages shipped with crosscheck, each with ``ENGINES``.
BUILTIN = (
    "crosscheck.engines.mujoco",
    "crosscheck.engines.pinocchio",
    "crosscheck.engines.compliant",
    "crosscheck.engines.drake",
    "crosscheck.engines.bullet",
    "crosscheck.engines.physx",
    "crosscheck.engines.dart",
)

#: The engine a study runs when none is named (the studies' ``engine=`` default): MuJoCo, the engine the ladder explains.
DEFAULT = "mujoco"

_builtin: dict[str, EngineSpec] = {}
_registered: dict[str, EngineSpec] = {}


def _builtins() -> dict[str, EngineSpec]:
    if not _builtin:
        for package in BUILTIN:
            for spec in importlib.import_module(package).ENGINES:
                if spec.name in _builtin:
                    raise RuntimeError(f"two built-in engines are named {spec.name!r}")
                _builtin[spec.name] = spec
    return _builtin


def specs() -> list[EngineSpec]:
    """Every available engine's record: built-in ones by their report order, then registered ones in the order added."""
    builtin = sorted(
        _builtins().values(), key=lambda s: (s.report.order if s.report else 1000, list(_builtins()).index(s.name))
    )
    return builtin + list(_registered.values())


def names() -> list[str]:
    """Names of every available engine, sorted."""
    return sorted(set(_builtins()) | set(_registered))


def get(name: str) -> EngineSpec:
    """The engine called ``name`` (ValueError listing the available names otherwise)."""
    if not isinstance(
        name, str
    ):  # a list or None is not a name: the same one line, not a TypeError from the dict lookup
        raise ValueError(f"engine must be one of {', '.join(names())}; got {name!r}")
    if name in _registered:
        return _registered[name]
    if name in _builtins():
        return _builtin[name]
    raise ValueError(f"engine must be one of {', '.join(names())}; got {name!r}")


def labels() -> dict[str, str]:
    """Engine name -> its label for tables and messages ("mujoco" -> "MuJoCo")."""
    return {s.name: s.label for s in specs()}


def libraries() -> tuple[str, ...]:
    """The PyPI distributions of every engine's library, in engine order without repeats (for provenance and result keys)."""
    return tuple(dict.fromkeys(lib for s in specs() for lib in s.libraries))


def register(engine: EngineSpec) -> EngineSpec:
    """Make ``engine`` available by ``engine.name``; returns it.  A built-in or taken name is refused."""
    if not isinstance(engine, EngineSpec):
        raise ValueError(f"engine must be a crosscheck.engines.EngineSpec; got {type(engine).__name__}")
    if engine.name in _builtins() or engine.name in _registered:
        raise ValueError(f"an engine named {engine.name!r} is already registered")
    _registered[engine.name] = engine
    return engine


def unregister(name: str) -> None:
    """Remove an engine added by ``register`` (built-in engines stay)."""
    if name not in _registered:
        raise ValueError(f"no registered engine named {name!r} (built-in engines cannot be removed)")
    del _registered[name]
