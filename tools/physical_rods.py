"""Measure which engines are scale-invariant: one start at the scaled rod against physical rods of the same alpha.

    PYTHONPATH=<tree> OPENBLAS_CORETYPE=Haswell python tools/physical_rods.py [--extreme]

Per engine: the outcome, and the largest difference over the rods, as max |difference| / (1 + max |field|), of the
state fields row by row and of the contact fields row by row and in their mean (the rods, start and measure of
``tests/test_physical_rod_records.py``; ``--extreme``: a 1 mm rod of 1 g, a 100 m rod of 10 t, g = 0.01 and 1e4).
The table of docs/engines.md is its output.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from test_physical_rod_records import (
    CONTACT_FIELDS,
    HORIZON,
    MU,
    RODS,
    STATE,
    STATE_FIELDS,
    _error,
    _options,
)

from crosscheck import Rod, engines

EXTREME = {
    "mm_1g": Rod.uniform(1e-3, 1e-3),
    "giant": Rod.uniform(1e4, 100.0),
    "low_g": Rod.uniform(1.0, 1.0, gravity=0.01),
    "high_g": Rod.uniform(1.0, 1.0, gravity=1e4),
}


def measure(name: str, rods: dict) -> str:
    spec, t0 = engines.get(name), time.time()
    opts = _options(spec)
    base = spec.simulate(Rod.scaled(3.0), STATE, MU, horizon=HORIZON, **opts)
    states = rows = mean = 0.0
    same, fails = True, []
    for rod_name, rod in rods.items():
        try:
            run = spec.simulate(rod, STATE, MU, horizon=HORIZON, **opts)
        except Exception as e:  # noqa: BLE001  (a rod the engine cannot build is a row of the table)
            fails.append(f"{rod_name}: {str(e).splitlines()[0][:90]}")
            continue
        same &= (run.outcome, run.nstep) == (base.outcome, base.nstep)
        R, B = run.record, base.record
        states = max(states, *(_error(getattr(R, f), getattr(B, f)) for f in STATE_FIELDS))
        rows = max(rows, *(_error(getattr(R, f), getattr(B, f)) for f in CONTACT_FIELDS))
        mean = max(mean, *(_error(np.mean(getattr(R, f), 0), np.mean(getattr(B, f), 0)) for f in CONTACT_FIELDS))
    return (
        f"{name}\t{base.outcome.name}\tsame outcome {same}\tstates {states:.2g}\tcontact rows {rows:.2g}\t"
        f"contact mean {mean:.2g}\tnot built: {fails or '-'}\t{time.time() - t0:.0f} s"
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--extreme", action="store_true", help="the extreme rods instead of the test's")
    args = ap.parse_args()
    for name in engines.names():
        print(measure(name, EXTREME if args.extreme else RODS), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
