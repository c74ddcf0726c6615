"""Progress bars: drawn on a terminal, or when asked; never by a library call whose output goes to a file or a pipe.

Every ``progress`` argument of the library means: ``None`` (the default) a bar
only when standard error is a terminal, ``True`` a bar wherever standard error
goes, ``False`` none.
"""

from __future__ import annotations

import os
import select
import signal
import sys
import threading
import time
from contextlib import contextmanager

__all__ = ["enabled", "bar", "ticking"]


def enabled(progress: bool | None, stream=None) -> bool:
    """Whether to draw a bar: ``progress`` when given, else whether ``stream`` (default ``sys.stderr``) is a terminal."""
    if progress is not None:
        return bool(progress)
    stream = sys.stderr if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False


def bar(iterable=None, *, progress: bool | None, **kwargs):
    """``tqdm(iterable, **kwargs)`` on standard error, disabled unless ``enabled(progress)``."""
    from tqdm.auto import tqdm

    return tqdm(iterable, disable=not enabled(progress), file=sys.stderr, **kwargs)


#: Seconds a Ctrl-C is left to the main thread before ``ticking`` ends the process itself (Python answers it within
#: microseconds when it runs Python code; not before a library's C call returns).
INTERRUPT_GRACE = 1.0


@contextmanager
def ticking(desc: str, *, progress: bool | None, every: float = 1.0, interrupted: str | None = None):
    """While the block runs, ``desc`` and the seconds elapsed on one line of standard error, drawn at once and redrawn
    every ``every`` seconds, erased when the block ends; nothing unless ``enabled(progress)``.

    For a run that is one call of an engine (``simulate``, a ladder): it cannot say how far it is, only that it is
    running and for how long, which a run of minutes (a horizon of thousands, a stiff compliant rod) must say.

    ``interrupted``: for a block that writes nothing (its caller writes its files after it), the line to print on a
    Ctrl-C the main thread cannot answer.  Python runs its signal handlers in the main thread between bytecodes, so a
    library's long C call (MuJoCo's rollout of a horizon of 1500: 55 s) would finish before the KeyboardInterrupt;
    this thread, woken by the signal (``signal.set_wakeup_fd``), prints the line and ends the process with exit
    status 130 once the main thread has not answered in ``INTERRUPT_GRACE`` seconds.
    """
    draw = enabled(progress)
    wake = _wakeup_pipe() if interrupted is not None else None
    if not draw and wake is None:
        yield
        return
    stop, t0 = threading.Event(), time.monotonic()

    def watch() -> None:
        while True:
            if draw and not _bars():  # a progress bar of the run says more than the seconds
                sys.stderr.write(f"\r{desc}: {time.monotonic() - t0:.0f} s (Ctrl-C stops it)")
                sys.stderr.flush()
            if wake is not None and _interrupted(wake[0], every) and not stop.wait(INTERRUPT_GRACE):
                sys.stderr.write(("\r\x1b[K" if draw else "") + interrupted + "\n")
                sys.stderr.flush()
                os._exit(130)
            if stop.wait(0 if wake is not None else every):
                return

    thread = threading.Thread(target=watch, name="ticking", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        if wake is not None:
            os.write(wake[1], b"\0")  # (not a SIGINT) wakes the watcher's select now, not at its timeout
        thread.join()
        if wake is not None:
            signal.set_wakeup_fd(wake[2])
            os.close(wake[0]), os.close(wake[1])
        if draw:
            sys.stderr.write("\r\x1b[K")  # the line erased: what the command prints next starts at its left
            sys.stderr.flush()


def _wakeup_pipe() -> tuple[int, int, int] | None:
    """(read end, write end, previous wakeup fd) of a pipe the signal module writes each signal's number to; None
    where it cannot (not the main thread)."""
    r, w = os.pipe()
    os.set_blocking(w, False)
    try:
        old = signal.set_wakeup_fd(w, warn_on_full_buffer=False)
    except ValueError:
        os.close(r), os.close(w)
        return None
    return r, w, old


def _interrupted(fd: int, timeout: float) -> bool:
    """Whether a SIGINT reached the wakeup pipe ``fd`` within ``timeout`` seconds."""
    ready, _, _ = select.select([fd], [], [], timeout)
    return bool(ready) and signal.SIGINT in os.read(fd, 64)


def _bars() -> bool:
    """Whether a tqdm bar is open in this process (its line is the one to show)."""
    from tqdm import tqdm

    return any(not getattr(b, "disable", False) for b in list(getattr(tqdm, "_instances", ())))
