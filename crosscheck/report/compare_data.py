"""Compare every number of two report data trees (``DIR/data``): JSON and CSV, ignoring timings and provenance.

Numbers are equal when |a - b| <= atol + rtol |a|: the default allows the
last-digit differences of an ODE integration on another machine, nothing
more; strings, labels and counts must be identical.  Used by the test that
keeps the committed reference report ``reports/quick`` current, and by
``python tools/compare_report_data.py OLD/data NEW/data``.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

__all__ = ["compare", "IGNORED", "RTOL", "ATOL"]

#: Relative and absolute allowance of a number: rounding of the saved 12 digits and of an integration's last digits.
RTOL, ATOL = 1e-9, 1e-12

#: Keys that hold timings or provenance, not results.
IGNORED = {"wall_time", "steps_per_second", "seconds", "date", "git", "revision", "dirty", "describe", "requires", "machine",
           "versions", "code_sha256", "crosscheck_version", "files"}  # (files: the checksums, which change with the last digit)


def _number(x):
    if isinstance(x, bool):
        return None
    if isinstance(x, (int, float)):
        return float(x)
    if isinstance(x, str):
        try:
            return float(x)
        except ValueError:
            return None
    return None


def _same(a, b, rtol: float, atol: float) -> bool:
    x, y = _number(a), _number(b)
    if x is None or y is None:
        return a == b
    if math.isnan(x) and math.isnan(y):
        return True
    if math.isinf(x) or math.isinf(y):
        return x == y
    return abs(x - y) <= atol + rtol * abs(x)


def _walk(a, b, path: str, out: list, rtol: float, atol: float, rename: dict) -> None:
    if isinstance(a, dict) and isinstance(b, dict):
        a = {rename.get(k, k): v for k, v in a.items()}
        for k in sorted(set(a) | set(b)):
            if k in IGNORED:
                continue
            if k not in a:
                out.append(f"{path}/{k}: only in new")
            elif k not in b:
                out.append(f"{path}/{k}: only in old")
            else:
                _walk(a[k], b[k], f"{path}/{k}", out, rtol, atol, rename)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: length {len(a)} (old) vs {len(b)} (new)")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            _walk(x, y, f"{path}[{i}]", out, rtol, atol, rename)
    elif not _same(a, b, rtol, atol):
        out.append(f"{path}: {a!r} (old) vs {b!r} (new)")


def _csv(path: Path, rename: dict) -> dict[str, list[str]]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    head = [rename.get(h, h) for h in rows[0]]
    return {h: [r[i] if i < len(r) else "<missing>" for r in rows[1:]] for i, h in enumerate(head)}


def compare(old: Path, new: Path, *, rtol: float = RTOL, atol: float = ATOL, rename: dict | None = None) -> dict[str, list[str]]:
    """{file: differences} of two data trees (files equal in every number map to []); provenance.json is skipped."""
    old, new, rename = Path(old), Path(new), rename or {}
    files = sorted({p.relative_to(old) for p in old.rglob("*") if p.suffix in (".json", ".csv")}
                   | {p.relative_to(new) for p in new.rglob("*") if p.suffix in (".json", ".csv")})
    result: dict[str, list[str]] = {}
    for rel in files:
        if rel.name == "provenance.json":
            continue
        a, b = old / rel, new / rel
        out: list[str] = []
        if not a.exists() or not b.exists():
            out.append(f"only in {'new' if b.exists() else 'old'}")
        elif rel.suffix == ".json":
            _walk(json.loads(a.read_text()), json.loads(b.read_text()), "", out, rtol, atol, rename)
        else:
            ca, cb = _csv(a, rename), _csv(b, rename)
            for col in sorted((set(ca) | set(cb)) - IGNORED):
                if col not in ca or col not in cb:
                    out.append(f"column {col}: only in {'new' if col in cb else 'old'}")
                elif len(ca[col]) != len(cb[col]):
                    out.append(f"column {col}: {len(ca[col])} rows (old) vs {len(cb[col])} (new)")
                else:
                    bad = [i for i, (x, y) in enumerate(zip(ca[col], cb[col])) if not _same(x, y, rtol, atol)]
                    if bad:
                        out.append(f"column {col}: {len(bad)} rows differ, first row {bad[0]}: {ca[col][bad[0]]} (old) vs {cb[col][bad[0]]} (new)")
        result[str(rel)] = out
    return result
