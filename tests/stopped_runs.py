"""Runs stopped once their first event is judged (``until_event``), set beside the whole runs: a helper for each engine's tests."""

from __future__ import annotations

import numpy as np

from crosscheck import Outcome, Rod, SlipState

#: Starts at mu 1.4, varphi -1.9, eta 1 (theta, Theta, Psi) that lift off, jam, stick and keep slipping in Drake and Bullet.
STARTS = ((1.2, 0.9, 0.0), (1.1, -0.6, 0.0), (1.0, 0.0, 1.8), (0.5, 0.0, 0.0))


def stopped_and_whole(spec, rod: Rod, *, horizon: float = 0.6) -> list:
    """(whole run, stopped run, rows the stopped run computed) per start of ``STARTS``, after checking what every stopped run
    owes: the whole run's outcome, event time and JAM numbers, and every row for a run that keeps slipping; at least
    two starts are stopped early."""
    out = []
    for theta, Theta, Psi in STARTS:
        state = SlipState(theta=theta, varphi=-1.9, Theta=Theta, Psi=Psi, eta=1.0)
        whole = spec.simulate(rod, state, 1.4, horizon=horizon)
        cut = spec.simulate(rod, state, 1.4, horizon=horizon, until_event=True)
        for f in ("outcome", "event_time", "jam_p_eff", "jam_impulse"):
            np.testing.assert_array_equal(getattr(cut, f), getattr(whole, f), err_msg=f"{state}: {f}")
        rows = int(np.isfinite(cut.record.t).sum())
        if whole.outcome == Outcome.SLIP:
            assert rows == len(whole.record)
        out.append((whole, cut, rows))
    assert sum(rows < len(whole.record) for whole, _, rows in out) >= 2
    return out
