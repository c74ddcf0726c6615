"""Where a report's numbers come from: versions, git revision, date, machine, parameters, tolerances, seed.

Collected once per run stage and saved as ``<out>/data/provenance.json``; the
render stage prints it as the report's provenance block.  Each section's
status also keeps the git revision and date of the run that produced it, so a
report assembled from runs of different revisions says so.
"""

from __future__ import annotations

import datetime as _dt
import importlib
import importlib.util
import os
import platform
import subprocess
import sys
from pathlib import Path

from crosscheck import engines, tolerances, versions

__all__ = [
    "PACKAGES",
    "collect",
    "git_revision",
    "package_versions",
    "all_tolerances",
    "machine",
    "provenance_rows",
    "revision_text",
    "seconds_text",
]

#: Distributions whose versions every report records besides the engines' libraries (PyPI names).
PACKAGES = ("crosscheck", "numpy", "scipy", "matplotlib", "tqdm")


def package_versions(packages=None) -> dict[str, str | None]:
    """Installed version of each distribution, None when it is not installed (``crosscheck.versions``; default:
    ``PACKAGES`` and every registered engine's libraries)."""
    if packages is None:
        packages = PACKAGES[:1] + engines.libraries() + PACKAGES[1:]
    return versions.package_versions(packages)


def _repo_root() -> Path:
    # The package is installed editable from the repository; its parent is the work tree.
    return Path(__file__).resolve().parents[2]


def git_revision(cwd: Path | None = None) -> dict[str, object]:
    """``{"revision": sha or None, "dirty": bool or None, "describe": str}`` of the source tree.

    ``dirty`` is True when tracked files differ from the revision (untracked
    files are ignored: generated reports live in the tree).  For the package
    itself (``cwd`` None) installed outside a checkout, the revision recorded
    when it was built (``crosscheck._build``), marked ``"source": "build"``
    with the build date as ``"built"``.
    """
    installed = cwd is None
    cwd = cwd or _repo_root()
    if not ((Path(cwd) / "pyproject.toml").is_file() and (Path(cwd) / "crosscheck").is_dir()):
        # an installed package (site-packages), even one inside some other work tree: the revision its build recorded
        # (crosscheck._build, written by setup.py's build_py from the checkout it was built from), else none
        from crosscheck._build import build_info

        built = build_info() if installed else None
        if built is not None:
            return {
                "revision": built["revision"],
                "dirty": built.get("dirty"),
                "describe": built.get("describe", built["revision"][:12]),
                "source": "build",
                "built": built.get("built"),
            }
        return {"revision": None, "dirty": None, "describe": "not a git checkout"}

    def git(*args: str) -> str | None:
        try:
            r = subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True, timeout=10)
        except (OSError, subprocess.SubprocessError):
            return None
        return r.stdout.strip() if r.returncode == 0 else None

    rev = git("rev-parse", "HEAD")
    if rev is None:
        return {"revision": None, "dirty": None, "describe": "not a git checkout"}
    status = git("status", "--porcelain", "--untracked-files=no")
    dirty = None if status is None else bool(status)
    return {"revision": rev, "dirty": dirty, "describe": rev[:12] + ("-dirty" if dirty else "")}


def machine() -> dict[str, object]:
    """Platform, processor, the CPU count the run could use, and the BLAS kernel numpy runs.

    The kernel matters to the numbers: scipy's Runge-Kutta steps sum their stages through BLAS, and OpenBLAS picks its
    kernel by processor or by ``OPENBLAS_CORETYPE``; Haswell's and SkylakeX's round differently (the analytic IC1 jam
    time moves from 0.000416723556 to 0.000416723551, and the rigid engine's PGS iterations after a jam with it).
    """
    try:
        usable = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        usable = os.cpu_count()
    return {
        "platform": platform.platform(),
        "machine": platform.machine(),
        "processor": platform.processor() or _cpu_model(),
        "cpu_count": os.cpu_count(),
        "usable_cpus": usable,
        "python_implementation": platform.python_implementation(),
        "python_executable": sys.executable,
        "blas": _blas(),
    }


def _blas() -> str:
    """numpy's BLAS ("scipy-openblas 0.3.31.188.0") with the kernel it runs ("kernel SkylakeX"), and OPENBLAS_CORETYPE
    when it is set.  The kernel is OpenBLAS's own answer (``*_get_corename``, from the library numpy loaded): the
    build's configuration string names the build's target, not the kernel chosen at run time."""
    import ctypes
    import glob

    import numpy as np

    try:
        info = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
        text = f"{info.get('name')} {info.get('version')}"
    except (KeyError, TypeError, AttributeError):
        text = "unknown BLAS"
    try:
        (path,) = glob.glob(str(Path(np.__file__).parent.parent / "numpy.libs" / "lib*openblas*"))[:1]
        lib = ctypes.CDLL(path)
        name = next(
            getattr(lib, f)
            for f in ("scipy_openblas_get_corename64_", "openblas_get_corename64_", "openblas_get_corename")
            if hasattr(lib, f)
        )
        name.restype = ctypes.c_char_p
        text += f", kernel {name().decode()}"
    except (ValueError, OSError, StopIteration, AttributeError):
        text += ", kernel unknown"
    core = os.environ.get("OPENBLAS_CORETYPE")
    return text + (f" (OPENBLAS_CORETYPE={core})" if core else "")


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return ""


def now() -> str:
    """Current UTC time, ISO 8601 to the second."""
    return _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()


def collect(*, quick: bool, seed: int, parameters: dict, argv: list[str] | None = None) -> dict:
    """The full provenance record of a run stage.

    Args:
      quick: whether the run used the quick (small-grid) settings.
      seed: the report's master seed (each section derives its own generator from it).
      parameters: ``{section slug: {parameter: value}}``, every parameter of every section.
      argv: the command line, for the record.
    """
    return {
        "date": now(),
        "command": argv,
        "quick": quick,
        "seed": seed,
        "versions": package_versions(),
        "git": git_revision(),
        "machine": machine(),
        "parameters": parameters,
        "tolerances": all_tolerances(),
    }


def all_tolerances() -> dict[str, dict]:
    """Every named tolerance: ``crosscheck.tolerances``' and each registered engine's (the ``tolerances`` module of
    the package that holds its ``module``), as the registry lists them."""
    found = []
    for spec in engines.specs():
        package = (spec.module or "").rpartition(".")[0]
        try:
            has = bool(package) and importlib.util.find_spec(f"{package}.tolerances") is not None
        except ModuleNotFoundError:  # its module is not in a package
            has = False
        if has and f"{package}.tolerances" not in found:
            found.append(f"{package}.tolerances")
    return tolerances.all_tolerances([importlib.import_module(m) for m in found])


def seconds_text(s) -> str:
    """A duration for the report: "12.3 s", or "" when not known."""
    return "" if s is None else f"{s:.1f} s"


def revision_text(git: dict, prov: dict) -> str:
    """The source revision as a reader can use it: the commit (clean or dirty), or the installed version outside a checkout."""
    if not git.get("revision"):
        return f"installed package, version {prov.get('versions', {}).get('crosscheck', '?')} (not a git checkout)"
    state = "dirty" if git.get("dirty") else "clean" if git.get("dirty") is False else "clean or dirty: unknown"
    if git.get("source") == "build":
        return f"{git['revision']} ({state}; installed package, revision recorded when it was built on {git.get('built') or '?'})"
    return f"{git['revision']} ({state})"


def provenance_rows(prov: dict) -> list[list[str]]:
    """The provenance block of a report: run and render revisions, command, mode, seed, versions, machine, run time."""
    git = prov.get("git", {})
    m = prov.get("machine", {})
    rows = [
        ["date (UTC)", prov.get("date", "")],
        ["git revision", revision_text(git, prov)],
        ["command", " ".join(prov.get("command") or [])],
        ["mode", "quick" if prov.get("quick") else "full"],
        ["seed", str(prov.get("seed"))],
    ]
    rows += [[f"version: {k}", str(v)] for k, v in prov.get("versions", {}).items()]
    rendered = prov.get("rendered", {})
    if rendered:
        rows += [
            ["rendered (UTC)", rendered.get("date", "")],
            ["render git revision", revision_text(rendered.get("git", {}), prov)],
        ]
    rows += [
        ["machine: platform", str(m.get("platform"))],
        ["machine: processor", str(m.get("processor"))],
        ["machine: CPUs (usable)", f"{m.get('cpu_count')} ({m.get('usable_cpus')})"],
        ["machine: BLAS", str(m.get("blas", "-"))],
        ["run time of the run stage", seconds_text(prov.get("seconds"))],
    ]
    # what each engine says of its runs (Newton: CPU seconds of each solver's kernel loads, apart from its steps)
    rows += [
        [f"{name}: {k}", f"{v:.3g}" if isinstance(v, float) else str(v)]
        for name, d in prov.get("engines", {}).items()
        for k, v in d.items()
    ]
    return rows
