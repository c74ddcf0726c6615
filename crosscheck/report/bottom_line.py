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

__all__ = ["Sentence", "bottom_line", "verdict"]


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


def _mechanism(r: dict) -> str:
    """The ladder's most named cause of an engine's disagreements, how many its intervention confirmed, its LAUNCHes."""
    parts = []
    if r.get("top_cause_n"):
        parts.append(f"{r['top_cause']}, {r['top_cause_confirmed']}/{r['top_cause_n']} confirmed")
    if r["n_launch"]:
        parts.append(f"LAUNCH {r['n_launch']}/{r['n_rated']}")
    return f" ({'; '.join(parts)})" if parts else ""


_RULE = (
    f"first event: agrees when the 95 % interval's lower end is >= {100 * CONVERGED:.0f} %, disagrees when its upper "
    f"end is < {100 * NOT_CONVERGED:.0f} %, inconclusive otherwise"
)


def _closest(maps: list[dict]) -> Sentence:
    best = max(maps, key=lambda r: (r["ci_low"], r["agreement"]))
    return Sentence(
        f"Closest to the theory (highest lower end of the 95 % interval): {_name(best)}, the theory's first event on "
        f"{best['n_agree']} of {best['n_rated']} starts, {interval(best)}: {verdict(best)}.",
        "closest: the highest lower end of the Wilson 95 % interval; " + _RULE,
    )


def _items(maps: list[dict], word: str, *, mechanism: bool) -> list[str]:
    group = sorted((r for r in maps if verdict(r) == word), key=lambda r: r["agreement"])
    return [f"{_name(r)} {interval(r)}" + (_mechanism(r) if mechanism else "") for r in group]


def _disagree(maps: list[dict]) -> Sentence | None:
    items = _items(maps, "disagrees", mechanism=True)
    if not items:
        return None
    return Sentence(
        f"Disagree (upper end < {100 * NOT_CONVERGED:.0f} %; the ladder's main cause, confirmed by intervention): "
        + ", ".join(items) + ".",
        _RULE + "; cause: the ladder's most named, confirmed when its intervention on the engine removes it",
    )  # fmt: skip


def _rest(maps: list[dict]) -> Sentence | None:
    """The engines that agree, and those neither shown to agree nor ruled out, in one sentence."""
    agree, open_ = _items(maps, "agrees", mechanism=False), _items(maps, "inconclusive", mechanism=False)
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
    """The rigid engines' jams and every engine that jams at under half the theory's jams, then the LAUNCHes."""
    shown = [r for r in maps if r["n_theory_jam"] and (r["rigid"] or 2 * r["agree_theory_jam"] < r["n_theory_jam"])]
    launch = [r for r in maps if r["n_launch"]]
    if not shown and not launch:
        return None
    jams = ", ".join(f"{_name(r)} {r['agree_theory_jam']}/{r['n_theory_jam']}" for r in shown)
    tail = ", ".join(f"{_name(r)} {r['n_launch']}/{r['n_rated']}" for r in launch) or "none"
    return Sentence(
        f"At the theory's jams (rigid engines, and any jamming at under half): {jams or 'none'}; LAUNCH (thrown off "
        f"the plane while b < 0): {tail}.",
        "jams among the starts where the theory jams, for the rigid engines and every engine below half; LAUNCH "
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
        parts.append(f"it does not for {', '.join(by['does not converge'])}: their gap is the contact model's")
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
    out = [
        _closest(maps),
        _disagree(maps),
        _rest(maps),
        _jams(maps),
        _takeaway(maps),
    ]
    return [s for s in out if s is not None][:5]
