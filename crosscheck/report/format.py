"""What the report's HTML and Markdown writers share: a section as rendered, cells, badges and the checks tables.

Both ``crosscheck.report.render`` (the HTML pages) and ``crosscheck.report.markdown`` (their Markdown twins) read these;
neither imports the other's writer.
"""

from __future__ import annotations

import html
import re
from dataclasses import dataclass, field, replace

from crosscheck import engines
from crosscheck.report.references import _REFERENCES, unlabel
from crosscheck.report.section import Figure, Preformatted, Section, Table, Text

__all__ = [
    "engine_label",
    "SectionView",
    "badge",
    "checks_cell",
    "checks_note",
    "checks_shown",
    "checks_table",
    "html_cell",
    "html_text",
    "is_long",
    "md_cell",
    "summary_table",
    "unlabelled",
    "verdicts",
    "FINDINGS",
    "RULES_TITLE",
]


def engine_label(name: str) -> str:
    """How the report names an engine: its registered label ("MuJoCo" for "mujoco"), else ``name`` itself."""
    return engines.labels().get(name, name)


@dataclass
class SectionView:
    """One section as rendered: its status, blocks, checks and any error."""

    section: Section
    status: dict | None
    blocks: list = field(default_factory=list)
    checks: list[dict] = field(default_factory=list)
    error: str = ""  # run or render error, "" when fine
    traceback: str = ""
    files: list[str] = field(default_factory=list)

    @property
    def state(self) -> str:
        if self.status is None:
            return "not run"
        if self.status["status"] == "running":
            return "unfinished"
        if self.error:
            return "failed"
        if self.status["status"] == "skipped":
            return "skipped"
        return "ok"

    @property
    def failed_checks(self) -> list[dict]:
        return [c for c in self.checks if not c["passed"] and not c.get("known_discrepancy")]

    @property
    def known_checks(self) -> list[dict]:
        return [c for c in self.checks if not c["passed"] and c.get("known_discrepancy")]


def unlabelled(b):
    """A block with the paper source's figure labels replaced by figure numbers (``unlabel``)."""
    if isinstance(b, Text):
        return replace(b, text=unlabel(b.text))
    if isinstance(b, Figure):
        return replace(b, caption=unlabel(b.caption))
    if isinstance(b, Table):
        return replace(b, caption=unlabel(b.caption), rows=[[unlabel(str(c)) for c in r] for r in b.rows])
    return b


_CODE = re.compile(r"`([^`]+)`")


def html_text(s: str) -> str:
    return _CODE.sub(lambda m: f"<code>{m.group(1)}</code>", html.escape(s))


#: A number with an exponent, or a number with its unit or percentage: kept on one line in a table cell.
_NUMBER_TOKEN = re.compile(
    r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?: ?%)?(?![\w.])"
)  # a whole number, not digits inside a word or hash
_NUMERIC_CELL = re.compile(
    r"[-+]?(?:\d[\d.]*(?:e[-+]?\d+)?|nan|inf)(?: ?%| deg)?(?: ?[\[(][-+\d.e/ %,]*[\])])?(?:, [-+]?\d[\d.]*(?:e[-+]?\d+)?)?"
)


def html_cell(c) -> str:
    """A table cell: a numeric cell never wraps; inside text, a number (``1e-12``, ``83 %``) does not break at its sign."""
    text = str(c)
    if _NUMERIC_CELL.fullmatch(text.strip()):
        return f'<td class="num">{html_text(text)}</td>'
    if "<" in text or "`" in text:
        return f"<td>{html_text(text)}</td>"
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


def md_cell(s: str) -> str:
    return str(s).replace("|", "\\|").replace("\n", " ")


def badge(state: str) -> str:
    return {"ok": "ok", "skipped": "skipped", "failed": "FAILED", "unfinished": "UNFINISHED", "not run": "NOT RUN"}[
        state
    ]


#: Preformatted output longer than this many lines is folded in the HTML and linked, not inlined, in the Markdown.
LONG_LINES = 15


def is_long(b) -> bool:
    return isinstance(b, Preformatted) and b.text.count("\n") > LONG_LINES


def checks_table(checks: list[dict]):
    rows, cls = [], []
    for c in checks:
        kind = c.get("kind", "physics")
        if c["passed"]:  # a guard that holds shows no change from its measured spread; it is not a physics pass
            verdict, k = (
                ("held (no change; not a physics check)", "guard") if kind == "regression guard" else ("passed", "ok")
            )
        elif c.get("known_discrepancy"):
            verdict, k = "KNOWN DISCREPANCY: " + unlabel(c["known_discrepancy"]), "known"
        else:
            verdict, k = "FAILED", "fail"
        rows.append(
            [
                unlabel(c["name"]),
                kind,
                _short(c.get("value")),
                _short(c.get("allowance")),
                verdict,
                unlabel(c.get("detail", "")),
            ]
        )
        cls.append(k)
    return Table(
        caption="Checks recorded by this section. A physics check's allowance comes from the paper, the integrator or the timestep; "
        "a regression guard's from a measured spread: it flags a change, it does not prove the physics.",
        header=["check", "kind", "value", "allowance", "result", "detail"],
        rows=rows,
        data=[],
        row_class=cls,
    )


def checks_shown(v: SectionView) -> bool:
    """Whether one of the section's own tables already lists every check (a validate section's per-quantity table: each
    check is named "<engine> <quantity> within tolerance" and its table has a row per quantity)."""
    names = [c["name"] for c in v.checks]
    for b in v.blocks:
        if isinstance(b, Table) and b.rows:
            first = {str(r[0]) for r in b.rows}
            if all(any(n.endswith(f" {q} within tolerance") or n == q for q in first) for n in names):
                return True
    return False


def checks_note(checks: list[dict]) -> Text:
    """What the checks table would add to a section whose own table lists its checks: their kinds and results."""
    guards = [c for c in checks if c.get("kind") == "regression guard"]
    text = (
        f"The table above lists this section's {len(checks)} checks ({checks_cell(checks)}); "
        "a physics check's allowance comes from the paper, the integrator or the timestep."
    )
    if guards:
        text += (
            " Regression guards (allowance from a measured spread: holding flags no change, it does not show the physics is right): "
            + "; ".join(f"{c['name']}: {'held' if c['passed'] else 'FAILED'}" for c in guards)
            + "."
        )
    return Text(text)


def _short(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


#: The findings lines and the rules behind their verdicts, written beside the report's data (derived, not computed).
FINDINGS = "findings.json"

RULES_TITLE = "How the verdicts are given (crosscheck.report.findings.RULES)"

_SUMMARY_CAPTION = (
    "Sections, in report order. Ran: whether the section's computation finished (ok), not whether an engine agrees "
    "with the theory. Checks: physics checks (allowance from the paper, the integrator or the timestep) apart from "
    "regression guards (allowance from a measured spread: holding means nothing changed, not that the physics is right). "
    "Finding: the verdict of the section's line(s) under Findings, by the rules given there."
)


def verdicts(found: list, slug: str) -> list[str]:
    """The distinct verdicts of the findings lines that come from section ``slug``, in order."""
    out = []
    for f in found:
        if f.slug == slug and f.verdict not in out:
            out.append(f.verdict)
    return out


def summary_table(summary_rows) -> Table:
    return Table(
        caption=_SUMMARY_CAPTION,
        header=["section", "paper", "ran", "run time", "checks", "finding"],
        rows=[r[0] for r in summary_rows],
        data=[f"data/{_REFERENCES}"],
        row_class=[r[1] for r in summary_rows],
    )


def checks_cell(checks: list[dict]) -> str:
    """Physics checks and regression guards counted apart: 'physics 3/3 passed; regression guards 1/1 held'."""
    out = []
    for kind, word, held in (("physics", "physics", "passed"), ("regression guard", "regression guards", "held")):
        cs = [c for c in checks if c.get("kind", "physics") == kind]
        if not cs:
            continue
        ok = sum(bool(c["passed"]) for c in cs)
        nf = sum(not c["passed"] and not c.get("known_discrepancy") for c in cs)
        nk = sum(not c["passed"] and bool(c.get("known_discrepancy")) for c in cs)
        out.append(
            f"{word} {ok}/{len(cs)} {held}"
            + (f", {nf} FAILED" if nf else "")
            + (f", {nk} known discrepanc{'y' if nk == 1 else 'ies'}" if nk else "")
        )
    return "; ".join(out)
