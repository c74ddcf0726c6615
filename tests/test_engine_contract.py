"""The contract every registered engine keeps (dm_control's ALL_TASKS habit): one test per engine and promise.

Parametrised over ``crosscheck.engines.names()``, so an engine added to the
registry (built in, or an installed plugin found through the ``crosscheck.engines``
entry points: tests/test_engine_plugin.py runs this file with the example installed)
is held to it without touching this file: its record's shapes, units
and finiteness, ``simulate`` equal to the matching row of ``sweep``, two runs
identical, the exact one-line message for a bad option, a well-formed
tolerance profile and tags, and its libraries in the report's provenance.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from crosscheck import engines
from crosscheck.engines import TAGS
from crosscheck.engines.record import FIELDS
from crosscheck.outcome import Outcome
from crosscheck.report.provenance import package_versions
from crosscheck.state import SlipState
from crosscheck.tolerances import EVENT_TOLERANCE_KEYS, Tolerance

ENGINES = engines.names()

#: A slipping start (b < 0 < p at mu = 0.5: it keeps slipping for the horizon below) and a second, off the
#: planar section with a rate, so a two-state sweep has two different rows.
STATES = (
    SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.0, eta=1.0),
    SlipState(theta=0.8, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.5, psi=0.4),
)
MU = 0.5

#: Scaled time simulated: a few windows of the classifier is more than the record's promises need, and short
#: enough for the continuous-time engines (an adaptive Radau run of the compliant rod takes ~0.3 s for 0.05).
HORIZON = 0.05

VECTORS = ("tip_pos", "tip_vel", "tip_acc", "force", "slip_vel")


def _options(spec) -> dict:
    """The engine's default options with a timestep fine enough for HORIZON to hold several rows."""
    opts = spec.options()
    return {"timestep": min(opts.timestep, HORIZON / 10)} if opts.timestep > HORIZON / 10 else {}


@pytest.mark.parametrize("name", ENGINES)
def test_record_has_the_promised_shapes_units_and_finite_values(name, rod):
    spec = engines.get(name)
    opts = _options(spec)
    run = spec.simulate(rod, STATES[0], MU, horizon=HORIZON, **opts)
    r, n = run.record, len(run.record)
    assert run.engine == name and run.outcome in set(Outcome) and n == run.nstep >= 2
    for f in FIELDS:
        x = getattr(r, f)
        assert x.shape == ((n, 3) if f in VECTORS else (n,)), f
        if f != "active":
            assert np.all(np.isfinite(x)), f
    # rows every timestep from t = 0 (scaled time), the start's angles and rates in row 0, slip horizontal
    timestep = spec.options(**opts).timestep
    np.testing.assert_allclose(np.diff(r.t), timestep, rtol=1e-9, atol=1e-12)
    assert r.t[0] == pytest.approx(0.0, abs=1e-12)
    for k in ("theta", "Theta", "Psi"):
        assert getattr(r, k)[0] == pytest.approx(getattr(STATES[0], k), abs=1e-9), k
    assert np.all(r.slip_vel[:, 2] == 0.0)
    # a slipping start on the plane: its contact point starts on it (within the engine's resting penetration) and slips at eta
    assert abs(r.gap[0]) < 1e-3 and r.eta[0] == pytest.approx(STATES[0].eta, rel=1e-6)


@pytest.mark.parametrize("name", ENGINES)
def test_simulate_equals_the_matching_row_of_sweep_and_repeats_exactly(name, rod):
    spec = engines.get(name)
    opts = _options(spec)
    res = spec.sweep(rod, list(STATES), MU, horizon=HORIZON, progress=False, **opts, **spec.one_core)
    assert len(res) == len(STATES) and res.engine == name
    for i, s in enumerate(STATES):
        a = spec.simulate(rod, s, MU, horizon=HORIZON, **opts)
        b = spec.simulate(rod, s, MU, horizon=HORIZON, **opts)
        for f in FIELDS:
            np.testing.assert_array_equal(getattr(a.record, f), getattr(b.record, f), err_msg=f)
        assert res.outcome[i] == a.outcome
        np.testing.assert_array_equal(res.event_time[i], a.event_time)
    if spec.solver_columns:
        assert set(spec.solver_columns) <= set(res.solver)


@pytest.mark.parametrize("name", ENGINES)
def test_a_bad_option_gets_one_line_naming_it(name, rod):
    spec = engines.get(name)
    known = ", ".join(sorted(f for f in spec.Options.__dataclass_fields__))
    with pytest.raises(ValueError) as e:
        spec.simulate(rod, STATES[0], MU, horizon=HORIZON, no_such_option=1.0)
    assert str(e.value) == f"unknown {spec.label} option 'no_such_option': options must be one of {known}"
    with pytest.raises(ValueError) as e:
        spec.simulate(rod, STATES[0], MU, horizon=-1.0)
    assert "\n" not in str(e.value) and "horizon" in str(e.value) and "-1" in str(e.value)


@pytest.mark.parametrize("name", ENGINES)
def test_declaration_is_complete_and_its_libraries_are_in_provenance(name):
    spec = engines.get(name)
    assert spec.tags <= TAGS and spec.label and spec.slug.isidentifier()
    assert not ({"rigid", "compliant"} <= spec.tags), "a contact is rigid or compliant, not both"
    assert ("time_stepping" in spec.tags) != ("continuous" in spec.tags), "a run is time-stepped or continuous"
    if spec.tolerances is not None:
        assert set(spec.tolerances) == set(EVENT_TOLERANCE_KEYS)
        assert all(isinstance(t, Tolerance) and t.why for t in spec.tolerances.values())
    versions = package_versions()
    for lib in spec.libraries:
        assert versions.get(lib), f"{lib} is not in the report's provenance or not installed"
    # every rung of its ladder is a model crosscheck.studies.ladder can run
    for cause, rung in (spec.ladder or {}).items():
        if rung not in ("capsule", "engine"):
            module, _, attr = rung.partition(":")
            assert callable(getattr(importlib.import_module(module), attr)), (cause, rung)
    # the options it runs with are valid as declared (its defaults, its report settings)
    spec.options()
    plan = spec.report
    if plan is not None:
        for which in ("quick", "full"):
            if plan.maps is not None:
                spec.options(**plan.maps[which])
            for setting in (plan.convergence or {}).get(which, []):
                spec.options(**setting)


#: Engines whose ``simulate`` can stop a run once its first event is judged (``EngineSpec.stops_at_event``).
STOPPING = [n for n in ENGINES if engines.get(n).stops_at_event]


def test_the_time_stepping_engines_declare_that_they_stop_at_their_first_event():
    assert {n for n in STOPPING} == {n for n in ENGINES if n.startswith(("drake_", "physx_"))} | {"bullet", "dart"}


@pytest.mark.parametrize("name", STOPPING)
def test_first_event_stops_early_with_the_whole_runs_outcome_and_event_time(name, rod):
    """The ladders' and interventions' run (``EngineSpec.first_event``) stops where the engine declares it can, and
    gives what the whole run gives."""
    spec = engines.get(name)
    state = SlipState(theta=1.2, varphi=-1.9, Theta=0.9, Psi=0.0, eta=1.0)  # lifts off at once at mu 1.4
    whole = spec.simulate(rod, state, 1.4, horizon=0.6)
    cut = spec.simulate(rod, state, 1.4, horizon=0.6, until_event=True)
    assert np.isfinite(whole.event_time) and np.isfinite(cut.record.t).sum() < len(whole.record)  # it stopped early
    assert spec.first_event(rod, state, 1.4, horizon=0.6) == (Outcome(int(whole.outcome)), float(whole.event_time))


def test_stops_at_event_must_be_a_bool():
    from crosscheck.engines.spec import Execution

    for bad in (1, "yes", None):
        with pytest.raises(ValueError, match=r"^stops_at_event must be True or False; got "):
            Execution(stops_at_event=bad)
