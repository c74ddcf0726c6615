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

from crosscheck.studies import validate as validation


def _run(args) -> int:
    n = validation.default_states(args.engine) if args.states is None else args.states
    if n < 1:
        raise ValueError(f"states must be an integer >= 1; got {n}")
    checks = validation.PARTS if args.checks == "all" else (args.checks,)
    result = validation.validate(args.engine, n, np.random.default_rng(args.seed), progress=not args.json and sys.stderr.isatty(), checks=checks)
    print(result.to_json() if args.json else result.to_table())
    return 0 if result.passed else 1


def register(sub) -> None:
    v = sub.add_parser("validate", help="compare an engine with the analytic reference")
    engines = v.add_subparsers(dest="engine", required=True, parser_class=type(v))
    for name in validation.names():
        e = engines.add_parser(name, help=f"{name} vs the analytic reference")
        e.add_argument("--states", type=int, default=None, help="number of random states (default: the engine's)")
        e.add_argument("--seed", type=int, default=0, help="seed of numpy.random.default_rng")
        e.add_argument("--json", action="store_true", help="print the result as JSON")
        e.add_argument("--checks", choices=["all", *validation.parts_of(name)], default="all", help="run only these checks (default: all the engine has)")
        e.set_defaults(func=_run)
