"""Fig. 21: the codimension-1 and -2 bifurcations between the kinematic cases 1-7 in (mu, Psi), as computed curves and points.

The paper's last section (sec:geobifs, fig:mechbifs) lays the cases of section 3.4 out on a
grid of strata: mu in [0, mu_P), mu = mu_P, (mu_P, mu_L), mu = mu_L, > mu_L
against |Psi| below, at and between Psi_L, Psi_1, Psi_2, with a picture in
each of its 19 cells.  Here the strata are computed:

* codimension 1, the curves where the case changes, each the zero set of one
  function of (mu, Psi) (alpha fixed):
  - Psi = Psi_L (eq. psil): F_L = b(Psi, Theta = 0, theta_L) = 0, the largest b at
    Theta = 0 over theta (db/dtheta = 0 at theta_L for every Psi, eq. thetal):
    b = 0 reaches Theta = 0; cases 1|2, 3|4, 3|5 for mu below mu_P, between
    mu_P and mu_L, above mu_L;
  - Psi = Psi_1(mu), Psi_2(mu) (eqs. psi1, psi2): F_1,2 = b(Psi, 0, theta_1,2(mu)) = 0,
    b = 0 touches the cylinder p = 0 at theta_1,2 (eq. theta12); cases 4|6,
    5|6 and 6|7;
  - mu = mu_P (eq. mup2D): F_P = p_min(mu) = 0 (the cylinder p < 0 appears);
    cases 1|3, 2|4, 2|7 below Psi_L, between Psi_L and Psi_P, above Psi_P;
* codimension 2, where those curves meet: (mu_P, Psi_L), (mu_P, Psi_P) (eq.
  psip: Psi_1 = Psi_2) and (mu_L, Psi_L) (eq. mul: Psi_1 = Psi_L, tangent).

The picture in each of the 19 cells is computed at one (mu, Psi) of its
stratum as Figs. 3-7 are (``crosscheck.report.surfaces.surface_meshes``): b = 0, p = 0
and the GB manifold in (theta, varphi, Theta).

Checks: every sampled point of each curve is a zero of its function (closed
form); just across each curve ``crosscheck.theory.critical.kinematic_case`` gives
the two cases the paper puts on either side; each codimension-2 point is a
zero of the functions of every curve through it (CLOSED_FORM); the case at a
point of each generic cell of the paper's grid is the one it circles.

The curves, points, cells and defining functions: ``crosscheck.report.bifurcation_strata``.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.bifurcation_strata import (
    CELLS,
    CURVES,
    MU_STRATA,
    POINTS,
    PSI_STRATA,
    across,
    cell_point,
    constants,
    curve_samples,
    defining_function,
    defining_scale,
)
from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.report.surfaces import draw_surfaces, surface_meshes
from crosscheck.theory import analytic, critical
from crosscheck.tolerances import CLOSED_FORM, ROOT_RESIDUAL

__all__ = ["SECTION"]

SLUG = "bifurcations"


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        "mu_max": 3.0,
        "Psi_max": 6.0,
        "mu_examples": [1.0, 1.4, 6.0],
        "n_curve": 200 if quick else 1000,
        "n_map_mu": 150 if quick else 450,
        "n_map_Psi": 120 if quick else 360,
        "n_thumb": 21 if quick else 41,
        "Theta_max": 2.2,
        "offset": 1e-6,
    }


def run(ctx: RunContext) -> None:
    P = ctx.params
    alpha = P["alpha"]
    c = constants(alpha, P["mu_max"], P["Psi_max"])
    ctx.store.write_json("constants", c)
    mu = cell_centres(0.0, P["mu_max"], P["n_map_mu"])
    Psi = cell_centres(0.0, P["Psi_max"], P["n_map_Psi"])
    ctx.store.write_grid(
        "cases", ("mu", mu), ("Psi", Psi), ("case", critical.kinematic_case(mu[None, :], Psi[:, None], alpha))
    )

    summary = _curves(ctx, c)
    points = []
    for name, (pm, pP, through) in POINTS.items():
        m, s = c[pm], c[pP]
        kinds = sorted({CURVES[cid][1] for cid in through})
        res = {k: float(abs(defining_function(k, m, s, alpha))) for k in kinds}
        allow = {k: float(CLOSED_FORM.allowance(defining_scale(k, m, s, alpha))) for k in kinds}
        points.append(
            {"point": name, "mu": m, "Psi": s, "curves": list(through), "residuals": res, "allowances": allow}
        )
    ctx.store.write_json("points", points)

    cells = _cells(ctx, c)
    _checks(ctx, c, summary, points, cells)


def _curves(ctx: RunContext, c: dict) -> list[dict]:
    """Each codimension-1 curve sampled (``curve_samples``): its residuals against CLOSED_FORM, the cases either side
    of it and, on Psi_1,2, the residual of p = 0 at theta_1,2; the summary (``curves``)."""
    P = ctx.params
    alpha = P["alpha"]
    cols = {k: [] for k in ("curve", "mu", "Psi", "residual", "allowance")}
    summary = []
    for cid, (label, kind, _along, _, (below, above)) in CURVES.items():
        m, s = curve_samples(cid, c, P["n_curve"])
        res = np.abs(defining_function(kind, m, s, alpha))
        allow = CLOSED_FORM.allowance(defining_scale(kind, m, s, alpha))
        for k, v in (("curve", [cid] * m.size), ("mu", m), ("Psi", s), ("residual", res), ("allowance", allow)):
            cols[k] += list(v)
        inner = slice(max(1, m.size // 50), m.size - max(1, m.size // 50))  # off the codimension-2 ends
        lo_case, hi_case = across(cid, m[inner], s[inner], P["offset"], alpha)
        wrong = int(np.sum((lo_case != below) | (hi_case != above)))
        # on the curves Psi_1,2 the cylinder p = 0 itself must hold at theta_1,2 (eq. theta12)
        p_res = 0.0
        if kind in ("1", "2"):
            th = critical.theta_12(m, alpha)[0 if kind == "1" else 1]
            p_res = float(np.max(np.abs(analytic.p(th, -np.pi / 2, m, alpha))))
        worst = int(np.argmax(res / allow))
        summary.append(
            {
                "curve": cid,
                "label": label,
                "function": kind,
                "cases": [below, above],
                "samples": int(m.size),
                "max_ratio": float(res[worst] / allow[worst]),
                "allowance_at_worst": float(allow[worst]),
                "max_residual": float(res[worst]),
                "p_residual": p_res,
                "side_mismatches": wrong,
                "sides_tested": int(lo_case.size),
                "cases_seen": sorted({int(v) for v in np.concatenate([lo_case, hi_case])}),
            }
        )
        ctx.store.write_json("curves", summary)
    ctx.store.write_table("curve_samples", cols)

    return summary


def _cells(ctx: RunContext, c: dict) -> list[dict]:
    """The paper's grid of pictures: each cell's (mu, Psi), its case or the cases across its curve, and its b = 0,
    p = 0 and GB meshes."""
    P = ctx.params
    alpha = P["alpha"]
    cells = []
    for col, row, what in CELLS:
        m, s = cell_point(col, row, what, c, P["mu_examples"])
        cell = {
            "col": col,
            "row": row,
            "kind": what[0],
            "what": what[1],
            "mu": m,
            "Psi": s,
            "case": critical.kinematic_case(m, s, alpha),
        }
        if what[0] == "curve":
            lo_case, hi_case = across(what[1], np.array([m]), np.array([s]), P["offset"], alpha)
            cell["sides"] = [int(lo_case[0]), int(hi_case[0])]
        # the paper's picture of the cell: b = 0, p = 0 and the GB manifold in (theta, varphi, Theta) at this (mu, Psi)
        meshes = surface_meshes(
            m,
            s,
            alpha,
            P["Theta_max"],
            n_surface=P["n_thumb"],
            n_varphi=P["n_thumb"] // 2 + 1,
            n_Theta=6,
            n_gb=P["n_thumb"],
        )
        for part in ("b0", "p0", "gb"):
            ctx.store.write_table(f"cell_{col}_{row}_{part}", meshes[part])
        cell["gb_points"] = len(meshes["gb"]["theta"])
        cells.append(cell)
        ctx.store.write_json("cells", cells)

    return cells


def _checks(ctx: RunContext, c: dict, summary: list, points: list, cells: list) -> None:
    """The section's checks: every curve a zero of its function and a boundary of its cases, every codimension-2 point
    on its curves, Psi_1 touching Psi_L at mu_L, and every cell's case."""
    P = ctx.params
    alpha = P["alpha"]
    for s_ in summary:
        ctx.check(
            f"{s_['label']} ({s_['curve']}): its {s_['samples']} samples are zeros of F_{s_['function']}",
            s_["max_ratio"] <= 1.0,
            value=s_["max_residual"],
            allowance=s_["allowance_at_worst"],
            detail=f"largest |F| / CLOSED_FORM allowance {s_['max_ratio']:.2g}"
            + (
                f"; max |p(theta_{s_['function']}, -pi/2)| {s_['p_residual']:.1e} (ROOT_RESIDUAL {ROOT_RESIDUAL.atol:g})"
                if s_["function"] in "12"
                else ""
            ),
        )
        if s_["function"] in "12":
            ctx.check(
                f"{s_['label']} ({s_['curve']}): theta_{s_['function']}(mu) lies on p = 0 (eq. theta12)",
                s_["p_residual"] <= ROOT_RESIDUAL.atol,
                value=s_["p_residual"],
                allowance=ROOT_RESIDUAL.atol,
            )
        ctx.check(
            f"{s_['label']} ({s_['curve']}) separates cases {s_['cases'][0]} | {s_['cases'][1]}",
            s_["side_mismatches"] == 0,
            value=s_["side_mismatches"],
            allowance=0,
            detail=f"kinematic_case at +-{P['offset']:g} across {s_['sides_tested']} samples; cases seen {s_['cases_seen']}",
        )
    for pt in points:
        k_ = max(pt["residuals"], key=lambda k: pt["residuals"][k] / pt["allowances"][k])
        ctx.check(
            f"codimension-2 point {pt['point']} = ({pt['mu']:.4f}, {pt['Psi']:.4f}) lies on each of its curves {', '.join(pt['curves'])}",
            pt["residuals"][k_] <= pt["allowances"][k_],
            value=pt["residuals"][k_],
            allowance=pt["allowances"][k_],
            detail=", ".join(f"|F_{k}| = {v:.1e}" for k, v in pt["residuals"].items()),
        )
    cv_L = critical.critical_values(c["mu_L"], alpha)
    gap = abs(cv_L.theta_1 - critical.theta_L)
    allow = float(CLOSED_FORM.allowance(critical.theta_L))
    ctx.check(
        "at (mu_L, Psi_L) the curve Psi_1 touches Psi = Psi_L: theta_1(mu_L) = theta_L (eq. mul)",
        gap <= allow,
        value=gap,
        allowance=allow,
    )
    wrong = [
        f"({cl['col']},{cl['row']})"
        for cl in cells
        if (cl["kind"] == "case" and cl["case"] != cl["what"])
        or (cl["kind"] == "curve" and cl["sides"] != list(CURVES[cl["what"]][4]))
    ]
    ctx.check(
        "each cell of the paper's grid: the case it circles, or the two cases either side of its curve",
        not wrong,
        value=len(wrong),
        allowance=0,
        detail=f"{len(cells)} cells; wrong: {', '.join(wrong) or 'none'}",
    )


# ------------------------------------------------------------------ render ---

_FN_COLOR = {"L": 0, "1": 1, "2": 3, "P": 4}  # LINE_COLORS index per critical value
_TEX = {
    "Psi = Psi_L": "$\\Psi=\\Psi_L$",
    "Psi = Psi_1(mu)": "$\\Psi=\\Psi_1(\\mu)$",
    "Psi = Psi_2(mu)": "$\\Psi=\\Psi_2(\\mu)$",
    "mu = mu_P": "$\\mu=\\mu_P$",
}
_POINT_TEX = {
    "(mu_P, Psi_L)": "$(\\mu_P,\\Psi_L)$",
    "(mu_P, Psi_P)": "$(\\mu_P,\\Psi_P)$",
    "(mu_L, Psi_L)": "$(\\mu_L,\\Psi_L)$",
}


def _case_colors():
    from crosscheck.report.plotting import LINE_COLORS

    return {
        k: tuple(0.7 + 0.3 * np.array(LINE_COLORS[k - 1])) for k in range(1, 8)
    }  # pale: the curves carry the figure


def render(ctx: RenderContext) -> list:
    c = ctx.store.read_json("constants")
    points = ctx.store.read_json("points")
    return [_curves_figure(ctx, c, points), _strata_figure(ctx), _points_table(ctx, points)]


def _curves_figure(ctx: RenderContext, c: dict, points: list):
    """Fig. 21's (mu, |Psi|) plane: the codimension-1 curves over the cases of Fig. 9a, the codimension-2 points."""
    from matplotlib.lines import Line2D

    from crosscheck.report.plotting import LINE_COLORS, categorical_image, plt

    t = ctx.store.read_table("curve_samples", text=("curve",))
    curves = ctx.store.read_json("curves")
    mu, Psi, cases, _ = ctx.store.read_grid("cases")

    fig, ax = plt.subplots(figsize=(7.0, 5.4))
    categorical_image(ax, mu, Psi, cases, _case_colors())
    ax.axvline(c["mu_L"], color="0.45", lw=0.7, ls=":")
    handles = {}
    for cid, (label, kind, *_rest) in CURVES.items():
        sel = t["curve"] == cid
        (h,) = ax.plot(t["mu"][sel], t["Psi"][sel], color=LINE_COLORS[_FN_COLOR[kind]], lw=2.0, solid_capstyle="butt")
        handles.setdefault(label, h)
    for pt in points:
        ax.plot(pt["mu"], pt["Psi"], "o", color="k", ms=6, zorder=5)
        off = {"(mu_P, Psi_L)": (-62, -14), "(mu_P, Psi_P)": (-64, 4), "(mu_L, Psi_L)": (4, -14)}[pt["point"]]
        ax.annotate(
            _POINT_TEX[pt["point"]],
            (pt["mu"], pt["Psi"]),
            textcoords="offset points",
            xytext=off,
            fontsize=9,
            bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8),
        )
    # the curves' names where they are alone
    ax.annotate(
        "$\\Psi_L$", (0.35, c["Psi_L"]), textcoords="offset points", xytext=(0, 4), color=LINE_COLORS[0], fontsize=10
    )
    for kind, cid, frac, dy in (("1", "1_III", 0.55, 5), ("2", "2", 0.3, 6)):
        sel = t["curve"] == cid
        i = int(frac * sel.sum())
        ax.annotate(
            f"$\\Psi_{kind}(\\mu)$",
            (t["mu"][sel][i], t["Psi"][sel][i]),
            textcoords="offset points",
            xytext=(0, dy),
            color=LINE_COLORS[_FN_COLOR[kind]],
            fontsize=10,
        )
    ax.annotate(
        "$\\mu_P$",
        (c["mu_P"], 0.5),
        textcoords="offset points",
        xytext=(-20, 0),
        color=LINE_COLORS[_FN_COLOR["P"]],
        fontsize=10,
    )
    circle = dict(boxstyle="circle,pad=0.2", fc="white", ec="k", lw=0.8)
    for k, (x, y) in {1: (0.6, 0.8), 2: (0.6, 4.0), 3: (2.4, 0.8), 6: (2.2, 3.6), 7: (1.6, 5.4)}.items():
        ax.text(x, y, str(k), ha="center", va="center", fontsize=10, fontweight="bold", bbox=circle)
    # cases 4 and 5 are thin wedges between Psi_L and Psi_1: label them beside, with a line in (as the paper's Fig. 9a)
    for k, cid, x, label_at in ((4, "1_II", 1.45, (1.75, 2.5)), (5, "1_III", 2.9, (2.75, 1.0))):
        sel = t["curve"] == cid
        y = 0.5 * (c["Psi_L"] + np.interp(x, t["mu"][sel], t["Psi"][sel]))
        ax.annotate(
            str(k),
            (x, y),
            xytext=label_at,
            ha="center",
            va="center",
            fontsize=10,
            fontweight="bold",
            bbox=circle,
            arrowprops=dict(arrowstyle="-", lw=0.8, color="k", shrinkA=6, shrinkB=0),
        )
    ax.set_xticks([0, 1, c["mu_P"], 2, c["mu_L"], 3], ["0", "1", "$\\mu_P$", "2", "$\\mu_L$", "3"])
    ax.set_xlim(0, c["mu_max"])
    ax.set_ylim(0, c["Psi_max"])
    ax.set_xlabel("$\\mu$")
    ax.set_ylabel("$|\\Psi|$")
    ax.set_title(f"codimension-1 curves and codimension-2 points, $\\alpha$ = {c['alpha']:g}")
    leg = list(handles.items()) + [("codimension 2", Line2D([], [], marker="o", ls="", color="k"))]
    ax.legend([h for _, h in leg], [_TEX.get(k, k) for k, _ in leg], loc="upper left", fontsize=8, framealpha=0.9)
    curve_rows = "; ".join(f"{s['label']} ({s['curve']}): {s['cases'][0]}|{s['cases'][1]}" for s in curves)
    cap_a = (
        f"Fig. 21 recomputed (fig:mechbifs), the (mu, |Psi|) plane for alpha = {c['alpha']:g}: the codimension-1 curves where the kinematic case changes, "
        f"coloured by the critical value each is (Psi_L = {c['Psi_L']:.4f}, eq. psil; Psi_1(mu), Psi_2(mu), eqs. psi1, psi2; mu_P = {c['mu_P']:.4f}, eq. mup2D), "
        f"and the codimension-2 points where they meet (black): (mu_P, Psi_L), (mu_P, Psi_P = {c['Psi_P']:.4f}) (eq. psip) and (mu_L = {c['mu_L']:.4f}, Psi_L) (eq. mul), "
        f"where Psi_1 touches Psi_L and cases 4 and 5 meet. mu = mu_L (dotted) is no boundary elsewhere. Pale shading: the cases of Fig. 9a. Curves and the cases either side: {curve_rows}."
    )
    return ctx.figure(
        "fig21_curves",
        fig,
        cap_a,
        ["curve_samples.csv", "curves.json", "points.json", "cases.json", "constants.json"],
    )


def _strata_figure(ctx: RenderContext):
    """Fig. 21 in the paper's layout: one picture of b = 0, p = 0 and the GB manifold per cell of the strata."""
    from crosscheck.report.plotting import LINE_COLORS, plt

    cells = ctx.store.read_json("cells")
    # the paper's layout: mu strata across, |Psi| strata up, one picture per cell
    # read at the report's 1100 px: labels of 9-11 pt (the thumbnails' own 6-7.5 pt were unreadable), and the strata
    # without a picture marked as such instead of left blank
    fig = plt.figure(figsize=(10.0, 12.6))
    gs = fig.add_gridspec(8, 6, width_ratios=[0.36] + [1] * 5, height_ratios=[1] * 7 + [0.16], wspace=0.02, hspace=0.24)
    for j, name in enumerate(MU_STRATA):
        ax = fig.add_subplot(gs[7, j + 1])
        ax.set_axis_off()
        ax.text(0.5, 0.5, name, ha="center", va="center", fontsize=11, transform=ax.transAxes)
    for i, name in enumerate(PSI_STRATA):
        ax = fig.add_subplot(gs[6 - i, 0])
        ax.set_axis_off()
        ax.text(0.5, 0.5, name, ha="center", va="center", fontsize=11, rotation=90, transform=ax.transAxes)
    drawn = {(cl["col"], cl["row"]) for cl in cells}
    for col in range(len(MU_STRATA)):
        for row in range(len(PSI_STRATA)):
            if (col, row) not in drawn:
                ax = fig.add_subplot(gs[6 - row, col + 1])
                ax.set_xticks([])
                ax.set_yticks([])
                for side in ax.spines.values():
                    side.set_color("0.92")
                ax.text(
                    0.5, 0.5, "no picture", ha="center", va="center", fontsize=9, color="0.6", transform=ax.transAxes
                )
    for cl in cells:
        ax = fig.add_subplot(gs[6 - cl["row"], cl["col"] + 1], projection="3d", computed_zorder=False)
        tables = [ctx.store.read_table(f"cell_{cl['col']}_{cl['row']}_{part}") for part in ("b0", "p0", "gb")]
        draw_surfaces(ax, *tables, ctx.params["Theta_max"], labels=False)
        if cl["kind"] == "case":
            color, text = "k", f"case {cl['case']}"
        elif cl["kind"] == "curve":
            label, kind = CURVES[cl["what"]][:2]
            color, text = LINE_COLORS[_FN_COLOR[kind]], f"{_TEX[label]}: {cl['sides'][0]}|{cl['sides'][1]}"
        else:
            color, text = "k", "codim 2: " + _POINT_TEX[cl["what"]]
        ax.set_title(text, fontsize=10, pad=0, color=color, fontweight="bold" if cl["kind"] != "case" else "normal")
        ax.text2D(
            0.5,
            -0.1,
            f"$\\mu$ = {cl['mu']:.3g}, $\\Psi$ = {cl['Psi']:.3g}",
            transform=ax.transAxes,
            ha="center",
            fontsize=9,
        )
    cap_b = (
        "Fig. 21 in the paper's layout: columns are the mu strata, rows the |Psi| strata, one picture for each of the 19 cells the paper draws (cells "
        "spanning several strata there sit in their middle column or row here). Each is computed at the (mu, Psi) printed under it: b = 0 (red), "
        "p = 0 (blue: absent below mu_P, a segment at mu_P) and the GB manifold (black) in (theta, varphi, Theta), Theta in [0, 2.2], viewed as Figs. 3-7. "
        "Titles: the case of a generic cell, a codimension-1 curve (coloured as in the (mu, Psi) plane) with the cases just either side, or a "
        'codimension-2 point. "no picture": the paper draws none for that pair of strata, or a cell of a neighbouring stratum spans it.'
    )
    return ctx.figure(
        "fig21_strata",
        fig,
        cap_b,
        ["cells.json"] + [f"cell_{cl['col']}_{cl['row']}_{p}.csv" for cl in cells for p in ("b0", "p0", "gb")],
    )


def _points_table(ctx: RenderContext, points: list) -> Table:
    """The codimension-2 points and the residuals of the curves' functions there."""
    rows = [
        [
            pt["point"],
            f"{pt['mu']:.6f}",
            f"{pt['Psi']:.6f}",
            ", ".join(pt["curves"]),
            ", ".join(f"|F_{k}| = {v:.1e}" for k, v in pt["residuals"].items()),
        ]
        for pt in points
    ]
    return Table(
        caption="Codimension-2 points and the residuals there of the functions whose zeros are the curves through them (F_L = b(Psi, 0, theta_L), "
        "F_1,2 = b(Psi, 0, theta_1,2(mu)), F_P = p_min(mu)).",
        header=["point", "mu", "Psi", "curves", "residuals"],
        rows=rows,
        data=ctx.data("points.json"),
    )


SECTION = Section(
    slug=SLUG,
    title="Bifurcations between the kinematic cases: Fig. 21",
    paper="Fig. 21 (fig:mechbifs); eqs. psil, psi1, psi2, psip, mul, mup2D",
    params=params,
    run=run,
    render=render,
)
