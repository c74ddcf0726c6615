"""``crosscheck validate ENGINE``: MuJoCo's contact and event checks and Pinocchio's dynamics terms, small sizes, real engines."""

from __future__ import annotations

import json

import numpy as np
import pytest

from crosscheck import Outcome, Rod
from crosscheck.cli import main
from crosscheck.engines.mujoco.studies import contact as mujoco_contact
from crosscheck.engines.mujoco.tolerances import MUJOCO_CONTACT_ACCELERATION
from crosscheck.studies import validate as validation
from crosscheck.studies.grids import random_event_points
from crosscheck.studies.onset import liftoff_onset
from crosscheck.theory import analytic
from crosscheck.theory.critical import Psi_L

RIGID_QUANTITIES = [
    "one-step normal impulse / dt vs -b/p",
    "slipping convergence order",
    "post-jam rates vs IWC order (planar impasse)",
    "lift-off onset Psi",
    "event disagreement",
    "median |event time difference|",
    "jams below mu_P",
    "Corollary 4.2 slip not ended",
]

QUANTITIES = [
    "tip acceleration with contact",
    "lift-off onset Psi",
    "event disagreement",
    "median |event time difference|",
    "jams below mu_P",
    "Corollary 4.2 slip not ended",
]


def test_cli_passes_and_writes_standard_json(capsys):
    assert main(["validate", "mujoco", "--states", "30", "--seed", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)  # json.loads rejects NaN only if asked; check below
    assert out["passed"] is True and out["engine"] == "mujoco"
    assert [s["quantity"] for s in out["stats"]] == QUANTITIES
    assert all(s["passed"] for s in out["stats"])
    runs = out["extra"]["event_agreement"]["runs"]
    assert [r["engine"] for r in runs] == ["mujoco"]
    conf = np.array(runs[0]["confusion"])
    assert conf.shape == (len(Outcome), len(Outcome)) and conf.sum() == 30 and runs[0]["labels"][3] == "JAM"
    assert {row["mu"] for row in out["extra"]["jams"]["below"]} == {0.5, 1.0, 1.15, 1.3}
    # only mu whose smallest p exceeds the JAM rule's p_eff bound are asserted
    assert out["extra"]["jams"]["asserted_below"] == [0.5, 1.0, 1.15]
    assert [r["mu"] for r in out["extra"]["jams"]["near_mu_P_not_asserted"]["rows"]] == [1.3]
    json.dumps(out, allow_nan=False)  # standard JSON: no NaN / Infinity survived


def test_cli_exits_one_and_names_the_check_when_the_reference_is_wrong(monkeypatch, capsys):
    """The contact check with the force left at A instead of the capsule's contact point misses by O(r): FAILED, exit 1."""
    monkeypatch.setattr(
        mujoco_contact,
        "capsule_tip_acceleration",
        lambda rod, psi, theta, psi_dot, theta_dot, F, offset: analytic.tip_acceleration(
            rod, psi, theta, psi_dot, theta_dot, F
        ),
    )
    assert main(["validate", "mujoco", "--states", "20", "--seed", "2"]) == 1
    lines = capsys.readouterr().out.rstrip().splitlines()
    assert lines[-1] == "FAILED"
    assert [line.split("  ")[0] for line in lines if " FAIL " in line] == ["tip acceleration with contact"]


def test_contact_acceleration_is_exact_at_the_contact_point_and_off_by_r_at_A():
    rng = np.random.default_rng(4)
    ca = mujoco_contact.contact_acceleration(Rod.scaled(3.0), 12, rng, radius=0.02)
    err = np.abs(ca["got"] - ca["want"]).max(axis=1) / ca["scale"]
    assert err.max() <= MUJOCO_CONTACT_ACCELERATION.atol


def test_liftoff_onset_brackets_Psi_L():
    onset, res = liftoff_onset(Rod.scaled(3.0), 1.0, engine="mujoco", rounds=3)
    assert res < 1e-6
    assert float(Psi_L) <= onset + res and onset - float(Psi_L) <= 1e-6 + res


def test_random_event_points_start_slipping_and_are_seeded():
    a = random_event_points(200, np.random.default_rng(7))
    b = random_event_points(200, np.random.default_rng(7))
    for k in a:
        np.testing.assert_array_equal(a[k], b[k])
    s, c = np.sin(a["theta"]), np.cos(a["theta"])
    assert np.all((a["Psi"] ** 2 * c**2 + a["Theta"] ** 2) * s - 1 < 0)
    assert np.all(1 + 3 + 3 * s * (a["mu"] * c * np.sin(a["varphi"]) - s) > 0)
    assert a["mu"].min() >= 0.3 and a["mu"].max() <= 6.0 and np.all((-np.pi < a["varphi"]) & (a["varphi"] <= 0))


def test_bad_state_count_and_engine():
    with pytest.raises(ValueError, match="n_states must be >= 1"):
        validation.validate("mujoco", 0, np.random.default_rng(0))
    with pytest.raises(ValueError, match="engine must be one of .*mujoco, pinocchio.*; got 'no_such_engine'"):
        validation.validate("no_such_engine", 10, np.random.default_rng(0))
    # validate judges exactly the engines that declare dynamics terms or an event-tolerance profile
    assert {"mujoco", "pinocchio"} <= set(validation.names()) and "compliant" not in validation.names()
    assert validation.parts_of("pinocchio") == ("dynamics", "events") and validation.parts_of("mujoco") == ("events",)
    with pytest.raises(ValueError, match="checks must be among dynamics, events; got 'speed'"):
        validation.validate("mujoco", 10, np.random.default_rng(0), checks=("speed",))
    with pytest.raises(ValueError, match=r"checks must include a part mujoco has \(events\); got dynamics"):
        validation.validate("mujoco", 10, np.random.default_rng(0), checks=("dynamics",))
    assert (
        validation.default_states("mujoco") == validation.DEFAULT_STATES
        and validation.default_states("pinocchio") == 10_000
    )


def test_rigid_engine_event_checks_pass():
    """The rigid engine's own and event checks pass on the real engine (small sizes: 30 states, 10 per jam row)."""
    out = validation.contact_events("pinocchio", 30, np.random.default_rng(1), jam_states=(10, 10))
    assert [s.quantity for s in out.stats] == RIGID_QUANTITIES and out.passed, out.to_table()
    assert out.extra["event_agreement"]["runs"][0]["solver_health"]["states"] == 30
    assert (
        out.extra["corollary_jam_fraction"] >= 0.5
    )  # regression guard: measured 0.74 at seed 1 with 30 per mu (mu = 6: 0.57)
