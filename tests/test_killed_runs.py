"""A run killed by SIGKILL leaves no worker and no lock behind: the same command can be rerun at once.

Real processes, real signals: a multi-worker sweep and a report are killed in
the middle and rerun; a stale lock file and a lock still held by a dead
writer's forked child are met as a user would meet them.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from conftest import small, tmpfs

from crosscheck import sweeps
from crosscheck.locking import exclusive, holders
from crosscheck.sweeps.store import Store

#: Seconds a killed run's workers may take to go (they get SIGKILL from the kernel when their parent dies).
ORPHAN_GRACE = 5.0

#: 24 rigid-engine runs (3 x 2 x 2 planar starts at two mu, 6667 steps each), 12 chunks of 2: long enough to be killed in the
#: middle (at horizon 0.6 and the default step the pool could finish before the test saw its workers).
SPEC = small("pinocchio", horizon=2.0, chunk=2, timestep=3e-4)


def _children(pid: int) -> list[int]:
    """Pids of the processes whose parent is ``pid`` (from /proc)."""
    kids = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                kids.append(int(d.name))
    return kids


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _wait_until(predicate, timeout: float, what: str):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if predicate():
            return
        time.sleep(0.02)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def _kill_when(proc: subprocess.Popen, predicate, what: str) -> list[int]:
    """SIGKILL ``proc`` once ``predicate()`` holds; returns the worker pids it had then."""
    _wait_until(lambda: predicate() or proc.poll() is not None, 120, what)
    assert proc.poll() is None, f"the run finished before it could be killed ({what})"
    workers = _children(proc.pid)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    return workers


def _no_orphans(workers: list[int]):
    _wait_until(
        lambda: not any(_alive(w) for w in workers), ORPHAN_GRACE, f"workers {workers} to die with their parent"
    )


def test_a_killed_multi_worker_sweep_leaves_no_workers_and_reruns_at_once(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    out = tmp_path / "store"
    proc = subprocess.Popen(
        [sys.executable, "-m", "crosscheck", "sweep", str(spec), "--out", str(out), "--workers", "2", "--no-progress"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    store = Store(out)

    def some_chunks():
        m = store.read_manifest() if store.manifest_path.exists() else None
        return bool(m and len(m["chunks"]) >= 1)

    # kill once the manifest is there and the pool's workers run: the manifest is written before the pool forks, so on a
    # fast engine "a manifest" alone could be met with no worker yet to orphan
    workers = _kill_when(
        proc, lambda: some_chunks() and len(_children(proc.pid)) >= 2, "a manifest and the pool's workers"
    )
    assert len(workers) >= 2, f"the sweep ran {len(workers)} workers; this test needs a pool"
    _no_orphans(workers)
    assert not holders(out / ".lock")
    rerun = subprocess.run(
        [sys.executable, "-m", "crosscheck", "sweep", str(spec), "--out", str(out), "--workers", "2", "--no-progress"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert rerun.returncode == 0, rerun.stderr
    assert "reused" in rerun.stdout + rerun.stderr
    assert len(sweeps.load(out)) == 24
    assert not (out / ".lock").exists(), "a finished run leaves no lock file"


def test_a_killed_report_leaves_no_workers_and_reruns_at_once(tmp_path):
    out = tmp_path / "report"
    cmd = [
        sys.executable,
        "-m",
        "crosscheck",
        "report",
        "--quick",
        "--only",
        "drake_sap_maps",
        "--out",
        str(out),
        "--workers",
        "2",
        "--no-progress",
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    stores = out / "sweeps" / "drake_sap_maps"

    def sweeping():
        return any(stores.glob("*/*/manifest.json")) and len(_children(proc.pid)) >= 2

    workers = _kill_when(proc, sweeping, "the section's sweep to start its workers")
    _no_orphans(workers)
    rerun = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert rerun.returncode == 0, rerun.stderr
    assert not list(out.rglob(".lock")), "a finished run leaves no lock file"


def test_a_lock_left_by_a_dead_writer_is_taken_over_with_a_note(tmp_path, capfd):
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    ).stdout.strip()
    lock = tmp_path / ".lock"
    lock.write_text(f"pid {dead} on somewhere: crosscheck sweep spec.toml")
    with exclusive(lock, "pid 1 here", lambda text: ValueError(text)):
        assert lock.read_text() == "pid 1 here"
    err = capfd.readouterr().err
    assert (
        f"took over the lock {str(lock)!r} left by a writer that is no longer running (pid {dead} on somewhere" in err
    )
    assert not lock.exists()


def test_a_lock_held_by_a_dead_writers_child_names_the_child(tmp_path):
    lock = tmp_path / ".lock"
    # A writer that forks a plain child (not one of crosscheck's workers) and dies: the child keeps the lock.
    script = textwrap.dedent(f"""
        import os, sys, time
        from crosscheck.locking import exclusive
        with exclusive({str(lock)!r}, f"pid {{os.getpid()}} on host: writer", ValueError):
            child = os.fork()
            if child == 0:
                os.close(1), os.close(2)  # let the test read the parent's output to its end
                time.sleep(60)
                os._exit(0)
            print(child, flush=True)
            os._exit(0)
    """)
    child = int(
        subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60).stdout.strip()
    )
    try:
        with pytest.raises(ValueError) as e:
            with exclusive(lock, "pid 2 here", lambda text: ValueError(f"being written by {text}")):
                pass
        msg = str(e.value)
        assert (
            "no longer running" in msg and f"still held by its surviving processes {child}" in msg and "\n" not in msg
        )
    finally:
        os.kill(child, signal.SIGKILL)
    _wait_until(lambda: not _alive(child), 5, "the child to die")
    with exclusive(lock, "pid 2 here", ValueError):  # free again once the survivor is gone
        pass


def test_a_worker_of_a_pool_does_not_hold_its_parents_lock(tmp_path):
    from crosscheck.workers import pool

    lock = tmp_path / ".lock"
    with exclusive(lock, "pid 3 here", ValueError):
        with pool(1) as p:
            worker = p.submit(os.getpid).result()
            assert worker != os.getpid()
            assert worker not in holders(lock), "a forked worker must close its parent's lock"


def test_a_lock_on_a_full_disk_is_one_line_and_leaves_no_file(tmp_path):
    """A real 64 KiB tmpfs, filled: the lock's owner text does not fit (skipped where this process cannot mount one)."""
    from crosscheck.sweeps.store import StoreError

    with tmpfs(tmp_path / "full", "size=64k") as mnt:
        subprocess.run(["dd", "if=/dev/zero", f"of={mnt / 'fill'}", "bs=4k", "count=100"], capture_output=True)
        with pytest.raises(
            StoreError,
            match=rf"^out {str(mnt)!r} has no room left \(No space left on device\): writing \d+ bytes needs",
        ):
            with exclusive(mnt / ".lock", "pid 4 on host: crosscheck report", ValueError):
                pass
        assert not (mnt / ".lock").exists()
