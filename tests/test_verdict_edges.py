"""Every verdict rule of the findings and the engine table at its edges, from synthetic saved results.

The rules (``crosscheck.report.findings.RULES``; the engine table holds the same numbers) read two numbers where a careless rule reads one: the first event
reads a Wilson interval, not its point estimate; convergence reads the finest setting against the coarsest, not the
finest alone; the shares of the ladder and the interventions are compared as counts at their threshold.  Each test
puts the two numbers on opposite sides of a threshold, and puts a value exactly on it.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from crosscheck import engines
from crosscheck.report.engine_table import engine_records, interval
from crosscheck.report.findings import CONVERGED, NOT_CONVERGED, convergence_verdict, findings
from crosscheck.report.sections.engine_interventions import CONFIRMED_SHARE

LABELS = ["SLIP", "LIFTOFF", "STICK", "JAM", "DIVERGED", "GB", "LAUNCH"]
#: The engine whose saved sections these tests write (any registered engine with a slug would do).
ENGINE = "pinocchio"


def _maps(root: Path, slug: str, k: int, n: int) -> Path:
    """A saved map section whose confusion has k of n rated slipping starts agreeing (the rest: engine LIFTOFF)."""
    d = root / slug
    d.mkdir(parents=True, exist_ok=True)
    conf = [[0] * len(LABELS) for _ in LABELS]
    conf[0][0], conf[0][1] = k, n - k
    run = {"confusion": conf, "labels": LABELS, "options": {"timestep": 1e-3}}
    (d / "maps.json").write_text(json.dumps([{"runs": [run]}]))
    (d / "status.json").write_text(json.dumps({"status": "ok", "params": {"engine": ENGINE}}))
    return d


def _convergence(root: Path, slug: str, agreements: list[float]) -> Path:
    """A saved convergence section: one setting per agreement, the timestep halving from the coarsest."""
    d = root / slug
    d.mkdir(parents=True, exist_ok=True)
    (d / "status.json").write_text(json.dumps({"status": "ok", "params": {"engine": ENGINE}}))
    with (d / "convergence.csv").open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["engine", "timestep", "timeconst", "agreement", "agreement_planar", "agreement_off_plane"])
        for i, a in enumerate(agreements):
            w.writerow([ENGINE, 1e-2 / 2**i, 0.0, a, a, a])
    return d


# ------------------------------------------------------------------------------------------ first event ---


@pytest.mark.parametrize(
    "k, n, verdict, why, cell",
    [
        # the point estimate says agree (>= 95 %) or disagree (< 90 %), the interval does not rule out the other
        (96, 100, "inconclusive", "lower end 90.2 % < 95 %, upper end 98.4 % >= 90 %", "96 % [90-98]"),
        (950, 1000, "inconclusive", "lower end 93.5 % < 95 %, upper end 96.2 % >= 90 %", "95 % [93-96]"),
        (85, 100, "inconclusive", "lower end 76.7 % < 95 %, upper end 90.7 % >= 90 %", "85 % [77-91]"),
        (9, 10, "inconclusive", "lower end 59.6 % < 95 %, upper end 98.2 % >= 90 %", "90 % [60-98]"),
        # the whole interval on one side
        (9000, 9400, "agrees", "lower end 95.3 % >= 95 %, upper end 96.1 % >= 90 %", "96 % [95-96]"),
        (860, 1000, "disagrees", "lower end 83.7 % < 95 %, upper end 88.0 % < 90 %", "86 % [84-88]"),
    ],
    ids=["point_agrees", "point_at_95", "point_disagrees", "point_at_90_few", "interval_agrees", "interval_below"],
)
def test_the_first_event_verdict_reads_the_interval_not_the_point_estimate(tmp_path, k, n, verdict, why, cell):
    _maps(tmp_path, f"{engines.get(ENGINE).slug}_maps", k, n)
    (f,) = [f for f in findings(tmp_path) if f.leg.endswith("first event")]
    assert (f.verdict, f.why) == (verdict, why)
    assert f"same as the analytic one in {k} of {n} rated slipping starts ({100 * k / n:.0f} %" in f.text
    (rec,) = engine_records(tmp_path)  # the engine table holds the same point estimate and interval
    assert (rec["n_agree"], rec["n_rated"]) == (k, n) and interval(rec) == cell


# ------------------------------------------------------------------------------------------ convergence ---


@pytest.mark.parametrize(
    "agreements, verdict",
    [
        ([0.99, 0.96], "does not converge"),  # finest >= 95 % but below the coarsest: agreement falls with refinement
        ([0.97, 0.949], "does not converge"),  # finest below both
        ([0.92, 0.91], "does not converge"),  # finest in the middle band, below the coarsest
        ([0.80, 0.899], "does not converge"),  # rising, but the finest below 90 %
        ([0.96, 0.96], "converges"),  # the finest equal to the coarsest is not less
        ([0.90, 0.95], "converges"),  # the finest exactly at 95 %
        ([0.80, 0.93], "inconclusive"),  # rising into the middle band
        ([0.85, 0.90], "inconclusive"),  # the finest exactly at 90 % is not below it
        ([0.97, 0.50, 0.96], "does not converge"),  # only the ends count: the finest below the coarsest
        ([0.50, 0.99, 0.96], "converges"),  # ... and here above it, whatever the middle did
    ],
)
def test_convergence_reads_the_finest_against_the_coarsest(tmp_path, agreements, verdict):
    rows = [{"agreement": str(a)} for a in agreements]
    assert convergence_verdict(rows)[0] == verdict
    # the findings line and the engine table's convergence cell give the same verdict, from the saved table
    slug = engines.get(ENGINE).slug
    _convergence(tmp_path, f"{slug}_convergence", agreements)
    (f,) = [f for f in findings(tmp_path) if "convergence" in f.leg]
    first, last = 100 * agreements[0], 100 * agreements[-1]
    assert f.verdict == verdict and f.why.startswith(
        f"finest {last:.1f} % {'>=' if last >= 100 * CONVERGED else '<'} 95 % and "
        f"{'>=' if agreements[-1] >= agreements[0] else '<'} the coarsest {first:.1f} %"
    )
    assert f.why.endswith("; < 90 %") == (agreements[-1] < NOT_CONVERGED)
    _maps(tmp_path, f"{slug}_maps", 95, 100)
    (rec,) = engine_records(tmp_path)
    assert rec["convergence"] == {"timestep": verdict}


# ---------------------------------------------------------------------------------------- lift-off onset ---


@pytest.mark.parametrize("failed, verdict", [(0, "agrees"), (1, "disagrees")])
def test_the_onset_verdict_needs_every_check(tmp_path, failed, verdict):
    d = tmp_path / "toy_liftoff"
    d.mkdir()
    checks = [
        {"name": f"mu = 0.{i}: onset = Psi_L", "passed": i >= failed, "value": 1e-7, "allowance": 1e-6}
        for i in range(3)
    ]
    (d / "checks.json").write_text(json.dumps(checks))
    (f,) = [f for f in findings(tmp_path) if f.leg.startswith("lift-off onset")]
    assert f.verdict == verdict and f.text.startswith(f"{3 - failed} of 3 onset checks")


# -------------------------------------------------------------------------------- ladder, interventions ---


@pytest.mark.parametrize("attributed, verdict", [(0.9, "explained"), (0.8999, "partly explained"), (1.0, "explained")])
@pytest.mark.parametrize("engine", ["mujoco", "bullet"])
def test_the_ladder_explains_from_90_percent_attributed(tmp_path, engine, attributed, verdict):
    slug = f"{engines.get(engine).slug}_ladder"
    (tmp_path / slug).mkdir()
    counts = {"geometry": 9, "unexplained": 1}
    summary = {"engine": engine, "n_disagree": 10, "n_disagreements_on_maps": 12, "attributed": attributed}
    (tmp_path / slug / "summary.json").write_text(json.dumps({**summary, "counts": counts}))
    (f,) = [f for f in findings(tmp_path) if f.slug == slug]
    assert f.leg.endswith("causes of disagreement") and f.verdict == verdict


def _interventions(root: Path, slug: str, engine: str, confirmed: int, attributed: int) -> None:
    (root / slug).mkdir()
    per = {"geometry": {"none": attributed - confirmed, "by_other": {}, "by_other_starts": 0, "overdetermined": {}}}
    summary = {
        "engine": engine,
        "attributed": attributed,
        "confirmed": confirmed,
        "confirmed_share": confirmed / attributed,
        "jointly": 0,
        "per_cause": per,
    }
    (root / slug / "summary.json").write_text(json.dumps(summary))


@pytest.mark.parametrize(
    "confirmed, attributed, verdict",
    [(4, 5, "confirmed"), (800, 1000, "confirmed"), (799, 1000, "partly confirmed"), (3, 4, "partly confirmed")],
)
def test_causes_are_confirmed_from_80_percent_per_engine_and_over_every_engine(
    tmp_path, confirmed, attributed, verdict
):
    assert CONFIRMED_SHARE == 0.8
    _interventions(tmp_path, "bullet_interventions", "bullet", confirmed, attributed)
    (own,) = [f for f in findings(tmp_path) if f.slug == "bullet_interventions"]
    assert own.verdict == verdict
    # over every engine: the counts summed, one engine's share above 80 % cannot hide another's below
    _interventions(tmp_path, "mujoco_interventions", "mujoco", attributed, attributed)
    (overall,) = [f for f in findings(tmp_path) if f.leg.startswith("every engine")]
    total = confirmed + attributed
    assert overall.verdict == ("confirmed" if total >= CONFIRMED_SHARE * 2 * attributed else "partly confirmed")
    assert overall.slug == "bullet_interventions"  # the lowest engine is named


# ------------------------------------------------------------------------------------------------- rounding ---


@pytest.mark.parametrize("changed, verdict", [(0, "agrees"), (1, "disagrees")])
def test_the_rounding_verdict_allows_no_start_to_move(tmp_path, changed, verdict):
    slug = f"{engines.get(ENGINE).slug}_rounding"
    (tmp_path / slug).mkdir()
    (tmp_path / slug / "summary.json").write_text(json.dumps({"engine": ENGINE, "changed": changed, "n": 500}))
    (f,) = [f for f in findings(tmp_path) if f.slug == slug]
    assert f.verdict == verdict and f.text.startswith(f"{changed} of 500")
