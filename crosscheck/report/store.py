"""Saved results of one report section: CSV tables, JSON documents and 2D grids on disk.

The run stage writes through a ``SectionStore`` as each piece of work finishes
(so a later failure loses nothing already written); the render stage reads the
same files back, and nothing else, so that a report can be rebuilt without
re-simulating.

Layout: ``<out>/data/<slug>/<name>.csv|json``.  Formats, chosen so that a
reader can open them without this package:

* table: CSV with a header row; one column per quantity, one row per sample.
  Floats are written with 12 significant digits (``repr`` would be 17: the
  extra digits are rounding noise and triple the size of a committed report).
* JSON: plain JSON, NaN written as ``null``.
* grid: JSON ``{"x": {"name", "values"}, "y": {...}, "z": {"name", "values"}}``
  with ``z.values[j][i]`` the value at ``(x[i], y[j])`` (rows are y, as
  ``matplotlib.imshow`` and ``numpy.meshgrid`` expect).

Every file is written to a temporary file and renamed into place, so a reader
never sees half of one.  The documents that describe the others (a section's
``status.json``, the report's ``provenance.json``: ``SEALED``) get a
``<name>.json.sha256`` beside them, ``{"bytes", "sha256"}`` of what was
written, against which ``check_seal`` checks them; the other files are
checked against the manifest in their section's status (``verify_files``).
Before a render (and before a finished section is kept by a resumed run)
each file is checked, and ``status.json`` and ``provenance.json`` against
their schema and then their seal, so that an edit that keeps the shape (one
digit, one flipped bit) is caught as well.  A mismatch is one
``DamagedResults`` (a ``ValueError``) naming the file and what is wrong: a
report is never rendered from a truncated, edited or foreign file, and
``crosscheck report --from-results`` exits 2 on it.  A full
disk is one ``ValueError`` naming the directory and the bytes it needed.
"""

from __future__ import annotations

import csv
import io
import json
import math
import shutil
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from crosscheck import files
from crosscheck.files import sha256_file

__all__ = [
    "SectionStore",
    "to_jsonable",
    "FLOAT_DIGITS",
    "SEALED",
    "SEAL_SUFFIX",
    "DamagedResults",
    "manifest",
    "check_status",
    "check_provenance",
    "check_seal",
    "verify_files",
    "STATES",
    "STATUS_FILE",
    "PROVENANCE_FILE",
    "read_status",
    "read_provenance",
    "verified_status",
]

#: Significant digits of floats in saved tables and grids.
FLOAT_DIGITS = 12

#: The JSON documents written with a seal beside them (the section status and the report's provenance: the
#: manifest of a section's files is in its status, so the status and the provenance need one of their own).
SEALED = ("status", "provenance")
SEAL_SUFFIX = ".sha256"


def seal_of(data: bytes) -> dict:
    """The seal of a file's bytes: its size and sha256."""
    import hashlib

    return {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}


# ------------------------------------------------------------- integrity ---

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


def _fmt(v: Any, digits: int) -> Any:
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if not math.isfinite(v):
            return None if math.isnan(v) else (math.inf if v > 0 else -math.inf)
        return float(f"{v:.{digits}g}")
    return v


def to_jsonable(obj: Any, *, digits: int = 17) -> Any:
    """``obj`` with numpy scalars/arrays, dataclass-like ``as_dict`` objects and enums made JSON-able.

    NaN becomes ``None`` (JSON has no NaN); infinities become the strings
    ``"inf"``/``"-inf"``.
    """
    if hasattr(obj, "as_dict") and callable(obj.as_dict):
        obj = obj.as_dict()
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v, digits=digits) for k, v in obj.items()}
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist(), digits=digits)
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v, digits=digits) for v in obj]
    if hasattr(obj, "name") and isinstance(obj, int) and not isinstance(obj, bool):  # IntEnum
        return obj.name
    v = _fmt(obj, digits)
    if isinstance(v, float) and math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return v


def _from_json(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _from_json(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_from_json(v) for v in obj]
    if obj == "inf":
        return math.inf
    if obj == "-inf":
        return -math.inf
    return obj


class SectionStore:
    """Read and write the saved results of one section under ``root`` (``<out>/data/<slug>``)."""

    def __init__(self, root: Path | str):
        self.root = Path(root)

    # ------------------------------------------------------------ writing ---
    def reset(self) -> None:
        """Remove the results of a previous run of this section (called before it runs again)."""
        if self.root.exists():
            shutil.rmtree(self.root)
        self.root.mkdir(parents=True, exist_ok=True)

    def path(self, name: str) -> Path:
        return self.root / name

    def write_table(self, name: str, columns: Mapping[str, Iterable]) -> Path:
        """Write ``columns`` (equal-length 1D sequences) as ``<name>.csv``; returns the path."""
        cols = {k: list(np.asarray(v).tolist()) if not isinstance(v, list) else v for k, v in columns.items()}
        lengths = {len(v) for v in cols.values()}
        if len(lengths) > 1:
            raise ValueError(f"table {name}: columns differ in length: { {k: len(v) for k, v in cols.items()} }")
        n = lengths.pop() if lengths else 0
        path = self.root / f"{name}.csv"
        buf = io.StringIO(newline="")
        w = csv.writer(buf)
        w.writerow(cols.keys())
        for i in range(n):
            row = []
            for v in cols.values():
                x = _fmt(v[i], FLOAT_DIGITS)
                row.append("nan" if x is None else x)
            w.writerow(row)
        files.write_atomic(path, buf.getvalue().encode(), mkdir=True, error=files.out_error)
        return path

    def write_json(self, name: str, obj: Any) -> Path:
        """Write ``obj`` as ``<name>.json`` (see ``to_jsonable``), sealed if ``name`` is in ``SEALED``; returns the path."""
        path = self.root / f"{name}.json"
        data = (json.dumps(to_jsonable(obj), indent=1) + "\n").encode()
        if name in SEALED:
            files.write_atomic(
                path.with_name(path.name + SEAL_SUFFIX),
                (json.dumps(seal_of(data)) + "\n").encode(),
                mkdir=True,
                error=files.out_error,
            )
        files.write_atomic(path, data, mkdir=True, error=files.out_error)  # a reader never sees half a file
        return path

    def write_grid(
        self,
        name: str,
        x: tuple[str, np.ndarray],
        y: tuple[str, np.ndarray],
        z: tuple[str, np.ndarray],
        *,
        digits: int = 6,
    ) -> Path:
        """Write a 2D field z(y, x) (shape (len(y), len(x))) as ``<name>.json``."""
        (xn, xv), (yn, yv), (zn, zv) = x, y, z
        xv, yv, zv = np.asarray(xv), np.asarray(yv), np.asarray(zv)
        if zv.shape != (yv.size, xv.size):
            raise ValueError(f"grid {name}: z has shape {zv.shape}, expected (len(y), len(x)) = {(yv.size, xv.size)}")
        doc = {
            "x": {"name": xn, "values": to_jsonable(xv, digits=FLOAT_DIGITS)},
            "y": {"name": yn, "values": to_jsonable(yv, digits=FLOAT_DIGITS)},
            "z": {"name": zn, "values": [[_fmt(v, digits) for v in row] for row in zv.tolist()]},
        }
        path = self.root / f"{name}.json"
        files.write_atomic(
            path, (json.dumps(doc, separators=(",", ":")) + "\n").encode(), mkdir=True, error=files.out_error
        )
        return path

    # ------------------------------------------------------------ reading ---
    def exists(self, name: str) -> bool:
        return (self.root / name).exists()

    def files(self) -> list[str]:
        """Names of the saved files (status excluded), sorted."""
        if not self.root.exists():
            return []
        return sorted(
            p.name
            for p in self.root.iterdir()
            if p.is_file()
            and p.name not in ("status.json", "status.json" + SEAL_SUFFIX)
            and not p.name.endswith(".tmp")
            and ".tmp-" not in p.name
        )

    def manifest(self) -> dict[str, dict]:
        """Size and sha256 of every saved file (``manifest``), recorded in the status when the section ends."""
        return manifest(self.root, self.files())

    def verify(self, files: dict[str, dict]) -> None:
        """Check the saved files against the manifest ``files``; ``DamagedResults`` names the first that differs."""
        verify_files(self.root, files, self.files())

    def read_table(self, name: str, *, text: Iterable[str] = ()) -> dict[str, np.ndarray]:
        """Columns of ``<name>.csv``: numeric columns as float arrays, others (and those named in ``text``) as str arrays."""
        text = set(text)
        with open(self.root / f"{name}.csv", newline="") as f:
            rows = list(csv.reader(f))
        header, body = rows[0], rows[1:]
        out: dict[str, np.ndarray] = {}
        for j, key in enumerate(header):
            raw = [r[j] for r in body]
            if key in text:
                out[key] = np.array(raw, dtype=str)
                continue
            try:
                out[key] = np.array([float(v) for v in raw], dtype=float)
            except ValueError:
                out[key] = np.array(raw, dtype=str)
        return out

    def read_json(self, name: str) -> Any:
        return _from_json(json.loads((self.root / f"{name}.json").read_text()))

    def read_grid(self, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, str]]:
        """(x, y, z, names) of a saved grid; z has shape (len(y), len(x)), None read as NaN."""
        doc = json.loads((self.root / f"{name}.json").read_text())
        x = np.asarray(doc["x"]["values"], dtype=float)
        y = np.asarray(doc["y"]["values"], dtype=float)
        z = np.array([[np.nan if v is None else v for v in row] for row in doc["z"]["values"]], dtype=float)
        return x, y, z, {"x": doc["x"]["name"], "y": doc["y"]["name"], "z": doc["z"]["name"]}


# ------------------------------------------------------------- a report's saved documents ---

#: The name of each section's status document and of the report's provenance (``<name>.json``).
STATUS_FILE = "status"
PROVENANCE_FILE = "provenance"


def read_status(out: Path, slug: str) -> dict | None:
    """The saved status of a section, None if it never ran in ``out``; ``DamagedResults`` if it is not one."""
    path = Path(out) / "data" / slug / f"{STATUS_FILE}.json"
    if not path.exists():
        return None
    return check_status(read_json(path, "the section status"), path)


def read_provenance(out: Path) -> dict | None:
    """The saved provenance of a report, None if there is none; ``DamagedResults`` if it is not one."""
    path = Path(out) / "data" / f"{PROVENANCE_FILE}.json"
    if not path.exists():
        return None
    return check_provenance(read_json(path, "the provenance"), path)


def verified_status(out: Path, slug: str) -> dict | None:
    """``read_status`` with the section's saved files checked against the manifest in it (``DamagedResults``)."""
    status = read_status(out, slug)
    if status is not None and status["status"] != "running":
        SectionStore(Path(out) / "data" / slug).verify(status["files"])
    return status
