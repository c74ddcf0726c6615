"""The registry: the one place that knows which contact engines exist.

    from crosscheck import engines
    engines.names()                                   # ['compliant', 'mujoco', 'mujoco_law', 'pinocchio', ...]
    run = engines.get("mujoco").simulate(rod, state, mu, horizon=1.0, timestep=3e-4)

Each engine declares itself in an ``ENGINES`` tuple of ``crosscheck.engines.spec.EngineSpec``: the subpackages in
``BUILTIN``, and every installed distribution's entry points of the group ``crosscheck.engines`` (``ENTRY_POINTS``;
each names an ``EngineSpec``, a tuple of them, or a module with ``ENGINES``), found through
``importlib.metadata.entry_points`` when names are first asked for.  A plugin that fails to load, has the wrong type
or takes a name already taken costs one line (``broken()``; ``get`` of its entry point's name raises it) and nothing
else.  Everything else in the harness (studies, sweeps, tolerances, findings, provenance, the report's engine
sections) reads ``specs()`` and never names an engine.  An engine's library is imported only when it runs, so
listing the engines is cheap; one whose library is not installed is listed with the pip line that brings it.

The shared pieces are the ``Record`` every engine fills, the one classifier (``classify``), the ``Run`` /
``SweepResult`` they return, and the thin SI adapter (``crosscheck.engines.adapter``) for an outside engine.
``register`` adds an engine defined elsewhere in one process (a test, a user's script).
"""

from __future__ import annotations

import dataclasses
import importlib
from importlib import metadata

from crosscheck.engines.base import SERIES, SUMMARY, Engine, Run, SweepResult, n_steps, sweep_by_simulate
from crosscheck.engines.classifier import Classification, Thresholds, classify
from crosscheck.engines.record import Record
from crosscheck.engines.spec import (
    TAGS,
    EngineSpec,
    EngineUnavailable,
    Execution,
    Intervention,
    Ladder,
    ReportPlan,
    Validation,
)

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
    "EngineUnavailable",
    "ReportPlan",
    "Ladder",
    "Validation",
    "Execution",
    "Intervention",
    "ENTRY_POINTS",
    "broken",
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
    "crosscheck.engines.newton",
)

#: The engine a study runs when none is named (the studies' ``engine=`` default): MuJoCo, the engine the ladder explains.
DEFAULT = "mujoco"

#: The entry-point group an installed distribution declares its engines in (``docs/adding-an-engine.md``).
ENTRY_POINTS = "crosscheck.engines"

_builtin: dict[str, EngineSpec] = {}
_registered: dict[str, EngineSpec] = {}
#: entry-point (or engine) name -> the one line saying why that plugin's engines are not available
_broken: dict[str, str] = {}
_loaded = False


def _declared(obj) -> tuple:
    """The ``EngineSpec``s an entry point's object declares (an EngineSpec, an iterable of them, a module's ENGINES)."""
    if isinstance(obj, EngineSpec):
        return (obj,)
    obj = getattr(obj, "ENGINES", obj)
    if isinstance(obj, (tuple, list)) and obj and all(isinstance(s, EngineSpec) for s in obj):
        return tuple(obj)
    raise TypeError(f"it must name an EngineSpec or a tuple of them; got {type(obj).__name__}")


def _load_plugin(ep) -> None:
    """Add one entry point's engines to ``_builtin``, or one line to ``_broken``."""
    dist = getattr(ep, "dist", None)
    origin = f"{dist.name} {dist.version}" if dist is not None else ep.value
    try:
        specs_ = _declared(ep.load())
        taken = [s.name for s in specs_ if s.name in _builtin]
        if taken:
            raise ValueError(f"engine name {taken[0]!r} is already taken")
    except Exception as e:  # noqa: BLE001  (a plugin that fails costs one line, never the host)
        first = (str(e).strip().splitlines() or [""])[0]
        _broken[ep.name] = f"plugin {ep.name!r} ({origin}, {ep.value}) is broken: {type(e).__name__}: {first}"
        return
    for spec in specs_:
        _builtin[spec.name] = dataclasses.replace(spec, origin=origin)


def _builtins() -> dict[str, EngineSpec]:
    global _loaded
    if not _loaded:
        for package in BUILTIN:
            for spec in importlib.import_module(package).ENGINES:
                if spec.name in _builtin:
                    raise RuntimeError(f"two built-in engines are named {spec.name!r}")
                _builtin[spec.name] = spec
        for ep in sorted(metadata.entry_points(group=ENTRY_POINTS), key=lambda e: e.name):
            _load_plugin(ep)
        _loaded = True
    return _builtin


def broken() -> dict[str, str]:
    """Plugins that failed to load: entry-point name -> one line naming the distribution and the error."""
    _builtins()
    return dict(_broken)


def specs() -> list[EngineSpec]:
    """Every available engine's record (installed plugins among them) by report order, then registered ones in the order
    added."""
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
    if name in _broken:
        raise EngineUnavailable(_broken[name])
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
