"""Code an engine's declaration names but does not import: its own studies and report sections, a layer above it.

An ``EngineSpec`` already names code by ``"module:attr"`` where the code sits elsewhere (``module``, the ladder's
rungs, the interventions).  Its ``checks`` and its report plan's ``sections`` are callables; ``Named`` is such a
callable made from the name alone, so that an engine's subpackage declares its studies' checks and its report
sections without importing them (the layers: engines < studies < report).  The layer that calls it imports it then.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

__all__ = ["Named"]


@dataclass(frozen=True)
class Named:
    """The callable ``attr`` of ``module``, named ``"module:attr"``, imported when it is first called (it pickles by
    its name, as a module-level function does)."""

    ref: str

    def __post_init__(self):
        module, _, attr = self.ref.partition(":")
        if not (module and attr):
            raise ValueError(f"ref must be 'module:attr'; got {self.ref!r}")

    def __call__(self, *args, **kwargs):
        module, _, attr = self.ref.partition(":")
        return getattr(importlib.import_module(module), attr)(*args, **kwargs)
