"""The render stage: ``index.html``, one page per engine and their Markdown twins, from saved results alone.

Reads ``<out>/data`` (provenance and each section's status and results), asks each section to draw its figures and
tables, and writes the pages (``crosscheck.report.pages``: the theory's sections on the index, each engine's on
``engine_<slug>.html``; their HTML: ``crosscheck.report.html_pages``).  The index opens with the bottom line (``bottom_line``), the first figure (``first_figure``)
and one row per engine (``engine_table``).  Nothing here computes physics.

A section that failed to run is shown with its error, its traceback and the files it saved before failing; a section
whose render fails is shown the same way.  ``RenderSummary.failures`` lists everything that makes the command exit
non-zero: failed or unfinished sections and failed checks that are not known discrepancies of the paper.
"""

from __future__ import annotations

import dataclasses
import json
import multiprocessing
import os
import shutil
import traceback
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from crosscheck.report import plotting  # noqa: F401 - imported once here, not once per forked worker
from crosscheck.report import provenance as _provenance
from crosscheck.report.bottom_line import BOTTOM_LINE, bottom_line
from crosscheck.report.confirmed_overview import confirmed_block
from crosscheck.report.engine_table import (
    engine_records,
    summary_table,
    write_engine_data,
)
from crosscheck.report.findings import RULES, findings
from crosscheck.report.first_figure import figure_block
from crosscheck.report.format import (
    FINDINGS,
    SectionView,
    badge,
    checks_cell,
    unlabelled,
    verdicts,
)
from crosscheck.report.html_pages import engine_provenance, write_engine, write_index, write_stylesheet
from crosscheck.report.markdown import write_md
from crosscheck.report.pages import EnginePage, Pages, page_state, split
from crosscheck.report.pipeline import read_provenance, read_status, verified_status
from crosscheck.report.provenance import seconds_text as _fmt_seconds
from crosscheck.report.references import _REFERENCES, paper_reference, unlabel
from crosscheck.report.section import RenderContext, Section, Text
from crosscheck.report.store import SectionStore
from crosscheck.workers import process_pool

__all__ = ["render", "RenderSummary", "SectionView", "BOTTOM_LINE"]


@dataclass
class RenderSummary:
    html: Path
    markdown: Path
    views: list[SectionView]

    @property
    def failures(self) -> list[str]:
        out = []
        for v in self.views:
            if v.state not in ("ok", "skipped"):
                out.append(f"{v.section.slug}: {v.state}" + (f" ({v.error})" if v.error else ""))
            out += [f"{v.section.slug}: check failed: {c['name']}" for c in v.failed_checks]
        return out


def _view(section: Section, out: Path) -> SectionView:
    store = SectionStore(out / "data" / section.slug)
    status = read_status(out, section.slug)
    view = SectionView(
        section=section, status=status, files=[str(Path("data") / section.slug / f) for f in store.files()]
    )
    if status is None:
        view.error = (
            "no saved results: run `crosscheck report` without --from-results (or with --only " + section.slug + ")"
        )
        return view
    if store.exists("checks.json"):
        view.checks = store.read_json("checks")
    if status["status"] == "running":
        view.error = "the run of this section did not finish (the process was interrupted or killed)"
    elif status["status"] == "error":
        view.error = status.get("error", "error")
        view.traceback = status.get("traceback", "")
    elif status["status"] == "skipped":
        view.blocks = [Text("Skipped: " + status.get("reason", ""))]
        return view
    ctx = RenderContext(slug=section.slug, params=status.get("params", {}), store=store, out=out)
    stale = out / "figures" / section.slug
    if stale.exists():  # figures of an earlier render must not outlive it
        shutil.rmtree(stale)
    try:
        view.blocks = [unlabelled(b) for b in section.render(ctx)]
    except Exception as e:  # noqa: BLE001  (one section's figure must not stop the report)
        if not view.error:  # a failed run explains a failed render: show the run's error only
            view.error = f"render failed: {type(e).__name__}: {e}"
            if isinstance(e, (KeyError, FileNotFoundError)):  # results saved by another version of the section
                view.error += (
                    " (its saved results lack it: saved by another version of crosscheck?); rerun it with "
                    f"`crosscheck report --only {section.slug}`"
                )
            view.traceback = traceback.format_exc()
    return view


# ----------------------------------------------------------------- render ---

# Sections handed to forked render workers (fork shares them: a Section holds functions, which
# need not be picklable then; only the views come back, without their Section).
_JOB: tuple[list[Section], Path] | None = None


def _view_by_index(i: int) -> SectionView:
    sections, out = _JOB
    view = _view(sections[i], out)
    view.section = None
    return view


def _views(
    sections: list[Section], out: Path, *, jobs: int, progress: bool, meanwhile=lambda: None
) -> tuple[list[SectionView], object]:
    """Render every section, in ``jobs`` forked processes when there is more than one (figures are CPU-bound), and
    call ``meanwhile()`` in this process while they draw.  Returns (the views, what ``meanwhile`` returned).

    ``meanwhile`` is the page's own work (findings, the engine table and its figure): done here while the pool draws,
    it no longer runs alone on one core after the last section.
    """
    global _JOB

    def bar(it, n):
        if not progress:
            return it
        from tqdm.auto import tqdm

        return tqdm(it, total=n, desc="render", leave=True)

    if jobs <= 1 or len(sections) < 2 or "fork" not in multiprocessing.get_all_start_methods():
        views = [_view(s, out) for s in bar(sections, len(sections))]
        return views, meanwhile()
    _JOB = (sections, out)
    try:
        with process_pool(jobs) as pool:
            drawing = pool.imap(_view_by_index, range(len(sections)), chunksize=1)
            extra = meanwhile()
            views = list(bar(drawing, len(sections)))
    finally:
        _JOB = None
    for v, s in zip(views, sections):
        v.section = s
    return views, extra


def _first_screen(out: Path, slugs: set[str]) -> tuple[list, list[dict], list, list]:
    """(findings, engine records, the first screen's blocks, the findings' blocks) from the saved results; the engine
    table's data files, the first figure and the causes-confirmed figure written on the way.  Only the engines whose
    maps section is among ``slugs`` (the sections rendered: ``report --engines``) are in the table and the figure."""
    found = findings(out / "data")
    records = [r for r in engine_records(out / "data") if f"{r['slug']}_maps" in slugs]
    first = []
    if records:
        write_engine_data(out, records)
        first = [b for b in (figure_block(out, records), summary_table(records)) if b is not None]
    extra = [b for b in (confirmed_block(out),) if b is not None]
    return found, records, first, extra


def _summary_rows(index: list[SectionView], engine_pages: list[EnginePage], found: list) -> list:
    """The summary's rows: each index section, then one row per engine over its page's sections."""
    rows = []
    for v in index:
        nf = len(v.failed_checks)
        row = [v.section.title, paper_reference(v.section.paper), badge(v.state),
               _fmt_seconds((v.status or {}).get("seconds")), checks_cell(v.checks),
               ", ".join(verdicts(found, v.section.slug)) or "-"]  # fmt: skip
        rows.append((row, "ok" if v.state in ("ok", "skipped") and not nf else "fail"))
    for p in engine_pages:
        checks = [c for v in p.views for c in v.checks]
        seconds = sum((v.status or {}).get("seconds") or 0.0 for v in p.views)
        ws = list(dict.fromkeys(w for v in p.views for w in verdicts(found, v.section.slug)))
        state = page_state(p.views)
        nf = sum(len(v.failed_checks) for v in p.views)
        row = [
            p.title,
            f"{len(p.views)} sections",
            state,
            _fmt_seconds(seconds),
            checks_cell(checks),
            ", ".join(ws) or "-",
        ]
        rows.append((row, "ok" if state == "ok" and not nf else "fail"))
    return rows


def _write_references(out: Path) -> None:
    """The labels the tables leave out (figure and equation labels of the paper's source), derived, not computed: the same
    file whichever sections are rendered (every registered section), so a partial rebuild leaves the saved data as it was."""
    from dataclasses import asdict

    from crosscheck.report.sections import all_sections
    from crosscheck.theory.paper import FIGURES

    refs = {"figures": [asdict(f) for f in FIGURES], "sections": {s.slug: s.paper for s in all_sections()}}
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / _REFERENCES).write_text(json.dumps(refs, indent=1, default=list) + "\n")


def render(
    out: Path | str, sections: Sequence[Section], *, progress: bool = False, jobs: int | None = None
) -> RenderSummary:
    """Render ``index.html``, the engines' pages and their Markdown twins in ``out`` from ``out/data`` alone.

    ``jobs``: processes drawing figures (default: the usable CPUs, at most 4).  The output does not
    depend on it.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    # Everything read below is checked first against what the run wrote: a damaged file stops the render.
    prov = read_provenance(out) or {"date": "", "git": {}, "parameters": {}, "tolerances": {}}
    for s in sections:
        verified_status(out, s.slug)
    # the render stage's own revision: a report rebuilt by newer code says so (the run stage's is in prov["git"])
    prov = {**prov, "rendered": {"date": _provenance.now(), "git": _provenance.git_revision()}}
    if jobs is None:
        jobs = min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1), 4)
    # the page's own work (findings, the engine table and its figures) done here while the pool draws the sections
    views, (found, records, first, extra) = _views(
        list(sections),
        out,
        jobs=jobs,
        progress=progress,
        meanwhile=lambda: _first_screen(out, {s.slug for s in sections}),
    )
    index, engine_pages = split(views)
    summary = RenderSummary(html=out / "index.html", markdown=out / "report.md", views=views)
    pages = Pages(
        index=index,
        engines=engine_pages,
        prov=prov,
        found=found,
        records=records,
        bottom=bottom_line(records),
        first=first,
        extra=extra,
        summary_rows=_summary_rows(index, engine_pages, found),
        failures=summary.failures,
        known=[
            (v.section.slug, unlabel(c["name"]), unlabel(c["known_discrepancy"])) for v in views for c in v.known_checks
        ],
    )
    _write_references(out)
    (out / "data" / FINDINGS).write_text(
        json.dumps({"findings": [dataclasses.asdict(f) for f in found], "rules": dict(RULES)}, indent=1) + "\n"
    )
    if pages.bottom:  # (a render of no engine's maps leaves the saved one as it was, like the engine table)
        (out / "data" / BOTTOM_LINE).write_text(
            json.dumps([dataclasses.asdict(s) for s in pages.bottom], indent=1) + "\n"
        )
    write_stylesheet(out)
    write_index(out, pages, views)
    for p in engine_pages:
        write_engine(out, pages, p)
    write_md(out, pages, views, {p.stem: engine_provenance(p, prov, records) for p in engine_pages})
    return summary
