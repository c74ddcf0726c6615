"""``crosscheck validate <engine> [--states N] [--seed S] [--json]``.

Each engine's validation lives in its own module exposing

    DEFAULT_STATES: int
    validate(n_states: int, rng: numpy.random.Generator, *, progress: bool) -> ValidationResult

(see ``crosscheck.compare``).  The command prints the per-quantity table (or
JSON) and exits 1 when any quantity exceeds its tolerance.
"""

from __future__ import annotations

import importlib
import sys

import numpy as np

ENGINES = {
    "pinocchio": "crosscheck.validate_pinocchio",
    "mujoco": "crosscheck.validate_mujoco",
}


def _run(args) -> int:
    module = importlib.import_module(ENGINES[args.engine])
    n = module.DEFAULT_STATES if args.states is None else args.states
    if n < 1:
        raise ValueError(f"states must be an integer >= 1; got {n}")
    result = module.validate(n, np.random.default_rng(args.seed), progress=not args.json and sys.stderr.isatty())
    print(result.to_json() if args.json else result.to_table())
    return 0 if result.passed else 1


def register(sub) -> None:
    v = sub.add_parser("validate", help="compare an engine with the analytic reference")
    engines = v.add_subparsers(dest="engine", required=True, parser_class=type(v))
    for name in ENGINES:
        e = engines.add_parser(name, help=f"{name} vs the analytic reference")
        e.add_argument("--states", type=int, default=None, help="number of random states (default: the engine's)")
        e.add_argument("--seed", type=int, default=0, help="seed of numpy.random.default_rng")
        e.add_argument("--json", action="store_true")
        e.set_defaults(func=_run)
