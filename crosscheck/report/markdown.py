"""The report's Markdown twin, ``report.md``: the same blocks as ``index.html``, wrapped for reading as plain text.

Lines stay within ``MD_WIDTH`` characters of prose (tables within ``MD_ROW_WIDTH``), a long raw block is written to a
file and linked, and links and code spans are never broken.  ``report.md`` keeps the bottom line, the first figure,
the engine table and the findings and links to each engine's page, ``engine_<slug>.md``.  The helpers shared with the
HTML writer live in ``crosscheck.report.format``.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

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
    is_long,
    md_cell,
    summary_table,
    verdicts,
)
from crosscheck.report.pages import EnginePage, Pages, page_state
from crosscheck.report.pipeline import PROVENANCE_FILE
from crosscheck.report.provenance import provenance_rows
from crosscheck.report.references import _NUMBERING, _figures_table, paper_reference
from crosscheck.report.section import Figure, Preformatted, Table, Text

__all__ = ["write_md", "MD_WIDTH", "MD_ROW_WIDTH"]


def _md_block(b) -> str:
    if isinstance(b, Text):
        return b.text + "\n"
    if isinstance(b, Preformatted):
        return (f"**{b.title}**\n\n" if b.title else "") + "```text\n" + b.text.rstrip() + "\n```\n"
    if isinstance(b, Figure):
        links = " · ".join([f"[SVG]({b.stem}.svg)"] + [f"[data: {Path(d).name}]({d})" for d in b.data])
        return f"![{md_cell(b.caption[:80])}]({b.stem}.png)\n\n*{b.caption}*\n\n{links}\n"
    if isinstance(b, Table):
        lines = [b.caption, "", "| " + " | ".join(md_cell(x) for x in b.header) + " |", "|" + "---|" * len(b.header)]
        notes = []
        for r in b.rows:
            cells = [md_cell(x) for x in r]
            while len(" | ".join(cells)) > MD_ROW_WIDTH:  # the longest cell moves to a note under the table
                i = max(range(len(cells)), key=lambda j: len(cells[j]))
                notes.append(cells[i])
                cells[i] = f"note {len(notes)}"
            lines.append("| " + " | ".join(cells) + " |")
        if notes:
            lines += [""] + [f"- note {k}: {t}" for k, t in enumerate(notes, 1)]
        if b.notes:
            lines += [""] + [f"- {n}" for n in b.notes]
        if b.data:
            lines += ["", " · ".join(f"[data: {Path(d).name}]({d})" for d in b.data)]
        return "\n".join(lines) + "\n"
    raise TypeError(f"unknown block {type(b).__name__}")


#: A Markdown table row longer than this moves its longest cells to notes under the table.
MD_ROW_WIDTH = 380
#: Prose lines of the Markdown are wrapped at this width (soft line breaks: the rendered text is the same).
MD_WIDTH = 120


_UNBROKEN = re.compile(r"!?\[[^\]\n]*\]\([^)\n]*\)|`[^`\n]+`")
_BLOCK_START = re.compile(r"(?:[>#|*+=]|-(?:\s|$)|\d+[.)](?:\s|$))")


def _wrap_md(text: str) -> str:
    """Wrap the Markdown's prose (paragraphs, captions, list items) at ``MD_WIDTH``; tables, headings and code stay as they are."""
    import textwrap

    out, code = [], False
    for line in text.split("\n"):
        if line.startswith("```"):
            code = not code
        if code or len(line) <= MD_WIDTH or line.startswith(("|", "#", "    ")):
            out.append(line)
            continue
        indent = "  " if line.startswith("- ") else "> " if line.startswith("> ") else ""
        # a link, an image or a code span is never broken: its spaces are hidden from textwrap
        kept = _UNBROKEN.sub(lambda m: m.group(0).replace(" ", "\x00"), line)
        wrapped = [
            w.replace("\x00", " ")
            for w in textwrap.wrap(
                kept, MD_WIDTH, subsequent_indent=indent, break_long_words=False, break_on_hyphens=False
            )
        ]
        for w in wrapped[
            1:
        ]:  # a line that Markdown would read as a quote, a list item, a heading or a table row joins the one before
            if _BLOCK_START.match(w[len(indent) :].lstrip()):
                wrapped[wrapped.index(w) - 1] += " " + w[len(indent) :].lstrip()
                wrapped.remove(w)
        out.extend(wrapped)
    return "\n".join(out)


def _md_raw_link(out: Path, slug: str, b: Preformatted, k: int) -> str:
    """A long raw output (a command's JSON) written beside the section's figures and linked from the Markdown."""
    try:
        json.loads(b.text)
        ext = "json"
    except ValueError:
        ext = "txt"
    path = Path("figures") / slug / f"raw_{k}.{ext}"
    (out / path).parent.mkdir(parents=True, exist_ok=True)
    (out / path).write_text(b.text.rstrip() + "\n")
    return f"{b.title or 'raw output'}: [{path.name}]({path}) ({b.text.count(chr(10)) + 1} lines)\n"


def _md_section(out: Path, v: SectionView, found: list) -> list[str]:
    s = v.section
    ws = verdicts(found, s.slug)
    m = [f"## {s.title} [{badge(v.state)}]" + (f" finding: {', '.join(ws)}" if ws else ""), ""]
    if s.paper:
        m += [f"*Paper: {paper_reference(s.paper, labels=True)}*", ""]
    if v.error:
        m += [f"> **{badge(v.state)}**: {v.error}", ""]
        if s.requires:
            m += ["> This section needs: " + ", ".join(f"`{r}`" for r in s.requires), ""]
        if v.traceback:
            m += ["```text", v.traceback.rstrip(), "```", ""]
        if v.files:
            m += ["Saved before the failure: " + ", ".join(f"[{Path(f).name}]({f})" for f in v.files), ""]
    m += [_md_raw_link(out, s.slug, b, k) if is_long(b) else _md_block(b) for k, b in enumerate(v.blocks)]
    if v.checks and not checks_shown(v):
        m.append(_md_block(checks_table(v.checks)))
    elif v.checks:
        m.append(_md_block(checks_note(v.checks)))
    return m


def _md_findings(pages: Pages, found: list) -> list[str]:
    def where(slug: str) -> str:
        stem = pages.page_of(slug)
        return slug if stem == "index" else f"[{slug}]({stem}.md)"

    return [
        f"- **{f.leg}**: {f.text}. *{f.verdict}*" + (f" ({f.why})" if f.why else "") + f" ({where(f.slug)})"
        for f in found
    ]


def _md_index_top(pages: Pages) -> list[str]:
    m = ["# crosscheck: contact engines against the rigid theory of the 3D Painlevé rod", ""]
    m += [" ".join(s.text for s in pages.bottom), ""] if pages.bottom else []
    m += [_md_block(b) for b in pages.first]
    m += [
        "Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painlevé paradox*. Every figure is recomputed "
        f"from the project's model; beside each figure and table is the data behind it. {_NUMBERING} HTML version: "
        "[index.html](index.html); the bottom line's sentences with their rules: "
        "[data/bottom_line.json](data/bottom_line.json).",
        "",
        "Engines, one page each: "
        + ", ".join(f"[{p.title}]({p.stem}.md) [{page_state(p.views)}]" for p in pages.engines),
        "",
        "## Findings",
        "",
        *[_md_block(b) for b in pages.extra],
        *_md_findings(pages, pages.found),
        "",
        f"[data: {FINDINGS}](data/{FINDINGS})",
        "",
        f"**{RULES_TITLE}**",
        "",
        *(f"- *{k}*: {r}" for k, r in RULES),
        "",
        "## Summary",
        "",
        _md_block(summary_table(pages.summary_rows)),
    ]
    return m


def _md_index_rest(pages: Pages, views: list[SectionView]) -> list[str]:
    m = [
        "**Failures** (the command exits non-zero):\n\n" + "\n".join(f"- {f}" for f in pages.failures) + "\n"
        if pages.failures
        else "No failures.\n"
    ]
    if pages.known:
        m.append(
            "**Known discrepancies of the paper** (shown, not hidden):\n\n"
            + "\n".join(f"- {s}: {n}: {k}" for s, n, k in pages.known)
            + "\n"
        )
    m += ["## The paper's figures", "", _md_block(_figures_table(views)), "## Provenance", ""]
    m.append(_md_block(Table(caption="Versions, revision, date and machine of the run stage.", header=["item", "value"],
                             rows=provenance_rows(pages.prov), data=[f"data/{PROVENANCE_FILE}.json"])))  # fmt: skip
    return m


def _md_parameters(prov: dict) -> list[str]:
    return [
        "## Parameters and tolerances",
        "",
        "Every parameter of every section is in "
        f"[data/{PROVENANCE_FILE}.json](data/{PROVENANCE_FILE}.json) (key `parameters`) and in each section's "
        "`data/<section>/status.json`; every tolerance of `crosscheck.tolerances` is below.",
        "",
        _md_block(
            Table(
                caption="Tolerances.",
                header=["name", "atol", "rtol", "why"],
                rows=[[k, str(t["atol"]), str(t["rtol"]), t["why"]] for k, t in prov.get("tolerances", {}).items()],
                data=[],
            )
        ),
    ]


def _md_engine(out: Path, pages: Pages, page: EnginePage, provenance: list[list[str]]) -> Path:
    rec = next((r for r in pages.records if r["engine"] == page.spec.name and r["role"] == "map"), None)
    m = [f"# {page.title} [{page_state(page.views)}]", "", "[crosscheck report](report.md)", "", "## Findings", ""]
    m += _md_findings(pages, [f for f in pages.found if f.slug in page.slugs]) + [""]
    if rec is not None:
        m += [f"- {x}" for x in engine_facts(rec)] + ["", _md_block(settings_table(pages.records, page.spec.name))]
    m += ["## Provenance", "", _md_block(Table(caption="The engine's libraries, tags and the options of every setting.",
                                               header=["item", "value"], rows=provenance, data=[]))]  # fmt: skip
    for v in page.views:
        m += _md_section(out, v, pages.found)
    path = out / f"{page.stem}.md"
    path.write_text(_wrap_md("\n".join(m)))
    return path


def write_md(out: Path, pages: Pages, views: list[SectionView], provenance: dict | None = None) -> Path:
    """``report.md`` (the index's twin) and ``engine_<slug>.md`` per engine page; ``provenance``: each page's
    provenance rows by its stem (``html_pages.engine_provenance``)."""
    m = _md_index_top(pages) + _md_index_rest(pages, views)
    for v in pages.index:
        m += _md_section(out, v, pages.found)
    m += _md_parameters(pages.prov)
    path = out / "report.md"
    path.write_text(_wrap_md("\n".join(m)))
    for p in pages.engines:
        _md_engine(out, pages, p, (provenance or {}).get(p.stem, []))
    return path
