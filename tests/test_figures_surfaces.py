"""Figs. 3-7 (the surfaces b = 0 and p = 0 in 3D) and Fig. 21 (the bifurcations between the kinematic cases): geometry and the sections' checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck.report import bifurcation_strata as strata
from crosscheck.report import surfaces as meshes
from crosscheck.report.section import RunContext, section_rng
from crosscheck.report.sections import bifurcations
from crosscheck.report.sections import kinematic_surfaces as ks
from crosscheck.report.store import SectionStore
from crosscheck.theory import analytic, critical, gb
from crosscheck.tolerances import CLOSED_FORM, GB_IDENTITY, ROOT_RESIDUAL

MU, ALPHA, TMAX = 1.4, 3.0, 2.2


def _run(section, tmp_path):
    store = SectionStore(tmp_path / section.slug)
    ctx = RunContext(
        slug=section.slug, params=section.params(True), quick=True, rng=section_rng(0, section.slug), store=store
    )
    section.run(ctx)
    return ctx


@pytest.fixture(scope="module")
def surfaces(tmp_path_factory):
    return _run(ks.SECTION, tmp_path_factory.mktemp("ks"))


@pytest.fixture(scope="module")
def bifs(tmp_path_factory):
    return _run(bifurcations.SECTION, tmp_path_factory.mktemp("bif"))


def test_b0_below_Psi_L_is_one_piece_clipped_where_Theta_reaches_its_top():
    ((lo, hi),) = meshes.b0_pieces(0.0, TMAX)
    # at Psi = 0, Theta^2 = 1/sin theta on b = 0: the top Theta_max is reached at sin theta = 1/Theta_max^2
    assert abs(lo - math.asin(1 / TMAX**2)) <= CLOSED_FORM.allowance(lo)
    assert hi == pytest.approx(math.pi / 2, abs=1e-3)


def test_b0_above_Psi_L_leaves_Theta_0_exactly_across_the_theta_gap():
    pieces = meshes.b0_pieces(2.2, TMAX)
    ga, gb_ = gb.gb_theta_gap(2.2)
    assert len(pieces) == 2
    # brentq on Theta^2 = 0 and the cubic's roots of gb_theta_gap are two routes to the same edges
    assert abs(pieces[0][1] - ga) <= CLOSED_FORM.allowance(ga) and abs(pieces[1][0] - gb_) <= CLOSED_FORM.allowance(gb_)
    for edge in (pieces[0][1], pieces[1][0]):
        assert abs(analytic.b(2.2, 0.0, edge)) <= ROOT_RESIDUAL.atol


def test_b0_at_Psi_L_touches_Theta_0_without_splitting():
    pieces = meshes.b0_pieces(critical.Psi_L, TMAX)
    assert len(pieces) == 1 and pieces[0][0] < critical.theta_L < pieces[0][1]
    # slightly above Psi_L the surface does split (lift-off at Theta = 0 opens around theta_L)
    assert len(meshes.b0_pieces(critical.Psi_L * (1 + 1e-4), TMAX)) == 2


def test_p0_cylinder_is_closed_and_on_p_zero():
    theta, varphi = meshes.p0_cylinder(MU, ALPHA, n=41)
    cv = critical.critical_values(MU, ALPHA)
    assert theta[0] == theta[-1] and varphi[0] == varphi[-1]
    assert theta.min() == pytest.approx(cv.theta_1, abs=1e-15) and theta.max() == pytest.approx(cv.theta_2, abs=1e-15)
    assert np.max(np.abs(analytic.p(theta, varphi, MU, ALPHA))) <= ROOT_RESIDUAL.atol


def test_surfaces_section_checks_pass(surfaces):
    failed = [c["name"] for c in surfaces.checks if not c["passed"]]
    assert not failed
    # the figures' claims, measured: no inconsistent cell from Psi_2 on, some below it
    cells = {s["label"]: s["inconsistent_cells"] for s in surfaces.store.read_json("slices")}
    assert cells["Psi_2"] == 0 and cells["5"] == 0
    assert all(v > 0 for k, v in cells.items() if k not in ("Psi_2", "5"))


def test_surfaces_gb_curve_lies_on_both_surfaces(surfaces):
    for label in ("0", "2.2", "Psi_1"):
        g = surfaces.store.read_table(f"gb_{ks._tag(label)}")
        Psi = {"0": 0.0, "2.2": 2.2, "Psi_1": critical.critical_values(MU, ALPHA).Psi_1}[label]
        assert g["theta"].size > 10 and np.all(g["Theta"] >= 0)
        assert np.max(np.abs(analytic.b(Psi, g["Theta"], g["theta"]))) <= GB_IDENTITY.allowance(0.0)
        assert np.max(np.abs(analytic.p(g["theta"], g["varphi"], MU, ALPHA))) <= GB_IDENTITY.allowance(0.0)


def test_bifurcation_section_checks_pass(bifs):
    failed = [c["name"] for c in bifs.checks if not c["passed"]]
    assert not failed
    cells = bifs.store.read_json("cells")
    assert len(cells) == 19
    assert sorted(cl["case"] for cl in cells if cl["kind"] == "case") == [1, 2, 3, 4, 5, 6, 7]


@pytest.mark.parametrize("name", list(strata.POINTS))
def test_codim2_points_are_zeros_of_each_curve_function_and_a_step_off_is_not(name):
    pm, pP, through = strata.POINTS[name]
    c = {
        "mu_P": float(critical.mu_P(ALPHA)),
        "mu_L": float(critical.mu_L(ALPHA)),
        "Psi_L": critical.Psi_L,
        "Psi_P": float(critical.Psi_P(ALPHA)),
    }
    mu, Psi = c[pm], c[pP]
    for kind in {strata.CURVES[cid][1] for cid in through}:
        assert abs(strata.defining_function(kind, mu, Psi, ALPHA)) <= CLOSED_FORM.allowance(1 + Psi**2)
        # a relative step of 1e-6 off the point (in the coordinate the function depends on) leaves the curve by far more than rounding
        off = (
            strata.defining_function(kind, mu * (1 + 1e-6), Psi, ALPHA)
            if kind == "P"
            else strata.defining_function(kind, mu, Psi * (1 + 1e-6), ALPHA)
        )
        assert abs(off) > 1e3 * CLOSED_FORM.allowance(1 + Psi**2)


def test_every_case_boundary_of_fig_9a_is_one_of_the_curves():
    # the case map on a grid changes only across a listed curve: adjacent cells with different cases are the two sides of one.
    # Cases 4, 5 and 6 are wedges that close at the codimension-2 points, so a grid steps over them there: cell pairs
    # within 0.3 (in mu and Psi) of a point are left out; elsewhere the wedges are wider than a cell (0.025 x 0.005).
    mu = np.linspace(0.0125, 2.9875, 120)
    Psi = np.linspace(0.0025, 5.9975, 1200)
    M, S = np.meshgrid(mu, Psi)
    cases = critical.kinematic_case(M, S, ALPHA)
    corners = [
        (float(critical.mu_P(ALPHA)), critical.Psi_L),
        (float(critical.mu_P(ALPHA)), float(critical.Psi_P(ALPHA))),
        (float(critical.mu_L(ALPHA)), critical.Psi_L),
    ]
    far = np.all([(np.abs(M - m) > 0.3) | (np.abs(S - p) > 0.3) for m, p in corners], axis=0)
    pairs = {tuple(sorted(v[4])) for v in strata.CURVES.values()}
    seen = set()
    for a, b, keep in (
        (cases[:, :-1], cases[:, 1:], far[:, :-1] & far[:, 1:]),
        (cases[:-1, :], cases[1:, :], far[:-1, :] & far[1:, :]),
    ):
        diff = (a != b) & keep
        seen |= {tuple(sorted((int(x), int(y)))) for x, y in zip(a[diff], b[diff])}
    assert seen <= pairs, seen - pairs
    assert len(seen) == len(pairs)  # and every listed curve is crossed somewhere


def _meshes(mu, Psi):
    return meshes.surface_meshes(mu, Psi, ALPHA, TMAX, n_surface=21, n_varphi=11, n_Theta=6, n_gb=21)


def test_surface_meshes_below_mu_P_have_no_cylinder_and_at_mu_P_a_segment():
    assert len(_meshes(1.0, 0.0)["p0"]["theta"]) == 0 and len(_meshes(1.0, 0.0)["gb"]["theta"]) == 0
    m = _meshes(float(critical.mu_P(ALPHA)), 0.0)
    # at mu_P, p = 0 only at theta_P, varphi = -pi/2 (eqs. thetap, theta12): the cylinder is a segment
    assert np.ptp(m["p0"]["theta"]) == 0 and m["p0"]["theta"][0] == pytest.approx(
        float(critical.theta_P(ALPHA)), abs=1e-12
    )
    assert np.allclose(m["p0"]["varphi"], -np.pi / 2, atol=1e-12)


def test_surface_meshes_cut_the_cylinder_at_b_zero_and_find_the_Psi_2_tangency_point():
    cv = critical.critical_values(MU, ALPHA)
    m = _meshes(MU, 1.7)
    p0 = {k: np.asarray(v) for k, v in m["p0"].items()}
    top_of_lower = p0["Theta"][(p0["part"] == 0) & (p0["j"] == p0["j"].max())]
    th = p0["theta"][(p0["part"] == 0) & (p0["j"] == p0["j"].max())]
    # the lower part of the cylinder ends on b = 0 (where that is above Theta = 0)
    on = top_of_lower > 0
    assert on.any() and np.max(np.abs(analytic.b(1.7, top_of_lower[on], th[on]))) <= ROOT_RESIDUAL.atol
    m2 = _meshes(MU, cv.Psi_2)
    assert m2["tangency"] and m2["gb"]["theta"] == [cv.theta_2] and m2["gb"]["Theta"] == [0.0]
    assert not _meshes(MU, cv.Psi_2 * (1 + 1e-6))["gb"]["theta"]  # beyond Psi_2: no GB point at all


def test_interactive_page_is_self_contained_with_one_tooltip_per_start():
    from crosscheck.report.interactive import GridMap, Panel, engine_line, outcome_maps_page, start_tooltip

    t = {
        "theta": np.array([1.0, 1.1]),
        "varphi": np.array([-1.9, -1.9]),
        "Theta": np.array([0.0, 0.5]),
        "Psi": np.array([0.0, 0.0]),
        "mu": np.array([1.4, 1.4]),
        "eta": np.array([1.0, 1.0]),
        "b0": np.array([-0.5, 0.2]),
        "p0": np.array([0.3, 0.3]),
        "slipping": np.array([1, 0]),
        "analytic_outcome": np.array([1, 0]),
        "analytic_time": np.array([0.25, np.nan]),
        "analytic_reason": np.array(["b=0", ""]),
        "comparison_time": np.array([0.25, 0.0]),
        "mujoco": np.array([1, -2]),
        "mujoco_time": np.array([0.26, np.nan]),
    }
    tips = [
        [
            start_tooltip(t, 0) + "\n" + engine_line(t, 0, "mujoco", "MuJoCo"),
            start_tooltip(t, 1) + "\n" + engine_line(t, 1, "mujoco", "MuJoCo"),
        ]
    ]
    assert "analytic: liftoff at t = 0.25 (b=0)" in tips[0][0] and "MuJoCo: liftoff at t = 0.26" in tips[0][0]
    assert "not compared" in tips[0][1] and "b >= 0" in tips[0][1]
    codes = np.array([[1.0, np.nan]])  # a cell with no start is not drawn
    page = outcome_maps_page(
        "t",
        [GridMap("m", "theta", "Theta", np.array([1.0, 1.1]), np.array([0.0]), [Panel("a", codes)], tips)],
        colors={1: (1, 0.5, 0), -2: (0.8, 0.8, 0.8)},
        names={1: "liftoff", -2: "not compared"},
    )
    assert page.count("<title>") == 2  # the page's own and one cell's
    assert "b &gt;= 0" not in page.split("<title>", 2)[2]  # only the drawn cell carries a tooltip
    assert "<script" not in page and " src=" not in page and "<link" not in page
