"""The process's standard error at its file descriptor (fd 2), pointed elsewhere for a block: where C and C++
libraries write, below Python's ``sys.stderr``.

Bullet and Warp print a line at start-up and DART a warning per bad step straight to fd 2; ``redirected`` points fd 2
at another file for a ``with`` block and puts it back on leaving (also on an exception or a KeyboardInterrupt),
``silenced`` at the null device.
"""

from __future__ import annotations

import contextlib
import os
import sys

__all__ = ["redirected", "silenced"]


def _flush_python_stderr() -> None:
    """Python's own buffered stderr text out to fd 2 (sys.stderr may be None or closed: nothing to flush then)."""
    with contextlib.suppress(AttributeError, OSError, ValueError):
        sys.stderr.flush()


@contextlib.contextmanager
def redirected(fd: int):
    """fd 2 pointed at the open file descriptor ``fd`` for the block, Python's stderr flushed on both sides."""
    _flush_python_stderr()
    saved = os.dup(2)
    try:
        os.dup2(fd, 2)
        yield
    finally:
        _flush_python_stderr()
        os.dup2(saved, 2)
        os.close(saved)


@contextlib.contextmanager
def silenced():
    """fd 2 pointed at the null device for the block: what a library writes there is dropped."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        with redirected(devnull):
            yield
    finally:
        os.close(devnull)
