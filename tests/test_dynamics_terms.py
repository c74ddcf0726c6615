"""Pinocchio's dynamics terms (``crosscheck validate pinocchio``): passes on the real engine, fails on a wrong reference."""

from __future__ import annotations

import json

import numpy as np
import pytest

from crosscheck.cli import main
from crosscheck.engines.pinocchio.studies import dynamics_reference, dynamics_terms
from crosscheck.rod import Rod
from crosscheck.theory import analytic

QUANTITIES = [
    "tip acc, aba",
    "tip acc, G F + free",
    "Delassus G",
    "free tip acc",
    "M (crba)",
    "C (Coriolis matrix)",
    "g (gravity)",
    "C v + g = nle",
    "b",
    "p",
    "mode",
    "mu_P from p",
]


def test_validation_passes_on_a_few_hundred_states():
    result = dynamics_terms.validate(400, np.random.default_rng(7), progress=False)
    assert [s.quantity for s in result.stats] == QUANTITIES
    assert result.passed, result.to_table()
    for s in result.stats:
        assert s.n == (len(dynamics_terms.ALPHAS_MU_P) if s.quantity == "mu_P from p" else 400)
        assert 0.0 <= s.max_ratio <= 1.0
    mode = result.extra["mode"]
    assert np.sum(mode["confusion_reference_by_pinocchio"]) == 400
    assert mode["disagree_off_boundary"] == 0
    # The states reach the hard regions: near-vertical rods with |cos theta| <= 1e-2.
    assert result.extra["min_cos_theta"] < 1e-2
    assert result.extra["rods"] == dynamics_terms.MAX_RODS


def test_random_states_cover_the_required_ranges():
    s = dynamics_terms.random_states(3000, np.random.default_rng(3))
    assert np.all((s["theta"] > 0) & (s["theta"] < np.pi / 2))
    assert np.any(s["theta"] < 1e-6) and np.any(np.abs(np.cos(s["theta"])) < 2e-3)
    assert np.any(np.abs(np.cos(s["theta"]) - 1e-2) < 2e-3)
    assert np.all((s["varphi"] > -np.pi) & (s["varphi"] <= 0))
    assert np.ptp(np.log10(s["alpha"])) > 1.0 and np.ptp(np.log10(s["m"])) > 1.0 and np.ptp(np.log10(s["l"])) > 1.0
    np.testing.assert_allclose(s["alpha"], s["m"] * s["l"] ** 2 / s["I0"], rtol=1e-14)


def test_cli_exit_zero_and_json(capsys):
    assert main(["validate", "pinocchio", "--checks", "dynamics", "--states", "200", "--seed", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["engine"] == "pinocchio" and out["passed"] is True
    assert [s["quantity"] for s in out["stats"]] == QUANTITIES
    assert all(s["passed"] for s in out["stats"])


def test_validation_is_deterministic_for_a_seed():
    a = dynamics_terms.validate(150, np.random.default_rng(11), progress=False).to_json()
    b = dynamics_terms.validate(150, np.random.default_rng(11), progress=False).to_json()
    assert a == b


def _perturbed_inertia(original):
    # eq. linode2 with its I0/(m l^2) coefficient wrong by 1 part in 1e9 (the rod's factors of eq. linode2)
    def rod_factors(rod):
        return original(Rod(mass=rod.mass, length=rod.length, inertia=rod.inertia * (1 + 1e-9), gravity=rod.gravity))

    return rod_factors


def _perturbed_p(original):
    # eq. p with 1 + alpha replaced by 1 + alpha (1 + 1e-9)
    return lambda theta, varphi, mu, alpha: original(theta, varphi, mu, alpha) + 1e-9 * alpha


def _perturbed_b(original):
    # eq. b with the centripetal term Theta^2 sin theta off by 1e-9
    return lambda Psi, Theta, theta: original(Psi, Theta, theta) + 1e-9 * Theta**2 * np.sin(theta)


def _perturbed_reference_terms(original):
    # M_psipsi = I0 cos^2 theta (1 + 1e-9)
    def reference_terms(rod, q, v):
        M, C, g = original(rod, q, v)
        M = M.copy()
        M[:, 3, 3] *= 1 + 1e-9
        return M, C, g

    return reference_terms


WRONG_REFERENCES = {
    "linode2-I0-coefficient": (
        analytic,
        "rod_factors",
        _perturbed_inertia,
        {"tip acc, aba", "tip acc, G F + free", "Delassus G"},
    ),
    "p-coefficient": (analytic, "_p", _perturbed_p, {"p"}),
    "b-coefficient": (analytic, "_b", _perturbed_b, {"b"}),
    "M-psipsi": (dynamics_reference, "reference_terms", _perturbed_reference_terms, {"M (crba)"}),
}


@pytest.mark.parametrize("case", WRONG_REFERENCES, ids=str)
def test_validation_fails_on_a_wrong_reference(case, monkeypatch, capsys):
    module, name, perturb, must_fail = WRONG_REFERENCES[case]
    monkeypatch.setattr(module, name, perturb(getattr(module, name)))
    # The command exits non-zero and names the quantities that exceed their tolerance.
    assert main(["validate", "pinocchio", "--checks", "dynamics", "--states", "300", "--seed", "5", "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["passed"] is False
    failed = {s["quantity"] for s in out["stats"] if not s["passed"]}
    assert must_fail <= failed


def test_failed_table_says_FAILED(monkeypatch, capsys):
    monkeypatch.setattr(analytic, "_p", _perturbed_p(analytic._p))
    assert main(["validate", "pinocchio", "--checks", "dynamics", "--states", "100", "--seed", "2"]) == 1
    lines = capsys.readouterr().out.rstrip().splitlines()
    assert lines[-1] == "FAILED"
    assert [line.split()[0] for line in lines if " FAIL " in line] == ["p"]


def test_progress_bar_goes_to_stderr(capsys):
    result = dynamics_terms.validate(50, np.random.default_rng(1), progress=True)
    assert result.passed
    captured = capsys.readouterr()
    assert "validate pinocchio" in captured.err and "50/50" in captured.err
    assert captured.out == ""


@pytest.mark.parametrize("rtol", [0.0, 1e-3], ids=["atol-only", "with-rtol"])
def test_chunked_error_statistics_equal_error_stat_on_the_whole(rtol):
    """``validate``'s chunked statistics give exactly ``compare.error_stat``'s numbers: random errors with ties at the
    maximum, structural zeros of the reference, NaN and inf, split into random chunks (rtol > 0: its fallback steps)."""
    from crosscheck.error_stats import error_stat
    from crosscheck.tolerances import Tolerance

    rng = np.random.default_rng(7)
    tol = Tolerance(atol=1e-14, rtol=rtol, why="test")
    for case in range(40):
        n, shape = int(rng.integers(1, 60)), [(3,), (5, 5), (5,)][case % 3]
        want = rng.standard_normal((n, *shape))
        want[..., 0] = 0.0  # a structural zero column: judged by max_abs alone
        got = want + rng.choice([0.0, 1e-15, -1e-15, 2e-15], size=want.shape) * rng.integers(1, 4, size=want.shape)
        if case % 5 == 0:  # ties: the largest error in several states, the first must be reported
            got.reshape(n, -1)[:, 1] = want.reshape(n, -1)[:, 1] + 3e-15
        if case % 7 == 3:
            got.reshape(n, -1)[int(rng.integers(n)), 2] = np.nan if case % 2 else np.inf
        states = {"theta": rng.uniform(0, 1.5, n)}
        cuts = np.sort(rng.choice(np.arange(1, n), size=min(3, n - 1), replace=False)) if n > 1 else []
        stat = dynamics_terms._ErrorStats("q", tol)
        for part in np.split(np.arange(n), cuts):
            stat.add(got[part], want[part])
        a, b = stat.result(states), error_stat("q", got, want, tol, states)
        for field in ("n", "max_abs", "max_rel", "max_ratio", "worst_state", "passed"):
            x, y = getattr(a, field), getattr(b, field)
            assert x == y or (isinstance(x, float) and np.isnan(x) and np.isnan(y)), (case, field, x, y)
