"""The report: the quick report runs and writes every figure, table and data file; it rebuilds from
saved results alone; it records its provenance; a failing section is shown, keeps its partial
results and makes the command exit non-zero."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import re
import shutil
import subprocess
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest

from crosscheck import engines, report
from crosscheck.cli import main
from crosscheck.report.provenance import all_tolerances
from crosscheck.report.section import Figure, Section, Table
from crosscheck.report.store import SectionStore
from crosscheck.theory.paper import PRINTED

#: Every figure the report must contain (stem under figures/<section>/), by paper figure.
EXPECTED_FIGURES = {
    "p_region": ["fig2a_p_region_space", "fig2b_p_region"],
    "mode_maps": ["fig3a_modes_planar", "slices_theta_Theta", "slices_theta_varphi"],
    "kinematic_surfaces": ["fig3_surfaces", "fig4_surfaces", "fig5_surfaces", "fig6_surfaces", "fig7_surfaces"],
    "kinematic_cases": ["fig9a_cases"],
    "bifurcations": ["fig21_curves", "fig21_strata"],
    "mechanisms": ["fig9b_mechanisms"],
    "critical_angles": ["fig10_critical_angles"],
    "printed_numbers": [],
    "gb_manifold": ["fig11_gb_manifolds", "fig17_gb_stability"],
    "gb_eigenvectors": ["fig12_eigenvectors", "fig13_eigenvectors"],
    "gb_local": ["fig14_local_dynamics", "fig15_local_dynamics"],
    "gb_quartic": ["fig16_quartic"],
    "gb_det_zeros": ["fig18_det_zeros", "fig19_eigenvectors"],
    "gb_separatrix": ["fig20_separatrix"],
    "pinocchio": ["error_vs_theta"],
    "mujoco_liftoff": ["liftoff_onset"],
    "mujoco_trajectories": ["trajectories"],
    "mujoco_validate": [],
    "rigid_engine": ["jams", "trajectory_jam"],
    "friction_skew": ["skew"],
    "compliant_limit": ["slip_stop_time", "restitution", "jam_convergence"],
    "bullet_azimuth": ["azimuth"],
}
# the sections generated for every registered engine from its report plan, with the figures each draws
for _spec in engines.specs():
    _plan = _spec.report
    if _plan is not None and _plan.maps is not None:
        EXPECTED_FIGURES[f"{_spec.slug}_maps"] = [
            "map_Psi_mu",
            "map_theta_Theta_0",
            "map_theta_Theta_1",
            "confusion",
            "event_time_errors",
        ]
        EXPECTED_FIGURES[f"{_spec.slug}_contact"] = ["contact_quality"]
        EXPECTED_FIGURES[f"{_spec.slug}_ic"] = ["ic"]
        EXPECTED_FIGURES[f"{_spec.slug}_impact"] = []
        EXPECTED_FIGURES[f"{_spec.slug}_psi"] = []
        if _plan.onset:
            EXPECTED_FIGURES[f"{_spec.slug}_liftoff"] = []
    if _plan is not None and _plan.convergence is not None:
        EXPECTED_FIGURES[f"{_spec.slug}_convergence"] = ["convergence"]
    if _plan is not None and _plan.maps is not None:
        EXPECTED_FIGURES[f"{_spec.slug}_rounding"] = []
    if _plan is not None and _plan.ladder and _plan.maps is not None:
        EXPECTED_FIGURES[f"{_spec.slug}_ladder"] = [
            "causes_Psi_mu",
            "causes_theta_Theta_0",
            "causes_theta_Theta_1",
            "ic2_rungs",
        ]
    if _plan is not None and _spec.interventions and _plan.ladder and _plan.maps is not None:
        EXPECTED_FIGURES[f"{_spec.slug}_interventions"] = ["interventions"]

EXPECTED_FIGURES["impact_engines"] = ["theta_plus"]
EXPECTED_FIGURES["psi_engines"] = ["outcome_shares"]
if "newton_mujoco" in engines.names():  # Newton's own section: MuJoCo Warp against MuJoCo in C, a table, no figure
    EXPECTED_FIGURES["newton_mujoco_c"] = []

#: Sections the quick report skips (shown as skipped, with the reason): full report only.
FULL_ONLY = {"mujoco_validate"}


def _head() -> str:
    return subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=Path(report.__file__).parents[2], capture_output=True, text=True
    ).stdout.strip()


#: HEAD just before the quick report ran (the work tree is shared: a commit may land during the run).
HEADS: list[str] = []


#: The committed reference report the suite checks (``crosscheck report --quick --out reports/quick``).
COMMITTED = Path(__file__).resolve().parents[1] / "reports" / "quick"

#: The studies every engine's sections run (``<engine>_<study>``): the suite recomputes the cheapest section of each.
STUDIES = ("maps", "contact", "liftoff", "ic", "impact", "psi", "rounding", "convergence", "ladder", "interventions")

#: Seconds, as the committed report recorded them, of the sections the suite recomputes whatever their provenance:
#: the cheapest of each study (and a second map section of the same grids), then the cheapest of the others (the
#: theory's sections first) while the sum stays within this (a budget for the suite's time, not physics): ~70 of the
#: 172 sections.
RECOMPUTED_SECONDS = 12.0


def _recomputed(prov: dict) -> list[str]:
    """The committed report's sections ``quick`` recomputes (``RECOMPUTED_SECONDS``)."""
    cheapest = sorted(prov["section_seconds"].items(), key=lambda kv: (kv[1], kv[0]))
    ours = {e.slug for e in engines.specs()}
    chosen = [next(slug for slug, _ in cheapest if slug in {f"{e}_{study}" for e in ours}) for study in STUDIES]
    # and the cheapest other map section of the same grids: two engines that share the theory's kept events
    grid = report.section_by_slug(chosen[0]).params(True)["maps"]
    chosen.append(
        next(
            slug
            for slug, _ in cheapest
            if slug != chosen[0]
            and slug in {f"{e}_maps" for e in ours}
            and report.section_by_slug(slug).params(True)["maps"] == grid
        )
    )
    total = sum(prov["section_seconds"][slug] for slug in chosen)
    for slug, seconds in cheapest:
        if slug not in chosen:
            if total + seconds > RECOMPUTED_SECONDS:
                break
            chosen.append(slug)
            total += seconds
    return chosen


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    """The committed quick report, checked and rendered again: (directory, render summary, sections recomputed).

    A copy of ``reports/quick`` as a clean checkout holds it (no sweeps) is resumed as ``crosscheck report --quick``
    resumes a report: a section computed by other code (any change to the package or to a computing library's
    version), other parameters or another seed is recomputed, and so is every section of ``_recomputed``; the others
    are kept, their provenance (``status.json``: the code's sha256) saying this code computed them.  The numbers of
    the result are then compared with the committed ones (``test_the_committed_quick_report_is_current``)."""
    out = tmp_path_factory.mktemp("report") / "quick"
    shutil.copytree(COMMITTED, out, ignore=shutil.ignore_patterns("sweeps", ".lock"))
    recomputed = _recomputed(json.loads((COMMITTED / "data" / "provenance.json").read_text()))
    for slug in recomputed:
        for name in ("status.json", "status.json.sha256"):
            (out / "data" / slug / name).unlink(missing_ok=True)
    HEADS.append(_head())
    report.run(out, report.SECTIONS, quick=True, resume=True)  # `crosscheck report --quick --out DIR`, views kept
    summary = report.render(out, report.SECTIONS)
    HEADS.append(_head())
    resumed = set(json.loads((out / "data" / "provenance.json").read_text())["sections_resumed"])
    return out, summary, {s.slug for s in report.SECTIONS} - resumed


@pytest.fixture(scope="module")
def views(quick):
    """The quick report's sections as rendered."""
    return {v.section.slug: v for v in quick[1].views}


def _digest(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


def test_every_section_is_listed_in_the_expected_figures():
    # a new section must say which figures it draws, so that this test guards them
    assert {s.slug for s in report.SECTIONS} == set(EXPECTED_FIGURES)


def test_quick_report_succeeds_and_every_section_ran(quick):
    out, summary, _ = quick
    assert summary.failures == [], (out / "report.md").read_text()[:3000]
    for s in report.SECTIONS:
        st = json.loads((out / "data" / s.slug / "status.json").read_text())
        assert st["status"] == ("skipped" if s.slug in FULL_ONLY else "ok"), (s.slug, st.get("error"))
        assert st["checks_failed"] == []
        if s.slug in FULL_ONLY:
            assert "full report only" in st["reason"]


def test_every_section_was_computed_by_this_code_with_the_quick_parameters(quick):
    """Each section's results, kept or recomputed, name the sha256 of the code that computed them: this code's (the
    package and its computing libraries' versions), at this seed and these parameters; the cheapest were recomputed."""
    from crosscheck.report.pipeline import code_digest

    out, _, recomputed = quick
    code = code_digest()
    for s in report.SECTIONS:
        st = json.loads((out / "data" / s.slug / "status.json").read_text())
        assert (st["code_sha256"], st["seed"], st["quick"]) == (code, 0, True), s.slug
        assert st["params"] == json.loads(json.dumps(s.params(True), default=str)), s.slug
    chosen = set(_recomputed(json.loads((COMMITTED / "data" / "provenance.json").read_text())))
    assert chosen <= recomputed and {slug.rsplit("_", 1)[-1] for slug in chosen} >= set(STUDIES)


def test_the_code_digest_reads_the_model_behind_the_checkouts_link():
    # a checkout's crosscheck/_models is a link to models/; an installed package holds a copy: the same files either way
    from crosscheck.report.pipeline import code_files

    names = {p.as_posix() for p in code_files()}
    assert "_models/rod.xml" in names and "report/pipeline.py" in names
    assert not any("__pycache__" in n or not n.endswith((".py", ".xml")) for n in names)


def test_engines_mapping_one_grid_share_one_kept_theory_and_read_the_same_analytic_events(quick):
    """Each map grid's analytic events are integrated once and kept under the sweeps directory (``RunContext.shared``):
    one file per grid the recomputed map sections map, and every engine's events table of that grid holds the same
    analytic columns, bit for bit (the recomputed ones and the committed ones)."""
    import csv

    out, _, recomputed = quick
    kept = sorted((out / "sweeps" / "analytic_events").glob("*.npz"))
    maps = sorted(p for p in (out / "data").glob("*_maps") if (p / "maps.json").is_file())
    grids: dict = {}
    for m in maps:
        for mp in json.loads((m / "maps.json").read_text()):
            rows = list(csv.DictReader((m / f"events_{mp['name']}.csv").open()))
            cols = [
                (
                    r["theta"],
                    r["Theta"],
                    r["Psi"],
                    r["mu"],
                    r["analytic_outcome"],
                    r["analytic_time"],
                    r["analytic_reason"],
                )
                for r in rows
            ]
            grids.setdefault(json.dumps([mp["name"], mp["x"], mp["y"], mp["fixed"]], sort_keys=True), []).append(
                (m.name, cols)
            )
    shared = [g for g in grids.values() if len(g) > 1]
    assert len(maps) >= 8 and shared  # eight engines map the quick grids
    for g in shared:
        assert all(cols == g[0][1] for _, cols in g[1:]), [name for name, _ in g]
    # one kept file per distinct grid (its axes' values in the key above) the recomputed sections map, however many
    # of them map it
    ran = [[name for name, _ in g if name in recomputed] for g in grids.values()]
    assert (
        len([p for p in kept if not p.name.startswith("convergence-")])
        == len([r for r in ran if r])
        < sum(len(r) for r in ran)
    )


@pytest.mark.parametrize("section", report.SECTIONS, ids=lambda s: s.slug)
def test_every_figure_and_table_has_its_files(quick, views, section):
    out = quick[0]
    view = views[section.slug]
    figures = [b for b in view.blocks if isinstance(b, Figure)]
    stems = [Path(f.stem).name for f in figures]
    assert stems == EXPECTED_FIGURES[section.slug]
    for f in figures:
        for ext in (".png", ".svg"):
            assert (out / (f.stem + ext)).stat().st_size > 1000, f.stem + ext
        assert f.data, f"figure {f.stem} has no data file beside it"
    tables = [b for b in view.blocks if isinstance(b, Table)]
    for t in tables:
        assert t.data, f"table {t.caption!r} has no data file beside it"
    for path in [d for b in figures + tables for d in b.data]:
        p = out / path
        assert p.stat().st_size > 0, path
        if p.suffix == ".json":
            json.loads(p.read_text())
        # data files, and the outcome maps' hover page (crosscheck.report.interactive): self-contained, no script
        assert p.suffix in (".csv", ".json") or (
            p.suffix == ".html" and "<script" not in p.read_text() and " src=" not in p.read_text()
        ), path
    # the HTML and the Markdown twin of the section's page (the index, or its engine's page) link every figure and data file
    html, md = (out / f"{_page(section.slug)}.html").read_text(), _md_of(out, section.slug)
    for f in figures:
        assert f'src="{f.stem}.png"' in html and f"]({f.stem}.png)" in md
        for d in f.data:
            assert f'href="{d}"' in html and f"]({d})" in md


#: Sections rebuilt in the --from-results test: one of each kind (analytic, GB, engine), to keep it fast.
REBUILT = ("p_region", "gb_eigenvectors", "mujoco_liftoff")


def _page(slug: str) -> str:
    """The stem of the page a section is on: its engine's page, or the index (``crosscheck.report.pages``)."""
    from crosscheck.report.sections import engine_sections

    for spec in engines.specs():
        if slug in {s.slug for s in engine_sections(spec)}:
            return f"engine_{spec.slug}"
    return "index"


def _md_of(out: Path, slug: str) -> str:
    stem = _page(slug)
    return (out / ("report.md" if stem == "index" else f"{stem}.md")).read_text()


def _md_section(md: str, title: str) -> str:
    start = md.index(f"## {title} [")
    end = md.find("\n## ", start + 1)
    return md[start : end if end >= 0 else len(md)].rstrip()  # the page's last section ends at the page's end


def test_report_rebuilds_from_saved_results_without_running(quick, views, tmp_path, monkeypatch):
    out = quick[0]
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    data_before = _digest(copy / "data")
    md_before = {slug: _md_of(copy, slug) for slug in REBUILT}
    figures_before = _digest(copy / "figures")
    for p in [copy / "index.html", copy / "report.md", *copy.glob("engine_*.*")]:
        p.unlink()
    shutil.rmtree(copy / "figures")

    def must_not_run(ctx):
        raise AssertionError(f"section {ctx.slug} ran during --from-results")

    subset = tuple(dataclasses.replace(report.section_by_slug(slug), run=must_not_run) for slug in REBUILT)
    monkeypatch.setattr(report, "SECTIONS", subset)
    monkeypatch.setattr(report, "run", lambda *a, **k: pytest.fail("the run stage was called"))
    assert main(["report", "--from-results", "--out", str(copy), "--no-progress"]) == 0
    assert _digest(copy / "data") == data_before  # saved results untouched
    rebuilt = _digest(copy / "figures")
    for s in subset:
        assert _md_section(_md_of(copy, s.slug), s.title) == _md_section(md_before[s.slug], s.title)  # same text, links
        pngs = {k: v for k, v in figures_before.items() if k.startswith(s.slug + "/") and k.endswith(".png")}
        assert pngs and all(rebuilt[k] == v for k, v in pngs.items())  # same figures, byte for byte


def test_provenance_records_versions_revision_machine_parameters_tolerances_seed(quick):
    out = quick[0]
    prov = json.loads((out / "data" / "provenance.json").read_text())
    for dist in ("crosscheck", "mujoco", "pin", "numpy", "scipy"):
        assert prov["versions"][dist] == metadata.version(dist)
    assert re.fullmatch(r"\d+\.\d+\.\d+.*", prov["versions"]["python"])
    head = prov["git"]["revision"]
    assert head in HEADS and re.fullmatch(r"[0-9a-f]{40}", head)
    assert isinstance(prov["git"]["dirty"], bool)
    assert prov["machine"]["cpu_count"] >= 1 and prov["machine"]["platform"]
    assert ", kernel " in prov["machine"]["blas"]  # the BLAS kernel moves an integration's last digits (compare_data)
    assert prov["seed"] == 0 and prov["quick"] is True
    assert prov["tolerances"] == json.loads(json.dumps(all_tolerances()))
    assert prov["parameters"] == json.loads(json.dumps({s.slug: s.params(True) for s in report.SECTIONS}))
    md = (out / "report.md").read_text()
    assert (
        head in md
        and f"| version: mujoco | {metadata.version('mujoco')} |" in md
        and f"| version: pin | {metadata.version('pin')} |" in md
    )
    # what an engine's provenance hook says (Newton: each solver's kernel compile CPU seconds, apart from its steps)
    said = {s.name for s in engines.specs() if s.execution.provenance is not None and not s.unavailable()}
    assert set(prov["engines"]) == said
    for name in said & {"newton_mujoco", "newton_xpbd", "newton_featherstone"}:
        seconds = prov["engines"][name]["kernel_compile_seconds"]
        assert seconds >= 0.0 and f"| {name}: kernel_compile_seconds | {seconds:.3g} |" in md


def test_printed_numbers_table_flags_every_known_misprint_and_nothing_else(quick):
    out = quick[0]
    md = (out / "report.md").read_text()
    section = md[md.index("## Every number the paper prints") :]
    table = section[: section.index("[data: printed_values.csv]")]
    rows = [r for r in table.splitlines() if r.startswith("| ") and not r.startswith("| quantity")]
    assert len(rows) == len(PRINTED)
    for pv, row in zip(PRINTED, rows):
        assert row.startswith(f"| {pv.name} |") and f"| {pv.printed} |" in row
        assert ("KNOWN MISPRINT" in row) == bool(pv.known_discrepancy), row
        assert ("| agrees |" in row) == pv.agrees()


def test_the_pinocchio_validations_worst_states_are_saved_inside_the_papers_domain(quick):
    # the worst state of a quantity through M^-1 is often a near-horizontal rod (theta down to 1e-8): saved with too few
    # digits its theta read 0, a state the paper's equations exclude
    out = quick[0]
    t = SectionStore(out / "data" / "pinocchio").read_table(
        "errors_per_quantity", text=("quantity", "passed", "worst_state")
    )
    thetas = [json.loads(w)["theta"] for w, q in zip(t["worst_state"], t["quantity"]) if q != "mu_P from p"]
    assert thetas and all(0.0 < th < math.pi / 2 for th in thetas), thetas


def _toy_sections(tmp_marker: Path):
    """A section that works and one that fails after saving part of its results; the failing one touches ``tmp_marker``
    (a file: each section runs in its own process)."""

    def run_ok(ctx):
        ctx.store.write_table("values", {"x": np.arange(3.0)})
        ctx.check("toy check", True, value=0.0, allowance=1.0)

    def render_ok(ctx):
        return [
            Table(
                caption="values",
                header=["x"],
                rows=[[f"{v:g}"] for v in ctx.store.read_table("values")["x"]],
                data=ctx.data("values.csv"),
            )
        ]

    def run_bad(ctx):
        ctx.store.write_table("partial", {"y": [1.0, 2.0]})  # finished work before the failure
        tmp_marker.write_text("bad ran")
        raise RuntimeError("boom: the engine diverged")

    def render_bad(ctx):
        return [
            Table(
                caption="partial", header=["y"], rows=[[str(v)] for v in ctx.store.read_table("missing")["y"]], data=[]
            )
        ]

    def params(quick):
        return {"n": 3}

    return (
        Section("toy_ok", "Toy ok", "", params, run_ok, render_ok),
        Section("toy_bad", "Toy bad", "", params, run_bad, render_bad, requires=("crosscheck.nowhere",)),
    )


def test_failing_section_is_shown_keeps_partial_results_and_exits_nonzero(tmp_path, monkeypatch):
    marker = tmp_path / "marker"
    good, bad = _toy_sections(marker)
    monkeypatch.setattr(report, "SECTIONS", (bad, good))  # the failing one first: the next must still run
    out = tmp_path / "r"
    assert main(["report", "--out", str(out), "--no-progress"]) == 1
    assert marker.read_text() == "bad ran"
    st_bad = json.loads((out / "data" / "toy_bad" / "status.json").read_text())
    st_good = json.loads((out / "data" / "toy_ok" / "status.json").read_text())
    assert st_bad["status"] == "error" and st_bad["error"] == "RuntimeError: boom: the engine diverged"
    assert "raise RuntimeError" in st_bad["traceback"]
    assert st_good["status"] == "ok"
    assert (out / "data" / "toy_bad" / "partial.csv").read_text() == "y\n1.0\n2.0\n"
    html, md = (out / "index.html").read_text(), (out / "report.md").read_text()
    for doc in (html, md):
        assert (
            "boom: the engine diverged" in doc
            and "FAILED" in doc
            and "crosscheck.nowhere" in doc
            and "partial.csv" in doc
        )
    assert "toy_ok: " not in md.split("## Provenance")[0]  # the good section is not among the failures


def test_failed_check_makes_the_report_fail(tmp_path, monkeypatch):
    def run(ctx):
        ctx.check("a check that fails", False, value=2.0, allowance=1.0)

    s = Section("toy_check", "Toy check", "", lambda q: {}, run, lambda ctx: [])
    monkeypatch.setattr(report, "SECTIONS", (s,))
    assert main(["report", "--out", str(tmp_path / "r"), "--no-progress"]) == 1
    md = (tmp_path / "r" / "report.md").read_text()
    assert "toy_check: check failed: a check that fails" in md


def test_from_results_without_results_is_a_one_line_error(tmp_path, capsys):
    assert main(["report", "--from-results", "--out", str(tmp_path / "none")]) == 2
    assert capsys.readouterr().err == (
        f"crosscheck: error: out must hold saved results with --from-results; {str(tmp_path / 'none' / 'data')!r} has none "
        f"(run `crosscheck report --out {tmp_path / 'none'}` without --from-results first)\n"
    )


def test_unknown_section_is_a_one_line_error(tmp_path, capsys):
    assert main(["report", "--out", str(tmp_path), "--only", "nope"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("crosscheck: error: --only must be one of: p_region, ") and err.endswith("; got 'nope'\n")


def test_sweep_heavy_sections_keep_their_engine_runs_in_finished_stores(quick):
    """The agreement maps and convergence tables ran their engines through crosscheck.sweeps: complete stores, per setting one
    per run horizon (``crosscheck.studies.agreement_store``), each horizon a halving of the study's plus the margin."""
    out, _, recomputed = quick
    from crosscheck.sweeps import Store

    heavy = [(f"{e.slug}_maps", 3) for e in engines.specs() if e.report and e.report.maps]
    heavy += [
        (f"{e.slug}_convergence", len(e.report.convergence["quick"]))
        for e in engines.specs()
        if e.report and e.report.convergence
    ]
    assert ("mujoco_convergence", 4) in heavy and ("rigid_convergence", 3) in heavy
    # the sections recomputed here (a clean checkout's reports/quick keeps no sweeps): maps and convergence among them
    heavy = [(slug, n) for slug, n in heavy if slug in recomputed]
    assert {slug.rsplit("_", 1)[1] for slug, _ in heavy} == {"maps", "convergence"}  # (``STUDIES``: each recomputed)
    for slug, n_settings in heavy:
        manifests = sorted((out / "sweeps" / slug).rglob("manifest.json"))
        settings: dict = {}
        for p in manifests:
            m = Store(p.parent).read_manifest()
            assert len(m["chunks"]) == m["n_chunks"] and m["failed"] == {}
            key = (p.parent.parent, json.dumps(m["spec"]["options"], sort_keys=True))
            settings.setdefault(key, []).append(m["spec"]["sweep"]["horizon"])
        assert len(settings) == n_settings, slug  # a map or a setting each
        for horizons in settings.values():  # one store per run horizon
            assert len(set(horizons)) == len(horizons)


def test_a_rerun_keeps_finished_sections_and_redoes_an_interrupted_one(tmp_path, monkeypatch):
    """Resume: a section left 'running' (its process killed) is recomputed, a finished one is kept untouched; other code keeps nothing."""
    from crosscheck.report import pipeline
    from crosscheck.report.sections import critical_angles, p_region

    out = tmp_path / "r"
    sections = [p_region.SECTION, critical_angles.SECTION]
    pipeline.run(out, sections, quick=True, resume=True)
    kept = {p: p.stat().st_mtime_ns for p in (out / "data" / "p_region").iterdir()}
    status = out / "data" / "critical_angles" / "status.json"
    st = json.loads(status.read_text())
    status.write_text(json.dumps({**st, "status": "running"}))  # what a kill during the section leaves
    res = pipeline.run(out, sections, quick=True, resume=True)
    assert res["p_region"].get("resumed") is True and not res["critical_angles"].get("resumed")
    assert res["critical_angles"]["status"] == "ok"
    assert {p: p.stat().st_mtime_ns for p in (out / "data" / "p_region").iterdir()} == kept
    res = pipeline.run(out, sections, quick=True, resume=False)
    assert not any(v.get("resumed") for v in res.values())
    # other code (an edit, an upgrade): nothing is kept
    monkeypatch.setattr(pipeline, "code_digest", lambda: "0" * 64)
    res = pipeline.run(out, sections, quick=True, resume=True)
    assert not any(v.get("resumed") for v in res.values())


def test_sweeps_computed_by_other_code_are_deleted_before_any_section_reads_them(tmp_path, monkeypatch):
    """``<out>/sweeps`` (the engine sweeps' stores and the theory the sections share) is kept for the same code, so a
    killed run resumes its chunks, and deleted when other code reruns the report: a section recomputed after an edit or
    an upgrade never reads a chunk of the old code."""
    from conftest import small

    from crosscheck import sweeps
    from crosscheck.report import pipeline
    from crosscheck.report.sections import p_region

    out = tmp_path / "r"
    pipeline.run(out, [p_region.SECTION], quick=True, resume=True)
    spec = tmp_path / "spec.toml"
    spec.write_text(small("analytic"))
    store = out / "sweeps" / "p_region" / "analytic"
    first = sweeps.run(spec, store, workers=1, progress=False)
    assert len(first.computed) == 6
    pipeline.run(out, [p_region.SECTION], quick=True, resume=True)
    assert sweeps.run(spec, store, workers=1, progress=False).computed == []  # same code: every chunk kept
    monkeypatch.setattr(pipeline, "code_digest", lambda: "0" * 64)
    pipeline.run(out, [p_region.SECTION], quick=True, resume=True)
    assert not store.exists()
    assert json.loads((out / "sweeps" / "computed_by.json").read_text())["code_sha256"] == "0" * 64
    assert len(sweeps.run(spec, store, workers=1, progress=False).computed) == 6


def test_findings_come_first_with_a_line_per_engine(quick):
    """The Findings block: one first-event line per engine with maps, its counts those of the saved confusion matrices."""
    from crosscheck.report.findings import findings

    out = quick[0]
    found = findings(out / "data")
    first = {f.slug: f for f in found if f.leg.endswith("first event")}
    assert set(first) == {f"{e.slug}_maps" for e in engines.specs() if e.report and e.report.maps}
    assert first["rigid_maps"].leg.startswith("Pinocchio (rigid engine)")
    for slug, f in first.items():
        conf = sum(
            np.asarray(mp["runs"][0]["confusion"]) for mp in json.loads((out / "data" / slug / "maps.json").read_text())
        )
        k, n = int(np.trace(conf[:4, :4])), int(conf[:4].sum())
        assert f"{k} of {n} rated" in f.text and f.verdict in ("agrees", "disagrees", "inconclusive")
    md = (out / "report.md").read_text()
    flat = " ".join(md.split())  # the Markdown wraps its prose lines
    assert md.index("## Findings") < md.index("## Summary") and all(" ".join(f.text.split()) in flat for f in found)


def test_the_engine_table_holds_numbers_a_row_per_engine_and_setting(quick):
    """The engine table's data: one record per engine and setting (a map row, one per convergence setting), numbers only
    (its agreement the findings line's k of n, its LAUNCH count the saved confusion matrices'), the same rows in the
    tidy CSV."""
    import csv

    from crosscheck.report.findings import findings

    out = quick[0]
    records = json.loads((out / "data" / "engine_table.json").read_text())
    plans = [e for e in engines.specs() if e.report and e.report.maps]
    assert len(records) == sum(1 + len(e.report.convergence["quick"] if e.report.convergence else []) for e in plans)
    first = {f.slug: f for f in findings(out / "data") if f.leg.endswith("first event")}
    for e in plans:
        row = next(r for r in records if r["role"] == "map" and r["engine"] == e.name)
        k, n = (int(x) for x in re.search(r"in (\d+) of (\d+) rated", first[f"{e.slug}_maps"].text).groups())
        assert (row["n_agree"], row["n_rated"]) == (k, n) and row["agreement"] == k / n
        assert row["ci_low"] <= row["agreement"] <= row["ci_high"]
        conf = sum(
            np.asarray(mp["runs"][0]["confusion"])
            for mp in json.loads((out / "data" / f"{e.slug}_maps" / "maps.json").read_text())
        )
        assert row["n_launch"] == int(conf[:4, 6].sum()) and row["n_theory_jam"] == int(conf[3].sum())
        iv = out / "data" / f"{e.slug}_interventions" / "summary.json"
        if iv.exists():
            s = json.loads(iv.read_text())
            assert (row["confirmed"], row["attributed"]) == (s["confirmed"], s["attributed"])
        rounding = json.loads((out / "data" / f"{e.slug}_rounding" / "summary.json").read_text())
        assert (row["rounding_changed"], row["rounding_n"]) == (rounding["changed"], rounding["n"])
    for r in records:  # numbers, not display strings
        for key in ("agreement", "ci_low", "ci_high", "runs_per_s", "us_per_step", "wall_time_s"):
            assert isinstance(r[key], float), (key, r[key])
        assert all(isinstance(r[k], int) for k in r if k.startswith(("n_", "agree_theory_")))
    tidy = list(csv.DictReader((out / "data" / "engine_table.csv").open()))
    assert [(t["engine"], t["role"], t["setting"]) for t in tidy] == [
        (r["engine"], r["role"], r["setting"]) for r in records
    ]
    assert [float(t["agreement"]) for t in tidy] == [r["agreement"] for r in records]


def _between(doc: str, *marks: str) -> bool:
    at = [doc.index(m) for m in marks]
    return at == sorted(at)


def test_the_first_screen_is_the_bottom_line_the_figure_and_one_row_per_engine(quick):
    """index.html and report.md open with the bottom line (<= 5 sentences, each with numbers and its rule), the
    agreement-against-cost figure (its data numbers), the table of one row per engine (<= 9 columns, footnoted), then
    the contents and the findings."""
    from html import escape

    from crosscheck.report.engine_table import FOOTNOTES

    out = quick[0]
    html, md = (out / "index.html").read_text(), (out / "report.md").read_text()
    bottom = json.loads((out / "data" / "bottom_line.json").read_text())
    assert 1 <= len(bottom) <= 5
    for s in bottom:
        assert re.search(r"\d", s["text"]) and s["rule"] and html.count(escape(s["text"])) == 1
    assert _between(html, 'id="bottom-line"', "figures/overview/agreement_cost.png", 'class="engines"', 'id="contents"',
                    'id="findings"')  # fmt: skip
    assert _between(
        md, bottom[0]["text"][:40], "(figures/overview/agreement_cost.png)", "| engine | setting |", "## Findings"
    )
    points = json.loads((out / "data" / "first_figure.json").read_text())["points"]
    assert all(isinstance(p["runs_per_s"], float) and isinstance(p["agreement"], float) for p in points)
    assert any(p["pareto_agreement_cost"] for p in points)
    mapped = [e for e in engines.specs() if e.report and e.report.maps]
    table = html[html.index('class="engines"') :]
    table = table[: table.index("</table>")]
    assert table.count("<tr") == 1 + len(mapped) and table.count("<th>") <= 9
    assert all(f"{k}: " in html[html.index("class=notes") :] for k, _ in FOOTNOTES)


def test_every_engine_has_its_own_page_linked_from_the_contents(quick):
    """Each engine's sections are on engine_<slug>.html and .md (with its per-setting rows and provenance), not on the
    index; the index's contents list the theory's sections then one entry per engine (<= 40 entries)."""
    from crosscheck.report.sections import THEORY_SECTIONS, engine_sections

    out = quick[0]
    html, md = (out / "index.html").read_text(), (out / "report.md").read_text()
    nav = html[html.index('<nav class="toc" id="contents">') :]
    nav = nav[: nav.index("</nav>")]
    assert nav.count("<a ") <= 40 and all(f'href="#{s.slug}"' in nav for s in THEORY_SECTIONS)
    for spec in engines.specs():
        own = engine_sections(spec)
        if not own:
            continue
        page, page_md = (out / f"engine_{spec.slug}.html").read_text(), (out / f"engine_{spec.slug}.md").read_text()
        assert f'href="engine_{spec.slug}.html"' in nav and f"](engine_{spec.slug}.md)" in md
        for s in own:
            assert f'id="{s.slug}"' in page and f'id="{s.slug}"' not in html and f"## {s.title} [" in page_md
        assert "Provenance" in page and spec.name in page
        if spec.report.maps:
            assert "Every setting the report ran" in page
    assert _between(nav, *(f'href="#{s.slug}"' for s in THEORY_SECTIONS), 'class="engine"')


def test_the_first_screen_in_chromium_at_1400_by_900(quick):
    """As a reader opens it in Chromium at 1400 x 900: the bottom line and the whole figure are on the first screen,
    nothing is wider than the page, and an engine page opens from the contents."""
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    from browser import HEIGHT, WIDTH, measure

    out = quick[0]
    m = measure(out / "index.html")
    screen = min(HEIGHT, m["innerHeight"])
    assert m["scrollWidth"] <= m["clientWidth"] <= WIDTH, m
    assert 0 < m["bottom_line"]["top"] < m["bottom_line"]["bottom"] < m["figure"]["top"], m
    assert m["figure_loaded"] and m["figure"]["bottom"] <= screen and m["figure"]["width"] >= 0.6 * WIDTH, m
    for t in m["tables"]:
        assert t["box"]["right"] <= m["clientWidth"] and t["scrollWidth"] <= t["container"] + 1, t
    assert m["engine_links"]
    link = out / m["engine_links"][0]
    page = measure(link)
    assert page["scrollWidth"] <= page["clientWidth"] and page["h1_text"].startswith(
        next(e.label for e in engines.specs() if link.name == f"engine_{e.slug}.html")
    )


def test_the_committed_quick_report_is_current(quick):
    """A fresh quick report's numbers equal those of the committed reference reports/quick (timings and provenance
    aside): a change that moves a number must regenerate it (`crosscheck report --quick --out reports/quick`)."""
    from crosscheck.report.compare_data import compare

    out = quick[0]
    committed = Path(__file__).resolve().parents[1] / "reports" / "quick" / "data"
    differ = {k: v[:3] for k, v in compare(committed, out / "data").items() if v}
    assert not differ, f"reports/quick is stale; regenerate it: {differ}"


def test_provenance_outside_a_checkout_names_the_installed_version(tmp_path):
    from crosscheck.report import provenance
    from crosscheck.report.provenance import revision_text as _revision

    git = provenance.git_revision(tmp_path)
    assert git == {"revision": None, "dirty": None, "describe": "not a git checkout"}
    assert (
        _revision(git, {"versions": {"crosscheck": "0.1.0"}}) == "installed package, version 0.1.0 (not a git checkout)"
    )
    here = provenance.git_revision()
    assert here["revision"] and _revision(here, {}).startswith(here["revision"])


def test_findings_read_a_validate_ratio_as_a_ratio(tmp_path):
    """An onset check recorded as a ratio to its tolerance (allowance 1) is reported as a ratio, not as |onset - Psi_L|."""
    from crosscheck.report.findings import findings

    for slug, check in (
        (
            "toy_ratio",
            {"name": "MuJoCo lift-off onset Psi within tolerance", "passed": True, "value": 1.1e-4, "allowance": 1.0},
        ),
        (
            "toy_abs",
            {"name": "mu = 0.3, timestep 0.0003: onset = Psi_L", "passed": True, "value": 6e-11, "allowance": 5.5e-7},
        ),
    ):
        (tmp_path / slug).mkdir()
        (tmp_path / slug / "checks.json").write_text(json.dumps([check]))
    text = {f.slug: f.text for f in findings(tmp_path)}
    assert text["toy_ratio"].endswith("worst at 0.00011 of its tolerance")
    assert text["toy_abs"].endswith(
        "worst |onset - Psi_L| = 6e-11 against its allowance 5.5e-07 (mu = 0.3, timestep 0.0003)"
    )


def test_compare_data_allows_only_the_machine_dependent_bits(tmp_path):
    """The wider allowances across machines cover last-bit effects and nothing a code change would make:
    a 1e-6 shift of an adaptive integration's rows passes, 1e-3 does not; a 4 % change of PGS's unconverged
    steps passes, 20 % does not; every other number keeps the 1e-9 default."""
    from crosscheck.report.compare_data import compare

    def tree(root, t, unconverged, other):
        (root / "mujoco_trajectories").mkdir(parents=True)
        (root / "mujoco_trajectories" / "analytic_jam.csv").write_text(f"t,Psi\n{t!r},1.0\n")
        (root / "maps.json").write_text(
            json.dumps({"solver_health": {"unconverged_steps": unconverged}, "agreement": other})
        )
        return root

    old = tree(tmp_path / "old", 0.5, 250, 0.8)
    assert not any(compare(old, tree(tmp_path / "a", 0.5 * (1 + 1e-6), 240, 0.8)).values())
    differ = compare(old, tree(tmp_path / "b", 0.5 * (1 + 1e-3), 200, 0.8 * (1 + 1e-8)))
    assert differ["mujoco_trajectories/analytic_jam.csv"] and len(differ["maps.json"]) == 2


def test_the_causes_confirmed_on_every_engine_are_drawn_beside_the_engine_table_from_their_summaries(quick):
    """Each engine's bar is its interventions summary split into bins that hold each attributed start once."""
    out = quick[0]
    rows = json.loads((out / "data" / "causes_confirmed.json").read_text())
    assert {r["section"] for r in rows} == {
        p.parent.name
        for p in (out / "data").glob("*_interventions/summary.json")
        if json.loads(p.read_text())["attributed"]
    }
    for r in rows:
        s = json.loads((out / "data" / r["section"] / "summary.json").read_text())
        assert r["confirmed"] + r["pairs"] == s["confirmed"]
        assert (
            r["confirmed"] + r["pairs"] + r["other"] + r["jointly"] + r["none"] + r["no_intervention"]
            == r["attributed"]
            == s["attributed"]
        )
    assert (out / "figures" / "overview" / "causes_confirmed.png").is_file() and (
        out / "figures" / "overview" / "causes_confirmed.svg"
    ).is_file()
    md = (out / "report.md").read_text()
    assert (
        md.index("## Findings")
        < md.index("(figures/overview/causes_confirmed.png)")
        < md.index("- **", md.index("## Findings"))
    )


def test_findings_sum_the_causes_confirmed_over_every_engine_against_the_goal(tmp_path):
    """The line over all engines adds their summaries' counts and is 'confirmed' from 80 % on, the goal of the interventions."""
    from crosscheck.report.findings import findings

    def summary(slug, attributed, confirmed, pairs, jointly):
        (tmp_path / slug).mkdir()
        per = {"geometry": {"overdetermined": {"compliance": pairs}, "by_other": {}, "none": 0}}
        (tmp_path / slug / "summary.json").write_text(
            json.dumps(
                {
                    "engine": "mujoco",
                    "attributed": attributed,
                    "confirmed": confirmed,
                    "confirmed_share": confirmed / attributed,
                    "jointly": jointly,
                    "per_cause": per,
                }
            )
        )

    summary("a_interventions", 10, 8, 1, 0)
    summary("b_interventions", 10, 8, 0, 2)
    (line,) = [f for f in findings(tmp_path) if f.leg.startswith("every engine")]
    assert line.verdict == "confirmed" and line.why == "16 of 20 >= 80 % of 20 = 16"
    assert (
        line.text.startswith("16 of 20 attributed disagreements (80.0 %) over 2 engines")
        and "(1 of them overdetermined pairs" in line.text
    )
    assert "; 2 more only jointly" in line.text and line.text.endswith("; lowest MuJoCo, 8 of 10 (80 %)")
    (tmp_path / "b_interventions" / "summary.json").write_text(
        json.dumps(
            {
                "engine": "bullet",
                "attributed": 10,
                "confirmed": 7,
                "confirmed_share": 0.7,
                "jointly": 0,
                "per_cause": {},
            }
        )
    )
    (line,) = [f for f in findings(tmp_path) if f.leg.startswith("every engine")]
    assert (
        line.verdict == "partly confirmed"
        and line.why == "15 of 20 < 80 % of 20 = 16"
        and line.slug == "b_interventions"
    )
    assert line.text.endswith("; lowest Bullet, 7 of 10 (70 %)")


def test_findings_name_the_causes_of_disagreement_and_the_compliant_limit(tmp_path):
    """The ladder's line counts what its summary counts, and says 'partly explained' below 90 % attributed; the compliant
    limit's line fails when one of its physics checks does (regression guards do not count)."""
    from crosscheck.report.findings import findings

    (tmp_path / "mujoco_ladder").mkdir()
    counts = {
        "geometry": 1,
        "compliance": 0,
        "friction law": 2,
        "discretisation": 0,
        "unexplained": 2,
        "undetermined": 0,
    }
    (tmp_path / "mujoco_ladder" / "summary.json").write_text(
        json.dumps(
            {"engine": "mujoco", "n_disagree": 5, "n_disagreements_on_maps": 7, "attributed": 0.6, "counts": counts}
        )
    )
    (tmp_path / "compliant_limit").mkdir()
    checks = [
        {"name": "inconsistent starts: fitted slope", "passed": True, "value": [[0.70, 0.69]], "kind": "physics"},
        {"name": "indeterminate starts", "passed": False, "value": "3 of 4", "kind": "physics"},
        {"name": "some guard", "passed": False, "value": 1, "kind": "regression guard"},
    ]
    (tmp_path / "compliant_limit" / "checks.json").write_text(json.dumps(checks))
    by_slug = {f.slug: f for f in findings(tmp_path)}
    ladder = by_slug["mujoco_ladder"]
    assert ladder.verdict == "partly explained"
    assert "60 % attributed" in ladder.text and "geometry 1, friction law 2, unexplained 2" in ladder.text
    limit = by_slug["compliant_limit"]
    assert limit.verdict == "disagrees" and limit.text.startswith("1 of 2 physics checks")
