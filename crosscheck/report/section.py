"""What a report section is: a run function that saves results and a render function that reads them.

A section is one topic of the report (one paper figure, or one comparison).
It declares its parameters for the quick and the full report, a ``run`` that
computes and saves its results through a ``SectionStore`` (never figures), and
a ``render`` that turns the saved results into blocks: figures, tables, text.
``render`` must not compute physics: it reads the saved files only, so that
``crosscheck report --from-results`` rebuilds a report without re-running.

Checks.  A section may record checks (``RunContext.check``): a named
comparison with its measured value, the allowance, and whether it passed.
The report lists every failed check at the top; a known discrepancy (a
misprint of the paper, documented in ``crosscheck.theory.paper``) is shown as such
and does not fail the report.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from crosscheck.report.store import SectionStore

__all__ = [
    "Section",
    "RunContext",
    "RenderContext",
    "Block",
    "Figure",
    "Table",
    "Text",
    "Preformatted",
    "section_rng",
    "SkipSection",
]


class SkipSection(Exception):
    """Raised by a section's ``run`` that does not apply to this report (e.g. full report only).

    The section is shown as skipped with the message, which must say why and
    how to get it; a skip is not a failure.
    """


# ------------------------------------------------------------------ blocks ---


@dataclass
class Figure:
    """A saved figure: ``<out>/<stem>.png`` and ``.svg``, with the data files behind it."""

    stem: str  # relative to the report directory, no extension
    caption: str
    data: list[str]  # paths relative to the report directory


@dataclass
class Table:
    """A table shown in the report, with the data file it was read from."""

    caption: str
    header: list[str]
    rows: list[list[str]]
    data: list[str]
    row_class: list[str] = field(default_factory=list)  # per row: "", "fail", "known", "ok"
    notes: list[str] = field(default_factory=list)  # one-line footnotes under the table (column definitions)


@dataclass
class Text:
    """A paragraph (plain text; ``code`` spans in backticks are kept in both formats)."""

    text: str


@dataclass
class Preformatted:
    """Monospaced text (an error message, a command's table output)."""

    text: str
    title: str = ""


Block = Figure | Table | Text | Preformatted


# ---------------------------------------------------------------- contexts ---


def section_rng(seed: int, slug: str) -> np.random.Generator:
    """The generator of one section: independent of the other sections and of their order."""
    return np.random.default_rng([seed, zlib.crc32(slug.encode())])


def _no_progress(iterable, **_):
    return iterable


@dataclass
class RunContext:
    """What a section's ``run`` gets.

    Attributes:
      params: the section's parameters (quick or full), already recorded in the provenance.
      quick: True for the quick report.
      rng: the section's seeded generator.
      store: where to save results; save each piece as soon as it is computed.
      progress: ``progress(iterable, desc=..., total=...)``: a tqdm bar (or the bare iterable).
      show_progress: whether bars are shown (for engines' own ``progress=`` flags).
      sweeps: keyword arguments (store, scheduler, workers) for the engine
        sweeps of ``crosscheck.studies.agreement.agreement_study``: a
        resumable store per section (``crosscheck.sweeps``); None runs the
        engines directly.
      seed: the report's seed (``rng`` is the section's own stream of it; a
        computation several sections share seeds its own stream from it).
    """

    slug: str
    params: dict
    quick: bool
    rng: np.random.Generator
    store: SectionStore
    progress: Callable[..., Iterable] = _no_progress
    show_progress: bool = False
    sweeps: dict | None = None
    seed: int = 0
    checks: list[dict] = field(default_factory=list)

    def finished(self, slug: str) -> tuple[dict, SectionStore] | None:
        """(status, store) of the section ``slug`` of this report if it finished ok and its saved files are intact
        (a section whose run reads another's results, ``Section.after``); None otherwise."""
        from crosscheck.report.store import DamagedResults, verified_status

        out = self.store.root.parent.parent
        try:
            status = verified_status(out, slug)
        except (DamagedResults, OSError, ValueError):
            return None
        if not status or status.get("status") != "ok":
            return None
        return status, SectionStore(out / "data" / slug)

    def shared(self, kind: str, name: str, key: dict, suffix: str) -> tuple[Path | None, str]:
        """(file, digest): where sections that compute the same thing from ``key`` keep it once for all of them, under the
        report's sweeps directory (``<out>/sweeps/<kind>/<name>-<digest><suffix>``, the digest a sha256 of ``key``), and
        that digest; the file is None when the section runs its engines without a sweeps store.

        Such a file is a cache, as the sweeps' chunks are: what reads it checks it and computes again what it cannot
        trust (``crosscheck.studies.analytic_events``), and ``--fresh`` deletes it with the sweeps."""
        import hashlib
        import json

        digest = hashlib.sha256(json.dumps(key, sort_keys=True, default=str).encode()).hexdigest()[:16]
        if self.sweeps is None:
            return None, digest
        return Path(self.sweeps["store"]).parent / kind / f"{name}-{digest}{suffix}", digest

    def check(
        self,
        name: str,
        passed: bool,
        *,
        value: Any = None,
        allowance: Any = None,
        detail: str = "",
        known: str = "",
        guard: bool = False,
    ) -> bool:
        """Record a check and save the list at once (a later failure keeps it).

        ``guard``: the allowance is a regression guard (set from a measured spread), not a physical
        bound; the report labels it so (``crosscheck.tolerances.Tolerance.guard``)."""
        self.checks.append(
            {
                "name": name,
                "passed": bool(passed),
                "value": value,
                "allowance": allowance,
                "detail": detail,
                "known_discrepancy": known,
                "kind": "regression guard" if guard else "physics",
            }
        )
        self.store.write_json("checks", self.checks)
        return bool(passed)


@dataclass
class RenderContext:
    """What a section's ``render`` gets: the saved results and where figures go."""

    slug: str
    params: dict
    store: SectionStore
    out: Path  # the report directory

    def data(self, *names: str) -> list[str]:
        """Paths (relative to the report) of saved files, for a figure's or table's data links."""
        return [str(self.store.path(n).relative_to(self.out)) for n in names]

    def figure(self, name: str, fig, caption: str, data: Sequence[str]) -> Figure:
        """Save ``fig`` as PNG and SVG under ``figures/<slug>/`` and close it."""
        from crosscheck.report.plotting import save_figure

        stem = Path("figures") / self.slug / name
        save_figure(fig, self.out / stem)
        return Figure(stem=str(stem), caption=caption, data=self.data(*data))


# ---------------------------------------------------------------- sections ---


@dataclass(frozen=True)
class Section:
    """One topic of the report.

    Attributes:
      slug: directory name and HTML anchor.
      title: heading.
      paper: the paper's figures/equations this section recomputes ("" if none).
      params: ``params(quick) -> dict`` of every parameter (grids, mu, alpha, horizons ...).
      run: ``run(ctx: RunContext) -> None``; saves results through ``ctx.store``.
      render: ``render(ctx: RenderContext) -> list[Block]``; reads saved results only.
      requires: modules of the project the run imports (listed when the run fails on them).
      finding: ``finding(data_dir) -> list[Finding]``, the section's lines in the report's findings, read
        from its saved results (``crosscheck.report.findings``); None: the generic lines only.
      after: slugs of the sections whose saved results this one's run reads; it starts once they have
        finished (the report runs the others at the same time, ``crosscheck.report.pipeline``).
    """

    slug: str
    title: str
    paper: str
    params: Callable[[bool], dict]
    run: Callable[[RunContext], None]
    render: Callable[[RenderContext], list]
    requires: tuple[str, ...] = ()
    finding: Callable[[Path], list] | None = None
    after: tuple[str, ...] = ()
