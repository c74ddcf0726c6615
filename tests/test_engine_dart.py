"""The DART engine (dartpy): the free step, its pyramid friction, the record's units across rods, bad input.

Every check runs real DART.  The numbers each one allows are the module-level constants below, each with
where it comes from.  Scaled units throughout (section 2.1): on ``Rod.scaled`` m = l = g = omega = 1.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from crosscheck import Rod, SlipState, analytic, engines
from crosscheck.coordinates import to_generalized
from crosscheck.engines.dart import ENGINES
from crosscheck.engines.dart.engine import DartHealth
from crosscheck.engines.dart.model import World
from crosscheck.engines.dart.options import Options
from crosscheck.engines.record import FIELDS

ROD = Rod.scaled(3.0)
SPEC = ENGINES[0]
EPS = np.finfo(float).eps

#: The free step against eqs. rotode / linode2: (v1 - v0) / dt loses the digits of v, ~eps |v| / dt; allowance
#: 64 eps (1 + |v|) / dt, as Bullet's.  The chain's small masses (1e-12) are below it.
FREE_STEP_ROUNDING = 64.0


#: A run of a physical rod against the same run of ``Rod.scaled``, relative to 1 + max |field|: every field but
#: tip_acc agrees to ~1e-13; tip_acc is a difference quotient carrying eps |v| / dt: measured 3e-12 over 250 steps
#: on rods of 1 m, 10 cm and a heavy 30 cm one; regression guard 1e-9.  A 1 cm rod (capsule radius 0.2 mm) is
#: not the same run: its tip_acc departs by 0.66 g (DART's Bullet collision detection keeps tolerances in metres),
#: so the test stops at 10 cm.
SCALE_INVARIANCE = 1e-9

SLIPPING = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)


def test_declared_and_importing_it_does_not_import_dartpy():
    assert SPEC.name == "dart" and "dart" in engines.names() and SPEC.libraries == ("dartpy",)
    assert SPEC.tags == {"rigid", "time_stepping"} and SPEC.stops_at_event and SPEC.options().contact_time == 0.0
    assert set(SPEC.solver_columns) <= set(DartHealth.__dataclass_fields__)
    code = (
        "import sys, crosscheck.engines.dart as d, crosscheck.engines.dart.options as o; o.Options(); d.ENGINES[0].label; "
        "assert 'dartpy' not in sys.modules, 'dartpy was imported'"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr


def test_free_step_is_the_rods_exact_acceleration():
    """Lifted above the plane, a physical rod: v1 = v0 + dt a(q0, v0) with a from eqs. rotode, linode2."""
    rod = Rod(mass=2.0, length=0.7, inertia=0.1, gravity=9.81)
    rng = np.random.default_rng(0)
    opts = Options()
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
        allowance = FREE_STEP_ROUNDING * EPS * (1 + np.abs(v0).max()) / dt
        assert np.abs(got - want).max() <= allowance * (1 + np.abs(want).max())


#: A friction row's force against mu times the frictionless normal force of the same step: DART's boxed LCP (ODE's
#: Dantzig solver with friction indices) sets each friction row's bound from the normal impulse solved before the
#: friction rows enter, and does not update it; measured equal to 1e-5 relative at mu 0.2-2 (the rounding of a
#: solve whose rows are ~1e-3 m g s at dt = 1e-3); allowance 1e-4.
FROZEN_BOUND = 1e-4


@pytest.mark.parametrize("mu", [0.5, 2.0])
def test_friction_rows_are_boxed_by_mu_times_the_frictionless_normal_force(mu):
    """On a slip along world y (varphi = -pi/2, psi = 0: one row saturates), |F_y| = mu F_n0 with F_n0 the normal force
    of the same step at mu = 0, not mu F_n: friction at the tip raises the normal force (here F_n / F_n0 = 1.19 at
    mu 0.5, 1.78 at mu 2) and DART's bound does not follow it, so the friction falls short of Coulomb's by that ratio;
    the feedback that makes a rigid rod jam (friction growing with the normal force it raises, eq. p < 0) is cut.
    On the diagonal slip (varphi = -1.9) both rows saturate: |F_t| = sqrt(2) mu F_n0, the square pyramid."""
    opts = Options()
    along_y = SlipState(theta=0.5, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0)
    q0, v0 = to_generalized(ROD, along_y, tip=(0.0, 0.0, opts.radius))
    F0 = World(ROD, 0.0, opts).rollout(q0, v0, 3).force[1]
    F = World(ROD, mu, opts).rollout(q0, v0, 3).force[1]
    assert F0[2] > 0 and F[2] > 1.15 * F0[2] and abs(F[0]) <= 1e-9
    assert abs(F[1] / (mu * F0[2]) - 1) <= FROZEN_BOUND
    diagonal = SlipState(theta=0.5, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)
    q0, v0 = to_generalized(ROD, diagonal, tip=(0.0, 0.0, opts.radius))
    F0 = World(ROD, 0.0, opts).rollout(q0, v0, 3).force[1]
    F = World(ROD, mu, opts).rollout(q0, v0, 3).force[1]
    assert abs(np.linalg.norm(F[:2]) / (math.sqrt(2) * mu * F0[2]) - 1) <= FROZEN_BOUND


def test_scaled_units_across_physical_rods():
    s = SlipState(theta=1.4, varphi=-2.0, Theta=0.3, Psi=4.0, eta=1.0, psi=0.3)
    base = SPEC.simulate(ROD, s, 0.4, horizon=0.5, radius=0.02, timestep=2e-3)
    R = base.record
    np.testing.assert_allclose(np.diff(R.t), 2e-3, rtol=1e-12, atol=0)
    assert len(R) == 250 and abs(R.gap[0]) <= 4 * EPS and R.active[0] and R.normal_force[0] > 0
    rods = {
        "uniform_1m": Rod.uniform(1.0, 1.0),
        "uniform_10cm": Rod.uniform(1.0, 0.1),
        "heavy_short": Rod(mass=50.0, length=0.3, inertia=1.5, gravity=9.81),
    }
    for name, rod in rods.items():
        other = SPEC.simulate(rod, s, 0.4, horizon=0.5, radius=0.02, timestep=2e-3)
        for f in FIELDS:
            got, want = np.asarray(getattr(other.record, f), float), np.asarray(getattr(R, f), float)
            assert np.abs(got - want).max() <= SCALE_INVARIANCE * (1 + np.abs(want).max()), (name, f)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"timestep": 0.0}, "timestep must be in (0, inf); got 0.0"),
        ({"radius": 0.5}, "radius must be in (0, 0.5); got 0.5"),
        (
            {"solver": "pgs"},
            "unknown DART option 'solver': options must be one of friction_solver, radius, timestep",
        ),
        (
            {"friction_solver": "pgs"},
            "friction_solver must be one of dantzig, nsgs_box, nsgs_coulomb; got 'pgs'",
        ),
    ],
    ids=["timestep", "radius", "unknown", "friction_solver"],
)
def test_bad_options_raise_one_line_naming_option_value_and_range(options, message):
    with pytest.raises(ValueError) as e:
        SPEC.simulate(ROD, SLIPPING, 0.5, horizon=0.1, **options)
    assert str(e.value) == message and "\n" not in str(e.value)


#: A start of the quick report's Psi-mu map: the theory sticks at t = 0.19197 (mu 1.125), DART slips on.
STUCK = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.375, eta=1.0)


def test_dart_slips_through_a_stick_for_its_fixed_friction_bound_not_its_pyramid():
    """DART's Dantzig step bounds the friction by mu times the frictionless normal impulse; the theory sticks.  DART's
    own NSGS solver, bounding the friction by mu times the normal impulse as solved, sticks with the pyramid (Box) and
    with the cone (Coulomb): the ladder names the friction bound, and its intervention on DART removes the slip."""
    from crosscheck.outcome import Outcome
    from crosscheck.studies.interventions import intervene
    from crosscheck.studies.ladder import run_ladder

    ld = run_ladder("dart", STUCK, 1.125, horizon=2.0)
    labels = {r.name: r.label for r in ld.rungs}
    assert labels == {
        "tip": Outcome.STICK,
        "capsule": Outcome.STICK,
        "coulomb_step": Outcome.STICK,
        "pyramid_step": Outcome.STICK,
        "engine": Outcome.SLIP,
    }
    assert ld.cause == "friction bound"
    r = intervene("dart", STUCK, 1.125, horizon=2.0, causes=("friction bound", "discretisation"))
    assert [x["removes"] for x in r["causes"]["friction bound"]] == [True]
    assert not any(x["removes"] for x in r["causes"]["discretisation"])  # a finer Dantzig step keeps the bound


def test_the_pyramid_stops_a_skew_slip_sooner_than_the_cone():
    """The slip of STUCK runs along neither world axis, so DART's two friction rows, bounded apart (a square pyramid),
    reach |F_t| up to sqrt(2) mu F_n where the cone allows mu F_n: the tip decelerates faster and sticks sooner (NSGS
    with its Box law against its Coulomb law, the bound following the normal impulse in both); the cone sticks within
    a few steps of the theory (t = 0.19197; measured 0.166, 0.179 at timestep 1e-3)."""
    box = SPEC.simulate(ROD, STUCK, 1.125, horizon=0.4, friction_solver="nsgs_box")
    cone = SPEC.simulate(ROD, STUCK, 1.125, horizon=0.4, friction_solver="nsgs_coulomb")
    assert box.outcome.name == cone.outcome.name == "STICK"
    assert box.event_time < cone.event_time - 0.005
    assert abs(cone.event_time - 0.19197) < abs(box.event_time - 0.19197)


#: A start whose DART run lifts off at its first step (t = 0.004, the event judged) and then blows up (theta ~1e260 by
#: t = 2; DART prints 6534 "Warning [...] Non-finite ..." lines over the full horizon; alpha 3, mu 1.4, timestep 0.004).
BLOWS_UP = SlipState(theta=0.85, varphi=-1.9, Theta=1.5, Psi=0.0, eta=1.0)
#: The quick report's DART convergence start that warns within a sweep (stopped once its first event is judged): it
#: lifts off at t = 0.108, judged at step 128 of 0.004, after its blow-up at t = 0.308 (720 warning lines to t = 0.5).
WARNS_IN_SWEEP = SlipState(theta=1.2833333333333332, varphi=-1.9, Theta=1.0, Psi=0.0, eta=1.0)


def test_darts_warnings_are_counted_not_printed_and_the_blow_up_is_recorded(capfd):
    """DART's C++ warnings reach neither stderr nor stdout: they are the run's ``DartHealth.warnings`` (and a sweep's
    ``warnings``); the blow-up after the lift-off is the run's ``diverged_time``, the outcome still the lift-off."""
    from crosscheck.outcome import Outcome

    capfd.readouterr()
    blown = SPEC.simulate(ROD, BLOWS_UP, 1.4, horizon=2.0, timestep=0.004)
    quiet = SPEC.simulate(ROD, SLIPPING, 0.5, horizon=0.2)
    out, err = capfd.readouterr()
    assert "Warning [" not in err and "Warning [" not in out
    assert blown.outcome.name == "LIFTOFF" and blown.event_time == pytest.approx(0.004)
    assert blown.solver.warnings > 0 and not abs(blown.record.theta[-1]) < 1e6
    assert blown.event_time < blown.diverged_time < 2.0
    assert quiet.outcome.name == "SLIP" and quiet.solver.warnings == 0 and math.isnan(quiet.diverged_time)
    sweep = SPEC.sweep(
        ROD, [WARNS_IN_SWEEP, SLIPPING], np.array([1.4, 0.5]), horizon=0.5, timestep=0.004, progress=False
    )
    out, err = capfd.readouterr()
    assert "Warning [" not in err and "Warning [" not in out
    assert sweep.solver["warnings"][0] > 0 and sweep.solver["warnings"][1] == 0
    assert sweep.warnings == {"DART warning": int(sweep.solver["warnings"][0])}
    assert [Outcome(int(o)).name for o in sweep.outcome] == ["LIFTOFF", "SLIP"]
    assert sweep.event_time[0] < sweep.diverged_time[0]  # the lift-off judged before the blow-up, which is recorded


def test_the_console_capture_passes_on_what_is_not_a_dart_warning_and_restores_stderr(capfd):
    """``console.captured``: a DART warning line (coloured as on a terminal) counted, any other line written to fd 2
    passed on in its order, and fd 2 put back also when the block raises (KeyboardInterrupt)."""
    import os

    from crosscheck.engines.dart.console import captured

    before = os.fstat(2)
    with captured() as seen:
        os.write(2, b"first line\n\x1b[1;33mWarning [GenericJoint.hpp:2544]\x1b[0m [x] Non-finite ...\n")
        os.write(2, b"Warning [BodyNode.cpp:2109] [y] Non-finite ...\nnot a Warning [line]\nlast, unterminated")
    _, err = capfd.readouterr()
    assert seen.warnings == 2
    assert err == "first line\nnot a Warning [line]\nlast, unterminated"
    with pytest.raises(KeyboardInterrupt), captured():
        os.write(2, b"Warning [a] b\n")
        raise KeyboardInterrupt
    after = os.fstat(2)
    assert (after.st_dev, after.st_ino) == (before.st_dev, before.st_ino)
    os.write(2, b"after\n")
    assert capfd.readouterr().err == "after\n"
