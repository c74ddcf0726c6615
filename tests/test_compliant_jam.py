"""A compliant contact's impact without collision reads as a JAM (crosscheck.engines.classifier, ``contact_time``).

The compliant rod (Kelvin-Voigt normal law, exact Coulomb friction) from Painleve's inconsistent start resolves the
impact without collision in a slip stop after t_stop = (eps/lambda) ln(1/eps) + C eps (crosscheck.theory.compliant_limit),
under a force O(1/eps) while its p is < 0.  The window rule alone reads that stop as a STICK (the window holding it also
holds the stuck contact after it, whose static friction lifts the window's p_eff); with the engine's contact time the
stop itself is judged, and reads JAM at each eps with the stop's time, which tends to the rigid jam at t = 0 at the order
eps ln(1/eps).  A slip that decelerates to a stop under the slipping force at p = O(1) stays a STICK, and Drake's
continuous Hunt-Crossley contact jams as the compliant rod does.
"""

from __future__ import annotations

import math

import pytest

from crosscheck import Outcome, Rod, SlipState
from crosscheck.engines import Thresholds, classify, get
from crosscheck.engines.compliant.tolerances import COMPLIANT_LIMIT_SLIP_TIME
from crosscheck.theory import analytic as an
from crosscheck.theory.compliant_limit import fast_limit, time_corrections
from crosscheck.theory.slipping import slip_until_event

ALPHA = 3.0
SCALED = Rod.scaled(ALPHA)
COMPLIANT = get("compliant")
EPS = (3e-2, 1e-2, 3e-3)
#: Record rows per contact time: the look-back of jam_contact_times = 3 contact times then holds 30 rows.
ROWS_PER_EPS = 10

#: Painleve's inconsistent start on the planar section: p = 4 - 3/2 - 3 = -1/2, b = -1 (eqs. p, b).
INCONSISTENT = (SlipState(theta=math.pi / 4, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0), 2.0)

#: A consistent slip (p = 1.87, b = -0.85) that decelerates to a stop at t = 0.34 under the slipping force -b/p ~ 0.6 m g.
SLOW_STICK = (SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=0.2), 1.0)

#: A start of the report's ladders (mu = 1.4, p = 0.032, b = -0.94): the theory slips into p = 0 and jams at t = 0.0022
#: (Corollary 4.2); Drake's TAMSI and continuous contacts were read STICK there.
LADDER_JAM = (SlipState(theta=1.175, varphi=-1.9, Theta=0.25, Psi=0.0, eta=1.0), 1.4)


def _classify(run, mu, *, contact_time):
    o = run.options
    return classify(
        run.record,
        mu=mu,
        alpha=ALPHA,
        timestep=o.timestep,
        friction_timeconst=o.friction_time,
        contact_time=contact_time,
    )


@pytest.fixture(scope="module")
def inconsistent_runs():
    state, mu = INCONSISTENT
    return {
        eps: COMPLIANT.simulate(SCALED, state, mu, horizon=0.15, eps=eps, xi=1.0, timestep=eps / ROWS_PER_EPS)
        for eps in EPS
    }


@pytest.mark.parametrize("eps", EPS, ids=str)
def test_the_inconsistent_start_jams_at_its_first_slip_stop(inconsistent_runs, eps):
    """JAM at the first slip stop (within one row of the integration's exact stop), where the window rule read STICK."""
    state, mu = INCONSISTENT
    assert an.p(state.theta, state.varphi, mu, ALPHA) == pytest.approx(-0.5) and an.b(
        state.Psi, state.Theta, state.theta
    ) == pytest.approx(-1.0)
    run = inconsistent_runs[eps]
    dt = run.options.timestep
    assert run.options.contact_time == eps
    window_only = _classify(run, mu, contact_time=None)
    c = _classify(run, mu, contact_time=run.options.contact_time)
    assert Outcome(int(window_only.outcome)) == Outcome.STICK
    assert Outcome(int(c.outcome)) == Outcome.JAM and c.event_row == window_only.event_row
    assert abs(c.event_time - run.solver.slip_stop_time) <= dt
    # the engine's own p while it slipped is eq. p of the start (exact Coulomb friction; it drifts by O(t_stop))
    assert c.jam_p_eff == pytest.approx(-0.5, abs=0.05)
    # the look-back of 3 eps holds the stop's impulse P_stop (the fast problem's) but its first fraction
    # e^(-3 lambda), give or take the slip phase's drift C1 eps (relative, time_corrections)
    fast = fast_limit(state, mu, ALPHA, xi=1.0)
    C1, _ = time_corrections(fast)
    assert c.jam_impulse == pytest.approx(fast.P_stop, rel=math.exp(-3.0 * fast.lam) + C1 * eps)


def test_the_jam_time_tends_to_the_rigid_jam_as_eps_ln_one_over_eps(inconsistent_runs):
    """The JAM's time T = t/eps follows the compliant limit's slip-stop law ln(1/eps)/lambda + C + C1 eps T + C2 eps T^2:
    the jam time falls to the rigid jam's t = 0 as eps ln(1/eps).  Allowance: the law's (COMPLIANT_LIMIT_SLIP_TIME) and one
    record row (1/ROWS_PER_EPS in T: the classifier's stop row is the first row after the stop)."""
    state, mu = INCONSISTENT
    fast = fast_limit(state, mu, ALPHA, xi=1.0)
    C1, C2 = time_corrections(fast)
    times = []
    for eps in EPS:
        run = inconsistent_runs[eps]
        c = _classify(run, mu, contact_time=run.options.contact_time)
        assert Outcome(int(c.outcome)) == Outcome.JAM
        T = float(c.event_time) / eps
        correction = C1 * eps * T + C2 * eps * T * T
        remainder = T - (fast.coefficient * math.log(1.0 / eps) + fast.offset) - correction
        assert abs(remainder) <= COMPLIANT_LIMIT_SLIP_TIME.allowance(correction) + 1.0 / ROWS_PER_EPS, (
            eps,
            T,
            remainder,
            correction,
        )
        times.append(float(c.event_time))
    assert times[0] > times[1] > times[2] > 0.0


@pytest.mark.parametrize("eps", EPS, ids=str)
def test_a_slow_stop_under_the_slipping_force_stays_a_stick(eps):
    """A consistent slip (p = 1.87 > jam_p_eff) decelerating under ~-b/p to a stop: STICK with and without the contact time."""
    state, mu = SLOW_STICK
    assert an.p(state.theta, state.varphi, mu, ALPHA) > 1.0
    run = COMPLIANT.simulate(SCALED, state, mu, horizon=0.5, eps=eps, xi=1.0, timestep=eps / ROWS_PER_EPS)
    c = _classify(run, mu, contact_time=run.options.contact_time)
    window_only = _classify(run, mu, contact_time=None)
    assert Outcome(int(c.outcome)) == Outcome(int(window_only.outcome)) == Outcome.STICK
    assert c.event_row == window_only.event_row
    assert (
        abs(c.event_time - run.solver.slip_stop_time) < 0.05
    )  # the stop itself, read early by the stick speed / |eta'|
    assert run.record.normal_force.max() < 1.0  # no impulse: the force stays near the slipping -b/p ~ 0.6 m g


def test_drakes_continuous_contact_jams_where_the_theory_does():
    """Drake's continuous Hunt-Crossley contact at stiffness 1e6 (contact time 1e-3, rows of 2e-4) from the ladder's jam start:
    its slip stops at t = 0.0058 with p_eff < 0 on its last slipping rows: JAM there, where the window rule read STICK."""
    state, mu = LADDER_JAM
    theory = slip_until_event(state, mu, ALPHA, t_max=1.0)
    assert theory.outcome == Outcome.JAM and theory.time < 0.003
    run = get("drake_continuous").simulate(SCALED, state, mu, horizon=0.1, stiffness=1e6, timestep=2e-4)
    assert run.options.contact_time == pytest.approx(1e-3)
    window_only = _classify(run, mu, contact_time=None)
    c = _classify(run, mu, contact_time=run.options.contact_time)
    assert Outcome(int(window_only.outcome)) == Outcome.STICK
    assert Outcome(int(c.outcome)) == Outcome.JAM and c.event_row == window_only.event_row
    assert c.jam_p_eff <= 0.0
    # after the theory's jam, within a few contact times (the compliant lag behind a Corollary 4.2 jam)
    assert theory.time < c.event_time < theory.time + 5 * run.options.contact_time
    assert Thresholds().stop_rows(run.options.contact_time, run.options.timestep) == 15
