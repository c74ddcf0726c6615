"""The bad-input audit: run inputs that must be refused through the CLI and the Python API and judge each answer.

A bad input must get one line naming the parameter, the value and the allowed
range: exit status 2 with ``crosscheck: error: ...`` on the command line, a
``ValueError`` in Python.  ``judge_cli`` and ``judge_api`` sort every answer
into one verdict:

* ``clean``: the refusal the README promises;
* ``vague``: refused, but the message lacks the parameter's name or its range;
* ``traceback``: an exception other than ``ValueError`` escaped (CLI: any);
* ``accepted``: the bad input was taken and an answer printed or returned,
  a silent wrong answer;
* ``hang``: no answer within the time limit.

The case tables are in ``bad_inputs.py`` beside this module;
``python tools/audit_inputs.py`` prints the counts per verdict.
"""

from __future__ import annotations

import contextlib
import io
import re
import signal
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

__all__ = ["Verdict", "judge_message", "judge_cli", "judge_api", "run_cli", "VERDICTS"]

VERDICTS = ("clean", "vague", "traceback", "accepted", "hang")

# A message states a range when it shows an interval, a set, or a bound.
_RANGE = re.compile(
    r"[\[(][^\])]*[\])]|one of|choose from|at most|at least|>=|<=|\bin \{|must be (a |an )?(number|integer|file|directory|readable|writable|True)"
    r"|must be an? [A-Z]\w+|must be '[^']+' or|cannot write",
    re.IGNORECASE,
)


@dataclass
class Verdict:
    verdict: str
    detail: str  # the message, the traceback's last line, or what was returned


class _Timeout(Exception):
    pass


def _alarm(seconds: float):
    def handler(signum, frame):
        raise _Timeout()

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    return old


def _disarm(old) -> None:
    signal.setitimer(signal.ITIMER_REAL, 0)
    signal.signal(signal.SIGALRM, old)


def judge_message(message: str, param: str) -> bool:
    """True when ``message`` is one line that names ``param`` and states what is allowed."""
    lines = [line for line in message.strip().splitlines() if line.strip()]
    if len(lines) != 1:
        return False
    line = lines[0]
    names = re.search(r"(?<![A-Za-z_])" + re.escape(param) + r"(?![A-Za-z_])", line) is not None
    return names and _RANGE.search(line) is not None


def run_cli(argv: list[str], *, timeout: float = 60.0) -> tuple[int | None, str, str, str]:
    """(exit status, stdout, stderr, escaped traceback) of ``crosscheck argv`` run in this process."""
    from crosscheck.cli import main

    out, err = io.StringIO(), io.StringIO()
    code, tb = None, ""
    old = _alarm(timeout)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(argv)
            except SystemExit as e:
                code = e.code if isinstance(e.code, int) else (0 if e.code is None else 2)
    except _Timeout:
        tb = "hang"
    except BaseException:  # noqa: BLE001  (the audit records whatever escaped)
        tb = traceback.format_exc()
    finally:
        _disarm(old)
    return code, out.getvalue(), err.getvalue(), tb


def judge_cli(argv: list[str], param: str, *, timeout: float = 60.0) -> Verdict:
    """The verdict on ``crosscheck argv``, an input that must be refused because of ``param``."""
    code, out, err, tb = run_cli(argv, timeout=timeout)
    if tb == "hang":
        return Verdict("hang", f"no answer in {timeout:g} s")
    if tb or "Traceback" in err:
        last = (tb or err).strip().splitlines()[-1]
        return Verdict("traceback", last)
    if code == 0 or (code != 2 and not err.strip()):
        return Verdict("accepted", f"exit {code}: {out.strip()[:200]}")
    msg = err.strip()
    if code == 2 and msg.startswith("crosscheck: error: ") and judge_message(msg, param):
        return Verdict("clean", msg)
    return Verdict("vague", f"exit {code}: {msg[:300]}")


def judge_api(call: Callable[[], Any], param: str, *, timeout: float = 60.0) -> Verdict:
    """The verdict on ``call()``, a Python call that must raise ``ValueError`` because of ``param``."""
    old = _alarm(timeout)
    try:
        result = call()
    except _Timeout:
        return Verdict("hang", f"no answer in {timeout:g} s")
    except ValueError as e:
        msg = str(e)
        return Verdict("clean" if judge_message(msg, param) else "vague", msg)
    except BaseException as e:  # noqa: BLE001
        return Verdict("traceback", f"{type(e).__name__}: {e}"[:300])
    finally:
        _disarm(old)
    return Verdict("accepted", repr(result)[:200])
