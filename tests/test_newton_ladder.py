"""Newton's ladders and interventions: float32 against the same model in MuJoCo in C, XPBD's position projection, the
penalty contact's compliance.

Every check runs real Newton on a start of the quick report's maps (timestep 3e-3, as the report's Newton maps).  The
Newton models are kept per process (``crosscheck.engines.newton.model.batch``) and Warp's kernels in its disk cache,
so these tests compile no kernel the Newton engine tests do not (MuJoCo in C through Newton compiles none).
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("newton")

from crosscheck import Rod, SlipState, engines
from crosscheck.engines.newton import ENGINES
from crosscheck.outcome import Outcome
from crosscheck.studies.interventions import causes_with_interventions, intervene
from crosscheck.studies.ladder import run_ladder

ROD = Rod.scaled(3.0)
EPS32 = float(np.finfo(np.float32).eps)

#: The contract test's slipping start (b < 0 < p at mu = 0.5).
STATE = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)

#: A start of the quick report's theta-Theta map (Psi = 0, mu = 1.4): the theory jams at once (b < 0, p < 0 at mu 1.4).
JAM_START = SlipState(theta=1.0125, varphi=-1.9, Theta=0.375, Psi=0.0, eta=1.0)

#: MuJoCo in C through Newton (``mujoco_cpu``) against the ``mujoco`` engine (MuJoCo in C on rod.xml) over 300 steps
#: at timestep 1e-3: the same model in float64 from a start rounded to float32 once and read back in float32, so theta
#: agrees to a few float32 eps (measured 3.7e-7 = 3.1 eps32); MuJoCo Warp's float32 steps carry theirs along the run
#: (measured 1.3e-6 = 11 eps32).  Regression guard: 5 eps32.
CPU_THETA_ATOL = 5 * EPS32


def test_the_float32_intervention_runs_the_same_model_in_mujoco_in_c_in_float64():
    spec = engines.get("newton_mujoco")
    (iv,) = spec.interventions_for("float32", spec.options())
    c = engines.get("mujoco").simulate(ROD, STATE, 0.5, horizon=0.3, timestep=1e-3)
    cpu = spec.simulate(ROD, STATE, 0.5, horizon=0.3, timestep=1e-3, **iv.options)
    warp = spec.simulate(ROD, STATE, 0.5, horizon=0.3, timestep=1e-3)
    assert iv.options == {"mujoco_cpu": True}
    assert np.max(np.abs(cpu.record.theta - c.record.theta)) <= CPU_THETA_ATOL
    assert np.max(np.abs(warp.record.theta - c.record.theta)) > CPU_THETA_ATOL  # float32 steps: the difference removed
    k = int(np.argmax(c.record.normal_force > 0))  # the first contact step's force: float64's, to its float32 readback
    assert k > 0 and cpu.record.normal_force[k] == pytest.approx(c.record.normal_force[k], rel=4 * EPS32 / 1e-3)
    assert cpu.outcome == c.outcome


def test_mujoco_in_c_is_refused_for_another_solver_in_one_line():
    with pytest.raises(ValueError) as e:
        engines.get("newton_xpbd").options(mujoco_cpu=True)
    assert str(e.value) == "mujoco_cpu must be False for newton_xpbd (a SolverMuJoCo setting); got True"


@pytest.mark.parametrize("name", [s.name for s in ENGINES if s.ladder is not None])
def test_every_cause_of_a_newton_ladder_has_interventions_the_solver_accepts(name):
    """Each cause the ladder can name is tested on the solver itself, by settings its ``Options`` accept, each moving
    the solver toward the model of the rung before (a thinner capsule, a stiffer contact, a shorter step, ...)."""
    spec = engines.get(name)
    base = spec.options(**spec.report.maps["quick"])
    assert causes_with_interventions(name) == list(spec.ladder)
    for cause in spec.ladder:
        ivs = spec.interventions_for(cause, base)
        assert ivs, cause
        for iv in ivs:
            o = spec.options(**{**spec.report.maps["quick"], **iv.options})
            assert o != base, iv.text
            assert o.radius <= base.radius and o.timestep <= base.timestep, iv.text
            assert o.stiffness >= base.stiffness and o.friction_gain >= base.friction_gain, iv.text


def test_xpbd_slips_through_a_jam_its_converged_or_finer_projection_makes():
    """Theory and the rigid capsule jam at once; XPBD at 2 iterations and relaxation 0.8 slips on: its projection
    corrects only part of the step's penetration, so the slip goes on.  The projection converged within the step
    (8 or 32 iterations at relaxation 1) or a finer step makes XPBD jam too: the cause is the position projection."""
    ld = run_ladder("newton_xpbd", JAM_START, 1.4, horizon=2.0, timestep=3e-3)
    assert [r.label for r in ld.rungs] == [Outcome.JAM, Outcome.JAM, Outcome.SLIP]
    assert ld.cause == "position projection"
    r = intervene("newton_xpbd", JAM_START, 1.4, horizon=2.0, causes=("position projection",), timestep=3e-3)
    rows = r["causes"]["position projection"]
    assert r["theory"] == "JAM" and len(rows) == 4 and all(x["removes"] and x["label"] == "JAM" for x in rows)


def test_featherstone_slips_through_the_jam_as_the_compliant_rod_with_its_spring_does():
    """The same jam: the rigid capsule jams, the compliant rod with Featherstone's spring (eps = 1 / sqrt(stiffness) =
    0.01, xi = 2) slips on, as do the penalty law at a sixteenth of the step and Featherstone itself: compliance."""
    ld = run_ladder("newton_featherstone", JAM_START, 1.4, horizon=2.0, timestep=3e-3)
    assert [r.label for r in ld.rungs] == [Outcome.JAM, Outcome.JAM, Outcome.SLIP, Outcome.SLIP, Outcome.SLIP]
    assert ld.cause == "compliance"


#: A start of the quick report's Psi-mu map at which the theory sticks (t = 0.192, mu 1.125).
STUCK = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.375, eta=1.0)


def test_a_steeper_friction_slope_slows_a_stuck_tip_until_the_step_sets_its_chatter():
    """Featherstone's friction min(mu F_n, kf |u|) is explicit: at kf dt below the tip's effective mass a steeper slope
    holds a stuck tip closer (its mean slip speed after the stick falls), beyond it the slope overshoots to the Coulomb
    bound every step and the speed no longer depends on kf (measured 0.035, 0.014, 0.014 l omega at kf 1e3, 1e4, 1e5,
    timestep 3e-3): why the friction law's intervention shrinks the step with the slope."""
    speeds = []
    for kf in (1e3, 1e4, 1e5):
        run = engines.get("newton_featherstone").simulate(
            ROD, STUCK, 1.125, horizon=0.6, timestep=3e-3, friction_gain=kf
        )
        assert run.outcome == Outcome.STICK
        after = run.record.t >= 0.3
        speeds.append(float(np.mean(np.linalg.norm(run.record.slip_vel[after, :2], axis=-1))))
    assert speeds[1] < 0.5 * speeds[0]
    assert speeds[2] == pytest.approx(speeds[1], rel=1e-6)


def test_every_cause_a_ladder_can_name_has_its_colour_in_the_cause_maps():
    from crosscheck.report.sections.engine_ladder_render import CAUSE_COLORS
    from crosscheck.studies.ladder import CAUSES

    assert set(CAUSES) <= set(CAUSE_COLORS)
    assert len(set(CAUSE_COLORS.values())) == len(CAUSE_COLORS)  # each told apart on the map
