"""The registered engine of Newton's semi-implicit solver (SolverSemiImplicit): its ``Options`` (the solver as their default), ``simulate``, ``sweep``.

Every study builds an engine's options as ``Options(**given)``, so the class carries the solver; ``simulate`` and
``sweep`` are ``crosscheck.engines.newton.engine``'s with it, imported at the first run (listing the engines
imports no Warp).
"""

from __future__ import annotations

from crosscheck.engines.newton.options import SemiImplicitOptions as Options

__all__ = ["Options", "simulate", "sweep"]


def simulate(rod, state, mu, *, horizon, thresholds=None, **options):
    """``crosscheck.engines.newton.engine.simulate`` with this engine's ``Options``."""
    from crosscheck.engines.newton import engine

    return engine.simulate(rod, state, mu, horizon=horizon, thresholds=thresholds, options_class=Options, **options)


def sweep(rod, states, mu, *, horizon, thresholds=None, **options):
    """``crosscheck.engines.newton.engine.sweep`` with this engine's ``Options``."""
    from crosscheck.engines.newton import engine

    return engine.sweep(rod, states, mu, horizon=horizon, thresholds=thresholds, options_class=Options, **options)
