"""Event agreement, analytic first events vs MuJoCo (issue 4, 5c and 5d): small grids, real engines."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from crosscheck import Outcome, Rod, SlipState
from crosscheck.mujoco_agreement import (
    AXES,
    P_EFF_JAM,
    EventGrid,
    agreement_study,
    boundary_distance,
    classified_rollout,
    convergence_table,
    friction_skew,
    jam_check,
    mujoco_labels,
    study_thresholds,
)
from crosscheck.critical import Psi_on_b0
from crosscheck.mujoco_rod import Options, simulate
from crosscheck.mujoco_sweep import sweep
from crosscheck.slipping import slip_until_event
from crosscheck.tolerances import MUJOCO_EVENT_DISAGREEMENT

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
COARSE = {"timestep": 1e-3, "timeconst": 0.1}  # ~0.3 ms and 32 ms for a 1 m rod: fast, still resolved

#: A hopping (chattering) tip at mu = 1.3 < mu_P whose landing at t = 0.62 passes part A's JAM tests
#: (window-mean force 1.5-1.7 m g > 3 (-b/p), slip loss > 20 %; part A's classify says JAM when this
#: was written) although MuJoCo's own p_eff there is 0.45.
HOPPING_BELOW_MU_P = (SlipState(theta=0.6113389398285725, varphi=-0.77475770919191, Theta=0.45376828769404165, Psi=0.3126466205827283, eta=2.343864226276094), 1.3)

#: A slip at mu = 1.3 < mu_P in near-continuous contact with p ~0.05 (eq. p; p >= 0.04 at mu = 1.3):
#: MuJoCo's force is the slipping -b/p_eff of 15-20 m g and b reaches 0 (lift-off, analytic at t =
#: 0.066) inside the first window.  With the window mean of b (not of max(0, -b)) the lift-off's b > 0
#: rows cancelled the slipping force and classify_effective said JAM at t = 0.006 (full report, seed 0).
NEAR_JAM_SLIP_BELOW_MU_P = (SlipState(theta=1.061401264098454, varphi=-1.5792227104861805, Theta=0.4796557348275663, Psi=0.5291082563291338,
                                      eta=2.039633923548985), 1.3)

#: A Corollary 4.2 state (mu = 1.7 > mu_P): analytic JAM at t = 0.460 with b < 0, off the planar
#: section; MuJoCo delivers an impulse there (window force ~7 m g, p_eff ~0.09) and the tip lifts off.
COROLLARY_JAM = (SlipState(theta=0.4493666453680196, varphi=-0.8058921019999438, Theta=0.7483528201200262, Psi=0.766434722261458, eta=2.753242890054462), 1.7)


def test_grid_points_follow_the_axes_in_c_order():
    g = EventGrid(theta=(0.3, 0.9), varphi=(-1.0,), Theta=(0.0, 0.5), Psi=(1.0, 2.0, 3.0), mu=(0.5,), eta=(1.0, 2.0))
    pts = g.points()
    assert len(g) == 2 * 2 * 3 * 2 == len(pts["theta"])
    assert g.shape == (2, 1, 2, 3, 1, 2)
    # C order: eta fastest, theta slowest
    assert pts["eta"][:2].tolist() == [1.0, 2.0] and pts["Psi"][:6].tolist() == [1, 1, 2, 2, 3, 3]
    assert pts["theta"][:24].tolist() == [0.3] * 12 + [0.9] * 12
    assert set(pts) == set(AXES)


@pytest.mark.parametrize("axis, value, message", [("theta", 2.0, "theta must be in (0, pi/2)"), ("varphi", 0.5, "varphi must be in (-pi, 0]"),
                                                  ("mu", -1.0, "mu must be in [0, inf)"), ("Psi", (), "Psi must be a non-empty")], ids=str)
def test_grid_rejects_values_outside_the_paper(axis, value, message):
    kw = {"theta": (0.5,), "varphi": (-1.0,), "Theta": (0.0,), "Psi": (0.0,), "mu": (1.0,)}
    kw[axis] = value
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[").replace("]", r"\]")):
        EventGrid(**kw)


def test_mujoco_labels_censor_events_after_the_comparison_time():
    outcome = np.array([Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM, Outcome.DIVERGED, Outcome.SLIP], dtype=np.int8)
    t = np.array([0.5, 1.2, 0.3, 5.0, np.nan])
    until = np.array([0.5, 1.0, 0.2, 1.0, 2.0])
    got = mujoco_labels(outcome, t, until)
    assert got.tolist() == [Outcome.LIFTOFF, Outcome.SLIP, Outcome.SLIP, Outcome.DIVERGED, Outcome.SLIP]


def test_mirror_symmetry_used_by_the_default_grid():
    """(varphi, Psi) -> (-pi - varphi, -Psi) maps analytic runs onto each other (mirror in the rod's plane)."""
    rng = np.random.default_rng(5)
    for _ in range(6):
        s = SlipState(theta=rng.uniform(0.1, 1.4), varphi=-rng.uniform(0.1, 3.0), Theta=rng.normal(), Psi=rng.normal(), eta=1.0)
        m = SlipState(theta=s.theta, varphi=-math.pi - s.varphi, Theta=s.Theta, Psi=-s.Psi, eta=1.0)
        a, b = slip_until_event(s, 1.7, ALPHA, t_max=2.0), slip_until_event(m, 1.7, ALPHA, t_max=2.0)
        assert a.outcome == b.outcome
        assert a.time == pytest.approx(b.time, abs=1e-8)


def test_boundary_distance_is_small_at_the_liftoff_boundary_and_large_far_from_it():
    s_near = SlipState(theta=0.6, varphi=-math.pi / 2, Theta=0.0, Psi=float(Psi_on_b0(0.6)) - 0.002, eta=1.0)  # b = -0.003: b = 0 is next
    s_far = SlipState(theta=0.3, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0)  # b = -0.70 at mu 0.5
    pts = {k: np.array([getattr(s_near, k), getattr(s_far, k)]) for k in ("theta", "varphi", "Theta", "Psi", "eta")}
    pts["mu"] = np.array([0.5, 0.5])
    outcome = np.array([slip_until_event(s, 0.5, ALPHA, t_max=1.0).outcome for s in (s_near, s_far)])
    d = boundary_distance(pts, outcome, alpha=ALPHA, horizon=1.0, rng=np.random.default_rng(0), directions=8)
    assert d[0] == 0.01
    assert d[1] >= 0.1


def test_classified_rollout_reproduces_sweep_exactly():
    rng = np.random.default_rng(3)
    states = [SlipState(theta=rng.uniform(0.2, 1.3), varphi=-rng.uniform(0.1, 3.0), Theta=0.5 * rng.normal(), Psi=rng.normal(), eta=rng.uniform(0.3, 2)) for _ in range(6)]
    mu = np.array([0.5, 1.0, 1.7, 3.0, 0.8, 6.0])
    th = study_thresholds(Options(**COARSE))
    r = classified_rollout(ROD, states, mu, horizon=1.0, thresholds=th, **COARSE)
    s = sweep(ROD, states, mu, horizon=1.0, thresholds=th, progress=False, **COARSE)
    np.testing.assert_array_equal(r["outcome_a"], s.outcome)
    np.testing.assert_array_equal(r["time_a"], s.event_time)


def test_effective_jam_rule_rejects_a_hopping_landing_below_mu_P():
    s, mu = HOPPING_BELOW_MU_P
    r = classified_rollout(ROD, [s], mu, horizon=0.8, thresholds=study_thresholds(Options()))
    assert r["outcome_e"][0] != Outcome.JAM


def test_effective_jam_rule_does_not_take_a_liftoff_inside_the_window_for_a_jam_below_mu_P():
    s, mu = NEAR_JAM_SLIP_BELOW_MU_P
    a = slip_until_event(s, mu, ALPHA, t_max=2.0)
    assert a.outcome == Outcome.LIFTOFF and a.time < 0.1
    th = study_thresholds(Options())
    run = simulate(ROD, s, mu, horizon=0.3, thresholds=th)
    R, w = run.record, th.window_rows(Options().timestep)
    # the tip is in contact from row 3 past the old JAM row 21 (the force rise is no landing)
    assert R.active[3:30].all() and R.normal_force[3] > 10.0 and w > 30
    r = classified_rollout(ROD, [s], mu, horizon=0.3, thresholds=th)
    assert r["outcome_e"][0] == Outcome.LIFTOFF and r["outcome_a"][0] == Outcome.LIFTOFF
    assert abs(r["time_e"][0] - a.time) < 0.06


def test_effective_jam_rule_fires_where_mujoco_reproduces_a_corollary_jam():
    s, mu = COROLLARY_JAM
    a = slip_until_event(s, mu, ALPHA, t_max=2.0)
    assert a.outcome == Outcome.JAM and a.b < -0.1 and abs(a.state.varphi + math.pi / 2) > 0.1
    r = classified_rollout(ROD, [s], mu, horizon=1.0, thresholds=study_thresholds(Options()))
    assert r["outcome_e"][0] == Outcome.JAM
    assert abs(r["time_e"][0] - a.time) < 0.15
    assert r["p_eff_e"][0] <= P_EFF_JAM


def test_friction_skew_vanishes_on_the_plane_and_explains_the_force_off_it():
    planar = SlipState(theta=0.6, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0)
    off = SlipState(theta=0.4665, varphi=-2.9864, Theta=0.741, Psi=-0.9655, eta=1.98)
    r = friction_skew([planar, off], [1.0, 1.7], duration=0.1)
    assert abs(r["skew"][0]) < 1e-9  # symmetry: friction stays in the rod's vertical plane
    assert abs(r["p_eff"][0] - r["p"][0]) < 1e-9
    assert abs(r["skew"][1]) > 0.3  # ~25 degrees off -slip
    assert np.all(np.abs(r["saturation"] - 1.0) < 1e-3)  # still on the cone's surface: slipping
    # MuJoCo's mean normal force is what slipping with ITS friction direction needs (-b/p_eff), not -b/p
    assert abs(r["force"][1] - r["rigid_force_eff"][1]) < 0.5 * abs(r["force"][1] - r["rigid_force"][1])


def test_agreement_study_on_a_small_grid():
    g = EventGrid(theta=(0.3, 0.9), varphi=(-math.pi / 2, -math.pi / 4), Theta=(0.0,), Psi=(-1.0, 0.0, 1.0), mu=(0.6, 1.4, 4.0))
    res = agreement_study(g, timesteps=(COARSE["timestep"],), timeconsts=(COARSE["timeconst"],), rng=np.random.default_rng(0))
    a = res.analytic
    assert np.all((a.b0[res.index] < 0) & (a.p0[res.index] > 0))
    assert res.index.size == int(a.slipping.sum()) < len(g)
    part_a, eff = res.runs
    assert (part_a.classifier, eff.classifier) == ("part_a", "effective")
    for run in res.runs:
        rated = np.isin(a.outcome[res.index], [Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM])
        assert run.confusion.sum() == res.index.size and run.n_rated == rated.sum()
        assert run.agreement == pytest.approx(np.trace(run.confusion[:4, :4]) / run.n_rated)
        assert run.time_difference.size == sum(run.confusion[o, o] for o in (1, 2, 3))
    # MuJoCo meets the theory here, and where it does not the state is next to an analytic boundary
    assert eff.agreement_jam_as_stop >= 1 - MUJOCO_EVENT_DISAGREEMENT.atol
    disagree = eff.label != a.outcome[res.index]
    assert np.all(res.distance[disagree] < 0.05)
    assert np.median(np.abs(eff.time_difference)) < COARSE["timeconst"]
    table = convergence_table(res)
    assert [row["classifier"] for row in table] == ["part_a", "effective"]
    assert table[1]["n_planar"] + table[1]["n_off_plane"] == eff.n_rated and table[1]["agreement_planar"] == 1.0
    doc = json.loads(res.to_json())  # standard JSON (NaN/inf -> null)
    assert doc["runs"][1]["confusion"] == eff.confusion.tolist() and doc["n_slipping"] == res.index.size


def test_event_agreement_detects_a_wrong_analytic_reference(monkeypatch):
    """The study is not blind: with the right reference all 36 states agree; with 3x the friction, 22 do not."""
    from crosscheck import mujoco_agreement

    g = EventGrid(theta=(0.3, 0.9), varphi=(-math.pi / 2, -math.pi / 4), Theta=(0.0,), Psi=(-1.0, 0.0, 1.0), mu=(0.3, 0.6, 1.0))
    run = dict(timesteps=(COARSE["timestep"],), timeconsts=(COARSE["timeconst"],), boundary_directions=0)
    assert agreement_study(g, **run).runs[1].agreement_jam_as_stop == 1.0
    right = mujoco_agreement.slip_until_event
    monkeypatch.setattr(mujoco_agreement, "slip_until_event", lambda s, mu, alpha, **kw: right(s, 3 * mu, alpha, **kw))
    assert 1 - agreement_study(g, **run).runs[1].agreement_jam_as_stop > 2 * MUJOCO_EVENT_DISAGREEMENT.atol


def test_jam_check_no_jam_below_mu_P_and_bad_input():
    jc = jam_check(mus_below=(1.3,), mus_above=(), n_below=12, rng=np.random.default_rng(2), horizon=1.0, **COARSE)
    row = jc.below[0]
    assert row["analytic_jams"] == 0 and row["effective"]["n_jam"] == 0 and row["n"] == 12
    with pytest.raises(ValueError, match="mus_below must be < mu_P"):
        jam_check(mus_below=(1.4,), mus_above=(), rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match="mus_above must be > mu_P"):
        jam_check(mus_below=(), mus_above=(1.0,), rng=np.random.default_rng(0))


def test_agreement_study_bad_input():
    g = EventGrid(theta=(0.3,), varphi=(-1.0,), Theta=(0.0,), Psi=(0.0,), mu=(1.0,))
    with pytest.raises(ValueError, match="same length"):
        agreement_study(g, timesteps=(1e-3, 3e-4), timeconsts=(0.1,))
    with pytest.raises(ValueError, match="unknown MuJoCo option 'stiffness'"):
        agreement_study(g, stiffness=3.0)
    lifting = EventGrid(theta=(0.6,), varphi=(-1.0,), Theta=(0.0,), Psi=(3.0,), mu=(1.0,))  # b > 0 at t = 0
    with pytest.raises(ValueError, match="no slipping state"):
        agreement_study(lifting)
    with pytest.raises(ValueError, match="points lack the keys"):
        agreement_study({"theta": np.array([0.5])})
