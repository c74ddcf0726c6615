"""DART's models in between, for its ladder (``crosscheck.studies.ladder``): DART's step with the theory's friction law,
then with a pyramid of friction.

DART's contact differs from the rigid theory's in its friction law twice (``crosscheck.engines.dart.engine``): its
Dantzig step bounds each friction row by mu times the frictionless normal impulse (a bound fixed before the friction
enters), and its two rows are bounded apart (a square pyramid instead of the cone).  dartpy 6.20's
``NsgsFrictionSolver`` solves the same step's boxed LCP with the bound following the normal impulse, with either law,
so the rungs after the capsule point are DART's step with Coulomb's cone (``coulomb_step``: the theory's law, stepped:
discretisation), with the pyramid (``pyramid_step``: pyramid cone), and DART itself (friction bound).

Scaled units (section 2.1).
"""

from __future__ import annotations

from crosscheck import engines

__all__ = ["coulomb_step", "pyramid_step"]


def _dart(rod, state, mu, horizon, thresholds, options, solver: str):
    given = {k: getattr(options, k) for k in options.__dataclass_fields__}
    return engines.get("dart").simulate(
        rod, state, mu, horizon=horizon, thresholds=thresholds, until_event=True, **{**given, "friction_solver": solver}
    )


def coulomb_step(rod, state, mu, *, horizon, thresholds, options):
    """DART at the run's options with NSGS and Coulomb's cone; stopped once its first event is judged."""
    return _dart(rod, state, mu, horizon, thresholds, options, "nsgs_coulomb")


def pyramid_step(rod, state, mu, *, horizon, thresholds, options):
    """DART at the run's options with NSGS and its Box law (the pyramid); stopped once its first event is judged."""
    return _dart(rod, state, mu, horizon, thresholds, options, "nsgs_box")
