"""The paper's three critical values of Psi as an engine sees them: lift-off above Psi_L, indeterminacy at Theta = 0
above
Psi_1, and no jam above Psi_2.

At mu = 1.4, alpha = 3 (section 3.3; ``crosscheck.theory.critical``): Psi_L = 1.6119, Psi_1 = 1.9480, Psi_2 = 3.0097.

* Above Psi_1 (mu in (mu_P, mu_L]) a rod with Theta = 0 can be indeterminate, p < 0 < b: the rigid theory allows both a
  lift-off and a slip with an impulsive force (an impact without collision).  ``indeterminate_starts`` draws such starts
  and ``engine_events`` records which the engine chooses.  For a compliant contact that starts untouched (no
  penetration,
  no normal velocity) the compliant theory decides: the start lies on the lift-off side of the boundary of
  ``crosscheck.theory.compliant_limit.indeterminate_boundary`` whatever the stiffness (``compliant_prediction``).
* Above Psi_2 the inconsistent region p < 0, b < 0 is empty (b grows with Theta^2, so Theta = 0 is the worst case): a
  slipping rod cannot reach p = 0 with b < 0, so it cannot jam.  ``slipping_starts`` draws slipping starts (b < 0 < p)
  with |Psi| spread over a band that crosses Psi_2; a jam is judged by |Psi| at the jam row (the slip moves Psi:
  a start above Psi_2 may jam legitimately once Psi has fallen below it).  A jam with |Psi| > Psi_2 at the jam is one
  the paper's theorem rules out.

Scaled units (section 2.1).
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Mapping, Sequence

import numpy as np

from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic, critical
from crosscheck.theory.slipping import slip_until_event

__all__ = [
    "BANDS",
    "compliant_prediction",
    "engine_events",
    "indeterminate_starts",
    "ruled_out_jams",
    "slipping_starts",
    "starts_rng",
    "theory_events",
]

#: The bands of |Psi| whose slipping starts' jams are counted: below Psi_2 (and above Psi_1) and above it.
BANDS = ((1.95, 3.0), (3.1, 5.0))


def starts_rng(seed: int) -> np.random.Generator:
    """The generator of the study's starts: every engine's section draws the same starts from the report's seed."""
    return np.random.default_rng([seed, zlib.crc32(b"psi_critical")])


def slipping_starts(
    n: int, rng: np.random.Generator, mu: float, alpha: float, *, abs_Psi: tuple[float, float] = (1.0, 5.0)
) -> list[SlipState]:
    """n slipping starts (b < 0 < p): |Psi| ~ U(abs_Psi) with a random sign, theta ~ U(0.05, 1.5), varphi ~ -U(0, pi),
    Theta ~ U(-1.5, 1.5), eta ~ U(0.2, 3)."""
    out = []
    while len(out) < n:
        th, vp, Th = rng.uniform(0.05, 1.5), -rng.uniform(0.0, math.pi * (1 - 1e-9)), rng.uniform(-1.5, 1.5)
        Ps, eta = rng.choice((-1.0, 1.0)) * rng.uniform(*abs_Psi), rng.uniform(0.2, 3.0)
        if analytic.b(Ps, Th, th) < 0.0 < analytic.p(th, vp, mu, alpha):
            out.append(SlipState(theta=th, varphi=vp, Theta=Th, Psi=Ps, eta=eta))
    return out


def indeterminate_starts(
    n: int, rng: np.random.Generator, mu: float, alpha: float, *, abs_Psi: tuple[float, float] | None = None
) -> list[SlipState]:
    """n indeterminate starts at Theta = 0 (p < 0 < b): |Psi| ~ U(Psi_1, 5) by default, random sign, theta ~ U(0.05,
    1.5),
    varphi ~ -U(0, pi), eta ~ U(0.3, 2).  ValueError where none exists (mu <= mu_P: p > 0 everywhere)."""
    if not mu > critical.mu_P(alpha):
        raise ValueError(f"mu must be > mu_P = {critical.mu_P(alpha):.6g} for an indeterminate start; got {mu!r}")
    lo, hi = abs_Psi or (float(critical.critical_values(mu=mu, alpha=alpha).Psi_1), 5.0)
    out = []
    while len(out) < n:
        th, vp = rng.uniform(0.05, 1.5), -rng.uniform(0.0, math.pi * (1 - 1e-9))
        Ps, eta = rng.choice((-1.0, 1.0)) * rng.uniform(lo, hi), rng.uniform(0.3, 2.0)
        if analytic.p(th, vp, mu, alpha) < 0.0 < analytic.b(Ps, 0.0, th):
            out.append(SlipState(theta=th, varphi=vp, Theta=0.0, Psi=Ps, eta=eta))
    return out


def theory_events(states: Sequence[SlipState], mu: float, alpha: float, *, horizon: float) -> dict[str, np.ndarray]:
    """The slipping flow's first event of each start: outcome (int), time, and Psi at the event."""
    rs = [slip_until_event(s, mu, alpha, t_max=horizon) for s in states]
    return {
        "outcome": np.array([int(r.outcome) for r in rs], np.int8),
        "time": np.array([r.time for r in rs]),
        "Psi_event": np.array([r.state.Psi for r in rs]),
    }


def engine_events(
    spec, rod: Rod, states: Sequence[SlipState], mu: float, *, horizon: float, options: Mapping
) -> dict[str, np.ndarray]:
    """``spec``'s first event of each start at ``options`` (stopped once judged where the engine can): outcome (int),
    time, and Psi at the event's row (NaN for a SLIP)."""
    stop = {"until_event": True} if spec.stops_at_event else {}
    out = {"outcome": [], "time": [], "Psi_event": []}
    for run in spec.simulate_each(rod, states, mu, horizon=horizon, **options, **stop):
        t = float(run.event_time)
        psi = math.nan
        if math.isfinite(t):
            k = min(int(np.searchsorted(run.record.t, t)), len(run.record) - 1)
            psi = float(run.record.Psi[k])
        out["outcome"].append(int(run.outcome))
        out["time"].append(t)
        out["Psi_event"].append(psi)
    return {
        "outcome": np.array(out["outcome"], np.int8),
        "time": np.array(out["time"]),
        "Psi_event": np.array(out["Psi_event"]),
    }


def compliant_prediction(state: SlipState, mu: float, alpha: float) -> str:
    """The compliant theory's choice at an indeterminate ``state`` for a contact that starts untouched (gap 0, gap rate
    0): "LIFTOFF" when the start's gap rate 0 is above the boundary's (``indeterminate_boundary`` at D0 = 0, any eps and
    damping: gap_rate* = -eps |lambda_2| b/|p| < 0), "JAM" (an impact without collision) otherwise."""
    from crosscheck.theory.compliant_limit import indeterminate_boundary

    _, rate = indeterminate_boundary(state, mu, alpha, xi=1.0, eps=1e-2, D0=0.0)
    return "LIFTOFF" if 0.0 > rate else "JAM"


def ruled_out_jams(outcome: np.ndarray, Psi_event: np.ndarray, mu: float, alpha: float) -> np.ndarray:
    """Mask of the jams with |Psi| > Psi_2(mu, alpha) at the jam: no inconsistent state exists there (the paper's
    theorem)."""
    Psi_2 = float(critical.critical_values(mu=mu, alpha=alpha).Psi_2)
    return (np.asarray(outcome) == int(Outcome.JAM)) & (np.abs(np.asarray(Psi_event)) > Psi_2)
