"""The rigid engine's batched closed-form stepper against Pinocchio's terms and its PGS stepper, step by step and by outcome."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from crosscheck import Rod, SlipState
from crosscheck.coordinates import to_generalized
from crosscheck.engines import get
from crosscheck.engines.pinocchio import closed_form as cf
from crosscheck.engines.pinocchio import ncp
from crosscheck.engines.pinocchio.batch import BatchStepper
from crosscheck.engines.pinocchio.model import TIP_FRAME, build_model
from crosscheck.engines.pinocchio.stepper import Options, Stepper
from crosscheck.engines.pinocchio.tolerances import PIN_MATRICES, PIN_THROUGH_MINV, RIGID_BATCH_STEP
from crosscheck.theory import analytic
from crosscheck.theory.corollary import corollary_states

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
ENGINE = get("pinocchio")
LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def _random_qv(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    q = np.column_stack([rng.normal(size=(n, 3)), rng.uniform(-math.pi, math.pi, n), rng.uniform(0.05, 1.5, n)])
    return q, 3.0 * rng.normal(size=(n, 5))


def test_closed_form_terms_are_pinocchios():
    """Tip position, velocity J v, dJ v, G, v_free and M^-1 J^T lambda against Pinocchio at seeded random states (physical units).

    Allowances: PIN_MATRICES (~45 eps of the term's scale) for what does not go through M^-1; PIN_THROUGH_MINV times
    cond(M) = 1/cos^2 theta for G and M^-1 J^T lambda, whose Pinocchio values carry that rounding (model.py)."""
    rng = np.random.default_rng(11)
    q, v = _random_qv(rng, 64)
    lam = rng.normal(size=(64, 3))
    dt = 1e-3
    A = cf.angles(q)
    T = cf.tip_terms(ROD, q, v, A)
    vf, dv = cf.free_velocity(ROD, q, v, dt, A), cf.velocity_change(ROD, q, lam, A)
    vel = cf.jacobian_times(ROD, A, v)
    model = build_model(ROD)
    data = model.createData()
    tip = model.getFrameId(TIP_FRAME)
    for i in range(len(q)):
        a = pin.aba(model, data, q[i], v[i], np.zeros(5))
        pin.forwardKinematics(model, data, q[i], v[i], np.zeros(5))
        pin.updateFramePlacement(model, data, tip)
        J = pin.computeFrameJacobian(model, data, q[i], tip, LWA)[:3]
        M = pin.crba(model, data, q[i])
        M = np.triu(M) + np.triu(M, 1).T
        kappa = 1.0 / math.cos(q[i, 4]) ** 2
        scale = 1.0 + np.abs(v[i]).sum()
        plain = {
            "pos": (data.oMf[tip].translation, T.pos[i], 1.0 + np.abs(q[i]).sum()),
            "vel": (pin.getFrameVelocity(model, data, tip, LWA).linear, vel[i], scale),
            "dJv": (pin.getFrameClassicalAcceleration(model, data, tip, LWA).linear, T.dJv[i], scale**2),
            "v_free": (v[i] + dt * a, vf[i], scale**2),
        }
        for name, (want, got, s) in plain.items():
            assert np.abs(got - want).max() <= PIN_MATRICES.atol * s, (name, i)
        through = {
            "G": (J @ np.linalg.solve(M, J.T), T.G[i], 1.0 + ALPHA),
            "M^-1 J^T lambda": (np.linalg.solve(M, J.T @ lam[i]), dv[i], (1.0 + ALPHA) * (1.0 + np.abs(lam[i]).sum())),
        }
        for name, (want, got, s) in through.items():
            assert np.abs(got - want).max() <= PIN_THROUGH_MINV.atol * kappa * s, (name, i)


def test_the_closed_form_solution_satisfies_the_ncp_on_random_problems():
    """Where ``ncp.solve`` answers: lambda in the cone, u+ = u + G lambda with u+_n >= 0 and lambda_n u+_n = 0, and a
    slip's friction opposite the end-of-step slip at the cone's edge; a stick has u+ = 0.  Rounding: ~100 eps of |u|."""
    rng = np.random.default_rng(5)
    q, _ = _random_qv(rng, 2000)
    G = cf.tip_terms(ROD, q, np.zeros_like(q)).G
    u = rng.normal(size=(2000, 3)) - np.array([0.0, 0.0, 0.3])
    mu = rng.choice([0.0, 0.3, 1.0, 2.5, 6.0], 2000)
    lam, solved, kind = ncp.solve(G, u, mu)
    assert solved.mean() > 0.98  # several solutions are the exception, even for these random problems
    lam, u, G, mu, kind = lam[solved], u[solved], G[solved], mu[solved], kind[solved]
    up = u + np.einsum("pij,pj->pi", G, lam)
    tol = 1e-13 * (1.0 + np.abs(u).sum(axis=1))
    lt = np.hypot(lam[:, 0], lam[:, 1])
    assert np.all(lam[:, 2] >= 0) and np.all(lt <= mu * lam[:, 2] * (1 + 1e-12) + 1e-300)
    assert np.all(up[:, 2] >= -tol)
    assert np.all(np.abs(lam[:, 2] * up[:, 2]) <= tol * (1 + lam[:, 2]))
    assert np.all(lam[kind == 0] == 0) and np.all(u[kind == 0, 2] >= 0)
    stick = kind == 1
    assert np.all(np.abs(up[stick]).max(axis=1) <= tol[stick])
    slip = (kind == 2) & (mu > 0)
    ut = np.hypot(up[slip, 0], up[slip, 1])
    assert np.all(np.abs(lt[slip] - mu[slip] * lam[slip, 2]) <= 1e-12 * lt[slip])
    cos = -(lam[slip, 0] * up[slip, 0] + lam[slip, 1] * up[slip, 1]) / (lt[slip] * ut)
    assert np.all(cos >= 1 - 1e-9)


def _starts():
    """(name, state, mu, steps, timestep): a slip, a lift-off (b > 0), a slip that stops and sticks, and jams (Corollary 4.2)."""
    slip = SlipState(theta=0.6, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.0)
    liftoff = SlipState(theta=0.5, varphi=-math.pi / 2, Theta=0.0, Psi=2.5, eta=1.0)
    stick = SlipState(theta=0.8, varphi=-2.0, Theta=0.0, Psi=0.0, eta=0.05)
    jams, t_jam, _ = corollary_states(1.7, 2, np.random.default_rng(0))
    out = [("slip", slip, 0.5, 300, 1e-3), ("liftoff", liftoff, 0.5, 100, 1e-3), ("stick", stick, 1.0, 300, 1e-3)]
    out += [(f"jam{i}", s, 1.7, int((t + 0.05) / 3e-3), 3e-3) for i, (s, t) in enumerate(zip(jams, t_jam))]
    return out


STARTS = _starts()


@pytest.mark.parametrize("name, state, mu, steps, dt", STARTS, ids=[s[0] for s in STARTS])
def test_each_step_is_pgs_step(name, state, mu, steps, dt):
    """From each state of the PGS engine's trajectory, one batched step and one PGS step: the same impulse and velocity
    (``RIGID_BATCH_STEP``) wherever PGS met its tolerance; the steps handed to PGS are PGS's own."""
    opts = Options(timestep=dt)
    pgs, batch = Stepper(ROD, mu, opts), BatchStepper(ROD, np.array([mu]), opts)
    q, v = to_generalized(ROD, state)
    row = np.empty((1, 20))
    scale = ROD.force_scale * pgs.dt  # m g dt: a slipping step's impulse is O(1) of it
    seen, n_handed = set(), 0
    for _ in range(steps):
        q1, v1, info = pgs.step(q, v)
        bq, bv = batch.step(q[None], v[None], row)
        handed = row[0, 17] > 0
        n_handed += handed
        if info.converged:
            dlam = np.abs(row[0, 9:12] - info.impulse).max() / max(scale, np.abs(info.impulse).max())
            dv = np.abs(bv[0] - v1).max() / (
                1.0 + np.abs(v1).max()
            )  # relative to the velocity's size (units of l omega ~ 1)
            assert dlam <= RIGID_BATCH_STEP.rtol and dv <= RIGID_BATCH_STEP.rtol, (name, dlam, dv)
        if handed:
            assert np.array_equal(row[0, 9:12], info.impulse) and np.array_equal(bv[0], v1)
        lam = info.impulse
        seen.add(
            "free"
            if not info.active
            else "none"
            if lam[2] == 0
            else "handed"
            if handed
            else "stick"
            if math.hypot(lam[0], lam[1]) < mu * lam[2] * (1 - 1e-6)
            else "slip"
        )
        q, v = q1, v1
    # each start exercises what it is named for
    want = {"slip": {"slip"}, "liftoff": {"none", "free"}, "stick": {"slip", "stick"}}.get(name, {"slip"})
    assert want <= seen, seen
    if name == "liftoff":
        assert analytic.b(state.Psi, state.Theta, state.theta) > 0
    # below mu_P the closed form decides every step (one solution); at a jam PGS decides the steps with several
    assert n_handed <= {"slip": 0, "liftoff": 0, "stick": 2}.get(name, steps), n_handed
    if name.startswith("jam"):
        assert n_handed > 0


def test_jams_are_handed_to_pgs_and_keep_its_outcome():
    """At a jam the step's NCP has the stick and a slip (or none but the stick): the batch hands those steps to PGS,
    and the sweep gives the PGS engine's outcome and event time."""
    states, t_jam, _ = corollary_states(1.7, 4, np.random.default_rng(1))
    a = ENGINE.sweep(ROD, states, 1.7, horizon=float(t_jam.max()) + 0.1, timestep=1e-3, solver="closed_form", workers=1)
    b = ENGINE.sweep(ROD, states, 1.7, horizon=float(t_jam.max()) + 0.1, timestep=1e-3, solver="pgs", workers=1)
    assert np.array_equal(a.outcome, b.outcome)
    np.testing.assert_array_equal(a.event_time, b.event_time)
    assert a.solver["max_iterations"].max() > 0  # some step went to PGS


def test_outcomes_over_random_states_are_pgs_outcomes():
    """A seeded random set across mu_P (mu in [0.1, 3]): every outcome and event time equal to the PGS engine's (event
    times are row times, so equal means the same row)."""
    rng = np.random.default_rng(2024)
    states = [
        SlipState(
            theta=rng.uniform(0.2, 1.3),
            varphi=-rng.uniform(0.1, 3.0),
            Theta=0.7 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.2, 3),
        )
        for _ in range(24)
    ]
    mu = rng.uniform(0.1, 3.0, 24)
    a = ENGINE.sweep(ROD, states, mu, horizon=1.0, timestep=3e-3, solver="closed_form", workers=1)
    b = ENGINE.sweep(ROD, states, mu, horizon=1.0, timestep=3e-3, solver="pgs", workers=1)
    np.testing.assert_array_equal(a.outcome, b.outcome)
    np.testing.assert_array_equal(a.event_time, b.event_time)
    assert len(set(a.outcome.tolist())) >= 3  # the set reaches several outcomes, not only slips


def test_simulate_is_a_batch_of_one():
    """``simulate`` with the closed form steps one state through the same code as a sweep: the same record rows."""
    s = SlipState(theta=0.6, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.0)
    run = ENGINE.simulate(ROD, s, 0.5, horizon=0.3, solver="closed_form")
    sw = ENGINE.sweep(
        ROD,
        [s, SlipState(theta=1.0, varphi=-2.0, Theta=0.0, Psi=1.0, eta=0.5)],
        0.5,
        horizon=0.3,
        solver="closed_form",
        workers=1,
    )
    assert run.outcome == sw.outcome[0] and run.solver.contact_steps == sw.solver["contact_steps"][0]
    pgs = ENGINE.simulate(ROD, s, 0.5, horizon=0.3, solver="pgs")
    np.testing.assert_allclose(run.record.theta, pgs.record.theta, rtol=0, atol=1e-12)
    np.testing.assert_allclose(run.record.normal_force, pgs.record.normal_force, rtol=RIGID_BATCH_STEP.rtol, atol=0)


def test_auto_steps_every_sweep_in_closed_form_whatever_its_size_and_single_runs_with_pgs():
    """The default solver: every sweep is stepped in closed form (0 PGS iterations below mu_P, where every step's NCP has one
    solution), so a state's outcome does not depend on the states swept with it: the first two of 16 states alone give the
    same outcomes, times and rows' solver counts; ``simulate`` goes through PGS (>= 1 iteration per contact step)."""
    rng = np.random.default_rng(3)
    states = [
        SlipState(
            theta=rng.uniform(0.3, 1.2),
            varphi=-rng.uniform(0.5, 2.5),
            Theta=0.3 * rng.normal(),
            Psi=0.5 * rng.normal(),
            eta=rng.uniform(0.5, 2),
        )
        for _ in range(16)
    ]
    assert Options().solver == "auto"
    big = ENGINE.sweep(ROD, states, 0.5, horizon=0.1, workers=1)
    assert (
        big.options.solver == "auto"
        and np.all(big.solver["max_iterations"] == 0)
        and np.all(big.solver["contact_steps"] > 0)
    )
    small = ENGINE.sweep(ROD, states[:2], 0.5, horizon=0.1, workers=1)
    assert np.all(small.solver["max_iterations"] == 0)
    np.testing.assert_array_equal(small.outcome, big.outcome[:2])
    np.testing.assert_array_equal(small.event_time, big.event_time[:2])
    np.testing.assert_array_equal(small.solver["contact_steps"], big.solver["contact_steps"][:2])
    assert ENGINE.simulate(ROD, states[0], 0.5, horizon=0.1).solver.max_iterations >= 1


@pytest.mark.parametrize("half_gap", [0.25, 0.45, 0.75], ids=lambda x: f"roots {2 * x:g} cells apart")
def test_two_roots_in_one_grid_cell_are_not_lost(half_gap):
    """h = cos(phi - phi0) - cos(eps) has the roots phi0 +- eps; centred in a grid cell with eps below half a cell,
    no end of the cell sees a sign change: the problem must be flagged (handed to PGS), otherwise both roots found."""
    delta = 2 * math.pi / ncp.GRID
    phi0, eps = (10 + 0.5) * delta, half_gap * delta
    coef = np.zeros((1, 3, 5))
    coef[0, 0, :3] = -math.cos(eps), math.cos(phi0), math.sin(phi0)
    coef[0, 1:, 0] = 1.0  # D and a D positive everywhere: every root is a candidate
    row, phi, hidden = ncp._roots(coef)
    if eps < delta / 2:
        assert hidden[0]
    else:
        assert not hidden[0] and np.allclose(np.sort(phi), [phi0 - eps, phi0 + eps], rtol=0, atol=1e-12)


def test_agreement_cuts_the_rigid_engines_store_in_its_own_chunks_and_a_rerun_resumes(tmp_path, monkeypatch):
    """The rigid engine declares ``sweep_chunk`` (one closed-form batch per chunk): a study's sweep store is cut in chunks of
    that many runs, the manifest and the spec's doc say so, every chunk but the last is full, and a rerun computes nothing.
    Another chunk size is another sweep: the study writes a store of its own beside the old one (never resumed into),
    and the sweep itself refuses the old store's directory in one ValueError line."""
    import json

    from crosscheck import sweeps
    from crosscheck.studies import agreement_store
    from crosscheck.studies.agreement import agreement_study
    from crosscheck.studies.agreement_store import STORE_CHUNK, store_chunk
    from crosscheck.studies.grids import random_event_points

    monkeypatch.setattr(agreement_store, "HORIZON_HALVINGS", 0)  # every state to the horizon: one sweep, one store
    chunk = ENGINE.sweep_chunk
    assert store_chunk(ENGINE) == chunk and chunk != STORE_CHUNK and store_chunk(get("mujoco")) == STORE_CHUNK
    points = random_event_points(chunk + 40, np.random.default_rng(5))
    kw = dict(engine="pinocchio", boundary_directions=0, horizon=0.05, store=tmp_path, workers=1)
    run = agreement_study(points, **kw).runs[0]
    (store,) = [p for p in tmp_path.iterdir() if p.is_dir()]
    manifest = json.loads((store / "manifest.json").read_text())
    assert manifest["chunk"] == chunk and manifest["n_runs"] == len(run.outcome) > chunk
    assert manifest["n_chunks"] == math.ceil(len(run.outcome) / chunk) == 2
    table = sweeps.load(store)
    assert table["chunk"].value_counts().to_dict() == {0: chunk, 1: len(run.outcome) - chunk}
    stamps = {p: p.stat().st_mtime_ns for p in (store / "chunks").iterdir()}
    again = agreement_study(points, **kw).runs[0]
    assert {p: p.stat().st_mtime_ns for p in (store / "chunks").iterdir()} == stamps
    np.testing.assert_array_equal(again.outcome, run.outcome)

    monkeypatch.setattr(agreement_store, "store_chunk", lambda E: chunk // 2)
    halves = agreement_study(points, **kw).runs[0]
    (other,) = [p for p in tmp_path.iterdir() if p.is_dir() and p != store]
    assert json.loads((other / "manifest.json").read_text())["chunk"] == chunk // 2
    assert {p: p.stat().st_mtime_ns for p in (store / "chunks").iterdir()} == stamps
    np.testing.assert_array_equal(halves.outcome, run.outcome)  # every chunk in the same closed form
    doc = json.loads((other / "manifest.json").read_text())["spec"]
    with pytest.raises(
        ValueError,
        match=r"^out .* holds a different sweep \(spec sha256 [0-9a-f]{12}, this one [0-9a-f]{12}\); use --fresh",
    ):
        sweeps.run(sweeps.parse_spec(doc), store, workers=1, progress=False)


def test_sweep_chunk_out_of_range_is_one_line_naming_it():
    from crosscheck.engines.spec import Execution

    for bad in (0, 2.5, True, "128"):
        with pytest.raises(ValueError, match=r"^sweep_chunk must be an integer in \[1, 1000000\] or None; got "):
            Execution(sweep_chunk=bad)
