"""Which page each section goes on: the theory's on ``index``, each registered engine's on its own page.

An engine's sections are those ``crosscheck.report.sections.engine_sections`` generates from its ``EngineSpec`` (its
maps, contact quality, onset, IC1/IC2, rounding, convergence, ladder, interventions and its own sections); every other
section stays on the index.  ``Pages`` holds what both writers (HTML and Markdown) show, computed once.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from crosscheck import engines
from crosscheck.report.format import SectionView, badge
from crosscheck.report.sections import engine_sections

__all__ = ["EnginePage", "Pages", "split", "page_state"]


@dataclass
class EnginePage:
    """One engine's page: ``engine_<slug>.html`` and ``engine_<slug>.md``."""

    spec: object  # crosscheck.engines.EngineSpec
    views: list[SectionView]

    @property
    def stem(self) -> str:
        return f"engine_{self.spec.slug}"

    @property
    def title(self) -> str:
        return (self.spec.label or self.spec.name) + (" (rigid)" if self.spec.has("rigid") else "")

    @property
    def slugs(self) -> set[str]:
        return {v.section.slug for v in self.views}


def page_state(views: list[SectionView]) -> str:
    """One badge for a page's sections: the first that is not ok or skipped, else ok."""
    worst = next((v.state for v in views if v.state not in ("ok", "skipped")), "ok")
    return badge(worst)


def split(views: list[SectionView]) -> tuple[list[SectionView], list[EnginePage]]:
    """(the index's sections, one page per registered engine with a rendered section), in report order."""
    owner = {s.slug: spec.name for spec in engines.specs() for s in engine_sections(spec)}
    pages = []
    for spec in engines.specs():
        own = [v for v in views if owner.get(v.section.slug) == spec.name]
        if own:
            pages.append(EnginePage(spec, own))
    return [v for v in views if v.section.slug not in owner], pages


@dataclass
class Pages:
    """Everything the writers show, read from the saved results once.

    ``first``: the first screen's blocks after the bottom line (the figure, the one-row-per-engine table);
    ``bottom``: the bottom line's sentences; ``records``: the engine table's records; ``extra``: the findings' blocks
    (the causes confirmed on every engine).
    """

    index: list[SectionView]
    engines: list[EnginePage]
    prov: dict
    found: list
    records: list[dict]
    bottom: list
    first: list
    extra: list
    summary_rows: list
    failures: list[str]
    known: list = field(default_factory=list)

    def page_of(self, slug: str) -> str:
        """The file stem (``index`` or ``engine_<slug>``) the section ``slug`` is on."""
        return next((p.stem for p in self.engines if slug in p.slugs), "index")
