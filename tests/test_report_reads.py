"""What a reader of the report, the command line and the API sees: verdicts with their rules, no LaTeX labels, short
Markdown lines, a traceable revision, labelled outcomes, quiet library calls, a plot of any run.

Fast: synthetic saved results, or a few sections of the committed ``reports/quick`` re-rendered without recomputing.
"""

from __future__ import annotations

import csv
import html
import json
import shutil
from pathlib import Path

import pytest

QUICK = Path(__file__).resolve().parents[1] / "reports" / "quick"

# --------------------------------------------------------------- findings ---


def _convergence_dir(root: Path, engine: str, rows: list[tuple[float, float, float]]) -> Path:
    """A saved convergence section of ``engine``: rows (timestep, timeconst, agreement) as ``convergence_table`` writes them."""
    d = root / f"{engine}_convergence"
    d.mkdir(parents=True)
    (d / "status.json").write_text(json.dumps({"status": "ok", "params": {"engine": engine}}))
    with (d / "convergence.csv").open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["engine", "timestep", "timeconst", "agreement", "agreement_planar", "agreement_off_plane"])
        for ts, tc, a in rows:
            w.writerow([engine, ts, tc, a, a, a])
    return d


# The full report's MuJoCo settings: three timesteps at time constant 0.06, then the time constant shrinks at the finest timestep.
MUJOCO_FULL = [
    (0.003, 0.06, 0.827),
    (0.001, 0.06, 0.849),
    (0.0003, 0.06, 0.864),
    (0.0003, 0.02, 0.84),
    (0.0001, 0.02, 0.87),
    (0.0001, 0.006, 0.83),
]


def test_convergence_is_read_one_parameter_at_a_time(tmp_path):
    """The timestep's trend is read at one time constant (82.7 -> 84.9 -> 86.4 % at 0.06), the time constant's at one
    timestep, each with its own verdict; the timestep's line says its limit is the compliant model."""
    from crosscheck.report.findings import convergence_trends, findings

    _convergence_dir(tmp_path, "mujoco", MUJOCO_FULL)
    rows = list(csv.DictReader((tmp_path / "mujoco_convergence" / "convergence.csv").open()))
    trends = {t.parameter: t for t in convergence_trends(rows)}
    assert set(trends) == {"timestep", "timeconst"}
    assert [float(r["timestep"]) for r in trends["timestep"].rows] == [0.003, 0.001, 0.0003]
    assert trends["timestep"].fixed == {"timeconst": 0.06}
    assert [float(r["timeconst"]) for r in trends["timeconst"].rows] == [
        0.02,
        0.006,
    ]  # at timestep 1e-4 (ties: the finest)
    assert trends["timeconst"].fixed == {"timestep": 0.0001}
    conv = [f for f in findings(tmp_path) if "convergence" in f.leg]
    assert [f.leg for f in conv] == [
        "MuJoCo: convergence in timestep (contact time constant 0.06)",
        "MuJoCo: convergence in contact time constant (timestep 0.0001)",
    ]
    ts, tc = conv
    assert "rises 82.7 % -> 84.9 % -> 86.4 % as the timestep goes 0.003 -> 0.001 -> 0.0003" in ts.text
    assert "the timestep's limit is the compliant model, not the rigid theory" in ts.text
    assert ts.verdict == "does not converge" and ts.why.startswith("finest 86.4 % < 95 %")
    assert (
        "falls 87.0 % -> 83.0 % as the contact time constant goes 0.02 -> 0.006" in tc.text
        and tc.verdict == "does not converge"
    )


def test_a_rigid_engine_has_one_trend_in_the_timestep_and_no_compliant_limit(tmp_path):
    from crosscheck.report.findings import findings

    _convergence_dir(tmp_path, "pinocchio", [(0.01, 0.0, 0.857), (0.003, 0.0, 0.886), (0.001, 0.0, 0.971)])
    (conv,) = [f for f in findings(tmp_path) if "convergence" in f.leg]
    assert conv.leg == "Pinocchio (rigid engine): convergence in timestep" and conv.verdict == "converges"
    assert "compliant" not in conv.text and conv.why == "finest 97.1 % >= 95 % and >= the coarsest 85.7 %"


def test_the_first_event_verdict_gives_the_interval_ends_it_was_judged_by(tmp_path):
    """94 % of 300 is inconclusive because its interval's lower end is below 95 % and its upper end above 90 %; the line says so."""
    from crosscheck.report.findings import findings

    d = tmp_path / "toy_maps"
    d.mkdir()
    labels = ["SLIP", "LIFTOFF", "STICK", "JAM", "DIVERGED", "GB", "LAUNCH"]
    conf = [[0] * 7 for _ in labels]
    conf[0][0], conf[0][1] = 282, 18  # 282 of 300 = 94 %
    (d / "maps.json").write_text(json.dumps([{"runs": [{"confusion": conf, "labels": labels}]}]))
    (f,) = findings(tmp_path)
    assert f.verdict == "inconclusive" and "(94 %, 95 % interval 91-96 %)" in f.text
    assert f.why == "lower end 90.7 % < 95 %, upper end 96.2 % >= 90 %"


# ------------------------------------------------------------------ render ---

#: Sections of the committed quick report re-rendered by the tests: the ones the reader's audit named.
SECTIONS = ("p_region", "bifurcations", "gb_separatrix", "mujoco_maps", "mujoco_convergence", "pinocchio")


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    """A few sections of the committed quick report rendered from their saved results (nothing recomputed)."""
    from crosscheck.report import render
    from crosscheck.report.sections import all_sections

    out = tmp_path_factory.mktemp("quick")
    (out / "data").mkdir()
    for name in ("provenance.json", *[p.name for p in (QUICK / "data").glob("provenance.json.*")]):
        shutil.copy(QUICK / "data" / name, out / "data" / name)
    for slug in SECTIONS:
        shutil.copytree(QUICK / "data" / slug, out / "data" / slug)
    _seal_if_needed(out / "data")
    sections = [s for s in all_sections() if s.slug in SECTIONS]
    render(out, sections, jobs=1)
    return out


def _seal_if_needed(data: Path) -> None:
    """Seal copied status and provenance files when this checkout's store seals them and the committed data predates it."""
    try:
        from crosscheck.report.store import SEAL_SUFFIX, seal_of
    except ImportError:
        return
    for p in [data / "provenance.json", *data.glob("*/status.json")]:
        seal = p.with_name(p.name + SEAL_SUFFIX)
        if not seal.exists():
            seal.write_text(json.dumps(seal_of(p.read_bytes())))


def test_the_rules_behind_the_verdicts_are_in_the_report(rendered):
    from crosscheck.report.findings import RULES

    md, page = (rendered / "report.md").read_text(), (rendered / "index.html").read_text()
    for name, rule in RULES:
        assert f"- *{name}*: " in md and rule.split(";")[0] in " ".join(md.split())
        assert f"<dt>{html.escape(name)}</dt>" in page
    # the verdicts' colours: in the one stylesheet every page links
    css = (rendered / "style.css").read_text()
    assert '<link rel="stylesheet" href="style.css">' in page
    assert "lower end" in md and ".v-explained" in css and ".v-inconclusive" in css
    saved = json.loads((rendered / "data" / "findings.json").read_text())  # the findings' data beside them
    assert saved["rules"] == dict(RULES) and all(
        f["verdict"] and f["text"] in " ".join(md.split()) for f in saved["findings"]
    )
    assert "](data/findings.json)" in md


def test_no_line_of_the_markdown_is_over_400_characters(rendered):
    """Long raw JSON is linked, not inlined; prose is wrapped; a long table cell moves to a note (every page)."""
    lines = [ln for p in sorted(rendered.glob("*.md")) for ln in p.read_text().splitlines()]
    assert max(map(len, lines)) <= 400, max(lines, key=len)[:200]
    assert "validate JSON (crosscheck validate pinocchio --json): [raw_" in "\n".join(lines)
    linked = list((rendered / "figures" / "pinocchio").glob("raw_*.json"))
    assert linked and json.loads(linked[0].read_text())


def test_the_summary_names_no_latex_label_and_separates_ran_from_agrees(rendered):
    md = (rendered / "report.md").read_text()
    summary = md[md.index("## Summary") : md.index("## The paper's figures")]
    assert "fig:" not in summary and "ghastly" not in summary
    assert "| section | paper | ran | run time | checks | finding |" in summary
    row = next(line for line in summary.splitlines() if line.startswith("| MuJoCo |"))  # one row per engine page
    assert "| disagrees" in row and "| ok |" in row
    for page in rendered.glob("*.md"):  # captions and check names give the figure's number instead
        assert "fig:" not in page.read_text()
    refs = json.loads((rendered / "data" / "paper_references.json").read_text())
    assert "fig:my_ugly_simulations" in refs["sections"]["gb_separatrix"]  # the labels are kept in the data


def test_paper_references_keep_numbers_and_drop_labels():
    from crosscheck.report.references import paper_reference, unlabel

    ref = "Figs. 11 (fig:GBs_bif3) and 17 (fig:stabilty_on_GB); eq. K, Theorem 4.1"
    assert paper_reference(ref) == "Figs. 11 and 17; Theorem 4.1; 1 equation"
    assert (
        paper_reference("eqs. thetal, psil (section 3.3)", labels=True)
        == "section 3.3; equations, by their labels in the paper's source: thetal, psil"
    )
    assert unlabel("four critical points (fig:pandora: (d), (h))") == "four critical points (Fig. 19: (d), (h))"
    assert unlabel("(sec. 3.5, Fig. GBs_bif3 text); Fig. 13(a)") == "(sec. 3.5, Fig. 11 text); Fig. 13(a)"


def test_a_regression_guard_holds_it_does_not_pass_and_a_listed_check_is_not_tabled_twice():
    """A validate section's own table lists its checks: the generic checks table is replaced by a note that still says which
    are regression guards, and a guard that holds never reads 'passed'."""
    from crosscheck.report.format import SectionView
    from crosscheck.report.format import checks_note as _checks_note
    from crosscheck.report.format import checks_shown as _checks_shown
    from crosscheck.report.format import checks_table as _checks_table
    from crosscheck.report.section import Table

    checks = [
        {"name": "MuJoCo contact acc within tolerance", "passed": True, "kind": "physics"},
        {"name": "MuJoCo event disagreement within tolerance", "passed": True, "kind": "regression guard"},
    ]
    own = Table(caption="the checks", header=["check"], rows=[["contact acc"], ["event disagreement"]], data=["x.csv"])
    view = SectionView(section=None, status={"status": "ok"}, blocks=[own], checks=checks)
    assert _checks_shown(view)
    note = _checks_note(checks).text
    assert (
        "physics 1/1 passed; regression guards 1/1 held" in note
        and "MuJoCo event disagreement within tolerance: held" in note
    )
    assert not _checks_shown(
        SectionView(
            section=None, status={"status": "ok"}, blocks=[own], checks=checks + [{"name": "other", "passed": True}]
        )
    )
    results = {r[0]: r[4] for r in _checks_table(checks).rows}
    assert results == {
        "MuJoCo contact acc within tolerance": "passed",
        "MuJoCo event disagreement within tolerance": "held (no change; not a physics check)",
    }


def test_interactive_maps_tick_round_values_where_they_fall():
    import numpy as np

    from crosscheck.report.interactive import _ticks

    centres = 0.2 + (np.arange(7) + 0.5) * (1.3 / 7)  # cells of [0.2, 1.5]: centres 0.293, 0.479, ...
    ticks = _ticks(centres)
    assert [t for _, t in ticks] == ["0.5", "1", "1.5"]
    for pos, label in ticks:  # each label sits where its value is, in cells from the grid's outer edge
        assert pos == pytest.approx((float(label) - 0.2) / (1.3 / 7))


# -------------------------------------------------------------- provenance ---

ROOT = Path(__file__).resolve().parents[1]


def test_the_build_records_the_checkouts_revision(tmp_path):
    """setup.py's build_py writes the checkout's revision into the built package; outside a checkout nothing is written."""
    import subprocess
    import sys

    from crosscheck import _build

    head = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.strip()
    rev = _build.source_revision(ROOT)
    assert rev["revision"] == head and isinstance(rev["dirty"], bool) and rev["describe"].startswith(head[:12])
    assert _build.source_revision(tmp_path) is None and _build.write_build_info(tmp_path, tmp_path) is None
    assert not (tmp_path / _build.BUILD_INFO).exists()
    subprocess.run(
        [sys.executable, "setup.py", "-q", "build_py", "--build-lib", str(tmp_path / "lib")],
        cwd=ROOT,
        check=True,
        capture_output=True,
    )
    built = _build.build_info(tmp_path / "lib" / "crosscheck")
    assert built["revision"] == head and built["dirty"] == rev["dirty"] and built["built"]


def test_an_installed_package_names_the_revision_it_was_built_from(tmp_path, monkeypatch):
    from crosscheck import _build
    from crosscheck.report import provenance
    from crosscheck.report.provenance import revision_text as _revision

    package = tmp_path / "site-packages" / "crosscheck"
    package.mkdir(parents=True)
    read = _build.build_info
    monkeypatch.setattr(
        provenance, "_repo_root", lambda: tmp_path / "site-packages"
    )  # no pyproject.toml: not a checkout
    monkeypatch.setattr(_build, "build_info", lambda package_dir=None: read(package))
    assert provenance.git_revision() == {
        "revision": None,
        "dirty": None,
        "describe": "not a git checkout",
    }  # built from an sdist
    (package / _build.BUILD_INFO).write_text(
        json.dumps({"revision": "a" * 40, "dirty": False, "describe": "a" * 12, "built": "2026-01-01T00:00:00+00:00"})
    )
    git = provenance.git_revision()
    assert git["revision"] == "a" * 40 and git["dirty"] is False and git["source"] == "build"
    assert (
        _revision(git, {})
        == "a" * 40 + " (clean; installed package, revision recorded when it was built on 2026-01-01T00:00:00+00:00)"
    )
    assert (
        provenance.git_revision(tmp_path)["revision"] is None
    )  # an explicit directory is asked itself, never the build record


# --------------------------------------------------------------------- API ---


def test_an_outcome_prints_its_name_and_keeps_its_value():
    from crosscheck.outcome import Outcome

    assert str(Outcome.JAM) == "JAM" and f"{Outcome.LIFTOFF}" == "LIFTOFF" and f"{Outcome.JAM:d}" == "3"
    assert Outcome.JAM == 3 and int(Outcome.LAUNCH) == 6 and json.dumps([Outcome.STICK]) == "[2]"


def _sweep(progress):
    import crosscheck as cc
    from crosscheck import engines

    state = cc.SlipState(theta=1.1067, varphi=-1.8913, Theta=0.9, Psi=-0.1027, eta=2.1307)
    kwargs = {} if progress == "default" else {"progress": progress}
    return engines.get("mujoco").sweep(cc.Rod.scaled(3), [state] * 3, [0.5, 1.0, 1.4], horizon=0.3, **kwargs)


def test_a_library_sweep_draws_no_bar_unless_on_a_terminal_or_asked(capsys):
    """Under pytest standard error is not a terminal: the default draws nothing, progress=True draws the bar."""
    import sys

    from crosscheck.progress import enabled

    assert not sys.stderr.isatty() and enabled(None) is False and enabled(True) is True and enabled(False) is False

    class Terminal:
        def isatty(self):
            return True

    assert enabled(None, Terminal()) is True
    _sweep("default")
    assert capsys.readouterr().err == ""
    _sweep(True)
    assert "mujoco sweep" in capsys.readouterr().err


def test_a_sweep_is_a_labelled_data_frame():
    res = _sweep(False)
    df = res.to_pandas()
    assert list(df["outcome"].astype(str)) == [o.name for o in map(__import__("crosscheck").Outcome, res.outcome)]
    assert list(df["mu"]) == [0.5, 1.0, 1.4] and {"theta", "varphi", "Theta", "Psi", "eta", "event_time"} <= set(
        df.columns
    )
    counts = df["outcome"].value_counts()
    assert counts["LAUNCH"] == 0 and counts.sum() == 3  # every outcome is a category, even one that did not occur


# -------------------------------------------------------------- the CLI ---

from crosscheck import engines as _engines  # noqa: E402

#: The paper's IC2 (Fig. 20): the theory lifts off at t = 0.0165.
IC2 = ["--theta", "1.1031", "--varphi", "-1.9233", "--Theta", "0.9", "--Psi", "0", "--eta", "2.0", "--mu", "1.4"]


@pytest.mark.parametrize("engine", _engines.names(), ids=str)
def test_simulate_plots_and_tabulates_a_run_of_every_engine(engine, tmp_path, capsys):
    """--plot writes the figure with the run's and the theory's CSV beside it; the CSV's first row is the start."""
    from PIL import Image

    from crosscheck.cli import main

    png = tmp_path / "run.png"
    assert (
        main(
            [
                "simulate",
                "--engine",
                engine,
                *IC2,
                "--horizon",
                "0.05",
                "--plot",
                str(png),
                "--csv",
                str(tmp_path / "run_record.csv"),
            ]
        )
        == 0
    )
    assert f"wrote {png}" in capsys.readouterr().out
    with Image.open(png) as im:
        assert im.format == "PNG" and im.size[0] > 1000
    rows = list(csv.DictReader((tmp_path / "run_record.csv").open()))
    assert float(rows[0]["theta"]) == pytest.approx(1.1031, abs=1e-9) and float(rows[-1]["t"]) <= 0.05 + 1e-6
    theory = list(csv.DictReader((tmp_path / "run_theory.csv").open()))
    assert float(theory[0]["eta"]) == pytest.approx(2.0) and float(theory[-1]["t"]) == pytest.approx(
        0.0165399, rel=1e-4
    )  # its lift-off


def test_a_slip_says_how_much_of_its_end_the_classifier_cannot_judge(capsys):
    """SLIP is "no event judged", and the JAM and LAUNCH rules judge no row whose window passes the end: ``simulate``
    names that tail (the classifier's window at the run's timestep), and a run shorter than the window says so."""
    from crosscheck.cli import main
    from crosscheck.engines.thresholds import Thresholds

    dt = _engines.get("mujoco").options().timestep
    below_mu_P = [*IC2[:-2], "--mu", "0.5"]  # IC2 at mu 0.5 slips through 0.3 in MuJoCo
    assert main(["simulate", "--engine", "mujoco", *below_mu_P, "--horizon", "0.3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    tail = Thresholds().window_rows(dt) * dt
    assert out["outcome"] == "SLIP" and out["unjudged_tail"] == pytest.approx(tail, rel=1e-12)
    assert main(["simulate", "--engine", "mujoco", *below_mu_P, "--horizon", "0.3"]) == 0
    assert f"an event in its last {tail:.3g} can be missed (the classifier's window)" in capsys.readouterr().out
    assert main(["simulate", "--engine", "drake_sap", *IC2, "--horizon", "2", "--timestep", "1"]) == 0
    assert (
        capsys.readouterr().out.strip()
        == "drake_sap: SLIP  (horizon 2, 2 steps; shorter than the classifier's window: any event can be missed)"
    )


def test_explain_plots_every_rung(tmp_path, capsys):
    from crosscheck.cli import main

    png = tmp_path / "ladder.png"
    assert main(["explain", "--engine", "bullet", *IC2, "--plot", str(png)]) == 0
    doc = json.loads(png.with_suffix(".json").read_text())
    assert png.stat().st_size > 10_000 and len(doc["rungs"]) >= 2 and doc["cause"] in capsys.readouterr().out


def test_the_validate_table_stays_aligned_and_prints_no_nan():
    """A quantity name longer than the old 28-character column and a count check (no relative error) keep every column in place."""
    from crosscheck.error_stats import ErrorStat, ValidationResult

    stats = [
        ErrorStat("median |event time difference|", 300, 0.012, 0.5, 0.4, {"theta": 1.0}, {}, True),
        ErrorStat("jams below mu_P", 300, 0.0, float("nan"), 0.0, {"theta": 0.5}, {}, True),
    ]
    lines = ValidationResult("mujoco", stats).to_table().splitlines()
    head, rows = lines[1], lines[3:5]
    assert "nan" not in "\n".join(lines)
    for col in ("max abs", "max rel", "/tol", "result"):
        at = head.index(col) + len(col)  # right-aligned numbers end where their header ends
        if col != "result":
            assert all(r[at - 1] != " " and r[at] == " " for r in rows), (col, rows)
    assert rows[1].split()[5:7] == ["-", "0.000"]  # after "jams below mu_P 300 0.00e+00": max rel, /tol


def test_the_readme_counts_the_bad_inputs_the_audit_runs(tmp_path):
    import re
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    import bad_inputs

    n_cli, n_api = (
        int(x)
        for x in re.search(
            r"\((\d+) command lines and (\d+) API calls\)", " ".join((ROOT / "README.md").read_text().split())
        ).groups()
    )
    assert (n_cli, n_api) == (len(list(bad_inputs.cli_cases(tmp_path))), len(list(bad_inputs.api_cases())))


def test_the_readmes_first_lines_are_the_two_commands():
    assert (ROOT / "README.md").read_text().splitlines()[:2] == [
        'python3 -m pip install ".[all]" && crosscheck report',
        'python3 -m pip install ".[test]" && python3 -m pytest -q',
    ]


def test_the_readme_opens_short_with_the_figure_and_links_every_concept_in_docs():
    """At most 250 words before the README's first section, among them the report's first figure (the path the report
    writes) and a link to each concept page; the reading guide defines every column the engine table footnotes."""
    from crosscheck.report.engine_table import FOOTNOTES
    from crosscheck.report.first_figure import STEM

    readme = (ROOT / "README.md").read_text()
    opening = readme[: readme.index("\n## ")]
    assert len(opening.split()) <= 250
    assert f"](reports/quick/{STEM}.png)" in opening
    for doc in ("theory", "engines", "ladder-and-interventions", "reading-the-report"):
        assert f"](docs/{doc}.md)" in opening and (ROOT / "docs" / f"{doc}.md").is_file()
    guide = (ROOT / "docs" / "reading-the-report.md").read_text()
    assert all(f"| {k} |" in guide for k, _ in FOOTNOTES)
