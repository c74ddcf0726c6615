"""Contact engines behind one interface, looked up by name.

    from crosscheck import engines
    engines.names()                                   # ['mujoco']
    run = engines.get("mujoco").simulate(rod, state, mu, horizon=1.0, timestep=3e-4)

One module per engine (``crosscheck.engines.mujoco``), each exposing
``ENGINE``, an object with the attributes of ``crosscheck.engines.base.Engine``;
the shared pieces are the ``Record`` every engine fills, the one classifier
(``classify``) and the ``Run`` / ``SweepResult`` they return.  Built-in engines
are imported on first use, so ``import crosscheck.engines`` does not load
MuJoCo.  ``register`` adds an engine (for example one defined in a test or a
user's script); every study and ``--engine`` option then accepts its name.
"""

from __future__ import annotations

import importlib

from crosscheck.engines.base import SERIES, SUMMARY, Engine, Run, SweepResult, n_steps, sweep_by_simulate
from crosscheck.engines.classifier import Classification, Thresholds, classify
from crosscheck.engines.record import Record

__all__ = ["names", "get", "register", "unregister", "Engine", "Run", "SweepResult", "Record", "Thresholds", "Classification",
           "classify", "n_steps", "sweep_by_simulate", "SERIES", "SUMMARY"]

#: Engines shipped with crosscheck: name -> module whose ``ENGINE`` it is.
BUILTIN = {"mujoco": "crosscheck.engines.mujoco", "pinocchio": "crosscheck.engines.pinocchio", "compliant": "crosscheck.engines.compliant",
           "mujoco_law": "crosscheck.engines.mujoco_ode"}

_registered: dict[str, Engine] = {}


def names() -> list[str]:
    """Names of every available engine, sorted."""
    return sorted(set(BUILTIN) | set(_registered))


def get(name: str) -> Engine:
    """The engine called ``name`` (ValueError listing the available names otherwise)."""
    if name in _registered:
        return _registered[name]
    if name in BUILTIN:
        return importlib.import_module(BUILTIN[name]).ENGINE
    raise ValueError(f"engine must be one of {', '.join(names())}; got {name!r}")


def register(engine: Engine) -> Engine:
    """Make ``engine`` available by ``engine.name``; returns it.  A built-in or taken name is refused."""
    if not isinstance(engine, Engine):
        raise ValueError(f"engine must have name, Options, simulate and sweep; got {type(engine).__name__}")
    name = engine.name
    if not (isinstance(name, str) and name.isidentifier()):
        raise ValueError(f"engine name must be an identifier; got {name!r}")
    if name in BUILTIN or name in _registered:
        raise ValueError(f"an engine named {name!r} is already registered")
    _registered[name] = engine
    return engine


def unregister(name: str) -> None:
    """Remove an engine added by ``register`` (built-in engines stay)."""
    if name not in _registered:
        raise ValueError(f"no registered engine named {name!r} (built-in engines cannot be removed)")
    del _registered[name]
