"""The thin SI adapter (``crosscheck.engines.adapter``): its coordinates, its conversion, and its one-line refusals.

Identities over seeded random states (a free body's pose and twist against the chain's), the shared conversion
against the paper's quantities it must reproduce (tip velocity, slip at C), and the example plugin's engine
(``examples/engine_plugin``, imported from its source folder here; tests/test_engine_plugin.py installs it) against
the rigid slipping force -b/p it must approach on a slipping start.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from crosscheck import Rod, SlipState
from crosscheck.coordinates import tip_position, tip_velocity, to_generalized
from crosscheck.engines import adapter

ROOT = Path(__file__).resolve().parents[1]


def _random_chain(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    q = np.column_stack((rng.normal(size=(n, 3)), rng.uniform(-np.pi, np.pi, n), rng.uniform(-1.4, 1.4, n)))
    return q, rng.normal(size=(n, 5))


def test_a_free_body_pose_and_twist_are_the_chain_state_and_back():
    q, v = _random_chain(np.random.default_rng(41), 200)
    pose, twist = adapter.free_from_chain(q, v)
    assert np.allclose(np.linalg.norm(pose[:, 3:], axis=1), 1.0, rtol=0, atol=1e-15)
    q2, v2 = adapter.chain_from_free(pose, twist)
    # psi wraps to (-pi, pi]: compare it on the circle; everything else to rounding
    np.testing.assert_allclose(np.angle(np.exp(1j * (q2[:, 3] - q[:, 3]))), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.delete(q2, 3, axis=1), np.delete(q, 3, axis=1), rtol=0, atol=1e-12)
    np.testing.assert_allclose(v2, v, rtol=0, atol=1e-12)


def test_the_quaternion_puts_the_tip_where_the_chain_does_and_a_spin_about_the_axis_is_dropped():
    rod = Rod(mass=2.0, length=0.7, inertia=0.2, gravity=9.81)
    q, v = _random_chain(np.random.default_rng(42), 50)
    pose, twist = adapter.free_from_chain(q, v)
    w_, x_, y_, z_ = pose[:, 3:].T
    # R e_y of the quaternion, times -l: A - S
    axis = np.column_stack((2 * (x_ * y_ - w_ * z_), 1 - 2 * (x_ * x_ + z_ * z_), 2 * (y_ * z_ + w_ * x_)))
    np.testing.assert_allclose(pose[:, :3] - rod.length * axis, tip_position(rod, q), rtol=0, atol=1e-14)
    spun = twist.copy()
    spun[:, 3:] += 0.7 * axis  # a spin about the rod's own axis: no chain coordinate moves
    _, v2 = adapter.chain_from_free(pose, spun)
    np.testing.assert_allclose(v2, v, rtol=0, atol=1e-12)


def test_record_from_chain_gives_the_papers_slip_and_the_difference_of_the_tip_velocity():
    rod = Rod(mass=2.0, length=0.7, inertia=0.2, gravity=9.81)
    state = SlipState(theta=0.8, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.5, psi=0.4)
    q0, v0 = to_generalized(rod, state, tip=(0.0, 0.0, 0.01))
    dt = 1e-3 / rod.omega
    q = np.stack([q0 + k * dt * v0 for k in range(4)])  # a free drift: the velocity is constant
    v = np.stack([v0] * 4)
    rec = adapter.record_from_chain(rod, q, v, np.zeros((3, 3)), np.zeros(3, bool), timestep=1e-3, radius=0.01)
    # row 0 is the state: tip at z = r, its scaled slip at C = A - r K the state's (eta, varphi) up to r Theta
    assert rec.tip_pos[0, 2] == pytest.approx(0.01, abs=1e-15) and rec.gap[0] == pytest.approx(0.0, abs=1e-15)
    u = tip_velocity(rod, q[:3], v[:3]) / (rod.length * rod.omega)
    np.testing.assert_array_equal(rec.tip_vel, u)
    np.testing.assert_allclose(rec.slip_vel[0, :2] - u[0, :2], 0.01 * 0.3 * np.array([-np.sin(0.4), np.cos(0.4)]))
    np.testing.assert_allclose(rec.t, [0.0, 1e-3, 2e-3], rtol=0, atol=1e-18)


def test_an_engine_returning_a_wrong_shape_is_refused_in_one_line():
    def run(p):
        return adapter.Rows(
            q=np.zeros((p.steps, 5)),
            v=np.zeros((p.steps, 5)),
            force=np.zeros((p.steps, 3)),
            point=np.zeros((p.steps, 3)),
        )

    eng = adapter.Adapted(name="short", run=run)
    state = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)
    with pytest.raises(ValueError, match=r"^engine 'short' returned q of shape \(10, 5\); it must be \(11, 5\)$"):
        eng.simulate(Rod.scaled(3.0), state, 0.5, horizon=1e-2)


def test_the_example_penalty_rod_carries_the_rigid_slipping_force():
    """On a slipping start (b < 0 < p), the penalty rod's normal force settles on the rigid -b/p of its own states.

    At the tip (radius 0) and after the spring's damped transient (10 contact times 1/sqrt(k) = 0.1), what is left is
    the first-order step's O(dt) error: tolerance 2 dt = 2e-3 relative (measured 8e-4).  With the default capsule
    (r = 0.01) the force moves by O(r) (measured 0.66 %): the theory's contact is at the tip.
    """
    sys.path.insert(0, str(ROOT / "examples" / "engine_plugin" / "src"))
    try:
        from numpy_rod.engine import ENGINE
    finally:
        sys.path.pop(0)
    rod = Rod.scaled(3.0)
    state = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)
    r = ENGINE.simulate(rod, state, 0.5, horizon=0.5, radius=0.0).record
    late = slice(100, None)
    want = -r.b[late] / r.p(0.5, rod.alpha)[late]
    np.testing.assert_allclose(r.normal_force[late], want, rtol=2e-3)
