"""The one event classifier (crosscheck.engines.classifier): hand-made records, engine records, every past misclassification."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from crosscheck import Outcome, Rod, SlipState
from crosscheck.engines import Record, Thresholds, classify, get
from crosscheck.theory import analytic as an
from crosscheck.theory.slipping import slip_until_event

ALPHA = 3.0
SCALED = Rod.scaled(ALPHA)
ROD = Rod(mass=1.0, length=1.0, inertia=1.0 / 3.0, gravity=9.81)
COARSE = 1e-3 * ROD.omega  # dt = 1 ms for the 1 m rod, in scaled time
MUJOCO = get("mujoco")

#: A hopping (chattering) tip at mu = 1.3 < mu_P whose landing at t = 0.62 has a window-mean force of
#: 1.5-1.7 m g > 3 (-b/p) and a slip loss > 20 %: a JAM for a rule that compares the force with -b/p,
#: although MuJoCo's own p_eff there is 0.45.
HOPPING_BELOW_MU_P = (
    SlipState(
        theta=0.6113389398285725,
        varphi=-0.77475770919191,
        Theta=0.45376828769404165,
        Psi=0.3126466205827283,
        eta=2.343864226276094,
    ),
    1.3,
)

#: A slip at mu = 1.3 < mu_P in near-continuous contact with p ~0.05 (eq. p; p >= 0.04 at mu = 1.3):
#: MuJoCo's force is the slipping -b/p_eff of 15-20 m g and b reaches 0 (lift-off, analytic at t =
#: 0.066) inside the first window.  With the window mean of b (not of max(0, -b)) the lift-off's b > 0
#: rows cancelled the slipping force and the JAM rule fired at t = 0.006 (full report, seed 0).
NEAR_JAM_SLIP_BELOW_MU_P = (
    SlipState(
        theta=1.061401264098454,
        varphi=-1.5792227104861805,
        Theta=0.4796557348275663,
        Psi=0.5291082563291338,
        eta=2.039633923548985,
    ),
    1.3,
)

#: A Corollary 4.2 state (mu = 1.7 > mu_P): analytic JAM at t = 0.460 with b < 0, off the planar
#: section; MuJoCo delivers an impulse there (window force ~7 m g, p_eff ~0.09) and the tip lifts off.
COROLLARY_JAM = (
    SlipState(
        theta=0.4493666453680196,
        varphi=-0.8058921019999438,
        Theta=0.7483528201200262,
        Psi=0.766434722261458,
        eta=2.753242890054462,
    ),
    1.7,
)


def slipping_record(
    n: int = 400, dt: float = 1e-3, *, force: float = 0.5, eta: float = 1.0, theta: float = 0.6
) -> Record:
    """A rod slipping along x (varphi = -pi/2 at psi = pi/2: the rod lies along y) with a steady normal force."""
    t = dt * np.arange(n)
    z3 = np.zeros((n, 3))
    vel = z3.copy()
    vel[:, 0] = eta
    F = z3.copy()
    F[:, 2] = force
    F[:, 0] = -0.5 * force  # mu = 0.5 opposite the slip
    acc = z3.copy()
    acc[:, 2] = 0.0
    return Record(
        t=t,
        tip_pos=z3.copy(),
        tip_vel=vel,
        tip_acc=acc,
        force=F,
        normal_force=F[:, 2].copy(),
        active=np.ones(n, bool),
        gap=np.zeros(n),
        slip_vel=np.column_stack([vel[:, :2], np.zeros(n)]),
        psi=np.full(n, math.pi / 2),
        theta=np.full(n, theta),
        Psi=np.zeros(n),
        Theta=np.zeros(n),
    )


def with_rows(R: Record, k: int, **fields) -> Record:
    """R with the given fields replaced from row k on (values broadcast)."""
    out = {}
    for name, value in fields.items():
        x = np.array(getattr(R, name), dtype=float if name != "active" else bool)
        x[k:] = value
        out[name] = x
    return replace(R, **out)


# ------------------------------------------------------------ hand-made records ---


def test_steady_slip_is_slip():
    c = classify(slipping_record(), mu=0.5, alpha=ALPHA, timestep=1e-3)
    assert c.outcome == Outcome.SLIP and math.isnan(c.event_time) and c.event_row == -1


def test_force_free_upward_rows_are_a_liftoff_at_the_first_of_them():
    R = slipping_record()
    acc = R.tip_acc.copy()
    acc[150:, 2] = 0.3  # b > 0: the free tip accelerates up
    F = R.force.copy()
    F[150:] = 0.0
    R = replace(R, tip_acc=acc, force=F, normal_force=F[:, 2].copy(), active=np.arange(len(R)) < 150)
    c = classify(R, mu=0.5, alpha=ALPHA, timestep=1e-3)
    assert c.outcome == Outcome.LIFTOFF and c.event_row == 150 and c.event_time == pytest.approx(0.150)


def test_two_free_rows_are_not_yet_a_liftoff():
    """lift_steps = 3 force-free upward rows are needed (the first row after a force-free start is free anyway)."""
    R = slipping_record()
    acc = R.tip_acc.copy()
    acc[150:152, 2] = 0.3
    F = R.force.copy()
    F[150:152] = 0.0
    c = classify(replace(R, tip_acc=acc, force=F, normal_force=F[:, 2].copy()), mu=0.5, alpha=ALPHA, timestep=1e-3)
    assert c.outcome == Outcome.SLIP


def test_stick_threshold_follows_the_friction_time_constant():
    """A contact that creeps at eta = 0.03 is stuck for a soft contact with tau_f = 0.06 (creep ~0.4 tau_f), not for a rigid one."""
    R = slipping_record()
    vel = R.tip_vel.copy()
    vel[200:, 0] = 0.03
    R = replace(R, tip_vel=vel, slip_vel=np.column_stack([vel[:, :2], np.zeros(len(R))]))
    rigid = classify(R, mu=0.5, alpha=ALPHA, timestep=1e-3, friction_timeconst=0.0)
    soft = classify(R, mu=0.5, alpha=ALPHA, timestep=1e-3, friction_timeconst=0.06)
    assert rigid.outcome == Outcome.SLIP
    assert soft.outcome == Outcome.STICK and soft.event_row == 200
    assert Thresholds().stick_threshold(0.06) == 0.06 and Thresholds().stick_threshold(0.0) == 0.01


def test_an_impulse_at_the_engines_own_p_zero_with_a_slip_loss_is_a_jam():
    """A window of large force whose friction makes p_eff ~ 0, with the slip speed falling: JAM at the window's start.

    theta = 0.6, friction mu F_z = 2.5 F_z opposite the slip: p_eff = 1 + 3 - 3 s^2 - 3 s c mu = -0.45, eq. p at
    varphi = -pi/2 (slip along +x, rod along y).
    """
    R = slipping_record(force=0.5)
    k = 200
    F, vel = R.force.copy(), R.tip_vel.copy()
    F[k : k + 5, 2] = 40.0
    F[k : k + 5, 0] = -2.5 * 40.0  # mu F_z opposite the slip along +x
    vel[k + 5 :, 0] = 0.05
    R = replace(
        R, force=F, normal_force=F[:, 2].copy(), tip_vel=vel, slip_vel=np.column_stack([vel[:, :2], np.zeros(len(R))])
    )
    c = classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3)
    assert c.outcome == Outcome.JAM
    assert k - Thresholds().window_rows(1e-3) < c.event_row <= k
    assert c.jam_p_eff <= Thresholds().jam_p_eff


def test_the_same_impulse_with_friction_along_the_rod_axis_is_no_jam():
    """The same force window, but friction that leaves p_eff ~ 1 + alpha cos^2 theta (no paradox): not a jam."""
    R = slipping_record(force=0.5)
    k = 200
    F, vel = R.force.copy(), R.tip_vel.copy()
    F[k : k + 5, 2] = 40.0
    F[k : k + 5, 0] = 0.0  # no component along e = (-sin psi, cos psi) = (-1, 0)
    vel[k + 5 :, 0] = 0.05
    R = replace(
        R, force=F, normal_force=F[:, 2].copy(), tip_vel=vel, slip_vel=np.column_stack([vel[:, :2], np.zeros(len(R))])
    )
    c = classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3)
    assert c.outcome != Outcome.JAM


def compliant_stop_record(*, slip_friction: float, k: int = 0, slip_rows: int = 10, stuck_rows: int = 20) -> Record:
    """A compliant impulse ending in a slip stop: from row k the normal force is 40 m g for slip_rows + stuck_rows rows.

    At k = 0 (an inconsistent start jams at once) every window that holds the slip loss also holds the stuck rows.  While it slips (slip_rows rows, eta falling linearly from 1 to 0) the friction is slip_friction F_z opposite the slip
    along +x; stuck, the friction has no component along e = (-1, 0), so p_eff = 1 + alpha cos^2 theta = 3.05 there, as
    the compliant rod's static friction lifts it (-0.5 slipping, +1.6 stuck, from the inconsistent start).
    """
    R = slipping_record(force=0.5)
    F, vel = R.force.copy(), R.tip_vel.copy()
    slip, stuck = slice(k, k + slip_rows), slice(k + slip_rows, k + slip_rows + stuck_rows)
    F[slip, 2], F[slip, 0] = 40.0, -slip_friction * 40.0
    F[stuck, 2], F[stuck, 0] = 40.0, 0.0
    F[k + slip_rows + stuck_rows :, 0] = 0.0
    vel[slip, 0] = np.linspace(1.0, 0.0, slip_rows + 1)[:-1]
    vel[k + slip_rows :, 0] = 0.0
    return replace(
        R, force=F, normal_force=F[:, 2].copy(), tip_vel=vel, slip_vel=np.column_stack([vel[:, :2], np.zeros(len(R))])
    )


def test_a_fast_slip_stop_at_the_engines_own_p_below_zero_is_a_jam_given_the_contact_time():
    """The impulse of a compliant jam ends in a slip stop.  The window that holds it also holds the stuck rows after it
    (p_eff 3.05): the window rule reads STICK.  With the contact time, the stop's look-back (slipping rows at p_eff = -0.45,
    40 m g) reads JAM at the stop's own row; with friction along the rod axis while it slips (p_eff 3.05) it stays STICK."""
    dt = 1e-3
    R = compliant_stop_record(slip_friction=2.5)
    window_only = classify(R, mu=2.5, alpha=ALPHA, timestep=dt)
    c = classify(R, mu=2.5, alpha=ALPHA, timestep=dt, contact_time=5e-3)
    assert Outcome(int(window_only.outcome)) == Outcome.STICK
    assert Outcome(int(c.outcome)) == Outcome.JAM and c.event_row == window_only.event_row
    assert c.jam_p_eff == pytest.approx(1 + 3 - 3 * math.sin(0.6) ** 2 - 3 * math.sin(0.6) * math.cos(0.6) * 2.5)
    assert c.jam_impulse == pytest.approx(10 * 40.0 * dt)  # the look-back, 3 x 5 rows cut at row 0: 10 rows of 40 m g
    along_axis = classify(compliant_stop_record(slip_friction=0.0), mu=2.5, alpha=ALPHA, timestep=dt, contact_time=5e-3)
    assert Outcome(int(along_axis.outcome)) == Outcome.STICK
    # a stop under a force below jam_ratio jam_force (a slow stop at p_eff < 0 is no rigid rod's, but the force test
    # alone must reject it): 2 m g < 3 m g
    weak = compliant_stop_record(slip_friction=2.5)
    F = weak.force * np.where(weak.force[:, 2:3] > 1.0, 2.0 / 40.0, 1.0)
    weak = replace(weak, force=F, normal_force=F[:, 2].copy())
    assert Outcome(int(classify(weak, mu=2.5, alpha=ALPHA, timestep=dt, contact_time=5e-3).outcome)) == Outcome.STICK


def test_the_slip_stop_reads_p_at_the_capsules_contact_point():
    """A capsule's friction acts at C, r below the tip: its moment arm is sin theta + r, and its p_eff reaches 0 at a
    smaller friction than the tip's.  At theta 0.6 and friction 2.16 F_z the tip's arm gives p_eff 0.024 > 0, whose
    slipping force -b/p_eff = 42 m g is more than the stop's 40 m g can beat thrice: STICK.  With r = 0.05 the
    contact point's p_eff is -0.24: the stop is a JAM, with that p_eff."""
    dt, theta, f, r = 1e-3, 0.6, 2.16, 0.05
    st, ct = math.sin(theta), math.cos(theta)
    R = compliant_stop_record(slip_friction=f)
    tip = classify(R, mu=2.5, alpha=ALPHA, timestep=dt, contact_time=5e-3)
    at_C = classify(R, mu=2.5, alpha=ALPHA, timestep=dt, contact_time=5e-3, radius=r)
    p_tip, p_C = (
        1 + ALPHA - ALPHA * st * st - ALPHA * st * ct * f,
        1 + ALPHA - ALPHA * st * st - ALPHA * (st + r) * ct * f,
    )
    assert (
        0 < p_tip < Thresholds().jam_p_eff and 1.0 / p_tip > 40.0 / Thresholds().jam_ratio and p_C < 0
    )  # the case described
    assert Outcome(int(tip.outcome)) == Outcome.STICK
    assert Outcome(int(at_C.outcome)) == Outcome.JAM and at_C.event_row == tip.event_row
    assert at_C.jam_p_eff == pytest.approx(p_C)
    with pytest.raises(ValueError, match=r"radius must be in \[0, inf\); got -0.01"):
        classify(R, mu=2.5, alpha=ALPHA, timestep=dt, contact_time=5e-3, radius=-0.01)


def test_the_compliant_jam_tends_to_the_rigid_rule_as_the_contact_time_vanishes():
    """As contact_time -> 0 the look-back shrinks to lift_steps rows (the rigid rule's look-ahead), and on a Coulomb
    record both rules read the impulse as a JAM: the rigid one at the impulse's first row, the compliant one at the stop."""
    th = Thresholds()
    assert th.stop_rows(1e-12, 1e-3) == th.lift_steps and th.stop_rows(0.06, 3e-4) == 600
    R = compliant_stop_record(slip_friction=2.5)
    rigid = classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3, rigid=True)
    for contact_time in (1e-2, 1e-3, 1e-6):
        c = classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3, contact_time=contact_time)
        assert Outcome(int(c.outcome)) == Outcome(int(rigid.outcome)) == Outcome.JAM, contact_time
        assert rigid.event_row == 0 and c.event_row == 10


def test_a_rigid_engine_or_a_missing_contact_time_keeps_the_window_rule():
    """rigid=True ignores contact_time (its JAM is one row's impulse); a bad contact time is named."""
    R = compliant_stop_record(slip_friction=2.5)
    a = classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3, rigid=True)
    b = classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3, rigid=True, contact_time=5e-3)
    assert (a.outcome, a.event_row) == (b.outcome, b.event_row)
    assert (
        classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3, contact_time=0.0).outcome
        == classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3).outcome
    )
    with pytest.raises(ValueError, match=r"contact_time must be in \[0, inf\); got -0.001"):
        classify(R, mu=2.5, alpha=ALPHA, timestep=1e-3, contact_time=-1e-3)


@pytest.mark.parametrize("fault", ["nan", "stalled_clock", "runaway_speed"], ids=str)
def test_faults_in_a_clean_slip_record_are_diverged_at_the_faulty_row(fault):
    """Injected faults in a clean MuJoCo SLIP record give DIVERGED at the faulty row."""
    s = SlipState(theta=0.5, varphi=-math.pi / 2, Theta=0.0, Psi=0.5, eta=1.0)
    run = MUJOCO.simulate(ROD, s, 0.5, horizon=0.3, timestep=COARSE)
    assert run.outcome == Outcome.SLIP
    R, k = run.record, 40
    if fault == "nan":
        R = with_rows(R, k, tip_vel=np.nan)
    elif fault == "stalled_clock":
        R = with_rows(R, k, t=R.t[k - 1])
    else:
        v = R.tip_vel.copy()
        v[k:, 0] = 2e3
        R = replace(R, tip_vel=v)
    c = classify(R, mu=0.5, alpha=ROD.alpha, timestep=COARSE, friction_timeconst=run.options.friction_time)
    assert c.outcome == Outcome.DIVERGED
    assert c.event_row == k
    assert c.diverged_time == pytest.approx(run.record.t[k] if fault != "stalled_clock" else run.record.t[k - 1])


def test_a_run_with_no_finite_force_is_diverged_with_nan_maxima_and_no_warning():
    """A record whose forces are NaN from its first row (a run that blew up at once): DIVERGED at row 0, its largest
    forces NaN, and no numpy warning on the user's terminal (nanmax warns on an all-NaN row); a batch keeps the other
    run's maxima."""
    import warnings

    from crosscheck.engines.record import FIELDS

    R = slipping_record(n=120)
    bad = with_rows(R, 0, normal_force=np.nan, force=np.nan, tip_vel=np.nan)
    batch = Record(**{name: np.stack([getattr(R, name), getattr(bad, name)]) for name in FIELDS})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = classify(batch, mu=0.5, alpha=ALPHA, timestep=1e-3)
    assert list(c.outcome) == [Outcome.SLIP, Outcome.DIVERGED] and c.event_row[1] == 0
    assert c.max_normal_force[0] == 0.5 and c.max_window_force[0] == pytest.approx(0.5, rel=1e-12)
    assert np.isnan(c.max_normal_force[1]) and np.isnan(c.max_window_force[1])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"diverged_speed": math.nan}, r"diverged_speed must be in \(0, inf\); got nan"),
        ({"window": -0.05}, r"window must be in \(0, inf\); got -0.05"),
        ({"window_steps": 0}, "window_steps must be an integer >= 1; got 0"),
        ({"lift_steps": 2.5}, "lift_steps must be an integer >= 1; got 2.5"),
        ({"jam_p_eff": -0.1}, r"jam_p_eff must be in \[0, inf\); got -0.1"),
        ({"jam_contact_times": -3.0}, r"jam_contact_times must be in \[0, inf\); got -3.0"),
    ],
    ids=[
        "nan_speed",
        "negative_window",
        "zero_window_steps",
        "fractional_lift_steps",
        "negative_p_eff",
        "negative_contact_times",
    ],
)
def test_bad_thresholds_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Thresholds(**kwargs)


# -------------------------------------------------------------- engine records ---


def test_engine_outcome_is_the_classifier_on_its_record():
    """Each MuJoCo run's outcome and event time are exactly ``classify`` of its own record."""
    rng = np.random.default_rng(3)
    states = [
        SlipState(
            theta=rng.uniform(0.2, 1.3),
            varphi=-rng.uniform(0.1, 3.0),
            Theta=0.5 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.3, 2),
        )
        for _ in range(6)
    ]
    mu = [0.5, 1.0, 1.7, 3.0, 0.8, 6.0]
    kinds = set()
    for s, m in zip(states, mu):
        run = MUJOCO.simulate(SCALED, s, m, horizon=1.0, timestep=1e-3, timeconst=0.1)
        o = run.options  # the engine's own rules: its contact time (the slip stop's look-back) and its capsule radius
        c = classify(
            run.record,
            mu=m,
            alpha=ALPHA,
            timestep=1e-3,
            friction_timeconst=0.1,
            contact_time=o.contact_time,
            radius=o.radius,
        )
        assert (run.outcome, run.event_time if run.outcome else 0.0) == (c.outcome, c.event_time if c.outcome else 0.0)
        kinds.add(run.outcome)
    assert len(kinds) >= 2


def test_chatter_spikes_are_not_jams():
    """Slipping at mu = 0.5 (< mu_P, p > 0): normal-force spikes of several m g, window means near -b/p, no JAM."""
    s = SlipState(theta=0.5, varphi=-math.pi / 2, Theta=0.0, Psi=0.5, eta=1.0)
    rigid = float(an.normal_force(s.Psi, s.Theta, s.theta, s.varphi, 0.5, ROD.alpha))
    for dt in (COARSE, COARSE / 10, COARSE / 100):
        r = MUJOCO.sweep(ROD, [s], 0.5, horizon=0.3, timestep=dt, progress=False)
        assert r.outcome[0] == Outcome.SLIP, dt
        assert r.summary["max_normal_force"][0] > 5 * rigid  # the spikes are there
        assert r.summary["max_window_force"][0] < 3 * rigid  # and average out


def test_a_hopping_landing_below_mu_P_is_no_jam():
    s, mu = HOPPING_BELOW_MU_P
    r = MUJOCO.sweep(SCALED, [s], mu, horizon=0.8, progress=False)
    assert r.outcome[0] != Outcome.JAM


def test_a_liftoff_inside_the_window_does_not_cancel_the_slipping_force():
    s, mu = NEAR_JAM_SLIP_BELOW_MU_P
    a = slip_until_event(s, mu, ALPHA, t_max=2.0)
    assert a.outcome == Outcome.LIFTOFF and a.time < 0.1
    run = MUJOCO.simulate(SCALED, s, mu, horizon=0.3)
    R, w = run.record, Thresholds().window_rows(run.options.timestep)
    # the tip is in contact from row 3 past the row where the JAM rule once fired (21): the force rise is no landing
    assert R.active[3:30].all() and R.normal_force[3] > 10.0 and w > 30
    assert run.outcome == Outcome.LIFTOFF
    assert abs(run.event_time - a.time) < 0.06


def test_the_jam_rule_fires_where_mujoco_reproduces_a_corollary_jam():
    s, mu = COROLLARY_JAM
    a = slip_until_event(s, mu, ALPHA, t_max=2.0)
    assert a.outcome == Outcome.JAM and a.b < -0.1 and abs(a.state.varphi + math.pi / 2) > 0.1
    run = MUJOCO.simulate(SCALED, s, mu, horizon=1.0)
    assert run.outcome == Outcome.JAM
    assert abs(run.event_time - a.time) < 0.15
    assert run.jam_p_eff <= Thresholds().jam_p_eff


def test_a_divergence_after_the_domain_exit_is_still_the_outcome():
    """Rigid engine, mu = 1.3: the rod slips through theta = 0 (the analytic run is censored there) and its angles blow up near
    theta = -pi/2 (the joints' gimbal singularity) a second later: DIVERGED, with the exit time before it (never hidden as SLIP)."""
    from crosscheck import Rod, SlipState
    from crosscheck.engines import get

    s = SlipState(
        theta=0.4915311379637795,
        varphi=-1.3440367621732925,
        Theta=-0.9155531610879961,
        Psi=0.24270625937538748,
        eta=1.9393780355886552,
    )
    r = get("pinocchio").simulate(Rod.scaled(3.0), s, 1.3, horizon=2.0)
    assert r.outcome == Outcome.DIVERGED and 0.4 < r.exit_time < 0.5 and r.diverged_time == r.event_time > 1.0


def _launched(speed: float, *, at: int = 100, theta: float = 0.6, dt: float = 1e-3) -> Record:
    """A slip (b = sin 0.6 - 1 < 0 at rest rates) whose contact step at row ``at`` throws the tip up at ``speed`` into a free flight."""
    R = slipping_record(dt=dt, theta=theta)
    n = len(R)
    vel = R.tip_vel.copy()
    vel[at + 1 :, 2] = speed  # the flight's rise (its fall under b does not matter within the window)
    free = np.arange(n) > at
    F = np.where(free[:, None], 0.0, R.force)
    return replace(R, tip_vel=vel, force=F, normal_force=F[:, 2].copy(), active=~free)


def test_launch_is_a_contact_step_that_throws_the_tip_up_while_b_is_negative():
    """SAP's gliding in the probe: 0.45 l omega up at eta = 1 after a contact step, then a flight; the theory slips (b < 0)."""
    th = Thresholds()
    c = classify(_launched(0.45), mu=0.5, alpha=ALPHA, timestep=1e-3, rigid=True, thresholds=th)
    assert Outcome(int(c.outcome)) == Outcome.LAUNCH and c.event_time == pytest.approx(0.1)
    # the same flight started at a speed below launch_ratio eta is no launch (a soft contact's small hop) ...
    slow = classify(_launched(0.5 * th.launch_ratio), mu=0.5, alpha=ALPHA, timestep=1e-3, rigid=True, thresholds=th)
    assert Outcome(int(slow.outcome)) != Outcome.LAUNCH
    # ... nor is a rise after which the tip lands and the contact pushes again within the window (a hop, not a flight)
    R = _launched(0.45)
    F, vel = R.force.copy(), R.tip_vel.copy()
    F[130:] = slipping_record().force[130:]
    vel[131:, 2] = 0.0
    hop = classify(
        replace(R, force=F, normal_force=F[:, 2].copy(), tip_vel=vel),
        mu=0.5,
        alpha=ALPHA,
        timestep=1e-3,
        rigid=True,
        thresholds=th,
    )
    assert Outcome(int(hop.outcome)) != Outcome.LAUNCH
    # and with b > 0 (theta such that the free acceleration points up) leaving the plane is the paper's lift-off, not a launch
    up = _launched(0.45)
    up = replace(up, Psi=np.full(len(up), 3.0))  # b = Psi^2 cos^2 theta sin theta - 1 > 0 at theta = 0.6
    assert (
        Outcome(int(classify(up, mu=0.5, alpha=ALPHA, timestep=1e-3, rigid=True, thresholds=th).outcome))
        != Outcome.LAUNCH
    )


# ------------------------------------------------------------ records cut after the first event ---


def _cut(R: Record, k: int) -> Record:
    """R with rows k.. not computed (NaN everywhere, time too; ``active`` False), as an engine that stopped there leaves them."""
    out = {}
    for f in (
        "t",
        "tip_pos",
        "tip_vel",
        "tip_acc",
        "force",
        "normal_force",
        "gap",
        "slip_vel",
        "psi",
        "theta",
        "Psi",
        "Theta",
    ):
        x = np.array(getattr(R, f), dtype=float)
        x[k:] = np.nan
        out[f] = x
    active = np.array(R.active, bool)
    active[k:] = False
    return replace(R, active=active, **out)


def test_a_run_cut_once_its_first_event_is_judged_keeps_that_event_and_nothing_after_it():
    """MuJoCo runs of several outcomes, cut at the first row where ``first_event_final`` holds for their first rows: the
    outcome, time and JAM numbers are the whole run's; a cut is not a divergence nor a domain exit; a cut a row before
    the event's look-ahead ends is not final (the event could still be judged otherwise)."""
    from crosscheck.engines.classifier import first_event_final

    th, dt = Thresholds(), 1e-3
    w = th.window_rows(dt)
    seen = set()
    starts = (
        COROLLARY_JAM,
        (SlipState(theta=1.2, varphi=-1.9, Theta=0.9, Psi=0.0, eta=1.0), 1.4),  # JAM at 0.40, LIFTOFF at 0.087
        (SlipState(theta=1.1, varphi=-1.9, Theta=-0.6, Psi=0.0, eta=1.0), 1.4),
    )  # STICK at 0.11
    for s, m in starts:
        R = MUJOCO.simulate(SCALED, s, m, horizon=1.0, timestep=dt, timeconst=0.1).record
        kw = dict(mu=m, alpha=ALPHA, timestep=dt, friction_timeconst=0.1, contact_time=0.1)
        whole = classify(R, **kw)
        assert whole.event_row >= 0, s
        seen.add(int(whole.outcome))
        k = int(whole.event_row) + w + max(2, th.lift_steps)  # the fewest rows that settle it
        head = classify(R.rows(slice(0, k)), **kw)
        assert first_event_final(head, k, th, dt) and not first_event_final(
            classify(R.rows(slice(0, k - 1)), **kw), k - 1, th, dt
        )
        cut = classify(_cut(R, k), **kw)
        for f in ("outcome", "event_time", "event_row", "jam_p_eff", "jam_impulse"):
            np.testing.assert_array_equal(getattr(cut, f), getattr(whole, f), err_msg=f)
        assert math.isnan(cut.diverged_time) and (math.isnan(cut.exit_time) or cut.exit_time < k * dt)
    assert seen == {int(Outcome.JAM), int(Outcome.LIFTOFF), int(Outcome.STICK)}


# ------------------------------------------------------------ one rule at a time ---


def _rows_of(R: Record):
    from crosscheck.engines import classifier_rules

    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return classifier_rules, classifier_rules.rows_of(R)


def _marked(mask: np.ndarray) -> list[int]:
    return [int(k) for k in np.flatnonzero(mask)]


def test_rule_diverged_marks_the_faulty_rows_and_no_clean_one():
    cl, s = _rows_of(slipping_record())
    assert _marked(cl.diverged_rows(slipping_record(), s, Thresholds())) == []
    R = with_rows(slipping_record(), 300, theta=np.nan)
    cl, s = _rows_of(R)
    assert _marked(cl.diverged_rows(R, s, Thresholds()))[:2] == [300, 301]
    t = slipping_record().t.copy()
    t[250] = t[249]  # a stopped clock: the row that repeats its predecessor's time
    R = replace(slipping_record(), t=t)
    cl, s = _rows_of(R)
    assert _marked(cl.diverged_rows(R, s, Thresholds())) == [250]


def test_rule_window_jam_marks_the_windows_holding_the_impulse_at_negative_p_eff():
    R = compliant_stop_record(slip_friction=2.5, k=200)
    cl, s = _rows_of(R)
    w = Thresholds().window_rows(1e-3)
    jam, p_eff, _ = cl.window_jam_rows(s, Thresholds(), alpha=ALPHA, w=w)
    assert jam.any() and all(200 - w < k <= 200 for k in _marked(jam))
    assert (p_eff[jam] <= Thresholds().jam_p_eff).all()
    along_axis = compliant_stop_record(slip_friction=0.0, k=200)
    cl, s = _rows_of(along_axis)
    assert not cl.window_jam_rows(s, Thresholds(), alpha=ALPHA, w=w)[0].any()


def test_rule_impulse_jam_marks_the_rigid_impulse_row_at_eq_p_below_zero():
    R = compliant_stop_record(slip_friction=2.5, k=200)
    cl, s = _rows_of(R)
    impulse, p_row = cl.impulse_jam_rows(R, s, Thresholds(), mu=np.asarray(2.5)[..., None], alpha=ALPHA)
    assert _marked(impulse)[0] == 200 and (p_row[impulse] <= Thresholds().jam_p_eff).all()
    # below mu_P eq. p stays positive and the same record holds no rigid jam
    assert not cl.impulse_jam_rows(R, s, Thresholds(), mu=np.asarray(0.5)[..., None], alpha=ALPHA)[0].any()


def test_rule_liftoff_needs_lift_steps_free_upward_rows_or_one_for_a_rigid_contact():
    R = slipping_record()
    acc, F = R.tip_acc.copy(), R.force.copy()
    acc[150:152, 2], F[150:152] = 0.3, 0.0
    R = replace(R, tip_acc=acc, force=F, normal_force=F[:, 2].copy())
    cl, s = _rows_of(R)
    assert _marked(cl.liftoff_rows(R, s, Thresholds(), rigid=False)) == []
    assert _marked(cl.liftoff_rows(R, s, Thresholds(), rigid=True)) == [150, 151]


def test_rule_launch_marks_the_contact_step_that_throws_the_tip_up():
    cl, s = _rows_of(_launched(0.45))
    assert _marked(
        cl.launch_rows(_launched(0.45), s, Thresholds(), w=Thresholds().window_rows(1e-3), timestep=1e-3)
    ) == [100]
    slow = _launched(0.5 * Thresholds().launch_ratio)  # below launch_ratio eta
    cl, s = _rows_of(slow)
    assert not cl.launch_rows(slow, s, Thresholds(), w=Thresholds().window_rows(1e-3), timestep=1e-3).any()


def test_rule_stick_marks_slow_rows_with_a_touch_in_the_last_window():
    R = slipping_record()
    vel = R.tip_vel.copy()
    vel[200:, 0] = 0.005
    R = replace(R, tip_vel=vel, slip_vel=np.column_stack([vel[:, :2], np.zeros(len(R))]))
    cl, s = _rows_of(R)
    w = Thresholds().window_rows(1e-3)
    assert _marked(cl.stick_rows(s, w=w, stick_speed=0.01))[0] == 200
    F = R.force.copy()
    F[:] = 0.0  # no force at all: a slow free rod is not stuck
    R = replace(R, force=F, normal_force=F[:, 2].copy())
    cl, s = _rows_of(R)
    assert not cl.stick_rows(s, w=w, stick_speed=0.01).any()


def test_rule_stop_jam_relabels_the_stop_row_and_writes_its_p_eff_and_impulse():
    R = compliant_stop_record(slip_friction=2.5)
    cl, s = _rows_of(R)
    w = Thresholds().window_rows(1e-3)
    has, k = cl.first_row(cl.stick_rows(s, w=w, stick_speed=0.01))
    p_eff, sF = np.zeros(len(R)), np.zeros(len(R))
    stop = cl.stop_jam_rows(
        s, Thresholds(), has_stick=has, k_stick=k, m=15, stick_speed=0.01, alpha=ALPHA, radius=0.0, p_eff=p_eff, sF=sF
    )
    assert _marked(stop) == [10] and p_eff[10] < 0 and sF[10] == pytest.approx(10 * 40.0)


def test_first_event_takes_the_earliest_and_breaks_ties_by_the_order_given():
    from crosscheck.engines.classifier import first_event

    yes, no = np.array([True, True, False]), np.array([False, True, False])
    outcome, row = first_event([(Outcome.JAM, no, np.array([0, 5, 0])), (Outcome.STICK, yes, np.array([3, 5, 0]))])
    assert list(outcome) == [Outcome.STICK, Outcome.JAM, Outcome.SLIP] and list(row[:2]) == [3, 5]
