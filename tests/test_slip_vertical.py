"""Near the vertical the slipping rod leaves the paper's domain at once, and says so.

The cause is the slender rod's: Psi' = -alpha mu F_z cos varphi / cos theta + ... (the friction's moment about the
vertical over an inertia I0 cos^2 theta), so from Theta = Psi = 0 the azimuth turns varphi to -pi in
t ~ sqrt(2 Delta cos theta / (alpha mu F_z |cos varphi|)), with Psi ~ 1 / sqrt(cos theta) at the exit
(``crosscheck.theory.slipping``'s docstring).  The run reports a SLIP up to that time only (``left_domain``), never a
SLIP of the whole horizon.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from crosscheck import SlipState
from crosscheck.cli import main
from crosscheck.theory.slipping import slip_until_event
from crosscheck.tolerances import THETA_MARGIN

START = dict(varphi=-1.9233, eta=2.0)
MU, ALPHA = 1.4, 3.0
DISTANCES = np.array([1e-5, 1e-4, 1e-3])  # pi/2 - theta, beyond THETA_MARGIN (1e-6)


def test_the_exit_time_and_rate_scale_as_the_slender_rods_azimuthal_spin():
    runs = [
        slip_until_event(SlipState(theta=math.pi / 2 - d, Theta=0.0, Psi=0.0, **START), MU, ALPHA, t_max=1.0)
        for d in DISTANCES
    ]
    assert all(r.left_domain and r.reason == "varphi=-pi" for r in runs)
    t = np.array([r.time for r in runs])
    Psi = np.array([r.state.Psi for r in runs])
    # the slopes of t and Psi against cos theta ~ pi/2 - theta on log axes: 1/2 and -1/2 (the estimate's sqrt)
    assert np.polyfit(np.log(DISTANCES), np.log(t), 1)[0] == pytest.approx(0.5, abs=0.02)
    assert np.polyfit(np.log(DISTANCES), np.log(np.abs(Psi)), 1)[0] == pytest.approx(-0.5, abs=0.02)
    # within a factor 2 of the estimate with F_z = 1 and |cos varphi| at its mean over the turn from -1.9233 to -pi
    turn = math.pi - 1.9233
    mean_cos = math.sin(1.9233) / turn  # mean |cos varphi| on [-pi, -1.9233], where cos varphi < 0
    estimate = np.sqrt(2 * turn * np.cos(math.pi / 2 - DISTANCES) / (ALPHA * MU * abs(mean_cos)))
    assert np.all((0.5 < t / estimate) & (t / estimate < 2.0)), t / estimate
    # the rod itself turns less the nearer the vertical: its angular velocity normal to its axis, Psi cos theta,
    # goes to 0 as sqrt(cos theta) (0.026 at 1e-5)
    normal = np.abs(Psi * np.sin(DISTANCES))
    assert np.all(np.diff(normal) > 0) and normal[0] < 0.03


@pytest.mark.parametrize("Theta", [0.3, 0.9])
def test_a_start_falling_through_the_vertical_leaves_when_it_reaches_the_margin(Theta):
    d = 1e-5
    r = slip_until_event(SlipState(theta=math.pi / 2 - d, Theta=Theta, Psi=0.0, **START), MU, ALPHA, t_max=1.0)
    assert r.left_domain and r.reason == "theta=pi/2"
    assert r.time == pytest.approx((d - THETA_MARGIN.atol) / Theta, rel=1e-3)


def test_slip_says_a_domain_exit_is_not_the_horizons_slip(capsys):
    argv = ["slip", "--theta", repr(math.pi / 2 - 1e-4), "--varphi", "-1.9233", "--Theta", "0", "--Psi", "0"]
    argv += ["--eta", "2", "--mu", "1.4", "--t-max", "1"]
    assert main(argv) == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert line.startswith("SLIP up to t = 0.00") and line.split(" only: ")[1].startswith(
        "the run left the paper's domain there (varphi reached -pi, the tip slipping square to the rod's projection, "
        "then towards S); no event before it, nothing said after it;"
    )
    assert main([*argv, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["left_domain"] is True
    far = ["slip", "--theta", "1.1031", "--varphi", "-1.9233", "--Theta", "0.9", "--Psi", "0", "--eta", "2"]
    assert main([*far, "--mu", "0.5", "--t-max", "0.2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["outcome"], out["reason"], out["left_domain"]) == ("SLIP", "t_max", False)
