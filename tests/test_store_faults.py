"""A sweep store's files edited, copied, replaced or cut short by a full disk: each is named, and a re-run of the
same sweep repairs it without throwing away the chunks that are intact."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest
from conftest import tmpfs

from crosscheck import sweeps
from crosscheck.cli import main
from crosscheck.sweeps.store import StoreError

SPEC = """
[sweep]
engine = "analytic"
horizon = 0.2
seed = 0
chunk = 2
[states]
theta = {start = 0.5, stop = 1.1, num = 3}
varphi = -1.5707963267948966
Theta = [0.0, 0.6]
Psi = 0.0
eta = 1.0
[parameters]
mu = 0.5
alpha = 3.0
"""  # 6 runs in 3 chunks


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    root = tmp_path_factory.mktemp("store")
    spec = root / "spec.toml"
    spec.write_text(SPEC)
    out = root / "ref"
    sweeps.run(spec, out, workers=1, progress=False)
    return spec, out, sweeps.load(out).drop(columns=["wall_time"])


@pytest.fixture
def store(built, tmp_path):
    spec, ref_out, ref = built
    out = tmp_path / "store"
    shutil.copytree(ref_out, out)
    return spec, out, ref


def rerun(spec, out, *warned: str):
    """Re-run the sweep, expecting a warning matching each of ``warned``; the summary."""
    if not warned:
        return sweeps.run(spec, out, workers=1, progress=False)
    with pytest.warns(UserWarning) as record:
        s = sweeps.run(spec, out, workers=1, progress=False)
    messages = [str(w.message) for w in record]
    for pattern in warned:
        assert any(pattern in m for m in messages), (pattern, messages)
    return s


def same(out, ref):
    pd.testing.assert_frame_equal(sweeps.load(out).drop(columns=["wall_time"]), ref)


def test_a_copied_chunk_record_is_damaged_named_and_recomputed(store):
    spec, out, ref = store
    shutil.copy(out / "chunks" / "chunk-000001.json", out / "chunks" / "chunk-000002.json")
    with pytest.raises(
        StoreError,
        match=r"chunk 2 of .* has a damaged record chunk-000002.json \(names the file 'chunk-000001.parquet', "
        r"not 'chunk-000002.parquet' \(copied or edited\)\); re-run",
    ):
        sweeps.load(out)
    s = rerun(spec, out, "chunk 2 of", "damaged record chunk-000002.json")
    assert (s.reused, s.computed) == ([0, 1], [2])
    same(out, ref)


def test_a_copied_record_and_table_are_caught_by_the_table_s_runs(store):
    spec, out, ref = store
    for ext in ("json", "parquet"):
        shutil.copy(out / "chunks" / f"chunk-000001.{ext}", out / "chunks" / f"chunk-000002.{ext}")
    rec = json.loads((out / "chunks" / "chunk-000002.json").read_text())
    rec["file"] = "chunk-000002.parquet"
    (out / "chunks" / "chunk-000002.json").write_text(json.dumps(rec))
    with pytest.raises(StoreError, match=r"chunk 2 of .* is damaged \(its table does not hold runs 4 to 5\)"):
        sweeps.load(out)


@pytest.mark.parametrize("n_chunks", [4, 1, 0, "3", 2.5])
def test_an_edited_manifest_is_named_and_rebuilt_by_a_rerun(store, n_chunks):
    spec, out, ref = store
    m = json.loads((out / "manifest.json").read_text())
    m["n_chunks"] = n_chunks
    (out / "manifest.json").write_text(json.dumps(m))
    with pytest.raises(
        StoreError,
        match=r"manifest .* is damaged \(its content differs from its sha256: edited after it was written\); "
        r"re-run the same crosscheck sweep command to rebuild it \(its intact chunks are kept\)",
    ):
        sweeps.load(out)
    s = rerun(spec, out, "rebuilt from the spec, keeping the 3 chunks recorded for it")
    assert (s.reused, s.computed) == ([0, 1, 2], [])
    same(out, ref)


def test_an_unsealed_manifest_must_agree_with_itself(store):
    """A manifest of the first format (no seal of its own) is still read, and checked: n_chunks is n_runs in chunks."""
    spec, out, ref = store
    m = json.loads((out / "manifest.json").read_text())
    del m["sha256"]
    m["format"], m["n_chunks"] = 1, 10
    (out / "manifest.json").write_text(json.dumps(m))
    with pytest.raises(StoreError, match=r"is damaged \(n_chunks 10 is not n_runs 6 in chunks of 2\)"):
        sweeps.load(out)
    m["n_chunks"] = 3
    (out / "manifest.json").write_text(json.dumps(m))
    same(out, ref)


@pytest.mark.parametrize("damage", ["missing", "empty", "binary"])
def test_a_missing_or_damaged_manifest_is_rebuilt_keeping_the_intact_chunks(store, damage, capsys):
    spec, out, ref = store
    stamps = {p.name: p.stat().st_mtime_ns for p in (out / "chunks").iterdir()}
    if damage == "missing":
        (out / "manifest.json").unlink()
    else:
        (out / "manifest.json").write_bytes(b"" if damage == "empty" else b"\xff\xfe{")
    with pytest.warns(UserWarning, match="rebuilt from the spec, keeping the 3 chunks recorded for it"):
        assert main(["sweep", str(spec), "--out", str(out), "--no-progress", "--workers", "1"]) == 0
    assert "3 reused, 0 computed" in capsys.readouterr().out
    assert {p.name: p.stat().st_mtime_ns for p in (out / "chunks").iterdir()} == stamps
    same(out, ref)


def test_a_stray_file_in_chunks_is_named_and_ignored(store):
    spec, out, ref = store
    (out / "chunks" / "chunk-1.json").write_text("{}")
    same(out, ref)
    s = rerun(spec, out, "chunk-1.json' is not a file of the sweep store; it is ignored")
    assert s.computed == []
    assert (out / "chunks" / "chunk-1.json").exists()


@pytest.mark.parametrize("text", ["{", '{"file": "chunk-000000.parquet"}', '{"error": 3}'])
def test_a_damaged_record_is_named_when_it_is_recomputed(store, text):
    spec, out, ref = store
    (out / "chunks" / "chunk-000000.json").write_text(text)
    s = rerun(spec, out, "chunk 0 of", "has a damaged record chunk-000000.json")
    assert s.computed == [0]
    same(out, ref)


def test_a_record_past_the_last_chunk_is_named(store):
    spec, out, ref = store
    shutil.copy(out / "chunks" / "chunk-000001.json", out / "chunks" / "chunk-000007.json")
    with pytest.raises(StoreError, match=r"chunk 7 of .* \(chunk 7 is past the sweep's last chunk 2\)"):
        sweeps.load(out)
    rerun(spec, out, "chunk 7 of")
    same(out, ref)


def test_chunks_replaced_by_a_file_is_one_line(store, capsys):
    spec, out, _ = store
    shutil.rmtree(out / "chunks")
    (out / "chunks").write_text("x")
    assert main(["sweep", str(spec), "--out", str(out), "--no-progress", "--workers", "1"]) == 2
    assert capsys.readouterr().err == (
        f"crosscheck: error: out {str(out)!r} is damaged: {str(out / 'chunks')!r} is not a directory; "
        "use --fresh to start the sweep again\n"
    )
    with pytest.raises(StoreError, match="is not a directory"):
        sweeps.load(out)
    assert main(["sweep", str(spec), "--out", str(out), "--no-progress", "--workers", "1", "--fresh"]) == 0


# ------------------------------------------------------------------ a full disk ---


@pytest.fixture
def small_disk(tmp_path):
    """A real 1 MiB tmpfs (skipped where this process cannot mount one)."""
    with tmpfs(tmp_path / "disk") as mnt:
        yield mnt


def fill(mnt: Path, leave: int) -> None:
    """Fill the file system at ``mnt`` up to ``leave`` bytes."""
    import os

    st = os.statvfs(mnt)
    (mnt / "filler").write_bytes(b"\0" * max(st.f_bavail * st.f_frsize - leave, 0))


@pytest.mark.parametrize("leave", [0, 12 * 1024])
def test_a_full_disk_is_one_line_naming_the_directory_and_the_space(built, small_disk, capsys, leave):
    """No room at all (the manifest cannot be written), or room for the manifest but not for every chunk."""
    spec, _, ref = built
    fill(small_disk, leave)
    out = small_disk / "out"
    assert main(["sweep", str(spec), "--out", str(out), "--no-progress", "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert (
        err.count("\n") == 1
        and err.startswith("crosscheck: error: out ")
        and "has no room left (No space left on device): writing " in err
    )
    assert "bytes needs at least that much free space" in err and str(small_disk) in err
    if out.exists():
        assert not [p for p in out.rglob(".*tmp*")]  # nothing half-written left behind ...
        if (out / "manifest.json").exists():
            with pytest.raises(StoreError, match="unfinished"):  # ... or read
                sweeps.load(out)
    (small_disk / "filler").unlink()
    assert main(["sweep", str(spec), "--out", str(out), "--no-progress", "--workers", "1"]) == 0
    same(out, ref)


def test_option_combinations_are_checked_before_any_chunk_runs(tmp_path, capsys):
    """Each swept option is valid alone; one combination is not (MuJoCo's timeconst >= 2 timestep): refused before the store is touched."""
    spec = tmp_path / "combo.toml"
    spec.write_text(
        SPEC.replace('engine = "analytic"', 'engine = "mujoco"')
        + "[options]\ntimestep = [1e-3, 0.02]\ntimeconst = [0.06, 0.03]\n"
    )
    assert main(["sweep", str(spec), "--out", str(tmp_path / "o"), "--no-progress"]) == 2
    assert capsys.readouterr().err == (
        "crosscheck: error: options timestep = 0.02, timeconst = 0.03: timeconst must be >= 2 timestep = 0.04 "
        "(MuJoCo's refsafe); got 0.03\n"
    )
    assert not (tmp_path / "o").exists()


def test_a_store_without_its_manifest_holding_another_sweep_is_not_rebuilt(store, tmp_path):
    """Chunks recorded for another spec (or before specs were recorded) are not deleted to rebuild a manifest."""
    spec, out, _ = store
    (out / "manifest.json").unlink()
    other = tmp_path / "other.toml"
    other.write_text(SPEC.replace("mu = 0.5", "mu = 0.6"))
    with pytest.raises(
        StoreError,
        match=r"manifest .* is missing, and chunk record chunk-000000.json was not recorded for this spec; use --fresh",
    ):
        sweeps.run(other, out, workers=1, progress=False)
    assert len(list((out / "chunks").glob("*.parquet"))) == 3
