"""The Bullet engine (pybullet): its free step, its contact step against the rigid theory at C, the record's rows and units, bad input.

Every check runs real pybullet.  The numbers each one allows are the module-level
constants below, each with where it comes from.  Scaled units throughout (section 2.1):
on ``Rod.scaled`` m = l = g = omega = 1, so Bullet's SI step is the scaled timestep.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from stopped_runs import stopped_and_whole

from crosscheck import Outcome, Rod, SlipState, analytic, engines
from crosscheck.coordinates import tip_position, tip_velocity, to_generalized
from crosscheck.engines.bullet import ENGINES
from crosscheck.engines.bullet.engine import BulletHealth, Options, record_from_raw
from crosscheck.engines.bullet.model import world
from crosscheck.engines.record import FIELDS

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
SPEC = ENGINES[0]
EPS = np.finfo(float).eps

#: Bullet's free step v1 = v0 + dt a(q0, v0) against eqs. rotode / linode2: (v1 - v0) / dt loses the digits of v to
#: the subtraction, ~eps |v| / dt, so the allowance is 64 eps (1 + |v|) / dt (1.4e-11 (1 + |v|) at dt = 1e-3);
#: measured 1.6e-13 relative over random states (physical rod).
FREE_STEP_ROUNDING = 64.0

#: |F_t| = mu F_n on Bullet's cone: the radial clip scales both friction rows by the sines and cosines of one atan2,
#: a few eps; measured 2.2e-16.
CONE_RTOL = 1e-12

#: The first step's normal force against -(b - Theta^2 sin theta) / p_eff: the step zeroes the contact's normal
#: velocity to its rounding (~1e-13 l omega: J v of O(1) terms), i.e. the force to 1e-13 / dt relative to O(1) m g;
#: measured 3.8e-10 at dt = 1e-3.
STEP_FORCE_RTOL = 2e-9

#: The friction's direction against -diag(D)^-1 u_t, the fixed point of PGS's two friction rows projected together:
#: measured 1.5e-8 rad on random slipping states (PGS at its fixed point, 50 iterations).
DIRECTION_RAD = 1e-6

#: First order: an error at dt divided by the error at dt / 10 (semi-implicit Euler: 10 expected).
FIRST_ORDER = (5.0, 20.0)

#: A run of a physical rod against the same run of ``Rod.scaled`` (the same scaled state, mu and options), relative
#: to 1 + max |field|: every field agrees to ~1e-14 but tip_acc, a difference quotient (v_k+1 - v_k) / dt whose
#: rounding eps |v| / dt is carried along the run: measured 2.6e-9 after 500 steps.
SCALE_INVARIANCE = 1e-8

#: The momentum of the centre of mass against the recorded contact force, m (v_S,k+1 - v_S,k) / dt - m g = F_k, in
#: m g: the same loss of digits as FREE_STEP_ROUNDING.
MOMENTUM_ROUNDING = 64.0

#: The state of the brief: slipping (b < 0 < p) at mu = 0.5.
SLIPPING = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)
#: The same with both rates and an azimuth (Theta^2 sin theta = 0.54 enters the first step).
SLIPPING_TURNING = SlipState(theta=1.0, varphi=-1.9, Theta=0.8, Psi=0.7, eta=1.0, psi=0.6)


@pytest.fixture(autouse=True, scope="module")
def registered():
    """``crosscheck.engines.get("bullet")`` (the sweep runs through it), registered here until the package is in BUILTIN."""
    added = "bullet" not in engines.names()
    if added:
        engines.register(SPEC)
    yield engines.get("bullet")
    if added:
        engines.unregister("bullet")


def rollout(rod: Rod, q0, v0, nstep: int, mu: float = 0.5, **options):
    opts = Options(**options)
    raw = world(rod, mu, opts).rollout(np.asarray(q0, float), np.asarray(v0, float), nstep)
    return raw, record_from_raw(raw, rod, opts)


def kinetic_plus_potential(rod: Rod, q, v) -> np.ndarray:
    """m |v_S|^2 / 2 + I0 (theta'^2 + psi'^2 cos^2 theta) / 2 + m g Z (zero axial inertia, eq. inertia)."""
    return (
        0.5 * rod.mass * (v[:, :3] ** 2).sum(1)
        + 0.5 * rod.inertia * (v[:, 4] ** 2 + (v[:, 3] * np.cos(q[:, 4])) ** 2)
        + rod.mass * rod.gravity * q[:, 2]
    )


def first_step(state: SlipState, mu: float, **options):
    """Row 0 of a run from ``state``: the force (m g), and the end-of-step slip u of C = J_C(q0) v1, its eq. b, kappa, p_eff."""
    opts = Options(**options)
    q0, v0 = to_generalized(ROD, state, tip=(0.0, 0.0, opts.radius))
    raw, rec = rollout(ROD, q0, v0, 2, mu, **options)
    F = rec.force[0]
    v1 = raw.v[1]
    psi, th, r = q0[3], q0[4], opts.radius
    e = np.array([-math.sin(psi), math.cos(psi)])  # j: the rod's horizontal direction, from A towards S
    u = tip_velocity(ROD, q0, v1)[:2] + r * v1[4] * e  # C's material velocity at q0 after the step
    b = analytic.b(state.Psi, state.Theta, state.theta)
    kappa = math.sin(th) * state.Theta**2  # the centripetal part of the gap's free acceleration, dJ v
    # the gap's normal acceleration per unit F_z with the engine's own friction (crosscheck.capsule's p_C with F_j = F.j)
    p_eff = 1 + ALPHA * math.cos(th) ** 2 - ALPHA * math.cos(th) * (math.sin(th) + r) * (F[:2] @ e) / F[2]
    # the tangential Delassus diagonal at C in Bullet's world rows: (1 + alpha) along i, 1 + alpha (sin theta + r)^2 along j
    d_i, d_j = 1 + ALPHA, 1 + ALPHA * (math.sin(th) + r) ** 2
    D = np.array(
        [d_i * math.cos(psi) ** 2 + d_j * math.sin(psi) ** 2, d_i * math.sin(psi) ** 2 + d_j * math.cos(psi) ** 2]
    )
    return F, u, b, kappa, p_eff, D, rec


def angle(a, b) -> float:
    return math.acos(float(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1.0, 1.0)))


# ---------------------------------------------------------------- the declaration


def test_the_spec_declares_bullet_and_importing_it_does_not_import_pybullet(registered):
    assert registered is SPEC and SPEC.name == "bullet" and SPEC.label == "Bullet" and SPEC.libraries == ("pybullet",)
    assert SPEC.tags == {"rigid", "time_stepping"} and SPEC.one_core == {"workers": 1} and SPEC.tolerances is None
    assert set(SPEC.solver_columns) <= {
        f for f in BulletHealth.__dataclass_fields__ if BulletHealth.__dataclass_fields__[f].type == "int"
    }
    assert SPEC.report.order == 50 and set(SPEC.report.maps) == set(SPEC.report.convergence) == {"quick", "full"}
    assert SPEC.report.beside == "rigid_maps"
    code = (
        "import sys, crosscheck.engines.bullet as b, crosscheck.engines.bullet.options as o; o.Options(); b.ENGINES[0].label; "
        "assert 'pybullet' not in sys.modules, 'pybullet was imported'"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert SPEC.options().contact_time == 0.0 and SPEC.options().friction_time == 0.0  # the classifier's rigid rules


# ---------------------------------------------------------------- free flight


def test_free_step_is_the_rods_exact_acceleration_with_semi_implicit_euler():
    """Lifted well above the plane: v1 = v0 + dt a(q0, v0) with a from eqs. rotode, linode2 (no damping, no motors), q1 = q0 + dt v1."""
    rod = Rod(mass=2.0, length=0.7, inertia=0.1, gravity=9.81)  # a physical rod: SI inside Bullet
    rng = np.random.default_rng(0)
    dt = 1e-3 / rod.omega
    for _ in range(20):
        s = SlipState(
            theta=rng.uniform(0.05, 1.5),
            varphi=-rng.uniform(0, 3),
            Theta=rng.normal(),
            Psi=2 * rng.normal(),
            eta=rng.uniform(0, 2),
            psi=rng.uniform(-3, 3),
        )
        q0, v0 = to_generalized(rod, s, tip=(0.0, 0.0, 0.5))
        raw, rec = rollout(rod, q0, v0, 1)
        assert raw.points[0] == 0 and not rec.active[0] and np.all(rec.force == 0.0)
        theta_dd, psi_dd = analytic.rotational_acceleration(rod, q0[3], q0[4], v0[3], v0[4], np.zeros(3))
        want = np.array([0.0, 0.0, -rod.gravity, psi_dd, theta_dd])
        got = (raw.v[1] - v0) / dt
        allowance = FREE_STEP_ROUNDING * EPS * (1 + np.abs(v0).max()) / dt
        assert np.abs(got - want).max() <= allowance * (1 + np.abs(want).max())
        np.testing.assert_allclose(raw.q[1], q0 + dt * raw.v[1], rtol=0, atol=4 * EPS * (1 + np.abs(q0).max()))


def test_free_flight_tip_acceleration_is_b_and_energy_is_kept_to_first_order():
    """tip_acc_z of row 0 -> b (eq. b) and the energy drift of a flight of t = 1 -> 0, both at first order in dt.

    Bullet's default damping (0.04 linear and angular) would take a fixed fraction of the energy whatever dt."""
    s = SlipState(theta=0.7, varphi=-1.0, Theta=0.8, Psi=1.3, eta=1.0, psi=0.4)
    q0, v0 = to_generalized(ROD, s, tip=(0.0, 0.0, 5.0))
    b = analytic.b(s.Psi, s.Theta, s.theta)
    acc_err, drift = {}, {}
    for dt in (1e-3, 1e-4):
        raw, rec = rollout(ROD, q0, v0, round(1.0 / dt), timestep=dt)
        assert not rec.active.any() and np.all(rec.gap > 1.0)  # in flight all along, no contact point
        acc_err[dt] = abs(rec.tip_acc[0, 2] - b)
        E = kinetic_plus_potential(ROD, raw.q, raw.v)
        drift[dt] = np.abs(E - E[0]).max() / abs(E[0])
    assert acc_err[1e-3] < 1e-2 and FIRST_ORDER[0] <= acc_err[1e-3] / acc_err[1e-4] <= FIRST_ORDER[1], acc_err
    assert drift[1e-3] < 1e-2 and FIRST_ORDER[0] <= drift[1e-3] / drift[1e-4] <= FIRST_ORDER[1], drift


# ---------------------------------------------------------------- the contact step


@pytest.mark.parametrize("state", [SLIPPING, SLIPPING_TURNING], ids=["brief_state", "turning"])
def test_slipping_step_is_rigid_coulomb_on_bullets_cone(state):
    """Row 0 of a slipping start (b < 0 < p): |F_t| = mu F_n (one cone, not two multiplied frictions), the gap held
    (F_n = -(b - Theta^2 sin theta) / p_eff, the step zeroing J v at q0: no dt dJ v term), and the friction opposite
    diag(D)^-1 u: PGS's fixed point, skewed off -u (Coulomb's direction) wherever the two world rows' D differ."""
    mu = 0.5
    F, u, b, kappa, p_eff, D, rec = first_step(state, mu)
    Fn, Ft = F[2], F[:2]
    assert b < 0 and Fn > 0 and rec.normal_force[0] == Fn and rec.active[0]
    assert abs(np.linalg.norm(Ft) / (mu * Fn) - 1) <= CONE_RTOL
    assert abs(Fn / (-(b - kappa) / p_eff) - 1) <= STEP_FORCE_RTOL
    predicted = -u / D
    assert angle(Ft, predicted) <= DIRECTION_RAD
    skew = angle(predicted, -u)
    assert skew > 0.01  # the check discriminates: Bullet's friction is 1.2-3.7 degrees off -u on these states
    assert abs(angle(Ft, -u) - skew) <= DIRECTION_RAD


def test_cone_off_is_a_pyramid():
    """cone=False clips the two friction rows separately: both saturate here, |F_t| = sqrt(2) mu F_n (so the cone option acts)."""
    mu = 0.5
    F, *_ = first_step(SLIPPING, mu, cone=False)
    ratio = np.linalg.norm(F[:2]) / (mu * F[2])
    assert abs(ratio - math.sqrt(2)) <= CONE_RTOL


def test_after_two_steps_the_slipping_force_is_minus_b_over_p_eff_to_first_order():
    """The gap left by each position step (sin theta (dt Theta)^2 / 2) and the speculative row closing it put back the dt dJ v
    term: from row 2 on the normal force is -b/p_eff with the engine's own friction, the error first order in dt."""
    err = {}
    for dt in (1e-3, 1e-4):
        run = SPEC.simulate(ROD, SLIPPING_TURNING, 0.5, horizon=0.3, timestep=dt)
        R = run.record
        Fj = -np.sin(R.psi) * R.force[:, 0] + np.cos(R.psi) * R.force[:, 1]
        st, ct, r = np.sin(R.theta), np.cos(R.theta), run.options.radius
        p_eff = 1 + ALPHA * ct**2 - ALPHA * ct * (st + r) * Fj / R.normal_force
        assert np.all(R.active) and np.all(R.normal_force > 0)  # slipping all along
        err[dt] = np.abs(R.normal_force / (-R.b / p_eff) - 1)[2:].max()
        np.testing.assert_allclose(
            R.gap[1:], st[1:] * (dt * R.Theta[1:]) ** 2 / 2, rtol=0.02, atol=0
        )  # the gap it keeps
    assert err[1e-3] < 1e-2 and FIRST_ORDER[0] <= err[1e-3] / err[1e-4] <= FIRST_ORDER[1], err


def test_the_first_step_decides_liftoff_on_b_minus_theta_dot_squared_sin_theta():
    """From a touching start the first step holds J v = 0: the tip with b > 0 > b - Theta^2 sin theta gets one row of force
    and lifts off one row late; with b - Theta^2 sin theta > 0 (here Theta = 0) it lifts off at t = 0 (the exact decision)."""
    late = SlipState(theta=1.0, varphi=-1.9, Theta=1.2, Psi=0.0, eta=1.0)  # b = 0.21, b - kappa = -1.0
    at_once = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=2.2, eta=1.0)  # b = 0.19, kappa = 0
    a = SPEC.simulate(ROD, late, 0.5, horizon=0.1)
    assert (
        analytic.b(late.Psi, late.Theta, late.theta) > 0
        and a.record.normal_force[0] > 0.1
        and a.record.normal_force[1] == 0
    )
    assert a.outcome == Outcome.LIFTOFF and a.event_time == pytest.approx(a.options.timestep, abs=1e-15)
    c = SPEC.simulate(ROD, at_once, 0.5, horizon=0.1)
    assert analytic.b(at_once.Psi, at_once.Theta, at_once.theta) > 0 and c.record.normal_force[0] == 0
    assert c.outcome == Outcome.LIFTOFF and c.event_time == 0.0


def test_row_k_holds_state_k_and_the_force_of_step_k():
    """The centre of mass's momentum balance, m (v_S,k+1 - v_S,k) / dt - m g = F_k, row by row: the record's force is the
    impulse of the step that starts at its row's state, summed over Bullet's points, in m g, on the rod."""
    opts = Options()
    q0, v0 = to_generalized(ROD, SLIPPING_TURNING, tip=(0.0, 0.0, opts.radius))
    raw, rec = rollout(ROD, q0, v0, 300)
    dt = opts.timestep
    gravity = np.array([0.0, 0.0, -1.0])
    balance = ROD.mass * np.diff(raw.v[:, :3], axis=0) / dt - ROD.mass * gravity
    allowance = MOMENTUM_ROUNDING * EPS * (1 + np.abs(raw.v).max()) / dt
    assert np.abs(balance - rec.force).max() <= allowance and np.all(rec.normal_force > 0)
    np.testing.assert_array_equal(rec.tip_pos[:, 2], tip_position(ROD, raw.q[:-1])[:, 2])
    np.testing.assert_allclose(
        rec.tip_acc, np.diff(tip_velocity(ROD, raw.q, raw.v), axis=0) / dt, rtol=0, atol=1e-15 / dt
    )


# ---------------------------------------------------------------- the runs


def test_simulate_equals_its_sweep_row_whatever_ran_before(registered):
    """A run depends on its state, mu and options only: the sweep (mu changing between states, so the world is rebuilt),
    simulate afterwards, simulate after another state in the same world, and two worker processes give the same numbers."""
    states = [
        SlipState(theta=0.6, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.0),
        SLIPPING_TURNING,
        SlipState(theta=1.2, varphi=-2.5, Theta=-0.4, Psi=-0.8, eta=0.4, psi=2.0),
    ]
    mus = np.array([0.5, 1.2, 0.5])
    horizon = 0.4
    sw = registered.sweep(ROD, states, mus, horizon=horizon, progress=False)
    sw2 = registered.sweep(ROD, states, mus, horizon=horizon, progress=False, workers=2)
    every = max(1, sw.nstep // 200)
    for i, (s, mu) in enumerate(zip(states, mus)):
        run = registered.simulate(ROD, s, float(mu), horizon=horizon, until_event=True)  # as the sweep runs it
        whole = registered.simulate(ROD, s, float(mu), horizon=horizon)
        assert whole.outcome == run.outcome
        np.testing.assert_array_equal(whole.event_time, run.event_time)  # NaN for a SLIP
        assert run.outcome == sw.outcome[i] == sw2.outcome[i]
        np.testing.assert_array_equal([run.event_time, run.event_time], [sw.event_time[i], sw2.event_time[i]])
        for k in ("theta", "Theta", "Psi", "gap", "eta"):
            kept = getattr(run.record, k)[::every][: sw.series[k].shape[1]]
            np.testing.assert_array_equal(sw.series[k][i], kept)
            np.testing.assert_array_equal(sw2.series[k][i], kept)
        assert {f: sw.solver[f][i] for f in sw.solver} == vars(run.solver)
    first = registered.simulate(ROD, states[2], 0.5, horizon=horizon)  # after states[1] at mu = 1.2: a rebuilt world
    registered.simulate(ROD, states[0], 0.5, horizon=horizon)  # the same world, another state
    again = registered.simulate(ROD, states[2], 0.5, horizon=horizon)
    for f in FIELDS:
        np.testing.assert_array_equal(getattr(first.record, f), getattr(again.record, f))
    assert isinstance(first.solver, BulletHealth) and first.solver.max_points == 1
    assert first.solver.max_penetration <= 4 * EPS  # the start's rounding only: the speculative row never lets C sink


def test_solver_health_counts_steps_short_of_pgs_fixed_point():
    """At the default 50 sweeps every contact step of a slip reaches the solver tolerance (~36 sweeps measured); capped at
    5 sweeps every contact step stops short, and is counted."""
    ok = SPEC.simulate(ROD, SLIPPING_TURNING, 0.5, horizon=0.05)
    assert ok.solver.contact_steps == ok.nstep and ok.solver.unconverged_steps == 0
    assert ok.solver.max_residual <= Options().solver_tolerance
    assert 1 < ok.solver.max_iterations < Options().solver_iterations
    starved = SPEC.simulate(ROD, SLIPPING_TURNING, 0.5, horizon=0.05, solver_iterations=5)
    assert (
        starved.solver.unconverged_steps == starved.nstep
        and starved.solver.max_iterations == 5
        and starved.solver.max_residual > 0
    )


def test_solver_health_shows_pgs_cycling_at_high_mu():
    """A slip at mu = 2.44 (seed 5 of random_event_points) on which PGS cycles: the iterates alternate between two impulses
    (0.02 and 11 m g normal at row 399) so more sweeps do not help, and the cap's parity picks the impulse.  The health
    columns must show it: steps missing the tolerance at 50 and at 1000 sweeps, a residual of O(0.1) l omega, and the
    capsule sinking (2.2e-4 l) on the even cap; a run that reaches its fixed point has none of these."""
    s = SlipState(
        theta=1.1907200661442665,
        varphi=-2.92145649557482,
        Theta=-0.16186553664387748,
        Psi=-0.27737646445869313,
        eta=1.5399713354017732,
    )
    runs = {n: SPEC.simulate(ROD, s, 2.4390655192837145, horizon=0.4, solver_iterations=n) for n in (50, 51, 1000)}
    for n, run in runs.items():
        assert run.solver.unconverged_steps > 0 and run.solver.max_residual > 1e-3, (n, run.solver)
    assert runs[50].solver.max_penetration > 1e-4 and runs[51].solver.max_penetration == 0.0
    assert not np.array_equal(runs[50].record.normal_force, runs[51].record.normal_force)


def test_scaled_units_and_the_start_on_the_plane():
    """t spaced by the timestep; the tip at z = r and C on the plane in row 0; a 1 m rod, a 1 cm rod (psi' = 125 rad/s, beyond
    Bullet's default joint-velocity clamp of 100) and a heavy short rod give the scaled rod's record."""
    s = SlipState(theta=1.4, varphi=-2.0, Theta=0.3, Psi=4.0, eta=1.0, psi=0.3)
    base = SPEC.simulate(ROD, s, 0.4, horizon=0.5, radius=0.02, timestep=2e-3)
    R = base.record
    np.testing.assert_allclose(np.diff(R.t), 2e-3, rtol=1e-12, atol=0)
    assert R.t[0] == 0.0 and len(R) == 250 and base.nstep == 250
    assert abs(R.tip_pos[0, 2] - 0.02) <= 4 * EPS and abs(R.gap[0]) <= 4 * EPS and R.active[0] and R.normal_force[0] > 0
    assert base.outcome == Outcome.SLIP and np.all(R.normal_force > 0)  # slipping throughout: the contact is exercised
    rods = {
        "uniform_1m": Rod.uniform(1.0, 1.0),
        "uniform_1cm": Rod.uniform(0.2, 0.01),
        "heavy_short": Rod(mass=50.0, length=0.3, inertia=1.5, gravity=9.81),
    }
    for name, rod in rods.items():
        other = SPEC.simulate(rod, s, 0.4, horizon=0.5, radius=0.02, timestep=2e-3)
        for f in FIELDS:
            got, want = np.asarray(getattr(other.record, f), float), np.asarray(getattr(R, f), float)
            assert np.abs(got - want).max() <= SCALE_INVARIANCE * (1 + np.abs(want).max()), (name, f)
    assert 4.0 * Rod.uniform(0.2, 0.01).omega > 100.0


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "options, message",
    [
        ({"timestep": 0.0}, "timestep must be in (0, inf); got 0.0"),
        ({"timestep": 0.5}, "timestep must be in (0, horizon = 0.1]; got 0.5"),
        ({"radius": 0.5}, "radius must be in (0, 0.5); got 0.5"),
        ({"solver_iterations": 0}, "solver_iterations must be an integer in [1, 100000]; got 0"),
        ({"solver_iterations": 2.0}, "solver_iterations must be an integer in [1, 100000]; got 2.0"),
        ({"solver_tolerance": -1e-9}, "solver_tolerance must be in [0, inf); got -1e-09"),
        ({"contact_erp": 1.5}, "contact_erp must be in [0, 1]; got 1.5"),
        ({"contact_margin": math.inf}, "contact_margin must be in (0, inf); got inf"),
        ({"cone": "yes"}, "cone must be True or False; got 'yes'"),
        (
            {"stiffness": 1.0},
            (
                "unknown Bullet option 'stiffness': options must be one of cone, contact_erp, contact_margin, friction_axes, radius, "
                "solver_iterations, solver_tolerance, timestep"
            ),
        ),
    ],
    ids=[
        "timestep",
        "timestep_above_horizon",
        "radius",
        "iterations",
        "iterations_float",
        "tolerance",
        "erp",
        "margin",
        "cone",
        "unknown",
    ],
)
def test_bad_options_raise_one_line_naming_option_value_and_range(options, message):
    with pytest.raises(ValueError) as e:
        SPEC.simulate(ROD, SLIPPING, 0.5, horizon=0.1, **options)
    assert str(e.value) == message and "\n" not in str(e.value)


@pytest.mark.parametrize(
    "mu, message",
    [
        (11.0, "mu must be in [0, 10] for Bullet (it clamps the combined friction to 10); got 11.0"),
        (-1.0, "mu must be in [0, 1000]; got -1.0"),
    ],
    ids=["above_bullets_clamp", "negative"],
)
def test_bad_mu_is_named(mu, message):
    with pytest.raises(ValueError) as e:
        SPEC.simulate(ROD, SLIPPING, mu, horizon=0.1)
    assert str(e.value) == message


def test_a_rollout_stopped_once_its_first_event_is_judged_has_the_whole_runs_first_event(registered):
    """From starts that lift off, jam, stick and keep slipping (mu 1.4, varphi -1.9): ``until_event`` stops the rollout
    early where an event settles it, with the whole run's outcome, time and JAM numbers, and health over the steps taken;
    a run that keeps slipping is never cut."""
    for whole, cut, _rows in stopped_and_whole(registered, ROD):
        assert cut.solver.contact_steps <= whole.solver.contact_steps
