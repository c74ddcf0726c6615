"""Run the bad-input audit (tests/bad_inputs.py) and print the count of each verdict, then every case that is not clean.

python tools/audit_inputs.py [--json FILE]
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import audit
import bad_inputs


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", default=None, help="write every case's verdict here")
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds per case before it counts as a hang")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, argv, param in bad_inputs.cli_cases(Path(tmp)):
            v = audit.judge_cli(argv, param, timeout=args.timeout)
            rows.append({"where": "cli", "case": name, "param": param, "verdict": v.verdict, "detail": v.detail})
        for name, call, param in bad_inputs.api_cases():
            v = audit.judge_api(call, param, timeout=args.timeout)
            rows.append({"where": "api", "case": name, "param": param, "verdict": v.verdict, "detail": v.detail})
    for where in ("cli", "api"):
        counts = collections.Counter(r["verdict"] for r in rows if r["where"] == where)
        total = sum(counts.values())
        print(f"{where}: {total} cases: " + ", ".join(f"{k} {counts.get(k, 0)}" for k in audit.VERDICTS))
    for r in rows:
        if r["verdict"] != "clean":
            print(f"  [{r['verdict']}] {r['where']} {r['case']}: {r['detail'][:160]}")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0 if all(r["verdict"] == "clean" for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
