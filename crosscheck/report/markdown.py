"""The report's Markdown twin, ``report.md``: the same blocks as ``index.html``, wrapped for reading as plain text.

Lines stay within ``MD_WIDTH`` characters of prose (tables within ``MD_ROW_WIDTH``), a long raw block is written to a
file and linked, and links and code spans are never broken.  The helpers shared with the HTML writer live in
``crosscheck.report.format``.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from crosscheck.report.findings import RULES
from crosscheck.report.format import (
    FINDINGS_FILE,
    RULES_TITLE,
    SectionView,
    badge,
    checks_note,
    checks_shown,
    checks_table,
    long_block,
    md_cell,
    summary_table,
    verdicts,
)
from crosscheck.report.provenance import provenance_rows
from crosscheck.report.references import NUMBERING, figures_table, paper_reference, unlabel
from crosscheck.report.section import Figure, Preformatted, Table, Text
from crosscheck.report.store import PROVENANCE_FILE

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


def write_md(
    out: Path, views: list[SectionView], prov: dict, summary_rows, failures: list[str], found: list, table
) -> Path:
    m = [
        "# crosscheck report: contact engines against the rigid theory of the 3D Painlevé rod",
        "",
        "Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painlevé paradox*. Every figure is recomputed "
        f"from the project's model; beside each figure and table is the data behind it. {NUMBERING} HTML version: [index.html](index.html).",
        "",
        "## Findings",
        "",
        *[_md_block(b) for b in table],
        *(f"- **{f.leg}**: {f.text}. *{f.verdict}*" + (f" ({f.why})" if f.why else "") + f" ({f.slug})" for f in found),
        "",
        f"[data: {FINDINGS_FILE}](data/{FINDINGS_FILE})",
        "",
        f"**{RULES_TITLE}**",
        "",
        *(f"- *{k}*: {r}" for k, r in RULES),
        "",
        "## Summary",
        "",
    ]
    m.append(_md_block(summary_table(summary_rows)))
    m.append(
        "**Failures** (the command exits non-zero):\n\n" + "\n".join(f"- {f}" for f in failures) + "\n"
        if failures
        else "No failures.\n"
    )
    known = [(v.section.slug, c) for v in views for c in v.known_checks]
    if known:
        m.append(
            "**Known discrepancies of the paper** (shown, not hidden):\n\n"
            + "\n".join(f"- {s}: {unlabel(c['name'])}: {unlabel(c['known_discrepancy'])}" for s, c in known)
            + "\n"
        )
    m += ["## The paper's figures", "", _md_block(figures_table(views))]
    m += [
        "## Provenance",
        "",
        _md_block(
            Table(
                caption="Versions, revision, date and machine of the run stage.",
                header=["item", "value"],
                rows=provenance_rows(prov),
                data=[f"data/{PROVENANCE_FILE}.json"],
            )
        ),
    ]
    for v in views:
        s = v.section
        found_verdicts = verdicts(found, s.slug)
        m += [
            f"## {s.title} [{badge(v.state)}]" + (f" finding: {', '.join(found_verdicts)}" if found_verdicts else ""),
            "",
        ]
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
        m += [_md_raw_link(out, s.slug, b, k) if long_block(b) else _md_block(b) for k, b in enumerate(v.blocks)]
        if v.checks and not checks_shown(v):
            m.append(_md_block(checks_table(v.checks)))
        elif v.checks:
            m.append(_md_block(checks_note(v.checks)))
    m += [
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
    path = out / "report.md"
    path.write_text(_wrap_md("\n".join(m)))
    return path
