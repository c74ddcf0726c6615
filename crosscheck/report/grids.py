"""Sampling grids of the report's maps."""

from __future__ import annotations

import numpy as np

__all__ = ["cell_centres"]


def cell_centres(lo: float, hi: float, n: int) -> np.ndarray:
    """``n`` points at the centres of ``n`` equal cells of (lo, hi).

    Centres never touch the ends, so open intervals such as theta in (0, pi/2)
    are sampled without hitting the excluded end points, and an image of the
    samples covers (lo, hi) exactly.
    """
    if n < 1:
        raise ValueError(f"n must be an integer >= 1; got {n}")
    return lo + (np.arange(n) + 0.5) * (hi - lo) / n
