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
import errno
import importlib
import os
import re
import sys

from crosscheck.cli.options import interrupted_line

__all__ = ["main", "COMMAND_MODULES"]

#: Modules that register sub-commands, in help order.
COMMAND_MODULES = [
    "crosscheck.cli.analytic",
    "crosscheck.cli.simulate",
    "crosscheck.cli.validate",
    "crosscheck.cli.report",
    "crosscheck.cli.gb",
    "crosscheck.cli.sweep",
    "crosscheck.cli.explain",
    "crosscheck.cli.engines",
]


# argparse takes "-inf", "-nan" and "-1e400" for option names (its own pattern knows only digits), and
# then says "expected one argument": values that look like negative numbers are values.
_NEGATIVE_NUMBER = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)
_OPTION_IN_MESSAGE = re.compile(r"^argument (\S+?)(?:/\S+)?: ")


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message: str):  # one line, no usage dump: the message names the problem
        # argparse's own messages ("expected one argument") name the option but not what it takes: add its help.
        m = _OPTION_IN_MESSAGE.match(message)
        action = self._option_string_actions.get(m.group(1)) if m else None
        if action is not None and action.help and "choose from" not in message:
            message = f"{message} ({m.group(1)}: {action.help})"
        if message.startswith("the following arguments are required: "):
            names = message.split(": ", 1)[1].split(", ")
            helps = [f"{n}: {self._option_string_actions[n].help}" for n in names if n in self._option_string_actions]
            if helps:
                message = f"{message} ({'; '.join(helps)})"
        sys.stderr.write(f"crosscheck: error: {message}\n")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="crosscheck",
        description="Cross-validation of the 3D Painleve rod: the paper's analytic reference against contact engines "
        "(crosscheck simulate --help lists them).",
    )
    from crosscheck import __version__

    parser.add_argument("--version", action="version", version=f"crosscheck {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def _stdout_lost(e: OSError) -> int:
    """One line for a standard output the system refuses (``> /dev/full``: ENOSPC); later flushes go to /dev/null, so
    that Python's own flush at exit does not print a second error."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass
    sys.stderr.write(f"crosscheck: error: standard output cannot be written: {e.strerror or e}\n")
    return 1


def main(argv: list[str] | None = None) -> int:
    try:
        return _main(argv)
    except KeyboardInterrupt:  # before the command was known (its imports) or after it answered
        sys.stderr.write(f"{interrupted_line()}\n")
        return 130


def _main(argv: list[str] | None) -> int:
    try:  # a path or a name the terminal's encoding cannot show is shown escaped, never an error after the work
        sys.stdout.reconfigure(errors="backslashreplace")
    except (AttributeError, ValueError):
        pass
    parser = build_parser()

    try:
        args, extra = parser.parse_known_args(argv)
        if extra:  # argparse would say "unrecognized arguments" and nothing of what the command takes
            sub = parser._subparsers._group_actions[0].choices[args.command]
            takes = ", ".join(sorted(o for o in sub._option_string_actions if o.startswith("--")))
            parser.error(f"unrecognized arguments: {' '.join(extra)} (crosscheck {args.command} takes one of: {takes})")
    except SystemExit as e:  # a usage error (already printed on one line) or --help / --version
        return e.code if isinstance(e.code, int) else 0
    try:
        code = int(args.func(args) or 0)
        sys.stdout.flush()  # here, not at exit: a full device is one line
        return code
    except ValueError as e:
        sys.stderr.write(f"crosscheck: error: {e}\n")
        return 2
    except BrokenPipeError:  # output piped into `head`: not an error of ours
        sys.stderr.close()
        return 0
    except KeyboardInterrupt:  # Ctrl-C: one line, exit 130 (128 + SIGINT), as a shell reports it
        sys.stderr.write(f"{interrupted_line(args.command)}\n")
        return 130
    except OSError as e:
        if e.errno not in (errno.ENOSPC, errno.EDQUOT, errno.EIO, errno.EFBIG):
            raise
        if e.filename is not None:
            sys.stderr.write(f"crosscheck: error: {str(e.filename)!r} cannot be written: {e.strerror or e}\n")
            return 1
        return _stdout_lost(e)


if __name__ == "__main__":
    raise SystemExit(main())
