"""The compliant rod (``crosscheck.compliant``) behind the shared engine interface, as engine "compliant"."""

from __future__ import annotations

from collections.abc import Sequence

from crosscheck.compliant.run import NAME, Options, simulate
from crosscheck.engines.base import ModuleEngine, SweepResult, sweep_by_simulate
from crosscheck.engines.classifier import Thresholds
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["ENGINE", "Options", "simulate", "sweep"]


def sweep(rod: Rod, states: Sequence[SlipState], mu, *, horizon: float, thresholds: Thresholds | None = None, progress: bool = True,
          workers: int = 1, **options) -> SweepResult:
    """Every state through ``simulate`` (``sweep_by_simulate``; ``workers`` forked processes)."""
    return sweep_by_simulate(ENGINE, rod, states, mu, horizon=horizon, thresholds=thresholds, progress=progress, workers=workers,
                             **options)


ENGINE = ModuleEngine(NAME, Options, simulate, sweep)
