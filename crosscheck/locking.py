"""One writer per directory: an exclusive lock that names its real owner, is never inherited, and leaves no file behind.

The sweep store (``crosscheck.sweeps.store``) and the report
(``crosscheck.report.pipeline``) hold ``<dir>/.lock`` while they write.

Why each piece:

* ``flock`` is dropped by the kernel when every descriptor of the open file is
  closed, so a writer killed by SIGKILL releases it.  But a forked child
  shares the parent's open file, and so the lock: a worker that outlives a
  killed parent would keep the directory locked.  ``crosscheck.workers``
  closes every descriptor listed in ``HELD`` in each child it starts, and
  makes the child die with its parent.
* The lock file holds its owner's pid, host and command.  A lock that is
  free but names a pid that no longer runs was left by a killed writer: it is
  taken over with a note on stderr.  A lock that is held although the pid it
  names is gone is held by that writer's surviving children (started by an
  older crosscheck, or by user code): the refusal names them.
* The file is unlinked while still locked when the writer finishes, so a
  finished run leaves no ``.lock``.  A process that opened the old file
  before the unlink and then gets its lock sees that the path is no longer its
  file and starts again.
"""

from __future__ import annotations

import errno
import fcntl
import os
import platform
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from crosscheck.files import NO_SPACE, StoreError, no_space

__all__ = ["exclusive", "HELD", "owner_text", "holders"]

#: Descriptors of the locks this process holds now (closed by ``crosscheck.workers`` in forked children).
HELD: set[int] = set()


def owner_text() -> str:
    """What a lock file says of its owner: ``pid N on HOST: COMMAND``."""
    cmd = " ".join(os.path.basename(a) if i == 0 else a for i, a in enumerate(sys.argv))[:200]
    return f"pid {os.getpid()} on {platform.node()}: {cmd}"


def _pid_of(text: str) -> int | None:
    """The pid a lock file names (``pid N ...`` or a bare number), None if it names none."""
    words = text.replace(":", " ").split()
    for i, w in enumerate(words):
        if w.isascii() and w.isdigit() and (i == 0 or words[i - 1] == "pid"):
            return int(w)
    return None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def holders(path: Path | str) -> list[int]:
    """Pids of the processes on this machine with ``path`` open (from ``/proc``; empty where there is no ``/proc``)."""
    try:
        st = os.stat(path)
    except OSError:
        return []
    found = []
    proc = Path("/proc")
    if not proc.is_dir():
        return found
    for d in proc.iterdir():
        if not d.name.isdigit() or int(d.name) == os.getpid():
            continue
        try:
            for fd in (d / "fd").iterdir():
                try:
                    s = os.stat(fd)
                except OSError:
                    continue
                if (s.st_ino, s.st_dev) == (st.st_ino, st.st_dev):
                    found.append(int(d.name))
                    break
        except OSError:
            continue  # another user's process, or gone meanwhile
    return sorted(found)


def _refusal_text(path: Path, text: str) -> str:
    """What the refusal says of the holder: the recorded owner, and the real holders when the owner is gone."""
    pid = _pid_of(text)
    if pid is None or _alive(pid):
        return text or "unknown"
    others = holders(path)
    held = (
        f"; still held by its surviving processes {', '.join(map(str, others))} (kill them to free it)"
        if others
        else ""
    )
    return f"{text} (no longer running{held})"


@contextmanager
def exclusive(path: Path | str, holder: str, refuse: Callable[[str], Exception]) -> Iterator[Path]:
    """Hold an exclusive lock on ``path`` (created if missing) for the ``with`` block, writing ``holder`` into it.

    When another process holds it, raises ``refuse(text)`` at once, ``text``
    being what that process wrote (and, when that process is gone, which of
    its survivors hold it).  The lock file is removed when the block ends.
    """
    path = Path(path)
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            text = os.pread(fd, 4096, 0).decode("utf-8", "replace").strip()
            os.close(fd)
            raise refuse(_refusal_text(path, text)) from None
        try:
            same = os.fstat(fd).st_ino == os.stat(path).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)  # the previous owner removed this file after we opened it: lock the new one
    try:
        previous = os.pread(fd, 4096, 0).decode("utf-8", "replace").strip()
        pid = _pid_of(previous)
        if pid is not None and pid != os.getpid() and not _alive(pid):
            sys.stderr.write(
                f"note: took over the lock {str(path)!r} left by a writer that is no longer running ({previous})\n"
            )
        os.ftruncate(fd, 0)
        try:
            os.pwrite(fd, holder.encode(), 0)
        except OSError as e:  # a full disk: one line naming the directory, not a traceback from the lock
            if e.errno in NO_SPACE:
                raise StoreError(no_space(path.parent, len(holder.encode()), e)) from None
            raise
        HELD.add(fd)
        yield path
    finally:
        HELD.discard(fd)
        try:
            if os.fstat(fd).st_nlink:
                os.unlink(path)
        except OSError as e:
            if e.errno != errno.ENOENT:
                raise
        os.close(fd)
