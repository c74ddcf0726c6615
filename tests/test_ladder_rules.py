"""The ladder's promises that its engine runs do not show by themselves (``crosscheck.studies.ladder``).

Its engine rung is the engine's own run at the ladder's thresholds, not at the defaults; its rerun without the
capsule's offset needs a model after the capsule.  The ladders of the engines are in ``test_ladder.py`` and
``test_engine_ladder.py``.
"""

from __future__ import annotations

import json
from dataclasses import replace

from crosscheck import Rod, SlipState, engines
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.spec import EngineSpec, Ladder
from crosscheck.outcome import Outcome
from crosscheck.studies.ladder import Rung, run_ladder, without_capsule_offset

#: A start whose theory slips to its exit from the paper's chart, its slip speed falling to 2.6e-3 on the way, below
#: a rigid engine's STICK floor (``tests/test_mutation_survivors.py``): the engine's STICK time follows the floor.
SLIP_BELOW_FLOOR = (SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.875, eta=1.0), 0.875)


def _toy(name: str, like: str, rungs: dict) -> EngineSpec:
    spec = engines.get(like)
    declared = spec.ladder.interventions if spec.ladder else {}
    ladder = Ladder(rungs=rungs, interventions={c: r for c, r in declared.items() if c in rungs})
    return EngineSpec(name=name, engine=spec.engine, tags=spec.tags, ladder=ladder)


def test_the_engine_rung_runs_at_the_ladders_thresholds():
    """A STICK floor ten times the default's (100 timesteps for a rigid contact) moves the rigid engine's STICK earlier:
    the ladder's engine rung is that run, the engine's own at the same thresholds."""
    state, mu = SLIP_BELOW_FLOOR
    th = replace(Thresholds(), rigid_stick_steps=100.0)
    engines.register(_toy("toy_rigid_rung", "pinocchio", {"discretisation": "engine"}))
    try:
        ladder = run_ladder("toy_rigid_rung", state, mu, thresholds=th, timestep=1e-3)
    finally:
        engines.unregister("toy_rigid_rung")
    pinocchio = engines.get("pinocchio")
    rod, kw = Rod.scaled(3.0), {"horizon": ladder.until + ladder.lag, "timestep": 1e-3}
    own = pinocchio.first_event(rod, state, mu, thresholds=th, **kw)
    default = pinocchio.first_event(rod, state, mu, thresholds=Thresholds(), **kw)
    rung = ladder.rungs[-1]
    assert own[0] == default[0] == Outcome.STICK and own[1] < default[1]  # (the floor decides the time)
    assert (rung.outcome, rung.time) == own
    # as saved (the ladder sections' JSON): outcomes by name, None where a rung has none
    saved = json.loads(json.dumps(ladder.as_dict()))
    assert saved["rungs"][-1]["outcome"] == "STICK"  # its outcome; the reference is its label as compared
    assert saved["reference"] == ladder.reference.name == saved["rungs"][-1]["label"]
    assert (saved["comparison_time"], saved["lag"]) == (ladder.until, ladder.lag)


def test_a_failed_rung_is_saved_without_an_outcome():
    failed = Rung(2, "boom", "compliance", "failed", detail="RuntimeError: no")
    assert json.loads(json.dumps(failed.as_dict())) | {"time": None} == {
        "rung": 2,
        "name": "boom",
        "cause": "compliance",
        "status": "failed",
        "outcome": None,
        "time": None,
        "label": None,
        "detail": "RuntimeError: no",
        "wall_time": 0.0,
    }


def test_the_rerun_without_the_capsules_offset_needs_a_model_after_the_capsule():
    """Bullet's ladder has a model after the capsule (its friction law): the rerun gives its rungs at the thin capsule.
    A ladder whose only model is the capsule has nothing to rerun without the offset: None, as for no geometry
    intervention."""
    state, mu = SLIP_BELOW_FLOOR
    rerun = without_capsule_offset("bullet", state, mu, Outcome.JAM)
    assert [r["cause"] for r in rerun["rungs"]] == ["geometry", "friction law"]
    assert rerun["radius"] < engines.get("bullet").options().radius
    engines.register(_toy("toy_capsule_only", "bullet", {"geometry": "capsule", "discretisation": "engine"}))
    try:
        assert without_capsule_offset("toy_capsule_only", state, mu, Outcome.JAM) is None
    finally:
        engines.unregister("toy_capsule_only")
