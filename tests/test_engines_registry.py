"""The engine registry, and the proof that a new engine is one record: a toy engine declared and registered in this file.

The toy engine is the analytic slipping flow (``slip_until_event``) written
into the shared ``Record`` on a uniform time grid and judged by the one
classifier.  Its ``EngineSpec`` (``TOY``: tags, a tolerance profile, a map
section) is all it takes for the event-agreement study, the engine contract
(``tests/test_engine_contract.py``) and a report's map section to run on it;
nothing else in the package knows it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from crosscheck import Outcome, Rod, SlipState, engines
from crosscheck.checks import POSITIVE, check
from crosscheck.engines import (
    EngineSpec,
    Record,
    ReportPlan,
    Run,
    Thresholds,
    Validation,
    classify,
    n_steps,
    sweep_by_simulate,
)
from crosscheck.engines.base import options_from_kwargs
from crosscheck.engines.spec import Execution
from crosscheck.studies.agreement import agreement_study
from crosscheck.studies.grids import EventGrid
from crosscheck.theory.slipping import X_STATE, slip_until_event
from crosscheck.tolerances import EVENT_TOLERANCE_KEYS, Tolerance


@dataclass(frozen=True)
class ToyOptions:
    """Scaled time between record rows; the contact is rigid (no build-up, no creep)."""

    timestep: float = 1e-3

    @property
    def contact_time(self) -> float:
        return 0.0

    @property
    def friction_time(self) -> float:
        return 0.0


def simulate(
    rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds | None = None, **options
) -> Run:
    """The rigid slipping rod of the paper as an engine: slip with F_z = -b/p, then what the first event says."""
    opts = options_from_kwargs(ToyOptions, options, "analytic flow (toy)")
    horizon = float(check("horizon", horizon, POSITIVE))
    th = thresholds or Thresholds()
    alpha = rod.alpha
    a = slip_until_event(state, mu, alpha, t_max=horizon)
    n = n_steps(horizon, opts.timestep)
    t = opts.timestep * np.arange(n)
    before = t < a.time  # the event row is the first one after the event
    x = {k: np.interp(np.minimum(t, a.time), a.t, a.x[:, i]) for i, k in enumerate(X_STATE)}
    eta, varphi, psi, Psi, theta, Theta = (x[k] for k in X_STATE)
    s, c = np.sin(theta), np.cos(theta)
    b = (Psi**2 * c**2 + Theta**2) * s - 1.0
    p = 1 + alpha + alpha * s * (mu * c * np.sin(varphi) - s)
    Fz = np.where(before, -b / p, 0.0)
    eta = np.where(before, eta, 0.0) if a.outcome == Outcome.STICK else eta
    u = np.stack([eta * np.cos(psi + varphi), eta * np.sin(psi + varphi), np.zeros(n)], axis=-1)
    F = np.stack([-mu * Fz * np.cos(psi + varphi), -mu * Fz * np.sin(psi + varphi), Fz], axis=-1)
    acc = np.zeros((n, 3))
    if a.outcome == Outcome.LIFTOFF:  # free flight: b has crossed 0 upwards
        acc[~before, 2] = 1e-3
    if a.outcome == Outcome.STICK:  # stuck: the plane carries the weight
        F[~before] = (0.0, 0.0, 1.0)
    record = Record(
        t=t,
        tip_pos=np.zeros((n, 3)),
        tip_vel=u.copy(),
        tip_acc=acc,
        force=F,
        normal_force=F[:, 2].copy(),
        active=F[:, 2] > 0,
        gap=np.zeros(n),
        slip_vel=u,
        psi=psi,
        theta=theta,
        Psi=Psi,
        Theta=Theta,
    )
    cl = classify(
        record,
        mu=mu,
        alpha=alpha,
        timestep=opts.timestep,
        friction_timeconst=opts.friction_time,
        rigid=True,
        thresholds=th,
    )
    return Run.from_classification(
        "toy", cl, record, state=state, mu=mu, alpha=alpha, options=opts, thresholds=th, horizon=horizon, nstep=n
    )


def sweep(rod, states, mu, *, horizon, thresholds=None, progress=True, **options):
    return sweep_by_simulate(
        engines.get("toy"), rod, states, mu, horizon=horizon, thresholds=thresholds, progress=progress, **options
    )


#: The toy engine's whole declaration: what it is, its tolerance profile (it is the theory: no event may differ
#: beyond its first-row rounding) and a map section at a coarse timestep.
#: The module is what runs it (``Options``, ``simulate``, ``sweep``), named by a lazy reference as a plugin's would be.
Options = ToyOptions

TOY = EngineSpec(
    name="toy",
    engine=__name__,
    label="analytic flow (toy)",
    tags={"rigid", "continuous"},
    validation=Validation(
        tolerances={
            k: Tolerance(atol=1e-12, rtol=0.0, why="the toy engine is the theory itself") for k in EVENT_TOLERANCE_KEYS
        }
    ),
    report=ReportPlan(maps={"quick": {"timestep": 1e-2}, "full": {"timestep": 1e-3}}),
)


@pytest.fixture
def toy():
    engine = engines.register(TOY)
    try:
        yield engine
    finally:
        engines.unregister("toy")


def test_registry_lists_and_refuses():
    assert "mujoco" in engines.names()
    assert engines.get("mujoco").name == "mujoco"
    with pytest.raises(ValueError, match=f"engine must be one of {', '.join(engines.names())}; got 'nope'"):
        engines.get("nope")
    with pytest.raises(ValueError, match="an engine named 'mujoco' is already registered"):
        engines.register(engines.get("mujoco"))
    with pytest.raises(ValueError, match="engine must be a crosscheck.engines.EngineSpec; got int"):
        engines.register(3)
    with pytest.raises(ValueError, match="engine 'x' tags must be among .*; got 'soft'"):
        EngineSpec(name="x", engine=__name__, tags={"soft"})
    with pytest.raises(ValueError, match="^tolerance profile lacks 'event_time'"):
        Validation(tolerances={"liftoff_onset": None, "event_disagreement": None})
    with pytest.raises(
        ValueError,
        match=r"^engine 'x' engine must be a reference 'package.module' or 'package.module:attr'; got 'a b'$",
    ):
        EngineSpec(name="x", engine="a b")
    with pytest.raises(ValueError, match="^engine 'x' ladder must be a Ladder or None; got dict$"):
        EngineSpec(name="x", engine=__name__, ladder={"geometry": "capsule"})
    with pytest.raises(ValueError, match="no registered engine named 'mujoco'"):
        engines.unregister("mujoco")


def test_a_registered_engine_is_available_by_name(toy):
    builtin = {e.name for package in engines.BUILTIN for e in __import__(package, fromlist=["ENGINES"]).ENGINES}
    assert engines.names() == sorted(builtin | {"toy"}) and engines.get("toy") is toy and engines.specs()[-1] is toy
    run = toy.simulate(
        Rod.scaled(3.0),
        SlipState(theta=0.6154797087, varphi=-math.pi / 2, Theta=0.0, Psi=1.7, eta=1.0),
        0.5,
        horizon=0.2,
    )
    assert run.engine == "toy" and run.outcome == Outcome.LIFTOFF and run.event_time == 0.0


def test_the_agreement_study_runs_on_a_toy_engine_and_finds_it_agrees(toy):
    """The analytic flow as an engine agrees with the analytic first events (no jams on this grid: mu < mu_P).

    The toy's records are exact (a stuck tip has eta = 0), so STICK is read at a slip speed of 1e-6:
    with the rigid default of 10 timesteps (1e-2 here), starts at eta = 0.05 whose slip direction swings
    round as eta -> 0 (the analytic run leaves the domain through varphi = 0 or -pi, censored as SLIP)
    read as STICK first (29 of 216 here).
    """
    g = EventGrid(
        theta=(0.3, 0.7, 1.1),
        varphi=(-math.pi / 2, -1.2),
        Theta=(-0.4, 0.0, 0.4),
        Psi=(-1.5, 0.0, 1.0),
        mu=(0.3, 1.0),
        eta=(0.05, 1.0),
    )
    res = agreement_study(
        g, engine="toy", horizon=1.0, boundary_directions=0, thresholds=Thresholds(rigid_stick_steps=1e-3)
    )
    (run,) = res.runs
    ao = res.analytic.outcome[res.index]
    assert res.engine == run.engine == "toy" and not np.any(ao == Outcome.JAM)
    assert {Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK} <= set(ao.tolist())
    assert run.n_rated >= 50
    assert run.agreement >= 0.98, run.confusion
    assert run.median_abs_time_difference <= ToyOptions().timestep  # events land on the first row after them


def test_a_registered_engine_gets_its_own_map_section_in_a_report(toy, tmp_path):
    """Registered from its record alone, the toy engine's map section is in the report (``--only toy_maps``), runs, and the
    theory-as-engine agrees with the theory on its maps but in two known ways: a slip that slows below the rigid
    STICK threshold (10 rows of its 1e-2 timestep) reads as STICK (the artefact explained in the agreement test
    above), and a theory JAM reads as SLIP (the toy writes no impulse at p = 0: it has no impact to record)."""
    import json

    from crosscheck.cli import main

    assert "toy_maps" in [s.slug for s in __import__("crosscheck.report", fromlist=["SECTIONS"]).SECTIONS]
    assert main(["report", "--quick", "--only", "toy_maps", "--out", str(tmp_path / "r")]) == 0
    maps = json.loads((tmp_path / "r" / "data" / "toy_maps" / "maps.json").read_text())
    assert len(maps) == 3
    for mp in maps:
        run = mp["runs"][0]
        assert run["engine"] == "toy" and run["n_rated"] > 0
        conf, labels = np.array(run["confusion"]), run["labels"]
        off = conf - np.diag(np.diag(conf))
        slip, lift, stick, jam = (labels.index(o) for o in ("SLIP", "LIFTOFF", "STICK", "JAM"))
        slowed = off[slip, stick] + off[lift, stick]
        assert off.sum() == slowed + off[jam, slip] and slowed <= 0.1 * conf.sum(), (labels, conf)
    # on the engine's own page, linked from the index's contents and from report.md
    assert "analytic flow (toy) vs analytic" in (tmp_path / "r" / "engine_toy.md").read_text()
    assert 'href="engine_toy.html"' in (tmp_path / "r" / "index.html").read_text()
    assert "](engine_toy.md)" in (tmp_path / "r" / "report.md").read_text()


@pytest.mark.parametrize(
    "promise",
    [
        "test_record_has_the_promised_shapes_units_and_finite_values",
        "test_simulate_equals_the_matching_row_of_sweep_and_repeats_exactly",
        "test_a_bad_option_gets_one_line_naming_it",
        "test_declaration_is_complete_and_its_libraries_are_in_provenance",
    ],
)
def test_the_toy_engine_keeps_the_engine_contract(toy, rod, promise):
    """The contract every built-in engine keeps (tests/test_engine_contract.py), kept by the toy from its record alone."""
    import test_engine_contract as contract

    fn = getattr(contract, promise)
    fn("toy", rod) if "rod" in fn.__code__.co_varnames[: fn.__code__.co_argcount] else fn("toy")


def test_kept_models_are_built_once_per_key_and_the_least_recently_used_dropped():
    from crosscheck.engines.kept import Kept

    built = []
    kept = Kept(2)
    make = lambda k: lambda: built.append(k) or f"model {k}"  # noqa: E731 - a builder that records its calls
    assert kept.get("a", make("a")) == "model a" and kept.get("a", make("a")) == "model a" and built == ["a"]
    kept.get("b", make("b"))
    kept.get("a", make("a"))  # a is now the most recently used: b goes first
    kept.get("c", make("c"))
    assert len(kept) == 2 and built == ["a", "b", "c"]
    kept.get("a", make("a"))
    kept.get("b", make("b"))
    assert built == ["a", "b", "c", "b"]
    with pytest.raises(ValueError, match=r"^size must be an integer >= 1; got 0$"):
        Kept(0)


def test_simulate_each_of_an_engine_without_a_batched_path_is_one_simulate_per_state(toy):
    rod = Rod.scaled(3.0)
    starts = [SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=Psi, eta=1.0) for Psi in (0.0, 0.8)]
    runs = toy.simulate_each(rod, starts, [0.5, 0.9], horizon=0.2)
    for run, s, mu in zip(runs, starts, (0.5, 0.9)):
        one = toy.simulate(rod, s, mu, horizon=0.2)
        assert (run.outcome, run.mu, run.state) == (one.outcome, mu, s)
        np.testing.assert_array_equal(run.event_time, one.event_time)
        np.testing.assert_array_equal(run.record.theta, one.record.theta)
    with pytest.raises(ValueError, match=r"^horizon must be one number or one per state \(2\); got 3 values$"):
        toy.simulate_each(rod, starts, 0.5, horizon=[0.1, 0.2, 0.3])


def test_an_engine_without_preload_or_provenance_hooks_does_nothing_and_says_nothing(toy):
    toy.preload()
    assert toy.provenance() == {}
    with pytest.raises(
        ValueError,
        match=r"^Execution preload must be a reference 'package.module' or 'package.module:attr'; got 'a b'$",
    ):
        Execution(preload="a b")
