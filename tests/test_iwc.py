"""Impact without collision in 3D (crosscheck.theory.impact.darboux_keller): the planar closed form, energy, Pinocchio's Delassus, and the rigid engine's limit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck import Rod, SlipState
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.pinocchio.stepper import Options, Stepper
from crosscheck.engines.pinocchio.studies.rigid import planar_impasse
from crosscheck.theory import analytic
from crosscheck.theory.corollary import corollary_states
from crosscheck.theory.impact.darboux_keller import delassus, impact
from crosscheck.theory.slipping import slip_until_event

ALPHA = 3.0


def test_planar_impulse_is_keller_two_phase_closed_form():
    """Planar IWC (Keller, J. Appl. Mech. 53 (1986); Darboux 1880): slip at constant direction, then stick, then compression ends.

    With the slip direction fixed, du/dP = G (-mu u_hat, 1) is constant: the slip stops at P_s = eta / |du_t/dP| with
    u_n = p P_s < 0 (p = eq. p), the tip then sticks (|f_s| <= mu) and u_n grows at the Schur complement S of G until
    it is 0 again at P_c = P_s - p P_s / S.  The rod ends stuck, and the rates follow from v0 + M^-1 J^T (L_t, P_c).
    """
    mu = 1.4
    s = planar_impasse(mu, 0.5, ALPHA)
    p = float(analytic.p(s.theta, s.varphi, mu, ALPHA))
    assert p < -0.05 and analytic.b(s.Psi, s.Theta, s.theta) < 0
    G = delassus(s, ALPHA)
    u_hat = np.array([math.cos(s.varphi), math.sin(s.varphi)])  # psi = 0
    du_t = G[:2, :2] @ (-mu * u_hat) + G[:2, 2]
    assert G[2, 2] - mu * G[2, :2] @ u_hat == pytest.approx(p, abs=1e-14)
    P_s = s.eta / np.linalg.norm(du_t)
    f_s = -np.linalg.solve(G[:2, :2], G[:2, 2])
    S = G[2, 2] + G[2, :2] @ f_s
    P_c = P_s - p * P_s / S
    r = impact(s, mu, ALPHA)
    assert [ph.name for ph in r.phases] == ["slip", "stick"] and np.linalg.norm(f_s) <= mu
    assert r.phases[0].P_end == pytest.approx(P_s, rel=1e-10)
    assert r.normal_impulse == pytest.approx(P_c, rel=1e-10) == r.compression_impulse
    L = np.concatenate([-mu * u_hat * P_s + f_s * (P_c - P_s), [P_c]])
    assert r.tangential_impulse == pytest.approx(L[:2], abs=1e-10)
    assert r.eta == 0.0 and abs(r.w) < 1e-12 and r.Psi == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(r.tangential_impulse[0], 0.0, atol=1e-12)  # stays in the rod's vertical plane


def test_delassus_equals_pinocchios():
    rod = Rod.scaled(ALPHA)
    rng = np.random.default_rng(1)
    for _ in range(10):
        s = SlipState(
            theta=rng.uniform(0.1, 1.4),
            varphi=-rng.uniform(0.1, 3.0),
            Theta=rng.normal(),
            Psi=rng.normal(),
            eta=1.0,
            psi=rng.uniform(-3, 3),
        )
        st = Stepper(rod, 1.0, Options())
        q, _ = to_generalized(rod, s)
        import pinocchio as pin

        pin.computeJointJacobians(st.model, st.data, q)
        pin.crba(st.model, st.data, q)
        st.constraint.calc(st.model, st.data, st.datas[0])
        st.cholesky.compute(st.model, st.data, st.models, st.datas, 0.0)
        np.testing.assert_allclose(
            st.cholesky.getDelassusOperatorCholeskyExpression().matrix(), delassus(s, ALPHA), atol=1e-13
        )


def test_energy_is_lost_never_gained_and_restitution_rebounds():
    rng = np.random.default_rng(2)
    n = 0
    while n < 30:
        mu = rng.uniform(1.4, 6.0)
        s = SlipState(
            theta=rng.uniform(0.2, 1.3),
            varphi=-rng.uniform(0.1, 3.0),
            Theta=rng.uniform(-2, 2),
            Psi=rng.uniform(-2, 2),
            eta=rng.uniform(0.1, 3),
            psi=rng.uniform(-3, 3),
        )
        if not (analytic.p(s.theta, s.varphi, mu, ALPHA) < 0 and analytic.b(s.Psi, s.Theta, s.theta) < 0):
            continue
        n += 1
        r0 = impact(s, mu, ALPHA)
        r1 = impact(s, mu, ALPHA, restitution=1.0)
        assert r0.energy_lost >= 0.0 and r1.energy_lost >= -1e-12 * (1 + r1.energy_lost)
        assert abs(r0.w) < 1e-10 and r0.normal_impulse > 0
        assert (
            r1.normal_impulse == pytest.approx(2 * r1.compression_impulse, rel=1e-12) and r1.w > 0
        )  # the tip rebounds
        assert r1.compression_impulse == pytest.approx(r0.compression_impulse, rel=1e-9)


def test_rigid_engine_after_the_jam_converges_to_the_impulse_at_first_order():
    """Corollary 4.2 state: the time-stepper's state after its jam row tends to iwc.impact at the analytic jam, as dt -> 0."""
    rod = Rod.scaled(ALPHA)
    (s0,), (t_jam,), _ = corollary_states(1.7, 1, np.random.default_rng(0))
    a = slip_until_event(s0, 1.7, ALPHA, t_max=2.0)
    r = impact(a.state, 1.7, ALPHA)
    dts, errs = [1e-3, 3e-4, 1e-4], []
    for dt in dts:
        run = get("pinocchio").simulate(rod, s0, 1.7, horizon=float(t_jam) + 0.05, timestep=dt)
        R, k = run.record, int(round(run.event_time / dt)) + 1
        errs.append(max(abs(R.Theta[k] - r.Theta), abs(R.Psi[k] - r.Psi), abs(R.eta[k] - r.eta)))
    rate = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    assert rate == pytest.approx(1.0, abs=0.1) and errs[-1] < 1e-3


@pytest.mark.parametrize(
    "mu, Theta", [(1.4, 0.5), (1.4, -0.3), (2.0, 0.5)], ids=["mu=1.4 lifts", "mu=1.4 sticks", "mu=2"]
)
def test_rigid_engine_from_a_planar_impasse_converges_to_keller_at_first_order(mu, Theta):
    """Planar state with p < 0, b < 0 (Painleve's impasse): the time-stepper's first step is the IWC.

    Its impulse and its post-impulse rates tend to Keller's two-phase impact (checked in closed form above)
    at first order in dt: the step solves the same impulse problem at the same configuration, plus the
    O(dt) gravity, Coriolis and dJ v terms of the step.
    """
    rod = Rod.scaled(ALPHA)
    s = planar_impasse(mu, Theta, ALPHA)
    r = impact(s, mu, ALPHA)
    dts, errs = [1e-3, 3e-4, 1e-4], []
    for dt in dts:
        run = get("pinocchio").simulate(rod, s, mu, horizon=10 * dt, timestep=dt)
        assert run.outcome.name == "JAM" and run.event_time == 0.0
        R = run.record
        errs.append(
            max(
                abs(R.Theta[1] - r.Theta),
                abs(R.Psi[1] - r.Psi),
                abs(R.eta[1] - r.eta),
                abs(run.jam_impulse - r.normal_impulse),
            )
        )
    rate = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    assert rate == pytest.approx(1.0, abs=0.05) and errs[-1] < 1e-3, (rate, errs)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"restitution": 1.5}, r"restitution must be in \[0, 1\]; got 1.5"),
        ({"mu": -1.0}, r"mu must be in \[0, 1000\]; got -1.0"),
        ({"alpha": 0.0}, r"alpha must be in \[0.001, 1000\]; got 0.0"),
    ],
    ids=["restitution", "mu", "alpha"],
)
def test_bad_input_is_named(kwargs, message):
    args = {"state": planar_impasse(1.4, 0.5, ALPHA), "mu": 1.4, "alpha": ALPHA, **kwargs}
    with pytest.raises(ValueError, match=message):
        impact(args.pop("state"), args.pop("mu"), args.pop("alpha"), **args)


def test_no_impulse_where_the_rod_can_slip_or_does_not_slip():
    with pytest.raises(ValueError, match=r"p must be <= 1e-12 .*; got p = "):
        impact(SlipState(theta=0.5, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0), 0.5, ALPHA)
    with pytest.raises(ValueError, match=r"eta must be in \(0, inf\) for an impact without collision"):
        impact(
            SlipState(theta=planar_impasse(1.4, 0.5, ALPHA).theta, varphi=-math.pi / 2, Theta=0.5, Psi=0.0, eta=0.0),
            1.4,
            ALPHA,
        )
