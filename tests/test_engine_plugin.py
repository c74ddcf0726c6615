"""An engine from another distribution: ``examples/engine_plugin`` installed as pip installs it, then used by name.

``pip install --target`` puts the example (and a deliberately broken plugin written here) into a temporary folder;
every command then runs in a fresh process with that folder on ``PYTHONPATH``, so the registry finds them through
``importlib.metadata.entry_points`` exactly as it finds a plugin installed into an environment.  One install serves
the module (~20 s: two wheels built); the quick report of the plugin alone is the slow test (~30-60 s).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "engine_plugin"

#: A distribution whose entry points fail each in its own way, and one engine whose library is not installed.
BROKEN_PYPROJECT = """\
[build-system]
requires = ["setuptools>=61", "wheel"]
build-backend = "setuptools.build_meta"

[project]
name = "crosscheck-broken-plugin"
version = "0.1.0"

[project.entry-points."crosscheck.engines"]
broken_import = "broken_plugin.missing:ENGINES"
wrong_type = "broken_plugin:NOT_A_SPEC"
taken_name = "broken_plugin:TAKEN"
missing_lib = "broken_plugin:MISSING"
"""

BROKEN_MODULE = """\
from crosscheck.engines.spec import EngineSpec

NOT_A_SPEC = 42
TAKEN = (EngineSpec(name="mujoco", engine="broken_plugin:nowhere"),)
from crosscheck.engines.spec import ReportPlan
MISSING = EngineSpec(name="missing_lib", engine="broken_plugin:nowhere", libraries=("crosscheck-no-such-library",),
                     tags={"rigid", "time_stepping"}, report=ReportPlan(maps={"quick": {}, "full": {}}))
"""

ORIGIN = "crosscheck-broken-plugin 0.1.0"


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The temporary folder both distributions are installed into (no network, no build isolation)."""
    tmp = tmp_path_factory.mktemp("plugins")
    broken = tmp / "broken"
    (broken / "broken_plugin").mkdir(parents=True)
    (broken / "pyproject.toml").write_text(BROKEN_PYPROJECT)
    (broken / "broken_plugin" / "__init__.py").write_text(BROKEN_MODULE)
    target = tmp / "site"
    cmd = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation", "--no-index"]
    # built from a copy: an in-tree build would leave build/ and *.egg-info in the checkout
    import shutil

    example = shutil.copytree(EXAMPLE, tmp / "example", ignore=shutil.ignore_patterns("build", "*.egg-info"))
    subprocess.run([*cmd, "--target", str(target), str(example), str(broken)], check=True, cwd=tmp)
    return target


def crosscheck(site: Path, *args: str, timeout: float = 600) -> subprocess.CompletedProcess:
    """``crosscheck ARGS`` in a fresh process that has ``site`` on its path."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    code = "import sys; from crosscheck.cli import main; raise SystemExit(main(sys.argv[1:]))"
    return subprocess.run(
        [sys.executable, "-c", code, *args], env=env, capture_output=True, text=True, timeout=timeout, cwd=site
    )


def test_engines_lists_the_plugin_with_its_origin_and_each_broken_plugin_in_one_line(site):
    out = crosscheck(site, "engines", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    by = {e["name"]: e for e in data["engines"]}
    rod = by["numpy_rod"]
    assert rod["origin"] == "crosscheck-numpy-rod 0.1.0" and rod["label"] == "numpy penalty rod"
    assert rod["installed"] and rod["libraries"] == [{"name": "numpy", "version": np.__version__}]
    assert rod["tags"] == ["compliant", "time_stepping"] and rod["studies"] == ["maps", "ladder", "interventions"]
    missing = by["missing_lib"]
    assert (
        missing["libraries"] == [{"name": "crosscheck-no-such-library", "version": None}] and not missing["installed"]
    )
    assert missing["install"] == "python3 -m pip install crosscheck-no-such-library"
    assert by["mujoco"]["origin"] == "built in"  # the plugin that took its name did not replace it
    assert data["broken"] == [
        f"plugin 'broken_import' ({ORIGIN}, broken_plugin.missing:ENGINES) is broken: ModuleNotFoundError: "
        "No module named 'broken_plugin.missing'",
        f"plugin 'taken_name' ({ORIGIN}, broken_plugin:TAKEN) is broken: ValueError: engine name 'mujoco' is already taken",
        f"plugin 'wrong_type' ({ORIGIN}, broken_plugin:NOT_A_SPEC) is broken: TypeError: it must name an EngineSpec or "
        "a tuple of them; got int",
    ]
    text = crosscheck(site, "engines")
    assert text.returncode == 0 and all(line in text.stdout.splitlines() for line in data["broken"])
    assert "crosscheck-no-such-library not installed  (install: python3 -m pip install crosscheck-no-such-library)" in (
        text.stdout
    )


def test_simulate_runs_the_plugin_and_a_broken_or_missing_engine_exits_2_in_one_line(site):
    args = ["simulate", "--theta", "1.0", "--varphi", "-1.9", "--Theta", "0", "--Psi", "0", "--eta", "1", "--mu", "0.5"]
    out = crosscheck(site, *args, "--engine", "numpy_rod", "--horizon", "0.5", "--json")
    assert out.returncode == 0, out.stderr
    run = json.loads(out.stdout)
    assert run["engine"] == "numpy_rod" and run["outcome"] == "SLIP"  # b < 0 < p: the theory slips
    for name, line in (
        (
            "broken_import",
            "plugin 'broken_import' (crosscheck-broken-plugin 0.1.0, broken_plugin.missing:ENGINES) is "
            "broken: ModuleNotFoundError: No module named 'broken_plugin.missing'",
        ),
        (
            "missing_lib",
            "engine 'missing_lib' needs crosscheck-no-such-library, which is not installed: "
            "python3 -m pip install crosscheck-no-such-library",
        ),
    ):
        bad = crosscheck(site, *args, "--engine", name)
        assert bad.returncode == 2 and bad.stderr == f"crosscheck: error: {line}\n" and bad.stdout == ""
        rep = crosscheck(site, "report", "--quick", "--engines", name, "--out", str(site.parent / "none"))
        assert rep.returncode == 2 and rep.stderr == f"crosscheck: error: {line}\n"


def test_the_engine_contract_holds_for_the_installed_plugin(site):
    """tests/test_engine_contract.py, parametrised over every engine the registry finds, finds the plugin too."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "-k",
            "numpy_rod",
            str(ROOT / "tests" / "test_engine_contract.py"),
        ],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
        cwd=ROOT,
    )
    assert out.returncode == 0, out.stdout[-3000:]
    assert "4 passed" in out.stdout, out.stdout[-3000:]


def test_a_quick_report_of_the_plugin_alone_holds_its_sections_and_no_other_engines(site):
    out_dir = site.parent / "report"
    out = crosscheck(site, "report", "--quick", "--engines", "numpy_rod", "--out", str(out_dir), "--no-progress")
    assert out.returncode == 0, out.stdout + out.stderr
    data = out_dir / "data"
    assert (data / "numpy_rod_maps" / "maps.json").is_file() and (data / "numpy_rod_ladder").is_dir()
    assert not any(p.name.startswith(("mujoco", "drake", "bullet", "rigid")) for p in data.iterdir())
    maps = json.loads((data / "numpy_rod_maps" / "maps.json").read_text())
    runs = [mp["runs"][0] for mp in maps]
    assert all(r["engine"] == "numpy_rod" and r["n_rated"] > 0 for r in runs)
    assert "numpy penalty rod" in (out_dir / "report.md").read_text()


def test_a_full_report_leaves_out_an_engine_whose_library_is_missing_with_one_line(site):
    """The full report's section list (what ``crosscheck report`` runs) has none of missing_lib's sections, and the one
    line it prints for it; the plugin that is installed keeps its sections."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    code = (
        "import json; from crosscheck.report.sections import all_sections, skipped_engines; "
        "print(json.dumps({'slugs': [s.slug for s in all_sections()], 'skipped': skipped_engines()}))"
    )
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300, cwd=site)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert got["skipped"] == [
        "skipped missing_lib's sections: engine 'missing_lib' needs crosscheck-no-such-library, which is not "
        "installed: python3 -m pip install crosscheck-no-such-library"
    ]
    assert "numpy_rod_maps" in got["slugs"] and not any(s.startswith("missing_lib") for s in got["slugs"])
