"""Figs. 3-7 as the paper draws them: the surfaces b = 0 and p = 0 in (theta, varphi, Theta) at fixed Psi, and their sections at varphi = -pi/2.

Section 3.3 of the paper, alpha = 3, mu = 1.4, Theta >= 0 (both surfaces are
symmetric about Theta = 0).  In the space (theta, varphi, Theta) at fixed Psi:

* b = 0 (eq. b) does not depend on varphi: it is the graph
  Theta = sqrt(1/sin theta - Psi^2 cos^2 theta) over every varphi, where the
  root is real; where it is not (the theta gap of ``crosscheck.theory.gb.gb_theta_gap``,
  |Psi| > Psi_L) b > 0 already at Theta = 0 and the surface has left the
  plane Theta = 0;
* p = 0 (eq. p) does not depend on Theta or Psi: it is the cylinder over the
  closed curve varphi = varphi_-+(theta), theta in [theta_1, theta_2] (eqs.
  varphistar, theta12); p < 0 inside it;
* they meet in the GB manifold (``crosscheck.theory.gb.gb_manifold``), drawn black.

Panels: Fig. 3 (a) the section at varphi = -pi/2 and (b) the 3D picture at
Psi = 0; Fig. 4 (a-d) the 3D picture at Psi = 1.56, 1.7, 2.2, 5; Figs. 5, 6,
7 (a) section and (b) 3D picture at Psi = Psi_L, Psi_1, Psi_2 (eqs. psil,
psi1, psi2).  The sections are shaded by the four modes of the LCP (the
paper's colours); the 3D pictures show the two surfaces as the paper does.

Checks (what the figures assert): b and p vanish on the computed GB curve to
GB_IDENTITY; at Psi = 0 the GB manifold in Theta > 0 is one closed curve off
Theta = 0 (Fig. 3b); b = 0 reaches Theta = 0 iff |Psi| >= Psi_L (Fig. 4) and
at Psi_L touches it at theta_L only (Fig. 5); at Psi_1 b = 0 touches the
cylinder at theta_1, Theta = 0 (Fig. 6); the part of the cylinder p < 0 below
b = 0 (inconsistent) is empty iff |Psi| >= Psi_2 (Figs. 4d, 7), counted on a
(theta, varphi, Theta) grid.

The surfaces' meshes and their 3D drawing: ``crosscheck.report.surfaces``.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.report.surfaces import Theta2_on_b0, draw_surfaces, surface_meshes
from crosscheck.theory import analytic, critical
from crosscheck.tolerances import CLOSED_FORM, GB_IDENTITY

__all__ = ["SECTION", "FIGURE_PANELS"]

SLUG = "kinematic_surfaces"

#: The paper's panels: figure -> [(letter, "2d" section at varphi = -pi/2 or "3d" picture, Psi label)].
FIGURE_PANELS = {
    3: [("a", "2d", "0"), ("b", "3d", "0")],
    4: [("a", "3d", "1.56"), ("b", "3d", "1.7"), ("c", "3d", "2.2"), ("d", "3d", "5")],
    5: [("a", "2d", "Psi_L"), ("b", "3d", "Psi_L")],
    6: [("a", "2d", "Psi_1"), ("b", "3d", "Psi_1")],
    7: [("a", "2d", "Psi_2"), ("b", "3d", "Psi_2")],
}
_LABELS = {3: "fig:p3s", 4: "fig:p3ss", 5: "fig:psi1.6119", 6: "fig:psi1.9483", 7: "fig:psi3.0097"}


def params(quick: bool) -> dict:
    return {
        "mu": 1.4,
        "alpha": 3.0,
        "Theta_max": 2.2,
        "n_map": 120 if quick else 360,
        "n_surface": 41 if quick else 81,
        "n_varphi": 31 if quick else 61,
        "n_Theta": 12 if quick else 24,
        "n_gb": 101 if quick else 401,
        "n_count": 60 if quick else 150,
        "n_fine": 20001,
    }


def _tag(label: str) -> str:
    return "Psi" + label.replace("Psi", "").replace(".", "p")


def run(ctx: RunContext) -> None:
    P = ctx.params
    mu, alpha, Tmax = P["mu"], P["alpha"], P["Theta_max"]
    cv = critical.critical_values(mu, alpha)
    ctx.store.write_json("critical_values", cv)
    named = {"Psi_L": cv.Psi_L, "Psi_1": cv.Psi_1, "Psi_2": cv.Psi_2}
    labels = list(dict.fromkeys(lab for panels in FIGURE_PANELS.values() for _, _, lab in panels))
    Psis = {lab: named[lab] if lab in named else float(lab) for lab in labels}

    # the (theta, varphi, Theta) grid on which the inconsistent region is counted
    gth = cell_centres(0.0, np.pi / 2, P["n_count"])
    gvp = cell_centres(-np.pi, 0.0, P["n_count"])
    gTh = cell_centres(0.0, Tmax, P["n_count"] // 2)
    p_grid = analytic.p(gth[None, :], gvp[:, None], mu, alpha)  # (varphi, theta)
    theta_map = cell_centres(0.0, np.pi / 2, P["n_map"])
    Theta_map = cell_centres(0.0, Tmax, P["n_map"])
    p_planar = analytic.p(theta_map, -np.pi / 2, mu, alpha)
    theta_fine = np.linspace(0.0, np.pi / 2, P["n_fine"])[1:-1]

    summary = []
    for label in ctx.progress(labels, desc="kinematic surfaces"):
        Psi, tag = Psis[label], _tag(label)
        m = surface_meshes(
            mu,
            Psi,
            alpha,
            Tmax,
            n_surface=P["n_surface"],
            n_varphi=P["n_varphi"],
            n_Theta=P["n_Theta"],
            n_gb=P["n_gb"],
            n_fine=P["n_fine"],
        )
        pieces, curves, tangency, g = m["pieces"], m["gb_curves"], m["tangency"], m["gb"]
        ctx.store.write_table(f"b0_surface_{tag}", m["b0"])
        ctx.store.write_table(f"p0_surface_{tag}", m["p0"])
        ctx.store.write_table(f"gb_{tag}", g)
        gth_, gvp_, gTh_ = (np.asarray(g[k], float) for k in ("theta", "varphi", "Theta"))
        b_gb = analytic.b(Psi, gTh_, gth_) if gth_.size else np.zeros(0)
        p_gb = analytic.p(gth_, gvp_, mu, alpha) if gth_.size else np.zeros(0)

        # the GB points in the section varphi = -pi/2: b = 0 on the lines theta_1, theta_2 (P+, Q+ at Psi = 0)
        section_gb = [
            [t, math.sqrt(max(float(Theta2_on_b0(Psi, t)), 0.0))]
            for t in (cv.theta_1, cv.theta_2)
            if Theta2_on_b0(Psi, t) >= -CLOSED_FORM.allowance(1 / math.sin(t))
        ]
        # the modes in the section varphi = -pi/2 (the paper's panels (a))
        modes = analytic.mode(analytic.b(Psi, Theta_map[:, None], theta_map[None, :]), p_planar[None, :])
        ctx.store.write_grid(f"section_{tag}", ("theta", theta_map), ("Theta", Theta_map), ("mode", modes))

        # inconsistent: p < 0 (inside the cylinder) and b < 0 (below b = 0), counted on the 3D grid
        bb = analytic.b(Psi, gTh[:, None], gth[None, :])  # (Theta, theta)
        n_inconsistent = int(np.sum((p_grid[None, :, :] < 0) & (bb[:, None, :] < 0)))
        T2 = Theta2_on_b0(Psi, theta_fine)
        summary.append(
            {
                "label": label,
                "Psi": Psi,
                "kinematic_case": critical.kinematic_case(mu, Psi, alpha),
                "pieces": pieces,
                "section_gb": section_gb,
                "gb_curves": len(curves),
                "gb_points": int(gth_.size),
                "gb_tangency_point": tangency,
                "gb_closed": [
                    bool(c.theta[0] == c.theta[-1] and c.varphi[0] == c.varphi[-1] and c.Theta[0] == c.Theta[-1])
                    for c in curves
                ],
                "gb_min_Theta": float(gTh_.min()) if gTh_.size else None,
                "gb_max_abs_b": float(np.max(np.abs(b_gb))) if b_gb.size else None,
                "gb_max_abs_p": float(np.max(np.abs(p_gb))) if p_gb.size else None,
                "inconsistent_cells": n_inconsistent,
                "min_Theta2_on_b0": float(T2.min()),
                "argmin_theta": float(theta_fine[np.argmin(T2)]),
            }
        )
        ctx.store.write_json("slices", summary)

    _checks(ctx, summary, cv, theta_fine[1] - theta_fine[0])


def _checks(ctx: RunContext, summary: list[dict], cv, dtheta: float) -> None:
    allow_gb = float(GB_IDENTITY.allowance(0.0))
    for s in summary:
        if s["gb_points"]:
            worst = max(s["gb_max_abs_b"], s["gb_max_abs_p"])
            ctx.check(
                f"Psi = {s['label']}: b = p = 0 on the computed GB curve ({s['gb_points']} points)",
                worst <= allow_gb,
                value=worst,
                allowance=allow_gb,
                detail=f"max |b| {s['gb_max_abs_b']:.2e}, max |p| {s['gb_max_abs_p']:.2e} (eqs. b, p; GB_IDENTITY)",
            )
    by = {s["label"]: s for s in summary}
    s0 = by["0"]
    ok = s0["gb_curves"] == 2 and all(s0["gb_closed"]) and s0["gb_min_Theta"] > 0
    ctx.check(
        "Fig. 3b: at Psi = 0 the GB manifold in Theta > 0 is one closed curve off Theta = 0",
        ok,
        detail=f"{s0['gb_curves']} curves in Theta > 0 and Theta < 0, closed: {s0['gb_closed']}, min Theta on the Theta > 0 curve {s0['gb_min_Theta']:.4f}",
    )
    # lift-off at Theta = 0 exists iff b = 0 reaches the plane Theta = 0 (min of Theta^2 on b = 0 <= 0)
    atol = CLOSED_FORM.atol
    wrong = [
        s["label"]
        for s in summary
        if s["label"] not in ("Psi_L", "Psi_1", "Psi_2") and (s["min_Theta2_on_b0"] <= atol) != (s["Psi"] >= cv.Psi_L)
    ]
    ctx.check(
        "Fig. 4: b = 0 reaches Theta = 0 iff |Psi| >= Psi_L (at Psi = 0, 1.56, 1.7, 2.2, 5)",
        not wrong,
        value=len(wrong),
        allowance=0,
        detail="min over theta of Theta^2 on b = 0: "
        + ", ".join(f"{s['label']}: {s['min_Theta2_on_b0']:.4g}" for s in summary),
    )
    sL = by["Psi_L"]
    r = abs(float(Theta2_on_b0(cv.Psi_L, critical.theta_L)))
    allow = float(CLOSED_FORM.allowance(1.0 / math.sin(critical.theta_L)))
    ctx.check(
        "Fig. 5: at Psi = Psi_L, b = 0 touches Theta = 0 at theta_L (eqs. thetal, psil)",
        r <= allow,
        value=r,
        allowance=allow,
        detail=f"|Theta^2 on b = 0| at theta_L = {critical.theta_L:.6f}",
    )
    cell_ok = (
        abs(sL["argmin_theta"] - critical.theta_L) <= dtheta
        and sL["min_Theta2_on_b0"] >= -atol
        and len(sL["pieces"]) == 1
    )
    ctx.check(
        "Fig. 5: at Psi = Psi_L, b = 0 does not cross Theta = 0 (one piece, min Theta^2 >= 0 at theta_L to one grid step)",
        cell_ok,
        value=sL["min_Theta2_on_b0"],
        allowance=-atol,
        detail=f"argmin theta {sL['argmin_theta']:.6f} vs theta_L {critical.theta_L:.6f} (step {dtheta:.1e}); {len(sL['pieces'])} piece(s)",
    )
    r1 = abs(float(Theta2_on_b0(cv.Psi_1, cv.theta_1)))
    allow1 = float(CLOSED_FORM.allowance(1.0 / math.sin(cv.theta_1)))
    ctx.check(
        "Fig. 6: at Psi = Psi_1, b = 0 touches the cylinder p = 0 at theta_1, Theta = 0 (eq. psi1)",
        r1 <= allow1,
        value=r1,
        allowance=allow1,
        detail=f"|Theta^2 on b = 0| at theta_1 = {cv.theta_1:.6f}; min Theta on the computed GB curve {by['Psi_1']['gb_min_Theta']:.2e}",
    )
    wrong = [s["label"] for s in summary if (s["inconsistent_cells"] == 0) != (s["Psi"] >= cv.Psi_2)]
    ctx.check(
        "Figs. 4d, 7: the part of the cylinder p < 0 below b = 0 (inconsistent) is empty iff |Psi| >= Psi_2 (eq. psi2)",
        not wrong,
        value=len(wrong),
        allowance=0,
        detail="inconsistent cells of the (theta, varphi, Theta) grid: "
        + ", ".join(f"{s['label']}: {s['inconsistent_cells']}" for s in summary),
    )


# ------------------------------------------------------------------ render ---


def _psi_title(s: dict) -> str:
    if s["label"].startswith("Psi_"):
        return f"$\\Psi=\\pm\\Psi_{{\\mathrm{{{s['label'][4:]}}}}}$ = $\\pm${s['Psi']:.4f}"
    return "$\\Psi$ = 0" if s["Psi"] == 0 else f"$\\Psi=\\pm${s['label']}"


def _draw_3d(ax, ctx: RenderContext, s: dict, cv: dict) -> None:
    tag = _tag(s["label"])
    draw_surfaces(
        ax,
        ctx.store.read_table(f"b0_surface_{tag}"),
        ctx.store.read_table(f"p0_surface_{tag}"),
        ctx.store.read_table(f"gb_{tag}"),
        ctx.params["Theta_max"],
    )


def _draw_2d(ax, ctx: RenderContext, s: dict, cv: dict) -> None:
    from crosscheck.report.plotting import B_COLOR, P_COLOR, mode_image

    tag = _tag(s["label"])
    x, y, z, _ = ctx.store.read_grid(f"section_{tag}")
    mode_image(ax, x, y, z)
    b0 = ctx.store.read_table(f"b0_surface_{tag}")
    first = b0["j"] == 0  # the section varphi = -pi/2 of b = 0 is its generating curve (any varphi)
    for k in np.unique(b0["piece"]):
        sel = first & (b0["piece"] == k)
        ax.plot(b0["theta"][sel], b0["Theta"][sel], color=B_COLOR, lw=1.6)
    for t in (cv["theta_1"], cv["theta_2"]):
        ax.axvline(t, color=P_COLOR, lw=1.4)
    for k, (t, T) in enumerate(s["section_gb"]):
        ax.plot(t, T, "ko", ms=4)
        if s["Psi"] == 0:  # the paper's names of the planar GB points
            ax.annotate(
                ("$P^+$", "$Q^+$")[k], (t, T), textcoords="offset points", xytext=(-17, 6) if k == 0 else (5, 6)
            )
    ticks = [0, np.pi / 4, cv["theta_1"], cv["theta_2"], np.pi / 2]
    names = ["0", "$\\pi/4$", "$\\theta_1$", "$\\theta_2$", "$\\pi/2$"]
    if s["label"] == "Psi_L":
        ticks.insert(1, critical.theta_L)
        names.insert(1, "$\\theta_L$")
    ax.set_xticks(ticks, names)
    ax.set_xlim(0, np.pi / 2)
    ax.set_ylim(0, ctx.params["Theta_max"])
    ax.set_xlabel("$\\theta$")
    ax.set_ylabel("$\\Theta$")


def render(ctx: RenderContext) -> list:
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from crosscheck.report.plotting import B_COLOR, MODE_COLORS, P_COLOR, plt

    cv = ctx.store.read_json("critical_values")
    slices = {s["label"]: s for s in ctx.store.read_json("slices")}
    blocks = []
    surf_handles = [
        Patch(color=B_COLOR, alpha=0.6, label="b = 0"),
        Patch(color=P_COLOR, alpha=0.5, label="p = 0"),
        Line2D([], [], color="k", lw=1.8, label="GB: b = p = 0"),
    ]
    mode_handles = [Patch(color=MODE_COLORS[m], label=m.name.lower()) for m in sorted(MODE_COLORS)]
    for number, panels in FIGURE_PANELS.items():
        n = len(panels)
        cols = 2 if n == 4 else n
        rows = (n + cols - 1) // cols
        fig = plt.figure(figsize=(5.2 * cols, 4.3 * rows + 0.5))
        data = ["critical_values.json", "slices.json"]
        for k, (letter, kind, label) in enumerate(panels):
            s = slices[label]
            tag = _tag(label)
            if kind == "3d":
                ax = fig.add_subplot(rows, cols, k + 1, projection="3d", computed_zorder=False)
                _draw_3d(ax, ctx, s, cv)
                where = "" if number == 4 else ", $\\varphi\\in(-\\pi,0]$"
            else:
                ax = fig.add_subplot(rows, cols, k + 1)
                _draw_2d(ax, ctx, s, cv)
                where = ", $\\varphi=-\\pi/2$"
                data.append(f"section_{tag}.json")
            ax.set_title(f"({letter}) {_psi_title(s)}{where}  (case {s['kinematic_case']})")
            data += [f"b0_surface_{tag}.csv", f"p0_surface_{tag}.csv", f"gb_{tag}.csv"]
        has_2d = any(kind == "2d" for _, kind, _ in panels)
        fig.legend(
            handles=surf_handles + (mode_handles if has_2d else []),
            loc="outside lower center",
            ncol=len(surf_handles) + (4 if has_2d else 0),
            fontsize=8,
        )
        blocks.append(
            ctx.figure(f"fig{number}_surfaces", fig, _caption(number, panels, slices, cv), list(dict.fromkeys(data)))
        )
    rows_t = []
    for s in slices.values():
        rows_t.append(
            [
                s["label"],
                f"{s['Psi']:.4f}",
                str(s["kinematic_case"]),
                str(s["gb_points"]) + (" (tangency point)" if s["gb_tangency_point"] else ""),
                "" if s["gb_max_abs_b"] is None else f"{max(s['gb_max_abs_b'], s['gb_max_abs_p']):.1e}",
                f"{s['min_Theta2_on_b0']:.4f}",
                str(s["inconsistent_cells"]),
            ]
        )
    blocks.append(
        Table(
            caption=f"Each Psi drawn (alpha = {cv['alpha']:g}, mu = {cv['mu']:g}): the GB points in Theta >= 0 and the larger of max |b|, max |p| on them; "
            "the smallest Theta^2 on b = 0 over theta (<= 0: b = 0 reaches Theta = 0, lift-off with no polar motion); the grid cells of the "
            "cylinder p < 0 below b = 0 (inconsistent).",
            header=[
                "Psi",
                "value",
                "case",
                "GB points",
                "max |b|, |p| on GB",
                "min Theta^2 on b = 0",
                "inconsistent cells",
            ],
            rows=rows_t,
            data=ctx.data("slices.json"),
        )
    )
    return blocks


def _caption(number: int, panels, slices: dict, cv: dict) -> str:
    common = (
        f"b = 0 (red, eq. b: independent of varphi) and p = 0 (blue, eq. p: the cylinder over varphi_-+(theta), independent of Theta and Psi) for "
        f"Theta >= 0, alpha = {cv['alpha']:g}, mu = {cv['mu']:g}; black: the GB manifold b = p = 0 (crosscheck.theory.gb.gb_manifold). Inside the cylinder "
        "p < 0: indeterminate above b = 0, inconsistent below; outside: lift-off above, slipping below."
    )
    if number == 3:
        return (
            f"Fig. 3 recomputed ({_LABELS[3]}): (a) the section varphi = -pi/2, shaded by mode (slipping yellow, lift-off orange, inconsistent lime, "
            f"indeterminate purple), where b = 0 and p = 0 meet at P+ and Q+; (b) the 3D picture at Psi = 0, where they meet in one closed curve. "
            + common
        )
    if number == 4:
        vals = ", ".join(f"({l}) {slices[p]['label']}" for l, _, p in panels)
        return (
            f"Fig. 4 recomputed ({_LABELS[4]}): the 3D picture as Psi grows, Psi = {vals}. From Psi_L = {cv['Psi_L']:.4f} b = 0 reaches Theta = 0 "
            "(lift-off with no polar motion, (b)); at 2.2 it does so inside the cylinder too (indeterminacy at Theta = 0, (c)); at 5 > Psi_2 "
            "b = 0 lies above the cylinder's interior everywhere: no inconsistent state (d). " + common
        )
    name, value, what = {
        5: (
            "Psi_L",
            cv["Psi_L"],
            "b = 0 touches Theta = 0 at theta_L = 0.6155 (eqs. thetal, psil): lift-off with Theta = 0 from here on",
        ),
        6: (
            "Psi_1",
            cv["Psi_1"],
            f"b = 0 touches the cylinder p = 0 at theta_1 = {cv['theta_1']:.4f}, Theta = 0 (eq. psi1): the GB curve reaches Theta = 0 there",
        ),
        7: (
            "Psi_2",
            cv["Psi_2"],
            f"b = 0 touches the cylinder at theta_2 = {cv['theta_2']:.4f}, Theta = 0 (eq. psi2): the GB manifold has shrunk to that point "
            "and the inconsistent region is empty",
        ),
    }[number]
    return (
        f"Fig. {number} recomputed ({_LABELS[number]}): Psi = +-{name} = +-{value:.4f}, (a) the section varphi = -pi/2 shaded by mode, (b) the 3D picture. {what}. "
        + common
    )


SECTION = Section(
    slug=SLUG,
    title="The surfaces b = 0 and p = 0 in 3D: Figs. 3-7",
    paper="Figs. 3-7 (fig:p3s, fig:p3ss, fig:psi1.6119, fig:psi1.9483, fig:psi3.0097); eqs. b, p, psil, psi1, psi2",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.theory.gb",),
)
