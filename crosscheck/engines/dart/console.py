"""DART's console warnings: its C++ "Warning [file:line] ..." lines on stderr, captured around a run and counted.

DART writes its warnings (dtwarn: "Non-finite joint accelerations detected ...", one line each, coloured on a
terminal) straight to the process's stderr, file descriptor 2, below Python's ``sys.stderr``; a run that blows up
after its first event writes thousands.  ``captured`` points fd 2 at a temporary file for the ``with`` block, puts it
back on leaving (also on an exception or KeyboardInterrupt), counts DART's warning lines and passes everything else
that was written to fd 2 in the block on to the real stderr, in its order.  fd 2 is the process's: another thread
writing to stderr during the block is passed on only when the block ends (the engine's workers are processes).
"""

from __future__ import annotations

import contextlib
import os
import re
import tempfile
from dataclasses import dataclass

from crosscheck.stderr_fd import redirected

__all__ = ["Captured", "captured", "is_warning"]

# A DART warning line: "Warning [" at its start, after the terminal's colour codes if any.
_WARNING = re.compile(rb"^(?:\x1b\[[0-9;]*m)*Warning \[")


@dataclass
class Captured:
    """What ``captured`` caught: ``warnings``, DART's warning lines (set when the block ends)."""

    warnings: int = 0


def is_warning(line: bytes) -> bool:
    """Whether one line written to stderr is a DART warning ("Warning [file:line] ...", colour codes allowed)."""
    return _WARNING.match(line) is not None


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


@contextlib.contextmanager
def captured():
    """fd 2 into a temporary file for the block; on leaving it is restored, DART's warning lines are counted into the
    yielded ``Captured`` and the other lines are written to the restored stderr."""
    seen = Captured()
    with tempfile.TemporaryFile() as sink:
        try:
            with redirected(sink.fileno()):
                yield seen
        finally:
            sink.seek(0)
            lines = sink.read().splitlines(keepends=True)
            seen.warnings = sum(map(is_warning, lines))
            _write_all(2, b"".join(line for line in lines if not is_warning(line)))
