"""The order a report's sections start in when they run side by side: longest known first, else the heads of the
longest ``after`` chains first (``crosscheck.report.pipeline`` runs them)."""

from __future__ import annotations

from pathlib import Path

from crosscheck.report import store as integrity
from crosscheck.report.section import Section
from crosscheck.report.store import read_status

__all__ = ["start_order", "waiting_on"]


def start_order(todo: list[Section], out: Path) -> list[Section]:
    """Longest first, by the time each took when it last ran in ``out``; sections never run there go ahead of those
    known, the heads of the longest chains first (most sections waiting on them through ``after``: an engine's maps
    before its ladder before its interventions), then in the declared order.  Two slots then finish close together
    (a fresh full report in the declared order left MuJoCo Warp's maps, ladder and interventions, 150 s of section
    time one after the other, for its last minutes)."""

    def last_seconds(s: Section) -> float:
        try:
            return float((read_status(out, s.slug) or {}).get("seconds") or float("inf"))
        except (integrity.DamagedResults, OSError, ValueError, TypeError):
            return float("inf")

    known = {s.slug: last_seconds(s) for s in todo}
    waiting = waiting_on(todo)
    return sorted(todo, key=lambda s: (-known[s.slug], -waiting[s.slug]))  # stable: ties keep the declared order


def waiting_on(todo: list[Section]) -> dict[str, int]:
    """How many sections of ``todo`` wait on each one, directly or through others (its ``after`` chains)."""
    later: dict[str, set[str]] = {s.slug: set() for s in todo}
    for s in todo:
        for a in s.after:
            if a in later:
                later[a].add(s.slug)

    def behind(slug: str, seen: set[str]) -> set[str]:
        for nxt in later[slug] - seen:
            seen.add(nxt)
            behind(nxt, seen)
        return seen

    return {slug: len(behind(slug, set())) for slug in later}
