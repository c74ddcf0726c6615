"""The MuJoCo engine's batched sweep: the same answers as ``simulate``, summaries, divergence labelled."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck import Outcome, Rod, SlipState
from crosscheck.engines import SERIES, SUMMARY, get

ROD = Rod(mass=1.0, length=1.0, inertia=1.0 / 3.0, gravity=9.81)
ENGINE = get("mujoco")
simulate, sweep = ENGINE.simulate, ENGINE.sweep
COARSE = 1e-3 * ROD.omega  # dt = 1 ms for the 1 m rod, in scaled time

#: A mix of outcomes at the default options (found by a seeded random search; the
#: outcome named is what MuJoCo gives, checked below through simulate).  The fourth
#: state jams analytically at t = 0.055 (its capsule at 0.046); MuJoCo's slip stops at
#: t = 0.104 with its contact point's own p_eff at -0.061: a JAM by the slip stop's rule
#: (a STICK while that rule read p_eff with the tip's moment arm; a rule that compared
#: the window force with -b/p instead of the engine's own friction fired at t = 0).
MIXED = [
    (0.5, SlipState(theta=0.5, varphi=-math.pi / 2, Theta=0.0, Psi=0.5, eta=1.0)),  # SLIP
    (0.5, SlipState(theta=0.6154797087, varphi=-math.pi / 2, Theta=0.0, Psi=1.62, eta=1.0)),  # LIFTOFF at 0
    (1.4, SlipState(theta=1.0248, varphi=-1.653, Theta=-0.2955, Psi=0.1496, eta=2.925)),  # JAM (p < 0, b < 0)
    (
        3.0,
        SlipState(theta=0.526, varphi=-0.7066, Theta=-0.383, Psi=0.882, eta=2.124),
    ),  # JAM at the slip stop (analytic JAM)
    (2.93, SlipState(theta=1.20, varphi=-0.38, Theta=-0.01, Psi=1.19, eta=0.20)),  # STICK
    (1.4, SlipState(theta=0.8, varphi=-math.pi / 2, Theta=0.5, Psi=0.0, eta=3.0)),
]


def test_sweep_equals_simulate_exactly():
    mu = np.array([m for m, _ in MIXED])
    states = [s for _, s in MIXED]
    result = sweep(ROD, states, mu, horizon=0.5, progress=False)
    single = [simulate(ROD, s, m, horizon=0.5) for m, s in MIXED]
    np.testing.assert_array_equal(result.outcome, [r.outcome for r in single])
    np.testing.assert_array_equal(result.event_time, [r.event_time for r in single])
    np.testing.assert_array_equal(result.exit_time, [r.exit_time for r in single])
    assert set(result.outcome[:5]) == {Outcome.SLIP, Outcome.LIFTOFF, Outcome.JAM, Outcome.STICK}
    assert list(result.outcome[:5]) == [Outcome.SLIP, Outcome.LIFTOFF, Outcome.JAM, Outcome.JAM, Outcome.STICK]
    assert result.engine == "mujoco" and all(r.engine == "mujoco" for r in single)
    np.testing.assert_array_equal(result.summary["jam_p_eff"], [r.jam_p_eff for r in single])
    assert set(result.summary) == set(SUMMARY) and set(result.series) == set(SERIES)
    assert all(v.shape == (len(MIXED),) for v in result.summary.values())
    n = result.series["t"].shape[1]
    assert 200 <= n < 400 and all(v.shape == (len(MIXED), n) for v in result.series.values())


@pytest.mark.parametrize(
    "chunk_steps, sizes", [(1, [1] * 16), (3 * 667, [3] * 5 + [1])], ids=["one state", "three states"]
)
def test_a_sweep_rolled_out_by_threads_chunk_by_chunk_equals_simulate_exactly(monkeypatch, chunk_steps, sizes):
    # each thread takes the next chunk as it finishes, in its own MjData: every chunk boundary and every thread must
    # leave each state's run as it is alone
    from crosscheck.engines.mujoco import engine as mj

    monkeypatch.setattr(mj, "THREAD_CHUNK_STEPS", chunk_steps)  # 667 steps per state at horizon 0.2
    rng = np.random.default_rng(11)
    states = [
        SlipState(
            theta=rng.uniform(0.3, 1.3),
            varphi=-rng.uniform(0.2, 3.0),
            Theta=0.5 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.3, 2.0),
        )
        for _ in range(16)
    ]
    mu = rng.uniform(0.3, 2.0, 16)
    batch = mj.Batch.build(ROD, states, mu, horizon=0.2, options=mj.Options(), nthread=2)
    assert batch.nstep == 667
    assert [sl.stop - sl.start for sl, _ in batch.chunks(progress=False)] == sizes
    result = sweep(ROD, states, mu, horizon=0.2, progress=False)
    single = [simulate(ROD, s, m, horizon=0.2) for s, m in zip(states, mu)]
    np.testing.assert_array_equal(result.outcome, [r.outcome for r in single])
    np.testing.assert_array_equal(result.event_time, [r.event_time for r in single])
    assert len(set(result.outcome.tolist())) > 1  # not one outcome everywhere, which a misplaced chunk could also give


def test_liftoff_events_have_upward_free_acceleration():
    """At a LIFTOFF event the state's b (eq. b) is positive: MuJoCo's force-free tip accelerates up."""
    rng = np.random.default_rng(4)
    states = [
        SlipState(
            theta=rng.uniform(0.2, 1.3),
            varphi=-rng.uniform(0.1, 3.0),
            Theta=rng.normal(),
            Psi=1.5 * rng.normal(),
            eta=rng.uniform(0.2, 2),
        )
        for _ in range(24)
    ]
    r = sweep(ROD, states, 0.6, horizon=0.3, progress=False)
    lift = r.outcome == Outcome.LIFTOFF
    assert lift.sum() >= 5
    assert np.all(r.summary["b"][lift] > 0)


def test_divergence_is_labelled_never_dropped():
    """A rod that stands up (theta -> pi/2, psi inertia I0 cos^2 -> 0) blows up at dt = 1 ms: DIVERGED.

    A second state jams first and diverges later: its outcome is JAM but the divergence time is kept.
    """
    diverges = SlipState(
        theta=1.3529531183696746,
        varphi=-2.76367127995412,
        Theta=0.748171685624696,
        Psi=-0.3250520988063787,
        eta=2.0675805227908657,
    )
    jams_then_diverges = SlipState(
        theta=1.010392123965898,
        varphi=-1.4564590645844966,
        Theta=1.0781271081094388,
        Psi=0.1628510662568078,
        eta=2.103872509041319,
    )
    r = sweep(
        ROD,
        [diverges, jams_then_diverges],
        np.array([0.407251725110177, 2.831664300620455]),
        horizon=1.0,
        timestep=COARSE,
        progress=False,
    )
    assert r.outcome[0] == Outcome.DIVERGED
    assert r.exit_time[0] < r.diverged_time[0] == r.event_time[0]
    assert r.outcome[1] == Outcome.JAM and np.isfinite(r.diverged_time[1])


def test_bad_sweep_input():
    s = SlipState(0.5, -1.0, 0.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="unknown MuJoCo option 'dt'"):
        sweep(ROD, [s], 0.5, horizon=0.1, dt=1e-4, progress=False)
    with pytest.raises(ValueError, match="states\\[1\\] must be a SlipState; got dict"):
        sweep(ROD, [s, {"theta": 0.5}], 0.5, horizon=0.1, progress=False)
    with pytest.raises(ValueError, match="mu must be in \\[0, 1000\\]; got -0.5"):
        sweep(ROD, [s, s], [0.5, -0.5], horizon=0.1, progress=False)
    with pytest.raises(ValueError, match="states must contain at least one SlipState"):
        sweep(ROD, [], 0.5, horizon=0.1, progress=False)


def test_mujoco_warnings_are_counted_not_printed(tmp_path, monkeypatch, capfd):
    """MuJoCo's instability warnings go to crosscheck.engines.mujoco.warning_counts: counted by kind in the sweep's result and
    in a stored sweep's chunk records, never printed on the console nor logged to MUJOCO_LOG.TXT in the working directory."""
    from crosscheck import sweeps
    from crosscheck.engines.mujoco import engine as mj

    monkeypatch.chdir(tmp_path)
    fast = SlipState(
        theta=1.1, varphi=-1.9, Theta=90.0, Psi=90.0, eta=90.0
    )  # rates at the top of the start range, a coarse step
    r = mj.sweep(Rod.scaled(3.0), [fast] * 3, 1.4, horizon=0.2, progress=False, timestep=3e-3)
    assert r.warnings == {"Nan, Inf or huge value in QACC": 3}
    assert np.all(np.isfinite(r.diverged_time))  # every warned run is one MuJoCo reset: its divergence is recorded
    spec = sweeps.parse_spec(
        {
            "sweep": {"engine": "mujoco", "horizon": 0.2, "seed": 0, "chunk": 2},
            "states": {
                "zip": True,
                "theta": [1.1] * 3,
                "varphi": [-1.9] * 3,
                "Theta": [90.0] * 3,
                "Psi": [90.0] * 3,
                "eta": [90.0] * 3,
                "mu": [1.4] * 3,
            },
            "parameters": {"alpha": 3.0},
            "options": {"timestep": 3e-3},
        }
    )
    sweeps.run(spec, tmp_path / "store", workers=1, progress=False)
    assert sweeps.Store(tmp_path / "store").warnings() == {"Nan, Inf or huge value in QACC": 3}
    err = capfd.readouterr().err
    assert "WARNING" not in err and not (tmp_path / "MUJOCO_LOG.TXT").exists()
