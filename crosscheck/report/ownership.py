"""A report writes, and deletes, only in a directory it can prove it wrote: its stamp ``<out>/.crosscheck-report``.

``claim(out)`` is called (under the report's lock) before anything is written.
An empty or missing ``out`` is stamped and used; a stamped one is the report's
own; one holding a report's provenance (``data/provenance.json``, written
before stamps existed) is stamped and used.  Any other non-empty directory (a
project, a checkout, a sweep store) is refused in one line naming ``--out``,
unless ``beside`` (``crosscheck report --beside-files``): the report then adds
its own files next to the others, and is refused if one of its names
(``OWN_NAMES``) is already taken.  Nothing that is not the report's is ever
deleted or overwritten, with or without ``beside``.

Inside a claimed directory, ``<out>/sweeps`` is deleted (stale code) only if it
holds the report's own ``computed_by.json`` (``sweeps_owned``).
"""

from __future__ import annotations

import fnmatch
import json
from pathlib import Path

__all__ = ["claim", "sweeps_owned", "STAMP", "OWN_NAMES", "OWN_PATTERNS", "BESIDE_FLAG"]

#: The report's stamp file in its directory: its presence is the proof that crosscheck report wrote the directory.
STAMP = ".crosscheck-report"
#: What a report writes at the top of its directory (the lock and the stamp aside).
OWN_NAMES = ("data", "figures", "sweeps", "index.html", "report.md", "style.css")
#: ... and the engines' pages beside them (``crosscheck.report.pages``).
OWN_PATTERNS = ("engine_*.html", "engine_*.md")
#: The command-line flag that lets a report share a directory with files that are not its own.
BESIDE_FLAG = "--beside-files"
_IGNORED = (".lock", STAMP)


def _legacy_report(out: Path) -> bool:
    """Whether ``out`` holds a report's provenance as crosscheck wrote it before stamps (a JSON object with its keys)."""
    try:
        p = json.loads((out / "data" / "provenance.json").read_bytes().decode())
    except (OSError, UnicodeDecodeError, ValueError):
        return False
    return isinstance(p, dict) and {"command", "versions", "seed"} <= set(p)


def claim(out: Path, *, beside: bool = False) -> None:
    """Stamp ``out`` as this report's directory, or raise ValueError (one line naming out) if it is someone else's."""
    out = Path(out)
    if not (out / STAMP).is_file():
        others = sorted(p.name for p in out.iterdir() if p.name not in _IGNORED) if out.is_dir() else []
        if others and not _legacy_report(out):
            if not beside:
                raise ValueError(
                    f"out must be a directory that is empty or a report crosscheck wrote; {str(out)!r} holds "
                    f"{len(others)} entries it did not write (first: {others[0]!r}); choose another --out, or pass "
                    f"{BESIDE_FLAG} to add the report beside them (nothing of theirs is deleted or overwritten)"
                )
            taken = [n for n in OWN_NAMES if n in others] + [
                n for n in others if any(fnmatch.fnmatch(n, pat) for pat in OWN_PATTERNS)
            ]
            if taken:
                raise ValueError(
                    f"out must be a directory where the report's names are free; {str(out)!r} already holds "
                    f"{taken[0]!r}, which crosscheck did not write ({BESIDE_FLAG} never replaces a file): move it or "
                    "choose another --out"
                )
    from crosscheck.files import write_atomic

    write_atomic(out / STAMP, b'{"written_by": "crosscheck report"}\n')


def sweeps_owned(root: Path) -> bool:
    """Whether the report may delete ``root`` (``<out>/sweeps``): absent, or holding the report's ``computed_by.json``;
    ValueError naming out if it holds anything else (someone's files: never deleted)."""
    if not root.exists():
        return False
    if root.is_dir() and (root / "computed_by.json").is_file():
        return True
    if root.is_dir() and not any(root.iterdir()):
        return True
    raise ValueError(
        f"out must be a directory whose sweeps/ a crosscheck report wrote; {str(root)!r} has no computed_by.json: "
        "crosscheck did not write it and does not delete it; move it or choose another --out"
    )
