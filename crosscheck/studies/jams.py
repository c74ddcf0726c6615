"""Jams: an engine never jams below mu_P; above it, does it jam where the theory's Corollary 4.2 states do?

Below mu_P, p > 0 for every slip direction (eq. mup), so the rigid theory has
no jam and an engine's JAM would be wrong.  Above mu_P the states of
``crosscheck.theory.corollary.corollary_states`` slip into p = 0 with b < 0 at a
known time; an engine's slip should end there (a JAM, or, for a soft contact,
a STICK or LIFTOFF right after an impulse).  Scaled units (section 2.1).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields

import numpy as np

from crosscheck import engines
from crosscheck.checks import ALPHA, check
from crosscheck.engines.base import options_from_kwargs
from crosscheck.engines.classifier import Thresholds
from crosscheck.error_stats import as_json
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.studies.agreement import DEFAULT_HORIZON
from crosscheck.studies.agreement_run import quantiles
from crosscheck.studies.comparison import EVENTS
from crosscheck.studies.grids import random_slipping_states
from crosscheck.theory.corollary import corollary_states
from crosscheck.theory.critical import mu_P
from crosscheck.theory.slipping import slip_until_event

__all__ = ["JamCheck", "jam_check", "outcome_counts"]


@dataclass(frozen=True, eq=False)
class JamCheck:
    """What ``jam_check`` measured; ``to_dict()`` is JSON-able.

    below: one dict per mu < mu_P: n random slipping states, the engine's
      outcome counts and n_jam, analytic_jams (0: p > 0 everywhere below mu_P).
    above: one dict per mu > mu_P: n Corollary 4.2 states; the engine's
      outcome counts, jam_fraction, median (t_engine - t_analytic) of its
      JAMs, near_fraction: per event (JAM, STICK, LIFTOFF) the fraction of
      states whose run ends with it within ``near_window`` of the analytic jam
      time, ended_near_fraction: their sum (the engine's slipping ends where
      the theory says slipping becomes impossible), time_difference:
      quantiles of t_engine - t_jam per event, p_at_jam: the engine's own p
      (window p_eff) at its JAM rows; |varphi + pi/2| of the analytic jam for
      the states the engine jams and for the others.
    """

    engine: str
    mu_P: float
    below: list
    above: list
    options: dict
    thresholds: dict

    def to_dict(self) -> dict:
        return as_json(
            {
                "engine": self.engine,
                "mu_P": self.mu_P,
                "below": self.below,
                "above": self.above,
                "options": self.options,
                "thresholds": self.thresholds,
            }
        )


def outcome_counts(outcome: np.ndarray) -> dict:
    """{Outcome name: count} of the outcomes present."""
    return {o.name: int((outcome == o).sum()) for o in Outcome if (outcome == o).any()}


def jam_check(
    *,
    engine: str = engines.DEFAULT,
    mus_below: Sequence[float] = (0.5, 1.0, 1.3),
    mus_above: Sequence[float] = (1.4, 1.7, 6.0),
    n_below: int = 100,
    n_above: int = 40,
    rng: np.random.Generator,
    alpha: float = 3.0,
    horizon: float = DEFAULT_HORIZON,
    thresholds: Thresholds | None = None,
    near_window: float = 0.15,
    progress: bool = False,
    **options,
) -> JamCheck:
    """No jam below mu_P; above it, the engine against the theory's jam states.

    Below mu_P: ``n_below`` random slipping states per mu
    (``crosscheck.studies.grids.random_slipping_states``).  Above:
    ``n_above`` ``corollary_states`` per mu.  ``near_window`` (0.15, 2.5 tau
    at MuJoCo's default tau = 0.06: a soft contact's lag ``LAG_TAU`` tau plus
    margin) is how close to the analytic jam an engine event must be to count
    as the end of the same slip.  Every state runs once through the engine's
    ``sweep`` and is classified by the one classifier.
    """
    E = engines.get(engine)
    alpha = float(check("alpha", alpha, ALPHA))
    muP = float(mu_P(alpha))
    for m in mus_below:
        if not m < muP:
            raise ValueError(f"mus_below must be < mu_P = {muP:.6g}; got {m!r}")
    for m in mus_above:
        if not m > muP:
            raise ValueError(f"mus_above must be > mu_P = {muP:.6g}; got {m!r}")
    opts = options_from_kwargs(E.Options, options, E.label)
    th = thresholds or Thresholds()
    kw = {f.name: getattr(opts, f.name) for f in fields(opts)}
    rod = Rod.scaled(alpha)
    below = []
    for m in mus_below:
        states = random_slipping_states(m, n_below, rng, alpha)
        r = E.sweep(rod, states, m, horizon=horizon, thresholds=th, progress=progress, **kw)
        analytic_jams = sum(slip_until_event(s, m, alpha, t_max=horizon).outcome == Outcome.JAM for s in states)
        below.append(
            {
                "mu": m,
                "n": len(states),
                "analytic_jams": int(analytic_jams),
                "outcomes": outcome_counts(r.outcome),
                "n_jam": int((r.outcome == Outcome.JAM).sum()),
            }
        )
    above = []
    for m in mus_above:
        states, t_a, varphi_a = corollary_states(m, n_above, rng, alpha=alpha, horizon=horizon)
        r = E.sweep(rod, states, m, horizon=horizon, thresholds=th, progress=progress, **kw)
        off = np.abs(varphi_a + math.pi / 2)
        o, t = r.outcome, r.event_time
        jam = o == Outcome.JAM
        near = np.abs(t - t_a) <= near_window
        above.append(
            {
                "mu": m,
                "n": len(states),
                "outcomes": outcome_counts(o),
                "jam_fraction": float(jam.mean()),
                "median_jam_time_difference": float(np.median(t[jam] - t_a[jam])) if jam.any() else math.nan,
                "near_fraction": {e.name: float(((o == e) & near).mean()) for e in EVENTS},
                "ended_near_fraction": float((np.isin(o, EVENTS) & near).mean()),
                "time_difference": {e.name: quantiles(t[o == e] - t_a[o == e]) for e in EVENTS},
                "p_at_jam": quantiles(r.summary["jam_p_eff"][jam]),
                "offplane_at_event_jam": quantiles(off[jam]),
                "offplane_at_event_other": quantiles(off[~jam]),
            }
        )
    return JamCheck(
        engine=E.name,
        mu_P=muP,
        below=below,
        above=above,
        options=kw,
        thresholds={**th.as_dict(), "stick_threshold": th.stick_threshold(opts.friction_time)},
    )
