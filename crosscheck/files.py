"""Files written now and read later: written whole or not at all, their checksum, and one writer per directory.

Shared by the sweep store (``crosscheck.sweeps.store``) and the report
(``crosscheck.report``), which both keep results on disk across runs.
"""

from __future__ import annotations

import errno
import hashlib
import os
from pathlib import Path

from crosscheck.locking import exclusive  # one writer per directory

__all__ = ["sha256_file", "exclusive", "write_atomic", "NO_SPACE", "no_space"]

#: The errors of a file system that has no room left (EFBIG: a file-size limit).
NO_SPACE = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


def no_space(directory: Path, needed: int | None, e: OSError) -> str:
    """The one line of a write that found no room: the directory, the bytes needed (None: not known) and those free."""
    try:
        st = os.statvfs(directory)
        free = f"{st.f_bavail * st.f_frsize} bytes free"
    except OSError:
        free = "free space unknown"
    if needed is None:
        what = Path(e.filename).name if e.filename else "its files"
        return f"out {str(directory)!r} has no room left ({e.strerror or e}): writing {what} needs more free space than that ({free})"
    return f"out {str(directory)!r} has no room left ({e.strerror or e}): writing {needed} bytes needs at least that much free space ({free})"


def write_atomic(path: Path, data: bytes, *, sync: bool = False) -> None:
    """Write ``data`` to ``path`` through a temporary file renamed over it, so that a reader never sees half of it;
    ``sync``: flush it to the disk first.  On an ``OSError`` the temporary file is removed and the error raised."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
            if sync:
                f.flush()
                os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError:
        try:
            tmp.unlink(missing_ok=True)  # nothing half-written stays behind
        except OSError:
            pass  # never created (its name, say, too long)
        raise


def sha256_file(path: Path | str) -> str:
    """sha256 of a file's bytes, read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()
