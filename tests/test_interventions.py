"""Interventions on the engine itself: every engine with a ladder declares one per cause, each changes the engine the way
its cause names, and on a start whose cause is known the right one removes the disagreement and the wrong one does not."""

from __future__ import annotations

import math

import pytest

from crosscheck import Rod, engines
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.spec import LADDER_CAUSES, EngineSpec, Intervention, Ladder
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.studies.comparison import LAG_TAU
from crosscheck.studies.interventions import intervene, summarise
from crosscheck.studies.ladder import run_ladder
from crosscheck.theory.jam_lag import P_FLOOR
from crosscheck.theory.slipping import slip_until_event

LADDERED = [s.name for s in engines.specs() if s.ladder is not None and s.report is not None]


def _settings(spec):
    """The options each report runs the engine at: its defaults and its maps' options."""
    out = [spec.options()]
    if spec.report and spec.report.maps:
        out += [spec.options(**spec.report.maps[k]) for k in ("quick", "full")]
    return out


@pytest.mark.parametrize("name", LADDERED, ids=str)
def test_every_laddered_cause_has_an_intervention_the_engine_accepts(name):
    spec = engines.get(name)
    rungs = [c for c in LADDER_CAUSES if c in spec.ladder]
    assert set(spec.interventions or ()) == set(rungs), (
        f"{name}: interventions for {sorted(spec.interventions or ())}, ladder {rungs}"
    )
    for base in _settings(spec):
        given = {k: getattr(base, k) for k in base.__dataclass_fields__}
        for cause in rungs:
            ivs = spec.interventions_for(cause, base)
            assert ivs and all(isinstance(iv, Intervention) and iv.options for iv in ivs)
            for iv in ivs:
                spec.options(**{**given, **iv.options})  # valid options of the engine (ValueError otherwise)


@pytest.mark.parametrize(
    "p_min", [None, 0.01, 2.0], ids=["start unknown", "slip close to p = 0", "slip far from p = 0"]
)
@pytest.mark.parametrize("name", LADDERED, ids=str)
def test_each_intervention_moves_the_engine_the_way_its_cause_names(name, p_min):
    """Geometry: a thinner capsule; compliance: a shorter contact time; discretisation: a shorter step; weakest first."""
    spec = engines.get(name)
    for base in _settings(spec):
        for cause, attr in (("geometry", "radius"), ("compliance", "contact_time"), ("discretisation", "timestep")):
            if cause not in (spec.interventions or {}):
                continue
            given = {k: getattr(base, k) for k in base.__dataclass_fields__}
            values = [
                getattr(spec.options(**{**given, **iv.options}), attr)
                for iv in spec.interventions_for(cause, base, p_min=p_min)
            ]
            now = getattr(base, attr)
            assert all(v < now for v in values) and values == sorted(values, reverse=True), (cause, now, values)


def test_a_spring_contact_gets_its_strongest_stiffening_again_at_the_closest_approach_to_p_zero():
    """Drake's point contact: stiffness / p_min and timestep * p_min^(1/2) beyond the strongest, only where p_min < 1."""
    spec = engines.get("drake_tamsi")
    base = spec.options()
    strongest = spec.interventions_for("compliance", base)[-1].options
    for p_min, slower in ((0.01, 10.0), (1e-6, 1 / math.sqrt(P_FLOOR))):
        *given, closest = spec.interventions_for("compliance", base, p_min=p_min)
        assert [iv.options for iv in given] == [iv.options for iv in spec.interventions_for("compliance", base)]
        assert math.isclose(closest.options["stiffness"], strongest["stiffness"] * slower**2, rel_tol=1e-12)
        assert math.isclose(closest.options["timestep"], strongest["timestep"] / slower, rel_tol=1e-12)
    for p_min in (
        1.0,
        3.5,
        math.nan,
        0.0,
        -0.2,
    ):  # far from p = 0, unknown, or a slip that reaches it (a jam: its own lag)
        assert spec.interventions_for("compliance", base, p_min=p_min) == spec.interventions_for("compliance", base)


def test_an_intervention_outside_the_ladder_is_refused():
    with pytest.raises(
        ValueError,
        match=r"^intervention causes must be among the ladder's \(geometry\); got 'compliance'$",
    ):
        Ladder(rungs={"geometry": "capsule"}, interventions={"compliance": "x:y"})


#: A start where Drake SAP launches the tip off the plane while the theory slips (the quick report's SAP ladder: rung 5,
#: TAMSI at the same step, slips; SAP itself launches, so the ladder names the relaxation).
SAP_LAUNCH = (SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.25, eta=1.0), 0.25)


def test_sap_launch_is_removed_by_dropping_the_relaxation_not_by_a_thinner_capsule():
    state, mu = SAP_LAUNCH
    r = intervene("drake_sap", state, mu, causes=("geometry", "relaxation"))
    assert r["theory"] == "SLIP"
    assert [x["label"] for x in r["causes"]["geometry"]] == ["LAUNCH", "LAUNCH"]
    assert [x["removes"] for x in r["causes"]["geometry"]] == [False, False]
    assert r["causes"]["relaxation"][-1]["label"] == "SLIP" and r["causes"]["relaxation"][-1]["removes"]


#: A start of the full report's Drake continuous maps (theta_Theta_0) where the theory jams at t = 0.0039 and the continuous
#: plant at its default stiffness slips past the comparison window (its ladder names compliance).
CONTINUOUS_LATE_JAM = (SlipState(theta=1.0125, varphi=-1.9, Theta=-0.375, Psi=0.0, eta=1.0), 1.4)


def test_a_late_compliant_jam_is_removed_by_a_stiffer_contact():
    """The continuous plant's jam comes later the softer its contact: a spring contact's slip stop lags the rigid jam by
    s* (eps^4 / (k |b|))^(1/5) (``crosscheck.theory.jam_lag``).  x 10, x 100 and x 1000 (at a tenth of the step) stiffer it
    jams at 0.015, 0.007 and 0.0031 against the theory's 0.0039: ever closer, each within its spring lag, the first two
    later than LAG_TAU contact times (the lag every other event gets, which would not confirm them)."""
    state, mu = CONTINUOUS_LATE_JAM
    r = intervene("drake_continuous", state, mu, causes=("compliance",))
    assert r["theory"] == "JAM" and r["theory_time"] == pytest.approx(0.0039, abs=1e-4)
    rows = r["causes"]["compliance"]
    assert [x["removes"] for x in rows] == [True, True, True], [(x["text"], x["outcome"], x["time"]) for x in rows]
    assert all(x["outcome"] == "JAM" for x in rows)
    lags = [x["time"] - r["theory_time"] for x in rows]
    assert all(abs(a) > abs(b) for a, b in zip(lags, lags[1:])), lags
    for x, lag in zip(rows[:2], lags[:2]):
        assert lag > LAG_TAU * engines.get("drake_continuous").options(**x["options"]).contact_time, (x["text"], lag)


#: A start of the full report's Psi_mu map whose theory slips to its exit from the paper's chart (varphi = -pi at
#: t = 0.788) with its slip speed falling to 2.6e-3 on the way: below every engine's STICK floor (0.01 here).
SLIP_BELOW_FLOOR = (SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.875, eta=1.0), 0.875)


def test_a_stick_where_the_theory_slips_slower_than_the_stick_floor_is_compared_as_that_slip():
    """The rigid engine, which follows the theory step by step, is classified STICK within two steps of the time the
    theory's own eta crosses its STICK floor (10 timesteps), while the exact theory slips on to its chart's edge at 0.788:
    the classifier cannot tell that STICK from the theory's slip, and the comparison reads it as the slip.  A STICK
    well before the theory's slip got that slow stays a disagreement."""
    from crosscheck.studies.comparison import compared_label, event_lag, stick_from

    state, mu = SLIP_BELOW_FLOOR
    raw = slip_until_event(state, mu, 3.0, t_max=2.0)
    assert raw.outcome == Outcome.SLIP and raw.reason == "varphi=-pi"
    r = intervene("pinocchio", state, mu, causes=())
    opts = engines.get("pinocchio").options()
    assert r["stick_floor"] == pytest.approx(Thresholds().rigid_stick_steps * opts.timestep)
    assert r["theory"] == "SLIP" and r["theory_eta_min"] < r["stick_floor"] and r["theory_below_floor_time"] < raw.time
    run = engines.get("pinocchio").simulate(Rod.scaled(3.0), state, mu, horizon=raw.time + 0.05)
    assert run.outcome == Outcome.STICK and abs(run.event_time - r["theory_below_floor_time"]) <= 2 * opts.timestep
    since = float(
        stick_from(Outcome.SLIP, raw.time, r["theory_below_floor_time"], event_lag(opts.contact_time, opts.timestep))
    )
    assert compared_label(run.outcome, run.event_time, raw.time, since) == Outcome.SLIP
    assert compared_label(Outcome.STICK, run.event_time - 0.1, raw.time, since) == Outcome.STICK
    # a slip whose speed stays above the floor (eta >= 0.18 to its chart exit at 0.42) has no such STICK
    other = intervene(
        "mujoco", SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=1.453125, eta=1.0), 1.359375, causes=()
    )
    assert (
        other["theory"] == "SLIP"
        and other["theory_eta_min"] > other["stick_floor"]
        and other["theory_below_floor_time"] != other["theory_below_floor_time"]
    )


def test_a_refused_intervention_is_reported_not_raised():
    state, mu = SAP_LAUNCH
    spec = engines.get("drake_sap")
    toy = EngineSpec(
        name="toy_bad_intervention",
        engine=spec.engine,
        defaults=spec.defaults,
        ladder=Ladder(rungs={"geometry": "capsule"}, interventions={"geometry": f"{__name__}:_bad"}),
    )
    engines.register(toy)
    try:
        r = intervene("toy_bad_intervention", state, mu)
    finally:
        engines.unregister("toy_bad_intervention")
    row = r["causes"]["geometry"][0]
    assert row["status"] == "failed" and row["detail"].startswith("ValueError: timestep") and not row["removes"]


def _bad(options):
    return (Intervention("timestep -> negative", {"timestep": -1.0}),)


def _result(cause, fixes: dict):
    """fixes: cause -> (removes at the weaker step, removes at the stronger)."""
    return {
        "cause": cause,
        "interventions": {
            "theory": "SLIP",
            "causes": {
                c: [{"text": f"{c} weaker", "removes": w}, {"text": f"{c} stronger", "removes": s}]
                for c, (w, s) in fixes.items()
            },
        },
    }


def test_summary_counts_confirmed_misattributed_and_unremoved():
    no, yes, weak = (False, False), (False, True), (True, False)
    results = [
        _result("geometry", {"geometry": yes, "compliance": no}),
        _result("geometry", {"geometry": weak, "compliance": no}),
        _result("geometry", {"geometry": no, "compliance": yes}),
        _result("compliance", {"geometry": no, "compliance": no}),
        _result("unexplained", {"geometry": yes, "compliance": no}),
        _result("friction law", {"geometry": no, "compliance": no}),
    ]
    s = summarise(results)
    assert s["attributed"] == 5 and s["confirmed"] == 2 and math.isclose(s["confirmed_share"], 0.4)
    g = s["per_cause"]["geometry"]
    assert (g["n"], g["confirmed"], g["not_at_strongest"], g["by_other"], g["none"]) == (3, 2, 1, {"compliance": 1}, 0)
    assert s["per_cause"]["compliance"]["none"] == 1
    assert s["per_cause"]["unexplained"]["by_other"] == {"geometry": 1}
    assert s["per_cause"]["friction law"]["no_intervention"] == 1
    assert (s["n"], s["removed_by_any"]) == (
        6,
        4,
    )  # all but the compliance and friction-law starts no intervention removes
    assert g["by_intervention"] == {
        "geometry weaker": 1,
        "geometry stronger": 1,
    }  # each of the cause's own, over its starts
    assert g["tried"] == {"geometry weaker": 3, "geometry stronger": 3}


def test_summary_counts_a_step_only_some_starts_get_out_of_those_starts():
    near = _result("compliance", {"compliance": (False, False)})
    near["interventions"]["causes"]["compliance"].append(
        {"text": "compliance at the closest approach", "removes": True}
    )
    far = _result("compliance", {"compliance": (False, True)})
    row = summarise([near, far])["per_cause"]["compliance"]
    assert (
        row["by_intervention"]["compliance at the closest approach"] == 1
        and row["tried"]["compliance at the closest approach"] == 1
    )
    assert row["tried"]["compliance stronger"] == 2 and row["confirmed"] == 2


def test_summary_counts_a_disagreement_removed_only_jointly_apart_from_confirmed_and_none():
    no = (False, False)
    joint = _result("geometry", {"geometry": no, "compliance": no})
    joint["interventions"]["joint"] = [{"with": "compliance", "removes": True}]
    still = _result("geometry", {"geometry": no, "compliance": no})
    still["interventions"]["joint"] = [{"with": "compliance", "removes": False}]
    s = summarise([joint, still])
    g = s["per_cause"]["geometry"]
    assert (s["confirmed"], s["jointly"], g["jointly"], g["none"], s["removed_by_any"]) == (
        0,
        1,
        {"compliance": 1},
        1,
        1,
    )


#: A start of the full report's Drake continuous theta-Theta map (Psi 1.7) where the theory slips on (p down to 0.026)
#: and the continuous plant jams at 0.026: so does the rigid rod at the capsule point C (r = 0.01, at 0.007), and so does
#: Drake's point contact with a capsule 16 times thinner (its softness alone) or 1000 times stiffer (its capsule alone).
OVERDETERMINED_JAM = (SlipState(theta=1.0125, varphi=-1.9, Theta=-0.125, Psi=1.7, eta=1.0), 1.4)


def test_an_overdetermined_jam_is_removed_only_by_the_thinner_capsule_and_the_stiffer_contact_together_as_the_ladder_predicts():
    """The ladder names geometry (the rigid capsule jams); its compliant rod with the capsule as thin as the geometry
    intervention makes it jams too, so the ladder itself says the softness alone also gives the jam: the pair, which
    the two interventions together confirm on Drake (neither alone removes it)."""
    state, mu = OVERDETERMINED_JAM
    assert run_ladder("drake_continuous", state, mu).cause == "geometry"
    r = intervene("drake_continuous", state, mu, causes=("geometry", "compliance"), named="geometry", reference="JAM")
    assert r["theory"] == "SLIP"
    assert not any(x["removes"] for x in r["causes"]["geometry"]) and not any(
        x["removes"] for x in r["causes"]["compliance"]
    )
    # (the compliance rows: x 10, x 100, x 1000 at a tenth of the step, and that again at the slip's closest approach to p = 0)
    assert [x["outcome"] for x in r["causes"]["geometry"] + r["causes"]["compliance"]] == ["JAM"] * 6
    (joint,) = r["joint"]
    assert (
        joint["with"] == "compliance"
        and joint["removes"]
        and joint["options"]["radius"] < 0.001
        and joint["options"]["stiffness"] > 1e6
    )
    thin = r["without_offset"]
    assert thin["radius"] == r["causes"]["geometry"][-1]["options"]["radius"] and thin["also"] == "compliance"
    # the rigid capsule that thin slips on as the theory does (the intervention is thin enough), the compliant rod jams
    assert thin["rungs"] == [{"cause": "geometry", "label": "SLIP"}, {"cause": "compliance", "label": "JAM"}]
    s = summarise([{"cause": "geometry", "interventions": r}])
    assert (s["confirmed"], s["jointly"], s["per_cause"]["geometry"]["overdetermined"]) == (1, 0, {"compliance": 1})
    assert s["pairs"] == {"predicted": 1, "confirmed": 1, "geometry alone": 0, "another alone": 0, "joint failed": 0}


def test_summary_confirms_a_pair_only_where_the_ladder_named_it_and_the_two_interventions_together_remove_it():
    no, yes = (False, False), (False, True)

    def start(also, fixes, joint_removes):
        r = _result("geometry", fixes)
        rungs = [
            {"cause": "geometry", "label": "SLIP"},
            *({"cause": c, "label": "JAM"} for c in ("compliance", "friction law")[: 1 + (also == "friction law")]),
        ]
        r["interventions"]["without_offset"] = {"radius": 0.001, "rungs": rungs, "also": also}
        r["interventions"]["joint"] = [{"with": "compliance", "removes": joint_removes}]
        return r

    s = summarise(
        [
            start("compliance", {"geometry": no, "compliance": no}, True),  # the ladder's pair, removed together
            start(None, {"geometry": no, "compliance": no}, True),  # the ladder saw no pair: only jointly
            start("friction law", {"geometry": no, "compliance": no}, True),  # the ladder's pair is another one
            start("compliance", {"geometry": yes, "compliance": no}, False),  # the offset alone after all
            start("compliance", {"geometry": no, "compliance": no}, False),
        ]
    )  # the two together fail
    g = s["per_cause"]["geometry"]
    assert (s["confirmed"], g["overdetermined"], s["jointly"], g["jointly"], g["none"]) == (
        2,
        {"compliance": 1},
        2,
        {"compliance": 2},
        1,
    )
    assert s["pairs"] == {"predicted": 4, "confirmed": 1, "geometry alone": 1, "another alone": 0, "joint failed": 2}


def test_a_cause_with_two_families_is_removed_at_the_strongest_when_the_last_of_either_removes_it():
    """MuJoCo's feed-forward lowered on every row or with the friction rows kept: removed by the strongest of the first
    family is not 'removed at a weaker step but not at the strongest', though the second family's last comes after it."""
    rows = [
        {"text": "a 0.1", "removes": False, "family": "a"},
        {"text": "a 0.01", "removes": True, "family": "a"},
        {"text": "b 0.5", "removes": True, "family": "b"},
        {"text": "b 0.01", "removes": False, "family": "b"},
    ]
    r = {"cause": "feed-forward", "interventions": {"theory": "SLIP", "causes": {"feed-forward": rows}}}
    assert summarise([r])["per_cause"]["feed-forward"]["not_at_strongest"] == 0
    rows[1]["removes"] = False
    assert summarise([r])["per_cause"]["feed-forward"]["not_at_strongest"] == 1


#: A start of the full report's theta-Theta map where MuJoCo's slip stops at once (JAM at t = 0) while the theory lifts
#: off at t = 0.030: the start is near p = 0, where the skew of MuJoCo's friction off the slip (p_eff depends on the
#: friction's direction) makes its own p negative.  The full report's ladder named geometry (the rigid rod at the capsule
#: point C jams too).
MUJOCO_SKEW_JAM = (SlipState(theta=0.992, varphi=-1.9, Theta=0.891, Psi=0.0, eta=1.0), 1.4)


def test_mujoco_skew_jam_is_removed_by_a_smaller_impratio_not_by_a_thinner_capsule():
    """impratio 0.1 (an isotropic friction regulariser ten times the normal one) turns MuJoCo's friction toward -u and
    the tip lifts off as the theory's does; a capsule 16 times thinner still jams: the geometry the ladder named is not
    what MuJoCo needs changed here (a misattribution the interventions section lists)."""
    state, mu = MUJOCO_SKEW_JAM
    r = intervene("mujoco", state, mu, causes=("geometry", "friction law"), timestep=3e-4)
    assert r["theory"] == "LIFTOFF"
    assert [x["label"] for x in r["causes"]["geometry"]] == ["JAM", "JAM"]
    by_text = {x["text"]: x for x in r["causes"]["friction law"]}
    assert by_text["impratio 1 -> 0.1"]["label"] == "LIFTOFF" and by_text["impratio 1 -> 0.1"]["removes"]
    # too soft a friction no longer stops anything: the tip keeps slipping past the theory's lift-off
    assert by_text["impratio 1 -> 0.01"]["label"] == "SLIP" and not by_text["impratio 1 -> 0.01"]["removes"]


#: A start of the theta-Theta map where the theory jams at t = 0.031 (p reaches 0 with b < 0; the capsule's p_C at 0.025)
#: and MuJoCo's slip ends in a STICK at 0.083, its contact point's own p_eff above the jam rule's.  The ladder names the
#: feed-forward: MuJoCo's law without it (rung 4) jams at 0.097, as the Kelvin-Voigt rod does, and with it (rung 5)
#: sticks at 0.085.  (The start used before, theta 0.992, Theta -0.703, now agrees: its stop is at the capsule's
#: p_C < 0, a JAM.)
MUJOCO_FED_STICK = (SlipState(theta=1.2359375, varphi=-1.9, Theta=-0.984375, Psi=0.0, eta=1.0), 1.4)


def test_mujoco_stick_before_the_jam_is_removed_by_less_feed_forward_not_by_a_closer_friction_direction():
    """Impedance 0.1: MuJoCo applies a tenth of the rigid force at once and builds the rest through its spring, as the matched
    Kelvin-Voigt rod does; the slip then lasts until p crosses 0 and ends in a jam.  A shorter friction time constant or a
    smaller impratio (the friction's direction) still stick: the ladder's feed-forward is confirmed on MuJoCo, the friction law is not."""
    from crosscheck.studies.ladder import run_ladder

    state, mu = MUJOCO_FED_STICK
    assert run_ladder("mujoco", state, mu, timestep=3e-4).cause == "feed-forward"
    r = intervene("mujoco", state, mu, causes=("friction law", "feed-forward"), timestep=3e-4)
    assert r["theory"] == "JAM"
    fed = {x["text"].split(" (")[0]: x for x in r["causes"]["feed-forward"]}
    assert fed["impedance 0.95 -> 0.1"]["label"] == "JAM" and fed["impedance 0.95 -> 0.1"]["removes"]
    # with the friction rows' regulariser kept (impratio raised as R_n grows), as the ladder's rung keeps it
    assert fed["impedance 0.95 -> 0.1"]["options"]["impratio"] == pytest.approx((0.9 / 0.1) / (0.05 / 0.95), rel=1e-12)
    direction = r["causes"]["friction law"]
    assert len(direction) == 4 and not any(x["removes"] for x in direction)


#: A start of the theta-Theta map whose theory slip passes p = 0.077 and goes on slipping (SLIP at the domain's edge at
#: 0.498) while MuJoCo jams in its first steps; the ladder names the feed-forward.
MUJOCO_FED_JAM = (SlipState(theta=0.9921875, varphi=-1.9, Theta=-0.234375, Psi=1.7, eta=1.0), 1.4)


def test_mujoco_feed_forward_near_p_zero_is_removed_with_the_friction_rows_softened_alike_not_kept_stiff():
    """Lowering the impedance on every row, as MuJoCo has one impedance per contact, lets the slip go on as the theory's does;
    lowering it with the friction rows' regulariser kept leaves stiff friction rows that MuJoCo's cone problem carries by
    raising the normal force, and the slip still stops (a jam, or at 0.01 a lift-off).  Both are the feed-forward removed,
    neither alone, so both run and either confirms it."""
    from crosscheck.studies.ladder import run_ladder

    state, mu = MUJOCO_FED_JAM
    assert run_ladder("mujoco", state, mu, timestep=3e-4).cause == "feed-forward"
    r = intervene("mujoco", state, mu, causes=("feed-forward",), timestep=3e-4)
    assert r["theory"] == "SLIP" and 0 < r["theory_p_min"] < Thresholds().jam_p_eff
    fed = {x["text"].split(" (")[0]: x for x in r["causes"]["feed-forward"]}
    assert (
        fed["impedance 0.95 -> 0.1 on every row"]["removes"] and fed["impedance 0.95 -> 0.01 on every row"]["removes"]
    )
    assert "impratio" not in fed["impedance 0.95 -> 0.1 on every row"]["options"]
    kept = [fed[f"impedance 0.95 -> {d}"] for d in ("0.5", "0.1", "0.01")]
    assert [x["label"] for x in kept[:2]] == ["JAM", "JAM"] and not any(x["removes"] for x in kept)


def test_summary_splits_the_confirmed_by_how_close_the_theory_slip_comes_to_p_zero():
    no, yes = (False, False), (False, True)
    results = [
        _result("geometry", {"geometry": yes}),
        _result("geometry", {"geometry": no}),
        _result("geometry", {"geometry": yes}),
        _result("unexplained", {"geometry": yes}),
    ]
    for r, p_min in zip(results, (0.05, 0.15, 0.6, 0.01)):
        r["interventions"]["theory_p_min"] = p_min
    s = summarise(
        results
    )  # the band is the classifier's jam_p_eff, 0.2: the first two starts and the unattributed one in it
    assert s["by_p"]["p_band"] == Thresholds().jam_p_eff
    assert s["by_p"]["in_band"] == {"attributed": 2, "confirmed": 1} and s["by_p"]["above"] == {
        "attributed": 1,
        "confirmed": 1,
    }
    narrow = summarise(results, p_band=0.1)
    assert narrow["by_p"]["in_band"] == {"attributed": 1, "confirmed": 1} and narrow["by_p"]["above"] == {
        "attributed": 2,
        "confirmed": 1,
    }


def test_summary_splits_the_confirmed_by_the_start_s_distance_to_the_theory_s_event_boundary():
    no, yes = (False, False), (False, True)
    results = [
        _result("geometry", {"geometry": yes}),
        _result("geometry", {"geometry": no}),
        _result("compliance", {"compliance": yes}),
        _result("geometry", {"geometry": yes}),
        _result("unexplained", {"geometry": yes}),
        _result("geometry", {"geometry": no}),
    ]
    # as saved: "inf" beyond the largest probe (JSON has no inf), None where the map section did not probe
    for r, d in zip(results, (0.01, 0.01, "inf", 0.3, 0.01, None)):
        r["boundary_distance"] = d
    s = summarise(results)
    assert s["by_distance"] == [
        {"distance": 0.01, "attributed": 2, "confirmed": 1},
        {"distance": 0.3, "attributed": 1, "confirmed": 1},
        {"distance": math.inf, "attributed": 1, "confirmed": 1},
    ]
    assert summarise(results[-1:])["by_distance"] == []


def test_each_start_gets_the_boundary_distance_of_its_own_row_of_its_map():
    from crosscheck.report.sections.engine_intervention_runs import boundary_distances

    state = {"theta": 1.0125, "varphi": -1.9, "Theta": -0.125, "Psi": 1.7, "eta": 1.0}
    table = {
        **{k: [v, v, v] for k, v in state.items()},
        "mu": [1.4, 1.5, 1.6],
        "boundary_distance": [0.03, math.inf, math.nan],
    }
    starts = [{"map": "m", "state": state, "mu": mu} for mu in (1.4, 1.5, 1.6, 1.7)] + [
        {"map": "other", "state": state, "mu": 1.4}
    ]
    boundary_distances(starts, {"m": table})
    assert [st["boundary_distance"] for st in starts] == [
        0.03,
        math.inf,
        None,
        None,
        None,
    ]  # NaN: not probed; no row; no table
    boundary_distances(starts[:1], {"m": {**table, "mu": [1.4, 1.4, 1.6]}})  # two rows of that start: not one, so none
    assert starts[0]["boundary_distance"] is None
    boundary_distances(starts[:1], {"m": {k: v for k, v in table.items() if k != "boundary_distance"}})
    assert starts[0]["boundary_distance"] is None
