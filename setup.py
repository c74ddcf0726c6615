"""Build hook: record the checkout's git revision in the built package (``crosscheck/_build.py``).

Everything else about the package is in ``pyproject.toml``.
"""

import importlib.util
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent


def _build_module():
    # loaded from its path: the package's own __init__ imports numpy, absent from the build environment
    spec = importlib.util.spec_from_file_location("crosscheck_build", ROOT / "crosscheck" / "_build.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class BuildPyWithRevision(build_py):
    """``build_py`` that also writes ``crosscheck/_build_info.json`` (revision, clean or dirty, build date)."""

    def run(self):
        super().run()
        if not self.dry_run:
            _build_module().write_build_info(Path(self.build_lib) / "crosscheck", ROOT)


setup(cmdclass={"build_py": BuildPyWithRevision})
