"""Ctrl-C: a real SIGINT to the command's process group stops a sweep at once with one line, keeps every chunk it
wrote, and the same command resumes them."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

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
        argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, start_new_session=True
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
