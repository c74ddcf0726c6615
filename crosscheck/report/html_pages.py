"""The report's HTML pages: ``index.html`` and ``engine_<slug>.html`` from the rendered sections, and their stylesheet.

The index opens with the bottom line, the first figure and one row per engine, then the contents, the findings and the
theory's sections; each engine's page has its findings, facts, provenance and sections.  Every page links the one
``style.css`` written beside them.  The Markdown twins: ``crosscheck.report.markdown``.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

from crosscheck.report.bottom_line import BOTTOM_LINE, verdict
from crosscheck.report.engine_table import engine_facts, settings_table
from crosscheck.report.findings import RULES
from crosscheck.report.format import (
    FINDINGS,
    RULES_TITLE,
    SectionView,
    badge,
    checks_note,
    checks_shown,
    checks_table,
    html_cell,
    html_text,
    is_long,
    verdicts,
)
from crosscheck.report.format import (
    summary_table as sections_table,
)
from crosscheck.report.pages import EnginePage, Pages, page_state
from crosscheck.report.pipeline import PROVENANCE_FILE
from crosscheck.report.provenance import provenance_rows
from crosscheck.report.references import _NUMBERING, _figures_table, paper_reference
from crosscheck.report.section import Figure, Preformatted, Table, Text

__all__ = ["STYLESHEET", "write_index", "write_engine", "write_stylesheet", "engine_provenance"]

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


def write_index(out: Path, pages: Pages, views: list[SectionView]) -> Path:
    """``index.html``: the first screen, the contents, the findings, the theory's sections and the parameters."""
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


def write_engine(out: Path, pages: Pages, page: EnginePage) -> Path:
    """``engine_<slug>.html``: one engine's findings, facts, provenance and sections."""
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


def write_stylesheet(out: Path) -> Path:
    """``style.css``, the one stylesheet every page links."""
    path = out / STYLESHEET
    path.write_text(_CSS.lstrip())
    return path
