"""Compare every number of two report data trees (``DIR/data``): JSON and CSV, ignoring timings and provenance.

    python tools/compare_report_data.py OLD/data NEW/data [--rtol 1e-9] [--atol 1e-12] [--rename OLD_KEY=NEW_KEY ...]

Numbers are equal when |a - b| <= atol + rtol |a| (the default allows the
last-digit differences of an ODE integration on another machine, nothing
more); strings, labels and counts must be identical.  ``--rename`` maps a
JSON key or CSV column of the old tree to its new name before comparing.
Prints one block per file that differs and the count of files equal in every
number; exits 1 when any file differs.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys
from pathlib import Path

#: Keys that hold timings or provenance, not results.
IGNORED = {"wall_time", "steps_per_second", "seconds", "date", "git", "revision", "dirty", "describe", "requires", "machine",
           "versions"}


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


def compare(old: Path, new: Path, *, rtol: float, atol: float, rename: dict) -> int:
    files = sorted({p.relative_to(old) for p in old.rglob("*") if p.suffix in (".json", ".csv")}
                   | {p.relative_to(new) for p in new.rglob("*") if p.suffix in (".json", ".csv")})
    equal, differ = 0, 0
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
        if out:
            differ += 1
            print(f"{rel}: {len(out)} differences")
            for line in out[:20]:
                print(f"    {line}")
            if len(out) > 20:
                print(f"    ... {len(out) - 20} more")
        else:
            equal += 1
    print(f"{equal} files equal in every number, {differ} differ (rtol {rtol:g}, atol {atol:g})")
    return 1 if differ else 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--rtol", type=float, default=1e-9)
    ap.add_argument("--atol", type=float, default=1e-12)
    ap.add_argument("--rename", action="append", default=[], metavar="OLD=NEW")
    args = ap.parse_args(argv)
    rename = dict(r.split("=", 1) for r in args.rename)
    return compare(args.old, args.new, rtol=args.rtol, atol=args.atol, rename=rename)


if __name__ == "__main__":
    sys.exit(main())
