"""Sweeps at scale: a TOML spec, a resumable Parquet store, and this machine's cores or a Dask cluster.

    from crosscheck import sweeps
    summary = sweeps.run("examples/sweep.toml", "sweeps/demo", workers=2)   # resumes what is already in the directory
    df = sweeps.load("sweeps/demo")                                         # pandas.DataFrame, one row per run

``crosscheck.sweeps.spec`` reads and checks the spec, ``chunk`` computes one
chunk, ``store`` keeps finished chunks safe, ``runner`` runs the missing
ones, ``compare`` compares two stores.
"""

from __future__ import annotations

from pathlib import Path

from crosscheck.sweeps.runner import SweepSummary, run
from crosscheck.sweeps.spec import Spec, SpecError, load_spec, parse_spec
from crosscheck.sweeps.store import Store, StoreError

__all__ = ["run", "load", "load_spec", "parse_spec", "Spec", "SpecError", "Store", "StoreError", "SweepSummary"]


def load(out: str | Path, *, partial: bool = False):
    """The sweep in ``out`` as a ``pandas.DataFrame``, one row per run (inputs, options, outcome name, times, solver health)."""
    return Store(out).load(partial=partial)
