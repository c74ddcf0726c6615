"""Saved results are checked against what the run wrote before the report uses them.

Every section's ``status.json`` carries, once the section has finished, a
manifest of the files it saved (size in bytes and sha256).  Before a render
(and before a finished section is kept by a resumed run) each file is checked
against it, and ``status.json`` and ``provenance.json`` against their schema
and then against the seal written beside them (``<name>.json.sha256``: size
and sha256, ``crosscheck.report.store.SEALED``), so that an edit that keeps
the shape (one digit, one flipped bit) is caught as well.
A mismatch is one ``DamagedResults`` (a ``ValueError``) naming the file and
what is wrong: a report is never rendered from a truncated, edited or foreign
file, and ``crosscheck report --from-results`` exits 2 on it.
"""

from __future__ import annotations

import json
from pathlib import Path

from crosscheck.files import sha256_file

__all__ = ["DamagedResults", "manifest", "check_status", "check_provenance", "check_seal", "verify_files", "STATES"]

#: The states a section's status may record.
STATES = ("running", "ok", "skipped", "error")


class DamagedResults(ValueError):
    """A saved result does not match what the run wrote (the message names the file)."""


def manifest(root: Path, names: list[str]) -> dict[str, dict]:
    """{name: {"bytes", "sha256"}} of the files ``names`` under ``root``."""
    return {n: {"bytes": (root / n).stat().st_size, "sha256": sha256_file(root / n)} for n in names}


def read_json(path: Path, what: str):
    """The JSON document at ``path``; ``DamagedResults`` naming it when it cannot be read or parsed."""
    try:
        return json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise DamagedResults(
            f"{path}: {what} is not readable JSON ({e}); rerun the report without --from-results"
        ) from None


def check_status(doc, path: Path) -> dict:
    """``doc`` if it is a section status the run stage writes; ``DamagedResults`` naming ``path`` otherwise."""

    def bad(why: str):
        return DamagedResults(
            f"{path}: not a section status written by crosscheck report ({why}); rerun the section with --only"
        )

    if not isinstance(doc, dict):
        raise bad(f"a JSON {type(doc).__name__}, expected an object")
    if doc.get("status") not in STATES:
        raise bad(f"status {doc.get('status')!r}, expected one of {', '.join(STATES)}")
    if not isinstance(doc.get("params"), dict):
        raise bad("no params object")
    if doc["status"] != "running":
        files = doc.get("files")
        if not isinstance(files, dict) or not all(
            isinstance(v, dict) and isinstance(v.get("bytes"), int) and isinstance(v.get("sha256"), str)
            for v in files.values()
        ):
            raise bad("no manifest of the files it saved")
    check_seal(path, "the section status", "rerun the section with --only")
    return doc


def check_seal(path: Path, what: str, fix: str) -> None:
    """``DamagedResults`` naming ``path`` unless its bytes are what the seal beside it records."""
    from crosscheck.report.store import SEAL_SUFFIX, seal_of

    seal_path = path.with_name(path.name + SEAL_SUFFIX)
    try:
        data = path.read_bytes()
        want = json.loads(seal_path.read_bytes().decode())
    except FileNotFoundError:
        raise DamagedResults(
            f"{path}: {what} has no seal {seal_path.name} (size and sha256 of what the run wrote); {fix}"
        ) from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise DamagedResults(f"{path}: the seal {seal_path.name} of {what} is not readable ({e}); {fix}") from None
    if not isinstance(want, dict) or not isinstance(want.get("bytes"), int) or not isinstance(want.get("sha256"), str):
        raise DamagedResults(f"{path}: the seal {seal_path.name} of {what} is not one (no bytes and sha256); {fix}")
    got = seal_of(data)
    if got["bytes"] != want["bytes"]:
        raise DamagedResults(
            f"{path}: {got['bytes']} bytes, the run wrote {want['bytes']} (truncated or edited after the run); {fix}"
        )
    if got["sha256"] != want["sha256"]:
        raise DamagedResults(f"{path}: sha256 differs from what the run wrote (edited after the run); {fix}")


def check_provenance(doc, path: Path) -> dict:
    """``doc`` if it has the provenance's shape; ``DamagedResults`` naming ``path`` otherwise."""
    expected = {"date": str, "git": dict, "parameters": dict, "tolerances": dict, "versions": dict}
    if not isinstance(doc, dict):
        raise DamagedResults(
            f"{path}: not the provenance written by crosscheck report (a JSON {type(doc).__name__}, expected an object)"
        )
    for key, kind in expected.items():
        if not isinstance(doc.get(key), kind):
            raise DamagedResults(
                f"{path}: not the provenance written by crosscheck report ({key} is {type(doc.get(key)).__name__}, "
                f"expected {kind.__name__}); rerun the report without --from-results"
            )
    check_seal(path, "the provenance", "rerun the report without --from-results")
    return doc


def verify_files(root: Path, files: dict[str, dict], present: list[str]) -> None:
    """Check the saved files of one section (``present``: those on disk) against its manifest ``files``."""
    for name in present:
        if name not in files:
            raise DamagedResults(f"{root / name}: not written by the run of this section (not in its manifest)")
    for name, want in files.items():
        path = root / name
        if not path.is_file():
            raise DamagedResults(f"{path}: missing; the run wrote {want['bytes']} bytes")
        size = path.stat().st_size
        if size != want["bytes"]:
            raise DamagedResults(
                f"{path}: {size} bytes, the run wrote {want['bytes']} (truncated or edited after the run)"
            )
        if sha256_file(path) != want["sha256"]:
            raise DamagedResults(f"{path}: sha256 differs from what the run wrote (edited after the run)")
