"""``crosscheck.progress.ticking``: the seconds of a long run on a terminal, nothing elsewhere, the signal module's
wakeup fd given back.  (A Ctrl-C inside an engine's long C call: ``tests/test_interrupt.py``, in real processes.)"""

from __future__ import annotations

import signal
import time

from crosscheck.progress import ticking


def test_the_seconds_are_drawn_at_once_redrawn_and_erased(capsys):
    with ticking("simulating mujoco to t = 1500", progress=True, every=0.05):
        time.sleep(0.3)
    err = capsys.readouterr().err
    draws = err.split("\r")[1:-1]
    assert draws[0] == "simulating mujoco to t = 1500: 0 s (Ctrl-C stops it)"
    assert len(draws) >= 3 and all(d.startswith("simulating mujoco to t = 1500: ") for d in draws)
    assert err.endswith("\r\x1b[K")  # the line erased: the result starts at the left


def test_nothing_is_drawn_off_a_terminal_and_the_wakeup_fd_is_given_back(capsys):
    def wakeup_fd() -> int:
        fd = signal.set_wakeup_fd(-1)
        signal.set_wakeup_fd(fd)
        return fd

    before = wakeup_fd()
    with ticking("validating mujoco on 10 states", progress=None, every=0.05, interrupted="crosscheck: interrupted"):
        assert wakeup_fd() not in (-1, before)  # the block's own pipe, which hears a Ctrl-C while it runs
        time.sleep(0.2)
    assert wakeup_fd() == before
    assert capsys.readouterr().err == ""  # capsys's stderr is not a terminal


def test_a_block_that_hears_sigint_ends_when_it_ends_not_at_the_watchers_next_tick():
    # the watcher waits on the wakeup pipe ``every`` seconds at a time: the block's end wakes it (every refused or short
    # `crosscheck simulate` waited up to a second after its answer)
    t0 = time.monotonic()
    with ticking("simulating", progress=None, every=30.0, interrupted="crosscheck: interrupted"):
        pass
    assert time.monotonic() - t0 < 5.0  # ended by the block, not after the watcher's 30 s wait
