"""The engine table read back from the committed quick report's saved results: its records and every string it shows.

``crosscheck.report.engine_table`` derives its records from the saved results alone and every displayed string from
the records, so the quick report's own data rebuild, byte for byte, the ``engine_table.json`` and ``.csv`` beside it
and the rows its pages show.  A regression guard against the committed reference report (``reports/quick``, made at
this code): a change of a rule moves these numbers, and then the report is regenerated with it.  The rules' edges
(the interval, the convergence verdict) are in ``test_verdict_edges.py``; here, what the saved results alone decide.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from crosscheck import engines
from crosscheck.report.engine_table import (
    FOOTNOTES,
    best_setting,
    engine_facts,
    engine_records,
    interval,
    pct,
    settings_table,
    summary_table,
    write_engine_data,
)

QUICK = Path(__file__).resolve().parents[1] / "reports" / "quick"


@pytest.fixture(scope="module")
def records():
    return engine_records(QUICK / "data")


def _md_rows(path: Path) -> set[str]:
    return {ln for ln in path.read_text().splitlines() if ln.startswith("| ")}


def _md(row: list[str]) -> str:
    return "| " + " | ".join(row) + " |"


def test_the_records_rebuilt_from_the_saved_results_are_the_saved_engine_table(records, tmp_path):
    (tmp_path / "data").mkdir()
    write_engine_data(tmp_path, records)
    for name in ("engine_table.json", "engine_table.csv"):
        assert (tmp_path / "data" / name).read_text() == (QUICK / "data" / name).read_text(), name


def test_the_summary_rows_are_the_ones_the_report_shows(records):
    table = summary_table(records)
    shown = _md_rows(QUICK / "report.md")
    assert len(table.rows) == len([r for r in records if r["role"] == "map"]) > 1
    assert all(_md(row) in shown for row in table.rows), [r for r in table.rows if _md(r) not in shown]
    assert _md(table.header) in shown
    assert table.notes == [f"{k}: {v}" for k, v in FOOTNOTES]
    assert all(f"- {n}" in (QUICK / "report.md").read_text().splitlines() for n in table.notes)


def test_each_engine_page_shows_its_settings_and_its_facts(records):
    names = [r["engine"] for r in records if r["role"] == "map"]
    for name in names:
        page = QUICK / f"engine_{engines.get(name).slug}.md"
        table, shown = settings_table(records, name), _md_rows(page)
        assert len(table.rows) == len([r for r in records if r["engine"] == name])
        assert all(_md(row) in shown for row in table.rows), (name, [r for r in table.rows if _md(r) not in shown])
        assert _md(table.header) in shown and all(f"- {n}" in page.read_text().splitlines() for n in table.notes)
        assert len(table.notes) == 2  # the two columns a reader cannot guess: the event-time error and us/step
        (rec,) = [r for r in records if r["engine"] == name and r["role"] == "map"]
        text = " ".join(page.read_text().split())  # (the page wraps a long line)
        assert all(f"- {x} - " in text for x in engine_facts(rec)[:-1]), (name, engine_facts(rec))
        assert f"- {engine_facts(rec)[-1]}" in text


def test_the_best_setting_is_the_convergence_setting_of_highest_agreement_then_the_cheaper():
    recs = [
        {"engine": "e", "role": "map", "n_rated": 10, "agreement": 1.0, "runs_per_s": 9.0},
        {"engine": "e", "role": "convergence", "n_rated": 10, "agreement": 0.8, "runs_per_s": 5.0, "id": 1},
        {"engine": "e", "role": "convergence", "n_rated": 10, "agreement": 0.9, "runs_per_s": 1.0, "id": 2},
        {"engine": "e", "role": "convergence", "n_rated": 10, "agreement": 0.9, "runs_per_s": 2.0, "id": 3},
        {"engine": "e", "role": "convergence", "n_rated": 0, "agreement": math.nan, "runs_per_s": 9.0, "id": 4},
        {"engine": "f", "role": "convergence", "n_rated": 10, "agreement": 1.0, "runs_per_s": 9.0, "id": 5},
    ]
    assert best_setting(recs, "e")["id"] == 3  # not the map row, not another engine's, not a grid with no rated start
    assert best_setting(recs[:1], "e") is None


def test_a_share_and_an_interval_print_as_the_report_prints_them():
    assert (pct(0.834), pct(None), pct(math.nan), pct(1.0)) == ("83 %", "-", "-", "100 %")
    rec = {"n_rated": 149, "agreement": 0.8255, "ci_low": 0.7565, "ci_high": 0.8775}
    assert interval(rec) == "83 % [76-88]" and interval({"n_rated": 0}) == "-"


def test_the_saved_records_hold_numbers_with_none_for_a_missing_one(records):
    saved = json.loads((QUICK / "data" / "engine_table.json").read_text())
    for rec, out in zip(records, saved):
        for k, v in rec.items():
            if isinstance(v, float) and not math.isfinite(v):
                assert out[k] is None, k
