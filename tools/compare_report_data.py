"""Compare every number of two report data trees (``DIR/data``): JSON and CSV, ignoring timings and provenance.

    python tools/compare_report_data.py OLD/data NEW/data [--rtol 1e-9] [--atol 1e-12] [--rename OLD_KEY=NEW_KEY ...]

``--rename`` maps a JSON key or CSV column of the old tree to its new name
before comparing.  Prints one block per file that differs and the count of
files equal in every number; exits 1 when any file differs.  The comparison
itself is ``crosscheck.report.compare_data``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from crosscheck.report.compare_data import ATOL, RTOL, compare


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--rtol", type=float, default=RTOL)
    ap.add_argument("--atol", type=float, default=ATOL)
    ap.add_argument("--rename", action="append", default=[], metavar="OLD=NEW")
    args = ap.parse_args(argv)
    rename = dict(r.split("=", 1) for r in args.rename)
    result = compare(args.old, args.new, rtol=args.rtol, atol=args.atol, rename=rename)
    differ = {k: v for k, v in result.items() if v}
    for rel, out in differ.items():
        print(f"{rel}: {len(out)} differences")
        for line in out[:20]:
            print(f"    {line}")
        if len(out) > 20:
            print(f"    ... {len(out) - 20} more")
    print(
        f"{len(result) - len(differ)} files equal in every number, {len(differ)} differ (rtol {args.rtol:g}, atol {args.atol:g})"
    )
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
