"""The hybrid rigid model (crosscheck.theory.impact.continuation): slipping, an impact without collision at a jam, and what follows."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck import Outcome, SlipState
from crosscheck.cli import main
from crosscheck.theory.corollary import corollary_states
from crosscheck.theory.impact.continuation import run
from crosscheck.theory.impact.darboux_keller import impact
from crosscheck.theory.slipping import slip_until_event

ALPHA = 3.0


def test_without_a_jam_the_hybrid_run_is_the_slipping_flow():
    s = SlipState(theta=0.6, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.0)
    h, r = run(s, 0.5, ALPHA, horizon=2.0), slip_until_event(s, 0.5, ALPHA, t_max=2.0)
    assert (h.outcome, h.time, h.reason) == (r.outcome, r.time, r.reason) and len(h.segments) == 1 and not h.impacts


def test_a_corollary_jam_goes_through_the_impact_that_iwc_computes():
    (s,), (t_jam,), _ = corollary_states(1.7, 1, np.random.default_rng(0))
    h = run(s, 1.7, ALPHA, horizon=2.0)
    seg = h.segments[0]
    assert seg.slip.outcome == Outcome.JAM and seg.t1 == pytest.approx(t_jam)
    want = impact(seg.slip.state, 1.7, ALPHA)
    assert seg.impact.normal_impulse == want.normal_impulse and seg.impact.Theta == want.Theta
    # e = 0: the slip stops inside the cone; at rest the tip would need a pull (b > 0): it leaves the plane at once, as the
    # rigid engine's tip does (tests/test_theory_sticking.py)
    assert seg.impact.eta == 0.0 and abs(seg.impact.w) < 1e-12
    assert (h.outcome, h.reason) == (
        Outcome.LIFTOFF,
        "impact: at rest with b > 0 (sticking would need F_n < 0)",
    ) and h.time == pytest.approx(t_jam)
    # a restitution > 0 makes the tip rebound: lift-off at the jam
    assert run(s, 1.7, ALPHA, horizon=2.0, restitution=0.5).reason == "impact: rebound (w > 0)"


def test_cli_continue_prints_the_impact_and_bad_restitution_is_named(capsys):
    args = [
        "slip",
        "--theta",
        "1.1067",
        "--varphi",
        "-1.8913",
        "--Theta",
        "0.9",
        "--Psi",
        "-0.1027",
        "--eta",
        "2.1307",
        "--mu",
        "1.4",
    ]
    assert main(args + ["--continue"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("slip from t = 0 to 0.000434") and "impact without collision: P = 0.5712" in out[1]
    assert out[-1] == "LIFTOFF at t = 0.00043400815 (impact: at rest with b > 0 (sticking would need F_n < 0))"
    assert main(args + ["--continue", "--restitution", "2"]) == 2
    assert capsys.readouterr().err.strip() == "crosscheck: error: restitution must be in [0, 1]; got 2.0"
    assert math.isfinite(float(out[1].split("P = ")[1].split(",")[0]))
