"""Files written now and read later: their checksum, and one writer per directory.

Shared by the sweep store (``crosscheck.sweeps.store``) and the report
(``crosscheck.report``), which both keep results on disk across runs.
"""

from __future__ import annotations

import fcntl
import hashlib
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator

__all__ = ["sha256_file", "exclusive"]


def sha256_file(path: Path | str) -> str:
    """sha256 of a file's bytes, read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


@contextmanager
def exclusive(path: Path | str, holder: str, refuse: Callable[[str], Exception]) -> Iterator[Path]:
    """Hold an exclusive ``flock`` on ``path`` (created if missing) for the ``with`` block, writing ``holder`` into it.

    When another process holds it, raises ``refuse(text)`` at once, ``text`` being what that process wrote.
    The kernel drops the lock when its holder dies, also by SIGKILL, so a killed writer never leaves it held.
    """
    f = open(path, "a+")
    try:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            f.seek(0)
            raise refuse(f.read().strip()) from None
        f.seek(0)
        f.truncate()
        f.write(holder)
        f.flush()
        yield Path(path)
    finally:
        f.close()
