"""The MuJoCo engine: its model file, geometry, free dynamics, the start on the plane, outcomes, bad input."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from conftest import random_slip_states
from mujoco import rollout

from crosscheck import Outcome, Rod, SlipState
from crosscheck.coordinates import GENERALIZED, tip_position, to_generalized
from crosscheck.engines import get
from crosscheck.engines.mujoco.engine import Batch, Options
from crosscheck.engines.mujoco.model import (
    START_GAP,
    ModelFileError,
    SensorLayout,
    build_model,
    initial_state,
    model_path,
    record_from_sensordata,
)
from crosscheck.engines.mujoco.tolerances import MUJOCO_FREE_ACCELERATION
from crosscheck.theory import analytic as an
from crosscheck.theory.critical import Psi_L, theta_L

ROD = Rod(mass=1.0, length=1.0, inertia=1.0 / 3.0, gravity=9.81)
simulate = get("mujoco").simulate
#: One generator for every rod of the joint-order test (its states differ from rod to rod, as they always have).
_JOINT_ORDER_RNG = np.random.default_rng(7)

RODS = {
    "uniform_1m": ROD,
    "scaled_alpha5": Rod.scaled(5.0),
    "heavy_short": Rod(mass=2.5, length=0.3, inertia=0.05, gravity=9.81),
}


def test_packaged_file_loads_and_steps_as_it_is():
    model = mujoco.MjModel.from_xml_path(model_path())
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("slipping").id)
    for _ in range(100):
        mujoco.mj_step(model, data)
    assert np.all(np.isfinite(data.qpos))
    assert data.time == pytest.approx(100 * model.opt.timestep)
    assert [model.joint(i).name for i in range(model.njnt)] == list(GENERALIZED)
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    assert model.pair_dim[0] == 3


@pytest.mark.parametrize("name", RODS, ids=str)
def test_joint_order_gives_the_coordinates_of_crosscheck(name, rng=_JOINT_ORDER_RNG):
    """Five joints in the order X, Y, Z, psi, theta: MuJoCo's tip site = eq. tipfromcentre of q."""
    rod = RODS[name]
    model = build_model(rod, 0.7, Options())
    data = mujoco.MjData(model)
    for _ in range(20):
        q = np.concatenate([rng.normal(size=3), rng.uniform(-math.pi, math.pi, 1), rng.uniform(0.01, 1.56, 1)])
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        np.testing.assert_allclose(
            data.site("tip").xpos, tip_position(rod, q), rtol=0, atol=1e-14 * (1 + np.abs(q[:3]).max())
        )


@pytest.mark.parametrize("name", RODS, ids=str)
def test_free_tip_acceleration_is_linode2_and_b(name):
    """Contacts disabled: MuJoCo's tip acceleration = eq. linode2 with F = 0, vertical = b (eq. b)."""
    rod = RODS[name]
    model = build_model(rod, 1.0, Options())
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    data = mujoco.MjData(model)
    layout = SensorLayout.from_model(model)
    states = random_slip_states(np.random.default_rng(11), 100)
    got = []
    for s in states:
        mujoco.mj_setState(model, data, initial_state(model, rod, s, 0.01), mujoco.mjtState.mjSTATE_FULLPHYSICS)
        mujoco.mj_forward(model, data)
        got.append(record_from_sensordata(data.sensordata, layout, rod, 0.01).tip_acc)
    got = np.array(got)
    S = {k: np.array([getattr(s, k) for s in states]) for k in ("psi", "theta", "Psi", "Theta")}
    want = (
        an.tip_acceleration(rod, S["psi"], S["theta"], S["Psi"] * rod.omega, S["Theta"] * rod.omega, np.zeros(3))
        / rod.gravity
    )
    assert MUJOCO_FREE_ACCELERATION.ok(got, want), np.max(MUJOCO_FREE_ACCELERATION.ratio(got, want))
    assert MUJOCO_FREE_ACCELERATION.ok(got[:, 2], an.b(S["Psi"], S["Theta"], S["theta"]))


def test_start_touches_and_keeps_the_state_velocities():
    """z_A = r + START_GAP: the capsule's lowest point START_GAP above the plane, velocities the state's."""
    s = SlipState(theta=0.7, varphi=-1.0, Theta=0.3, Psi=0.8, eta=1.2, psi=0.4)
    radius = 0.02
    model = build_model(ROD, 0.5, Options(radius=radius))
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, initial_state(model, ROD, s, radius), mujoco.mjtState.mjSTATE_FULLPHYSICS)
    mujoco.mj_forward(model, data)
    capsule_bottom = data.site("tip").xpos[2] - radius * ROD.length
    assert abs(capsule_bottom - START_GAP * ROD.length) < 1e-15
    _, v = to_generalized(ROD, s, tip=(0, 0, radius))
    np.testing.assert_array_equal(data.qvel, v)


def test_no_start_has_a_contact_in_its_first_row_and_every_falling_start_has_one_in_its_second():
    """At t = 0 MuJoCo's distance is START_GAP l (+-1e-16 l of rounding): no contact, no force, for every start.

    With the capsule's lowest point exactly on the plane, the sign of MuJoCo's
    distance was the rounding of r and of the rotated tip offset, and whether
    row 0 had a contact was a tie (14 % of 400 random states had one).  The
    start now sits START_GAP above, 3000 times that rounding.  A slipping start
    whose tip's free acceleration b points into the plane falls |b| dt^2 / 2 >> START_GAP in the first
    step: its contact is on in row 1.  (With b > 0 the capsule's lowest point C may still sink: its acceleration
    differs from A's by the capsule's O(r) terms.)
    """
    rng = np.random.default_rng(0)
    states = random_slip_states(rng, 200)
    batch = Batch.build(ROD, states, 1.0, horizon=2 * Options().timestep, options=Options(), nthread=1)
    sd = np.concatenate([sd[:, :2].copy() for _, sd in batch.chunks(progress=False)])  # a chunk's buffer is reused
    L = batch.layout
    dist, found, force = sd[:, 0, L.dist], sd[:, 0, L.found] > 0, sd[:, 0, L.force.start]
    assert not np.any(found) and np.all(force == 0.0)
    gap = sd[:, 0, L.tip_pos.start + 2] - Options().radius * ROD.length
    assert np.all(np.abs(gap - START_GAP * ROD.length) < 1e-15) and np.all(
        dist == 0.0
    )  # no contact: the sensor reads 0
    b = np.array([an.b(s.Psi, s.Theta, s.theta) for s in states])
    down = b < 0
    assert 0 < down.sum() < len(b)  # both kinds of start occur
    assert np.all(sd[down, 1, L.found] > 0)


def test_slip_velocity_formula_matches_mujoco_contact_velocity():
    """Record.slip_vel (v_A + r theta' (-sin psi, cos psi, 0)) = MuJoCo's contact linvel while in contact.

    An identity of rigid-body kinematics: both are the velocity of a material point of the rod.
    """
    s = SlipState(theta=0.9, varphi=-2.0, Theta=0.8, Psi=-0.7, eta=1.0, psi=1.1)  # b = -0.35: slips
    run = simulate(ROD, s, 0.3, horizon=0.3, radius=0.05)
    rec = run.record
    model = build_model(ROD, 0.3, Options(radius=0.05))
    layout = SensorLayout.from_model(model)
    # Re-run to read MuJoCo's own linvel (contact frame) next to the record.
    _, sd = rollout.rollout(model, mujoco.MjData(model), initial_state(model, ROD, s, 0.05)[None], nstep=run.nstep)
    sd = sd[0]
    on = sd[:, layout.found] > 0
    assert on.sum() >= 10  # the contact chatters: active in a few % of the rows
    n_, t1 = sd[on][:, layout.normal], sd[on][:, layout.tangent]
    lv = sd[on][:, layout.linvel]
    world = lv[:, :1] * n_ + lv[:, 1:2] * t1 + lv[:, 2:3] * np.cross(n_, t1)
    # MuJoCo's contact point is midway into the penetration, dist / 2 above the capsule's lowest point
    r_eff = 0.05 + sd[on][:, layout.dist] / 2 / ROD.length
    extra = (r_eff - 0.05) * rec.Theta[on]
    psi = rec.psi[on]
    want = rec.slip_vel[on][:, :2] + extra[:, None] * np.stack([-np.sin(psi), np.cos(psi)], axis=1)
    np.testing.assert_allclose(world[:, :2] / (ROD.length * ROD.omega), want, rtol=0, atol=1e-12)


def test_a_batch_record_is_the_record_of_each_of_its_rows():
    """``record_from_sensordata`` of a (2, 3, N) batch equals, bit for bit, the record of each of its rows alone.

    The batch's sensor columns are transposed in blocks of ``COPY_ROWS`` rows; N = 2 COPY_ROWS + 7 puts block
    boundaries inside every run and across runs, so a block copied to the wrong place shows as a row that differs.
    """
    from crosscheck.engines.mujoco.model import COPY_ROWS
    from crosscheck.engines.record import FIELDS

    model = build_model(ROD, 0.3, Options(radius=0.05))
    layout = SensorLayout.from_model(model)
    states = random_slip_states(np.random.default_rng(5), 6)
    n = 2 * COPY_ROWS + 7
    x0 = np.stack([initial_state(model, ROD, s, 0.05) for s in states])
    _, sd = rollout.rollout(model, mujoco.MjData(model), x0, nstep=n)
    sd = sd.reshape(2, 3, n, -1)
    batch = record_from_sensordata(sd, layout, ROD, 0.05)
    assert np.ptp(batch.psi) > 0 and np.any(batch.active)  # rows that differ, with a contact: a misplaced block shows
    for i, j, k in [(0, 0, 0), (0, 2, COPY_ROWS - 1), (1, 0, COPY_ROWS), (1, 1, 2 * COPY_ROWS + 6), (1, 2, 777)]:
        one = record_from_sensordata(sd[i, j, k], layout, ROD, 0.05)
        for name in FIELDS:
            got = getattr(batch, name)[i, j, k]
            assert np.array_equal(got, getattr(one, name)), (name, i, j, k)
    rows = record_from_sensordata(
        sd[1, 2], layout, ROD, 0.05
    )  # the last run alone: the same arrays as its place in the batch
    for name in FIELDS:
        assert np.array_equal(getattr(batch, name)[1, 2], getattr(rows, name)), name


@pytest.mark.parametrize("dPsi, outcome", [(-1e-4, Outcome.SLIP), (1e-4, Outcome.LIFTOFF)], ids=["below", "above"])
def test_liftoff_threshold_at_theta_L(dPsi, outcome):
    """At theta_L, Theta = 0, varphi = -pi/2: lift-off at t = 0 iff Psi > Psi_L (eq. psil)."""
    s = SlipState(theta=theta_L, varphi=-math.pi / 2, Theta=0.0, Psi=Psi_L + dPsi, eta=1.0)
    run = simulate(ROD, s, 0.5, horizon=0.1)
    assert run.outcome == outcome
    if outcome == Outcome.LIFTOFF:
        assert run.event_time == 0.0


# ------------------------------------------------------------- bad input ---


def test_unknown_option_is_named():
    with pytest.raises(ValueError, match="unknown MuJoCo option 'time_step'"):
        simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=0.1, time_step=1e-4)


def test_state_must_be_a_slipstate_in_range():
    with pytest.raises(ValueError, match=r"theta must be in \(0, pi/2\); got 2.0"):
        simulate(ROD, SlipState(2.0, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=0.1)
    with pytest.raises(ValueError, match="state must be a SlipState; got tuple"):
        simulate(ROD, (0.5, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=0.1)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"horizon": 0.0}, r"horizon must be in \(0, inf\); got 0.0"),
        ({"horizon": 0.1, "timestep": -1.0}, r"timestep must be in \(0, inf\); got -1.0"),
        (
            {"horizon": 0.1, "timeconst": 1e-4},
            r"timeconst must be >= 2 timestep = 0.0006 \(MuJoCo's refsafe\); got 0.0001",
        ),
        ({"horizon": 0.1, "solimp": (0.9, 0.95)}, "solimp must have 5 numbers"),
    ],
    ids=["horizon", "timestep", "timeconst", "solimp"],
)
def test_bad_options(kwargs, message):
    with pytest.raises(ValueError, match=message):
        simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), 0.5, **kwargs)


def test_bad_mu():
    with pytest.raises(ValueError, match=r"mu must be in \[0, 1000\]; got -1.0"):
        simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), -1.0, horizon=0.1)


def test_missing_model_file_is_named(tmp_path):
    path = tmp_path / "nope.xml"
    with pytest.raises(ModelFileError, match=f"MuJoCo model file not found: {path}"):
        simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=0.1, model_file=path)


def test_malformed_model_file_is_named(tmp_path):
    path = tmp_path / "bad.xml"
    path.write_text("<mujoco><worldbody><body></mujoco>")
    with pytest.raises(ModelFileError, match=f"malformed MuJoCo model file {path}"):
        simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=0.1, model_file=path)


def test_model_file_without_the_rod_is_named(tmp_path):
    path = tmp_path / "empty.xml"
    path.write_text("<mujoco><worldbody/></mujoco>")
    with pytest.raises(ModelFileError, match=f"{path} lacks body 'rod'"):
        simulate(ROD, SlipState(0.5, -1.0, 0.0, 0.0, 1.0), 0.5, horizon=0.1, model_file=path)


@pytest.mark.parametrize(
    "horizon, message",
    [
        (
            1e5,
            r"horizon / timestep must be at most 5592405 steps with nthread = 1 \(records of 4 GiB\); got 100000 / 0.0003 = 333333334 steps",
        ),
        (1e308, r"horizon / timestep must be at most 1e15 steps; got 1e\+308 / 0.0003 = inf"),
    ],
    ids=["27-GiB", "overflow"],
)
def test_a_run_too_long_to_record_is_refused_before_allocating(horizon, message):
    from crosscheck import Rod, SlipState
    from crosscheck.engines import get

    with pytest.raises(ValueError, match=message):
        get("mujoco").simulate(Rod.scaled(3.0), SlipState(1.0, -1.9, 0.0, 1.0, 1.0), 0.5, horizon=horizon)


def test_a_setting_compiles_once_and_an_edited_model_file_anew(tmp_path):
    import os
    import shutil

    from crosscheck.engines.mujoco.model import model

    opts = Options(radius=0.02)
    first = model(ROD, 0.6, opts)
    assert model(ROD, 0.6, opts) is first and model(ROD, 0.61, opts) is not first
    state = SlipState(0.9, -1.7, 0.3, 0.5, 1.0)
    path = tmp_path / "rod.xml"
    shutil.copy(model_path(), path)
    before = simulate(ROD, state, 0.6, horizon=0.05, model_file=path)
    fresh = simulate(
        ROD, state, 0.6, horizon=0.05, model_file=path
    )  # the cached model: the same numbers as the first compile
    assert np.array_equal(before.record.force, fresh.record.force) and np.array_equal(
        before.record.tip_pos, fresh.record.tip_pos
    )
    # the same file edited (gravity switched off: build_model sets its value, not the flag), same path
    text = path.read_text()
    assert '<flag autoreset="disable"/>' in text
    path.write_text(text.replace('<flag autoreset="disable"/>', '<flag autoreset="disable" gravity="disable"/>'))
    os.utime(path, ns=(1, 1))  # an mtime of its own, whatever the clock's resolution
    edited = simulate(ROD, state, 0.6, horizon=0.05, model_file=path)
    assert not np.array_equal(before.record.tip_pos, edited.record.tip_pos)


def test_a_run_in_used_data_is_the_run_in_fresh_data():
    # the engine lends the MjData of earlier runs (engine._lent_data): nothing of an earlier run may reach a later one
    from crosscheck.engines.mujoco import engine

    state, other = SlipState(0.9, -1.7, 0.3, 0.5, 1.0), SlipState(1.3, -2.4, -0.8, 1.6, 0.7)
    engine._spare.clear()
    fresh = simulate(ROD, state, 0.8, horizon=0.3)
    simulate(
        ROD, other, 1.9, horizon=0.4, timeconst=0.02
    )  # another setting of the same layout: leaves its data to the next
    simulate(ROD, other, 0.8, horizon=0.4)
    assert any(engine._spare.values())
    used = simulate(ROD, state, 0.8, horizon=0.3)
    for f in ("t", "force", "tip_pos", "tip_vel", "tip_acc", "active"):
        assert np.array_equal(getattr(fresh.record, f), getattr(used.record, f)), f
