"""The report's bottom line: at most five sentences generated from the engine table's numbers, each with its rule.

Read from the records of ``crosscheck.report.engine_table`` at each engine's map setting; the verdicts are the
findings' (``crosscheck.report.findings.RULES``): an engine agrees when the lower end of its agreement's Wilson 95 %
interval is >= ``CONVERGED``, disagrees when the upper end is < ``NOT_CONVERGED``, is inconclusive otherwise.
Nothing here is written by hand about an engine: a new engine, or a changed number, changes the sentences.
"""

from __future__ import annotations

from dataclasses import dataclass

from crosscheck.report.engine_table import interval
from crosscheck.report.findings import CONVERGED, NOT_CONVERGED

__all__ = ["BOTTOM_LINE", "Sentence", "bottom_line", "verdict"]

#: The bottom line's sentences and rules, written beside the report's data (derived, not computed).
BOTTOM_LINE = "bottom_line.json"


@dataclass(frozen=True)
class Sentence:
    """One sentence of the bottom line and the rule that gave its verdict."""

    text: str
    rule: str


def verdict(r: dict) -> str:
    """The first-event verdict of a record: agrees, disagrees or inconclusive (``findings.RULES``)."""
    return "agrees" if r["ci_low"] >= CONVERGED else "disagrees" if r["ci_high"] < NOT_CONVERGED else "inconclusive"


def _name(r: dict) -> str:
    return r["label"] + (" (rigid)" if r["rigid"] else "")


_RULE = (
    f"first event: agrees when the 95 % interval's lower end is >= {100 * CONVERGED:.0f} %, disagrees when its upper "
    f"end is < {100 * NOT_CONVERGED:.0f} %, inconclusive otherwise"
)


def _closest(maps: list[dict]) -> tuple[dict, Sentence]:
    best = max(maps, key=lambda r: (r["ci_low"], r["agreement"]))
    return best, Sentence(
        f"Closest to the theory (highest lower end of the 95 % interval): {_name(best)}, the theory's first event on "
        f"{best['n_agree']} of {best['n_rated']} starts, {interval(best)}: {verdict(best)}.",
        "closest: the highest lower end of the Wilson 95 % interval; " + _RULE,
    )


def _pct(r: dict) -> str:
    return f"{100 * r['agreement']:.0f} %"


def _disagree(maps: list[dict]) -> Sentence | None:
    """The engines that disagree, grouped by the ladder's most named cause with the share its interventions confirm."""
    group = sorted((r for r in maps if verdict(r) == "disagrees"), key=lambda r: r["agreement"])
    if not group:
        return None
    by: dict[str, list[dict]] = {}
    for r in group:
        by.setdefault(r.get("top_cause") or "no ladder", []).append(r)
    parts = []
    for cause, rs in by.items():
        n, k = sum(r.get("top_cause_n", 0) for r in rs), sum(r.get("top_cause_confirmed", 0) for r in rs)
        names = ", ".join(
            f"{_name(r)} {_pct(r)}" + (f" (LAUNCH {r['n_launch']}/{r['n_rated']})" if r["n_launch"] else "") for r in rs
        )
        parts.append(f"{cause}" + (f" ({k}/{n} confirmed)" if n else "") + f": {names}")
    return Sentence(
        f"Disagree (upper end < {100 * NOT_CONVERGED:.0f} %), by the ladder's main cause: " + "; ".join(parts) + ".",
        _RULE + "; cause: the ladder's most named; confirmed: removed by that cause's intervention on the engine",
    )


def _rest(maps: list[dict], closest: dict) -> Sentence | None:
    """The engines that agree, and those neither shown to agree nor ruled out, in one sentence (the closest aside)."""
    rest = [r for r in maps if r is not closest]
    agree = [f"{_name(r)} {_pct(r)}" for r in rest if verdict(r) == "agrees"]
    open_ = [
        f"{_name(r)} {_pct(r)}" for r in sorted(rest, key=lambda r: r["agreement"]) if verdict(r) == "inconclusive"
    ]
    parts = ([f"Agree (lower end >= {100 * CONVERGED:.0f} %): {', '.join(agree)}"] if agree else []) + (
        [f"inconclusive (interval across {100 * NOT_CONVERGED:.0f}-{100 * CONVERGED:.0f} %): {', '.join(open_)}"]
        if open_
        else []
    )
    if not parts:
        return None
    text = "; ".join(parts)
    return Sentence(text[0].upper() + text[1:] + ".", _RULE)


def _jams(maps: list[dict]) -> Sentence | None:
    """The rigid engines' jams and every other engine that jams at under half the theory's jams, then the LAUNCHes."""
    rigid = [r for r in maps if r["n_theory_jam"] and r["rigid"]]
    low = [r for r in maps if r["n_theory_jam"] and not r["rigid"] and 2 * r["agree_theory_jam"] < r["n_theory_jam"]]
    launch = [r for r in maps if r["n_launch"]]
    if not rigid and not low and not launch:
        return None

    def counts(rs: list[dict], k: str, n: str) -> str:
        return ", ".join(f"{r['label']} {r[k]}/{r[n]}" for r in rs) or "none"

    text = f"At the theory's jams the rigid engines jam at {counts(rigid, 'agree_theory_jam', 'n_theory_jam')}"
    if low:
        text += f", and under half of them: {counts(low, 'agree_theory_jam', 'n_theory_jam')}"
    return Sentence(
        text + f"; LAUNCH (thrown off the plane while b < 0): {counts(launch, 'n_launch', 'n_rated')}.",
        "jams among the starts where the theory jams, for the rigid engines and every other engine below half; LAUNCH "
        "among all rated starts; each engine at its map setting",
    )


def _convergence(r: dict) -> str | None:
    """One verdict per engine: converges when one of its parameters does, does not when none converges and one does
    not, inconclusive otherwise."""
    vs = set((r.get("convergence") or {}).values())
    if not vs:
        return None
    return "converges" if "converges" in vs else "does not converge" if "does not converge" in vs else "inconclusive"


def _takeaway(maps: list[dict]) -> Sentence | None:
    by: dict[str, list[str]] = {}
    for r in maps:
        v = _convergence(r)
        if v is not None:
            by.setdefault(v, []).append(_name(r))
    if not by:
        return None
    parts = []
    if by.get("converges"):
        parts.append(f"a finer timestep or stiffer contact brings {', '.join(by['converges'])} to the theory")
    if by.get("does not converge"):
        parts.append(f"not {', '.join(by['does not converge'])}: their gap is the contact model's")
    if by.get("inconclusive"):
        parts.append(f"inconclusive for {', '.join(by['inconclusive'])}")
    return Sentence(
        f"Take-away (convergence: finest setting >= {100 * CONVERGED:.0f} % and not below the coarsest): "
        + "; ".join(parts) + ".",
        f"convergence, per parameter with the others held: converges when the finest setting agrees on >= "
        f"{100 * CONVERGED:.0f} % and not less than the coarsest; does not converge when below "
        f"{100 * NOT_CONVERGED:.0f} % or the coarsest; an engine converges when one of its parameters does",
    )  # fmt: skip


def bottom_line(records: list[dict]) -> list[Sentence]:
    """At most five sentences from the engine table's records (``engine_table.engine_records``); [] without one."""
    maps = [r for r in records if r["role"] == "map" and r["n_rated"]]
    if not maps:
        return []
    closest, first = _closest(maps)
    out = [
        first,
        _disagree(maps),
        _rest(maps, closest),
        _jams(maps),
        _takeaway(maps),
    ]
    return [s for s in out if s is not None][:5]
