"""The ladder any engine declares (crosscheck.studies.ladder): IC2 through Drake's and Bullet's, a failing rung, explain --engine."""

from __future__ import annotations

import pytest

from crosscheck import engines
from crosscheck.cli import main
from crosscheck.engines import EngineSpec, Ladder
from crosscheck.engines.spec import LADDER_CAUSES
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.studies.ladder import run_ladder
from crosscheck.theory import capsule
from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS

IC2 = SlipState(**FIG20_INITIAL_CONDITIONS[1])


@pytest.mark.parametrize("engine", ["drake_tamsi", "drake_sap", "bullet"])
def test_ic2_jams_at_the_capsule_point_in_every_engine_geometry_is_its_cause(engine):
    """The paper's rod lifts off from IC2 at t = 0.01654 (Fig. 20) with p = 0.0125; a radius of 0.01 below the tip the rigid
    rod jams at once (p_C < 0), and so does each engine: the ladder names geometry, its first rung to match."""
    ld = run_ladder(engine, IC2, 1.4)
    tip, cap = ld.rungs[0], ld.rungs[1]
    assert tip.outcome == Outcome.LIFTOFF and tip.time == pytest.approx(0.01654, abs=5e-6)
    assert cap.name == "capsule" and cap.outcome == Outcome.JAM
    radius = engines.get(engine).options().radius
    assert cap.time == capsule.slip_until_event(IC2, 1.4, 3.0, radius=radius, t_max=ld.until + ld.lag).time
    assert ld.reference == Outcome.JAM and ld.cause == "geometry"
    assert [r.cause for r in ld.rungs[1:]] == [c for c in LADDER_CAUSES if c in engines.get(engine).ladder]


def boom(rod, state, mu, *, horizon, thresholds, options):
    """A rung that cannot run."""
    raise RuntimeError("this model is not built")


def test_a_failing_rung_is_reported_and_leaves_the_cause_undetermined():
    spec = engines.get("bullet")
    broken = EngineSpec(
        name="bullet_broken",
        engine=spec.engine,
        label="Bullet (broken ladder)",
        defaults=spec.defaults,
        tags=spec.tags,
        ladder=Ladder(rungs={"compliance": "test_engine_ladder:boom", "discretisation": "engine"}),
    )
    engines.register(broken)
    try:
        ld = run_ladder("bullet_broken", IC2, 1.4)
    finally:
        engines.unregister("bullet_broken")
    assert ld.rungs[1].status == "failed" and "this model is not built" in ld.rungs[1].detail
    assert ld.rungs[2].ok and ld.cause == "undetermined"


def test_explain_runs_a_declared_ladder_and_refuses_an_engine_without_one(capsys):
    args = [
        "explain",
        "--theta",
        "1.1031",
        "--varphi",
        "-1.9233",
        "--Theta",
        "0.9",
        "--Psi",
        "0",
        "--eta",
        "2",
        "--mu",
        "1.4",
    ]
    assert main([*args, "--engine", "drake_tamsi"]) == 0
    out = capsys.readouterr().out
    assert "2 capsule     geometry        JAM" in out and "cause: geometry (Drake TAMSI JAM, theory LIFTOFF)" in out
    # confirmed on Drake TAMSI itself: the thinner capsule only together with the stiffer contact
    assert out.rstrip().splitlines()[-1] == "confirmation: geometry: confirmed as a pair with compliance"
    assert main([*args, "--engine", "pinocchio"]) == 2
    assert "engine must be one of" in capsys.readouterr().err


def test_a_convex_relaxations_launch_is_its_relaxation():
    """A slipping start (b < 0 < p) that SAP throws off the plane at its default stiffness: Drake's continuous plant and TAMSI's
    non-convex step at the same timestep and contact keep it on the plane, so the ladder names the relaxation itself."""
    s = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0)
    ld = run_ladder("drake_sap", s, 0.5)
    by_cause = {r.cause: r for r in ld.rungs[1:]}
    assert ld.rungs[0].outcome == Outcome.SLIP and ld.reference == Outcome.LAUNCH
    assert by_cause["friction law"].label != Outcome.LAUNCH and by_cause["discretisation"].label != Outcome.LAUNCH
    assert by_cause["relaxation"].name == "engine" and ld.cause == "relaxation"


def test_the_cause_map_codes_each_start_by_its_ladders_cause_or_why_it_has_none(tmp_path):
    """A cell of an engine's cause map: its ladder's cause where laddered, else whether it agrees, disagrees unladdered,
    or does not slip at t = 0 (not compared); the codes saved are what the section's figure colours."""
    from types import SimpleNamespace

    import numpy as np

    from crosscheck.report.sections.engine_ladder import _cause_maps
    from crosscheck.report.sections.engine_ladder_render import AGREE, NOT_RUN, NOT_SLIPPING, cause_codes
    from crosscheck.report.store import SectionStore

    S, J, T = int(Outcome.SLIP), int(Outcome.JAM), int(Outcome.STICK)
    t = {
        "theta": np.array([0.5, 0.7, 0.9, 1.1]),
        "Theta": np.array([0.0, 0.0, 0.5, 0.5]),
        "slipping": np.array([1, 1, 1, 0]),
        "analytic_outcome": np.array([S, J, T, S]),
        "bullet": np.array([S, T, S, -2]),
    }
    m = {"name": "theta_Theta_0", "x": "theta", "y": "Theta"}
    store = SectionStore(tmp_path)
    store.reset()
    ctx = SimpleNamespace(params={"ladder_engine": "bullet"}, store=store)
    _cause_maps(ctx, {m["name"]: t}, [m], [(m["name"], t, 1)], [SimpleNamespace(cause="compliance")])
    saved = store.read_table("causes_theta_Theta_0")
    assert saved["code"].tolist() == [AGREE, cause_codes()["compliance"], NOT_RUN, NOT_SLIPPING]
    assert saved["theta"].tolist() == t["theta"].tolist() and store.read_json("cause_maps") == [m]
