"""How the report names the paper: figure numbers and sections for readers, the source's LaTeX labels kept in the data.

``paper_reference`` turns a section's ``paper`` string into what a reader finds in the printed paper, ``unlabel``
removes figure labels from any text, ``_figures_table`` lists the paper's figures and where the report recomputes
them, and ``crosscheck.report.render._write_references`` writes the labels the tables leave out to ``data/paper_references.json``.
"""

from __future__ import annotations

import re

from crosscheck.report.section import Table

__all__ = ["paper_reference", "unlabel"]


_FIG_LABELS = re.compile(r"\s*\((?:fig:[^()]*)\)")
_EQS = re.compile(r"^eqs?\. ")
_PLAIN = re.compile(r"^(?:(?:section|sections|Theorem|Corollary|Appendix|Lemma|Proposition)\b|Figs?\.)")


def paper_reference(paper: str, *, labels: bool = False) -> str:
    """A section's place in the paper as a reader finds it: figure numbers, sections, theorems, without the source's LaTeX labels.

    ``paper`` is a section's ``paper`` string (e.g. "Figs. 11 (fig:GBs_bif3) and 17 (fig:stabilty_on_GB); eq. K, Theorem 4.1").
    Figure labels are dropped (the number is there); equation labels are counted ("3 equations"), or listed after
    "equations, by their labels in the paper's source:" when ``labels``.  The full string stays in the report's data files.
    """
    parts, eqs = [], []
    for part in (p.strip() for p in _FIG_LABELS.sub("", paper).split(";")):
        if not _EQS.match(part):
            parts.append(part)
            continue
        for item in (i.strip() for i in re.split(r",(?![^(]*\))", _EQS.sub("", part))):
            inner = re.fullmatch(r"(\S+) \((.+)\)", item)  # "psil (section 3.3)": the label, then its place
            if inner:
                eqs.append(inner.group(1))
                parts.append(inner.group(2))
            elif _PLAIN.match(item):
                parts.append(item)
            elif item:
                eqs.append(item)
    if eqs:
        parts.append(
            ("equations, by their labels in the paper's source: " + ", ".join(eqs))
            if labels
            else f"{len(eqs)} equation{'s' if len(eqs) > 1 else ''}"
        )
    return "; ".join(p for p in parts if p)


_FIG_LABEL = re.compile(r"fig:[\w.+-]*\w")
_FIG_NAMED = re.compile(r"Fig\. ([A-Za-z_][\w.]*[\w])")


def unlabel(text: str) -> str:
    """``text`` without the paper source's figure labels: "(fig:p3s)" after a figure's number is dropped, any other
    "fig:pandora" becomes the figure's number ("Fig. 19"); the labels stay in ``data/paper_references.json``."""
    if "fig:" not in text and "Fig. " not in text:
        return text
    from crosscheck.theory.paper import FIGURES

    number = {label: f.number for f in FIGURES for label in f.labels}
    text = _FIG_LABELS.sub("", text)
    text = _FIG_LABEL.sub(lambda m: f"Fig. {number[m.group(0)]}" if m.group(0) in number else m.group(0), text)
    # "Fig. GBs_bif3": a label written after "Fig." without its prefix
    return _FIG_NAMED.sub(
        lambda m: f"Fig. {number['fig:' + m.group(1)]}" if "fig:" + m.group(1) in number else m.group(0), text
    )


_NUMBERING = (
    "Figure numbers are the printed paper's (the order of its figure environments), with panel letters; "
    "the table of the paper's figures below says which ones this report recomputes."
)


def _figures_table(views: list) -> Table:
    """The paper's figures: where the report recomputes each, or why it does not (``crosscheck.theory.paper.FIGURES``)."""
    from crosscheck.theory.paper import FIGURES

    titles = {v.section.slug: v.section.title for v in views}
    rows, cls = [], []
    for f in FIGURES:
        where = ", ".join(titles.get(s, s) for s in f.sections)
        rows.append([f"Fig. {f.number}", f.shows, where or "not recomputed", f.why_not])
        cls.append("ok" if f.sections and not f.why_not else ("known" if f.sections else "skip"))
    return Table(
        caption="The paper's figures, numbered as printed: where this report recomputes each, and what it leaves out and why "
        "(white: recomputed; yellow: recomputed in part or in another form; grey: not recomputed). The figures' LaTeX labels "
        "and each section's references to the paper are in the data file.",
        header=["figure", "shows", "recomputed in", "not drawn / why"],
        rows=rows,
        data=[f"data/{_REFERENCES}"],
        row_class=cls,
    )


#: The paper's figures with their LaTeX labels and every section's reference to the paper, written beside the report's data.
_REFERENCES = "paper_references.json"
