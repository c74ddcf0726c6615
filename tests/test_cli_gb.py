"""``crosscheck gb`` and ``crosscheck slip``: output agrees with the API; bad input is one line, exit 2."""

import json

import numpy as np
import pytest

from crosscheck import SlipState
from crosscheck.cli import main
from crosscheck.theory import gb

SLIP_ARGS = [
    "slip",
    "--theta",
    "1.1031",
    "--varphi",
    "-1.9233",
    "--Theta",
    "0.9",
    "--Psi",
    "0",
    "--eta",
    "2",
    "--mu",
    "1.4",
]


def test_gb_json_matches_the_api(capsys):
    assert main(["gb", "--mu", "1.4", "--alpha", "3", "--Psi", "0", "--samples", "5", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    curves = gb.gb_manifold(1.4, 0.0, 3.0)
    assert [c["Theta_sign"] for c in got["curves"]] == [c.sign for c in curves] == [1, -1]
    first = got["curves"][0]["samples"][0]  # P+ = (theta_1, -pi/2), a stable node (eq. K2d)
    assert first["type"] == "STABLE_NODE" and first["theta"] == pytest.approx(0.9702, abs=1e-4)
    zeros = got["curves"][0]["det_K_zeros"]
    assert len(zeros) == 2 and zeros[0]["theta"] == pytest.approx(1.0953, abs=1e-4)  # Fig. 12(c)
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
        (
            SLIP_ARGS[:-4] + ["--mu", "1.4"],
            "the following arguments are required: --eta (--eta: scaled slip speed of the tip, in [0, 100])",
        ),
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
    from crosscheck.theory import analytic

    for c in got["curves"]:
        th = np.array([s["theta"] for s in c["samples"]])
        vp = np.array([s["varphi"] for s in c["samples"]])
        Th = np.array([s["Theta"] for s in c["samples"]])
        assert np.max(np.abs(analytic.b(1.8997, Th, th))) < 1e-12
        assert np.max(np.abs(analytic.p(th, vp, 6.0, 3.0))) < 1e-12


def test_det_K_zeros_do_not_depend_on_the_samples_printed(capsys):
    """The zeros are bracketed on the command's own resolution: asking to see 1, 2 or 9 samples finds the same four."""
    found = []
    for n in ("1", "2", "9"):
        assert main(["gb", "--mu", "1.7", "--Psi", "0", "--eta", "2", "--samples", n, "--json"]) == 0
        doc = json.loads(capsys.readouterr().out)
        assert all(len(c["samples"]) == int(n) for c in doc["curves"])
        found.append([(z["theta"], z["varphi"], z["Theta"]) for c in doc["curves"] for z in c["det_K_zeros"]])
    assert len(found[0]) == 4 and len({tuple(np.round(np.ravel(f), 12)) for f in found}) == 1


def test_a_start_on_p_0_at_mu_P_is_on_the_boundary_and_does_not_jam(capsys):
    """At mu = mu_P, theta_P, varphi = -pi/2 p = 0 exactly (computed -8.9e-16): no paradox exists (p_min = 0).

    classify names the boundary and the modes either side of it; the run does not jam at t = 0: F_z = -b/p is
    unbounded there, so the slip stops at once (STICK at t = 0, as MuJoCo's rod sticks)."""
    from crosscheck.theory import critical

    th, mu = critical.theta_P(3.0), critical.mu_P(3.0)
    state = [
        "--theta",
        repr(float(th)),
        "--varphi",
        repr(-np.pi / 2),
        "--Theta",
        "0",
        "--Psi",
        "0",
        "--mu",
        repr(float(mu)),
    ]
    assert main(["classify", *state, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert abs(doc["p"]) <= doc["p_rounding"] and doc["p"] != 0.0
    assert (
        doc["mode"] == "BOUNDARY"
        and doc["boundary"] == "p = 0"
        and doc["modes_either_side"] == ["INCONSISTENT", "SLIP"]
    )
    assert doc["F_z"] is None
    assert main(["slip", *state, "--eta", "1", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["outcome"] == "STICK" and r["time"] == 0.0
    # just above mu_P the paradox exists and the same start is inside it: a JAM at t = 0
    assert main(["slip", *state[:-1], repr(float(mu) * 1.01), "--eta", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["outcome"] == "JAM"


def test_a_start_slower_than_the_stick_speed_is_stuck():
    """eta = 1e-300 once gave a JAM at t = 1.7e-304: a start below the run's own stick speed is STICK at t = 0."""
    from crosscheck.state import SlipState
    from crosscheck.theory.slipping import slip_until_event
    from crosscheck.tolerances import STICK_SPEED

    for eta in (1e-300, 0.5 * STICK_SPEED.atol):
        r = slip_until_event(SlipState(theta=1.1031, varphi=-1.9233, Theta=0.9, Psi=0.0, eta=eta), 1.4, 3.0)
        assert r.outcome.name == "STICK" and r.time == 0.0 and r.reason == "start"


GLOCKER_ARGS = [
    "slip",
    "--theta",
    repr(float(np.radians(31.0))),
    "--varphi",
    repr(-np.pi / 2),
    "--Theta",
    "0",
    "--Psi",
    "0",
    "--eta",
    repr(30 / 10**0.5),
    "--mu",
    repr(5 / 3),
]


def test_slip_continue_goes_through_the_gb_point(capsys):
    """Glocker's rod reaches P+ (b = p = 0) at t* = 2.5758: the limit impulse stops its slip, and at rest with b > 0 it lifts off."""
    assert main(GLOCKER_ARGS + ["--continue"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("slip from t = 0 to 2.57583219: GB (gb)")
    assert (
        out[1].startswith("  impact without collision: P = 1.10677, tangential (")
        and "slip to P = 1.10677, stick to P = 1.10677" in out[1]
    )
    assert out[2].startswith("  after: Theta = 2.754417  Psi = -0.000000  eta = 0")
    assert out[-1] == "LIFTOFF at t = 2.57583219 (impact: at rest with b > 0 (sticking would need F_n < 0))"


def test_slip_continue_sticks_and_slips_again(capsys):
    args = [
        "slip",
        "--theta",
        "1.2",
        "--varphi",
        repr(-np.pi / 2),
        "--Theta",
        "-0.3",
        "--Psi",
        "0.5",
        "--psi",
        "0.4",
        "--eta",
        "0",
        "--mu",
        "0.3",
    ]
    assert main(args + ["--t-max", "1", "--continue"]) == 0
    assert capsys.readouterr().out.splitlines() == [
        "slip from t = 0 to 0: STICK (start); b = -0.886, p = 1.09",
        "stick from t = 0 to 0.174368173: SLIP (cone); F_j = 0.218, F_n = 0.728; slips at varphi = -1.570796",
        "slip from t = 0.174368173 to 1: SLIP (t_max); b = -0.64, p = 2.34",
        "SLIP at t = 1 (t_max)",
    ]
    assert main(args + ["--t-max", "1", "--continue", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [s["mode"] for s in doc["segments"]] == ["slip", "stick", "slip"] and doc["segments"][1][
        "slip_varphi"
    ] == -np.pi / 2
    assert doc["segments"][1]["start"]["varphi"] is None
