"""``crosscheck gb`` and ``crosscheck slip``: output agrees with the API; bad input is one line, exit 2."""

import json

import numpy as np
import pytest

from crosscheck import SlipState
from crosscheck import gb
from crosscheck.cli import main

SLIP_ARGS = ["slip", "--theta", "1.1031", "--varphi", "-1.9233", "--Theta", "0.9", "--Psi", "0", "--eta", "2", "--mu", "1.4"]


def test_gb_json_matches_the_api(capsys):
    assert main(["gb", "--mu", "1.4", "--alpha", "3", "--Psi", "0", "--samples", "5", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    curves = gb.gb_manifold(1.4, 0.0, 3.0)
    assert [c["Theta_sign"] for c in got["curves"]] == [c.sign for c in curves] == [1, -1]
    first = got["curves"][0]["samples"][0]  # P+ = (theta_1, -pi/2), a stable node (eq. K2d)
    assert first["type"] == "STABLE_NODE" and first["theta"] == pytest.approx(0.9702, abs=1e-4)
    zeros = got["curves"][0]["det_K_zeros"]
    assert len(zeros) == 2 and zeros[0]["theta"] == pytest.approx(1.0953, abs=1e-4)  # Fig. 8(c)
    assert got["kinematic_case"] == 3


def test_gb_text_reports_no_manifold_above_Psi_2(capsys):
    assert main(["gb", "--mu", "1.4", "--Psi", "3.1"]) == 0
    out = capsys.readouterr().out
    assert "0 closed curve(s)" in out and "|Psi| > Psi_2" in out


def test_slip_json_matches_the_api(capsys):
    assert main(SLIP_ARGS + ["--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    r = gb.slip_until_event(SlipState(theta=1.1031, varphi=-1.9233, Theta=0.9, Psi=0.0, eta=2.0), 1.4, 3.0)
    assert got["outcome"] == r.outcome.name == "LIFTOFF"
    assert got["time"] == r.time and got["state"] == r.state.as_dict()


def test_slip_text(capsys):
    assert main(SLIP_ARGS) == 0
    assert capsys.readouterr().out.startswith("LIFTOFF at t = 0.01653993")


@pytest.mark.parametrize(
    "argv, message",
    [
        (["gb", "--mu", "-1"], "mu must be in [0, 1000]; got -1.0"),
        (["gb", "--mu", "1.4", "--Psi", "abc"], "Psi must be a number in [-100, 100]; got 'abc'"),
        (["gb", "--mu", "1.4", "--eta", "-2"], "eta must be in [0, 100]; got -2.0"),
        (["gb"], "the following arguments are required: --mu (--mu: friction coefficient, in [0, 1000])"),
        (["slip", "--theta", "2"] + SLIP_ARGS[3:], "theta must be in (0, pi/2); got 2.0"),
        (SLIP_ARGS[:3] + ["--varphi", "0.5"] + SLIP_ARGS[5:], "varphi must be in (-pi, 0]; got 0.5"),
        (SLIP_ARGS[:-4] + ["--mu", "1.4"], "the following arguments are required: --eta (--eta: scaled slip speed of the tip, in [0, 100])"),
        (SLIP_ARGS + ["--t-max", "0"], "t_max must be in (0, 10000]; got 0.0"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(argv, message, capsys):
    assert main(argv) == 2
    assert capsys.readouterr().err == f"crosscheck: error: {message}\n"


def test_gb_samples_are_on_the_manifold(capsys):
    assert main(["gb", "--mu", "6", "--Psi", "1.8997", "--eta", "10", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert len(got["curves"]) == 2 and all(c["crosses_Theta_0"] for c in got["curves"])
    from crosscheck import analytic

    for c in got["curves"]:
        th = np.array([s["theta"] for s in c["samples"]])
        vp = np.array([s["varphi"] for s in c["samples"]])
        Th = np.array([s["Theta"] for s in c["samples"]])
        assert np.max(np.abs(analytic.b(1.8997, Th, th))) < 1e-12
        assert np.max(np.abs(analytic.p(th, vp, 6.0, 3.0))) < 1e-12
