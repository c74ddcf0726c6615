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


def test_an_engine_with_only_its_maps_has_zero_counts_and_no_numbers_for_the_sections_it_did_not_run(tmp_path):
    """No liftoff, contact, ladder, interventions, rounding, impact or convergence section: their counts are 0 and
    their numbers missing (NaN, saved as null), never a count the engine did not earn."""
    d = tmp_path / f"{engines.get('pinocchio').slug}_maps"
    d.mkdir()
    labels = ["SLIP", "LIFTOFF", "STICK", "JAM", "DIVERGED", "GB", "LAUNCH"]
    conf = [[0] * 7 for _ in labels]
    conf[0][0], conf[3][3], conf[3][6] = 8, 1, 1
    (d / "maps.json").write_text(json.dumps([{"runs": [{"confusion": conf, "labels": labels, "options": {}}]}]))
    (rec,) = engine_records(tmp_path)
    counts = ("attributed", "confirmed", "confirmed_jointly", "top_cause_n", "top_cause_confirmed", "rounding_changed")
    assert all(rec[k] == 0 for k in (*counts, "rounding_n", "impact_n_jammed", "impact_n")), rec
    assert rec["top_cause"] == "" and rec["convergence"] == {}
    assert all(rec[k] == 0 for k in rec if k.startswith("ladder_"))
    missing = ("onset_max_abs_error_Psi", "friction_skew_median_deg", "cone_violation_max_mg")
    assert all(math.isnan(rec[k]) for k in (*missing, "impact_median_abs_Theta_plus_error", "runs_per_s"))
    assert (rec["n_rated"], rec["n_agree"], rec["n_theory_jam"], rec["agree_theory_jam"], rec["n_launch"]) == (
        10,
        9,
        2,
        1,
        1,
    )
