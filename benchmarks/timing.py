"""Timing shared by the benchmarks: the best of repeated wall-clock runs (other processes share the 2 cores)."""

from __future__ import annotations

import time


def best_of(repeat: int, f) -> float:
    """The shortest of ``repeat`` wall-clock timings of ``f()`` [s] (garbage collection left on, as in a real run)."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)
