"""``crosscheck sweep SPEC --out DIR`` (run or resume a sweep) and ``crosscheck compare DIR_A DIR_B`` (two stores run by run)."""

from __future__ import annotations

import sys
from pathlib import Path

from crosscheck.checks import integer
from crosscheck.cli.options import ascii_number, directory


def _sweep(args) -> int:
    from crosscheck import sweeps

    workers = None if args.workers is None else integer("workers", args.workers, 1, 1024)
    from crosscheck.sweeps.runner import check_reachable

    check_reachable(args.scheduler)  # before any chunk is computed
    spec = sweeps.load_spec(args.spec)  # before the store is touched: a bad spec leaves OUT as it was
    out = directory("out", args.out)
    summary = sweeps.run(
        spec,
        out,
        workers=workers,
        scheduler=args.scheduler,
        fresh=args.fresh,
        progress=False if args.no_progress else None,
    )
    print(summary)
    return 1 if summary.failed else 0


def _compare(args) -> int:
    from crosscheck.sweeps.store_diff import compare_stores

    if args.out is not None:
        if not args.out.strip() or args.out.endswith("/"):
            raise ValueError(
                f"out must be a file name prefix (the JSON and CSV are <out>.json and <out>-disagreeing.csv); got {args.out!r}"
            )
        directory("out", Path(args.out).parent)  # before the stores are read: the same checks as every --out
    c, files = compare_stores(args.DIR_A, args.DIR_B, out=args.out)
    print(c.table())
    print("wrote " + ", ".join(str(f) for f in files), file=sys.stderr)
    return 0


def register(sub) -> None:
    s = sub.add_parser("sweep", help="run (or resume) a sweep from a TOML spec into a result store")
    s.add_argument("spec", help="the sweep's TOML spec (examples/sweep.toml)")
    s.add_argument("--out", required=True, help="the store directory (resumed if it holds the same sweep)")
    s.add_argument(
        "--workers",
        type=ascii_number,
        default=None,
        help="processes (or Dask workers with --scheduler local); default: the usable cores",
    )
    s.add_argument(
        "--scheduler",
        default=None,
        help="'local' (a Dask LocalCluster for this run) or a Dask scheduler address tcp://host:8786",
    )
    s.add_argument("--fresh", action="store_true", help="replace whatever sweep OUT holds")
    s.add_argument("--no-progress", action="store_true", help="no progress bar or log lines")
    s.set_defaults(func=_sweep)
    c = sub.add_parser("compare", help="compare two sweep stores run by run (confusion, agreement, event times)")
    c.add_argument("DIR_A", help="the reference store (e.g. an analytic sweep)")
    c.add_argument("DIR_B", help="the store compared with it")
    c.add_argument("--out", default=None, help="prefix of the JSON and CSV written (default: B/compare-<name of A>)")
    c.set_defaults(func=_compare)
