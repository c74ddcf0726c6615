"""JSON as the commands print it: strict (no NaN or Infinity tokens, which JSON does not have), non-finite numbers
written as null, so that a run whose numbers include a NaN (an event that did not happen) still prints."""

from __future__ import annotations

import json
import math

__all__ = ["json_text"]


def _finite(obj):
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def json_text(obj, *, indent: int = 2) -> str:
    """``obj`` as strict JSON text, every non-finite float as null."""
    return json.dumps(_finite(obj), indent=indent, allow_nan=False)
