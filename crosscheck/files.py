"""Files written now and read later: written whole or not at all, their checksum, and the one line of a failed write.

Shared by the sweep store (``crosscheck.sweeps.store``) and the report
(``crosscheck.report``), which both keep results on disk across runs; the lock
that keeps one writer per directory is ``crosscheck.locking``.  ``write_atomic``
is the one writer of a whole file: each caller passes how an ``OSError``
becomes its own one-line error (``store_error`` for a sweep store,
``out_error`` for a report's directory).
"""

from __future__ import annotations

import errno
import hashlib
import os
from collections.abc import Callable
from pathlib import Path

__all__ = ["sha256_file", "write_atomic", "NO_SPACE", "no_space", "StoreError", "store_error", "out_error"]

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


class StoreError(ValueError):
    """A store that cannot be used as asked (another writer, another spec, a damaged manifest, no room left)."""


def store_error(path: Path, e: OSError, needed: int) -> StoreError:
    """A sweep store's failed write of ``needed`` bytes to ``path``: a ``StoreError`` naming its directory."""
    if e.errno in NO_SPACE:
        return StoreError(no_space(path.parent, needed, e))
    return StoreError(f"out {str(path.parent)!r} cannot be written: {e.strerror or e}")


def out_error(path: Path, e: OSError, needed: int) -> ValueError:
    """A report's failed write of ``needed`` bytes to ``path``: a ``ValueError`` naming the directory (and the bytes
    needed where the disk is full)."""
    if e.errno in NO_SPACE:
        return ValueError(no_space(path.parent, needed, e))
    name = path.name if len(path.name) <= 60 else f"{path.name[:40]}... ({len(path.name)} characters)"
    return ValueError(
        f"out must be a writable path; cannot write {name} in {str(path.parent)[:200]!r}: {e.strerror or e}"
    )


def write_atomic(
    path: Path,
    data: bytes,
    *,
    sync: bool = False,
    mkdir: bool = False,
    error: Callable[[Path, OSError, int], Exception] | None = None,
) -> None:
    """Write ``data`` to ``path`` through a temporary file renamed over it, so that a reader never sees half of it.

    ``sync``: flush it to the disk first.  ``mkdir``: create the missing parent directories first.  On an
    ``OSError`` the temporary file is removed and ``error(path, e, len(data))`` raised in its place (``store_error``,
    ``out_error``), or the ``OSError`` itself when ``error`` is None.
    """
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        if mkdir:
            path.parent.mkdir(parents=True, exist_ok=True)
        with open(tmp, "wb") as f:
            f.write(data)
            if sync:
                f.flush()
                os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as e:
        try:
            tmp.unlink(missing_ok=True)  # nothing half-written stays behind
        except OSError:
            pass  # never created (its name, say, too long)
        if error is None:
            raise
        raise error(path, e, len(data)) from None


def sha256_file(path: Path | str) -> str:
    """sha256 of a file's bytes, read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()
