"""The findings' lines read from saved results: the committed quick report's, and synthetic ones at each rule's parts.

``crosscheck.report.findings`` reads the saved results alone, so the quick report's own data rebuild the
``findings.json`` beside it line for line (a regression guard against the committed reference report, made at this
code: a change of a rule moves its lines, and then the report is regenerated with it).  The verdicts' thresholds are
in ``test_verdict_edges.py``; here, the parts of a line that a verdict does not show.
"""

from __future__ import annotations

import csv
import json
from dataclasses import asdict
from pathlib import Path

from crosscheck import engines
from crosscheck.report.finding import convergence_trends, convergence_verdict
from crosscheck.report.findings import RULES, findings

QUICK = Path(__file__).resolve().parents[1] / "reports" / "quick"


def test_the_findings_rebuilt_from_the_saved_results_are_the_saved_findings():
    saved = json.loads((QUICK / "data" / "findings.json").read_text())
    assert [asdict(f) for f in findings(QUICK / "data")] == saved["findings"]
    assert saved["rules"] == dict(RULES)


def _convergence(root: Path, engine: str, rows: list[tuple[float, float, float]]) -> None:
    """A saved convergence section of ``engine``: rows (timestep, timeconst, agreement)."""
    d = root / f"{engines.get(engine).slug}_convergence"
    d.mkdir(parents=True)
    (d / "status.json").write_text(json.dumps({"status": "ok", "params": {"engine": engine}}))
    with (d / "convergence.csv").open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["engine", "timestep", "timeconst", "agreement", "agreement_planar", "agreement_off_plane"])
        for ts, tc, a in rows:
            w.writerow([engine, ts, tc, a, a, a])


def test_a_convergence_section_saved_without_its_status_still_has_its_line(tmp_path):
    """A section's status (its parameters, naming the engine) may be missing, as in results saved before it was
    written: the line stands, for an engine the findings cannot name and do not call compliant."""
    _convergence(tmp_path, "mujoco", [(0.01, 0.06, 0.96), (0.005, 0.06, 0.97)])
    (tmp_path / f"{engines.get('mujoco').slug}_convergence" / "status.json").unlink()
    (f,) = [f for f in findings(tmp_path) if "convergence" in f.leg]
    assert f.leg == "?: convergence in timestep" and f.verdict == "converges"
    assert "compliant" not in f.text  # (MuJoCo's own line says its timestep's limit is the compliant model)


def _interventions(root: Path, engine: str, confirmed: int, attributed: int) -> None:
    d = root / f"{engines.get(engine).slug}_interventions"
    d.mkdir()
    per = {"geometry": {"none": attributed - confirmed, "by_other": {}, "by_other_starts": 0, "overdetermined": {}}}
    summary = {"engine": engine, "attributed": attributed, "confirmed": confirmed, "jointly": 0, "per_cause": per}
    summary["confirmed_share"] = confirmed / attributed
    (d / "summary.json").write_text(json.dumps(summary))


def test_the_every_engine_interventions_line_gives_the_counts_it_was_judged_by(tmp_path):
    _interventions(tmp_path, "bullet", 7, 10)
    _interventions(tmp_path, "mujoco", 9, 10)
    (f,) = [f for f in findings(tmp_path) if f.leg.startswith("every engine")]
    assert (f.verdict, f.why) == ("confirmed", "16 of 20 >= 80 % of 20 = 16")
    assert f.text.startswith("16 of 20 attributed disagreements (80.0 %) over 2 engines")
    assert (
        f.text.endswith("; lowest Bullet, 7 of 10 (70 %)") and f.slug == f"{engines.get('bullet').slug}_interventions"
    )
    _interventions(tmp_path, "dart", 0, 1)
    (f,) = [f for f in findings(tmp_path) if f.leg.startswith("every engine")]
    assert (f.verdict, f.why) == ("partly confirmed", "16 of 21 < 80 % of 21 = 16.8")


LABELS = ["SLIP", "LIFTOFF", "STICK", "JAM", "DIVERGED", "GB", "LAUNCH"]


def _maps(root: Path, engine: str, confusions: list[list[list[int]]]) -> None:
    """A saved map section of ``engine``, one map per confusion matrix (theory rows, engine columns, ``LABELS``)."""
    d = root / f"{engines.get(engine).slug}_maps"
    d.mkdir(parents=True)
    maps = [{"runs": [{"confusion": c, "labels": LABELS, "options": {"timestep": 1e-3}}]} for c in confusions]
    (d / "maps.json").write_text(json.dumps(maps))
    (d / "status.json").write_text(json.dumps({"status": "ok", "params": {"engine": engine}}))


def _confusion(cells: dict[tuple[str, str], int]) -> list[list[int]]:
    c = [[0] * len(LABELS) for _ in LABELS]
    for (theory, engine), n in cells.items():
        c[LABELS.index(theory)][LABELS.index(engine)] = n
    return c


def test_the_first_event_line_sums_every_map_and_says_what_the_engine_does_at_the_theorys_jams(tmp_path):
    """The maps' confusions are summed; the rated rows (SLIP, LIFTOFF, STICK, JAM) count, DIVERGED and GB rows do not;
    the JAM row is told column by column in the labels' order; a map set without a theory jam says 'none'."""
    a = _confusion({("SLIP", "SLIP"): 40, ("JAM", "SLIP"): 2, ("JAM", "JAM"): 5, ("GB", "SLIP"): 9})
    b = _confusion({("LIFTOFF", "LIFTOFF"): 10, ("JAM", "LAUNCH"): 3, ("DIVERGED", "DIVERGED"): 4})
    _maps(tmp_path, "pinocchio", [a, b])
    (f,) = [f for f in findings(tmp_path) if f.leg.endswith("first event")]
    assert f.text.startswith("same as the analytic one in 55 of 60 rated slipping starts (92 %")
    assert f.text.endswith("at the theory's jams: 2 slip, 5 jam, 3 launch")
    _maps(tmp_path / "none", "pinocchio", [_confusion({("SLIP", "SLIP"): 40, ("LIFTOFF", "SLIP"): 1})])
    (f,) = [f for f in findings(tmp_path / "none") if f.leg.endswith("first event")]
    assert f.text.endswith("(98 %, 95 % interval 87-100 %); at the theory's jams: none")


def test_the_papers_known_discrepancies_are_one_line_naming_their_sections(tmp_path):
    """Checks marked as known discrepancies (a misprint, a caption that does not fit its numbers) are counted over
    every section in one line, verdict "known", anchored at the first section that has one; none, no line."""
    for slug, checks in {
        "b_section": [{"name": "a", "passed": False, "known_discrepancy": True}, {"name": "b", "passed": True}],
        "a_section": [{"name": "c", "passed": True}],
        "c_section": [{"name": "d", "passed": False, "known_discrepancy": True}] * 2,
    }.items():
        (tmp_path / slug).mkdir()
        (tmp_path / slug / "checks.json").write_text(json.dumps(checks))
    (f,) = [f for f in findings(tmp_path) if f.leg == "the paper"]
    assert (f.verdict, f.slug) == ("known", "b_section")
    assert f.text.startswith("3 known discrepancies between what the paper prints and its own model")
    assert f.text.endswith("shown in b_section, c_section")
    (tmp_path / "b_section" / "checks.json").write_text("[]")
    (tmp_path / "c_section" / "checks.json").write_text("[]")
    assert not [f for f in findings(tmp_path) if f.leg == "the paper"]


def test_a_parameter_without_a_trend_leaves_the_next_parameters_trend(tmp_path):
    """No two timesteps share a contact time constant, so the timestep has no trend; the time constant still has its
    own, at the timestep that has two of its settings."""
    rows = [(0.01, 0.1, 0.80), (0.005, 0.05, 0.90), (0.005, 0.02, 0.97)]
    _convergence(tmp_path, "mujoco", rows)
    table = list(csv.DictReader((tmp_path / f"{engines.get('mujoco').slug}_convergence" / "convergence.csv").open()))
    (trend,) = convergence_trends(table)
    assert (trend.parameter, trend.fixed, trend.verdict) == ("timeconst", {"timestep": 0.005}, "converges")
    (f,) = [f for f in findings(tmp_path) if "convergence" in f.leg]
    assert f.leg == "MuJoCo: convergence in contact time constant (timestep 0.005)"


def test_the_convergence_verdict_gives_its_trend_in_percent_coarsest_first():
    rows = [{"agreement": "0.857"}, {"agreement": "0.886"}, {"agreement": "0.971"}]
    assert convergence_verdict(rows) == ("converges", "85.7 % -> 88.6 % -> 97.1 %")


def test_a_flat_trend_in_the_middle_band_is_inconclusive_not_falling():
    """The finest equal to the coarsest is not below it: at 92 % -> 92 % neither converged (>= 95 %) nor falling."""
    assert convergence_verdict([{"agreement": "0.92"}, {"agreement": "0.92"}])[0] == "inconclusive"
    assert convergence_verdict([{"agreement": "0.92"}, {"agreement": "0.9199"}])[0] == "does not converge"


def test_a_table_whose_settings_vary_nothing_gives_one_trend_in_the_timestep(tmp_path):
    _convergence(tmp_path, "pinocchio", [(0.001, 0.0, 0.9), (0.001, 0.0, 0.97)])
    (f,) = [f for f in findings(tmp_path) if "convergence" in f.leg]
    assert f.leg == "Pinocchio (rigid engine): convergence in timestep" and f.verdict == "converges"
    assert "as the timestep goes 0.001 -> 0.001" in f.text
