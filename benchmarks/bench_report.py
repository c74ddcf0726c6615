"""The quick report (``crosscheck report --quick --fresh``) with forked workers freezing the heap they inherit, against without.

    python benchmarks/bench_report.py [--rounds 3] [--out DIR]

Every section process and pool worker runs ``crosscheck.workers.adopt``
first, which calls ``gc.freeze()``: the objects inherited from the parent are
then out of the cyclic collector's reach, and a collection in the child no
longer writes to (and so copies) the parent's pages.  The baseline is the same
command with that one call made a no-op, run in turn with the shipped one in
each round, each in its own process.  Reported per run: wall time, the user
and system CPU of the report and all its processes, and their minor page
faults (``resource.getrusage(RUSAGE_CHILDREN)``); then the ratios of the
means, baseline / shipped.  Both write the same results (the freeze changes
no number); the second directory is checked against the first with
``crosscheck.report.compare_data``.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: The report as ``crosscheck report`` runs it, with ``adopt``'s freeze replaced when asked (the forks inherit the patch).
RUN = """
import sys, types
if sys.argv[1] == "baseline":
    import crosscheck.workers as workers
    workers.gc = types.SimpleNamespace(freeze=lambda: None)
from crosscheck.cli import main
raise SystemExit(main(["report", "--quick", "--fresh", "--no-progress", "--out", sys.argv[2]]))
"""


def run(variant: str, out: Path) -> dict:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", RUN, variant, str(out)], capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"the {variant} report failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return {
        "wall": wall,
        "user": after.ru_utime - before.ru_utime,
        "sys": after.ru_stime - before.ru_stime,
        "faults": after.ru_minflt - before.ru_minflt,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--out", default=None, help="directory for the two reports (default: a temporary one)")
    args = parser.parse_args()
    root = Path(args.out or tempfile.mkdtemp(prefix="bench_report_"))
    runs: dict[str, list[dict]] = {"baseline": [], "shipped": []}
    for k in range(args.rounds):
        for variant in runs:
            r = run(variant, root / variant)
            runs[variant].append(r)
            print(
                f"round {k + 1} {variant:9} wall {r['wall']:6.1f} s  user {r['user']:6.1f} s  sys {r['sys']:5.1f} s  "
                f"minor faults {r['faults']:>9,}",
                flush=True,
            )
    from crosscheck.report.compare_data import compare

    differ = {k: v for k, v in compare(root / "baseline" / "data", root / "shipped" / "data").items() if v}
    for key in ("wall", "user", "sys", "faults"):
        b, s = (statistics.mean(r[key] for r in runs[v]) for v in ("baseline", "shipped"))
        print(f"{key:6}: baseline {b:12,.1f}  shipped {s:12,.1f}  baseline / shipped {b / s:.3f}")
    print("same results:", "yes" if not differ else f"no: {differ}")


if __name__ == "__main__":
    main()
