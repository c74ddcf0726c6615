"""The impact without collision in size on an engine (``crosscheck.studies.jam_impact``): theory, energy and the rigid
engine."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck import engines
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.studies.jam_impact import compare_jam, mechanical_energy, theory_after_jam
from crosscheck.theory.impact.darboux_keller import impact
from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS
from crosscheck.theory.slipping import slip_until_event

IC1 = SlipState(**FIG20_INITIAL_CONDITIONS[0])
MU, ALPHA = 1.4, 3.0


def test_the_theory_jams_from_ic1_at_the_time_and_with_the_impact_the_issue_quotes():
    th = theory_after_jam(IC1, MU, ALPHA, settle=0.01)
    # 4 printed digits each: t_jam 4.34e-4, Theta+ 2.2564, Psi+ 1.0227 (the 3D Darboux-Keller impulse, e = 0)
    assert th["t_jam"] == pytest.approx(4.34e-4, abs=5e-7)
    assert th["Theta_plus"] == pytest.approx(2.2564, abs=5e-5)
    assert th["Psi_plus"] == pytest.approx(1.0227, abs=5e-5)
    # IC1's rod lifts off from rest after the impulse (b > 0 at Theta+) and flies over settle, energy kept: what it has
    # is its start's less the impulse's loss and the friction's work over the 4.34e-4 of slip before it
    h = IC1.varphi + IC1.psi
    start = mechanical_energy(
        IC1.theta, IC1.psi, IC1.Theta, IC1.Psi, [IC1.eta * math.cos(h), IC1.eta * math.sin(h), 0.0], 0.0, ALPHA
    )
    friction_work = start - th["energy_lost_impact"] - th["theory_energy"]
    assert 0.0 < friction_work < th["energy_lost_impact"]  # measured 0.103 against the impulse's 0.772
    assert th["theory_Theta"] != th["Theta_plus"]


def test_mechanical_energy_loses_exactly_the_impulses_energy_at_the_jam_state():
    """Identity: E(before) - E(after) at the jam's configuration equals the impulse's own energy loss (from M and v)."""
    a = slip_until_event(IC1, MU, ALPHA, t_max=1.0)
    iwc = impact(a.state, MU, ALPHA)
    s = a.state
    heading = s.varphi + s.psi
    before = mechanical_energy(
        s.theta, s.psi, s.Theta, s.Psi, [s.eta * math.cos(heading), s.eta * math.sin(heading), 0.0], 0.0, ALPHA
    )
    after = mechanical_energy(s.theta, s.psi, iwc.Theta, iwc.Psi, [0.0, 0.0, iwc.w], 0.0, ALPHA)
    assert before - after == pytest.approx(iwc.energy_lost, rel=1e-9)


@pytest.mark.parametrize("timestep", [3e-3, 1e-3], ids=str)
def test_the_rigid_stepper_makes_the_theorys_impact_at_ic1(timestep):
    """Pinocchio's exact-cone time-stepper jams at IC1 and its Theta+, Psi+ are the impact's to 1 % of the jump.

    Tolerance: 1 % of the jump Theta_jam -> Theta+ (0.9 -> 2.26) and Psi_jam -> Psi+, the impact's size to two digits;
    a soft jam that dissipates the jump (MuJoCo's, ~0.3 off) or no jam (~1.3 off) is far outside.  Measured: 1.0e-3 and
    4.6e-4 in Theta (0.07 % and 0.03 %), 2.5e-3 and 1.2e-3 in Psi.
    """
    r = compare_jam(engines.get("pinocchio"), Rod.scaled(ALPHA), IC1, MU, {"timestep": timestep})
    a = slip_until_event(IC1, MU, ALPHA, t_max=1.0)
    assert r["engine_outcome"] == "JAM"
    assert abs(r["Theta_plus_engine"] - r["Theta_plus"]) <= 0.01 * abs(r["Theta_plus"] - a.state.Theta)
    assert abs(r["Psi_plus_engine"] - r["Psi_plus"]) <= 0.01 * abs(r["Psi_plus"] - a.state.Psi)
    # the slip stops in the impulse: what is left at t* is the flight's tip speed, first order in the timestep
    assert r["engine_eta"] == pytest.approx(r["theory_eta"], abs=15 * timestep)
    assert np.isfinite(r["engine_P_N"]) and r["engine_P_N"] == pytest.approx(r["P_N"], rel=0.1)
