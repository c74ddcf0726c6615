"""MuJoCo's own warnings ("Nan, Inf or huge value in QACC ..."), captured and counted instead of printed.

MuJoCo's default handler prints each warning on stderr and appends it to
``MUJOCO_LOG.TXT`` in the working directory.  ``install`` replaces it (once
per process) with a handler that counts the warnings by kind; ``counts``
returns the counts so far, so that whoever ran a batch (an engine sweep, a
chunk of a stored sweep) can report the warnings it caused: the difference
of ``counts()`` before and after.  A warning of instability is also the
reason MuJoCo resets a run, which the classifier reads as DIVERGED (the
clock stops advancing), so the count is the number of such runs.
"""

from __future__ import annotations

import re
import threading
from collections import Counter

import mujoco

__all__ = ["install", "counts", "since", "kind"]

_LOCK = threading.Lock()
_COUNTS: Counter = Counter()
_INSTALLED = False

# The variable parts of a message's first sentence (the DOF, an index): the rest is the warning's kind.
_VARIABLE = re.compile(r"\s+at DOF \d+|\s+\d+")


def kind(message: str) -> str:
    """The kind of a warning: its first sentence without the DOF and other numbers ("Nan, Inf or huge value in QACC")."""
    first = message.strip().split(". ")[0].rstrip(".")
    return _VARIABLE.sub("", first) or message.strip()


def _handler(message: str) -> None:
    with _LOCK:
        _COUNTS[kind(message)] += 1


def install() -> None:
    """Route MuJoCo's warnings to the counter (idempotent; the handler is process-global, as MuJoCo's is)."""
    global _INSTALLED
    if not _INSTALLED:
        mujoco.set_mju_user_warning(_handler)
        _INSTALLED = True


def counts() -> dict[str, int]:
    """Warnings counted in this process so far, by kind."""
    with _LOCK:
        return dict(_COUNTS)


def since(before: dict[str, int]) -> dict[str, int]:
    """Warnings counted since ``before`` (an earlier ``counts()``), by kind; kinds with none left out."""
    now = counts()
    return {k: n - before.get(k, 0) for k, n in now.items() if n - before.get(k, 0) > 0}
