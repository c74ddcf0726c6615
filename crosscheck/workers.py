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

Each worker also puts every object it inherited out of the cyclic garbage
collector's reach (``gc.freeze``).  A forked child shares its parent's memory
pages until it writes to one, which copies it; a collection of the oldest
generation writes to the header of every object it scans, so a child that
collected once copied most of the parent's heap (its numpy, Drake, MuJoCo,
Pinocchio and matplotlib objects).  Reference counting still frees what a
worker drops; only a reference cycle among the inherited objects that a
worker lets go stays in it until it exits.  On the quick report (83 section
processes and the figures' workers; ``/usr/bin/time``, three runs each in
turn): 40.1, 40.0 and 39.0 s instead of 43.0, 43.8 and 42.1; 72.4, 72.2 and
70.7 s of user CPU instead of 77.3, 78.7 and 76.1; 850 000-870 000 page faults
instead of 957 000-970 000.  The Python documentation of ``gc.freeze``
describes this use.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import multiprocessing
import os
import signal
from concurrent.futures import ProcessPoolExecutor

from crosscheck import locking

__all__ = ["pool", "process_pool", "default_workers", "adopt", "stop"]

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


def default_workers() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def adopt(parent: int) -> None:
    """Run first in a forked worker of ``parent``: die with it, drop its locks, and leave its objects to it (``gc.freeze``)."""
    gc.freeze()
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


def _adopt_deaf(parent: int) -> None:
    """``adopt``, and ignore SIGINT: a Ctrl-C reaches the whole process group, and the parent alone answers it
    (``stop``) instead of every worker printing its own KeyboardInterrupt."""
    adopt(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def pool(workers: int, *, deaf: bool = False) -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` of ``workers`` forked processes that die with this one (module docstring);
    ``deaf``: they ignore SIGINT, and the parent stops them (``stop``)."""
    return ProcessPoolExecutor(
        workers,
        mp_context=multiprocessing.get_context("fork"),
        initializer=_adopt_deaf if deaf else adopt,
        initargs=(os.getpid(),),
    )


def stop(executor: ProcessPoolExecutor) -> None:
    """End ``executor`` now: its queued tasks cancelled, its running ones killed (SIGKILL: their partial work is lost,
    what they finished before is the caller's).  For a Ctrl-C, which must not wait for every queued task."""
    processes = list((getattr(executor, "_processes", None) or {}).values())
    executor.shutdown(wait=False, cancel_futures=True)
    for p in processes:
        try:
            p.kill()
        except (OSError, ValueError):
            pass
    for p in processes:
        p.join(5.0)


def process_pool(workers: int):
    """A ``multiprocessing.Pool`` of ``workers`` forked processes that die with this one (module docstring)."""
    return multiprocessing.get_context("fork").Pool(workers, initializer=adopt, initargs=(os.getpid(),))
