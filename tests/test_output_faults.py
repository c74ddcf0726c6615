"""Where the output goes wrong after the work is done: a full standard output, a terminal that shows only ASCII.

Real processes with a real ``/dev/full`` and a real ``PYTHONIOENCODING=ascii``: one line and the work kept, never a
traceback.  Also the one JSON rule of the commands (no NaN token) and a MuJoCo rod a centimetre long.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

from crosscheck import Outcome, Rod, SlipState, engines
from crosscheck.cli.json_text import json_text
from crosscheck.sweeps import load

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def _crosscheck(argv, **kw):
    return subprocess.run([sys.executable, "-m", "crosscheck", *argv], text=True, env=kw.pop("env", ENV), **kw)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full on this system")
@pytest.mark.parametrize(
    "argv", [["critical", "--mu", "0.83", "--alpha", "5"], ["gb", "--mu", "2.3", "--json"]], ids=str
)
def test_a_full_standard_output_is_one_line(argv):
    with open("/dev/full", "w") as full:
        r = _crosscheck(argv, stdout=full, stderr=subprocess.PIPE, timeout=120)
    assert r.returncode == 1
    assert r.stderr == "crosscheck: error: standard output cannot be written: No space left on device\n"


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full on this system")
def test_a_sweep_into_a_full_standard_output_keeps_its_store(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(
        '[sweep]\nengine = "analytic"\nhorizon = 0.2\nchunk = 2\n[states]\ntheta = [0.6, 1.2, 1.4]\n'
        "varphi = -2.1\nTheta = 0.3\nPsi = 0.1\neta = 0.7\n[parameters]\nmu = 0.25\n"
    )
    with open("/dev/full", "w") as full:
        r = _crosscheck(
            ["sweep", str(spec), "--out", str(tmp_path / "o"), "--workers", "1"],
            stdout=full,
            stderr=subprocess.PIPE,
            timeout=120,
        )
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert r.stderr.splitlines()[-1] == "crosscheck: error: standard output cannot be written: No space left on device"
    assert len(load(tmp_path / "o")) == 3  # the work was done and saved before the summary line failed


def test_a_non_ascii_path_under_an_ascii_terminal_is_written_and_shown_escaped(tmp_path):
    target = tmp_path / "r\u00e9sultats" / "\u0440\u043e\u0434.csv"
    r = _crosscheck(
        [
            "simulate",
            "--engine",
            "pinocchio",
            "--theta",
            "0.92",
            "--varphi",
            "-1.2",
            "--Theta",
            "0.1",
            "--Psi",
            "0.4",
            "--eta",
            "0.8",
            "--mu",
            "0.35",
            "--horizon",
            "0.03",
            "--csv",
            str(target),
        ],
        capture_output=True,
        env={**ENV, "PYTHONIOENCODING": "ascii"},
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    assert target.read_text().startswith("t,")
    assert r.stdout.isascii() and "r\\xe9sultats" in r.stdout


def test_json_text_writes_no_nan_token():
    text = json_text({"event_time": math.nan, "rungs": [{"t": math.inf}, {"t": 0.5}], "n": 3})
    assert json.loads(text) == {"event_time": None, "rungs": [{"t": None}, {"t": 0.5}], "n": 3}
    assert "NaN" not in text and "Infinity" not in text


def test_mujoco_runs_a_centimetre_rod_and_refuses_one_below_its_minimum_mass():
    state = SlipState(theta=0.88, varphi=-1.1, Theta=0.25, Psi=-0.3, eta=0.9)
    small = engines.get("mujoco").simulate(Rod.uniform(0.5, 0.01), state, 0.4, horizon=0.1)
    scaled = engines.get("mujoco").simulate(Rod.scaled(3.0), state, 0.4, horizon=0.1)
    assert small.outcome is not Outcome.DIVERGED
    assert small.outcome == scaled.outcome
    with pytest.raises(ValueError, match=r"^rod must have a mass \[kg\] and an inertia I0 \[kg m\^2\] above 1e-14"):
        engines.get("mujoco").simulate(Rod.uniform(3e-15, 0.3), state, 0.4, horizon=0.1)
