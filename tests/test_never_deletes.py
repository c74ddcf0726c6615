"""crosscheck deletes or overwrites only what it can prove it wrote: directories holding a user's files stay as they were.

Each test fills a directory with a user's files (a project, a web app, the
package's own source), runs the real command into it, and compares every
file's bytes before and after.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

import crosscheck
from crosscheck.cli import main
from crosscheck.sweeps import Store
from crosscheck.sweeps.spec import parse_spec


def _snapshot(root: Path) -> dict[str, str]:
    """Every file under ``root`` by relative path, with the sha256 of its bytes."""
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest() for p in root.rglob("*") if p.is_file()
    }


def _user_project(root: Path) -> dict[str, str]:
    """A user's project with the names a report and a sweep write (a sweep store of theirs, pages, a manifest)."""
    files = {
        "index.html": "<p>my site</p>",
        "report.md": "# my notes",
        "style.css": "body{color:red}",
        "sweeps/mine/notes.txt": "a store of mine",
        "data/table.csv": "a,b\n1,2\n",
        "figures/f.png": "not a png",
        "manifest.json": '{"name": "my app"}',
        "chunks/app.js": "console.log(1)",
        "chunks/chunk-000000.parquet": "my own file with the store's name",
    }
    for name, text in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return _snapshot(root)


QUICK = ["report", "--quick", "--only", "critical_angles", "--no-progress"]
SPEC = (
    '[sweep]\nengine = "analytic"\nhorizon = 0.3\nchunk = 2\n[states]\ntheta = [0.7, 0.9, 1.3]\nvarphi = -1.2\n'
    "Theta = 0.1\nPsi = 0.0\neta = 0.5\n[parameters]\nmu = 0.3\n"
)


@pytest.mark.parametrize("extra", [[], ["--fresh"], ["--beside-files"], ["--beside-files", "--fresh"]], ids=str)
def test_report_refuses_a_users_directory_and_deletes_nothing(tmp_path, capsys, extra):
    before = _user_project(tmp_path)
    assert main(QUICK + ["--out", str(tmp_path), *extra]) == 2
    err = capsys.readouterr().err
    assert err.startswith("crosscheck: error: out must be a directory") and err.count("\n") == 1, err
    assert "--beside-files" in err  # the flag that would help, or that it never replaces a file
    assert _snapshot(tmp_path) == before


def test_report_into_the_package_source_deletes_nothing(capsys):
    package = Path(crosscheck.__file__).parent
    before = _snapshot(package / "sweeps")
    for extra in ([], ["--fresh"], ["--beside-files"]):
        assert main(QUICK + ["--out", str(package), *extra]) == 2
        assert "crosscheck: error: out must be a directory" in capsys.readouterr().err
    assert _snapshot(package / "sweeps") == before
    assert not (package / ".crosscheck-report").exists()


def test_report_beside_a_users_files_adds_its_own_and_keeps_theirs(tmp_path, capsys):
    (tmp_path / "thesis.tex").write_text("\\begin{document}")
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "run.csv").write_text("1,2\n")
    before = _snapshot(tmp_path)
    assert main(QUICK + ["--out", str(tmp_path)]) == 2  # refused without the flag
    assert main(QUICK + ["--out", str(tmp_path), "--beside-files"]) == 0
    after = _snapshot(tmp_path)
    assert {k: after[k] for k in before} == before
    assert {"index.html", "report.md", "style.css", ".crosscheck-report"} <= set(after)
    # every page links the one stylesheet beside it instead of carrying its own copy
    index = (tmp_path / "index.html").read_text()
    assert '<link rel="stylesheet" href="style.css">' in index and "<style>" not in index
    # the directory is the report's now: a rerun needs no flag, and --fresh still keeps the user's files
    assert main(QUICK + ["--out", str(tmp_path), "--fresh"]) == 0
    assert {k: _snapshot(tmp_path)[k] for k in before} == before


def test_a_reports_sweeps_without_its_stamp_is_refused_not_deleted(tmp_path, capsys):
    assert main(QUICK + ["--out", str(tmp_path)]) == 0
    (tmp_path / "sweeps" / "computed_by.json").unlink()
    (tmp_path / "sweeps" / "theirs.txt").write_text("x")
    assert main(QUICK + ["--out", str(tmp_path)]) == 2
    assert "has no computed_by.json" in capsys.readouterr().err
    assert (tmp_path / "sweeps" / "theirs.txt").read_text() == "x"


@pytest.mark.parametrize("extra", [[], ["--fresh"]], ids=str)
def test_sweep_refuses_a_web_app_and_deletes_nothing(tmp_path, capsys, extra):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    app = tmp_path / "webapp"
    app.mkdir()
    before = _user_project(app)
    assert main(["sweep", str(spec), "--out", str(app), "--no-progress", *extra]) == 2
    err = capsys.readouterr().err
    assert err.startswith("crosscheck: error: out must be a directory") and err.count("\n") == 1, err
    assert _snapshot(app) == before


def test_sweep_fresh_deletes_only_the_stores_own_files(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    out = tmp_path / "store"
    assert main(["sweep", str(spec), "--out", str(out), "--no-progress", "--workers", "1"]) == 0
    (out / "chunks" / "app.js").write_text("mine")
    (out / "chunks" / "chunk-0000001.json").write_text("mine too: a leading zero is not the store's name")
    (out / "notes.txt").write_text("mine")
    assert main(["sweep", str(spec), "--out", str(out), "--no-progress", "--workers", "1", "--fresh"]) == 0
    assert "2 chunks (3 runs): 0 reused, 2 computed" in capsys.readouterr().out
    assert (out / "chunks" / "app.js").read_text() == "mine"
    assert (out / "chunks" / "chunk-0000001.json").read_text().startswith("mine too")
    assert (out / "notes.txt").read_text() == "mine"


def test_a_chunk_past_999999_counts_as_finished(tmp_path):
    """Chunk 1000000 is named chunk-1000000.*: the store reads it as its own, keeps it, and loads it."""
    spec = parse_spec(
        {
            "sweep": {"engine": "analytic", "horizon": 0.3, "chunk": 1},
            "states": {"theta": 0.9, "varphi": -1.2, "Theta": 0.0, "Psi": 0.0, "eta": 0.5},
            "parameters": {"mu": {"start": 0.0, "stop": 1.0, "num": 1_000_002}},
        }
    )
    store = Store(tmp_path / "s")
    m = store.open(spec)
    for cid in (999_999, 1_000_000, 1_000_001):
        store.write_chunk(m, cid, {"run": [cid], "chunk": [cid], "x": [float(cid)]}, 0.1)
    store.record_failure(m, 1_000_001, "a failure recorded after the chunk")
    got = store.read_manifest()
    assert sorted(got["chunks"], key=int) == ["999999", "1000000", "1000001"]
    assert got["failed"] == {"1000001": "a failure recorded after the chunk"}
    assert got["stray"] == [] and got["damaged"] == {}
    assert store.verified(got) == {999_999, 1_000_000, 1_000_001}
    table = store.load(partial=True)
    np.testing.assert_array_equal(table["run"], [999_999, 1_000_000, 1_000_001])


SIM = ["simulate", "--engine", "pinocchio", "--theta", "0.83", "--varphi", "-2.4", "--Theta", "-0.3", "--Psi", "0.7"]
SIM += ["--eta", "1.3", "--mu", "0.6", "--horizon", "0.05"]


@pytest.mark.parametrize(
    "outputs, param",
    [
        (["--plot", "fig.svg", "--csv", "fig.svg"], "csv"),
        (["--plot", "run.pdf", "--csv", "run_theory.csv"], "csv"),
        (["--plot", "sub/../b.png", "--csv", "b_theory.csv"], "csv"),
        (["--plot", "mine.json"], "plot"),
        (["--plot", "mine.csv"], "plot"),
    ],
    ids=str,
)
def test_simulate_never_writes_one_output_over_another_or_a_users_file(tmp_path, monkeypatch, capsys, outputs, param):
    monkeypatch.chdir(tmp_path)
    for name in ("fig.svg", "run_theory.csv", "b_theory.csv", "mine.json", "mine.csv"):
        (tmp_path / name).write_text("the user's")
    before = _snapshot(tmp_path)
    assert main(SIM + outputs) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"crosscheck: error: {param} must be a file") and err.count("\n") == 1, err
    assert _snapshot(tmp_path) == before


def test_simulate_plot_without_a_suffix_names_the_file_it_wrote(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(SIM + ["--plot", "fig7"]) == 0
    out = capsys.readouterr().out
    assert [line for line in out.splitlines() if line.startswith("wrote")] == [
        "wrote fig7.png",
        "wrote fig7.csv",
        "wrote fig7_theory.csv",
    ]
    assert (tmp_path / "fig7.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
