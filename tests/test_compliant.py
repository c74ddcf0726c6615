"""The compliant rod (crosscheck.engines.compliant): the rigid limit, stick and its edge, the capsule's contact point, energy, bad inputs.

Every run is short (horizon <= 1, eps >= 1e-2, but for one fast slip stop at eps 3e-3 to 3e-4, 0.5 s): the file takes a
few seconds.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck import engines
from crosscheck.coordinates import tip_position, tip_velocity, to_generalized
from crosscheck.engines.compliant import integrate, simulate, slow_manifold
from crosscheck.engines.compliant.model import SLIP, STICK, y_from_qv
from crosscheck.engines.compliant.tolerances import (
    COMPLIANT_ENERGY,
    COMPLIANT_INTEGRATION,
    COMPLIANT_KINEMATICS,
    COMPLIANT_ORDER,
    COMPLIANT_RESTART,
)
from crosscheck.engines.compliant.trajectory import make_dynamics
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic
from crosscheck.theory.impact.darboux_keller import delassus
from crosscheck.theory.slipping import slip_until_event
from crosscheck.tolerances import CLOSED_FORM

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
#: Two slipping states (b < 0 < p) that slip without an event over t in [0, 1]; the second well out of the plane varphi = -pi/2.
SLIPPING = (
    SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=1.0),
    SlipState(theta=0.9, varphi=-2.0, Theta=-0.5, Psi=1.0, eta=1.5),
)
MUS = (0.3, 0.5)
KEYS = ("eta", "varphi", "Psi", "theta", "Theta")


def _slow_error(state: SlipState, mu: float, eps: float, law: str, horizon: float = 1.0) -> float:
    """Largest error of (eta, varphi, Psi, theta, Theta) at t = horizon against the rigid flow (slip_until_event)."""
    rigid = slip_until_event(state, mu, ALPHA, t_max=horizon)
    assert rigid.reason == "t_max"
    want = dict(zip(("eta", "varphi", "psi", "Psi", "theta", "Theta"), rigid.x[-1]))
    gap, gap_rate = slow_manifold(ROD, state, mu, eps=eps, xi=1.0, law=law)
    got = integrate(ROD, state, mu, horizon=horizon, eps=eps, xi=1.0, gap=gap, gap_rate=gap_rate, law=law).state_at(
        horizon
    )
    return max(abs(got[k] - want[k]) for k in KEYS)


@pytest.mark.parametrize("k, law", [(0, "kelvin-voigt"), (1, "kelvin-voigt"), (1, "hunt-crossley")])
def test_slipping_from_the_slow_manifold_converges_to_the_rigid_flow_at_second_order(k, law):
    """Started on the slow manifold, the slow variables' error at t = 1 is O(eps^2): the fitted order over eps = 0.04, 0.02, 0.01.

    Both laws share the manifold delta = eps^2 F_z to leading order (measured slopes 2.006 and 1.986 for Hunt-Crossley)."""
    eps = np.array([0.04, 0.02, 0.01])
    err = np.array([_slow_error(SLIPPING[k], MUS[k], e, law) for e in eps])
    assert np.all(np.diff(err) < 0)
    # the solver's error (COMPLIANT_INTEGRATION: ~5e-9) is 1e-3 of the smallest model error: it does not move the fit
    assert err[-1] > 1e3 * 5e-9
    order = np.polyfit(np.log(eps), np.log(err), 1)[0]
    assert COMPLIANT_ORDER.ok(order, 2.0), order


def test_the_slip_stop_converges_to_the_rigid_stick_at_second_order():
    """A slow slip at mu = 1 stops; the compliant stop time tends to the rigid flow's STICK time as eps^2."""
    state = SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=0.2)
    rigid = slip_until_event(state, 1.0, ALPHA, t_max=1.0)
    assert rigid.outcome == Outcome.STICK
    eps = np.array([0.04, 0.02, 0.01])
    err = np.array(
        [
            abs(
                integrate(ROD, state, 1.0, horizon=1.0, eps=e, xi=1.0, stop_at={"slip_stop"}).slip_stop_time
                - rigid.time
            )
            for e in eps
        ]
    )
    order = np.polyfit(np.log(eps), np.log(err), 1)[0]
    assert COMPLIANT_ORDER.ok(order, 2.0), (order, err)


def _stick_run(radius: float):
    state = SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=0.2)
    return integrate(ROD, state, 1.0, horizon=0.8, eps=1e-2, xi=1.0, radius=radius)


@pytest.mark.parametrize("radius", [0.0, 0.1])
def test_a_slow_rod_sticks_and_holds(radius):
    """After the slip stops the rod stays stuck to the horizon: the force in the cone, C's slip held at zero.

    C's slip speed is held at 0 by the stick force (its tangential acceleration is zero); what remains is the
    solver's error, bounded by the sum over the stick phase's steps of the local allowance
    atol + rtol max|y| per step (COMPLIANT_INTEGRATION), with max|y| the largest state component.
    """
    traj = _stick_run(radius)
    assert [e.kind for e in traj.events] == ["slip_stop"]
    seg = next(s for s in traj.segments if s.mode == STICK)
    assert seg.t1 == pytest.approx(0.8, abs=1e-12)
    dyn = traj.dynamics
    steps = len(seg.sol.ts) - 1
    bound = steps * (COMPLIANT_INTEGRATION.atol + COMPLIANT_INTEGRATION.rtol * np.abs(traj.v).max())
    for t in np.linspace(seg.t0, seg.t1, 41):
        y = seg.sol(t)
        F = dyn.force(y, STICK)
        assert F[2] > 0.0 and math.hypot(F[0], F[1]) <= dyn.mu * F[2]
        assert math.hypot(*dyn.slip(y)) <= bound


@pytest.mark.parametrize("side", [+1, -1])
def test_a_rod_at_rest_sticks_or_slips_by_the_closed_form_cone_edge(side):
    """A rod released at rest (psi = 0) sticks iff mu >= alpha sin cos / (1 + alpha sin^2), the tip's cone edge.

    At rest C's only tangential acceleration is the normal force's, G_tn F_n with G_tt = diag(1 + alpha,
    1 + alpha sin^2), G_yz = -alpha sin cos: the stick force per unit F_n is G_tt^-1 G_tn.  2 % either side of
    the edge: inside, C stays stuck from t = 0; outside, the slip restarts at once (``slip_restart`` at 0).
    """
    theta = 0.8
    s, c = math.sin(theta), math.cos(theta)
    mu_edge = ALPHA * s * c / (1 + ALPHA * s * s)
    traj = integrate(
        ROD,
        SlipState(theta=theta, varphi=-1.0, Theta=0.0, Psi=0.0, eta=0.0),
        mu_edge * (1 + 0.02 * side),
        horizon=0.05,
        eps=1e-2,
        xi=1.0,
    )
    if side > 0:
        assert traj.segments[0].mode == STICK and not traj.events
    else:
        assert traj.segments[0].mode == SLIP and [(e.kind, e.time) for e in traj.events][0] == ("slip_restart", 0.0)
        assert traj.state_at(0.05)["eta_C"] > 0.0


def test_at_the_cone_edge_the_slip_restarts_with_continuous_friction_along_it():
    """A stuck rod whose stick force reaches the cone edge restarts slipping opposite that force, from rest.

    At the break |F_t| = mu F_n (an event root: the time is found to ~1e-15, so the ratio to the rounding of the
    force, CLOSED_FORM); the slip's friction equals the stick force (friction continuous: the restart
    direction is -F_t/|F_t| at lambda = 0) up to the removal of the stick phase's residual slip; C's tangential acceleration is zero there, so the slip grows as
    tau^2 and along the friction's opposite (COMPLIANT_RESTART).
    """
    traj = integrate(
        ROD, SlipState(theta=0.83, varphi=-2.0, Theta=-0.2, Psi=0.8, eta=0.1), 0.57, horizon=0.6, eps=1e-2, xi=1.0
    )
    assert [e.kind for e in traj.events] == ["slip_stop", "stick_break"]
    dyn, tb = traj.dynamics, traj.events[1].time
    stuck = next(s for s in traj.segments if s.mode == STICK)
    after = next(s for s in traj.segments if s.mode == SLIP and s.t0 == tb)
    F_stick = dyn.force(stuck.sol(tb), STICK)
    assert CLOSED_FORM.ok(math.hypot(F_stick[0], F_stick[1]), dyn.mu * F_stick[2])
    F_slip = dyn.force(after.y0, SLIP, after.direction)
    # the break removes the stick phase's residual slip s_res (the solver's drift, bounded as in the stick test) by an
    # impulse that moves the gap rate by <= |G_nt G_tt^-1| |s_res| <= 2 |s_res|, hence F_n by (xi / eps) 2 |s_res|
    drift = (len(stuck.sol.ts) - 1) * (COMPLIANT_INTEGRATION.atol + COMPLIANT_INTEGRATION.rtol * np.abs(traj.v).max())
    np.testing.assert_allclose(F_slip, F_stick, rtol=0, atol=(1 + dyn.xi / dyn.eps) * 2 * drift)
    friction_dir = F_stick[:2] / math.hypot(F_stick[0], F_stick[1])
    speeds = []
    for tau in (1e-4, 1e-3):
        s = dyn.slip(after.sol(tb + tau))
        speeds.append(math.hypot(*s))
        # the slip opposes the friction at the break, turning at the state's O(1) rate
        assert COMPLIANT_RESTART.ok(np.arccos(np.clip(-friction_dir @ s / speeds[-1], -1, 1)) / tau, 0.0)
    # tau^2 growth: ten times the time, a hundred times the speed (a finite acceleration would give ten)
    assert speeds[1] / speeds[0] == pytest.approx(100.0, rel=0.1)


#: A Corollary 4.2 state at mu = 6 (b < 0 < p, slipping into p = 0) whose slip stops fast (|ds/dt| ~ 400 at the stop).
JAM_STATE = SlipState(
    theta=0.28608144662606594,
    varphi=-2.8900580018074526,
    Theta=-0.04555998322800074,
    Psi=-1.8305718794815617,
    eta=3.4509638878123847,
)


def test_a_fast_slip_stop_is_located_and_tends_to_the_rigid_jam():
    """Slipping into a Corollary 4.2 jam (mu = 6), the compliant slip stops after the rigid jam, the later the larger eps.

    At eps = 1e-3 one solver step carries C's slip through s = 0 to the far side with |s| above the slip-stop speed at
    both ends, so the event is not seen there; the far side's slip must then fall through that speed where the
    friction direction s/|s| is smooth (a slip floor at the event's speed made |s| = 1e-9 attract from both sides,
    and the run ended in a solver failure).  The stop is located at each eps, and its lag behind the rigid jam falls
    with eps (the compliant rod tends to the rigid one; the section compliant_limit measures the rate).
    """
    mu = 6.0
    rigid = slip_until_event(JAM_STATE, mu, ALPHA, t_max=2.0)
    assert rigid.outcome == Outcome.JAM
    lags = []
    for eps in (3e-3, 1e-3, 3e-4):
        traj = integrate(ROD, JAM_STATE, mu, horizon=rigid.time + 0.3, eps=eps, xi=1.0, stop_at={"slip_stop"})
        assert [e.kind for e in traj.events][:1] == ["slip_stop"], (
            eps,
            [(e.kind, e.time, e.reason) for e in traj.events],
        )
        lags.append(traj.slip_stop_time - rigid.time)
    assert 0.0 < lags[2] < lags[1] < lags[0], lags


def test_a_graze_after_lift_off_leaves_the_rod_free_instead_of_chattering():
    """After a jam and a lift-off the capsule comes back to the plane only to graze it (C's height has a root where C
    already rises, by rounding), with the Hunt-Crossley law at a ladder's Drake stiffness (eps = 1e-2, xi = 2).

    The law cannot push a rising C at zero penetration (its push changes sign at delta = 0 too): the graze must
    leave the rod free.  Entering contact there ended it at once, and the push's sign change at delta = 0 started it
    again: 20,000 zero-length segments at t = 0.0994 (22 s) and a run that stopped short of the horizon.
    """
    state = SlipState(theta=1.22916666667, varphi=-1.9, Theta=0.375, Psi=0.0, eta=1.0)
    traj = integrate(ROD, state, 1.4, horizon=0.14, eps=1e-2, xi=2.0, radius=0.01, law="hunt-crossley")
    kinds = [e.kind for e in traj.events]
    assert kinds == ["contact_start", "slip_stop", "stick_break", "contact_end"], kinds
    assert traj.t[-1] == pytest.approx(0.14, abs=1e-12)
    # free after the lift-off: no contact force and C at or above the plane (to rounding) from there on
    after = traj.t > traj.events[-1].time
    assert np.all(traj.normal_force[after] == 0.0) and np.all(traj.mode[after] == 0)


# ------------------------------------------------------------------------- the contact point's kinematics


def _rotation(psi: float, theta: float) -> np.ndarray:
    """Rz(psi) Rx(theta) (eq. rotmatrix): the body frame in the world."""
    cp, sp, c, s = math.cos(psi), math.sin(psi), math.cos(theta), math.sin(theta)
    return np.array([[cp, -sp, 0], [sp, cp, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


@pytest.mark.parametrize("radius", [0.0, 0.05, 0.3])
def test_the_contact_points_gap_and_slip_velocity_agree_with_the_material_point_by_differences(radius):
    """Gap z_A - r and C's slip velocity v_A + r Theta (-sin psi, cos psi, 0) (the MuJoCo record's definition), against
    central differences of the world position of the body-fixed point that is C at q (independent of the model's Jacobian).

    Differences with step h = 1e-5 on O(1) positions: truncation h^2 |x'''| / 6 ~ 2e-11, rounding 1e-16 / h = 1e-11
    (COMPLIANT_KINEMATICS).  The model's C-acceleration J_C q'' + dJ_C q' against second differences of the same point
    along a constant-acceleration path (truncation h^2 ~ 1e-10 times O(10) derivatives, rounding 1e-16 / h^2 = 1e-6: step 1e-4).
    """
    rng = np.random.default_rng(7)
    dyn = make_dynamics(ALPHA, 0.5, eps=1e-2, xi=1.0, radius=radius, law="kelvin-voigt")
    for _ in range(5):
        q = np.array([*rng.uniform(-1, 1, 3), rng.uniform(-3, 3), rng.uniform(0.2, 1.3)])
        v = rng.uniform(-2, 2, 5)
        y = y_from_qv(q, v, radius)
        tip = tip_position(ROD, q)
        assert CLOSED_FORM.ok(y[2], tip[2] - radius)
        C = tip - np.array([0.0, 0.0, radius])
        body = _rotation(q[3], q[4]).T @ (C - q[:3])  # C's position in the body frame

        def point(qq):
            return qq[:3] + _rotation(qq[3], qq[4]) @ body

        h = 1e-5
        vel = (point(q + h * v) - point(q - h * v)) / (2 * h)
        s = dyn.slip(y)
        assert COMPLIANT_KINEMATICS.ok(s, vel[:2]) and COMPLIANT_KINEMATICS.ok(y[7], vel[2])
        mujoco_def = tip_velocity(ROD, q, v)[:2] + radius * v[4] * np.array([-math.sin(q[3]), math.cos(q[3])])
        assert CLOSED_FORM.ok(s, mujoco_def)
        # C's slip acceleration: the derivative of the velocity of the body point that is C at q(t), along
        # q(t) = q + t v + t^2/2 a (C moves over the capsule: a rolling contact's C is not one material point)
        a = rng.uniform(-1, 1, 5)

        def c_velocity(qq, vv):
            b = _rotation(qq[3], qq[4]).T @ (tip_position(ROD, qq) - np.array([0.0, 0.0, radius]) - qq[:3])
            pt = lambda x: x[:3] + _rotation(x[3], x[4]) @ b  # noqa: E731
            return (pt(qq + h * vv) - pt(qq - h * vv)) / (2 * h)

        h2 = 1e-3
        acc = (
            c_velocity(q + h2 * v + 0.5 * h2 * h2 * a, v + h2 * a)
            - c_velocity(q - h2 * v + 0.5 * h2 * h2 * a, v - h2 * a)
        ) / (2 * h2)
        Minv, Q, J, dJv, qd, G, a_free, MJt = dyn.terms(y)
        # outer step 1e-3: truncation h2^2 |third derivative| ~ 1e-6 x O(100), inner error 2e-9 / h2 = 2e-6
        np.testing.assert_allclose(J @ a + dJv, acc, rtol=0, atol=1e-4)


def test_the_dynamics_match_eq_linode2_and_the_delassus_matrix_of_the_impact_model():
    """At r = 0 the model's tip acceleration under a force at A is eq. linode2 (crosscheck.theory.analytic.tip_acceleration),
    its rotational accelerations eq. rotode, and its Delassus matrix crosscheck.theory.impact.darboux_keller's (CLOSED_FORM: ~20 flops each)."""
    rng = np.random.default_rng(11)
    dyn = make_dynamics(ALPHA, 0.5, eps=1e-2, xi=1.0, radius=0.0, law="kelvin-voigt")
    for _ in range(5):
        q = np.array([*rng.uniform(-1, 1, 3), rng.uniform(-3, 3), rng.uniform(0.2, 1.3)])
        v = rng.uniform(-2, 2, 5)
        F = rng.uniform(-1, 1, 3)
        y = y_from_qv(q, v, 0.0)
        want = analytic.tip_acceleration(ROD, q[3], q[4], v[3], v[4], F)
        assert CLOSED_FORM.ok(dyn.tip_acceleration(y, F), want)
        acc = dyn.accel(y, F)
        assert CLOSED_FORM.ok(acc[[4, 3]], analytic.rotational_acceleration(ROD, q[3], q[4], v[3], v[4], F))
        G = dyn.terms(y)[5]
        state = SlipState(theta=q[4], varphi=-1.0, Theta=0.0, Psi=0.0, eta=1.0, psi=q[3])
        assert CLOSED_FORM.ok(G, delassus(state, ALPHA))


@pytest.mark.parametrize("radius", [0.0, 0.2])
def test_a_run_starts_where_the_mujoco_engine_starts(radius):
    """integrate's start is to_generalized(rod, state, tip=(0, 0, radius)), as the MuJoCo engine's initial_state; the gap of C is 0."""
    state = SLIPPING[1]
    traj = integrate(ROD, state, 0.5, horizon=0.01, eps=1e-2, xi=1.0, radius=radius)
    q, v = to_generalized(ROD, state, tip=(0.0, 0.0, radius))
    assert CLOSED_FORM.ok(traj.q[0], q) and CLOSED_FORM.ok(traj.v[0], v)
    assert abs(traj.state_at(0.0)["gap"]) <= CLOSED_FORM.atol


# ------------------------------------------------------------------------- energy

ENERGY_RUNS = {
    # a landing: C hits the plane at 1 l omega, bounces (light damping) and flies
    "impact": dict(
        state=SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=0.5), mu=0.8, xi=0.3, gap_rate=-1.0, radius=0.1
    ),
    # slip, stop, stick, stick break, slip again
    "stick-slip": dict(
        state=SlipState(theta=0.83, varphi=-2.0, Theta=-0.2, Psi=0.8, eta=0.1),
        mu=0.57,
        xi=1.0,
        gap_rate=0.0,
        radius=0.0,
    ),
}


@pytest.mark.parametrize("case", ENERGY_RUNS, ids=str)
def test_the_energy_never_increases_with_damping_and_friction(case):
    """Kinetic + gravity + the law's elastic energy is non-increasing (the package docstring's power balance) to the solver's error.

    COMPLIANT_ENERGY bounds one step's rise by the local error allowance.  Sampled densely (the dense output between steps)
    and at the steps; the run must dissipate (a test that could not fail on a conservative bug otherwise).
    """
    kw = ENERGY_RUNS[case]
    traj = integrate(
        ROD, kw["state"], kw["mu"], horizon=0.6, eps=1e-2, xi=kw["xi"], gap_rate=kw["gap_rate"], radius=kw["radius"]
    )
    dyn = traj.dynamics
    E = np.array([dyn.energy(traj.y_at(t)[0]) for t in np.linspace(0.0, traj.t[-1], 400)])
    assert np.max(np.diff(E)) <= COMPLIANT_ENERGY.atol
    assert np.max(np.diff(traj.energy())) <= COMPLIANT_ENERGY.atol
    assert E[0] - E[-1] > 1e3 * COMPLIANT_ENERGY.atol


def test_without_damping_and_friction_the_energy_is_conserved():
    """mu = 0, xi = 0: the rod's Lagrangian dynamics with a conservative spring conserve E (to the solver's error), through
    the landing, the bounce and the flight: a wrong Coriolis or gravity term, or a wrong generalised force, would not."""
    traj = integrate(
        ROD,
        SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=0.5),
        0.0,
        horizon=0.4,
        eps=1e-2,
        xi=0.0,
        gap_rate=-1.0,
    )
    assert "contact_end" in [e.kind for e in traj.events]
    E = traj.energy()
    assert np.max(np.abs(E - E[0])) <= len(traj.t) * COMPLIANT_ENERGY.atol


# ------------------------------------------------------------------------- the engine's record


def test_the_engines_record_has_the_free_tip_acceleration_b_and_classifies_each_outcome():
    """simulate's Record through the one classifier: a slow rod is STICK no later than its exact slip stop (the
    classifier's floor 1e-2 on eta is reached first), a slipping rod SLIP with the contact active in every row, and a
    rod with b > 0 LIFTOFF, whose force-free rows record the tip acceleration eq. b (the record's own b, CLOSED_FORM)."""
    stick = simulate(
        ROD,
        SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=0.2),
        1.0,
        horizon=0.5,
        eps=1e-2,
        xi=1.0,
        timestep=2e-3,
    )
    assert stick.outcome == Outcome.STICK and stick.event_time <= stick.solver.slip_stop_time + 2e-3
    slipping = simulate(ROD, SLIPPING[0], MUS[0], horizon=0.3, eps=1e-2, xi=1.0, timestep=2e-3)
    assert slipping.outcome == Outcome.SLIP and slipping.record.active.all()
    lifting = SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=2.0, eta=0.5)
    assert analytic.b(lifting.Psi, lifting.Theta, lifting.theta) > 0
    free = simulate(ROD, lifting, 0.5, horizon=0.1, eps=1e-2, xi=1.0, timestep=2e-3)
    rec = free.record
    assert free.outcome == Outcome.LIFTOFF and not rec.active.any()
    assert CLOSED_FORM.ok(rec.tip_acc[:, 2], rec.b) and np.all(rec.gap[1:] > 0)


def test_the_engine_is_registered_and_sweeps_as_it_simulates():
    """engines.get("compliant") satisfies the Engine protocol; its sweep gives each state the outcome of its own simulate."""
    engine = engines.get("compliant")
    assert (
        isinstance(engine, engines.Engine)
        and engine.Options().friction_time == 0.0
        and engine.Options(eps=0.02).contact_time == 0.02
    )
    states = [SLIPPING[0], SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=0.2)]
    res = engine.sweep(ROD, states, [MUS[0], 1.0], horizon=0.4, progress=False, eps=1e-2, xi=1.0, timestep=2e-3)
    one = [
        engine.simulate(ROD, s, m, horizon=0.4, eps=1e-2, xi=1.0, timestep=2e-3) for s, m in zip(states, [MUS[0], 1.0])
    ]
    assert list(res.outcome) == [int(Outcome.SLIP), int(Outcome.STICK)] == [int(r.outcome) for r in one]
    assert res.solver["slip_stops"].tolist() == [0, 1]


# ------------------------------------------------------------------------- bad input

BAD = {
    "eps": (dict(eps=0.0, xi=1.0), "eps must be in [1e-07, 1]; got 0.0"),
    "xi": (dict(eps=1e-2, xi=-1.0), "xi must be in [0, 1000]; got -1.0"),
    "radius": (dict(eps=1e-2, xi=1.0, radius=0.5), "radius must be in [0, 0.5); got 0.5"),
    "negative radius": (dict(eps=1e-2, xi=1.0, radius=-0.1), "radius must be in [0, 0.5); got -0.1"),
    "law": (dict(eps=1e-2, xi=1.0, law="hertz"), "law must be one of hunt-crossley, kelvin-voigt; got 'hertz'"),
    "gap": (dict(eps=1e-2, xi=1.0, gap=1e-3), "gap must be in [-1, 0]; got 0.001"),
    "tiny eps": (dict(eps=1e-300, xi=1.0), "eps must be in [1e-07, 1]; got 1e-300"),
    "huge eps": (dict(eps=1e300, xi=1.0), "eps must be in [1e-07, 1]; got 1e+300"),
    "huge xi": (dict(eps=1e-2, xi=1e300), "xi must be in [0, 1000]; got 1e+300"),
    "gap rate": (dict(eps=1e-2, xi=1.0, gap_rate=1e308), "gap_rate must be in [-100, 100]; got 1e+308"),
    "stop_at": (
        dict(eps=1e-2, xi=1.0, stop_at={"bang"}),
        "stop_at must be event kinds, each one of contact_start, contact_end, slip_stop, "
        "slip_restart, stick_break, domain_exit, segments, solver_failure; got 'bang'",
    ),
    "method": (dict(eps=1e-2, xi=1.0, method="RK45"), "method must be one of Radau, BDF; got 'RK45'"),
    "horizon": (dict(eps=1e-2, xi=1.0, horizon=0.0), "horizon must be in (0, 10000]; got 0.0"),
}


@pytest.mark.parametrize("case", BAD, ids=str)
def test_bad_inputs_are_named_literally(case):
    kw, message = BAD[case]
    kw = {"horizon": 0.1, **kw}
    with pytest.raises(ValueError) as e:
        integrate(ROD, SLIPPING[0], 0.3, **kw)
    assert str(e.value) == message
    if case in ("eps", "xi", "radius", "negative radius", "law", "method", "horizon"):
        with pytest.raises(ValueError) as e:
            simulate(ROD, SLIPPING[0], 0.3, **kw)
        assert str(e.value) == message
    with pytest.raises(ValueError) as e:
        integrate(ROD, SLIPPING[0], -1.0, horizon=0.1, eps=1e-2, xi=1.0)
    assert str(e.value) == "mu must be in [0, 1000]; got -1.0"


def test_bad_engine_options_are_named_literally():
    with pytest.raises(ValueError) as e:
        simulate(ROD, SLIPPING[0], 0.3, horizon=0.1, stiffness=3.0)
    assert (
        str(e.value)
        == "unknown compliant option 'stiffness': options must be one of atol, eps, law, method, radius, rtol, timestep, xi"
    )
    with pytest.raises(ValueError) as e:
        simulate(ROD, SLIPPING[0], 0.3, horizon=0.1, timestep=0.2)
    assert str(e.value) == "timestep must be in (0, horizon = 0.1]; got 0.2"
