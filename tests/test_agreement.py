"""Event agreement and jams: an engine's first events against the analytic ones, on small grids with the real MuJoCo."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from crosscheck import Outcome, Rod, SlipState, engines
from crosscheck.engines.mujoco.tolerances import MUJOCO_EVENT_DISAGREEMENT
from crosscheck.studies.agreement import agreement_study, boundary_distance, comparison_labels, convergence_table
from crosscheck.studies.grids import AXES, EventGrid
from crosscheck.studies.jams import jam_check
from crosscheck.theory.critical import Psi_on_b0
from crosscheck.theory.slipping import slip_until_event

ALPHA = 3.0
ROD = Rod.scaled(ALPHA)
COARSE = {"timestep": 1e-3, "timeconst": 0.1}  # ~0.3 ms and 32 ms for a 1 m rod: fast, still resolved


def test_grid_points_follow_the_axes_in_c_order():
    g = EventGrid(theta=(0.3, 0.9), varphi=(-1.0,), Theta=(0.0, 0.5), Psi=(1.0, 2.0, 3.0), mu=(0.5,), eta=(1.0, 2.0))
    pts = g.points()
    assert len(g) == 2 * 2 * 3 * 2 == len(pts["theta"])
    assert g.shape == (2, 1, 2, 3, 1, 2)
    # C order: eta fastest, theta slowest
    assert pts["eta"][:2].tolist() == [1.0, 2.0] and pts["Psi"][:6].tolist() == [1, 1, 2, 2, 3, 3]
    assert pts["theta"][:24].tolist() == [0.3] * 12 + [0.9] * 12
    assert set(pts) == set(AXES)


@pytest.mark.parametrize(
    "axis, value, message",
    [
        ("theta", 2.0, "theta must be in (0, pi/2)"),
        ("varphi", 0.5, "varphi must be in (-pi, 0]"),
        ("mu", -1.0, "mu must be in [0, 1000]"),
        ("Psi", (), "Psi must be a non-empty"),
    ],
    ids=str,
)
def test_grid_rejects_values_outside_the_paper(axis, value, message):
    kw = {"theta": (0.5,), "varphi": (-1.0,), "Theta": (0.0,), "Psi": (0.0,), "mu": (1.0,)}
    kw[axis] = value
    with pytest.raises(
        ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[").replace("]", r"\]")
    ):
        EventGrid(**kw)


def test_comparison_labels_censor_events_after_the_comparison_time():
    outcome = np.array([Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM, Outcome.DIVERGED, Outcome.SLIP], dtype=np.int8)
    t = np.array([0.5, 1.2, 0.3, 5.0, np.nan])
    until = np.array([0.5, 1.0, 0.2, 1.0, 2.0])
    got = comparison_labels(outcome, t, until)
    assert got.tolist() == [Outcome.LIFTOFF, Outcome.SLIP, Outcome.SLIP, Outcome.DIVERGED, Outcome.SLIP]


def test_a_stick_the_classifier_cannot_tell_from_the_theorys_slip_is_compared_as_that_slip():
    """``stick_from``: where the theory SLIPs to its comparison time and its slip speed falls below the engine's STICK floor on
    the way (at t_floor), an engine STICK from t_floor - lag on is read as SLIP; an earlier STICK, any other event, and
    every theory that does not slip (or never falls below the floor) are compared as before."""
    from crosscheck.studies.comparison import floor_time, stick_from

    assert floor_time([0.0, 1.0, 2.0], [1.0, 0.5, 0.0], 0.25) == pytest.approx(1.5)  # linear between the samples
    assert math.isnan(floor_time([0.0, 1.0], [1.0, 0.5], 0.25)) and floor_time([0.0, 1.0], [0.1, 0.5], 0.25) == 0.0
    S, L, T = (int(o) for o in (Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK))
    theory = np.array([S, S, S, L, S], np.int8)
    until = np.array([0.8, 0.8, 2.0, 0.5, 0.8])
    since = stick_from(theory, until, np.array([0.78, 0.78, 2.5, 0.4, np.nan]), 0.01)
    assert since.tolist() == pytest.approx([0.77, 0.77, math.inf, math.inf, math.inf])
    engine = np.array([T, T, T, T, T], np.int8)
    t = np.array([0.775, 0.70, 1.9, 0.45, 0.79])
    assert comparison_labels(engine, t, until, since).tolist() == [S, T, T, T, T]
    assert comparison_labels(np.array([L], np.int8), np.array([0.775]), np.array([0.8]), since[:1]).tolist() == [
        L
    ]  # only a STICK


def test_mirror_symmetry_used_by_the_default_grid():
    """(varphi, Psi) -> (-pi - varphi, -Psi) maps analytic runs onto each other (mirror in the rod's plane)."""
    rng = np.random.default_rng(5)
    for _ in range(6):
        s = SlipState(
            theta=rng.uniform(0.1, 1.4), varphi=-rng.uniform(0.1, 3.0), Theta=rng.normal(), Psi=rng.normal(), eta=1.0
        )
        m = SlipState(theta=s.theta, varphi=-math.pi - s.varphi, Theta=s.Theta, Psi=-s.Psi, eta=1.0)
        a, b = slip_until_event(s, 1.7, ALPHA, t_max=2.0), slip_until_event(m, 1.7, ALPHA, t_max=2.0)
        assert a.outcome == b.outcome
        assert a.time == pytest.approx(b.time, abs=1e-8)


def test_boundary_distance_is_small_at_the_liftoff_boundary_and_large_far_from_it():
    s_near = SlipState(
        theta=0.6, varphi=-math.pi / 2, Theta=0.0, Psi=float(Psi_on_b0(0.6)) - 0.002, eta=1.0
    )  # b = -0.003: b = 0 is next
    s_far = SlipState(theta=0.3, varphi=-math.pi / 2, Theta=0.0, Psi=0.0, eta=1.0)  # b = -0.70 at mu 0.5
    pts = {k: np.array([getattr(s_near, k), getattr(s_far, k)]) for k in ("theta", "varphi", "Theta", "Psi", "eta")}
    pts["mu"] = np.array([0.5, 0.5])
    outcome = np.array([slip_until_event(s, 0.5, ALPHA, t_max=1.0).outcome for s in (s_near, s_far)])
    d = boundary_distance(pts, outcome, alpha=ALPHA, horizon=1.0, rng=np.random.default_rng(0), directions=8)
    assert d[0] == 0.01
    assert d[1] >= 0.1


def test_agreement_study_on_a_small_grid():
    g = EventGrid(
        theta=(0.3, 0.9), varphi=(-math.pi / 2, -math.pi / 4), Theta=(0.0,), Psi=(-1.0, 0.0, 1.0), mu=(0.6, 1.4, 4.0)
    )
    res = agreement_study(g, settings=(COARSE,), rng=np.random.default_rng(0))
    a = res.analytic
    assert np.all((a.b0[res.index] < 0) & (a.p0[res.index] > 0))
    assert res.index.size == int(a.slipping.sum()) < len(g)
    (eff,) = res.runs
    assert res.engine == eff.engine == "mujoco" and (eff.timestep, eff.timeconst) == (
        COARSE["timestep"],
        COARSE["timeconst"],
    )
    for run in res.runs:
        rated = np.isin(a.outcome[res.index], [Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM])
        assert run.confusion.sum() == res.index.size and run.n_rated == rated.sum()
        assert run.agreement == pytest.approx(np.trace(run.confusion[:4, :4]) / run.n_rated)
        assert run.time_difference.size == sum(run.confusion[o, o] for o in (1, 2, 3))
    # MuJoCo meets the theory here, and where it does not the state is next to an analytic boundary
    assert eff.agreement_jam_as_stop >= 1 - MUJOCO_EVENT_DISAGREEMENT.atol
    # the STICKs read as the theory's slip: where the theory's least slip speed is below MuJoCo's STICK floor
    read = (eff.outcome == Outcome.STICK) & (eff.label == Outcome.SLIP) & (eff.event_time <= a.until[res.index])
    assert eff.stick_as_slip == read.sum() and np.all(a.eta_min[res.index][read] < eff.stick_floor)
    disagree = eff.label != a.outcome[res.index]
    assert np.all(res.distance[disagree] < 0.05)
    assert np.median(np.abs(eff.time_difference)) < COARSE["timeconst"]
    table = convergence_table(res)
    assert [row["engine"] for row in table] == ["mujoco"]
    assert table[0]["n_planar"] + table[0]["n_off_plane"] == eff.n_rated and table[0]["agreement_planar"] == 1.0
    doc = json.loads(res.to_json())  # standard JSON (NaN/inf -> null)
    assert doc["runs"][0]["confusion"] == eff.confusion.tolist() and doc["n_slipping"] == res.index.size


def test_event_agreement_detects_a_wrong_analytic_reference(monkeypatch):
    """The study is not blind: with the right reference all 36 states agree; with 3x the friction, 22 do not."""
    g = EventGrid(
        theta=(0.3, 0.9), varphi=(-math.pi / 2, -math.pi / 4), Theta=(0.0,), Psi=(-1.0, 0.0, 1.0), mu=(0.3, 0.6, 1.0)
    )
    run = dict(settings=(COARSE,), boundary_directions=0)
    assert agreement_study(g, **run).runs[0].agreement_jam_as_stop == 1.0
    from crosscheck.studies import analytic_events

    right = analytic_events.slip_until_event
    monkeypatch.setattr(analytic_events, "slip_until_event", lambda s, mu, alpha, **kw: right(s, 3 * mu, alpha, **kw))
    assert 1 - agreement_study(g, **run).runs[0].agreement_jam_as_stop > 2 * MUJOCO_EVENT_DISAGREEMENT.atol


def test_jam_check_no_jam_below_mu_P_and_bad_input():
    jc = jam_check(mus_below=(1.3,), mus_above=(), n_below=12, rng=np.random.default_rng(2), horizon=1.0, **COARSE)
    row = jc.below[0]
    assert row["analytic_jams"] == 0 and row["n_jam"] == 0 and row["n"] == 12 and jc.engine == "mujoco"
    with pytest.raises(ValueError, match="mus_below must be < mu_P"):
        jam_check(mus_below=(1.4,), mus_above=(), rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match="mus_above must be > mu_P"):
        jam_check(mus_below=(), mus_above=(1.0,), rng=np.random.default_rng(0))


def test_agreement_study_bad_input():
    g = EventGrid(theta=(0.3,), varphi=(-1.0,), Theta=(0.0,), Psi=(0.0,), mu=(1.0,))
    with pytest.raises(ValueError, match="settings must hold at least one dict"):
        agreement_study(g, settings=())
    with pytest.raises(ValueError, match=f"engine must be one of {', '.join(engines.names())}; got 'no_such_engine'"):
        agreement_study(g, engine="no_such_engine")
    with pytest.raises(ValueError, match="unknown MuJoCo option 'stiffness'"):
        agreement_study(g, stiffness=3.0)
    lifting = EventGrid(theta=(0.6,), varphi=(-1.0,), Theta=(0.0,), Psi=(3.0,), mu=(1.0,))  # b > 0 at t = 0
    with pytest.raises(ValueError, match="no slipping state"):
        agreement_study(lifting)
    with pytest.raises(ValueError, match="points lack the keys"):
        agreement_study({"theta": np.array([0.5])})


def test_through_a_sweep_store_the_study_is_the_same_and_resumes(tmp_path):
    """store=: the engine runs go through crosscheck.sweeps (chunks on 2 processes); same outcomes and times, and a rerun computes nothing."""
    from crosscheck import sweeps
    from crosscheck.studies.grids import SMALL_GRID

    kw = dict(engine="mujoco", settings=[{"timestep": 1e-3, "timeconst": 0.06}], boundary_directions=0, horizon=1.0)
    direct = agreement_study(SMALL_GRID, **kw).runs[0]
    stored = agreement_study(SMALL_GRID, store=tmp_path, workers=2, **kw).runs[0]
    np.testing.assert_array_equal(stored.outcome, direct.outcome)
    np.testing.assert_array_equal(stored.event_time, direct.event_time)
    assert stored.agreement == direct.agreement
    stores = [p for p in tmp_path.iterdir() if p.is_dir()]  # one sweep per run horizon
    assert len(stores) > 1
    stamps = {p: p.stat().st_mtime_ns for st in stores for p in (st / "chunks").iterdir()}
    agreement_study(SMALL_GRID, store=tmp_path, workers=2, **kw)
    assert {p: p.stat().st_mtime_ns for st in stores for p in (st / "chunks").iterdir()} == stamps
    assert sum(len(sweeps.load(st)) for st in stores) == len(direct.outcome)


@pytest.mark.parametrize("engine, options", [("mujoco", COARSE), ("pinocchio", {"timestep": 1e-3})])
def test_runs_cut_at_each_states_comparison_label_every_state_as_runs_to_the_horizon(monkeypatch, engine, options):
    """Each state runs to its comparison time plus lag (rounded up to horizon / 2^k) plus two windows: the labels, and the
    event times of every event the comparison sees, are those of runs to the horizon (HORIZON_HALVINGS = 0), with fewer steps."""
    from crosscheck.studies import agreement_store

    # slips, lift-offs, sticks and jams, early and late
    grid = EventGrid(
        theta=(0.5, 0.9, 1.0, 1.2), varphi=(-1.9, -math.pi / 2), Theta=(-0.7, 0.0, 0.9), Psi=(0.0, 1.7), mu=(0.6, 1.4)
    )
    kw = dict(engine=engine, settings=[options], boundary_directions=0, horizon=2.0)
    cut = agreement_study(grid, **kw)
    runs_to = agreement_store.run_horizons(cut.analytic.until[cut.index], 2.0)
    monkeypatch.setattr(agreement_store, "HORIZON_HALVINGS", 0)
    whole = agreement_study(grid, **kw)
    c, w = cut.runs[0], whole.runs[0]
    np.testing.assert_array_equal(c.label, w.label)
    seen = np.isin(c.label, [int(o) for o in (Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM, Outcome.LAUNCH)])
    assert seen.any() and np.array_equal(c.event_time[seen], w.event_time[seen])
    assert len(set(c.label.tolist())) == 4  # a grid with every rated outcome, not one that agrees by being dull
    # the states whose comparison ends early ran shorter
    assert (runs_to < 2.0).sum() >= len(runs_to) // 4


def test_run_horizons_are_the_smallest_halving_of_the_horizon_past_the_comparison():
    from crosscheck.studies.agreement_store import HORIZON_HALVINGS, run_horizons

    h = run_horizons([0.0, 0.1, 0.125, 0.126, 0.9, 1.0, 1.5, 2.0, 7.0], 2.0)
    assert HORIZON_HALVINGS == 4
    assert h.tolist() == [0.125, 0.125, 0.125, 0.25, 1.0, 1.0, 2.0, 2.0, 2.0]


def _events_equal(a, b) -> None:
    from dataclasses import fields

    for f in fields(a):
        np.testing.assert_array_equal(getattr(a, f.name), getattr(b, f.name), err_msg=f.name)
        assert getattr(a, f.name).dtype == getattr(b, f.name).dtype, f.name


def test_analytic_events_kept_in_a_file_are_read_back_and_a_foreign_or_damaged_file_is_replaced(tmp_path):
    """Engines mapping one grid share its analytic events through ``kept``: the file returns exactly what the integration
    gave; a file of another grid (its b0, p0 differ), a damaged one or one lacking a field is integrated again and replaced."""
    from crosscheck.studies.analytic_events import analytic_events

    pts = EventGrid(
        theta=(0.3, 0.9), varphi=(-math.pi / 2, -2.5), Theta=(0.0, 1.2), Psi=(-1.0, 1.0), mu=(0.6, 1.4)
    ).points()
    other = EventGrid(
        theta=(0.4, 1.0), varphi=(-math.pi / 2, -2.5), Theta=(0.0, 1.2), Psi=(-1.0, 1.0), mu=(0.6, 1.4)
    ).points()
    kept = tmp_path / "analytic_events" / "grid.npz"
    plain = analytic_events(pts, alpha=ALPHA, horizon=2.0)
    assert len(set(plain.outcome.tolist())) > 1  # the grid is not one outcome throughout
    _events_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept), plain)
    assert kept.exists()
    _events_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept), plain)
    # the file is what is read: a time changed in it comes back
    with np.load(kept) as z:
        fields_ = dict(z)
    np.savez(kept, **{**fields_, "time": fields_["time"] + 1.0})
    np.testing.assert_array_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept).time, plain.time + 1.0)
    # another grid's events under the name: integrated again, and the file now holds this grid's
    _events_equal(
        analytic_events(other, alpha=ALPHA, horizon=2.0, kept=kept), analytic_events(other, alpha=ALPHA, horizon=2.0)
    )
    _events_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept), plain)
    for damaged in (b"not a numpy file", b"PK\x03\x04 truncated"):
        kept.write_bytes(damaged)
        _events_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept), plain)
        _events_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept), plain)  # rewritten whole
    np.savez(kept, **{k: v for k, v in fields_.items() if k != "reason"})
    _events_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept), plain)
    np.save(tmp_path / "bare.npy", plain.time)
    (tmp_path / "bare.npy").rename(kept)  # a bare array under the name
    _events_equal(analytic_events(pts, alpha=ALPHA, horizon=2.0, kept=kept), plain)


def test_boundary_distances_kept_in_a_file_are_read_back_and_a_damaged_file_is_replaced(tmp_path):
    """Two studies of one grid with the same probe stream share the distances through ``boundary_cache``: the second reads
    the file (a different stream then changes nothing); a file of another length or damaged is computed again."""
    g = EventGrid(theta=(0.3, 0.9), varphi=(-math.pi / 2,), Theta=(0.0,), Psi=(-1.0, 1.0), mu=(0.6, 1.4))
    run = dict(settings=(COARSE,), boundary_directions=2, boundary_radii=(0.03, 0.3))
    cache = tmp_path / "probes" / "grid.npy"
    first = agreement_study(g, rng=np.random.default_rng(5), boundary_cache=cache, **run)
    assert cache.exists() and np.load(cache).shape == (len(g),)
    again = agreement_study(g, rng=np.random.default_rng(99), boundary_cache=cache, **run)
    np.testing.assert_array_equal(again.distance, first.distance)
    fresh = agreement_study(
        g, rng=np.random.default_rng(5), **run
    )  # the same stream without the file: the same distances
    np.testing.assert_array_equal(fresh.distance, first.distance)
    assert not np.array_equal(
        agreement_study(g, rng=np.random.default_rng(99), **run).distance, first.distance
    )  # the file was read
    cache.write_bytes(b"not a numpy file")
    redone = agreement_study(g, rng=np.random.default_rng(5), boundary_cache=cache, **run)
    np.testing.assert_array_equal(redone.distance, first.distance)
    assert np.load(cache).shape == (len(g),)
