"""Helpers for maps of first events (``crosscheck.Outcome`` codes on a 2D grid of starts)."""

from __future__ import annotations

import numpy as np

from crosscheck.outcome import Outcome

__all__ = ["OUTCOME_NAMES", "NOT_SLIPPING", "boundary_cells"]

#: ``Outcome`` names indexed by code.
OUTCOME_NAMES = [o.name for o in Outcome]
#: Map code of a start that does not slip at t = 0 (not compared with an engine).
NOT_SLIPPING = -2


def boundary_cells(codes: np.ndarray) -> np.ndarray:
    """Cells of a 2D map of codes with a 4-neighbour of a different code (the map's boundaries)."""
    c = np.asarray(codes)
    edge = np.zeros(c.shape, bool)
    edge[1:, :] |= c[1:, :] != c[:-1, :]
    edge[:-1, :] |= c[:-1, :] != c[1:, :]
    edge[:, 1:] |= c[:, 1:] != c[:, :-1]
    edge[:, :-1] |= c[:, :-1] != c[:, 1:]
    return edge
