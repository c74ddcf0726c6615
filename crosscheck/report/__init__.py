"""The report: the paper's figures recomputed and the cross-validation results, in one command.

Two stages (``crosscheck report`` runs both; ``--from-results`` only the second):

1. ``run(out, sections, quick=...)`` computes every section and saves its
   results (CSV/JSON) under ``<out>/data/<section>/``, section by section;
2. ``render(out, sections)`` reads those files alone and writes figures
   (PNG + SVG under ``<out>/figures/``), ``<out>/index.html`` and its Markdown
   twin ``<out>/report.md``.

``SECTIONS`` is every section in report order, the theory's and each
registered engine's (``crosscheck.report.sections.all_sections``, read when
the attribute is).
"""

from __future__ import annotations

from pathlib import Path

from crosscheck.report import sections as _sections
from crosscheck.report.pipeline import lock, run
from crosscheck.report.render import RenderSummary, render
from crosscheck.report.section import Section
from crosscheck.report.sections import section_by_slug

__all__ = ["SECTIONS", "Section", "RenderSummary", "run", "render", "lock", "default_out", "section_by_slug"]


def default_out(quick: bool) -> Path:
    """``reports/latest`` (git-ignored), for the quick and the full report alike: never over the committed
    reference ``reports/quick``, which is written only when asked for (``--out reports/quick``)."""
    return Path("reports") / "latest"


def __getattr__(name: str):
    if name == "SECTIONS":
        return _sections.all_sections()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
