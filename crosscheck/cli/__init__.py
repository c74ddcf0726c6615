"""The ``crosscheck`` command line.

Each sub-command lives in a module of this package that exposes
``register(subparsers)``; that function adds its parser(s) and sets
``func(args) -> int``.  Engines are imported lazily inside ``func`` so that
``crosscheck critical`` does not load MuJoCo or Pinocchio.

Errors from bad arguments (the ``ValueError``s of ``crosscheck.checks``) are
printed as one line ``crosscheck: error: <message>`` with exit status 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

__all__ = ["main", "COMMAND_MODULES"]

#: Modules that register sub-commands, in help order.
COMMAND_MODULES = [
    "crosscheck.cli.analytic",
    "crosscheck.cli.simulate",
    "crosscheck.cli.validate",
    "crosscheck.cli.report",
    "crosscheck.cli.gb",
    "crosscheck.cli.sweep",
]


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, no usage dump: the message names the problem
        sys.stderr.write(f"crosscheck: error: {message}\n")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="crosscheck", description="Cross-validation of the 3D Painleve rod: analytic vs Pinocchio vs MuJoCo.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except ValueError as e:
        sys.stderr.write(f"crosscheck: error: {e}\n")
        return 2
    except BrokenPipeError:  # output piped into `head`: not an error of ours
        sys.stderr.close()
        return 0


if __name__ == "__main__":
    raise SystemExit(main())
