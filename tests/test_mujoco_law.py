"""MuJoCo's contact law (crosscheck.engines.mujoco.law) against MuJoCo's own solver arrays, and its continuous-time engine."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck import Rod, SlipState
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.mujoco.law import (
    NO_FEED_FORWARD_IMPEDANCE,
    Parameters,
    accelerations,
    contact_force,
    contact_problem,
    inverse_weight,
    skew_angle,
    solve_cone,
)
from crosscheck.engines.mujoco.ode import integrate
from crosscheck.engines.mujoco.options import Options
from crosscheck.engines.mujoco.studies import friction_skew as fs
from crosscheck.engines.mujoco.studies.contact import friction_skew
from crosscheck.engines.mujoco.studies.law_check import convergence_order, random_contact
from crosscheck.engines.mujoco.tolerances import (
    MUJOCO_LAW_FORCE,
    MUJOCO_LAW_KKT,
    MUJOCO_LAW_ORDER,
    MUJOCO_LAW_PIECES,
    MUJOCO_LAW_SKEW,
    MUJOCO_LAW_SKEW_IDENTITY,
)
from crosscheck.tolerances import CLOSED_FORM


def test_force_R_aref_equal_mujoco_solver_arrays():
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(16):
        rod, mu, opts, impratio, model, data = random_contact(rng)
        assert data.nefc == 3
        pb = contact_problem(rod, data.qpos, data.qvel, mu, opts, impratio=impratio)
        # MuJoCo's diagApprox is the rod's translational invweight0, not A's diagonal
        assert MUJOCO_LAW_PIECES.ok(inverse_weight(rod), model.body_invweight0[1, 0])
        assert MUJOCO_LAW_PIECES.ok(pb.dist, data.contact[0].dist)
        assert MUJOCO_LAW_PIECES.ok(pb.frame.ravel(), data.contact[0].frame)
        assert MUJOCO_LAW_PIECES.ok(pb.R, data.efc_R)
        # aref = -B v - K imp dist: its normal row is a near-cancelling difference, so the allowance is on the terms' size
        terms = np.abs(data.efc_KBIP[:, 1] * data.efc_vel) + np.abs(
            data.efc_KBIP[:, 0] * data.efc_KBIP[:, 2] * data.efc_pos
        )
        assert np.all(np.abs(pb.aref - data.efc_aref) <= MUJOCO_LAW_PIECES.allowance(terms))
        assert MUJOCO_LAW_PIECES.ok(pb.imp, data.efc_KBIP[0, 2])
        assert MUJOCO_LAW_PIECES.ok(pb.B, data.efc_KBIP[:, 1])
        f = pb.force()
        scale = np.abs(data.efc_force).max()
        assert np.abs(f - data.efc_force).max() <= MUJOCO_LAW_FORCE.allowance(scale)
        worst = max(worst, np.abs(f - data.efc_force).max() / scale)
        # the public world force in m g is the same force
        world = contact_force(rod, data.qpos, data.qvel, mu, opts, impratio=impratio) * rod.force_scale
        assert np.abs(
            world - data.contact[0].frame.reshape(3, 3).T @ data.efc_force
        ).max() <= MUJOCO_LAW_FORCE.allowance(scale)
    assert worst > 0.0  # the comparison saw two independent computations


def test_cone_solution_satisfies_the_optimality_conditions():
    rng = np.random.default_rng(3)
    for _ in range(200):
        L = rng.normal(size=(3, 3))
        H = L @ L.T + 0.05 * np.eye(3)
        g, mu = rng.normal(size=3) * 3, rng.uniform(0.0, 3.0)
        f = solve_cone(H, g, mu)
        y = H @ f + g
        size = np.abs(g).max() + np.abs(H).max() * np.abs(f).max()
        assert f[0] >= -MUJOCO_LAW_KKT.atol * size and math.hypot(f[1], f[2]) <= mu * f[0] + MUJOCO_LAW_KKT.atol * size
        if (
            mu > 0
        ):  # y in the dual cone {y_n >= mu |y_t|} (for mu = 0 the tangential rows are free of force: y_t unconstrained)
            assert y[0] >= mu * math.hypot(y[1], y[2]) - MUJOCO_LAW_KKT.atol * size
        else:
            assert y[0] >= -MUJOCO_LAW_KKT.atol * size
        assert abs(f @ y) <= MUJOCO_LAW_KKT.atol * size * max(1.0, np.abs(f).max())


def test_friction_opposes_slip_extrapolated_over_one_over_B_and_anisotropy_of_A_makes_the_skew():
    rod = Rod.scaled(3.0)
    opts = Options()
    off = SlipState(theta=0.4665, varphi=-2.9864, Theta=0.741, Psi=-0.9655, eta=1.98)
    q, v = to_generalized(rod, off, tip=(0.0, 0.0, opts.radius))
    q[2] -= 1e-9
    pb = contact_problem(rod, q, v, 1.7, opts)
    f = pb.force()
    assert abs(math.hypot(f[1], f[2]) - 1.7 * f[0]) < 1e-9 * f[0]  # slipping: on the cone's surface
    at = pb.J @ (pb.qacc_smooth + pb.minv * (pb.J.T @ f))
    solved = math.atan2(f[2], f[1]) - math.atan2(-pb.vel[2], -pb.vel[1])
    assert MUJOCO_LAW_SKEW_IDENTITY.ok(np.angle(np.exp(1j * solved)), skew_angle(pb.vel[1:], at[1:], pb.B[1]))
    a = fs.ablation(rod, off, 1.7)
    assert abs(a["law"]) > 0.3  # ~25 degrees, as mujoco_contact's test measures in MuJoCo
    assert (
        abs(a["neither"]) <= MUJOCO_LAW_SKEW_IDENTITY.atol
    )  # isotropic, decoupled A and no free tangential acceleration: none
    assert abs(a["isotropic"]) < 0.2 * abs(a["law"])  # the anisotropy and coupling of A carry it


def test_predicted_skew_equals_measured_and_measured_is_friction_skew():
    rng = np.random.default_rng(0)
    states, mu = fs.random_states(3, rng)
    mine = fs.measured(states, mu, duration=0.1)
    theirs = friction_skew(states, mu, duration=0.1)
    assert np.array_equal(mine["skew"], theirs["skew"], equal_nan=True)
    law = fs.predicted(states, mu, duration=0.1)
    on = np.isfinite(mine["skew"])
    assert (
        np.array_equal(on, np.isfinite(law["skew"])) and on.sum() >= 2
    )  # no force in either only where the start lifts off
    assert MUJOCO_LAW_SKEW.ok(law["skew"][on], mine["skew"][on])
    assert MUJOCO_LAW_SKEW_IDENTITY.ok(law["closed"][on], law["solved"][on])


def test_mujoco_approaches_the_continuous_law_at_first_order():
    c = convergence_order(
        Rod.scaled(3.0),
        SlipState(theta=0.8, varphi=-1.2, Theta=0.3, Psi=1.0, eta=1.0),
        0.3,
        timesteps=(2e-4, 1e-4, 5e-5),
    )
    assert MUJOCO_LAW_ORDER.ok(c["order"], 1.0)
    assert c["rms"][-1] < 1e-4  # and close: ~1e-5 l at dt = 5e-5


def test_sliding_mode_holds_the_capsule_on_the_plane_with_a_fraction_of_the_force():
    rod, opts, mu = Rod.scaled(3.0), Options(timestep=1e-2), 0.3
    q0, v0 = to_generalized(
        rod, SlipState(theta=0.8, varphi=-1.2, Theta=0.3, Psi=1.0, eta=1.0), tip=(0.0, 0.0, opts.radius)
    )
    traj = integrate(rod, q0, v0, mu, opts, times=np.arange(30) * 1e-2)
    assert traj.events == []  # it slides on dist = 0 from the start to the end
    dist = traj.q[:, 2] - np.sin(traj.q[:, 4]) - opts.radius
    assert np.abs(dist).max() < 1e-9
    # the law's own force there would push the capsule off the plane: the sliding mode applies a fraction of it
    full = np.array([accelerations(rod, q, v, mu, opts, contact=True)[1][0] for q, v in zip(traj.q, traj.v)])
    assert np.all(traj.force[:, 0] > 0) and np.all(traj.force[:, 0] < 0.2 * full)


def test_the_law_without_its_feed_forward_is_solrefs_spring_damper_on_the_normal_row():
    """feed_forward=False: the normal row at impedance d = NO_FEED_FORWARD_IMPEDANCE, the friction rows MuJoCo's.  Its normal force
    (the normal row's balance, friction aside) obeys f_n (w + d (A_nn - w)) = s - d a0_n exactly, s = -(2/tau) v_n - dist/(tau^2 zeta^2)
    the solref spring-damper: f_n = s / w up to a fraction of order d of the rigid force, where MuJoCo's own row feeds ~0.9 of it forward."""
    rng = np.random.default_rng(11)
    d = NO_FEED_FORWARD_IMPEDANCE
    for _ in range(16):
        rod, mu, opts, impratio, model, data = random_contact(rng)
        with_ff = contact_problem(rod, data.qpos, data.qvel, mu, opts, impratio=impratio)
        par = Parameters.of(rod, opts, impratio=impratio, feed_forward=False)
        pb = contact_problem(rod, data.qpos, data.qvel, mu, opts, parameters=par)
        # the friction rows and everything but the normal row's K, B, R are MuJoCo's
        assert (
            np.array_equal(pb.R[1:], with_ff.R[1:])
            and np.array_equal(pb.aref[1:], with_ff.aref[1:])
            and np.array_equal(pb.B[1:], with_ff.B[1:])
        )
        assert np.array_equal(pb.A, with_ff.A) and np.array_equal(pb.a0, with_ff.a0) and pb.imp == with_ff.imp
        w, tau, zeta = inverse_weight(rod), par.timeconst, par.dampratio
        s = -(2.0 / tau) * pb.vel[0] - pb.dist / (tau * tau * zeta * zeta)
        H, g = pb.A + np.diag(pb.R), pb.a0 - pb.aref
        fn = -g[0] / H[0, 0]
        size = abs(s) + d * abs(pb.a0[0]) + abs(fn) * (w + d * abs(pb.A[0, 0] - w))
        assert abs(fn * (w + d * (pb.A[0, 0] - w)) - (s - d * pb.a0[0])) <= CLOSED_FORM.allowance(size)
        # MuJoCo's own normal row is far from the spring alone: it carries most of the rigid force -a0_n / A_nn at once
        Hf, gf = with_ff.A + np.diag(with_ff.R), with_ff.a0 - with_ff.aref
        assert abs(-gf[0] / Hf[0, 0] - s / w) > 10 * abs(fn - s / w)


def test_bad_inputs():
    rod = Rod.scaled(3.0)
    with pytest.raises(ValueError, match="q and v must each have 5 numbers"):
        contact_force(rod, np.zeros(4), np.zeros(5), 1.0, Options())
    with pytest.raises(ValueError, match="mu"):
        contact_force(rod, np.zeros(5), np.zeros(5), -1.0, Options())
    with pytest.raises(ValueError, match="options must be crosscheck.engines.mujoco.options.Options"):
        contact_problem(rod, np.zeros(5), np.zeros(5), 1.0, {"timestep": 1e-3})
    with pytest.raises(ValueError, match="impratio"):
        contact_force(rod, np.zeros(5), np.zeros(5), 1.0, Options(), impratio=0.0)
    s = SlipState(theta=0.8, varphi=-1.2, Theta=0.3, Psi=1.0, eta=1.0)
    with pytest.raises(ValueError, match="model_file must be None"):
        get("mujoco_law").simulate(rod, s, 1.0, horizon=0.1, model_file="x.xml")
    with pytest.raises(ValueError, match="rtol"):
        get("mujoco_law").simulate(rod, s, 1.0, horizon=0.1, rtol=1.0)
    with pytest.raises(ValueError, match="unknown"):
        get("mujoco_law").simulate(rod, s, 1.0, horizon=0.1, bogus=1)
    with pytest.raises(ValueError, match="feed_forward must be True or False; got 'no'"):
        get("mujoco_law").simulate(rod, s, 1.0, horizon=0.1, feed_forward="no")


def test_hops_shrink_and_end_in_the_sliding_mode():
    # a stuck rod whose capsule starts hopping at t ~ 0.59: the hops shrink (algebraically) until the engine averages them
    rod, opts = Rod.scaled(3.0), Options()
    states, mu = fs.random_states(1, np.random.default_rng(5))
    q0, v0 = to_generalized(rod, states[0], tip=(0.0, 0.0, opts.radius))
    traj = integrate(rod, q0, v0, float(mu[0]), opts, times=np.arange(0, 2.0, 0.01))
    kinds = [k for _, k in traj.events]
    assert kinds.count("contact_end") >= 5 and "slide_start" in kinds
    last = max(t for t, k in traj.events if k == "slide_start")
    hops = [t for t, k in traj.events if k == "contact_end" and t < last]
    assert np.all(np.diff(np.diff(hops)) < 0)  # each hop shorter than the one before
    # then on the plane: the sliding mode pulls the last hop's dist' <= GRAZING_SPEED back to 0 over the time constant
    # (critically damped: an excursion <= GRAZING_SPEED tau, then (1 + t/tau) e^(-t/tau): 5e-4 of it at 10 tau)
    after = traj.t >= last + 10 * opts.timeconst
    assert after.sum() >= 10
    assert np.abs(traj.q[after, 2] - np.sin(traj.q[after, 4]) - opts.radius).max() < 1e-8


def test_delassus_operator_closed_forms_at_the_contact_point():
    # across the rod (along i) the contact point has inverse inertia (1 + alpha)/m, along the rod's horizontal projection
    # (1 + alpha (sin theta + offset/l)^2)/m with offset = r + dist/2: the anisotropy behind the skew
    for alpha, theta in ((3.0, 0.3), (1.5, 1.2)):
        rod, opts = Rod.scaled(alpha), Options()
        q, v = to_generalized(
            rod, SlipState(theta=theta, varphi=-1.0, Theta=0.2, Psi=0.5, eta=1.0), tip=(0.0, 0.0, opts.radius)
        )
        q[2] -= 1e-6
        pb = contact_problem(rod, q, v, 1.0, opts)
        off = opts.radius + pb.dist / 2
        assert MUJOCO_LAW_PIECES.ok(pb.A[1, 1], 1 + alpha * (math.sin(theta) + off) ** 2)
        assert abs(pb.A[2, 2] - (1 + alpha)) < 1e-9  # the axial inertia 1e-12 I0 enters at 1e-12 tan^2(theta)


def test_one_point_paths_give_the_array_paths_numbers_bit_for_bit():
    # impedance and the cone's direction take scalar paths in the integration's hot loop; the numbers must be the
    # general path's to the last bit (the ladder's saved results were made by it)
    from crosscheck.engines.mujoco.law import _cone_direction, impedance, smooth_accelerations

    rng = np.random.default_rng(11)
    for solimp in (
        (0.9, 0.95, 1e-3, 0.5, 2.0),
        (0.9, 0.95, 1e-3, 0.3, 1.0),
        (0.5, 0.5, 1e-3, 0.5, 2.0),
        (0.2, 0.99, 0.01, 0.7, 3.5),
    ):
        dist = np.concatenate(
            (rng.uniform(-2e-3, 2e-3, 200), -solimp[2] * rng.uniform(0, 1, 50), [0.0, -solimp[2], solimp[2]])
        )
        whole = impedance(solimp, dist)
        assert np.array_equal([float(impedance(solimp, float(d))) for d in dist], whole)
        assert np.array_equal([float(impedance(solimp, np.float64(d))) for d in dist], whole)
    for mu in (0.0, 0.3, 1.4, 2.9):
        a = rng.uniform(-7.0, 7.0, 100)
        assert np.array_equal(np.array([_cone_direction(float(x), mu) for x in a]), _cone_direction(a, mu))
    rod = Rod.scaled(3.0)
    for _ in range(20):
        q, v = rng.normal(size=5), rng.normal(size=5)
        pb = contact_problem(rod, q, v, 1.0, Options())
        assert np.array_equal(smooth_accelerations(rod, q, v), pb.qacc_smooth)


def test_the_continuous_law_run_does_not_depend_on_the_runs_before_it():
    # solve_cone keeps its sampled directions per mu: a run after runs at other mu gives the same numbers
    rod, state = Rod.scaled(3.0), SlipState(theta=0.9, varphi=-1.7, Theta=0.4, Psi=0.6, eta=1.0)
    first = get("mujoco_law").simulate(rod, state, 0.9, horizon=0.05)
    for mu in (0.2, 1.7):
        get("mujoco_law").simulate(rod, state, mu, horizon=0.05)
    again = get("mujoco_law").simulate(rod, state, 0.9, horizon=0.05)
    assert np.array_equal(first.record.force, again.record.force) and np.array_equal(
        first.record.tip_acc, again.record.tip_acc
    )
