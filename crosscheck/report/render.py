"""The render stage: ``index.html``, one page per engine and their Markdown twins, from saved results alone.

Reads ``<out>/data`` (provenance and each section's status and results), asks each section to draw its figures and
tables, and writes the pages (``crosscheck.report.pages``: the theory's sections on the index, each engine's on
``engine_<slug>.html``).  The index opens with the bottom line (``bottom_line``), the first figure (``first_figure``)
and one row per engine (``engine_table``).  Nothing here computes physics.

A section that failed to run is shown with its error, its traceback and the files it saved before failing; a section
whose render fails is shown the same way.  ``RenderSummary.failures`` lists everything that makes the command exit
non-zero: failed or unfinished sections and failed checks that are not known discrepancies of the paper.
"""

from __future__ import annotations

import dataclasses
import html
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
from crosscheck.report.bottom_line import bottom_line, verdict
from crosscheck.report.confirmed_overview import confirmed_block
from crosscheck.report.engine_table import (
    engine_facts,
    engine_records,
    settings_table,
    summary_table,
    write_engine_data,
)
from crosscheck.report.findings import RULES, findings
from crosscheck.report.first_figure import figure_block
from crosscheck.report.format import (
    FINDINGS,
    RULES_TITLE,
    SectionView,
    badge,
    checks_cell,
    checks_note,
    checks_shown,
    checks_table,
    html_cell,
    html_text,
    is_long,
    unlabelled,
    verdicts,
)
from crosscheck.report.format import (
    summary_table as sections_table,
)
from crosscheck.report.markdown import write_md
from crosscheck.report.pages import EnginePage, Pages, page_state, split
from crosscheck.report.pipeline import PROVENANCE_FILE, read_provenance, read_status, verified_status
from crosscheck.report.provenance import provenance_rows
from crosscheck.report.provenance import seconds_text as _fmt_seconds
from crosscheck.report.references import _NUMBERING, _REFERENCES, _figures_table, paper_reference, unlabel
from crosscheck.report.section import Figure, Preformatted, RenderContext, Section, Table, Text
from crosscheck.report.store import SectionStore
from crosscheck.workers import process_pool

__all__ = ["render", "RenderSummary", "SectionView", "BOTTOM_LINE"]

#: The bottom line's sentences and rules, written beside the report's data (derived, not computed).
BOTTOM_LINE = "bottom_line.json"


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
            view.traceback = traceback.format_exc()
    return view


# ------------------------------------------------------------------- html ---

#: The stylesheet every HTML page of the report links, written beside them (one copy, not one per page).
STYLESHEET = "style.css"
_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1100px;margin:1em auto;padding:0 1em;color:#222;line-height:1.45}
h1{font-size:1.35em;margin:.3em 0}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:.6em 0;font-size:.88em}
th,td{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}
th{background:#f3f3f3}tr.fail td{background:#fdd}tr.known td{background:#fff3c4}tr.ok td{background:#fff}tr.guard td{background:#e8f0fe}tr.skip td{background:#f2f2f2;color:#666}
p.bottom{font-size:.95em;margin:.3em 0 .4em;line-height:1.35}p.bottom span{display:block;margin:.1em 0}
ul.notes{font-size:.8em;color:#444;margin:.2em 0 .8em;padding-left:1.2em}
figure.first{margin:.3em 0}figure.first img{max-height:400px}
.badge{font-weight:bold;padding:0 .4em;border-radius:3px}.b-ok{background:#d4f4d4}.b-skipped{background:#e8e8e8}.b-FAILED,.b-UNFINISHED,.b-NOTRUN{background:#f7c6c6}
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #eee}figcaption{font-size:.9em;color:#444}
.data{font-size:.85em}.data a{margin-right:.8em}
pre{background:#f6f6f6;padding:.6em;overflow-x:auto;font-size:.8em}
.error{border-left:4px solid #c00;padding:.3em .8em;background:#fff0f0}
.known{border-left:4px solid #d90;padding:.3em .8em;background:#fffbe8}
nav.toc{font-size:.82em;line-height:1.3}nav.toc a{display:block;padding:.12em 0;color:#235;text-decoration:none}nav.toc a:hover{text-decoration:underline}
nav.toc .st{font-size:.8em;margin-left:.3em}
@media (min-width:1500px){nav.toc{position:fixed;top:1em;left:1em;width:230px;max-height:95vh;overflow-y:auto;border-right:1px solid #ddd;padding-right:.6em}}
@media (min-width:1500px){body{margin-left:280px}}
@media (max-width:1499px){nav.toc{border:1px solid #ddd;padding:.5em 1em;columns:2}}
.v-agrees,.v-converges,.v-explained,.v-confirmed{color:#176317;font-weight:bold}.v-disagrees,.v-doesnotconverge,.v-notexplained{color:#a11;font-weight:bold}.v-inconclusive,.v-known,.v-partlyexplained,.v-partlyconfirmed{color:#8a5a00;font-weight:bold}.why{color:#555;font-size:.9em}
td.num,span.num{white-space:nowrap}.tw{overflow-x:auto}dl.rules dt{font-weight:bold}dl.rules dd{margin:0 0 .3em 1.5em}
a.top{font-size:.6em;font-weight:normal;margin-left:.6em;color:#888;text-decoration:none}
"""


def _h2(anchor: str, inner: str) -> str:
    return f'<h2 id="{anchor}">{inner}<a class="top" href="#top">top</a></h2>'


def _badge_html(state: str) -> str:
    return f'<span class="st badge b-{state.replace(" ", "")}">{state}</span>'


def _verdict_html(w: str, *, small: bool = False) -> str:
    style = ' style="font-size:.7em"' if small else ""
    return f'<span class="v-{w.replace(" ", "")}"{style}>{html.escape(w)}</span>'


def _toc(pages: Pages) -> str:
    """The index's contents: the fixed parts, the theory's sections, then one entry per engine with its badges."""
    fixed = [("bottom-line", "Bottom line"), ("findings", "Findings"), ("summary", "Summary"),
             ("figures", "The paper's figures"), ("provenance", "Provenance")]  # fmt: skip
    items = [f'<a href="#{a}">{t}</a>' for a, t in fixed]
    items += [
        f'<a href="#{v.section.slug}">{html.escape(v.section.title)}{_badge_html(badge(v.state))}</a>'
        for v in pages.index
    ]
    for p in pages.engines:
        first = next((r for r in pages.records if r["engine"] == p.spec.name and r["role"] == "map"), None)
        w = _verdict_html(verdict(first), small=True) if first and first["n_rated"] else ""
        items.append(
            f'<a class="engine" href="{p.stem}.html">{html.escape(p.title)}{_badge_html(page_state(p.views))} {w}</a>'
        )
    items.append('<a href="#parameters">Parameters and tolerances</a>')
    return '<nav class="toc" id="contents"><b>Contents</b>' + "".join(items) + "</nav>"


def _html_block(b, *, cls: str = "") -> str:
    if isinstance(b, Text):
        return f"<p>{html_text(b.text)}</p>"
    if isinstance(b, Preformatted):
        if is_long(b):  # long raw output (JSON, a command's table) folded: the figures and tables come first
            return f"<details><summary>{html.escape(b.title or 'raw output')}</summary><pre>{html.escape(b.text)}</pre></details>"
        title = f"<p><b>{html.escape(b.title)}</b></p>" if b.title else ""
        return f"{title}<pre>{html.escape(b.text)}</pre>"
    if isinstance(b, Figure):
        links = f'<a href="{b.stem}.svg">SVG</a>' + "".join(
            f'<a href="{d}">data: {html.escape(Path(d).name)}</a>' for d in b.data
        )
        return (
            f'<figure class="{cls}"><a href="{b.stem}.svg"><img src="{b.stem}.png" alt="{html.escape(b.caption[:80])}"></a>'
            f"<figcaption>{html_text(b.caption)}</figcaption><div class=data>{links}</div></figure>"
        )
    if isinstance(b, Table):
        head = "".join(f"<th>{html.escape(h)}</th>" for h in b.header)
        rows = []
        for i, r in enumerate(b.rows):
            row_cls = b.row_class[i] if i < len(b.row_class) else ""
            rows.append(f'<tr class="{row_cls}">' + "".join(html_cell(c) for c in r) + "</tr>")
        links = "".join(f'<a href="{d}">data: {html.escape(Path(d).name)}</a>' for d in b.data)
        notes = "<ul class=notes>" + "".join(f"<li>{html_text(n)}</li>" for n in b.notes) + "</ul>" if b.notes else ""
        return (
            f'<p>{html_text(b.caption)}</p><div class=tw><table class="{cls}"><tr>{head}</tr>{"".join(rows)}</table>'
            f"</div>{notes}<div class=data>{links}</div>"
        )
    raise TypeError(f"unknown block {type(b).__name__}")


def _html_error(v: SectionView) -> str:
    if not v.error:
        return ""
    parts = [f'<div class="error"><p><b>{badge(v.state)}</b>: {html.escape(v.error)}</p>']
    if v.section.requires:
        parts.append(f"<p>This section needs: {', '.join(f'<code>{r}</code>' for r in v.section.requires)}</p>")
    if v.traceback:
        parts.append(f"<details><summary>traceback</summary><pre>{html.escape(v.traceback)}</pre></details>")
    if v.files:
        parts.append(
            "<p>Saved before the failure: "
            + ", ".join(f'<a href="{f}">{html.escape(Path(f).name)}</a>' for f in v.files)
            + "</p>"
        )
    parts.append("</div>")
    return "".join(parts)


def _section_html(v: SectionView, found: list) -> list[str]:
    """One section: its heading with badge and verdicts, its paper reference, error, blocks, checks and parameters."""
    s = v.section
    finding = "".join(" " + _verdict_html(w, small=True) for w in verdicts(found, s.slug))
    h = [_h2(s.slug, f"{html.escape(s.title)} {_badge_html(badge(v.state))}{finding}")]
    if s.paper:
        h.append(f"<p><i>Paper: {html.escape(paper_reference(s.paper, labels=True))}</i></p>")
    h.append(_html_error(v))
    h += [_html_block(b) for b in v.blocks]
    if v.checks and not checks_shown(v):
        h.append(_html_block(checks_table(v.checks)))
    elif v.checks:
        h.append(_html_block(checks_note(v.checks)))
    if v.status and v.status.get("params"):
        h.append(
            f"<details><summary>parameters</summary><pre>{html.escape(json.dumps(v.status['params'], indent=1))}</pre></details>"
        )
    return h


def _head(title: str) -> list[str]:
    return [
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>',
        f'<link rel="stylesheet" href="{STYLESHEET}"></head><body>',
    ]


def _findings_html(pages: Pages, found: list) -> list[str]:
    """The findings' lines (each linked to its section, on whichever page it is) and the rules behind the verdicts."""
    items = "".join(
        f"<li><b>{html.escape(f.leg)}</b>: {html.escape(f.text)}. {_verdict_html(f.verdict)}"
        + (f' <span class="why">({html.escape(f.why)})</span>' if f.why else "")
        + f' (<a href="{_href(pages, f.slug)}">{html.escape(f.slug)}</a>)</li>'
        for f in found
    )
    return [f"<ul>{items}</ul>"]


def _href(pages: Pages, slug: str) -> str:
    stem = pages.page_of(slug)
    return f"#{slug}" if stem == "index" else f"{stem}.html#{slug}"


def _bottom_html(pages: Pages) -> str:
    spans = "".join(f'<span title="{html.escape(s.rule)}">{html.escape(s.text)}</span>' for s in pages.bottom)
    return f'<p class="bottom" id="bottom-line">{spans}</p>' if spans else ""


def _index_top(pages: Pages) -> list[str]:
    """The first screen: title, bottom line, figure, one row per engine; then the contents and the findings."""
    h = [
        '<h1 id="top">crosscheck: contact engines against the rigid theory of the 3D Painlevé rod</h1>',
        _bottom_html(pages),
        *[_html_block(b, cls="first" if isinstance(b, Figure) else "engines") for b in pages.first],
        "<p>Reference: Cheesman, Hogan &amp; Kristiansen, <i>The geometry of the Painlevé paradox</i>. Every figure "
        "is "
        "recomputed from the project's model; beside each figure and table is the data behind it. "
        f"{html.escape(_NUMBERING)} Each engine has its own page (contents). Markdown twin: "
        f'<a href="report.md">report.md</a>; the bottom line\'s rules: '
        f'<a href="data/{BOTTOM_LINE}">{BOTTOM_LINE}</a>.</p>',
        _toc(pages),
        _h2("findings", "Findings"),
        *[_html_block(b) for b in pages.extra],
        *_findings_html(pages, pages.found),
        f'<div class=data><a href="data/{FINDINGS}">data: {FINDINGS}</a></div>',
        f"<p><b>{RULES_TITLE}</b></p>",
        '<dl class="rules">'
        + "".join(f"<dt>{html.escape(k)}</dt><dd>{html.escape(r)}</dd>" for k, r in RULES)
        + "</dl>",
    ]
    return h


def _linked(table_html: str, pages: Pages, views: list[SectionView]) -> str:
    """Section titles in a table's cells linked to their sections (on their pages)."""
    for v in views:
        cell = f"<td>{html_text(v.section.title)}</td>"
        table_html = table_html.replace(
            cell, f'<td><a href="{_href(pages, v.section.slug)}">{html_text(v.section.title)}</a></td>', 1
        )
    return table_html


def _index_rest(pages: Pages, views: list[SectionView]) -> list[str]:
    """Summary, failures, known discrepancies, the paper's figures and the provenance."""
    h = [_h2("summary", "Summary"), _linked(_html_block(sections_table(pages.summary_rows)), pages, views)]
    for p in pages.engines:
        h[-1] = h[-1].replace(
            f"<td>{html_text(p.title)}</td>", f'<td><a href="{p.stem}.html">{html_text(p.title)}</a></td>', 1
        )
    if pages.failures:
        h.append(
            '<div class="error"><p><b>Failures</b> (the command exits non-zero):</p><ul>'
            + "".join(f"<li>{html.escape(f)}</li>" for f in pages.failures)
            + "</ul></div>"
        )
    else:
        h.append("<p>No failures.</p>")
    if pages.known:
        h.append(
            '<div class="known"><p><b>Known discrepancies of the paper</b> (shown, not hidden):</p><ul>'
            + "".join(f"<li>{html.escape(s)}: {html.escape(n)}: {html.escape(k)}</li>" for s, n, k in pages.known)
            + "</ul></div>"
        )
    table = _html_block(_figures_table(views))
    for v in views:
        table = table.replace(
            html_text(v.section.title), f'<a href="{_href(pages, v.section.slug)}">{html_text(v.section.title)}</a>'
        )
    h += [_h2("figures", "The paper's figures"), table, _h2("provenance", "Provenance")]
    provenance = Table(
        caption="Versions, revision, date and machine of the run stage.",
        header=["item", "value"],
        rows=provenance_rows(pages.prov),
        data=[f"data/{PROVENANCE_FILE}.json"],
    )
    h.append(_html_block(provenance))
    return h


def _parameters_html(prov: dict) -> list[str]:
    return [
        _h2("parameters", "Parameters and tolerances"),
        "<p>Every parameter of every section (also in each section's <code>data/&lt;section&gt;/status.json</code>) and "
        "every tolerance of <code>crosscheck.tolerances</code>.</p>",
        f"<details><summary>every parameter (JSON)</summary><pre>{html.escape(json.dumps(prov.get('parameters', {}), indent=1))}</pre></details>",
        _html_block(
            Table(
                caption="Tolerances (`crosscheck.tolerances.all_tolerances()`).",
                header=["name", "atol", "rtol", "why"],
                rows=[[k, str(t["atol"]), str(t["rtol"]), t["why"]] for k, t in prov.get("tolerances", {}).items()],
                data=[f"data/{PROVENANCE_FILE}.json"],
            )
        ),
    ]


def _write_index(out: Path, pages: Pages, views: list[SectionView]) -> Path:
    h = _head("crosscheck report") + _index_top(pages) + _index_rest(pages, views)
    for v in pages.index:
        h += _section_html(v, pages.found)
    h += _parameters_html(pages.prov) + ["</body></html>\n"]
    path = out / "index.html"
    path.write_text("\n".join(h))
    return path


def engine_provenance(page: EnginePage, prov: dict, records: list[dict]) -> list[list[str]]:
    """(item, value) rows of an engine's provenance: its libraries' versions, tags and the options of its settings."""
    spec, versions = page.spec, prov.get("versions", {})
    rows = [["registry name", spec.name], ["tags", ", ".join(sorted(spec.tags)) or "-"]]
    rows += [[f"library {lib}", str(versions.get(lib, "not recorded"))] for lib in spec.libraries]
    rows += [
        [f"{r['role']} setting: {r['setting']}", json.dumps(r["options"])] for r in records if r["engine"] == spec.name
    ]
    return rows


def _write_engine(out: Path, pages: Pages, page: EnginePage) -> Path:
    rec = next((r for r in pages.records if r["engine"] == page.spec.name and r["role"] == "map"), None)
    found = [f for f in pages.found if f.slug in page.slugs]
    h = _head(f"crosscheck: {page.title}") + [
        f'<p id="top"><a href="index.html">crosscheck report</a> / {html.escape(page.title)}</p>',
        f"<h1>{html.escape(page.title)} {_badge_html(page_state(page.views))}</h1>",
        '<nav class="toc"><b>Contents</b>'
        + "".join(
            f'<a href="#{v.section.slug}">{html.escape(v.section.title)}{_badge_html(badge(v.state))}</a>'
            for v in page.views
        )
        + "</nav>",  # fmt: skip
        _h2("findings", "Findings"),
        *_findings_html(pages, found),
    ]
    if rec is not None:
        h += ["<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in engine_facts(rec)) + "</ul>"]
        h += [_html_block(settings_table(pages.records, page.spec.name))]
    h += [_h2("provenance", "Provenance"), _html_block(Table(caption="The engine's libraries (versions of the run "
          "stage), tags and the options of every setting it ran.", header=["item", "value"],
          rows=engine_provenance(page, pages.prov, pages.records), data=[f"data/{PROVENANCE_FILE}.json"]))]  # fmt: skip
    for v in page.views:
        h += _section_html(v, pages.found)
    path = out / f"{page.stem}.html"
    path.write_text("\n".join(h + ["</body></html>\n"]))
    return path


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
    (out / STYLESHEET).write_text(_CSS.lstrip())
    _write_index(out, pages, views)
    for p in engine_pages:
        _write_engine(out, pages, p)
    write_md(out, pages, views, {p.stem: engine_provenance(p, prov, records) for p in engine_pages})
    return summary
