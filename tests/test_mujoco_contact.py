"""MuJoCo against the analytic model: its contact force at the capsule point, its lift-off onset, its friction direction."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from crosscheck import Outcome, Rod, SlipState
from crosscheck.engines import Thresholds, get
from crosscheck.engines.mujoco.model import SensorLayout, build_model, initial_state, record_from_sensordata
from crosscheck.engines.mujoco.options import Options
from crosscheck.engines.mujoco.studies.contact import capsule_tip_acceleration, friction_skew
from crosscheck.engines.mujoco.tolerances import (
    MUJOCO_CONTACT_ACCELERATION,
    MUJOCO_DJV_KAPPA,
    MUJOCO_LIFTOFF_ONSET,
    MUJOCO_LIFTOFF_ONSET_COARSE,
)
from crosscheck.theory import analytic as an
from crosscheck.theory.critical import Psi_L, Psi_on_b0, theta_L

ROD = Rod(mass=1.0, length=1.0, inertia=1.0 / 3.0, gravity=9.81)
MS = 1e-3 * ROD.omega  # 1 ms in scaled time
DT = Options().timestep  # the default, 3e-4 (~0.1 ms)
sweep = get("mujoco").sweep


def _contact_rows(radius: float, n: int, seed: int):
    """MuJoCo's force, tip acceleration and state at n random slipping states, contact active (1e-4 l deep)."""
    model = build_model(ROD, 0.8, Options(radius=radius, solver_tolerance=0.0))
    data = mujoco.MjData(model)
    layout = SensorLayout.from_model(model)
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(n):
        s = SlipState(
            theta=rng.uniform(0.1, 1.45),
            varphi=-rng.uniform(0.05, 3.1),
            Theta=0.7 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.2, 3),
            psi=rng.uniform(-3, 3),
        )
        mujoco.mj_setState(model, data, initial_state(model, ROD, s, radius), mujoco.mjtState.mjSTATE_FULLPHYSICS)
        data.qpos[2] -= 1e-4 * ROD.length
        mujoco.mj_forward(model, data)
        rec = record_from_sensordata(data.sensordata, layout, ROD, radius)
        rows.append(
            (
                rec.force * ROD.force_scale,
                rec.tip_acc * ROD.gravity,
                data.qpos[3:].copy(),
                data.qvel[3:].copy(),
                data.sensordata[layout.dist],
            )
        )
    F, a, q, v, dist = (np.array(x) for x in zip(*rows))
    assert np.all(np.abs(F[:, 2]) > 0)  # every row has a contact force
    return F, a, q, v, dist


def _scale(F):
    return ROD.gravity * (1 + ROD.alpha * np.abs(F).sum(axis=-1) / ROD.force_scale)


def test_contact_tip_acceleration_is_linode2_at_the_contact_point():
    """With MuJoCo's own contact force applied a radius below A, eq. linode2 gives MuJoCo's tip acceleration."""
    radius = 0.02
    F, a, q, v, dist = _contact_rows(radius, 100, seed=2)
    want = capsule_tip_acceleration(ROD, q[:, 0], q[:, 1], v[:, 0], v[:, 1], F, radius * ROD.length + dist / 2)
    err = np.abs(a - want).max(axis=1) / _scale(F)
    assert np.all(err <= MUJOCO_CONTACT_ACCELERATION.atol), err.max()


def test_plain_linode2_converges_linearly_as_radius_goes_to_zero():
    """Uncorrected eq. linode2 (force at A) misses by O(r): measured rate 1 over r = 0.04 .. 0.005."""
    radii = np.array([0.04, 0.02, 0.01, 0.005])
    errs = []
    for r in radii:
        F, a, q, v, _ = _contact_rows(r, 40, seed=3)
        plain = an.tip_acceleration(ROD, q[:, 0], q[:, 1], v[:, 0], v[:, 1], F)
        errs.append(np.median(np.abs(a - plain).max(axis=1) / _scale(F)))
    rate = np.polyfit(np.log(radii), np.log(errs), 1)[0]
    assert rate == pytest.approx(1.0, abs=0.05)
    assert errs[-1] < 0.5 * radii[-1]  # and the constant is below 1/2 (0.27 measured)


def _onset_psi(theta, Theta, mu, timestep, lo, hi, rounds=5, n=33):
    """Smallest Psi (bisection on a grid) at which MuJoCo's outcome is LIFTOFF at t = 0."""
    for _ in range(rounds):
        Ps = np.linspace(lo, hi, n)
        states = [SlipState(theta=theta, varphi=-math.pi / 2, Theta=Theta, Psi=P, eta=1.0) for P in Ps]
        r = sweep(ROD, states, mu, horizon=0.03, timestep=timestep, progress=False)
        lift = (r.outcome == Outcome.LIFTOFF) & (r.event_time == 0.0)
        assert not lift[0] and lift[-1], (theta, Theta, mu, lo, hi)
        k = int(np.argmax(lift))
        assert lift[k:].all()  # one threshold, no islands
        lo, hi = Ps[k - 1], Ps[k]
    return hi, hi - lo


@pytest.mark.parametrize("mu", [0.3, 1.0, 2.0], ids=lambda m: f"mu={m}")
@pytest.mark.parametrize(
    "timestep, tol", [(DT, MUJOCO_LIFTOFF_ONSET), (MS, MUJOCO_LIFTOFF_ONSET_COARSE)], ids=["dt=default", "dt=1ms"]
)
def test_liftoff_onset_is_Psi_L(mu, timestep, tol):
    """At theta_L, Theta = 0, varphi = -pi/2 MuJoCo lifts off from Psi_L on (eq. psil)."""
    psi, res = _onset_psi(theta_L, 0.0, mu, timestep, Psi_L - 1e-3, Psi_L + 1e-3)
    assert -res <= psi - Psi_L <= tol.atol + res


@pytest.mark.parametrize("theta", [0.3, 0.9, 1.2], ids=lambda t: f"theta={t}")
def test_liftoff_boundary_follows_b_zero(theta):
    """Across theta (Theta = 0) the onset is where b = 0 (eqs. psi1/psi2's Psi(theta)).

    Tolerance derived from the timestep: b(t) = b0 + b''(0) t^2 / 2 along the free flight, and
    LIFTOFF needs b > 0 on lift_steps rows, so the onset may sit up to
    max(0, -b''/2) (lift_steps dt)^2 / (db/dPsi) above b = 0.
    """
    dt = DT
    Pb = float(Psi_on_b0(theta))
    s, c = math.sin(theta), math.cos(theta)
    c2 = -(Pb**2) * s * c  # Theta' on the free flight (Appendix A, c2)
    bdd = Pb**2 * c * (c * c - 2 * s * s) * c2 + 2 * s * c2**2 + 4 * Pb**2 * c * c * s * math.tan(theta) * c2
    tol = max(0.0, -bdd / 2) * (Thresholds().lift_steps * dt) ** 2 / (2 * Pb * c * c * s)
    psi, res = _onset_psi(theta, 0.0, 0.5, dt, Pb - 1e-2, Pb + 1e-2)
    assert -res <= psi - Pb <= tol + res


def _kappa(theta, Theta, Psi):
    s, c = math.sin(theta), math.cos(theta)
    b = (Psi**2 * c * c + Theta**2) * s - 1
    return b / (Theta**2 * s)


@pytest.mark.parametrize("Theta", [-1.0, 0.5], ids=lambda t: f"Theta={t}")
def test_liftoff_onset_with_Theta_shifts_by_half_dJv(Theta):
    """Started with the contact inactive, MuJoCo lifts off where b = Theta^2 sin(theta) / 2, not b = 0.

    The semi-implicit Euler step q1 = q0 + dt (v0 + dt qacc) moves the tip's height by
    dt^2 (J qacc + dJv / 2) = dt^2 (b - Theta^2 sin / 2): half the dJ v term is missing.
    """
    Pb = math.sqrt((1 / math.sin(theta_L) - Theta**2) / math.cos(theta_L) ** 2)
    psi, _ = _onset_psi(theta_L, Theta, 0.5, DT, Pb, 1.5 * Pb, rounds=4)
    assert MUJOCO_DJV_KAPPA.ok(_kappa(theta_L, Theta, psi), 0.5)


def test_active_contact_decision_misses_dJv():
    """With the contact active (mu = 0), MuJoCo's constraint sees b - Theta^2 sin(theta): the whole dJ v term is missing."""
    model = build_model(ROD, 0.0, Options())
    data = mujoco.MjData(model)
    layout = SensorLayout.from_model(model)

    def pushes(Theta, Psi):
        s = SlipState(theta=theta_L, varphi=-math.pi / 2, Theta=Theta, Psi=Psi, eta=0.0)
        mujoco.mj_setState(model, data, initial_state(model, ROD, s, 0.01), mujoco.mjtState.mjSTATE_FULLPHYSICS)
        data.qpos[2] -= 1e-9 * ROD.length
        mujoco.mj_forward(model, data)
        return data.sensordata[layout.force.start] > 0

    def onset(Theta):
        lo, hi = 0.0, 5.0
        for _ in range(50):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if pushes(Theta, mid) else (lo, mid)
        return hi

    s, c = math.sin(theta_L), math.cos(theta_L)
    b_offset = (onset(0.0) ** 2) * c * c * s - 1  # the penetration's reference acceleration, same for every Theta
    for Theta in (-1.0, 0.5, 1.0):
        P = onset(Theta)
        b = (P**2 * c * c + Theta**2) * s - 1
        assert MUJOCO_DJV_KAPPA.ok((b - b_offset) / (Theta**2 * s), 1.0)


def test_friction_skew_vanishes_on_the_plane_and_explains_the_force_off_it():
    planar = SlipState(theta=0.6, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0)
    off = SlipState(theta=0.4665, varphi=-2.9864, Theta=0.741, Psi=-0.9655, eta=1.98)
    r = friction_skew([planar, off], [1.0, 1.7], duration=0.1)
    assert abs(r["skew"][0]) < 1e-9  # symmetry: friction stays in the rod's vertical plane
    assert abs(r["p_eff"][0] - r["p"][0]) < 1e-9
    assert abs(r["skew"][1]) > 0.3  # ~25 degrees off -slip
    assert np.all(np.abs(r["saturation"] - 1.0) < 1e-3)  # still on the cone's surface: slipping
    # MuJoCo's mean normal force is what slipping with ITS friction direction needs (-b/p_eff), not -b/p
    assert abs(r["force"][1] - r["rigid_force_eff"][1]) < 0.5 * abs(r["force"][1] - r["rigid_force"][1])
