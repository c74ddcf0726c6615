"""The PhysX engines (SAPIEN 3, CPU; TGS and PGS): the free step, the friction of each solver, the record's units, bad input.

Every check runs real PhysX.  The numbers each one allows are the module-level constants below, each with
where it comes from; PhysX computes in float32, so rounding allowances are in float32's epsilon.  Scaled units
throughout (section 2.1): on ``Rod.scaled`` m = l = g = omega = 1.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from stopped_runs import stopped_and_whole

from crosscheck import Outcome, Rod, SlipState, analytic, engines
from crosscheck.coordinates import to_generalized
from crosscheck.engines.physx import ENGINES
from crosscheck.engines.physx.engine import PhysxHealth
from crosscheck.engines.physx.model import World
from crosscheck.engines.physx.options import Options
from crosscheck.engines.record import FIELDS

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
SPECS = {s.name: s for s in ENGINES}
EPS32 = float(np.finfo(np.float32).eps)

#: The free step v1 = v0 + dt a(q0, v0) against eqs. rotode / linode2: PhysX stores v in float32, so (v1 - v0) / dt
#: carries ~eps32 |v| / dt of rounding; the allowance is 64 eps32 (1 + |v|) / dt, 7.6e-3 (1 + |v|) at omega dt = 1e-3
#: (measured: 8.9e-5 relative for TGS, 2.7e-5 for PGS over random states of a physical rod).
FREE_STEP_ROUNDING = 64.0

#: |F_t| / (mu F_n) of TGS on a slipping start, the median over its rows: measured 1 + 1.3e-7 (float32 rounding of
#: the momenta the force is read from); regression guard 1e-4.
TGS_CONE = 1e-4

#: A run of a physical rod against the same run of ``Rod.scaled`` (same scaled state, mu, options), relative to
#: 1 + max |field|, for every field but the forces and tip_acc: float32 rounds each rod's numbers differently, and
#: each step's contact row amplifies a gap rounding e into a velocity e / dt: measured 6.6e-4 over 250 steps;
#: regression guard 4e-3.  Forces and tip_acc (one step's velocity change / dt) scatter by 0.2-0.5 m g row to row
#: (``crosscheck.engines.physx.engine``'s docstring), so they are compared in their mean over the run: regression
#: guard 0.02 m g (measured below 5e-3).
SCALE_FIELDS = 4e-3
SCALE_MEAN_FORCE = 0.02

SLIPPING = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)
SLIPPING_TURNING = SlipState(theta=1.0, varphi=-1.9, Theta=0.8, Psi=0.7, eta=1.0, psi=0.6)


def test_two_solvers_are_declared_and_importing_them_does_not_import_sapien():
    assert set(SPECS) == {"physx_tgs", "physx_pgs"} and all(n in engines.names() for n in SPECS)
    for name, spec in SPECS.items():
        assert spec.libraries == ("sapien",) and spec.tags == {"rigid", "time_stepping"} and spec.stops_at_event
        assert spec.options().solver == name.removeprefix("physx_") and spec.options().contact_time == 0.0
        assert set(spec.solver_columns) <= set(PhysxHealth.__dataclass_fields__)
    code = (
        "import sys, crosscheck.engines.physx as p, crosscheck.engines.physx.options as o; o.Options(); p.ENGINES[0].label; "
        "assert 'sapien' not in sys.modules, 'sapien was imported'"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr


@pytest.mark.parametrize("solver", ["tgs", "pgs"])
def test_free_step_is_the_rods_exact_acceleration_to_float32(solver):
    """Lifted well above the plane: v1 = v0 + dt a(q0, v0) with a from eqs. rotode, linode2, on a physical rod (SI
    inside PhysX): no damping, no joint friction, no velocity clamp, and the chain's small masses (4e-7) invisible."""
    rod = Rod(mass=2.0, length=0.7, inertia=0.1, gravity=9.81)
    rng = np.random.default_rng(0)
    opts = Options(solver=solver)
    dt = opts.timestep / rod.omega
    for _ in range(6):
        s = SlipState(
            theta=rng.uniform(0.05, 1.5),
            varphi=-rng.uniform(0, 3),
            Theta=rng.normal(),
            Psi=2 * rng.normal(),
            eta=rng.uniform(0, 2),
            psi=rng.uniform(-3, 3),
        )
        q0, v0 = to_generalized(rod, s, tip=(0.0, 0.0, 0.5))
        raw = World(rod, 0.5, opts).rollout(q0, v0, 1)
        assert raw.points[0] == 0 and np.all(raw.force == 0.0)
        theta_dd, psi_dd = analytic.rotational_acceleration(rod, q0[3], q0[4], v0[3], v0[4], np.zeros(3))
        want = np.array([0.0, 0.0, -rod.gravity, psi_dd, theta_dd])
        got = (raw.v[1] - raw.v[0]) / dt
        allowance = FREE_STEP_ROUNDING * EPS32 * (1 + np.abs(v0).max()) / dt
        assert np.abs(got - want).max() <= allowance * (1 + np.abs(want).max())


def test_tgs_friction_is_on_the_cone_and_pgs_patch_friction_is_a_pyramid():
    """On a slip, TGS's friction has |F_t| = mu F_n; PGS's patch friction clips its two tangent rows each to mu F_n, so
    where both saturate (the turning start's first step) |F_t| = sqrt(2) mu F_n: a square pyramid, not the cone."""
    mu = 0.5
    tgs = SPECS["physx_tgs"].simulate(ROD, SLIPPING, mu, horizon=0.1)
    R = tgs.record
    assert np.all(R.active) and np.all(R.normal_force > 0)
    ratio = np.linalg.norm(R.force[:, :2], axis=1) / (mu * R.normal_force)
    assert abs(np.median(ratio) - 1) <= TGS_CONE
    pgs = SPECS["physx_pgs"].simulate(ROD, SLIPPING_TURNING, mu, horizon=0.1)
    F = pgs.record.force[0]
    assert F[2] > 0 and abs(np.linalg.norm(F[:2]) / (mu * F[2]) - math.sqrt(2)) <= 1e-3


@pytest.mark.parametrize("solver", ["tgs", "pgs"])
def test_scaled_units_across_physical_rods(solver):
    """t spaced by the timestep, the tip at z = r in row 0; a 1 m rod, a 1 cm rod (psi' = 125 rad/s, past PhysX's default
    joint clamp of 100 and link clamp of 50 rad/s) and a heavy short rod give the scaled rod's record, field by field."""
    spec = SPECS[f"physx_{solver}"]
    s = SlipState(theta=1.4, varphi=-2.0, Theta=0.3, Psi=4.0, eta=1.0, psi=0.3)
    base = spec.simulate(ROD, s, 0.4, horizon=0.5, radius=0.02, timestep=2e-3)
    R = base.record
    np.testing.assert_allclose(np.diff(R.t), 2e-3, rtol=1e-12, atol=0)
    assert len(R) == 250 and abs(R.gap[0]) <= 4 * EPS32 and R.active.all()
    rods = {
        "uniform_1m": Rod.uniform(1.0, 1.0),
        "uniform_1cm": Rod.uniform(0.2, 0.01),
        "heavy_short": Rod(mass=50.0, length=0.3, inertia=1.5, gravity=9.81),
    }
    for name, rod in rods.items():
        other = spec.simulate(rod, s, 0.4, horizon=0.5, radius=0.02, timestep=2e-3).record
        for f in FIELDS:
            got, want = np.asarray(getattr(other, f), float), np.asarray(getattr(R, f), float)
            if f in ("force", "normal_force", "tip_acc"):
                assert np.abs(got.mean(0) - want.mean(0)).max() <= SCALE_MEAN_FORCE, (name, f)
            else:
                assert np.abs(got - want).max() <= SCALE_FIELDS * (1 + np.abs(want).max()), (name, f)
    assert 4.0 * Rod.uniform(0.2, 0.01).omega > 100.0


@pytest.mark.parametrize(
    "options, message",
    [
        ({"timestep": 0.0}, "timestep must be in (0, inf); got 0.0"),
        ({"radius": 0.5}, "radius must be in (0, 0.5); got 0.5"),
        ({"solver": "sor"}, "solver must be one of tgs, pgs; got 'sor'"),
        ({"position_iterations": 0}, "position_iterations must be an integer in [1, 255]; got 0"),
        ({"velocity_iterations": 256}, "velocity_iterations must be an integer in [0, 255]; got 256"),
        ({"contact_offset": 0.0}, "contact_offset must be in (0, inf); got 0.0"),
        ({"bounce_threshold": 0.0}, "bounce_threshold must be in (0, 1e+30]; got 0.0"),
        ({"sleep_threshold": -1.0}, "sleep_threshold must be in [0, inf); got -1.0"),
        ({"friction_every_iteration": 1}, "friction_every_iteration must be True or False; got 1"),
        ({"static_ratio": 0.5}, "static_ratio must be in [1, 100]; got 0.5"),
        ({"patch_radius": -0.1}, "patch_radius must be in [0, inf); got -0.1"),
    ],
    ids=[
        "timestep",
        "radius",
        "solver",
        "position",
        "velocity",
        "offset",
        "bounce",
        "sleep",
        "friction",
        "static",
        "patch",
    ],
)
def test_bad_options_raise_one_line_naming_option_value_and_range(options, message):
    with pytest.raises(ValueError) as e:
        SPECS["physx_tgs"].simulate(ROD, SLIPPING, 0.5, horizon=0.1, **options)
    assert str(e.value) == message and "\n" not in str(e.value)


def test_a_rollout_stopped_once_its_first_event_is_judged_has_the_whole_runs_first_event():
    for whole, cut, _rows in stopped_and_whole(SPECS["physx_pgs"], ROD):
        assert cut.solver.contact_steps <= whole.solver.contact_steps


def test_pgs_pyramid_jams_below_mu_P_where_tgs_slips():
    """theta = 1, varphi = -1.9, Psi = 1.25 at mu = 1.25 < mu_P = 4/3 (alpha = 3): Coulomb's rod cannot jam (p > 0 for
    every state, eq. mup2D).  PGS's first step saturates both friction rows, |F_t| = sqrt(2) mu F_n = 1.77 F_n, past
    mu_P, and it jams at once (the maps' check allows it from mu_P / sqrt(2) on: ``Options.friction_excess``); TGS,
    whose friction is on the cone, keeps slipping."""
    state = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=1.25, eta=1.0)
    mu = 1.25
    pgs = SPECS["physx_pgs"].simulate(ROD, state, mu, horizon=0.3)
    F = pgs.record.force[0]
    assert abs(np.linalg.norm(F[:2]) / (mu * F[2]) - math.sqrt(2)) <= 1e-3
    assert pgs.outcome == Outcome.JAM and pgs.event_time == 0.0
    assert SPECS["physx_pgs"].options().friction_excess == math.sqrt(2)
    tgs = SPECS["physx_tgs"].simulate(ROD, state, mu, horizon=0.3)
    assert tgs.outcome == Outcome.SLIP and SPECS["physx_tgs"].options().friction_excess == 1.0
