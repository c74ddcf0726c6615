"""The options every command shares (the rod's state and parameters), with help that states each range.

The ranges come from ``crosscheck.checks``, which also checks the values, so
the help and the error of an option always say the same thing.

How a number is written on the command line (one rule for every numeric
option declared here and in ``crosscheck.cli.sweep`` and ``simulate``): ASCII
only.  A value is an optional sign, ASCII digits with an optional point and an
optional exponent (``1.5``, ``-2e-3``, ``+7``), or ``inf`` / ``nan`` (which the
ranges then refuse), at most ``MAX_TEXT`` characters.  Python's ``float`` and
``int`` also read other scripts' digits (``٣``, full-width ``１.４``), digit-like
symbols (``²`` passes ``str.isdigit`` but not ``int``) and underscores
(``1_000``); the command line refuses all of them with one line naming the
option, so what the shell shows is what the run uses.  ``ascii_number`` is
the argparse ``type`` that applies the rule; the value stays text, parsed by
``crosscheck.checks`` as the Python API parses it.

``directory`` is ``crosscheck.checks.writable_directory`` for the command
line: a path the file system refuses (a name too long, a path through a file)
is one line naming the option as well.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from crosscheck.checks import ALPHA, AZIMUTH, ETA, MU, RATE, THETA, VARPHI, writable_directory

#: The longest numeric option text (a double needs at most 24 characters; Python refuses integers past 4300 digits
#: with a message that names no option).
MAX_TEXT = 100


def ascii_number(text: str) -> str:
    """``text`` if it is a number written as the module docstring says (argparse ``type``); argparse names the option otherwise."""
    # ASCII text that is not a number ("abc", "1,5") is left to crosscheck.checks, whose message states the range
    if len(text) > MAX_TEXT or not text.isascii() or "_" in text:
        shown = repr(text) if len(text) <= 40 else f"{text[:20]!r}... ({len(text)} characters)"
        raise argparse.ArgumentTypeError(
            f"must be a number written with ASCII digits (sign, point, exponent; no underscores), "
            f"at most {MAX_TEXT} characters; got {shown}"
        )
    return text


def directory(name: str, value) -> Path:
    """``writable_directory`` with every refusal of the file system (a name too long, a path through a file) one ValueError line."""
    try:
        return writable_directory(name, value)
    except OSError as e:
        shown = repr(str(value)) if len(str(value)) <= 80 else f"{str(value)[:60]!r}... ({len(str(value))} characters)"
        raise ValueError(f"{name} must be a writable directory; cannot use {shown}: {e.strerror or e}") from None


#: (help, metavar) of each state option; metavars differ where only the case does (--theta / --Theta).
STATE_HELP = {
    "theta": (f"polar angle of the rod to the plane [rad], in {THETA}", "THETA"),
    "varphi": (f"relative slip angle beta - psi [rad], in {VARPHI}", "VARPHI"),
    "Theta": (f"scaled polar rate theta_dot / omega, in {RATE}", "THETA_DOT"),
    "Psi": (f"scaled azimuthal rate psi_dot / omega, in {RATE}", "PSI_DOT"),
    "eta": (f"scaled slip speed of the tip, in {ETA}", "ETA"),
    "mu": (f"friction coefficient, in {MU}", "MU"),
}


def add_state(parser, names=("theta", "varphi", "Theta", "Psi", "eta", "mu"), *, required: bool = True) -> None:
    """Add the state options ``names`` (text, parsed by ``crosscheck.checks.number`` so the CLI and the API agree)."""
    for name in names:
        text, metavar = STATE_HELP[name]
        parser.add_argument(f"--{name}", type=ascii_number, metavar=metavar, required=required, help=text)


def add_alpha(parser) -> None:
    parser.add_argument(
        "--alpha",
        type=ascii_number,
        default="3",
        metavar="ALPHA",
        help=f"m l^2 / I0, in {ALPHA} (default 3: uniform rod)",
    )


def add_psi(parser) -> None:
    parser.add_argument(
        "--psi", type=ascii_number, default="0", metavar="PSI", help=f"azimuth [rad], in {AZIMUTH} (default 0)"
    )


#: What an interrupted command leaves, by command: a sweep's written chunks and a report's finished sections stay (their
#: rerun resumes them); every other command writes its files only once its run has finished.
INTERRUPTED = {
    "sweep": "finished sweep chunks and report sections are kept (the same command resumes)",
    "report": "finished sweep chunks and report sections are kept (the same command resumes)",
    None: "nothing was written (files are written once the run has finished)",
}


def interrupted_line(command: str | None = None) -> str:
    """The one line of a Ctrl-C of ``command`` (``INTERRUPTED``: what it keeps)."""
    return f"crosscheck: interrupted; {INTERRUPTED.get(command, INTERRUPTED[None])}"
