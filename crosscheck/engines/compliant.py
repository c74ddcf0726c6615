"""The compliant rod (``crosscheck.compliant``) behind the shared engine interface, as engine "compliant"."""

from __future__ import annotations

from collections.abc import Sequence

from crosscheck.compliant.run import NAME, Options, simulate
from crosscheck.engines.base import Run, SweepResult, sweep_by_simulate
from crosscheck.engines.classifier import Thresholds
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["ENGINE", "CompliantEngine", "Options", "simulate", "sweep"]


def sweep(rod: Rod, states: Sequence[SlipState], mu, *, horizon: float, thresholds: Thresholds | None = None, progress: bool = True,
          workers: int = 1, **options) -> SweepResult:
    """Every state through ``simulate`` (``sweep_by_simulate``; ``workers`` forked processes)."""
    return sweep_by_simulate(ENGINE, rod, states, mu, horizon=horizon, thresholds=thresholds, progress=progress, workers=workers,
                             **options)


class CompliantEngine:
    """The compliant rod behind ``crosscheck.engines.base.Engine``."""

    name = NAME
    Options = Options

    @staticmethod
    def simulate(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds | None = None, **options) -> Run:
        return simulate(rod, state, mu, horizon=horizon, thresholds=thresholds, **options)

    @staticmethod
    def sweep(rod: Rod, states: Sequence[SlipState], mu, *, horizon: float, thresholds: Thresholds | None = None,
              progress: bool = True, **options) -> SweepResult:
        return sweep(rod, states, mu, horizon=horizon, thresholds=thresholds, progress=progress, **options)


ENGINE = CompliantEngine()
