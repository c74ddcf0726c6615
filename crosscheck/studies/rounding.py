"""Outcomes that hang on the last bit: how many starts change an engine's outcome when theta moves by one or two ulp.

A start places the capsule touching the plane, so the contact's first-row
state can be a tie decided by rounding (MuJoCo: dist < margin = 0 with dist
within a few 1e-16 of 0).  An outcome that flips when theta moves by one ulp
is then not the engine's answer to the start but to its rounding.  This
study reruns each start at theta moved by each of ``ulps`` units in the last
place (``numpy.nextafter``) and counts the starts whose outcome changes.

Scaled units (section 2.1).
"""

from __future__ import annotations

import numpy as np

from crosscheck import engines
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["ulp_shifted", "ulp_sensitivity", "ULPS"]

#: Units in the last place theta is moved by (both ways).
ULPS = (-2, -1, 1, 2)


def ulp_shifted(x: float, k: int) -> float:
    """``x`` moved by ``k`` units in the last place (toward +inf for k > 0)."""
    for _ in range(abs(k)):
        x = float(np.nextafter(x, np.inf if k > 0 else -np.inf))
    return x


def ulp_sensitivity(
    engine: str, states: list[SlipState], mu, *, alpha: float = 3.0, horizon: float = 2.0, ulps=ULPS, **options
) -> dict:
    """Each start's outcome at theta and at theta moved by each of ``ulps``; the starts whose outcome changes.

    Returns {"n", "changed" (count), "changed_index" (list), "outcomes" ({shift: [names]})}.
    """
    spec = engines.get(engine)
    rod = Rod.scaled(alpha)
    mu = np.broadcast_to(np.asarray(mu, float), (len(states),))
    shifts = (0, *ulps)
    # one sweep of every shift (a batched engine steps them together; each state's outcome is its own either way)
    moved = [SlipState(**{**s.as_dict(), "theta": ulp_shifted(s.theta, k)}) for k in shifts for s in states]
    res = spec.sweep(rod, moved, np.tile(mu, len(shifts)), horizon=horizon, progress=False, **options)
    outcome = np.asarray(res.outcome, int).reshape(len(shifts), len(states))
    outcomes = dict(zip(shifts, outcome))
    base = outcomes[0]
    changed = np.zeros(len(states), bool)
    for k in ulps:
        changed |= outcomes[k] != base
    return {
        "n": len(states),
        "changed": int(changed.sum()),
        "changed_index": np.flatnonzero(changed).tolist(),
        "outcomes": {str(k): [Outcome(int(o)).name for o in v] for k, v in outcomes.items()},
    }
