"""crosscheck.error_stats: the error summary behind every `crosscheck validate` command."""

import json

import numpy as np

from crosscheck.error_stats import ValidationResult, error_stat
from crosscheck.tolerances import Tolerance

TOL = Tolerance(atol=1e-6, rtol=1e-3, why="test")


def test_error_stat_finds_the_worst_state_and_fails_beyond_tolerance():
    want = np.array([[1.0, 0.0], [2.0, 0.0], [4.0, 0.0]])
    got = want.copy()
    got[1, 0] += 0.01  # ratio 0.01 / (1e-6 + 2e-3) ~ 5
    got[2, 1] += 1e-7  # within atol at a structural zero
    s = error_stat("x", got, want, TOL, {"theta": np.array([0.1, 0.2, 0.3])})
    assert not s.passed and s.worst_state == {"theta": 0.2, "index": 1}
    assert (
        s.max_abs == abs(got[1, 0] - 2.0) and s.max_rel == abs(got[1, 0] - 2.0) / 2.0
    )  # relative only where want != 0
    assert 4.9 < s.max_ratio < 5.0
    ok = error_stat("x", want + 1e-7, want, TOL, {"theta": np.zeros(3)})
    assert ok.passed and ok.max_ratio < 1


def test_json_is_standard_even_with_nan():
    s = error_stat("x", np.zeros((2, 1)), np.zeros((2, 1)), TOL, {"i": np.arange(2)})
    r = ValidationResult("demo", [s], {"nan": float("nan")})
    doc = json.loads(r.to_json())  # json.loads rejects nothing, so check the text too
    assert "NaN" not in r.to_json() and doc["stats"][0]["max_rel"] is None and doc["extra"]["nan"] is None
    assert doc["passed"] is True
