"""An engine whose library is missing: Newton's three engines in a fresh process that cannot see Newton, Warp or
MuJoCo Warp (their distributions report "not found", their imports fail), as on a machine without the extra
``crosscheck[newton]``.  They are listed as not installed with the pip line, a run of one exits 2 in one line naming
the extra, and the report skips their sections, one line each (the engine plugin test does the same for a plugin's
missing library)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The distributions and modules of the extra ``crosscheck[newton]``.
HIDDEN_DISTRIBUTIONS = ("newton", "warp-lang", "mujoco-warp")
HIDDEN_MODULES = ("newton", "warp", "mujoco_warp")

#: ``crosscheck ARGS`` where the extra is not there: its distributions are not found and importing one of its modules
#: raises ImportError (``sys.modules[name] = None``), so listing the engines must import none of them.
WITHOUT_NEWTON = f"""
import importlib.metadata as md, sys
_version = md.version
def version(name):
    if name in {HIDDEN_DISTRIBUTIONS!r}:
        raise md.PackageNotFoundError(name)
    return _version(name)
md.version = version
for name in {HIDDEN_MODULES!r}:
    sys.modules[name] = None
from crosscheck.cli import main
raise SystemExit(main(sys.argv[1:]))
"""

NAMES = {
    "newton_mujoco": "Newton MuJoCo Warp",
    "newton_xpbd": "Newton XPBD",
    "newton_featherstone": "Newton Featherstone",
    "newton_semi_implicit": "Newton semi-implicit",
}


def _missing(name: str) -> str:
    libs = "newton, warp-lang, mujoco-warp" if name == "newton_mujoco" else "newton, warp-lang"
    return f'engine {name!r} needs {libs}, which is not installed: python3 -m pip install "crosscheck[newton]"'


def crosscheck(cwd: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-c", WITHOUT_NEWTON, *args], env=env, capture_output=True, text=True, timeout=600, cwd=cwd
    )


def test_newton_s_engines_without_newton_are_listed_as_not_installed_with_the_pip_line(tmp_path):
    out = crosscheck(tmp_path, "engines", "--json")
    assert out.returncode == 0, out.stderr
    by = {e["name"]: e for e in json.loads(out.stdout)["engines"]}
    for name in NAMES:
        assert not by[name]["installed"] and by[name]["install"] == 'python3 -m pip install "crosscheck[newton]"'
        assert {lib["name"]: lib["version"] for lib in by[name]["libraries"]} == {
            lib: None for lib in HIDDEN_DISTRIBUTIONS[: 3 if name == "newton_mujoco" else 2]
        }
    assert by["mujoco"]["installed"]  # the others are untouched


def test_a_run_of_a_newton_engine_without_newton_exits_2_in_one_line_naming_the_extra(tmp_path):
    args = ["simulate", "--theta", "1.0", "--varphi", "-1.9", "--Theta", "0", "--Psi", "0", "--eta", "1", "--mu", "0.5"]
    bad = crosscheck(tmp_path, *args, "--engine", "newton_featherstone")
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr == f"crosscheck: error: {_missing('newton_featherstone')}\n"


def test_the_report_without_newton_skips_its_engines_sections_one_line_each(tmp_path):
    out = crosscheck(tmp_path, "report", "--quick", "--only", "p_region", "--no-progress", "--out", str(tmp_path / "r"))
    assert out.returncode == 0, out.stderr
    skipped = [line for line in out.stdout.splitlines() if line.startswith("skipped ")]
    assert skipped == [f"skipped {label}'s sections: {_missing(name)}" for name, label in NAMES.items()]
    assert not list((tmp_path / "r" / "data").glob("newton_*"))
