"""What many test files share: the paper's uniform rod and seeded random slipping states."""

from __future__ import annotations

import os
import platform
import sys

# OpenBLAS picks its kernel by the CPU (Haswell, SkylakeX, ...) and the kernels round differently: scipy's
# Runge-Kutta stages and the rigid stepper's PGS counts after a jam follow them (crosscheck.report.provenance names the
# kernel).  The committed reference report reports/quick is made on the Haswell kernel, which every x86-64 CPU with
# AVX2 runs, so the suite asks for it before numpy loads and compares that report's numbers on any such machine.
if platform.machine() in ("x86_64", "AMD64"):
    assert "numpy" not in sys.modules, "numpy was imported before tests/conftest.py could choose OpenBLAS's kernel"
    os.environ["OPENBLAS_CORETYPE"] = "Haswell"

import math
import subprocess
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest

from crosscheck.rod import Rod
from crosscheck.state import SlipState

#: Warp's kernel cache filled once before the workers start (``pytest_configure``): a fresh machine compiles Newton's
#: kernels (about a minute of CPU per solver), and the suite's workers would otherwise each compile the same ones.  A
#: marker file in Warp's cache names the versions it was filled for (a cleared cache clears the marker with it).
#: ``check`` exits 3 when the cache is not filled, ``load NAME...`` preloads those engines, ``mark`` writes the marker.
_WARM_WARP = """
import json, pathlib, sys
from importlib import metadata
from crosscheck import engines
if not [s for s in engines.specs() if s.name.startswith("newton_") and not s.unavailable()]:
    sys.exit(0)
import warp
from crosscheck.engines.newton.options import init_warp
init_warp()
versions = {d: metadata.version(d) for d in ("newton", "warp-lang", "mujoco-warp", "crosscheck")}
marker = pathlib.Path(warp.config.kernel_cache_dir) / "crosscheck-warm.json"
if sys.argv[1] == "check":
    sys.exit(0 if marker.is_file() and json.loads(marker.read_text()) == versions else 3)
if sys.argv[1] == "mark":
    marker.write_text(json.dumps(versions))
for name in sys.argv[2:]:
    engines.get(name).preload()
"""

#: The Newton engines each warming process preloads, the two processes side by side: MuJoCo Warp's kernels, then
#: Newton's own solvers'.
_WARM_GROUPS = (("newton_mujoco",), ("newton_xpbd", "newton_featherstone", "newton_semi_implicit"))


def pytest_configure(config):
    # in the process that starts pytest-xdist's workers (or the only process): once, before any test
    if hasattr(config, "workerinput"):
        return
    warm = [sys.executable, "-c", _WARM_WARP]
    if subprocess.run([*warm, "check"]).returncode != 3:
        return
    procs = [subprocess.Popen([*warm, "load", *group]) for group in _WARM_GROUPS]
    if any(p.wait() != 0 for p in procs):
        raise pytest.UsageError("filling Warp's kernel cache failed (see above)")
    subprocess.run([*warm, "mark"], check=True)


#: alpha of a uniform rod (I0 = m l^2 / 3), the paper's running example.
ALPHA = 3.0


def random_slip_states(rng: np.random.Generator, n: int) -> list[SlipState]:
    """``n`` slipping states drawn from ``rng``: theta in (0.05, 1.5), varphi in (-3.1, 0], Theta ~ N(0, 1), Psi ~ N(0, 4),
    eta in (0, 2), psi in (-pi, pi): every quadrant of the slip direction, both signs of the rates."""
    return [
        SlipState(
            theta=rng.uniform(0.05, 1.5),
            varphi=-rng.uniform(0.0, 3.1),
            Theta=rng.normal(),
            Psi=2 * rng.normal(),
            eta=rng.uniform(0, 2),
            psi=rng.uniform(-math.pi, math.pi),
        )
        for _ in range(n)
    ]


@pytest.fixture
def rod() -> Rod:
    """The scaled uniform rod (m = l = g = 1, alpha = 3)."""
    return Rod.scaled(ALPHA)


@contextmanager
def tmpfs(path: Path, options: str = "size=1m"):
    """A real tmpfs mounted at ``path`` (created) for the ``with`` block: a small or read-only file system for the
    full-disk and unwritable-directory tests (the test is skipped where this process cannot mount one)."""
    path.mkdir(parents=True, exist_ok=True)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(path)], capture_output=True).returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    try:
        yield path
    finally:
        subprocess.run(["umount", str(path)], check=True)


def small(engine: str = "mujoco", horizon: float = 0.2, chunk: int = 4, **options) -> str:
    """A small sweep spec (TOML text): 3 x 2 x 2 planar starts at two mu (24 runs) of ``engine``, with ``options``."""
    opts = "".join(f"{k} = {v!r}\n" for k, v in options.items())
    return f"""
[sweep]
engine = "{engine}"
horizon = {horizon}
seed = 0
chunk = {chunk}
[states]
theta = {{start = 0.5, stop = 1.1, num = 3}}
varphi = -1.5707963267948966
Theta = [0.0, 0.6]
Psi = [0.0, 1.5]
eta = 1.0
[parameters]
mu = [0.5, 1.4]
alpha = 3.0
""" + (f"[options]\n{opts}" if opts else "")
