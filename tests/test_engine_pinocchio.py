"""The rigid engine (Pinocchio's NCP solvers): one step against eq. FZ, the exact cone, lift-off onset, convergence, jams."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from crosscheck import Outcome, Rod, SlipState
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.pinocchio.stepper import Options, Stepper
from crosscheck.engines.pinocchio.studies.rigid import slip_order, slipping_states
from crosscheck.engines.pinocchio.tolerances import RIGID_LIFTOFF_ONSET, RIGID_SLIP_ORDER, RIGID_STEP_FORCE
from crosscheck.studies.onset import liftoff_onset
from crosscheck.theory import analytic
from crosscheck.theory.corollary import corollary_states
from crosscheck.theory.critical import Psi_L

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
ENGINE = get("pinocchio")
LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@pytest.mark.parametrize("dt", [1e-3, 1e-4], ids=lambda d: f"dt={d:g}")
def test_one_step_normal_impulse_is_eq_FZ_with_coulomb_friction(dt):
    """Normal impulse / dt = -b/p (eq. FZ) for the step's friction direction; |tangential| = mu normal, opposite the slip."""
    worst = 0.0
    for s, mu in slipping_states(40, np.random.default_rng(0)):
        st = Stepper(ROD, mu, Options(timestep=dt))
        q, v = to_generalized(ROD, s)
        _, v1, info = st.step(q, v)
        lam = info.impulse
        # the slip the Coulomb law of the step sees: J v1 + dt dJ v (the contact velocity at the step's end)
        pin.forwardKinematics(st.model, st.data, q, v, np.zeros(5))
        dJv = pin.getFrameClassicalAcceleration(st.model, st.data, st.tip, LWA).linear
        pin.forwardKinematics(st.model, st.data, q, v1)
        u = pin.getFrameVelocity(st.model, st.data, st.tip, LWA).linear + dt * dJv
        assert abs(u[2]) < 1e-12  # still on the plane
        varphi = math.atan2(u[1], u[0]) - q[3]
        want = -analytic.b(s.Psi, s.Theta, s.theta) / analytic.p(s.theta, varphi, mu, ALPHA)
        worst = max(worst, abs(lam[2] / dt - want) / abs(want))
        if mu > 0:
            assert np.hypot(lam[0], lam[1]) == pytest.approx(mu * lam[2], rel=1e-9)
            cos = -(lam[0] * u[0] + lam[1] * u[1]) / (np.hypot(lam[0], lam[1]) * np.hypot(u[0], u[1]))
            assert cos > 1 - 1e-12  # opposite the slip
    assert worst <= RIGID_STEP_FORCE.rtol, worst


def test_the_convex_relaxation_launches_a_slipping_tip_and_the_engine_does_not_use_it():
    """ADMM on the relaxed cone (solve_ncp False) sends the tip up at w = mu |u_t| in one step; the NCP keeps it on the plane."""
    s, mu = SlipState(theta=0.6, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.0), 0.5
    w = {}
    for solver, ncp in (("pgs", True), ("admm", True), ("admm", False)):
        st = Stepper(ROD, mu, Options(timestep=1e-3, solver=solver, ncp=ncp))
        q, v = to_generalized(ROD, s)
        q1, v1, _ = st.step(q, v)
        pin.forwardKinematics(st.model, st.data, q1, v1)
        u = pin.getFrameVelocity(st.model, st.data, st.tip, LWA).linear
        w[solver, ncp] = (u[2], mu * math.hypot(u[0], u[1]))
    assert abs(w["pgs", True][0]) < 1e-6 and abs(w["admm", True][0]) < 1e-6  # O(dt^2 dJ v): on the plane
    launched, mu_ut = w["admm", False]
    assert launched == pytest.approx(mu_ut, rel=1e-2)
    assert Options().ncp is True and Options().solver == "auto"
    with pytest.raises(ValueError, match="ncp=False .* needs solver='admm'"):
        Options(ncp=False)


@pytest.mark.parametrize("mu", [0.5, 1.4], ids=lambda m: f"mu={m}")
@pytest.mark.parametrize("dt", [3e-3, 1e-3, 3e-4, 1e-4], ids=lambda d: f"dt={d:g}")
def test_liftoff_onset_is_Psi_L_at_every_timestep(mu, dt):
    onset, res = liftoff_onset(
        ROD, mu, engine="pinocchio", timestep=dt, rounds=6, n=33, half_width=1e-3, horizon=12 * dt
    )
    assert res < 1e-10
    assert abs(onset - float(Psi_L)) <= RIGID_LIFTOFF_ONSET.atol + res


def test_slipping_converges_to_the_analytic_flow_at_first_order():
    """crosscheck.engines.pinocchio.studies.rigid.slip_order: theta, eta, Theta, Psi at t = 0.3 against slip_until_event over dt = 4e-3 ... 5e-4."""
    rate, errs = slip_order(ROD)
    assert RIGID_SLIP_ORDER.ok(rate, 1.0), rate
    assert errs[-1] < 1e-4


def test_corollary_states_jam_with_an_impulse_near_the_analytic_jam():
    """States the theory sends to p = 0 with b < 0: the rigid engine jams (one row's impulse) and its jam time converges."""
    states, t_jam, _ = corollary_states(1.7, 6, np.random.default_rng(0))
    err = {}
    for dt in (1e-3, 1e-4):
        runs = [ENGINE.simulate(ROD, s, 1.7, horizon=float(t) + 0.1, timestep=dt) for s, t in zip(states, t_jam)]
        assert all(r.outcome == Outcome.JAM for r in runs), [r.outcome.name for r in runs]
        assert all(r.jam_impulse > 0.1 and r.jam_p_eff <= 0.2 for r in runs)
        err[dt] = np.abs([r.event_time - t for r, t in zip(runs, t_jam)])
    assert np.median(err[1e-3]) < 0.01 and np.median(err[1e-4]) < 0.3 * np.median(err[1e-3])


def test_solver_health_is_recorded_and_unconverged_steps_counted():
    s = SlipState(theta=0.6, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.0)
    ok = ENGINE.simulate(ROD, s, 0.5, horizon=0.05)
    assert (
        ok.solver.contact_steps == ok.nstep
        and ok.solver.unconverged_steps == 0
        and 1 <= ok.solver.max_iterations < 1000
    )
    starved = ENGINE.simulate(ROD, s, 0.5, horizon=0.05, max_iterations=1, max_iterations_limit=1)
    assert starved.solver.unconverged_steps > 0


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"timestep": 0.0}, r"timestep must be in \(0, inf\); got 0.0"),
        ({"timestep": 0.5}, r"timestep must be in \(0, horizon = 0.1\]; got 0.5"),
        ({"solver": "lemke"}, "solver must be one of auto, closed_form, pgs, admm; got 'lemke'"),
        ({"max_iterations": 0}, "max_iterations must be an integer >= 1; got 0"),
        ({"stiffness": 1.0}, "unknown Pinocchio option 'stiffness'"),
    ],
    ids=["timestep", "timestep_above_horizon", "solver", "iterations", "unknown"],
)
def test_bad_options_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        ENGINE.simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=0.1, **kwargs)


def test_bad_mu_is_named():
    for mu in (-1.0, math.nan):
        with pytest.raises(ValueError, match=r"mu must be in \[0, 1000\]"):
            ENGINE.simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), mu, horizon=0.1)


def test_a_run_too_long_to_record_is_refused_before_allocating():
    with pytest.raises(
        ValueError,
        match=r"horizon / timestep must be at most 2796202 steps \(a record of 4 GiB\); got 100000 / 0.001 = 100000000 steps",
    ):
        ENGINE.simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=1e5)


def test_above_mu_P_near_p_0_the_step_may_stick_the_tip_instead_of_slipping():
    """The step's NCP has two solutions where the sticking impulse lies in the cone (sticking_admissible); PGS returned the
    sticking one here (p = 0.085, mu = 1.79): an impulse, not eq. FZ.  Such states are outside the one-step check."""
    from crosscheck.engines.pinocchio.studies.rigid import one_step, sticking_admissible

    s = SlipState(
        theta=1.0209058092047891,
        varphi=-2.3322266822458038,
        Theta=0.05795417383545341,
        Psi=-0.5873795214394222,
        eta=0.9898204260155745,
        psi=-2.0166827712132678,
    )
    mu = 1.793
    assert 0 < analytic.p(s.theta, s.varphi, mu, ALPHA) < 0.1 and sticking_admissible(s, mu, ALPHA)
    c = one_step(ROD, s, mu)
    assert c.normal_force > 100 * c.slipping_force and c.friction_ratio < mu  # stuck inside the cone by one impulse
    assert not sticking_admissible(s, 1.0, ALPHA)  # below mu_P the slip is the only solution


def test_the_step_admits_the_impulsive_stop_longer_before_the_jam_the_larger_mu():
    """Along a Corollary 4.2 slip the sticking impulse enters the cone before p = 0 (its normal part grows as p -> 0); the
    wider cone of mu = 6 takes it in far earlier than mu = 1.4 just above mu_P (medians measured 0.017 and 0.19 over 12
    states each): ``jam_aftermath``'s stop_lead, the window in which the rigid step is not unique."""
    from crosscheck.engines.pinocchio.studies.rigid import jam_aftermath

    leads = {}
    for mu in (1.4, 6.0):
        states, t_jam, _ = corollary_states(mu, 6, np.random.default_rng(5))
        a = jam_aftermath(ROD, states, mu, timesteps=(1e-3,))
        assert np.all((a.stop_lead > 0) & (a.stop_lead <= t_jam)), (mu, a.stop_lead, t_jam)
        leads[mu] = float(np.median(a.stop_lead))
    assert leads[6.0] > 5 * leads[1.4], leads
