"""The render stage: ``index.html`` and its Markdown twin ``report.md`` from saved results alone.

Reads ``<out>/data`` (provenance and each section's status and results),
asks each section to draw its figures and tables, and writes both documents
with the same headings in the same order.  Nothing here computes physics.

A section that failed to run is shown with its error, its traceback and the
files it saved before failing; a section whose render fails is shown the same
way.  ``RenderSummary.failures`` lists everything that makes the command exit
non-zero: failed or unfinished sections and failed checks that are not known
discrepancies of the paper.
"""

from __future__ import annotations

import dataclasses
import html
import json
import multiprocessing
import os
import re
import shutil
import traceback
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from crosscheck.report.findings import RULES
from crosscheck.report.format import (
    FINDINGS_FILE,
    RULES_TITLE,
    SectionView,
    badge,
    checks_cell,
    checks_note,
    checks_shown,
    checks_table,
    long_block,
    summary_table,
    verdicts,
)
from crosscheck.report.provenance import provenance_rows
from crosscheck.report.provenance import seconds_text as _fmt_seconds
from crosscheck.report.references import (
    NUMBERING,
    REFERENCES_FILE,
    figures_table,
    paper_reference,
    unlabel,
)
from crosscheck.report.section import Figure, Preformatted, RenderContext, Section, Table, Text
from crosscheck.report.store import PROVENANCE_FILE, SectionStore, read_provenance, read_status, verified_status

__all__ = ["render", "RenderSummary", "SectionView"]


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


def _unlabelled(b):
    """A block with the paper source's figure labels replaced by figure numbers (``unlabel``)."""
    from dataclasses import replace

    if isinstance(b, Text):
        return replace(b, text=unlabel(b.text))
    if isinstance(b, Figure):
        return replace(b, caption=unlabel(b.caption))
    if isinstance(b, Table):
        return replace(b, caption=unlabel(b.caption), rows=[[unlabel(str(c)) for c in r] for r in b.rows])
    return b


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
        view.blocks = [_unlabelled(b) for b in section.render(ctx)]
    except Exception as e:  # noqa: BLE001  (one section's figure must not stop the report)
        if not view.error:  # a failed run explains a failed render: show the run's error only
            view.error = f"render failed: {type(e).__name__}: {e}"
            view.traceback = traceback.format_exc()
    return view


# ------------------------------------------------------------------- text ---

_CODE = re.compile(r"`([^`]+)`")


def _html_text(s: str) -> str:
    return _CODE.sub(lambda m: f"<code>{m.group(1)}</code>", html.escape(s))


#: A number with an exponent, or a number with its unit or percentage: kept on one line in a table cell.
_NUMBER_TOKEN = re.compile(
    r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?: ?%)?(?![\w.])"
)  # a whole number, not digits inside a word or hash
_NUMERIC_CELL = re.compile(
    r"[-+]?(?:\d[\d.]*(?:e[-+]?\d+)?|nan|inf)(?: ?%| deg)?(?: ?[\[(][-+\d.e/ %,]*[\])])?(?:, [-+]?\d[\d.]*(?:e[-+]?\d+)?)?"
)


def _html_cell(c) -> str:
    """A table cell: a numeric cell never wraps; inside text, a number (``1e-12``, ``83 %``) does not break at its sign."""
    text = str(c)
    if _NUMERIC_CELL.fullmatch(text.strip()):
        return f'<td class="num">{_html_text(text)}</td>'
    if "<" in text or "`" in text:
        return f"<td>{_html_text(text)}</td>"
    return (
        "<td>"
        + _NUMBER_TOKEN.sub(
            lambda m: (
                f'<span class="num">{m.group(0)}</span>' if "e" in m.group(0) or "%" in m.group(0) else m.group(0)
            ),
            html.escape(text),
        )
        + "</td>"
    )


# ------------------------------------------------------------------- html ---

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222;line-height:1.45}
h1{font-size:1.6em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:.6em 0;font-size:.88em}
th,td{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}
th{background:#f3f3f3}tr.fail td{background:#fdd}tr.known td{background:#fff3c4}tr.ok td{background:#fff}tr.guard td{background:#e8f0fe}tr.skip td{background:#f2f2f2;color:#666}
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


def _toc(views: list[SectionView]) -> str:
    """A table of contents that stays in view on a wide screen (a list on top otherwise)."""
    fixed = [
        ("findings", "Findings"),
        ("summary", "Summary"),
        ("figures", "The paper's figures"),
        ("provenance", "Provenance"),
    ]
    items = [f'<a href="#{a}">{t}</a>' for a, t in fixed]
    items += [
        f'<a href="#{v.section.slug}">{html.escape(v.section.title)}<span class="st badge b-{badge(v.state).replace(" ", "")}">'
        f"{badge(v.state)}</span></a>"
        for v in views
    ]
    items.append('<a href="#parameters">Parameters and tolerances</a>')
    return '<nav class="toc" id="top"><b>Contents</b>' + "".join(items) + "</nav>"


def _h2(anchor: str, inner: str) -> str:
    return f'<h2 id="{anchor}">{inner}<a class="top" href="#top">top</a></h2>'


#: Preformatted output longer than this many lines is folded in the HTML and linked, not inlined, in the Markdown.
def _html_block(b) -> str:
    if isinstance(b, Text):
        return f"<p>{_html_text(b.text)}</p>"
    if isinstance(b, Preformatted):
        if long_block(b):  # long raw output (JSON, a command's table) folded: the figures and tables come first
            return f"<details><summary>{html.escape(b.title or 'raw output')}</summary><pre>{html.escape(b.text)}</pre></details>"
        title = f"<p><b>{html.escape(b.title)}</b></p>" if b.title else ""
        return f"{title}<pre>{html.escape(b.text)}</pre>"
    if isinstance(b, Figure):
        links = f'<a href="{b.stem}.svg">SVG</a>' + "".join(
            f'<a href="{d}">data: {html.escape(Path(d).name)}</a>' for d in b.data
        )
        return (
            f'<figure><a href="{b.stem}.svg"><img src="{b.stem}.png" alt="{html.escape(b.caption[:80])}"></a>'
            f"<figcaption>{_html_text(b.caption)}</figcaption><div class=data>{links}</div></figure>"
        )
    if isinstance(b, Table):
        head = "".join(f"<th>{html.escape(h)}</th>" for h in b.header)
        rows = []
        for i, r in enumerate(b.rows):
            cls = b.row_class[i] if i < len(b.row_class) else ""
            rows.append(f'<tr class="{cls}">' + "".join(_html_cell(c) for c in r) + "</tr>")
        links = "".join(f'<a href="{d}">data: {html.escape(Path(d).name)}</a>' for d in b.data)
        return f"<p>{_html_text(b.caption)}</p><div class=tw><table><tr>{head}</tr>{''.join(rows)}</table></div><div class=data>{links}</div>"
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


def write_references(out: Path) -> None:
    """The labels the tables leave out (figure and equation labels of the paper's source), derived, not computed: the same
    file whichever sections are rendered (every registered section), so a partial rebuild leaves the saved data as it was."""
    from dataclasses import asdict

    from crosscheck.report.sections import all_sections
    from crosscheck.theory.paper import FIGURES

    refs = {"figures": [asdict(f) for f in FIGURES], "sections": {s.slug: s.paper for s in all_sections()}}
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / REFERENCES_FILE).write_text(json.dumps(refs, indent=1, default=list) + "\n")


def _html_section(v: SectionView, found: list) -> list[str]:
    """One section of the page: its heading with its state and verdicts, the paper's place, any error, its blocks,
    its checks and its parameters."""
    out = []
    s = v.section
    found_verdicts = verdicts(found, s.slug)
    finding = "".join(
        f' <span class="v-{w.replace(" ", "")}" style="font-size:.7em">{html.escape(w)}</span>' for w in found_verdicts
    )
    out.append(
        _h2(
            s.slug,
            f'{html.escape(s.title)} <span class="badge b-{badge(v.state).replace(" ", "")}">{badge(v.state)}</span>{finding}',
        )
    )
    if s.paper:
        out.append(f"<p><i>Paper: {html.escape(paper_reference(s.paper, labels=True))}</i></p>")
    out.append(_html_error(v))
    out += [_html_block(b) for b in v.blocks]
    if v.checks and not checks_shown(v):
        out.append(_html_block(checks_table(v.checks)))
    elif v.checks:
        out.append(_html_block(checks_note(v.checks)))
    if v.status and v.status.get("params"):
        out.append(
            f"<details><summary>parameters</summary><pre>{html.escape(json.dumps(v.status['params'], indent=1))}</pre></details>"
        )
    return out


def _write_html(
    out: Path, views: list[SectionView], prov: dict, summary_rows, failures: list[str], found: list, table: list
) -> Path:
    h = [
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>crosscheck report</title>',
        f"<style>{_CSS}</style></head><body>",
        "<h1>crosscheck report: contact engines against the rigid theory of the 3D Painlevé rod</h1>",
        "<p>Reference: Cheesman, Hogan &amp; Kristiansen, <i>The geometry of the Painlevé paradox</i>. "
        "Every figure is recomputed from the project's model; beside each figure and table is the data behind it. "
        f"{html.escape(NUMBERING)} "
        'Markdown twin: <a href="report.md">report.md</a>.</p>',
        _toc(views),
        _h2("findings", "Findings"),
        *[_html_block(b) for b in table],
        "<ul>"
        + "".join(
            f'<li><b>{html.escape(f.leg)}</b>: {html.escape(f.text)}. <span class="v-{f.verdict.replace(" ", "")}">{html.escape(f.verdict)}</span>'
            + (f' <span class="why">({html.escape(f.why)})</span>' if f.why else "")
            + f' (<a href="#{f.slug}">{html.escape(f.slug)}</a>)</li>'
            for f in found
        )
        + "</ul>",
        f'<div class=data><a href="data/{FINDINGS_FILE}">data: {FINDINGS_FILE}</a></div>',
        f"<p><b>{RULES_TITLE}</b></p>",
        '<dl class="rules">'
        + "".join(f"<dt>{html.escape(k)}</dt><dd>{html.escape(r)}</dd>" for k, r in RULES)
        + "</dl>",
        _h2("summary", "Summary"),
    ]
    table = _html_block(summary_table(summary_rows))
    for v in views:  # section names link to their sections
        cell = f"<td>{_html_text(v.section.title)}</td>"
        table = table.replace(cell, f'<td><a href="#{v.section.slug}">{_html_text(v.section.title)}</a></td>', 1)
    h.append(table)
    if failures:
        h.append(
            '<div class="error"><p><b>Failures</b> (the command exits non-zero):</p><ul>'
            + "".join(f"<li>{html.escape(f)}</li>" for f in failures)
            + "</ul></div>"
        )
    else:
        h.append("<p>No failures.</p>")
    known = [(v.section.slug, c) for v in views for c in v.known_checks]
    if known:
        h.append(
            '<div class="known"><p><b>Known discrepancies of the paper</b> (shown, not hidden):</p><ul>'
            + "".join(
                f"<li>{html.escape(s)}: {html.escape(unlabel(c['name']))}: {html.escape(unlabel(c['known_discrepancy']))}</li>"
                for s, c in known
            )
            + "</ul></div>"
        )
    h.append(_h2("figures", "The paper's figures"))
    table = _html_block(figures_table(views))
    for v in views:  # section names link to their sections
        table = table.replace(
            _html_text(v.section.title), f'<a href="#{v.section.slug}">{_html_text(v.section.title)}</a>'
        )
    h.append(table)
    h.append(_h2("provenance", "Provenance"))
    h.append(
        _html_block(
            Table(
                caption="Versions, revision, date and machine of the run stage.",
                header=["item", "value"],
                rows=provenance_rows(prov),
                data=[f"data/{PROVENANCE_FILE}.json"],
            )
        )
    )
    for v in views:
        h += _html_section(v, found)
    h.append(_h2("parameters", "Parameters and tolerances"))
    h.append(
        "<p>Every parameter of every section (also in each section's <code>data/&lt;section&gt;/status.json</code>) and every tolerance of <code>crosscheck.tolerances</code>.</p>"
    )
    h.append(
        f"<details><summary>every parameter (JSON)</summary><pre>{html.escape(json.dumps(prov.get('parameters', {}), indent=1))}</pre></details>"
    )
    h.append(
        _html_block(
            Table(
                caption="Tolerances (`crosscheck.report.provenance.all_tolerances()`).",
                header=["name", "atol", "rtol", "why"],
                rows=[[k, str(t["atol"]), str(t["rtol"]), t["why"]] for k, t in prov.get("tolerances", {}).items()],
                data=[f"data/{PROVENANCE_FILE}.json"],
            )
        )
    )
    h.append("</body></html>\n")
    path = out / "index.html"
    path.write_text("\n".join(h))
    return path


# --------------------------------------------------------------- markdown ---


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
    from crosscheck.report import plotting  # noqa: F401 - imported once here, not once per forked worker
    from crosscheck.workers import process_pool

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


def render(
    out: Path | str, sections: Sequence[Section], *, progress: bool = False, jobs: int | None = None
) -> RenderSummary:
    """Render ``index.html`` and ``report.md`` in ``out`` from ``out/data`` alone.

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
    from crosscheck.report import provenance as _provenance

    prov = {**prov, "rendered": {"date": _provenance.now(), "git": _provenance.git_revision()}}
    if jobs is None:
        jobs = min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1), 4)

    def page_blocks():
        # from the saved results alone, like every section's blocks: built while the sections draw
        from crosscheck.report.confirmed_overview import confirmed_block
        from crosscheck.report.engine_table import table_block
        from crosscheck.report.findings import findings

        found = findings(out / "data")
        # the engine table and the causes confirmed on the engines, read from the saved results once, for both pages
        return found, [b for b in (table_block(out), confirmed_block(out)) if b is not None]

    views, (found, table) = _views(list(sections), out, jobs=jobs, progress=progress, meanwhile=page_blocks)
    summary_rows = []
    for v in views:
        nf = len(v.failed_checks)
        row = [
            v.section.title,
            paper_reference(v.section.paper),
            badge(v.state),
            _fmt_seconds((v.status or {}).get("seconds")),
            checks_cell(v.checks),
            ", ".join(verdicts(found, v.section.slug)) or "-",
        ]
        summary_rows.append((row, "ok" if v.state in ("ok", "skipped") and not nf else "fail"))
    summary = RenderSummary(html=out / "index.html", markdown=out / "report.md", views=views)
    failures = summary.failures
    write_references(out)
    (out / "data" / FINDINGS_FILE).write_text(
        json.dumps({"findings": [dataclasses.asdict(f) for f in found], "rules": dict(RULES)}, indent=1) + "\n"
    )
    from crosscheck.report.markdown import write_md

    _write_html(out, views, prov, summary_rows, failures, found, table)
    write_md(out, views, prov, summary_rows, failures, found, table)
    return summary
