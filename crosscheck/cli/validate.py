"""``crosscheck validate ENGINE [--states N] [--seed S] [--json]``: an engine's checks against the analytic reference.

The checks of each engine are in ``crosscheck.studies.validate`` (dynamics
terms for Pinocchio; contact events for every engine with event tolerances,
each engine's own checks among them: MuJoCo's contact force, the rigid
engine's one-step impulse, convergence orders and jams against the IWC).
``--checks dynamics|events`` runs one part.  The command prints the
per-quantity table (or JSON) and exits 1 when any quantity exceeds its
tolerance.
"""

from __future__ import annotations

import sys

import numpy as np

from crosscheck.checks import integer
from crosscheck.cli.options import ascii_number, interrupted_line
from crosscheck.progress import ticking
from crosscheck.studies import validate as validation

#: The largest --states: beyond a million states a run belongs in ``crosscheck sweep`` (resumable, chunked).
MAX_STATES = 1_000_000


def _run(args) -> int:
    n = validation.default_states(args.engine) if args.states is None else integer("states", args.states, 1, MAX_STATES)
    seed = integer("seed", args.seed, 0, 2**63 - 1)
    checks = validation.PARTS if args.checks == "all" else (args.checks,)
    # on a terminal: the run's bars, and its seconds while no bar is open (an engine's own checks run without one)
    with ticking(f"validating {args.engine} on {n} states", progress=None, interrupted=interrupted_line()):
        result = validation.validate(
            args.engine, n, np.random.default_rng(seed), progress=not args.json and sys.stderr.isatty(), checks=checks
        )
    print(result.to_json() if args.json else result.to_table())
    return 0 if result.passed else 1


def register(sub) -> None:
    v = sub.add_parser("validate", help="compare an engine with the analytic reference")
    engines = v.add_subparsers(dest="engine", required=True, parser_class=type(v))
    for name in validation.names():
        e = engines.add_parser(name, help=f"{name} vs the analytic reference")
        e.add_argument(
            "--states",
            type=ascii_number,
            default=None,
            help=f"number of random states, 1 to {MAX_STATES} (default: the engine's); not capped further: a "
            "long run shows its bars and seconds on a terminal, and Ctrl-C stops it",
        )
        e.add_argument(
            "--seed", type=ascii_number, default="0", help="seed of numpy.random.default_rng, >= 0 (default 0)"
        )
        e.add_argument("--json", action="store_true", help="print the result as JSON")
        e.add_argument(
            "--checks",
            choices=["all", *validation.parts_of(name)],
            default="all",
            help="run only these checks (default: all the engine has)",
        )
        e.set_defaults(func=_run)
