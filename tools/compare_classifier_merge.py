"""Compare the MuJoCo data of a report made with two classifiers (rule on -b/p, rule on the engine's own friction) with one made with the merged classifier.

    python tools/compare_classifier_merge.py OLD/data NEW/data

Before the merge the agreement maps and the convergence study held two MuJoCo
runs per setting: classifier "part_a" (JAM judged against -b/p, STICK below
eta = 1e-2 outside the studies) and "effective" (JAM judged against the
engine's own friction, STICK below the friction time constant).  The merged
classifier is the second rule, so every number of the old "effective" runs
must equal the new single run; the script checks that (rtol 1e-12) and lists
every state whose label differs from the old "part_a" one, grouped by
(old label -> new label), with the old and new confusion matrices.
"""

from __future__ import annotations

import csv
import json
import math
import sys
from collections import Counter
from pathlib import Path

NAMES = ["SLIP", "LIFTOFF", "STICK", "JAM", "DIVERGED", "GB"]
TIMING = {"wall_time", "steps_per_second", "classifier", "engine"}


def _same(a, b) -> list[str]:
    out = []
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted((set(a) | set(b)) - TIMING):
            if k not in a or k not in b:
                out.append(f"{k}: only in {'new' if k in b else 'old'}")
            else:
                out += [f"{k}{d}" for d in _same(a[k], b[k])]
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f": length {len(a)} vs {len(b)}"]
        for i, (x, y) in enumerate(zip(a, b)):
            out += [f"[{i}]{d}" for d in _same(x, y)]
    elif isinstance(a, float) and isinstance(b, float):
        if not (a == b or (math.isnan(a) and math.isnan(b)) or abs(a - b) <= 1e-12 * abs(a)):
            out.append(f": {a!r} vs {b!r}")
    elif a != b:
        out.append(f": {a!r} vs {b!r}")
    return out


def _rows(path: Path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main(old: Path, new: Path) -> int:
    bad = 0
    for study in sorted(old.glob("mujoco_maps/study_*.json")) + [old / "mujoco_convergence/study.json"]:
        o, n = json.loads(study.read_text()), json.loads((new / study.relative_to(old)).read_text())
        eff = [r for r in o["runs"] if r["classifier"] == "effective"]
        for r in eff:  # the old runs stored the STICK speed they used as stick_speed; the new ones as stick_threshold
            r["thresholds"]["stick_threshold"] = r["thresholds"].pop("stick_speed")
        for r in n["runs"]:
            for k in ("stick_speed", "stick_creep", "jam_p_eff"):  # the new classifier's own parameters
                r["thresholds"].pop(k)
        diffs = _same(eff, n["runs"]) + _same([r for r in o["convergence_table"] if r["classifier"] == "effective"], n["convergence_table"])
        print(f"{study.relative_to(old)}: {len(eff)} old 'effective' runs vs {len(n['runs'])} new runs: "
              f"{'every number equal' if not diffs else f'{len(diffs)} differences'}")
        for d in diffs[:10]:
            print(f"    {d}")
        bad += bool(diffs)
    changes: Counter = Counter()
    listed = []
    total = {"part_a": [[0] * 6 for _ in range(6)], "new": [[0] * 6 for _ in range(6)]}
    for events in sorted(old.glob("mujoco_maps/events_*.csv")):
        o, n = _rows(events), _rows(new / events.relative_to(old))
        for a, b in zip(o, n):
            if a["slipping"] != "1":
                continue
            if b["mujoco"] != a["mujoco_effective"] or b["mujoco_time"] != a["mujoco_effective_time"]:
                print(f"{events.name}: new label differs from the old 'effective' one: {a} {b}")
                bad += 1
            an, pa, nw = int(a["analytic_outcome"]), int(a["mujoco_part_a"]), int(b["mujoco"])
            total["part_a"][an][pa] += 1
            total["new"][an][nw] += 1
            if pa != nw:
                key = (NAMES[pa], NAMES[nw])
                changes[key] += 1
                listed.append((events.stem[len("events_"):], {k: float(a[k]) for k in ("theta", "varphi", "Theta", "Psi", "mu", "eta")},
                               NAMES[an], a["analytic_time"], NAMES[pa], a["mujoco_part_a_time"], NAMES[nw], b["mujoco_time"]))
    print("\nStates whose MuJoCo label changed against the old 'part_a' rule (map, start, analytic, old, new):")
    for m, s, an, ta, pa, tp, nw, tn in listed:
        print(f"  {m:<14} " + " ".join(f"{k}={v:.4g}" for k, v in s.items()) + f"  analytic {an} at {float(ta):.3g}; old {pa} at {float(tp):.3g}; new {nw} at {float(tn):.3g}")
    print("\nChanges by (old -> new):", dict(changes))
    for name, m in total.items():
        print(f"\nConfusion, all maps, {'old part_a' if name == 'part_a' else 'merged'} (rows analytic, columns MuJoCo; SLIP LIFTOFF STICK JAM):")
        for i in range(4):
            print("   ", NAMES[i].ljust(8), " ".join(f"{v:4d}" for v in m[i][:4]))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1]), Path(sys.argv[2])))
