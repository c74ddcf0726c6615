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
written, against which ``crosscheck.report.integrity`` checks them; the other
files are checked against the manifest in their section's status.  A full
disk is one ``ValueError`` naming the directory and the bytes it needed.
"""

from __future__ import annotations

import csv
import io
import json
import math
import shutil
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

__all__ = ["SectionStore", "to_jsonable", "FLOAT_DIGITS", "SEALED", "SEAL_SUFFIX"]

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


def write_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file renamed into place; a full disk or an unwritable
    directory is a ``ValueError`` naming the directory (and the bytes needed), leaving no temporary file."""
    from crosscheck import files

    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        files.write_atomic(path, data)
    except OSError as e:
        if e.errno in files.NO_SPACE:
            raise ValueError(files.no_space(path.parent, len(data), e)) from None
        name = path.name if len(path.name) <= 60 else f"{path.name[:40]}... ({len(path.name)} characters)"
        raise ValueError(
            f"out must be a writable path; cannot write {name} in {str(path.parent)[:200]!r}: {e.strerror or e}"
        ) from None


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
        write_atomic(path, buf.getvalue().encode())
        return path

    def write_json(self, name: str, obj: Any) -> Path:
        """Write ``obj`` as ``<name>.json`` (see ``to_jsonable``), sealed if ``name`` is in ``SEALED``; returns the path."""
        path = self.root / f"{name}.json"
        data = (json.dumps(to_jsonable(obj), indent=1) + "\n").encode()
        if name in SEALED:
            write_atomic(path.with_name(path.name + SEAL_SUFFIX), (json.dumps(seal_of(data)) + "\n").encode())
        write_atomic(path, data)  # a reader never sees half a file
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
        write_atomic(path, (json.dumps(doc, separators=(",", ":")) + "\n").encode())
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
        """Size and sha256 of every saved file (``crosscheck.report.integrity``), recorded in the status when the section ends."""
        from crosscheck.report.integrity import manifest

        return manifest(self.root, self.files())

    def verify(self, files: dict[str, dict]) -> None:
        """Check the saved files against the manifest ``files``; ``DamagedResults`` names the first that differs."""
        from crosscheck.report.integrity import verify_files

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
