"""Lift-off onset: the smallest Psi at which an engine's rod lifts off at once from theta_L, against Psi_L (eq. psil).

At theta = theta_L, Theta = 0, varphi = -pi/2 the free tip acceleration b of
eq. b changes sign at Psi = Psi_L, whatever mu: below it the slipping tip is
pressed onto the plane, above it it lifts off at t = 0.  An engine without a
contact delay finds the same threshold; a time-stepping one finds it up to
its first step's own error (see ``crosscheck.tolerances``).
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck import engines
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory.critical import Psi_L, theta_L

__all__ = ["liftoff_onset"]


def liftoff_onset(
    rod: Rod,
    mu: float,
    *,
    engine: str = engines.DEFAULT,
    rounds: int = 5,
    n: int = 33,
    half_width: float = 1e-3,
    horizon: float = 0.03,
    **options,
) -> tuple[float, float]:
    """Smallest Psi at which ``engine`` lifts off at t = 0 from theta_L, Theta = 0, varphi = -pi/2.

    Bisection on grids of n values of Psi (``rounds`` times), starting from
    Psi_L +- ``half_width``, each grid one ``sweep`` of ``horizon``.
    ``options`` go to the engine (``timestep=...``).  Returns (onset,
    resolution): the first grid value that lifts off and the final grid
    spacing.

    Raises:
      ValueError: no single threshold in the bracket (LIFTOFF at the lower end,
        none at the upper end, or islands).
    """
    E = engines.get(engine)
    lo, hi = float(Psi_L) - half_width, float(Psi_L) + half_width
    for _ in range(rounds):
        Ps = np.linspace(lo, hi, n)
        states = [SlipState(theta=float(theta_L), varphi=-math.pi / 2, Theta=0.0, Psi=P, eta=1.0) for P in Ps]
        r = E.sweep(rod, states, mu, horizon=horizon, progress=False, **options)
        lift = (r.outcome == Outcome.LIFTOFF) & (r.event_time == 0.0)
        k = int(np.argmax(lift))
        if lift[0] or not lift[-1] or not lift[k:].all():
            raise ValueError(f"no single lift-off threshold in Psi in [{lo}, {hi}] at mu = {mu}")
        lo, hi = Ps[k - 1], Ps[k]
    return float(hi), float(hi - lo)
