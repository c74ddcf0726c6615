"""The Newton engines (MuJoCo Warp, XPBD, Featherstone on Warp's CPU device): scaled units, MuJoCo in C, bad options.

Every check runs real Newton.  Warp compiles each solver's kernels at their first use in a process and loads them
from its disk cache afterwards; the models are kept per process (``crosscheck.engines.newton.model.batch``), so
the tests of this file and the contract test share them and no test compiles a kernel another has compiled.  The
file needs the extra ``crosscheck[newton]``.  Newton is not in ``crosscheck[test]``: from an empty kernel cache
each solver's first model, solver and step cost 48 (Featherstone), 53 (XPBD) and 62 (MuJoCo Warp) CPU seconds here
(``benchmarks/bench_newton.py --cold``), ~2 CPU minutes together on a fresh machine, against the suite's 5 minutes on
2 cores that the other engines already nearly fill.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("newton")

from crosscheck import Rod, SlipState, engines
from crosscheck.engines.newton import ENGINES
from crosscheck.engines.newton.model import compile_seconds
from crosscheck.engines.record import FIELDS
from crosscheck.outcome import Outcome

NAMES = [s.name for s in ENGINES]
ALPHA = 3.0
ROD = Rod.scaled(ALPHA)

#: The contract test's slipping start (b < 0 < p at mu = 0.5).
STATE = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)
MU = 0.5

#: The same scaled run on a physical rod (2 kg, tip to centre 0.5 m, g = 9.81) against ``Rod.scaled``, relative to
#: 1 + max |field|: Warp steps in float32 in SI, so the two runs round differently.  States (positions, velocities,
#: angles, rates) agree to a few float32 eps carried along the run: 64 eps32 = 7.6e-6 (measured over 100 steps of
#: STATE: 4.1e-6 MuJoCo Warp, 2.2e-7 Featherstone).  Difference quotients over a step (tip_acc, force, normal_force)
#: lose the digits of v to the subtraction, eps32 |v| / dt: 2 eps32 / timestep = 2.4e-4 at 1e-3 (measured 5.6e-5 and
#: 4.0e-5).  XPBD's contact impulses alternate from step to step, so a rounding moves which step takes one: its states
#: agree to 9.7e-4 and its forces not step by step (0.47); its guard is on the states, 3 x the measured.
EPS32 = float(np.finfo(np.float32).eps)
#: The semi-implicit solver's states agree as Featherstone's (measured 5.6e-7, Psi) and its quotients to 4.0e-4
#: (tip_acc: its joint's torsion spring rounds differently in SI); its quotient guard is 3 x the measured.
STATE_RTOL = {
    "newton_mujoco": 64 * EPS32,
    "newton_featherstone": 64 * EPS32,
    "newton_xpbd": 3e-3,
    "newton_semi_implicit": 64 * EPS32,
}
QUOTIENTS = ("tip_acc", "force", "normal_force")
QUOTIENT_RTOL = {
    "newton_mujoco": 2 * EPS32 / 1e-3,
    "newton_featherstone": 2 * EPS32 / 1e-3,
    "newton_xpbd": None,
    "newton_semi_implicit": 1.2e-3,
}

#: MuJoCo Warp's first contact step against MuJoCo in C at the same settings (timestep 1e-3): the normal force of
#: the step the capsule first penetrates is the converged solution of the same convex problem, in float32 against
#: float64: measured 6.1e-6 relative (12.59009 against 12.59001 m g); 1e-4 allows ~1e3 float32 eps.
FIRST_FORCE_RTOL = 1e-4


@pytest.mark.parametrize("name", NAMES)
def test_a_physical_rod_gives_the_scaled_record(name):
    spec = engines.get(name)
    physical = Rod.uniform(2.0, 0.5)
    a = spec.simulate(ROD, STATE, MU, horizon=0.1)
    b = spec.simulate(physical, STATE, MU, horizon=0.1)
    assert a.outcome == b.outcome
    for f in FIELDS:
        x, y = np.asarray(getattr(a.record, f), float), np.asarray(getattr(b.record, f), float)
        rtol = QUOTIENT_RTOL[name] if f in QUOTIENTS else STATE_RTOL[name]
        if rtol is not None:
            assert np.max(np.abs(x - y)) <= rtol * (1 + np.max(np.abs(x))), f


def test_mujoco_warp_runs_a_1_cm_rod_with_its_axial_inertia_held_above_mujoco_s_floor():
    """1e-12 I0 of a 1 cm rod (3e-17 kg m^2) is below MuJoCo's mjMINVAL, which MuJoCo Warp's compiler refuses; held
    at 10 mjMINVAL (3e-10 I0, as negligible in the psi inertia) the run is the scaled rod's."""
    spec = engines.get("newton_mujoco")
    a = spec.simulate(ROD, STATE, MU, horizon=0.1)
    b = spec.simulate(Rod.uniform(1.0, 0.01), STATE, MU, horizon=0.1)
    assert a.outcome == b.outcome
    # the contact flag where the gap is beyond float32's rounding of the start placed touching (~1e-8 l): a flag on
    # a gap within it flips with the rounding, as XPBD's (``RESTING_GAP``)
    clear = np.abs(a.record.gap) > 64 * EPS32
    assert clear.sum() > 0.9 * clear.size and np.array_equal(a.record.active[clear], b.record.active[clear])
    for f in set(FIELDS) - {"active"}:
        x, y = np.asarray(getattr(a.record, f), float), np.asarray(getattr(b.record, f), float)
        rtol = QUOTIENT_RTOL["newton_mujoco"] if f in QUOTIENTS else STATE_RTOL["newton_mujoco"]
        if rtol is not None:
            assert np.max(np.abs(x - y)) <= rtol * (1 + np.max(np.abs(x))), f
    with pytest.raises(
        ValueError, match=r"^rod must have a mass .* above 1e-14 .*got mass 1e-15, inertia 3.33333e-16$"
    ):
        spec.simulate(Rod.uniform(1e-15, 1.0), STATE, MU, horizon=0.1)


@pytest.mark.parametrize("name", NAMES)
def test_each_solver_records_its_kernel_compile_time_apart_from_the_steps(name):
    spec = engines.get(name)
    spec.simulate(ROD, STATE, MU, horizon=0.01)
    solver = spec.Options().solver
    assert solver in compile_seconds() and compile_seconds()[solver] >= 0.0


def test_mujoco_warp_makes_mujoco_s_first_contact_force_in_float32():
    """The same model in float32 (MuJoCo Warp through Newton) and float64 (MuJoCo in C): the first step with a
    contact gives the same force to float32 rounding."""
    a = engines.get("newton_mujoco").simulate(ROD, STATE, MU, horizon=0.01)
    b = engines.get("mujoco").simulate(ROD, STATE, MU, horizon=0.01, timestep=1e-3)
    k = int(np.argmax(b.record.normal_force > 0))
    assert k > 0 and a.record.normal_force[k] > 1.0
    assert a.record.normal_force[k] == pytest.approx(b.record.normal_force[k], rel=FIRST_FORCE_RTOL)


def test_the_penalty_solver_slips_under_a_spring_normal_force():
    """Featherstone's penalty contact: the normal force builds up over the contact spring's time 1/sqrt(stiffness) and
    holds the slipping tip near -b/p; the contact point stays within the spring's static penetration of the plane."""
    run = engines.get("newton_featherstone").simulate(ROD, STATE, MU, horizon=0.3)
    r = run.record
    assert run.outcome == Outcome.SLIP
    assert r.normal_force[1] < 0.5 * r.normal_force[10]  # a spring: built over steps, not one impulse
    assert np.all(r.gap[1:] > -10.0 / 1e4)  # within 10 m g / stiffness of the plane


def test_xpbd_holds_the_axial_spin_at_its_declared_axial_inertia_and_not_at_rod_xml_s():
    """XPBD projects the D6 joint's locked axis after the contact: at 1e-4 I0 about the axis the spin stays small;
    at rod.xml's 1e-12 the contact's friction correction turns the capsule about its axis instead."""
    spec = engines.get("newton_xpbd")
    held = spec.simulate(ROD, STATE, MU, horizon=0.3)
    assert held.solver.max_spin < 0.1
    loose = spec.simulate(ROD, STATE, MU, horizon=0.3, axial_inertia=1e-12)
    assert loose.solver.max_spin > 100 * held.solver.max_spin


#: The semi-implicit solver against Featherstone from STATE over a horizon of 0.3 at timestep 1e-3: the same penalty
#: contact, in maximal coordinates with the axis spring-locked, so theta follows to float32 rounding carried along the
#: run and the lock's small twist (measured 6.7e-6 over a horizon of 1; regression guard 2e-5).
SEMI_THETA_ATOL = 2e-5


def test_the_semi_implicit_solver_locks_the_axial_spin_with_a_soft_torsion_spring_and_not_with_newton_s():
    """Maximal coordinates: the D6 joint's locked axis is a torsion spring on the capsule's small axial moment.  At the
    declared stiffness (sqrt(k / (a I0)) dt < 2) the spin stays small and the rod moves as Featherstone's; at Newton's
    default stiffness (1e4 m g l / rad on this rod) the explicit spring diverges within the horizon."""
    semi, feather = engines.get("newton_semi_implicit"), engines.get("newton_featherstone")
    held = semi.simulate(ROD, STATE, MU, horizon=0.3)
    ref = feather.simulate(ROD, STATE, MU, horizon=0.3)
    assert held.outcome == ref.outcome == Outcome.SLIP and held.solver.max_spin < 0.3
    assert np.max(np.abs(held.record.theta - ref.record.theta)) <= SEMI_THETA_ATOL
    stiff = semi.simulate(ROD, STATE, MU, horizon=0.3, joint_stiffness=1e4, joint_damping=1e2)
    assert stiff.outcome == Outcome.DIVERGED and stiff.solver.max_spin > 1e3


@pytest.mark.parametrize(
    "option, value, message",
    [
        ("solver", "xpbd", "solver must be mujoco for newton_mujoco (one engine per solver); got 'xpbd'"),
        ("device", "gpu", "device must be one of cpu, cuda; got 'gpu'"),
        ("iterations", -1, "iterations must be an integer in [0, 1000]; got -1"),
        ("axial_inertia", 2.0, "axial_inertia must be in (0, 1] (a fraction of I0); got 2.0"),
        ("timeconst", 1e-3, "timeconst must be >= 2 timestep = 0.002 (MuJoCo's refsafe); got 0.001"),
    ],
)
def test_a_bad_option_is_refused_in_one_line(option, value, message):
    with pytest.raises(ValueError) as e:
        engines.get("newton_mujoco").simulate(ROD, STATE, MU, horizon=0.01, **{option: value})
    assert str(e.value) == message


def test_cuda_is_refused_in_one_line_where_warp_finds_no_cuda_device():
    import warp as wp

    if wp.get_cuda_device_count() > 0:  # a machine with a GPU runs it instead
        run = engines.get("newton_mujoco").simulate(ROD, STATE, MU, horizon=0.01, device="cuda")
        assert run.outcome in set(Outcome)
        return
    with pytest.raises(ValueError) as e:
        engines.get("newton_mujoco").simulate(ROD, STATE, MU, horizon=0.01, device="cuda")
    assert str(e.value) == "device must be cpu on this machine (Warp finds no CUDA device); got 'cuda'"


def test_cuda_in_a_sweep_file_exits_2_with_one_line(tmp_path):
    import subprocess
    import sys

    import warp as wp
    from conftest import small

    if wp.get_cuda_device_count() > 0:
        pytest.skip("a CUDA device is present: the refusal is for machines without one")
    spec = tmp_path / "s.toml"
    spec.write_text(small("newton_mujoco", horizon=0.01, device="cuda"))
    p = subprocess.run(
        [sys.executable, "-m", "crosscheck", "sweep", str(spec), "--out", str(tmp_path / "o"), "--no-progress"],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2 and "Traceback" not in p.stderr
    lines = [x for x in p.stderr.splitlines() if x.strip()]
    assert len(lines) == 1 and "device must be cpu on this machine" in lines[0], p.stderr


def test_a_rod_that_lifts_off_at_once_records_no_force_in_flight_and_mujoco_s_event():
    """b > 0 at the start: MuJoCo in C lifts off at once.  MuJoCo Warp's force, read from float32 velocities, is rounding
    in free flight (~3e-6 m g); below the engine's floor (``FORCE_ROUNDING``) it reads 0 exactly, so the classifier sees
    the same lift-off (with the rounding left in, this start was a STICK at 0.093)."""
    s = SlipState(theta=0.820, varphi=-1.650, Theta=0.547, Psi=-2.431, eta=0.249)
    a = engines.get("newton_mujoco").simulate(ROD, s, 1.22, horizon=0.3, timestep=3e-3)
    b = engines.get("mujoco").simulate(ROD, s, 1.22, horizon=0.3, timestep=3e-3)
    assert b.outcome == Outcome.LIFTOFF and b.event_time == 0.0
    assert a.outcome == b.outcome and a.event_time == b.event_time
    flying = a.record.gap > 1e-6
    assert flying.sum() > 50 and np.all(a.record.force[flying] == 0.0)


#: A start of the full report's Featherstone map just below mu_P = 4/3 (p = 0.18 at the start).
BELOW_MU_P = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=1.3125, eta=1.0)


def test_the_penalty_solvers_declare_their_normal_law_as_the_compliant_rod_s_and_the_others_none():
    from crosscheck.engines.newton.options import FeatherstoneOptions, MuJoCoWarpOptions, XPBDOptions

    twin = FeatherstoneOptions(stiffness=4e4, damping=300.0, radius=0.02, timestep=2e-3).compliant_twin
    assert twin == {"eps": 1.0 / 200.0, "xi": 300.0 / 200.0, "radius": 0.02, "timestep": 2e-3}
    assert MuJoCoWarpOptions().compliant_twin is None and XPBDOptions().compliant_twin is None


def test_featherstone_s_jam_below_mu_P_is_its_compliant_law_s_and_goes_as_the_contact_stiffens():
    """Below mu_P the rigid theory forbids a JAM; Featherstone at stiffness 1e4 jams there (the full report's 8 x 8 map
    at timestep 2e-3), as the compliant rod with its normal law does, while that rod at eps / 10 slips: the maps' check
    sorts it as the compliant law's (an engine finding), not as an impact without collision."""
    from crosscheck.report.sections.engine_maps import _jam_kind

    spec, mu = engines.get("newton_featherstone"), 1.3125
    run = spec.simulate(ROD, BELOW_MU_P, mu, horizon=0.2, timestep=2e-3)
    assert run.outcome == Outcome.JAM and run.event_time < 0.1
    twin = spec.options(timestep=2e-3).compliant_twin
    P = {"alpha": ALPHA, "horizon": 0.2, "options": {"timestep": 2e-3}}
    assert _jam_kind("newton_featherstone", P, twin, BELOW_MU_P.as_dict(), mu, run.event_time) == "compliant"
    # without the twin the same JAM counts against the theory
    assert _jam_kind("newton_featherstone", P, None, BELOW_MU_P.as_dict(), mu, run.event_time) == "iwc"


#: Starts, friction and horizons of different lengths for the batched ``simulate_each`` (seeded, slipping at t = 0).
def _batch_starts():
    from crosscheck.theory import analytic

    rng = np.random.default_rng(20261129)
    out = []
    while len(out) < 5:
        s = SlipState(
            theta=float(rng.uniform(0.3, 1.4)),
            varphi=float(-rng.uniform(0.1, 3.0)),
            Theta=float(rng.uniform(-1.0, 1.0)),
            Psi=float(rng.uniform(-2.0, 2.0)),
            eta=float(rng.uniform(0.2, 2.0)),
        )
        mu = float(rng.uniform(0.2, 1.2))
        if analytic.b(s.Psi, s.Theta, s.theta) < 0.0 < analytic.p(s.theta, s.varphi, mu, ALPHA):
            out.append((s, mu))
    return out


@pytest.mark.parametrize("name", NAMES)
def test_simulate_each_steps_the_starts_together_and_gives_each_start_s_own_simulate_record_for_record(name):
    """Five starts at their own mu and horizon in one batch of worlds (64) give the Runs of five ``simulate`` calls
    (4 worlds each) exactly: worlds do not interact and a run's first steps do not depend on how many follow."""
    spec = engines.get(name)
    starts, horizons = _batch_starts(), [0.05, 0.2, 0.012, 0.2, 0.1]
    many = spec.simulate_each(ROD, [s for s, _ in starts], [mu for _, mu in starts], horizon=horizons, timestep=3e-3)
    for run, (s, mu), h in zip(many, starts, horizons):
        one = spec.simulate(ROD, s, mu, horizon=h, timestep=3e-3)
        assert (run.outcome, run.nstep, run.horizon, run.mu, run.solver) == (
            one.outcome,
            one.nstep,
            one.horizon,
            one.mu,
            one.solver,
        )
        np.testing.assert_array_equal([run.event_time, run.jam_p_eff], [one.event_time, one.jam_p_eff])
        for f in FIELDS:
            np.testing.assert_array_equal(getattr(run.record, f), getattr(one.record, f), err_msg=f)


@pytest.mark.parametrize("name", NAMES)
def test_preload_leaves_the_solver_s_compile_time_for_the_report_s_provenance(name):
    spec = engines.get(name)
    spec.preload()
    solver = spec.Options().solver
    assert spec.provenance() == {"kernel_compile_seconds": compile_seconds()[solver]}
    assert compile_seconds()[solver] >= 0.0
