"""Ctrl-C: a real SIGINT to the command's process group stops a sweep or a report at once with one line, keeps every
chunk and section it finished, and the same command resumes them; a simulation or a ladder stops at once, even inside
an engine's long C call, with one line and nothing written."""

from __future__ import annotations

import json
import os
import pty
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

SPEC = """[sweep]
engine = "pinocchio"
horizon = 0.4
chunk = 1
[states]
theta = {start = 0.55, stop = 1.25, num = 14}
varphi = -1.7
Theta = 0.2
Psi = 0.0
eta = 1.5
[parameters]
mu = 0.45
"""

#: How long a stop may take after the SIGINT: the workers are killed, not waited for (a chunk here takes ~0.3 s; the
#: pool's queued chunks once ran on for 11 s).
STOP_SECONDS = 5.0


def _hear_sigint() -> None:
    """In the child before its exec: SIGINT to its default, which Python turns into KeyboardInterrupt.  A shell
    without job control starts a background command (``pytest ... &``) with SIGINT ignored, and an ignored signal
    stays ignored across exec: the command would never hear the Ctrl-C this test sends."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _finished(out: Path) -> set[str]:
    return {p.name for p in (out / "chunks").glob("chunk-*.json")} if (out / "chunks").is_dir() else set()


def test_a_sigint_stops_a_sweep_with_one_line_and_the_rerun_resumes(tmp_path):
    spec, out = tmp_path / "spec.toml", tmp_path / "store"
    spec.write_text(SPEC)
    argv = [
        sys.executable,
        "-m",
        "crosscheck",
        "sweep",
        str(spec),
        "--out",
        str(out),
        "--workers",
        "2",
        "--no-progress",
    ]
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    proc = subprocess.Popen(
        argv,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        start_new_session=True,
        preexec_fn=_hear_sigint,
    )
    deadline = time.monotonic() + 120
    while len(_finished(out)) < 2 and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    assert proc.poll() is None, "the sweep ended before it could be interrupted: give it more chunks"
    os.killpg(proc.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the parent and every worker get it
    t0 = time.monotonic()
    out_text, err = proc.communicate(timeout=60)
    assert time.monotonic() - t0 < STOP_SECONDS
    assert proc.returncode == 130
    assert err.splitlines() == [
        "crosscheck: interrupted; finished sweep chunks and report sections are kept (the same command resumes)"
    ], err
    kept = _finished(out)
    assert 2 <= len(kept) < 14
    for name in kept:  # each kept chunk is whole: its record names its file and that file has its sha256
        rec = json.loads((out / "chunks" / name).read_text())
        assert (out / "chunks" / rec["file"]).is_file()
    rerun = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=300)
    assert rerun.returncode == 0, rerun.stderr
    assert f"14 chunks (14 runs): {len(kept)} reused, {14 - len(kept)} computed, 0 failed" in rerun.stdout


#: A report of a few sections: three of the theory's (a few ms each) and three engines' (~1 s each in the quick
#: report), so that the run is interrupted with some sections finished and some not.
REPORT_SECTIONS = [
    "critical_angles",
    "printed_numbers",
    "p_region",
    "mujoco_rounding",
    "physx_tgs_convergence",
    "drake_sap_convergence",
]
#: The report command in its own process, on the sections above (``crosscheck.report.SECTIONS``, which a caller sets).
REPORT = (
    "import sys, crosscheck.report as r; r.SECTIONS = [r.section_by_slug(s) for s in {sections!r}]; "
    "from crosscheck.cli import main; sys.exit(main(sys.argv[1:]))"
)


def _statuses(out: Path) -> dict[str, str]:
    got = {}
    for f in (out / "data").glob("*/status.json") if (out / "data").is_dir() else ():
        try:
            got[f.parent.name] = json.loads(f.read_text())["status"]
        except (OSError, ValueError, KeyError):  # being written
            pass
    return got


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_sigint_stops_a_report_and_the_rerun_resumes_its_finished_sections(tmp_path, jobs):
    out = tmp_path / "report"
    argv = [sys.executable, "-c", REPORT.format(sections=REPORT_SECTIONS), "report", "--quick", "--out", str(out)]
    argv += ["--no-progress", "--jobs", jobs, "--workers", "1"]
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    proc = subprocess.Popen(
        argv,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        start_new_session=True,
        preexec_fn=_hear_sigint,
    )
    deadline = time.monotonic() + 180
    while list(_statuses(out).values()).count("ok") < 2 and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    assert proc.poll() is None, "the report ended before it could be interrupted: give it longer sections"
    os.killpg(proc.pid, signal.SIGINT)
    t0 = time.monotonic()
    _, err = proc.communicate(timeout=60)
    assert time.monotonic() - t0 < STOP_SECONDS
    assert proc.returncode == 130
    assert err.splitlines() == [
        "crosscheck: interrupted; finished sweep chunks and report sections are kept (the same command resumes)"
    ], err
    finished = sorted(k for k, v in _statuses(out).items() if v == "ok")
    assert 2 <= len(finished) < len(REPORT_SECTIONS)
    rerun = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=600)
    assert rerun.returncode == 0, rerun.stderr
    assert f"kept {len(finished)} finished sections" in rerun.stdout
    prov = json.loads((out / "data" / "provenance.json").read_text())
    assert sorted(prov["sections_resumed"]) == finished
    assert prov["rod"] == {
        "mass": 1.0,
        "length": 1.0,
        "gravity": 1.0,
        "units": "scaled: time 1/omega, lengths l, forces m g",
    }
    assert sorted(_statuses(out)) == sorted(REPORT_SECTIONS) and set(_statuses(out).values()) == {"ok"}


IC2 = ["--theta", "1.1031", "--varphi", "-1.9233", "--Theta", "0.9", "--Psi", "0", "--eta", "2", "--mu", "1.4"]


@pytest.mark.parametrize(
    "argv",
    [
        # MuJoCo's rollout is one C call of about a minute: the KeyboardInterrupt would wait for its end
        ["simulate", "--engine", "mujoco", *IC2, "--horizon", "1500", "--csv", "run.csv"],
        ["simulate", "--engine", "pinocchio", *IC2, "--horizon", "2796", "--csv", "run.csv"],
        ["explain", "--engine", "mujoco", *IC2, "--horizon", "3000", "--plot", "ladder.png"],
    ],
    ids=lambda a: f"{a[0]} {a[2]}",
)
def test_a_sigint_stops_a_long_run_at_once_with_one_line(tmp_path, argv):
    """On a terminal (a real pseudo-terminal) the run shows its seconds; a SIGINT once it is shown ends it within
    STOP_SECONDS, one line, exit 130, and none of its files written."""
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    master, slave = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "crosscheck", *argv],
        stdout=subprocess.PIPE,
        stderr=slave,
        text=True,
        env=env,
        cwd=tmp_path,
        start_new_session=True,
        preexec_fn=_hear_sigint,
    )
    os.close(slave)
    shown = _read_until(master, f"ing {argv[2]} to t = {argv[argv.index('--horizon') + 1]}: ", 120)
    assert proc.poll() is None, shown
    os.killpg(proc.pid, signal.SIGINT)
    t0 = time.monotonic()
    out, _ = proc.communicate(timeout=300)
    assert time.monotonic() - t0 < STOP_SECONDS
    assert proc.returncode == 130
    assert out == ""
    err = _read_until(master, "\n", 10)
    assert err.split("\x1b[K")[-1].strip() == (  # after the erased seconds line
        "crosscheck: interrupted; nothing was written (files are written once the run has finished)"
    ), err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []
    os.close(master)


def _read_until(fd: int, text: str, timeout: float) -> str:
    """What the pseudo-terminal ``fd`` shows until ``text`` (or ``timeout`` seconds, or its end)."""
    got, deadline = "", time.monotonic() + timeout
    while text not in got and time.monotonic() < deadline:
        ready, _, _ = select.select([fd], [], [], 0.2)
        if ready:
            try:
                chunk = os.read(fd, 4096)
            except OSError:  # the other end closed
                break
            if not chunk:
                break
            got += chunk.decode(errors="replace")
    return got
