"""The comparison rule's edges (``crosscheck.studies.comparison``): where an engine STICK starts to read as the theory's slip.

``stick_from`` reads an engine STICK as the theory's SLIP from t_floor - lag on, where the theory SLIPs to its
comparison time ``until`` and its slip speed falls below the engine's STICK floor at t_floor <= until.  Each case puts
t_floor at, just inside or past ``until``, or the theory's outcome other than SLIP; the rule's use on engine runs is
in ``test_agreement.py`` and ``test_interventions.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck.outcome import Outcome
from crosscheck.studies.comparison import compared_label, stick_from

UNTIL, LAG = 1.5, 0.25


@pytest.mark.parametrize(
    "outcome, t_floor, expected",
    [
        (Outcome.SLIP, 1.0, 1.0 - LAG),  # below the floor before the comparison time
        (Outcome.SLIP, UNTIL, UNTIL - LAG),  # exactly at the comparison time: still compared as the slip
        (Outcome.SLIP, np.nextafter(UNTIL, 2.0), math.inf),  # past it: the theory's slip was never that slow in time
        (Outcome.SLIP, math.nan, math.inf),  # never below the floor
        (Outcome.JAM, 1.0, math.inf),  # the theory has an event of its own: a STICK stays a disagreement
        (Outcome.LIFTOFF, 1.0, math.inf),
    ],
    ids=["before", "at_until", "after", "never", "theory_jams", "theory_lifts_off"],
)
def test_a_stick_reads_as_the_theorys_slip_from_its_floor_time_less_the_lag_up_to_the_comparison_time(
    outcome, t_floor, expected
):
    assert float(stick_from(int(outcome), UNTIL, t_floor, LAG)) == expected
    # one start and many give the same
    many = stick_from(np.array([int(outcome)] * 2, np.int8), np.full(2, UNTIL), np.full(2, t_floor), np.full(2, LAG))
    assert list(many) == [expected, expected]
    # and an engine STICK at the floor time is compared as SLIP exactly where the rule says
    since = float(stick_from(int(outcome), UNTIL, t_floor, LAG))
    label = compared_label(Outcome.STICK, 1.4, UNTIL, since)
    assert label == (Outcome.SLIP if since <= 1.4 else Outcome.STICK)
