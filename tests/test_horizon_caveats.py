"""A horizon shorter than the classifier's window is said wherever an outcome is: the ``Run`` and ``SweepResult``, the
sweep's summary and its store's manifest, and ``compare``.

MuJoCo from the paper's IC2 (mu 1.4) answers SLIP, LIFTOFF and JAM at horizons 0.01, 0.04 and 0.05 (JAM from 0.05
on): each of those runs ends inside the window its JAM rule reads after a row (``Thresholds.window_rows`` at the
timestep: 167 rows of 3e-4 = 0.0501), so its outcome is not a judgement of the whole run.
"""

from __future__ import annotations

import json

import pytest

from crosscheck import Rod, SlipState, engines
from crosscheck.cli import main
from crosscheck.engines.thresholds import Thresholds

IC2 = SlipState(theta=1.1031, varphi=-1.9233, Theta=0.9, Psi=0.0, eta=2.0)
WINDOW = Thresholds().window_rows(3e-4) * 3e-4  # MuJoCo's default timestep


@pytest.mark.parametrize("horizon, short", [(0.01, True), (0.04, True), (0.05, True), (0.1, False), (0.2, False)])
def test_a_run_says_when_its_horizon_is_shorter_than_the_window(horizon, short):
    run = engines.get("mujoco").simulate(Rod.scaled(3.0), IC2, 1.4, horizon=horizon)
    assert run.unjudged_tail == pytest.approx(min(horizon, WINDOW), rel=1e-12)
    assert bool(run.caveats) == short
    if short:
        assert run.caveats[0].startswith(f"the horizon {horizon:g} is not longer than the classifier's window (0.0")
    batch = engines.get("mujoco").sweep(Rod.scaled(3.0), [IC2, IC2], [1.4, 1.4], horizon=horizon)
    assert batch.caveats == run.caveats


SPEC = """[sweep]
engine = "{engine}"
horizon = 0.04
chunk = 2
[states]
theta = [1.1031, 1.0]
varphi = -1.9233
Theta = 0.9
Psi = 0.0
eta = 2.0
[parameters]
mu = 1.4
"""


def test_a_short_sweep_says_so_in_its_summary_its_manifest_and_compare(tmp_path, capsys):
    stores = {}
    for engine in ("analytic", "mujoco"):
        (tmp_path / f"{engine}.toml").write_text(SPEC.format(engine=engine))
        stores[engine] = tmp_path / engine
        argv = ["sweep", str(tmp_path / f"{engine}.toml"), "--out", str(stores[engine]), "--workers", "1"]
        assert main([*argv, "--no-progress"]) == 0
        caveats = [x[len("caveat: ") :] for x in capsys.readouterr().out.splitlines() if x.startswith("caveat: ")]
        manifest = json.loads((stores[engine] / "manifest.json").read_text())
        assert manifest["caveats"] == caveats
        assert manifest["rod"] == {"mass": 1.0, "length": 1.0, "gravity": 1.0, "alpha": [3.0]}
    assert caveats and "the horizon 0.04 is not longer than the classifier's window" in caveats[0]  # MuJoCo's
    assert json.loads((stores["analytic"] / "manifest.json").read_text())["caveats"] == []  # the theory judges all
    assert main(["compare", str(stores["analytic"]), str(stores["mujoco"])]) == 0
    printed = capsys.readouterr().out
    assert "caveat: a horizon (0.04) is shorter than the classifier's window (0.05)" in printed


def test_a_run_names_the_rod_it_simulated():
    rod = Rod.uniform(2.0, 0.5)
    run = engines.get("pinocchio").simulate(rod, IC2, 1.4, horizon=0.2)
    assert run.rod == rod
    assert run.rod_text == (
        "rod of mass 2 kg, length 0.5 m (tip to centre), inertia 0.166667 kg m^2, gravity 9.81 m/s^2 (alpha 3)"
    )
    assert engines.get("pinocchio").sweep(rod, [IC2], [1.4], horizon=0.2).rod == rod
    assert engines.get("pinocchio").simulate(Rod.scaled(5.0), IC2, 1.4, horizon=0.2).rod_text == (
        "scaled rod (m = l = g = 1), alpha 5"
    )


@pytest.mark.parametrize("horizon", [0.1, 0.2])
def test_mujocos_jam_at_t_0_from_ic2_is_a_real_impulse_of_its_capsule(horizon):
    """MuJoCo's "JAM at t = 0" from IC2 is what its contact does, not a reading of the classifier: the rigid rod with
    its contact at the capsule point C (radius 0.01) jams within the first 1e-3 (the offset moves p, 0.024 at the tip,
    across 0), and MuJoCo's normal force removes more than half the slip speed in 0.03 where the rigid rod at the tip
    loses less than 15 % of it before it lifts off at 0.0165.  The JAM rule reads the window after the row where the
    impulse begins, row 0; a horizon shorter than that window cannot show it (the caveat above)."""
    from crosscheck.theory.capsule import slip_until_event
    from crosscheck.theory.slipping import slip_until_event as tip_slip

    run = engines.get("mujoco").simulate(Rod.scaled(3.0), IC2, 1.4, horizon=horizon)
    assert (run.outcome.name, run.event_time, run.caveats) == ("JAM", 0.0, ())
    capsule = slip_until_event(IC2, 1.4, 3.0, radius=run.options.radius)
    assert capsule.outcome.name == "JAM" and capsule.time < 1e-3
    tip = tip_slip(IC2, 1.4, 3.0)
    assert tip.outcome.name == "LIFTOFF" and tip.time == pytest.approx(0.0165399, rel=1e-4)
    assert tip.state.eta > 0.85 * IC2.eta
    rows = run.record.t <= 0.03
    assert run.record.eta[rows][-1] < 0.5 * IC2.eta
