"""Sweeps at scale (crosscheck.sweeps): the spec, identical tables on every executor, resume after kill -9, the store's guards."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import small

from crosscheck import engines, sweeps
from crosscheck.cli import main
from crosscheck.sweeps.spec import SpecError, parse_spec
from crosscheck.sweeps.store import Store, StoreError
from crosscheck.sweeps.store_diff import compare_frames, wilson_interval

EXAMPLE = Path(__file__).parents[1] / "examples" / "sweep.toml"


def write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def results(df: pd.DataFrame) -> pd.DataFrame:
    """Everything but the wall time (the one column that may differ between two runs of the same chunk)."""
    return df.drop(columns=["wall_time"])


def test_the_example_spec_runs_as_written(tmp_path):
    spec = sweeps.load_spec(EXAMPLE)
    assert (spec.n_states, spec.n_runs, spec.n_chunks) == (40, 80, 5) and spec.options == {"timestep": (3e-4,)}
    cols = spec.runs()
    assert np.all(cols["mu"][:2] == [0.5, 1.4]) and np.all(cols["theta"][:2] == 0.4)  # state-major, then mu
    s = sweeps.run(EXAMPLE, tmp_path / "example", workers=2, progress=False)
    df = sweeps.load(tmp_path / "example")
    assert (
        s.failed == {}
        and len(df) == 80
        and {"theta", "varphi", "Theta", "Psi", "eta", "mu", "alpha", "outcome", "event_time"} <= set(df.columns)
    )
    assert set(df.outcome) <= {"SLIP", "LIFTOFF", "STICK", "JAM", "DIVERGED"} and (df.timestep == 3e-4).all()


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    out = tmp_path_factory.mktemp("serial") / "store"
    spec = tmp_path_factory.mktemp("spec") / "spec.toml"
    spec.write_text(small(timestep=1e-3))
    summary = sweeps.run(spec, out, workers=1, progress=False)
    return spec, out, summary


def test_serial_run_has_one_row_per_run_with_the_promised_columns(serial):
    spec, out, summary = serial
    df = sweeps.load(out)
    assert summary.failed == {} and len(summary.computed) == 6 and len(df) == 24
    for c in ("theta", "varphi", "Theta", "Psi", "eta", "mu", "alpha", "outcome", "event_time", "timestep", "engine"):
        assert c in df.columns
    # solver statistics: exactly the columns the engine declares (MuJoCo's solver reports none per run)
    from crosscheck.sweeps.chunk import result_columns

    assert [c for c in df.columns if c.startswith("solver_")] == [
        c for c in result_columns("mujoco") if c.startswith("solver_")
    ]
    assert result_columns("pinocchio")[-5:-2] == (
        "solver_contact_steps",
        "solver_unconverged_steps",
        "solver_max_iterations",
    )
    assert set(df.outcome) <= {"SLIP", "LIFTOFF", "STICK", "JAM", "DIVERGED"} and list(df.run) == list(range(24))
    # the same runs through the engine directly give the same outcomes (the layer adds nothing to the physics)
    from crosscheck import Rod, SlipState
    from crosscheck.engines import get

    states = [SlipState(theta=r.theta, varphi=r.varphi, Theta=r.Theta, Psi=r.Psi, eta=r.eta) for r in df.itertuples()]
    direct = get("mujoco").sweep(Rod.scaled(3.0), states, df.mu.to_numpy(), horizon=0.2, timestep=1e-3, progress=False)
    assert [o.name for o in map(__import__("crosscheck").Outcome, direct.outcome)] == list(df.outcome)
    np.testing.assert_array_equal(direct.event_time, df.event_time.to_numpy())


def test_two_workers_and_a_dask_local_cluster_give_identical_tables(serial, tmp_path):
    spec, out, _ = serial
    ref = results(sweeps.load(out))
    sweeps.run(spec, tmp_path / "pool", workers=2, progress=False)
    pd.testing.assert_frame_equal(results(sweeps.load(tmp_path / "pool")), ref)
    s = sweeps.run(spec, tmp_path / "dask", workers=2, scheduler="local", progress=False)
    assert s.failed == {}
    pd.testing.assert_frame_equal(results(sweeps.load(tmp_path / "dask")), ref)


def test_rerun_reuses_every_finished_chunk(serial):
    spec, out, _ = serial
    before = {p.name: p.stat().st_mtime_ns for p in (out / "chunks").iterdir()}
    s = sweeps.run(spec, out, workers=1, progress=False)
    assert s.computed == [] and len(s.reused) == 6
    assert {p.name: p.stat().st_mtime_ns for p in (out / "chunks").iterdir()} == before


def test_kill_9_mid_sweep_then_resume_equals_an_uninterrupted_run(tmp_path):
    """A sweep killed after its first chunks: re-run computes only the rest, and the table equals an uninterrupted run's."""
    spec = write(tmp_path, small("pinocchio", horizon=0.6, chunk=2))
    out = tmp_path / "killed"
    proc = subprocess.Popen(
        [sys.executable, "-m", "crosscheck", "sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    store = Store(out)
    deadline = time.time() + 120
    while time.time() < deadline:
        m = store.read_manifest() if store.manifest_path.exists() else None
        if m and len(m["chunks"]) >= 2:
            break
        time.sleep(0.01)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    m = store.read_manifest()
    finished = {cid: rec for cid, rec in m["chunks"].items()}
    assert 2 <= len(finished) < 12, "the sweep must be killed in the middle"
    stamps = {rec["file"]: (out / "chunks" / rec["file"]).stat().st_mtime_ns for rec in finished.values()}
    with pytest.raises(StoreError, match="unfinished"):
        sweeps.load(out)
    s = sweeps.run(spec, out, workers=1, progress=False)
    assert sorted(s.reused) == sorted(int(c) for c in finished) and len(s.computed) == 12 - len(finished)
    assert {f: (out / "chunks" / f).stat().st_mtime_ns for f in stamps} == stamps  # not recomputed
    assert not [p for p in (out / "chunks").iterdir() if p.name.startswith(".")]  # no temporary file left behind ...
    sweeps.run(spec, tmp_path / "whole", workers=1, progress=False)
    pd.testing.assert_frame_equal(results(sweeps.load(out)), results(sweeps.load(tmp_path / "whole")))  # ... or read


def test_a_second_writer_is_refused_in_one_line(serial, tmp_path):
    spec, out, _ = serial
    with Store(out).writer():
        with pytest.raises(StoreError, match=r"is being written by pid \d+"):
            sweeps.run(spec, out, workers=1, progress=False)


def test_another_spec_into_the_same_store_is_refused_unless_fresh(tmp_path):
    out = tmp_path / "store"
    sweeps.run(write(tmp_path, small("analytic")), out, workers=1, progress=False)
    other = write(tmp_path, small("analytic").replace("mu = [0.5, 1.4]", "mu = [0.5, 1.5]"), "other.toml")
    with pytest.raises(StoreError, match="holds a different sweep .* use --fresh"):
        sweeps.run(other, out, workers=1, progress=False)
    sweeps.run(other, out, workers=1, progress=False, fresh=True)
    assert sorted(set(sweeps.load(out).mu)) == [0.5, 1.5]


def test_a_store_computed_with_other_versions_is_refused_unless_fresh(tmp_path, monkeypatch, capsys):
    """Resuming a store under other versions of what computes it (an upgrade between two runs) would mix two versions'
    results: one line naming the package and both versions, exit 2 on the command line; --fresh recomputes it.  A chunk
    kept through a rebuilt manifest is recomputed when its own record names other versions."""
    import crosscheck.sweeps.store as store_module

    spec, out = write(tmp_path, small("analytic")), tmp_path / "store"
    sweeps.run(spec, out, workers=1, progress=False)
    ref = results(sweeps.load(out))
    real = store_module.versions
    monkeypatch.setattr(store_module, "versions", lambda engine=None: {**real(engine), "numpy": "0.0.1"})
    with pytest.raises(StoreError) as e:
        sweeps.run(spec, out, workers=1, progress=False)
    assert str(e.value).startswith(
        f"out {str(out)!r} holds 6 chunks computed with numpy {np.__version__} (now 0.0.1); "
    )
    assert str(e.value).endswith("use --fresh to recompute it, or finish it with the versions it was started with")
    assert main(["sweep", str(spec), "--out", str(out), "--no-progress"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert len(sweeps.run(spec, out, workers=1, progress=False, fresh=True).computed) == 6
    pd.testing.assert_frame_equal(results(sweeps.load(out)), ref)
    # back to the real versions, through a manifest rebuilt from the spec: every chunk names numpy 0.0.1, so none is kept
    monkeypatch.undo()
    (out / "manifest.json").unlink()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s = sweeps.run(spec, out, workers=1, progress=False)
    said = [str(w.message) for w in caught]
    assert sum(f"(computed with numpy 0.0.1 (now {np.__version__})); it will be recomputed" in m for m in said) == 6, (
        said
    )
    assert s.computed == list(range(6))
    pd.testing.assert_frame_equal(results(sweeps.load(out)), ref)


def test_a_damaged_chunk_is_detected_by_its_checksum_and_recomputed(tmp_path):
    spec, out = write(tmp_path, small("analytic")), tmp_path / "store"
    sweeps.run(spec, out, workers=1, progress=False)
    ref = results(sweeps.load(out))
    victim = out / "chunks" / "chunk-000002.parquet"
    victim.write_bytes(victim.read_bytes()[:-40])  # truncated
    with pytest.raises(StoreError, match="chunk 2 .* damaged"):
        sweeps.load(out)
    with pytest.warns(UserWarning, match="chunk 2 .* damaged .* recomputed"):
        s = sweeps.run(spec, out, workers=1, progress=False)
    assert s.computed == [2]
    pd.testing.assert_frame_equal(results(sweeps.load(out)), ref)


def test_a_damaged_manifest_or_chunk_record_is_named_or_recomputed(tmp_path, capsys):
    """The other files of a store: a manifest that is not one is a one-line error naming it; a chunk record that is
    not one makes that chunk unfinished, so a resumed sweep recomputes it."""
    spec, out = write(tmp_path, small("analytic")), tmp_path / "store"
    sweeps.run(spec, out, workers=1, progress=False)
    ref = results(sweeps.load(out))
    (out / "chunks" / "chunk-000001.json").write_text("[1, 2]\n")
    with pytest.warns(
        UserWarning,
        match=r"chunk 1 of .* has a damaged record chunk-000001.json \(a JSON list, expected an object\); it will be recomputed",
    ):
        s = sweeps.run(spec, out, workers=1, progress=False)
    assert s.computed == [1]
    pd.testing.assert_frame_equal(results(sweeps.load(out)), ref)
    (out / "manifest.json").write_text("42\n")
    with pytest.raises(StoreError) as e:
        sweeps.load(out)
    assert str(e.value) == (
        f"manifest {str(out / 'manifest.json')!r} is damaged (no format, spec, spec_sha256, n_chunks); "
        "re-run the same crosscheck sweep command to rebuild it (its intact chunks are kept)"
    )
    with pytest.warns(UserWarning, match="is damaged .*; rebuilt from the spec, keeping the 6 chunks recorded for it"):
        assert main(["sweep", str(spec), "--out", str(out), "--no-progress"]) == 0
    assert "6 reused, 0 computed" in capsys.readouterr().out
    pd.testing.assert_frame_equal(results(sweeps.load(out)), ref)


def test_a_failing_chunk_is_recorded_and_the_sweep_goes_on(tmp_path, capsys):
    """timestep 1e-9 over horizon 0.2: 2e8 steps, a record of 286 GiB the rigid engine refuses when the run starts (its
    bytes per row are the engine's own); one run per chunk, so half the chunks fail, are recorded, and the others finish."""
    spec, out = write(tmp_path, small("pinocchio", chunk=1, timestep=[1e-3, 1e-9])), tmp_path / "store"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 1
    printed = capsys.readouterr().out
    m = Store(out).read_manifest()
    assert len(m["chunks"]) == 24 and len(m["failed"]) == 24 and "24 failed" in printed
    assert all(e.startswith("ValueError: horizon / timestep must be at most ") for e in m["failed"].values())
    assert "chunk 1 failed: ValueError: horizon / timestep must be at most " in printed
    with pytest.raises(StoreError, match="unfinished: 24 of 48 chunks missing"):
        sweeps.load(out)
    assert len(sweeps.load(out, partial=True)) == 24


def test_a_timestep_above_the_horizon_is_refused_before_any_chunk_runs(tmp_path):
    with pytest.raises(
        SpecError, match=r"^options timestep = 1\.0: timestep must be in \(0, sweep.horizon = 0.2\]; got 1\.0$"
    ):
        sweeps.load_spec(write(tmp_path, small("pinocchio", chunk=1, timestep=[1e-3, 1.0])))


BAD = {
    "unknown table": ("[sweeep]\n", r"unknown table \[sweeep\]; tables are \[sweep\], \[states\]"),
    "unknown key": (
        "[sweep]\nengine = 'mujoco'\nhorizon = 1\nspeed = 2\n[states]\n",
        r"unknown key 'speed' in \[sweep\]; keys are chunk, engine, horizon, seed",
    ),
    "horizon type": (
        "[sweep]\nengine = 'mujoco'\nhorizon = 'long'\n[states]\ntheta=1\n[parameters]\nmu=1\n",
        "sweep.horizon must be a number; got 'long'",
    ),
    "horizon nan": (
        "[sweep]\nengine = 'mujoco'\nhorizon = nan\n[states]\ntheta=1\n[parameters]\nmu=1\n",
        r"sweep.horizon must be in \(0, 10000\]; got nan",
    ),
    "engine": (
        "[sweep]\nengine = 'no_such_engine'\nhorizon = 1\n[states]\ntheta=1\n[parameters]\nmu=1\n",
        f"sweep.engine must be one of {', '.join(sorted(['analytic', *engines.names()]))}; got 'no_such_engine'",
    ),
}


@pytest.mark.parametrize("case", BAD, ids=str)
def test_bad_spec_sections_are_named(case):
    text, message = BAD[case]
    with pytest.raises(SpecError, match=message):
        parse_spec(__import__("tomllib").loads(text))


@pytest.mark.parametrize(
    "old, new, message",
    [
        ("num = 3", "num = 0", r"states.theta.num must be in \[1, 1e\+07\]; got 0"),
        ("Theta = [0.0, 0.6]", "Theta = []", "states.Theta must not be an empty list"),
        ("Theta = [0.0, 0.6]", "Theta = nan", r"states.Theta must be in \[-100, 100\]; got nan"),
        ("stop = 1.1", "stop = 1.7", r"states.theta must be in \(0, 1.5708\]; got 1.7"),
        ("mu = [0.5, 1.4]", "mu = [-0.5]", r"parameters.mu must be in \[0, 1000\]; got -0.5"),
        ("chunk = 4", "chunk = 0", r"sweep.chunk must be in \[1, inf\]; got 0"),
        ("chunk = 4", "chunk = 2.5", "sweep.chunk must be an integer; got 2.5"),
        ("eta = 1.0", "", r"\[states\] needs every axis theta, varphi, Theta, Psi, eta; missing eta"),
    ],
    ids=["num", "empty", "nan", "theta-range", "mu", "chunk", "chunk-type", "missing-axis"],
)
def test_bad_spec_values_are_named(old, new, message):
    with pytest.raises(SpecError, match=message):
        parse_spec(__import__("tomllib").loads(small().replace(old, new)))


def test_bad_options_are_named():
    with pytest.raises(
        SpecError, match="unknown mujoco option 'stiffness' in \\[options\\]; known options: .*timestep"
    ):
        parse_spec(__import__("tomllib").loads(small(stiffness=1.0)))
    with pytest.raises(SpecError, match=r"options.timestep: timestep must be in \(0, inf\); got -0.001"):
        parse_spec(__import__("tomllib").loads(small(timestep=-1e-3)))


def test_cli_bad_spec_exits_2_with_one_line(tmp_path, capsys):
    spec = write(tmp_path, small().replace("num = 3", "num = -1"))
    assert main(["sweep", str(spec), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["crosscheck: error: states.theta.num must be in [1, 1e+07]; got -1"]
    assert main(["sweep", str(tmp_path / "missing.toml"), "--out", str(tmp_path / "o")]) == 2
    assert "spec must be a readable TOML file" in capsys.readouterr().err


def test_random_states_are_seeded_and_inside_their_ranges():
    text = (
        small()
        .replace("theta = {start = 0.5, stop = 1.1, num = 3}", "random = 50\ntheta = {low = 0.2, high = 1.2}")
        .replace("Theta = [0.0, 0.6]", "Theta = {low = -1.0, high = 1.0}")
        .replace("Psi = [0.0, 1.5]", "Psi = 0.5")
    )
    a, b = (parse_spec(__import__("tomllib").loads(text)) for _ in range(2))
    assert a.digest == b.digest and a.n_states == 50
    assert a.states["theta"].min() >= 0.2 and a.states["theta"].max() <= 1.2 and np.all(a.states["Psi"] == 0.5)
    c = parse_spec(__import__("tomllib").loads(text.replace("seed = 0", "seed = 1")))
    assert c.digest != a.digest


def test_compare_two_stores(tmp_path, capsys):
    an, mj = tmp_path / "analytic", tmp_path / "mujoco"
    sweeps.run(write(tmp_path, small("analytic"), "a.toml"), an, workers=1, progress=False)
    sweeps.run(write(tmp_path, small("mujoco", timestep=1e-3), "m.toml"), mj, workers=1, progress=False)
    assert main(["compare", str(an), str(mj)]) == 0
    out = capsys.readouterr().out
    assert "24 runs, agreement" in out
    c = compare_frames(sweeps.load(an), sweeps.load(mj))
    assert c.n == 24 and c.confusion.sum() == 24 and c.agreement == np.trace(c.confusion) / 24
    assert len(c.disagreeing) == 24 - np.trace(c.confusion)
    assert (mj / f"compare-{an.name}.json").is_file() and (mj / f"compare-{an.name}-disagreeing.csv").is_file()


def test_wilson_interval():
    lo, hi = wilson_interval(8, 10)
    assert lo == pytest.approx(0.4902, abs=1e-4) and hi == pytest.approx(
        0.9433, abs=1e-4
    )  # textbook values (Wilson 1927)
    assert wilson_interval(10, 10)[1] == pytest.approx(1.0, abs=1e-15) and all(
        math.isnan(x) for x in wilson_interval(0, 0)
    )


def test_listed_states_with_their_own_mu():
    doc = __import__("tomllib").loads(
        small()
        .replace("theta = {start = 0.5, stop = 1.1, num = 3}", "zip = true\ntheta = [0.5, 0.9]\nmu = [0.3, 2.0]")
        .replace("Theta = [0.0, 0.6]", "Theta = [0.0, 0.6]")
        .replace("Psi = [0.0, 1.5]", "Psi = [1.0, 0.0]")
        .replace("eta = 1.0", "eta = [1.0, 2.0]")
        .replace("varphi = -1.5707963267948966", "varphi = [-1.0, -2.0]")
        .replace("mu = [0.5, 1.4]\n", "")
    )
    spec = parse_spec(doc)
    cols = spec.runs()
    assert spec.n_runs == 2 and list(cols["mu"]) == [0.3, 2.0] and list(cols["eta"]) == [1.0, 2.0]
    doc["parameters"]["mu"] = 1.0
    with pytest.raises(SpecError, match="mu goes in \\[parameters\\] .* not both or neither"):
        parse_spec(doc)
    doc["parameters"].pop("mu")
    doc["states"]["eta"] = [1.0]
    with pytest.raises(
        SpecError, match="need lists of one length; got lengths theta 2, varphi 2, Theta 2, Psi 2, eta 1, mu 2"
    ):
        parse_spec(doc)


def test_without_a_terminal_progress_is_log_lines(tmp_path, capsys):
    sweeps.run(
        write(tmp_path, small("analytic", chunk=2)), tmp_path / "s", workers=1
    )  # 12 chunks, stderr is not a terminal here
    lines = capsys.readouterr().err.strip().splitlines()
    assert [line.split(",")[0] for line in lines] == [
        "sweep: 10/12 chunks",
        "sweep: 12/12 chunks",
    ] and "runs/s, ETA" in lines[0]


def test_analytic_hybrid_option_goes_through_the_impact(tmp_path):
    """Corollary 4.2 states at mu = 1.7: the first event is JAM; with hybrid = true the run goes on through the IWC."""
    import tomllib

    from crosscheck.theory.corollary import corollary_states

    states, _, _ = corollary_states(1.7, 3, np.random.default_rng(0))
    lists = {k: [getattr(s, k) for s in states] for k in ("theta", "varphi", "Theta", "Psi", "eta")}
    body = "\n".join(f"{k} = {v!r}" for k, v in lists.items())
    text = f"[sweep]\nengine = 'analytic'\nhorizon = 2.0\nchunk = 2\n[states]\nzip = true\n{body}\n[parameters]\nmu = 1.7\n[options]\nhybrid = [false, true]\n"
    sweeps.run(sweeps.parse_spec(tomllib.loads(text)), tmp_path / "h", workers=1, progress=False)
    df = sweeps.load(tmp_path / "h")
    first, through = df[~df.hybrid], df[df.hybrid]
    assert list(first.outcome) == ["JAM"] * 3 and first.jam_impulse.isna().all()
    assert not (through.outcome == "JAM").any() and (through.jam_impulse > 0).all()
    with pytest.raises(SpecError, match="unknown analytic option 'timestep'"):
        parse_spec(tomllib.loads(text.replace("hybrid = [false, true]", "timestep = 1e-3")))
    with pytest.raises(SpecError, match=r"options.restitution must be in \[0, 1\]; got 2"):
        parse_spec(tomllib.loads(text.replace("hybrid = [false, true]", "restitution = 2")))
