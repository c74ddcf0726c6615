"""``crosscheck validate mujoco``: the four checks of issue 4 item 5, small sizes, real engines."""

from __future__ import annotations

import json

import numpy as np
import pytest

from crosscheck import analytic, validate_mujoco
from crosscheck.cli import main
from crosscheck.tolerances import MUJOCO_CONTACT_ACCELERATION

QUANTITIES = ["5a tip acc with contact", "5b lift-off onset Psi", "5c event disagreement", "5c median |event time diff|",
              "5d jams below mu_P", "5d Cor. 4.2 slip not ended"]


def test_cli_passes_and_writes_standard_json(capsys):
    assert main(["validate", "mujoco", "--states", "30", "--seed", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)  # json.loads rejects NaN only if asked; check below
    assert out["passed"] is True and out["engine"] == "mujoco"
    assert [s["quantity"] for s in out["stats"]] == QUANTITIES
    assert all(s["passed"] for s in out["stats"])
    runs = out["extra"]["event_agreement"]["runs"]
    assert [r["classifier"] for r in runs] == ["part_a", "effective"]
    conf = np.array(runs[1]["confusion"])
    assert conf.shape == (6, 6) and conf.sum() == 30 and runs[1]["labels"][3] == "JAM"
    assert {row["mu"] for row in out["extra"]["jams"]["below"]} == {0.5, 1.0, 1.15, 1.3}
    # only mu whose smallest p exceeds the JAM rule's p_eff bound are asserted
    assert out["extra"]["jams"]["asserted_below"] == [0.5, 1.0, 1.15]
    assert [r["mu"] for r in out["extra"]["jams"]["near_mu_P_not_asserted"]["rows"]] == [1.3]
    json.dumps(out, allow_nan=False)  # standard JSON: no NaN / Infinity survived


def test_cli_exits_one_and_names_the_check_when_the_reference_is_wrong(monkeypatch, capsys):
    """5a with the force left at A instead of the capsule's contact point misses by O(r): FAILED, exit 1."""
    monkeypatch.setattr(validate_mujoco, "capsule_tip_acceleration", lambda rod, psi, theta, psi_dot, theta_dot, F, offset: analytic.tip_acceleration(rod, psi, theta, psi_dot, theta_dot, F))
    assert main(["validate", "mujoco", "--states", "20", "--seed", "2"]) == 1
    lines = capsys.readouterr().out.rstrip().splitlines()
    assert lines[-1] == "FAILED"
    assert [line.split("  ")[0] for line in lines if " FAIL " in line] == ["5a tip acc with contact"]


def test_contact_acceleration_is_exact_at_the_contact_point_and_off_by_r_at_A():
    rng = np.random.default_rng(4)
    ca = validate_mujoco.contact_acceleration(validate_mujoco.Rod.scaled(3.0), 12, rng, radius=0.02)
    err = np.abs(ca["got"] - ca["want"]).max(axis=1) / ca["scale"]
    assert err.max() <= MUJOCO_CONTACT_ACCELERATION.atol


def test_liftoff_onset_brackets_Psi_L():
    onset, res = validate_mujoco.liftoff_onset(validate_mujoco.Rod.scaled(3.0), 1.0, rounds=3)
    assert res < 1e-6
    assert float(validate_mujoco.Psi_L) <= onset + res and onset - float(validate_mujoco.Psi_L) <= 1e-6 + res


def test_random_event_points_start_slipping_and_are_seeded():
    a = validate_mujoco.random_event_points(200, np.random.default_rng(7))
    b = validate_mujoco.random_event_points(200, np.random.default_rng(7))
    for k in a:
        np.testing.assert_array_equal(a[k], b[k])
    s, c = np.sin(a["theta"]), np.cos(a["theta"])
    assert np.all((a["Psi"] ** 2 * c**2 + a["Theta"] ** 2) * s - 1 < 0)
    assert np.all(1 + 3 + 3 * s * (a["mu"] * c * np.sin(a["varphi"]) - s) > 0)
    assert a["mu"].min() >= 0.3 and a["mu"].max() <= 6.0 and np.all((-np.pi < a["varphi"]) & (a["varphi"] <= 0))


def test_bad_state_count():
    with pytest.raises(ValueError, match="n_states must be >= 1"):
        validate_mujoco.validate(0, np.random.default_rng(0))
