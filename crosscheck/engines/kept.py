"""Built models kept by setting in one process: the most recently used ones, the oldest dropped past a size."""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any

__all__ = ["Kept"]


class Kept:
    """A least-recently-used store of ``size`` built things (compiled models, diagrams) keyed by what built them.

    Engines build a model per (rod, mu, options); a sweep or a ladder runs many starts at one setting, and
    building is a sizeable part of a short run (MuJoCo's compile 1.3 ms, Drake's diagram ~10 ms).
    """

    def __init__(self, size: int) -> None:
        if not (isinstance(size, int) and size >= 1):
            raise ValueError(f"size must be an integer >= 1; got {size!r}")
        self.size = size
        self._items: OrderedDict = OrderedDict()

    def get(self, key: Hashable, build: Callable[[], Any]) -> Any:
        """The thing kept under ``key``, or ``build()``'s, kept (dropping the least recently used past ``size``)."""
        hit = self._items.get(key)
        if hit is not None:
            self._items.move_to_end(key)
            return hit
        built = build()
        self._items[key] = built
        while len(self._items) > self.size:
            self._items.popitem(last=False)
        return built

    def __len__(self) -> int:
        return len(self._items)
