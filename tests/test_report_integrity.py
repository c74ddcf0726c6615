"""Saved results are checked before a report uses them; a report directory has one writer; a killed run is finished later."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import tmpfs

from crosscheck import report
from crosscheck.cli import main
from crosscheck.locking import owner_text
from crosscheck.report.section import Section, Table


def _run(ctx):
    ctx.store.write_table("values", {"x": np.arange(3.0), "y": np.arange(3.0) ** 2})
    ctx.store.write_json("summary", {"mean": 1.0, "n": 3})
    ctx.store.write_grid("field", ("x", np.arange(2.0)), ("y", np.arange(3.0)), ("z", np.ones((3, 2))))
    ctx.check("toy check", True, value=0.0, allowance=1.0)


def _render(ctx):
    t = ctx.store.read_table("values")
    ctx.store.read_json("summary")
    ctx.store.read_grid("field")
    return [
        Table(
            caption="values",
            header=["x", "y"],
            rows=[[f"{a:g}", f"{b:g}"] for a, b in zip(t["x"], t["y"])],
            data=ctx.data("values.csv"),
        )
    ]


TOY = Section("toy", "Toy", "", lambda quick: {"n": 3}, _run, _render)


@pytest.fixture
def saved(tmp_path, monkeypatch):
    """A finished toy report: its directory."""
    monkeypatch.setattr(report, "SECTIONS", (TOY,))
    out = tmp_path / "r"
    assert main(["report", "--out", str(out), "--no-progress"]) == 0
    return out


def _truncate(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def _edit_number(path: Path) -> None:
    """One digit changed, the size kept: only the checksum can tell."""
    data = path.read_bytes()
    path.write_bytes(data.replace(b"4", b"5", 1) if b"4" in data else data.replace(b"1", b"7", 1))


# (what is damaged, how, and the phrase the one-line error must contain besides the file's name)
DAMAGE = [
    ("toy/values.csv", _truncate, "bytes, the run wrote"),
    ("toy/values.csv", _edit_number, "sha256 differs"),
    ("toy/values.csv", Path.unlink, "missing"),
    ("toy/summary.json", _truncate, "bytes, the run wrote"),
    ("toy/summary.json", lambda p: p.write_text('{"mean": 2.0, "n": 3}\n'), ""),
    ("toy/field.json", _edit_number, "sha256 differs"),
    ("toy/checks.json", lambda p: p.write_text(p.read_text().replace("true", "false")), ""),
    ("toy/extra.csv", lambda p: p.write_text("x\n1\n"), "not written by the run"),
    ("toy/status.json", lambda p: p.write_text("42\n"), "a JSON int, expected an object"),
    ("toy/status.json", _truncate, "not readable JSON"),
    (
        "toy/status.json",
        lambda p: p.write_text(json.dumps({**json.loads(p.read_text()), "files": None})),
        "no manifest",
    ),
    (
        "toy/status.json",
        lambda p: p.write_text(json.dumps({**json.loads(p.read_text()), "status": "done"})),
        "status 'done'",
    ),
    ("provenance.json", _truncate, "not readable JSON"),
    ("provenance.json", lambda p: p.write_text('{"date": 1}'), "not the provenance"),
    ("provenance.json", lambda p: p.write_text("[]"), "a JSON list"),
    # one bit flipped, the shape kept: only the seal beside the file can tell
    (
        "provenance.json",
        lambda p: p.write_bytes(p.read_bytes().replace(b'"date": "2', b'"date": "3', 1)),
        "sha256 differs",
    ),
    ("provenance.json", lambda p: p.with_name(p.name + ".sha256").unlink(), "has no seal provenance.json.sha256"),
    ("provenance.json", lambda p: p.write_bytes(p.read_bytes() + b" "), "bytes, the run wrote"),
    (
        "toy/status.json",
        lambda p: p.write_bytes(p.read_bytes().replace(b'"seed": 0', b'"seed": 1', 1)),
        "sha256 differs",
    ),
    ("toy/status.json", lambda p: p.with_name(p.name + ".sha256").write_text("{}"), "is not one (no bytes and sha256)"),
]


@pytest.mark.parametrize(
    "name, damage, phrase", DAMAGE, ids=[f"{n}:{getattr(d, '__name__', 'edit')}:{p or 'changed'}" for n, d, p in DAMAGE]
)
def test_from_results_refuses_a_damaged_file_with_one_line_naming_it(saved, name, damage, phrase, capsys):
    path = saved / "data" / name
    damage(path)
    index = (saved / "index.html").read_bytes()
    capsys.readouterr()
    assert main(["report", "--from-results", "--out", str(saved), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"crosscheck: error: {path}: ") and phrase in err, err
    assert (saved / "index.html").read_bytes() == index  # nothing rendered from it


def test_an_undamaged_report_renders_from_results(saved):
    assert main(["report", "--from-results", "--out", str(saved), "--no-progress"]) == 0


def test_a_resumed_run_recomputes_a_damaged_section_instead_of_keeping_it(saved, capsys):
    _truncate(saved / "data" / "toy" / "values.csv")
    assert main(["report", "--out", str(saved), "--no-progress"]) == 0
    assert "kept" not in capsys.readouterr().out
    assert main(["report", "--from-results", "--out", str(saved), "--no-progress"]) == 0


def test_a_second_writer_is_refused_with_one_line(saved, capsys):
    with report.lock(saved):
        capsys.readouterr()
        assert main(["report", "--out", str(saved), "--no-progress"]) == 2
        err = capsys.readouterr().err
        assert err == (
            f"crosscheck: error: out must be a report directory no other process is writing; {str(saved)!r} is being written "
            f"by {owner_text()} (wait for it, or choose another --out)\n"
        )
        assert f"pid {os.getpid()} on " in err  # the holder: its pid, host and command
    assert main(["report", "--out", str(saved), "--no-progress"]) == 0  # released with its holder


_KILLED_RUN = textwrap.dedent("""
    import sys, time
    import numpy as np
    from crosscheck import report
    from crosscheck.cli import main
    from crosscheck.report.section import Section

    def run(ctx):
        ctx.store.write_table("half", {"x": np.arange(3.0)})
        if sys.argv[2] == "slow":
            time.sleep(120)  # killed here
        ctx.store.write_table("rest", {"x": np.arange(3.0)})

    report.SECTIONS = (Section("toy_slow", "Slow toy", "", lambda q: {}, run, lambda ctx: []),)
    extra = ["--from-results"] if sys.argv[2] == "render" else []
    sys.exit(main(["report", "--out", sys.argv[1], "--no-progress", *extra]))
""")


def test_a_section_killed_by_sigkill_is_shown_unfinished_and_the_next_run_completes_it(tmp_path):
    out = tmp_path / "r"
    script = tmp_path / "killed.py"
    script.write_text(_KILLED_RUN)
    proc = subprocess.Popen(
        [sys.executable, str(script), str(out), "slow"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    half = out / "data" / "toy_slow" / "half.csv"
    deadline = time.monotonic() + 120
    while not half.exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    assert half.exists(), "the section never started"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    status = json.loads((out / "data" / "toy_slow" / "status.json").read_text())
    assert status["status"] == "running" and "files" not in status
    shown = subprocess.run([sys.executable, str(script), str(out), "render"], capture_output=True, text=True)
    # rendered (the lock died with its holder), with the section unfinished, never as done
    assert shown.returncode == 1 and "toy_slow: unfinished" in shown.stdout, shown.stdout + shown.stderr
    done = subprocess.run([sys.executable, str(script), str(out), "fast"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    status = json.loads((out / "data" / "toy_slow" / "status.json").read_text())
    assert status["status"] == "ok" and set(status["files"]) == {"half.csv", "rest.csv"}


def test_a_full_disk_is_one_line_naming_the_directory_and_leaves_the_section_unfinished(tmp_path, monkeypatch, capsys):
    """A real 1 MiB tmpfs, full but for a few pages: the section's table does not fit."""
    import shutil

    with tmpfs(tmp_path / "disk") as mnt:
        st = os.statvfs(mnt)
        (mnt / "filler").write_bytes(b"\0" * (st.f_bavail * st.f_frsize - 40000))

        def big(ctx):
            ctx.store.write_table("values", {"x": np.arange(4000.0)})

        monkeypatch.setattr(
            report, "SECTIONS", (Section("toy", "Toy", "", lambda quick: {"n": 3}, big, lambda ctx: []),)
        )
        assert main(["report", "--out", str(mnt / "r"), "--no-progress"]) == 2
        err = capsys.readouterr().err
        # one line naming the directory under the report's data that it could not write (data/ or the section's own)
        assert err.count("\n") == 1 and err.startswith(f"crosscheck: error: out '{mnt / 'r' / 'data'}")
        assert "' has no room left (No space left on device): writing " in err
        assert "bytes needs at least that much free space" in err
        assert not list((mnt / "r").rglob(".*.tmp-*"))  # nothing half-written left ...
        status = mnt / "r" / "data" / "toy" / "status.json"
        if status.exists():  # ... and the section is not taken as finished
            assert json.loads(status.read_text())["status"] in ("running", "error")
        (mnt / "filler").unlink()
        assert main(["report", "--out", str(mnt / "r"), "--no-progress"]) == 0
        shutil.rmtree(mnt / "r")


def test_a_disk_that_fills_during_the_render_is_one_line(tmp_path, monkeypatch, capsys):
    """A real 1 MiB tmpfs that fills while the pages are written (a filler written by the section's render)."""
    with tmpfs(tmp_path / "disk") as mnt:

        def fill(ctx):
            st = os.statvfs(mnt)
            (mnt / "filler").write_bytes(b"\0" * (st.f_bavail * st.f_frsize))
            return [Table(caption="t", header=["x"], rows=[["1"]] * 20000, data=ctx.data("values.csv"))]

        monkeypatch.setattr(report, "SECTIONS", (Section("toy", "Toy", "", lambda quick: {"n": 3}, _run, fill),))
        assert main(["report", "--out", str(mnt / "r"), "--no-progress"]) == 2
        err = capsys.readouterr().err
        assert (
            err.count("\n") == 1
            and err.startswith(f"crosscheck: error: out {str(mnt / 'r')!r}")
            and "has no room left (No space left on device)" in err
        )


def _render_newer(ctx):
    """The toy's render as a later version of it: it reads a key its saved summary (an earlier version's) lacks."""
    return [Table(caption="n", header=["n"], rows=[[str(ctx.store.read_json("summary")["median"])]])]


def test_results_saved_by_another_version_of_a_section_name_the_missing_key_and_the_rerun(saved, monkeypatch, capsys):
    monkeypatch.setattr(report, "SECTIONS", (Section("toy", "Toy", "", lambda quick: {"n": 3}, _run, _render_newer),))
    capsys.readouterr()
    assert main(["report", "--from-results", "--out", str(saved), "--no-progress"]) == 1
    out = capsys.readouterr()
    line = next(x for x in (out.out + out.err).splitlines() if "render failed" in x)
    assert "KeyError: 'median'" in line and "rerun it with `crosscheck report --only toy`" in line, line
    assert "Traceback" not in out.out + out.err
