"""One line of the report's findings, and the verdict rules sections and the findings share.

``crosscheck.report.findings`` collects the lines; an engine's own sections (``Section.finding``) and the generic
engine sections write theirs with ``Finding`` and read their saved documents with ``read_json``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

__all__ = [
    "Finding",
    "Trend",
    "read_json",
    "convergence_verdict",
    "convergence_trends",
    "CONVERGED",
    "NOT_CONVERGED",
    "CONFIRMED_SHARE",
    "PARAMETER_WORDS",
]

#: Agreement at the finest timestep above which (and not below the coarsest) a convergence table "converges".
CONVERGED = 0.95
#: ... and below which it "does not converge".
NOT_CONVERGED = 0.90

#: Share of attributed disagreements their own cause's intervention must remove for the verdict "confirmed".
CONFIRMED_SHARE = 0.8


@dataclass(frozen=True)
class Finding:
    """One line: the leg, what was found, the verdict, and the section it comes from (its anchor)."""

    leg: str
    text: str
    verdict: str
    slug: str
    why: str = ""  # the rule applied to this line's numbers (shown beside the verdict)


@dataclass(frozen=True)
class Trend:
    """One parameter of a convergence table varied with the others held fixed: ``rows`` coarsest first."""

    parameter: str  # the column varied: "timestep" or "timeconst"
    fixed: dict  # the other varied columns and the value they are held at
    rows: list
    verdict: str
    why: str


#: A convergence table's columns that a setting varies, and their words.
PARAMETER_WORDS = {"timestep": "timestep", "timeconst": "contact time constant"}


def read_json(path: Path):
    """The JSON file at ``path``, or None when it is absent."""
    return json.loads(path.read_text()) if path.is_file() else None


def convergence_verdict(rows: list[dict]) -> tuple[str, str]:
    """(verdict, trend) of a convergence table's rows (coarsest setting first): *converges* when the finest agrees on
    >= ``CONVERGED`` and at least as much as the coarsest, *does not converge* when it is below ``NOT_CONVERGED`` or below
    the coarsest, *inconclusive* otherwise."""
    first, last = float(rows[0]["agreement"]), float(rows[-1]["agreement"])
    verdict = (
        "converges"
        if last >= CONVERGED and last >= first
        else "does not converge"
        if last < NOT_CONVERGED or last < first
        else "inconclusive"
    )
    return verdict, " -> ".join(f"{100 * float(r['agreement']):.1f} %" for r in rows)


def _why_convergence(rows: list[dict]) -> str:
    first, last = 100 * float(rows[0]["agreement"]), 100 * float(rows[-1]["agreement"])
    return (
        f"finest {last:.1f} % {'>=' if last >= 100 * CONVERGED else '<'} {100 * CONVERGED:.0f} % and {'>=' if last >= first else '<'} "
        f"the coarsest {first:.1f} %" + (f"; < {100 * NOT_CONVERGED:.0f} %" if last < 100 * NOT_CONVERGED else "")
    )


def convergence_trends(rows: list[dict]) -> list[Trend]:
    """One ``Trend`` per parameter (timestep, contact time constant) that the rows of a convergence table vary.

    Each parameter is read with the other varied parameters held at the value that has the most settings of it (ties:
    the finest), so a timestep trend is never mixed with a change of stiffness.  A parameter with no two settings at
    one value of the others has no trend.  A table whose settings vary nothing gives one trend in the timestep.
    """
    varied = [k for k in PARAMETER_WORDS if len({float(r[k]) for r in rows if r.get(k) not in (None, "")}) > 1]
    out = []
    for k in varied or ["timestep"]:
        others = [o for o in varied if o != k]
        groups: dict[tuple, list[dict]] = {}
        for r in rows:
            groups.setdefault(tuple(float(r[o]) for o in others), []).append(r)
        key = min(groups, key=lambda g: (-len({float(r[k]) for r in groups[g]}), g))
        group = sorted(groups[key], key=lambda r: -float(r[k]))
        if len(group) < 2 and varied:
            continue
        verdict, _ = convergence_verdict(group)
        out.append(Trend(k, dict(zip(others, key)), group, verdict, _why_convergence(group)))
    return out
