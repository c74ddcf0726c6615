"""The source revision recorded when the package is built from a git checkout (standard library only).

``pip install .`` copies the package into site-packages, where no git
history is left to ask: ``setup.py``'s ``build_py`` step calls
``write_build_info`` to save the checkout's revision, whether its tracked
files were clean, and the build date as ``crosscheck/_build_info.json`` in
the built package, and ``crosscheck.report.provenance.git_revision`` reads it
back (``build_info``) when the installed package is not itself a checkout.
This module is loaded by ``setup.py`` from its path, before any dependency is
installed: it imports nothing outside the standard library.
"""

from __future__ import annotations

import datetime as _dt
import json
import subprocess
from pathlib import Path

__all__ = ["BUILD_INFO", "source_revision", "write_build_info", "build_info"]

#: The file written into the built package, beside this module.
BUILD_INFO = "_build_info.json"


def source_revision(root: Path | str) -> dict | None:
    """``{"revision": sha, "dirty": bool or None, "describe": str}`` of the git checkout at ``root``; None when ``root``
    is not one (or git is missing).  ``dirty``: tracked files differ from the revision (untracked files are ignored:
    a build writes ``build/`` and ``*.egg-info`` into the tree)."""

    def git(*args: str) -> str | None:
        try:
            r = subprocess.run(["git", *args], cwd=root, capture_output=True, text=True, timeout=10)
        except (OSError, subprocess.SubprocessError):
            return None
        return r.stdout.strip() if r.returncode == 0 else None

    if not Path(root).is_dir():
        return None
    top = git("rev-parse", "--show-toplevel")
    if (
        top is None or Path(top).resolve() != Path(root).resolve()
    ):  # a tree inside some other repository is not this source
        return None
    rev = git("rev-parse", "HEAD")
    if rev is None:
        return None
    status = git("status", "--porcelain", "--untracked-files=no")
    dirty = None if status is None else bool(status)
    return {"revision": rev, "dirty": dirty, "describe": rev[:12] + ("-dirty" if dirty else "")}


def write_build_info(package_dir: Path | str, root: Path | str) -> Path | None:
    """Write ``BUILD_INFO`` into the built package at ``package_dir`` with the revision of the checkout ``root``.

    Returns the file written, or None (and writes nothing) when ``root`` is not a git checkout, e.g. a build from an
    sdist: an installed package then says it cannot be traced rather than naming a wrong revision.  An editable
    install (``pip install -e .``) builds no copy of the package (``package_dir`` is absent): the package runs from
    the checkout itself, whose git history answers directly, so nothing is written."""
    rev = source_revision(root)
    if rev is None or not Path(package_dir).is_dir():
        return None
    built = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    path = Path(package_dir) / BUILD_INFO
    path.write_text(
        json.dumps(
            {**rev, "built": built, "source": "recorded when the package was built from a git checkout"}, indent=1
        )
        + "\n"
    )
    return path


def build_info(package_dir: Path | str | None = None) -> dict | None:
    """The revision recorded in the installed package (``write_build_info``), or None when it has none."""
    path = Path(package_dir or Path(__file__).resolve().parent) / BUILD_INFO
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return doc if isinstance(doc, dict) and isinstance(doc.get("revision"), str) else None
