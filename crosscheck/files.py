"""Files written now and read later: their checksum, and one writer per directory.

Shared by the sweep store (``crosscheck.sweeps.store``) and the report
(``crosscheck.report``), which both keep results on disk across runs.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from crosscheck.locking import exclusive  # one writer per directory

__all__ = ["sha256_file", "exclusive"]


def sha256_file(path: Path | str) -> str:
    """sha256 of a file's bytes, read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


