"""The Drake engines (``crosscheck.engines.drake``): real Drake runs checked against the rod's rigid-body theory and against themselves.

Every tolerance below is data with where its number comes from; the scaled
rod is the paper's (alpha = 3, m = l = g = 1).
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from stopped_runs import stopped_and_whole

from crosscheck import Outcome, Rod, SlipState, engines
from crosscheck.engines.classifier import classify, window_sum
from crosscheck.engines.drake import ENGINES
from crosscheck.engines.drake.options import APPROXIMATIONS, Options
from crosscheck.theory import analytic, capsule

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
SPEC = {s.name: s for s in ENGINES}
R = 0.01  # the default capsule radius r / l

#: A slipping start of the brief: b = -1 < 0 < p_C = 1.22 (eq. p at C), rigid F_z = -b/p_C = 0.81 m g.
SLIP, SLIP_MU = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0), 0.5
#: A start that lifts off at once: b = (Theta^2) sin(theta) - 1 = 2.37 > 0.
LIFT = SlipState(theta=1.0, varphi=-1.9, Theta=2.0, Psi=0.0, eta=1.0)
#: A slipping start off the planar section (Theta, Psi != 0), for the row bookkeeping.
OFFPLANE = SlipState(theta=1.0, varphi=-1.9, Theta=0.3, Psi=0.5, eta=1.0)


def rigid_force(rec, mu):
    """-b / p_C on the record's own states: eq. FZ at the capsule's contact point C (crosscheck.theory.capsule)."""
    return -rec.b / capsule.p(rec.theta, rec.varphi, mu, ALPHA, R)


def capsule_tip_acceleration(rod, rec, offset):
    """Eq. linode2 (crosscheck.theory.analytic.tip_acceleration) with the record's force moved from A to A - offset K, in g.

    Moving F down by ``offset`` adds the torque (-offset K) x F = offset (F_y, -F_x, 0), whose component on the
    theta axis (cos psi, sin psi, 0) is offset (F_y cos psi - F_x sin psi) (on K it is 0; the joints carry the rest):
    theta'' grows by that / I0, which moves A along dA/dtheta = l (-sin theta sin psi, sin theta cos psi, -cos theta).
    """
    F = rec.force * rod.force_scale
    a = analytic.tip_acceleration(rod, rec.psi, rec.theta, rec.Psi * rod.omega, rec.Theta * rod.omega, F)
    extra = offset * rod.length * (F[:, 1] * np.cos(rec.psi) - F[:, 0] * np.sin(rec.psi)) / rod.inertia
    st, ct, sp, cp = np.sin(rec.theta), np.cos(rec.theta), np.sin(rec.psi), np.cos(rec.psi)
    lever = rod.length * np.stack((-st * sp, st * cp, -ct), -1)
    return (a + extra[:, None] * lever) / rod.gravity


# ---------------------------------------------------------------------------------------------- declaration ---


def test_one_record_per_approximation_and_no_pydrake_at_import():
    assert [s.name for s in ENGINES] == [
        "drake_sap",
        "drake_continuous",
        "drake_similar",
        "drake_lagged",
        "drake_tamsi",
    ]
    for s in ENGINES:
        a = s.defaults["approximation"]
        assert s.name == f"drake_{a}" and s.options().approximation == a and s.libraries == ("drake",)
        assert (
            s.has("compliant")
            and s.has("continuous") == (a == "continuous")
            and s.has("relaxed") == (a in ("sap", "similar", "lagged"))
        )
        assert engines.get(s.name) is s  # registered through BUILTIN
    assert set(APPROXIMATIONS) == {s.defaults["approximation"] for s in ENGINES}
    code = "import sys, crosscheck.engines.drake, crosscheck.engines.drake.options; assert 'pydrake' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)


# --------------------------------------------------------------------------------------------- bad options ---


@pytest.mark.parametrize(
    "options, message",
    [
        (
            {"approximation": "rigid"},
            "approximation must be one of continuous, sap, similar, lagged, tamsi; got 'rigid'",
        ),
        ({"stiffness": 10.0}, "stiffness must be in [100, 1e+10]; got 10.0"),
        ({"dissipation": -1.0}, "dissipation must be in [0, 1e+06]; got -1.0"),
        ({"relaxation_time": 2.0}, "relaxation_time must be in [0, 1]; got 2.0"),
        ({"stiction_tolerance": 0.0}, "stiction_tolerance must be in (0, 0.01]; got 0.0"),
        ({"accuracy": 1.0}, "accuracy must be in [1e-12, 0.1]; got 1.0"),
        (
            {"integrator": "explicit_euler"},
            (
                "integrator must be one of runge_kutta3, runge_kutta5, bogacki_shampine3, radau1, radau3, "
                "implicit_euler, velocity_implicit_euler; got 'explicit_euler'"
            ),
        ),
        ({"radius": 0.5}, "radius must be in (0, 0.5); got 0.5"),
        ({"timestep": -1e-3}, "timestep must be in (0, inf); got -0.001"),
        ({"near_rigid_threshold": -1.0}, "near_rigid_threshold must be in [0, 10]; got -1.0"),
        ({"timestep": 0.1}, "timestep must be in (0, horizon = 0.05]; got 0.1"),
        (
            {"penetration_allowance": 1e-3},
            (
                "unknown Drake SAP option 'penetration_allowance': options must be one of accuracy, approximation, "
                "dissipation, integrator, near_rigid_threshold, radius, relaxation_time, stiction_tolerance, "
                "stiffness, timestep"
            ),
        ),
    ],
)
def test_bad_options_are_one_line_errors_naming_option_value_and_range(options, message):
    with pytest.raises(ValueError) as e:
        SPEC["drake_sap"].simulate(ROD, SLIP, SLIP_MU, horizon=0.05, **options)
    assert str(e.value) == message


# ------------------------------------------------------------------------------------------- scaled record ---


def test_the_record_is_in_scaled_units_whatever_the_rod():
    """Row spacing = timestep, tip at z = r on the plane at row 0 with the state's slip, and the same scaled record
    for the scaled rod and a physical one with the same alpha (the dynamics are scale-free in the paper's units)."""
    physical = Rod.uniform(mass=2.0, length=0.5, gravity=9.81)  # alpha = 3, omega = 4.43 / s, m g = 19.6 N
    runs = [SPEC["drake_tamsi"].simulate(rod, OFFPLANE, SLIP_MU, horizon=0.2, timestep=1e-3) for rod in (ROD, physical)]
    a, b = (r.record for r in runs)
    assert np.array_equal(a.t, 1e-3 * np.arange(200))
    assert a.tip_pos[0] == pytest.approx([0.0, 0.0, R], abs=1e-15)
    beta = OFFPLANE.psi + OFFPLANE.varphi
    assert a.tip_vel[0] == pytest.approx([math.cos(beta), math.sin(beta), 0.0], abs=1e-14)  # eta = 1 at A
    j = [-math.sin(OFFPLANE.psi), math.cos(OFFPLANE.psi), 0.0]
    assert a.slip_vel[0] == pytest.approx(
        a.tip_vel[0] * [1, 1, 0] + R * OFFPLANE.Theta * np.array(j), abs=1e-14
    )  # C: v_A + r Theta j
    # TAMSI solves its step to a relative tolerance, so the two rods agree to the solver's 1e-6 (Drake's default), not
    # to rounding: measured 3e-9 in the force (m g), 1e-12 in the states.
    for name in ("tip_pos", "tip_vel", "theta", "Psi", "Theta"):
        assert np.abs(getattr(a, name) - getattr(b, name)).max() < 1e-9, name
    assert np.abs(a.force - b.force).max() < 1e-6
    assert a.active.sum() > 150  # it slips in contact


# ------------------------------------------------------------------------------------------ free flight ---


@pytest.mark.parametrize("name", ["drake_sap", "drake_continuous"])
def test_a_rod_with_b_above_zero_lifts_off_and_flies_freely(name):
    """b > 0 at the start: no force in any row, tip_acc = eq. linode2 with F = 0 (tip_acc_z = b, eq. b), the centre of
    mass on the exact parabola, and the classifier's LIFTOFF at the first rows.

    Allowances.  tip_acc: Drake's generalised acceleration is exact (the discrete step's (v_k+1 - v_k) / dt has the
    rounding eps |v| / (dt g) ~ 1e-12), and the axial inertia 1e-12 I0 changes the psi inertia by 1e-12 tan^2 theta
    (<= 1e-9 while theta <= 1.54): 1e-8 g (MuJoCo's MUJOCO_FREE_ACCELERATION has the same origin).  Parabola: Z(t) =
    Z0 + Z0' t - t^2 / 2 exactly for the continuous plant (RK3 integrates a quadratic exactly: rounding, 1e-12);
    semi-implicit Euler has Z_k = Z0 + Z0' t_k - t_k (t_k + dt) / 2 exactly.
    """
    run = SPEC[name].simulate(ROD, LIFT, SLIP_MU, horizon=0.4)
    rec = run.record
    assert run.outcome == Outcome.LIFTOFF and run.event_time <= 2e-3
    assert not rec.active.any() and not rec.force.any()
    inside = rec.theta < 1.54
    assert inside.sum() > 100
    free = capsule_tip_acceleration(ROD, rec.rows(inside), 0.0)
    assert np.abs(rec.tip_acc[inside] - free).max() < 1e-8
    assert np.abs(rec.tip_acc[inside, 2] - rec.b[inside]).max() < 1e-8
    Z = rec.tip_pos[:, 2] + np.sin(rec.theta)  # S = A + l sin(theta) K
    Zdot0 = rec.tip_vel[0, 2] + math.cos(LIFT.theta) * LIFT.Theta
    dt = run.options.timestep if name != "drake_continuous" else 0.0
    assert np.abs(Z - (Z[0] + Zdot0 * rec.t - rec.t * (rec.t + dt) / 2)).max() < 1e-12


# ------------------------------------------------------------------------------- rows and their forces ---

#: Relative consistency of a row's force with its step (see the next test): the solver's tolerance.  Continuous:
#: exact (measured 9e-13: the acceleration port and the contact results are evaluated at the same state).  TAMSI,
#: Similar, SAP: their iterative solvers stop at a relative tolerance of ~1e-6 (measured 4e-10, 5e-9, 5e-7).
#: Lagged: its reported force misses its own step by 2e-5 .. 9e-4 of the term scale in every contact row (measured on
#: OFFPLANE; not explained here): a regression guard, not a bound.
STEP_CONSISTENCY = {
    "drake_continuous": 1e-10,
    "drake_tamsi": 1e-6,
    "drake_similar": 1e-6,
    "drake_sap": 3e-6,
    "drake_lagged": 3e-3,
}


@pytest.mark.parametrize("name", sorted(STEP_CONSISTENCY))
def test_row_k_holds_the_force_that_moves_the_rod_from_row_k(name):
    """tip_acc of row k (from the step k -> k+1, or the plant's acceleration at row k) is eq. linode2 with row k's force
    acting at Drake's contact point, midway into the penetration: A - (r + gap / 2) K.  The force of the previous
    or the next step would miss it by the change of the force between rows (O(1) m g at a landing, up to 100 m g
    in SAP's hops): the measured error of the shifted rows is 0.04 .. 200 of the term scale.  Scale: 1 + (1 + alpha) |F|_1."""
    rec = SPEC[name].simulate(ROD, OFFPLANE, SLIP_MU, horizon=0.6).record  # SAP and Similar hop: 5 and 3 contact rows
    want = capsule_tip_acceleration(ROD, rec, R + rec.gap / 2)
    scale = 1.0 + (1.0 + ALPHA) * np.abs(rec.force).sum(-1)
    err = np.abs(rec.tip_acc - want).max(-1) / scale
    assert rec.active.sum() >= 3
    assert np.nanmax(err) < STEP_CONSISTENCY[name]
    shifted = np.abs(rec.tip_acc[1:] - want[:-1]).max(-1) / scale[1:]
    assert np.nanmax(shifted) > 1e-2


@pytest.mark.parametrize("name", [s.name for s in ENGINES])
def test_the_engines_states_are_drakes_own_simulator_states_bit_for_bit(name):
    """The engine's step loop (``engine.raw_run``: the contact results read, the discrete update set back by hand) and a
    bare ``Simulator.AdvanceTo`` over the same steps (one call over a discrete plant's steps, one per row of the
    continuous plant's, with the engine's integrator) reach the same states exactly: the reads change nothing."""
    from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator

    from crosscheck.coordinates import to_generalized
    from crosscheck.engines.drake.engine import raw_run
    from crosscheck.engines.drake.model import model, new_context

    opts = SPEC[name].options(timestep=2e-3)
    m, n, dt = model(ROD, SLIP_MU, opts), 40, opts.timestep / ROD.omega
    x0 = np.concatenate(to_generalized(ROD, OFFPLANE, tip=(0.0, 0.0, opts.radius)))
    raw = raw_run(m, x0, n, dt, np.ones(5))
    ctx = new_context(m)
    pc = m.plant.GetMyMutableContextFromRoot(ctx)
    m.plant.SetPositionsAndVelocities(pc, x0)
    sim = Simulator(m.diagram, ctx)
    if not opts.discrete:
        ResetIntegratorFromFlags(sim, opts.integrator, dt).set_target_accuracy(opts.accuracy)
    sim.Initialize()
    for k in range(1, n + 1 if opts.discrete else n):
        sim.AdvanceTo(k * dt)
        np.testing.assert_array_equal(m.plant.GetPositionsAndVelocities(pc), raw.x[k])
    assert raw.active.any() and raw.health.failed == 0


def test_a_runaway_is_cut_at_its_first_fast_step_whatever_the_steps_between_speed_checks(monkeypatch):
    """Lagged at the quick maps' timestep from a start that is thrown off the plane and spun up: step 170 passes
    ``RUNAWAY_SPEED`` (mid-way through a chunk of ``CHUNK`` steps).  The run keeps the rows before it and NaN after, and
    is the same run, bit for bit, as one whose speeds are checked at every step."""
    from crosscheck.engines.drake import engine

    start = SlipState(theta=1.045, varphi=-1.9, Theta=1.05, Psi=0.0, eta=1.0)
    runs, chunk0 = [], engine.CHUNK
    for chunk in (chunk0, 1):
        monkeypatch.setattr(engine, "CHUNK", chunk)
        runs.append(SPEC["drake_lagged"].simulate(ROD, start, 1.4, horizon=0.6, timestep=3e-3))
    (a, b), k = runs, runs[0].solver.steps
    assert a.solver == b.solver and a.solver.message == "runaway speed" and 0 < k % chunk0
    # row k is the state the fast step started from; its force and everything after it are NaN
    assert np.isfinite(a.record.theta[: k + 1]).all() and np.isnan(a.record.theta[k + 1 :]).all()
    assert np.isfinite(a.record.force[:k]).all() and np.isnan(a.record.force[k:]).all()
    for f in ("tip_pos", "tip_vel", "tip_acc", "force", "active", "theta", "Theta", "Psi"):
        assert getattr(a.record, f).tobytes() == getattr(b.record, f).tobytes(), f


def test_contact_forces_summed_after_the_run_are_the_per_row_sums_bit_for_bit():
    """``_contact_rows`` adds 0 + f or 0 + (-f) pair by pair, in order: the IEEE values of summing each row as it is read
    (zeros, then += the force on B, -= the force on A), signed zeros included."""
    from crosscheck.engines.drake.engine import _contact_rows

    rng = np.random.default_rng(7)
    f = [np.array([0.0, -0.0, 1.5]), np.array([-0.0, 0.0, -2.0]), *rng.normal(size=(5, 3))]
    pairs = [
        (0, True, f[0]),
        (0, False, f[1]),
        (2, False, f[0]),
        (3, True, f[1]),
        (3, True, f[2]),
        (3, False, f[3]),
        (5, False, f[4]),
        (6, True, f[5]),
        (6, False, f[6]),
    ]
    want, want_active = np.zeros((7, 3)), np.zeros(7, bool)
    for k, on_b, fk in pairs:
        want_active[k] = True
        if on_b:
            want[k] += fk
        else:
            want[k] -= fk
    got, active = np.zeros((7, 3)), np.zeros(7, bool)
    _contact_rows(pairs, got, active)
    assert got.tobytes() == want.tobytes() and (active == want_active).all()


# ---------------------------------------------------------------------------------- slipping vs theory ---


def window_errors(run, mu):
    """Relative error of the window-mean normal force (the classifier's window) against the window mean of -b/p_C,
    over windows starting 5 contact times after the start (the force builds up over the contact time)."""
    rec, dt = run.record, run.options.timestep
    w = run.thresholds.window_rows(dt)
    got, want = window_sum(rec.normal_force, w) / w, window_sum(rigid_force(rec, mu), w) / w
    start = int(math.ceil(5 * run.options.contact_time / dt))
    return np.nanmax(np.abs(got[start:] / want[start:] - 1.0))


def test_continuous_slipping_force_is_the_rigid_force_and_tends_to_it_as_the_contact_stiffens():
    """A slipping start (b < 0 < p): the window-mean normal force is -b/p_C of the engine's own states, within the
    contact's lag, and closer for a stiffer contact; the friction is Coulomb's, opposite the slip at C.

    The compliant force answers the rigid one with a lag ~ the contact time tau = 1/sqrt(stiffness): measured errors
    0.37 tau (stiffness 1e4, 3.7e-3) and 0.38 tau (1e5, 1.2e-3), so 0.6 tau; stiffer by 10 shrinks it by sqrt(10) =
    3.2 (measured 3.0): at least 2.  Friction: Stribeck's law is mu exactly above 3 v_s (v_s = 1e-4 << eta = 1):
    |F_t| = mu F_n to 1e-12; its direction opposes the slip of the material point at Drake's contact point, midway
    into the penetration, which moves with C up to |Theta gap| / 2: an angle of at most |Theta gap| / (2 eta_C)
    (measured up to 1.5e-7 rad), plus 1e-12 for rounding."""
    errors = {}
    for k in (1e4, 1e5):
        run = SPEC["drake_continuous"].simulate(ROD, SLIP, SLIP_MU, horizon=0.5, stiffness=k)
        assert run.outcome == Outcome.SLIP and run.record.active[1:].all()
        errors[k] = window_errors(run, SLIP_MU)
        assert errors[k] < 0.6 * run.options.contact_time, (k, errors[k])
    assert errors[1e5] < errors[1e4] / 2
    rec = run.record
    on = rec.normal_force > 0
    Ft = np.hypot(rec.force[on, 0], rec.force[on, 1])
    assert np.abs(Ft / (SLIP_MU * rec.normal_force[on]) - 1).max() < 1e-12
    u, f = rec.slip_vel[on], rec.force[on]
    angle = np.arctan2(
        np.abs(f[:, 0] * u[:, 1] - f[:, 1] * u[:, 0]), -(f[:, 0] * u[:, 0] + f[:, 1] * u[:, 1])
    )  # F_t against -u
    allowed = np.abs(rec.Theta[on] * rec.gap[on]) / (2 * rec.eta[on]) + 1e-12
    assert (angle <= allowed).all()


#: (stiffness, timestep, relaxation_time) pairs around SAP's gliding threshold G = mu eta_C k (dt + tau_d) / (-b/p_C)
#: = 1 at the start (module docstring of crosscheck.engines.drake.engine): G = 0.83 and 1.30 at tau_d = 0, 0.89 and
#: 1.19 at k dt = 1.  Measured: below 1 every row after the first is in contact and the gap never opens (<= 1e-17);
#: above it the tip leaves the plane (active 0.76 .. 0.93 of the rows, gaps 2e-7 .. 1e-5 l).
GLIDING = [
    ((1e4, 1.4e-4, 0.0), False),
    ((1e4, 2.2e-4, 0.0), True),
    ((1e3, 1e-3, 5e-4), False),
    ((1e3, 1e-3, 1e-3), True),
]


@pytest.mark.parametrize("setting, hops", GLIDING, ids=lambda x: str(x))
def test_sap_lifts_a_slipping_tip_when_its_gliding_force_beats_the_rigid_force(setting, hops):
    """SAP's convex relaxation treats a slip speed |v_t| as a separation speed mu |v_t| (Anitescu's cone
    complementarity; crosscheck.engines.pinocchio.stepper shows the rigid version), and its Kelvin-Voigt law turns it
    into an extra normal force mu |v_t| k (dt + tau_d).  While that is below the rigid -b/p_C the tip glides on the
    plane with the rigid force; above it, it is pushed off.  A wrong stiffness or relaxation time in the model (a
    factor 2 in the combination rules) moves the threshold across these pairs.  In contact, the window-mean force
    is -b/p_C within 2.5 contact times (measured 1.8 and 1.9 contact times: at tau_d <= 5e-4 the spring is barely
    damped and rings, where the continuous plant's critically damped contact lags by 0.4)."""
    k, dt, tau = setting
    run = SPEC["drake_sap"].simulate(ROD, SLIP, SLIP_MU, horizon=0.3, timestep=dt, stiffness=k, relaxation_time=tau)
    rec = run.record
    G = (SLIP_MU * rec.eta[0] * k * (dt + tau)) / rigid_force(rec, SLIP_MU)[0]
    assert (G > 1) == hops
    if hops:
        assert rec.gap.max() > 1e-7 and rec.active.mean() < 0.95
    else:
        assert rec.gap.max() < 1e-12 and rec.active[1:].all()
        assert window_errors(run, SLIP_MU) < 2.5 * run.options.contact_time
    on = rec.normal_force > 0
    Ft = np.hypot(rec.force[on, 0], rec.force[on, 1])
    assert (
        np.abs(Ft / (SLIP_MU * rec.normal_force[on]) - 1).max() < 1e-6
    )  # SAP's sliding projection: on the cone's surface


@pytest.mark.parametrize(
    "name, glides",
    [
        ("drake_sap", True),
        ("drake_similar", True),
        ("drake_lagged", False),
        ("drake_tamsi", False),
        ("drake_continuous", False),
    ],
)
def test_at_their_defaults_the_convex_relaxations_launch_a_slipping_tip_and_the_others_keep_it(name, glides):
    """At the defaults G = mu eta k (dt + tau_d) / (-b/p_C) is 130 for SAP (tau_d = 2/sqrt(k), critical damping) and the
    excess mu eta k dt (1 + d mu eta) / (-b/p_C) is 630 for Similar (d = 2 sqrt(k)): the first contact step throws the
    tip up (measured 0.097 and 0.19 l omega), the contact is active in ~1 % of the rows (measured 1.0 % and 0.4 %;
    5 % allows for the hops' phase) and the classifier calls the run a LAUNCH (a flight with b < 0: never a LIFTOFF).
    Lagged, TAMSI and the continuous plant do not relax the normal velocity: the tip stays on the plane in every row
    after the first and the run slips to the horizon, as the rigid rod does (b < 0 < p throughout: measured p_C >= 1.2)."""
    run = SPEC[name].simulate(ROD, SLIP, SLIP_MU, horizon=0.5)
    rec = run.record
    if glides:
        assert rec.active.mean() < 0.05 and rec.gap.max() > 1e-3
        assert run.outcome == Outcome.LAUNCH
    else:
        assert rec.active[1:].all() and rec.gap.max() < 1e-12
        assert run.outcome == Outcome.SLIP


# ------------------------------------------------------------------------------- simulate = sweep rows ---


def test_sweep_rows_are_simulate_runs_exactly():
    """sweep (one process and two) returns for each state exactly what simulate, stopped once its first event is
    judged, returns for it, diagrams reused; and that first event is the whole run's."""
    states = [SLIP, LIFT, OFFPLANE]
    mus = np.array([SLIP_MU, SLIP_MU, 1.4])
    spec = SPEC["drake_sap"]
    opts = {"timestep": 2e-3}
    whole = [spec.simulate(ROD, s, m, horizon=0.3, **opts) for s, m in zip(states, mus)]
    runs = [spec.simulate(ROD, s, m, horizon=0.3, until_event=True, **opts) for s, m in zip(states, mus)]
    assert any(np.isnan(r.record.t).any() for r in runs)  # some run stopped early, ...
    for a, b in zip(whole, runs):  # ... with the whole run's first event
        assert a.outcome == b.outcome
        np.testing.assert_array_equal(a.event_time, b.event_time)  # NaN for a SLIP
    for workers in (1, 2):
        res = spec.sweep(ROD, states, mus, horizon=0.3, progress=False, workers=workers, **opts)
        assert res.engine == "drake_sap" and res.nstep == 150
        for i, run in enumerate(runs):
            assert res.outcome[i] == run.outcome
            np.testing.assert_array_equal([res.event_time[i], res.exit_time[i]], [run.event_time, run.exit_time])
            c = classify(
                run.record, mu=mus[i], alpha=ALPHA, timestep=2e-3, friction_timeconst=run.options.friction_time
            )
            for key in ("max_normal_force", "max_window_force", "active_fraction", "max_gap"):
                assert res.summary[key][i] == getattr(c, key), key
            assert res.solver["contact_rows"][i] == run.solver.contact_rows
    assert runs[0].engine == "drake_sap" and runs[1].outcome == Outcome.LIFTOFF


def test_every_approximation_runs_and_names_its_run():
    for s in ENGINES:
        run = s.simulate(ROD, SLIP, SLIP_MU, horizon=0.05)
        assert run.engine == s.name and run.solver.failed == 0 and len(run.record) == 50
        assert np.isfinite(run.record.force).all()


@pytest.mark.filterwarnings("ignore:All-NaN slice")
def test_a_run_drake_aborts_is_diverged_from_where_it_stopped():
    """Lagged at stiffness 1e10 and a 1e-2 step: its Newton solve fails on the third step (Drake raises
    "NewtonWithBisectionFallback did not converge").  The rows up to there are kept, the rest are NaN, the classifier
    calls it DIVERGED at the first NaN row, and the run says why."""
    run = SPEC["drake_lagged"].simulate(ROD, SLIP, SLIP_MU, horizon=0.5, timestep=1e-2, stiffness=1e10)
    rec = run.record
    assert run.outcome == Outcome.DIVERGED and run.solver.failed == 1 and "did not converge" in run.solver.message
    k = int(round(run.diverged_time / 1e-2))
    assert (
        k >= 1
        and np.isfinite(rec.force[:k]).all()
        and np.isnan(rec.force[k:]).all()
        and np.isfinite(rec.theta[:k]).all()
    )


def test_contact_and_friction_times_follow_the_options():
    assert Options(stiffness=1e4, approximation="continuous").contact_time == pytest.approx(0.01)
    # SAP's near-rigid cap: the contact period is at least beta dt
    assert Options(stiffness=1e8, timestep=1e-3).contact_time == pytest.approx(1e-3 / (2 * math.pi))
    assert Options(approximation="tamsi", stiction_tolerance=1e-3).friction_time == pytest.approx(2.5e-3)
    assert Options(timestep=1e-3).friction_time == pytest.approx(2.5e-6)


@pytest.mark.parametrize("name", sorted(SPEC))
def test_a_run_stopped_once_its_first_event_is_judged_has_the_whole_runs_first_event(name):
    """Each approximation from starts that lift off, jam, stick and keep slipping (at mu 1.4, varphi -1.9): ``until_event``
    stops the run early where an event settles it, with the whole run's outcome, time and JAM numbers, and counts only the
    steps it took; a run that keeps slipping is never cut."""
    for whole, cut, rows in stopped_and_whole(SPEC[name], ROD):
        assert cut.solver.failed == whole.solver.failed and cut.solver.message == whole.solver.message
        if rows < len(whole.record) and whole.options.discrete:
            assert cut.solver.steps == rows < whole.solver.steps


def test_tamsi_stiffened_toward_the_rigid_limit_jams_where_its_capsule_does():
    """The compliance intervention's strongest step (stiffness x 1000, timestep / 10) on a start where the theory jams
    (p reaches 0 at t 0.0133): the slip stops at 0.0088, after the rigid capsule's jam (p_C reaches 0 at 0.0076) and
    before the tip's, under a spike far above -b/p.  Read at the capsule's contact point (the classifier's ``radius``)
    the stop is a JAM at the engine's own p_C < 0; with the tip's moment arm it passed for a STICK."""
    from crosscheck.theory.slipping import slip_until_event

    state, mu = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.125, eta=1.0), 1.375
    run = engines.get("drake_tamsi").simulate(ROD, state, mu, horizon=0.03, timestep=1e-4, stiffness=1e7)
    t_tip = slip_until_event(state, mu, ALPHA).time
    t_capsule = capsule.slip_until_event(state, mu, ALPHA, radius=R).time
    assert t_capsule < run.event_time < t_tip
    assert Outcome(int(run.outcome)) == Outcome.JAM and run.jam_p_eff < 0.0
    o = run.options
    tip_arm = classify(
        run.record,
        mu=mu,
        alpha=ALPHA,
        timestep=o.timestep,
        friction_timeconst=o.friction_time,
        contact_time=o.contact_time,
    )
    assert Outcome(int(tip_arm.outcome)) == Outcome.STICK and tip_arm.event_row == int(
        round(run.event_time / o.timestep)
    )
