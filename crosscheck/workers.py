"""Forked worker processes that die with their parent and hold none of its locks.

Every process pool crosscheck starts (a sweep's chunks, an engine's
``sweep_by_simulate``, the report's sections and figures) comes from here, so
that a run killed by SIGKILL never leaves workers behind:

* each worker asks the kernel (Linux ``prctl(PR_SET_PDEATHSIG, SIGKILL)``) to
  be killed when its parent dies, and exits at once if the parent is already
  gone by the time it starts;
* each worker closes the descriptors of the parent's directory locks
  (``crosscheck.locking.HELD``): a forked child shares the parent's open
  files, and with them its ``flock``, which would otherwise outlive the parent
  for as long as the child runs.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import multiprocessing
import os
import signal
from concurrent.futures import ProcessPoolExecutor

from crosscheck import locking

__all__ = ["pool", "process_pool", "default_workers", "adopt"]

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


def default_workers() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def adopt(parent: int) -> None:
    """Run first in a forked worker of ``parent``: die with it, and drop its locks."""
    for fd in list(locking.HELD):
        try:
            os.close(fd)
        except OSError:
            pass
    locking.HELD.clear()
    libc_name = ctypes.util.find_library("c")
    if libc_name is not None:  # Linux; elsewhere workers exit when their pipe to the parent breaks
        try:
            ctypes.CDLL(libc_name, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent died between the fork and the prctl
        os._exit(1)


def pool(workers: int) -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` of ``workers`` forked processes that die with this one (module docstring)."""
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork"), initializer=adopt, initargs=(os.getpid(),))


def process_pool(workers: int):
    """A ``multiprocessing.Pool`` of ``workers`` forked processes that die with this one (module docstring)."""
    return multiprocessing.get_context("fork").Pool(workers, initializer=adopt, initargs=(os.getpid(),))
