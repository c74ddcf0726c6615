"""The base of every engine's ``Options``: built from keyword arguments with one line naming a bad one, read back as a dict.

Each engine's ``Options`` is a frozen dataclass of its parameters in the paper's scaled units that derives from
``EngineOptions`` and sets ``LABEL``, how messages name the engine.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

__all__ = ["EngineOptions", "options_from_kwargs"]


def options_from_kwargs(cls: type, options: dict[str, Any], label: str):
    """``cls(**options)`` with an error naming any unknown option and the known ones (``label``: the engine's)."""
    known = {f.name for f in fields(cls)}
    unknown = sorted(set(options) - known)
    if unknown:
        raise ValueError(f"unknown {label} option {unknown[0]!r}: options must be one of {', '.join(sorted(known))}")
    return cls(**options)


@dataclass(frozen=True)
class EngineOptions:
    """``from_kwargs`` and ``as_dict``, written once for every engine's ``Options``."""

    #: How messages name the engine ("MuJoCo"); a plain class attribute, not a field (nor a ``ClassVar``, which
    #: ``__dataclass_fields__`` would list).
    LABEL = ""

    @classmethod
    def label_of(cls, options: dict[str, Any]) -> str:
        """The engine's label for a run with ``options`` (one ``Options`` class may serve several engines)."""
        return cls.LABEL

    @classmethod
    def from_kwargs(cls, options: dict[str, Any]):
        """``cls(**options)`` with an error naming any unknown option and the known ones."""
        return options_from_kwargs(cls, options, cls.label_of(options))

    def as_dict(self) -> dict:
        """The options by field name."""
        return {f.name: getattr(self, f.name) for f in fields(self)}
