"""Every bad input, at every entry point, is refused with one line naming the parameter and its range.

The table is ``bad_inputs.py`` (each case a valid call with one value made
bad); ``audit.py`` judges the answers.  A case fails when the input got a
traceback, an answer (a silent wrong result), a message without the
parameter's name or range, or no answer at all.  ``python
tools/audit_inputs.py`` prints the same verdicts as counts.
"""

from __future__ import annotations

import atexit
import math
import re
import shutil
import tempfile
from pathlib import Path

import audit
import bad_inputs
import numpy as np
import pytest

_TMP = Path(tempfile.mkdtemp(prefix="crosscheck-bad-inputs-"))
atexit.register(shutil.rmtree, _TMP, ignore_errors=True)
CLI = bad_inputs.cli_cases(_TMP)
API = bad_inputs.api_cases()


def test_the_table_covers_every_command():
    from crosscheck.cli import build_parser

    commands = set(build_parser()._subparsers._group_actions[0].choices)
    covered = {argv[0] for _, argv, _ in CLI}
    assert commands <= covered, f"commands without bad-input cases: {sorted(commands - covered)}"
    assert len(CLI) + len(API) >= 336


@pytest.mark.parametrize("argv, param", [c[1:] for c in CLI], ids=[c[0] for c in CLI])
def test_cli_refuses(argv, param):
    v = audit.judge_cli(argv, param, timeout=60)
    assert v.verdict == "clean", v.detail


@pytest.mark.parametrize("call, param", [c[1:] for c in API], ids=[c[0] for c in API])
def test_api_refuses(call, param):
    v = audit.judge_api(call, param, timeout=60)
    assert v.verdict == "clean", v.detail


def test_judge_tells_a_vague_message_from_a_clean_one():
    assert audit.judge_message("mu must be in [0, 1000]; got -1.0", "mu")
    assert not audit.judge_message("argument --mu: expected one argument", "mu")  # no range
    assert not audit.judge_message("value must be in [0, 1]; got 2", "mu")  # names another parameter
    assert not audit.judge_message("mu must be in [0, 1000]\ngot -1.0", "mu")  # two lines


# ------------------------------------------------------------- property test ---

# Each command's numeric options and a valid value for the others.
_COMMANDS = {
    "critical": {"mu": "1.4", "alpha": "3"},
    "classify": {"theta": "1.1031", "varphi": "-1.9233", "Theta": "0.9", "Psi": "0", "mu": "1.4", "alpha": "3"},
    "gb": {"mu": "1.7", "alpha": "3", "Psi": "0", "eta": "2", "samples": "3"},
    "slip": {
        "theta": "1.1031",
        "varphi": "-1.9233",
        "Theta": "0.9",
        "Psi": "0",
        "eta": "2",
        "mu": "1.4",
        "alpha": "3",
        "t-max": "0.5",
    },
}
_NON_NUMBER = re.compile(r"\b(nan|inf|infinity)\b", re.IGNORECASE)


def _draw(rng: np.random.Generator) -> float:
    """A finite value of any size and sign (log-uniform magnitude), zero, or a non-finite one."""
    u = rng.uniform()
    if u < 0.1:
        return float(rng.choice([math.nan, math.inf, -math.inf]))
    if u < 0.15:
        return 0.0
    return float(10.0 ** rng.uniform(-320, 308) * rng.choice([-1.0, 1.0]))


@pytest.mark.parametrize("command", sorted(_COMMANDS))
def test_random_values_never_give_a_traceback_or_a_non_number(command):
    """Random finite and non-finite values, one option at a time: a clean refusal or an answer without NaN/inf."""
    rng = np.random.default_rng([2026, len(command)])
    options = _COMMANDS[command]
    answered = 0
    for _ in range(40):
        opt = str(rng.choice(list(options)))
        value = repr(_draw(rng))  # the CLI's text: "nan", "inf", "-inf", "0.0", "1.5e-07", ...
        argv = [command] + [x for k, v in options.items() for x in (f"--{k}", value if k == opt else v)]
        code, out, err, tb = audit.run_cli(argv, timeout=60)
        assert not tb and "Traceback" not in err, f"{argv}: {tb or err}"
        if code == 0:
            answered += 1
            assert not _NON_NUMBER.search(out), f"{argv} printed a non-number:\n{out}"
            assert math.isfinite(float(value)), f"{argv} accepted a non-finite value"
        else:
            assert code == 2 and audit.judge_message(err, opt.replace("-", "_")), f"{argv}: exit {code}: {err}"
    assert answered >= 1, "every draw was refused: the property test tested nothing"


def _finite_numbers(obj) -> bool:
    """Every float in a result (SlipResult, HybridResult, arrays, scalars) is finite."""
    from dataclasses import fields, is_dataclass

    if is_dataclass(obj):
        return all(_finite_numbers(getattr(obj, f.name)) for f in fields(obj))
    if isinstance(obj, (list, tuple)):
        return all(_finite_numbers(x) for x in obj)
    if isinstance(obj, np.ndarray) and obj.dtype.kind == "f":
        return bool(np.all(np.isfinite(obj)))
    if isinstance(obj, (float, np.floating)):
        return math.isfinite(obj)
    return True


def _api_functions():
    from crosscheck.state import SlipState
    from crosscheck.theory import analytic, critical
    from crosscheck.theory.impact import continuation as hybrid
    from crosscheck.theory.slipping import slip_until_event

    ok = dict(theta=1.1031, varphi=-1.9233, Theta=0.9, Psi=0.0, eta=2.0, mu=1.4, alpha=3.0)

    def state(kw):
        return SlipState(**{k: kw[k] for k in ("theta", "varphi", "Theta", "Psi", "eta")})

    return {
        "analytic.b": (lambda kw: analytic.b(kw["Psi"], kw["Theta"], kw["theta"]), ("Psi", "Theta", "theta")),
        "analytic.p": (
            lambda kw: analytic.p(kw["theta"], kw["varphi"], kw["mu"], kw["alpha"]),
            ("theta", "varphi", "mu", "alpha"),
        ),
        "kinematic_case": (
            lambda kw: critical.kinematic_case(kw["mu"], kw["Psi"], kw["alpha"]),
            ("mu", "Psi", "alpha"),
        ),
        "slip_until_event": (lambda kw: slip_until_event(state(kw), kw["mu"], kw["alpha"], t_max=0.5), tuple(ok)),
        "hybrid.run": (lambda kw: hybrid.run(state(kw), kw["mu"], kw["alpha"], horizon=0.5), tuple(ok)),
    }, ok


@pytest.mark.parametrize("name", ["analytic.b", "analytic.p", "kinematic_case", "slip_until_event", "hybrid.run"])
def test_random_api_values_never_give_an_exception_other_than_valueerror_or_a_nan(name):
    functions, ok = _api_functions()
    fn, params = functions[name]
    rng = np.random.default_rng([2026, len(name)])
    answered = 0
    for _ in range(40):
        param = str(rng.choice(params))
        value = _draw(rng)
        try:
            result = fn({**ok, param: value})
        except ValueError as e:
            assert audit.judge_message(str(e), param), f"{name}({param}={value!r}): {e}"
            continue
        answered += 1
        assert _finite_numbers(result), f"{name}({param}={value!r}) returned a non-finite number: {result!r}"
    assert answered >= 1, "every draw was refused: the property test tested nothing"
