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
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import analytic, critical
from crosscheck.tolerances import CLOSED_FORM, GB_IDENTITY

__all__ = ["SECTION", "FIGURE_PANELS", "Theta2_on_b0", "b0_pieces", "p0_cylinder", "surface_meshes", "draw_surfaces"]

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


def Theta2_on_b0(Psi, theta):
    """Theta^2 on b = 0 (eq. b): 1/sin theta - Psi^2 cos^2 theta; negative where b > 0 already at Theta = 0."""
    return 1.0 / np.sin(theta) - Psi**2 * np.cos(theta) ** 2


def b0_pieces(Psi: float, Theta_max: float, *, n: int = 20001) -> list[tuple[float, float]]:
    """theta intervals of (0, pi/2] where b = 0 has a root 0 <= Theta <= Theta_max, edges refined by brentq.

    Theta^2 on b = 0 tends to +inf as theta -> 0 (clipped at Theta_max) and to 1
    at theta = pi/2; it is negative in the theta gap (|Psi| > Psi_L).  A
    double root (|Psi| = Psi_L at theta_L) is not an edge: the surface touches
    Theta = 0 there and the interval goes on.
    """
    from scipy.optimize import brentq

    theta = np.linspace(0.0, np.pi / 2, n)[1:]
    g = Theta2_on_b0(Psi, theta)
    inside = (g >= 0) & (g <= Theta_max**2)
    pieces = []
    for lo_i, hi_i in _runs(inside):
        ends = []
        for i, side in ((lo_i, -1), (hi_i, +1)):
            j = i + side
            if j < 0 or j >= theta.size:  # the run reaches the end of the sampled range (theta = pi/2)
                ends.append(float(theta[i]))
                continue
            level = 0.0 if g[j] < 0 else Theta_max**2
            a, b = sorted((float(theta[i]), float(theta[j])))
            ends.append(brentq(lambda t: Theta2_on_b0(Psi, t) - level, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps))
        pieces.append((ends[0], ends[1]))
    return pieces


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    # (first, last) index of each run of True
    d = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


def _spaced(lo: float, hi: float, n: int) -> np.ndarray:
    # cosine spacing: Theta on b = 0 and varphi on p = 0 have square-root ends
    return lo + (hi - lo) * 0.5 * (1 - np.cos(np.pi * np.linspace(0.0, 1.0, n)))


def p0_cylinder(mu: float, alpha: float, *, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The closed curve p = 0 in (theta, varphi) (eqs. varphistar, theta12): theta_1 -> theta_2 on varphi_-, back on varphi_+.

    Returns (theta, varphi), 2n - 1 samples, the last equal to the first.
    """
    cv = critical.critical_values(mu, alpha)
    th = _spaced(cv.theta_1, cv.theta_2, n)
    vm, vp = critical.varphi_pm(th, mu, alpha)
    # varphi_-+ meet at -pi/2 where theta = theta_1,2; rounding of the arccos argument can leave NaN there
    vm, vp = np.where(np.isnan(vm), -np.pi / 2, vm), np.where(np.isnan(vp), -np.pi / 2, vp)
    return np.concatenate([th, th[::-1][1:]]), np.concatenate([vm, vp[::-1][1:]])


def surface_meshes(
    mu: float,
    Psi: float,
    alpha: float,
    Theta_max: float,
    *,
    n_surface: int,
    n_varphi: int,
    n_Theta: int,
    n_gb: int,
    n_fine: int = 20001,
) -> dict:
    """The 3D picture at one (mu, Psi) as tables (columns of equal length) ready to save and draw.

    Returns a dict with
      "b0": piece, i, j, theta, varphi, Theta: the mesh of b = 0 for Theta in [0, Theta_max] (i along theta, j along varphi);
      "p0": part, i, j, theta, varphi, Theta: the cylinder p = 0 in two parts, below b = 0 (part 0, inconsistent inside)
        and above it (part 1, indeterminate inside), so that a view from above draws b = 0 between them; empty for
        mu < mu_P, a segment at mu = mu_P;
      "gb": curve, theta, varphi, Theta: the GB manifold in Theta >= 0 (``crosscheck.theory.gb.gb_manifold``); where that is
        empty but b = 0 touches the cylinder at theta_1 or theta_2 with Theta = 0 (|Psi| = Psi_1, Psi_2), that point;
      "pieces": the theta intervals of b = 0 (``b0_pieces``); "gb_curves": the ``GBCurve`` list; "tangency": whether
        "gb" is such a touching point.
    """
    from crosscheck.theory import gb

    vp = np.linspace(-np.pi, 0.0, n_varphi)
    pieces = b0_pieces(Psi, Theta_max, n=n_fine)
    b0 = {k: [] for k in ("piece", "i", "j", "theta", "varphi", "Theta")}
    for k, (lo, hi) in enumerate(pieces):
        th = _spaced(lo, hi, n_surface)
        if (
            lo < critical.theta_L < hi
        ):  # where b = 0 comes closest to Theta = 0 at Psi_L (a tangency, eq. thetal): sample it
            th = np.sort(np.append(th, critical.theta_L))
        T = np.sqrt(np.maximum(Theta2_on_b0(Psi, th), 0.0))  # the edges are roots: clip their rounding
        for key, v in (
            ("piece", np.full(th.size * vp.size, k)),
            ("i", np.repeat(np.arange(th.size), vp.size)),
            ("j", np.tile(np.arange(vp.size), th.size)),
            ("theta", np.repeat(th, vp.size)),
            ("varphi", np.tile(vp, th.size)),
            ("Theta", np.repeat(T, vp.size)),
        ):
            b0[key] += list(v)
    p0 = {k: [] for k in ("part", "i", "j", "theta", "varphi", "Theta")}
    g = {k: [] for k in ("curve", "theta", "varphi", "Theta")}
    th1, th2 = (float(t) for t in critical.theta_12(mu, alpha))
    curves, tangency = [], False
    if not math.isnan(th1):  # p < 0 somewhere: mu >= mu_P
        cth, cvp = p0_cylinder(mu, alpha, n=n_surface)
        u = np.linspace(0.0, 1.0, n_Theta)
        cut = np.minimum(
            np.sqrt(np.maximum(Theta2_on_b0(Psi, cth), 0.0)), Theta_max
        )  # b = 0 on the cylinder (0 in the theta gap)
        for part, (lo, hi) in enumerate(((np.zeros_like(cut), cut), (cut, np.full_like(cut, Theta_max)))):
            Th = lo[:, None] + (hi - lo)[:, None] * u[None, :]
            for key, v in (
                ("part", np.full(Th.size, part)),
                ("i", np.repeat(np.arange(cth.size), u.size)),
                ("j", np.tile(np.arange(u.size), cth.size)),
                ("theta", np.repeat(cth, u.size)),
                ("varphi", np.repeat(cvp, u.size)),
                ("Theta", Th.ravel()),
            ):
                p0[key] += list(v)
        curves = gb.gb_manifold(mu, Psi, alpha, n=n_gb)
        for k, c in enumerate(curves):
            keep = c.Theta >= 0
            for key, v in (
                ("curve", np.full(keep.sum(), k)),
                ("theta", c.theta[keep]),
                ("varphi", c.varphi[keep]),
                ("Theta", c.Theta[keep]),
            ):
                g[key] += list(v)
        if not curves:
            # at |Psi| = Psi_2 the manifold is the point where b = 0 touches the cylinder at Theta = 0; gb_manifold's theta
            # gap can miss it by rounding (its edge lands 1e-15 beyond theta_2)
            for t in (th1, th2):
                if abs(Theta2_on_b0(Psi, t)) <= CLOSED_FORM.allowance(1 / math.sin(t)):
                    g = {"curve": [0], "theta": [t], "varphi": [-math.pi / 2], "Theta": [0.0]}
                    tangency = True
                    break
    return {"b0": b0, "p0": p0, "gb": g, "pieces": pieces, "gb_curves": curves, "tangency": tangency}


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


def draw_surfaces(ax, b0: dict, p0: dict, g: dict, Theta_max: float, *, labels: bool = True) -> None:
    """Draw the tables of ``surface_meshes`` on a 3D axes made with ``computed_zorder=False``: b = 0 red, p = 0 blue, GB black."""
    from matplotlib.colors import LightSource

    from crosscheck.report.plotting import B_COLOR, P_COLOR

    def mesh(t, key, k):
        sel = t[key] == k
        ni, nj = int(t["i"][sel].max()) + 1, int(t["j"][sel].max()) + 1
        return (np.asarray(t[c])[sel].reshape(ni, nj) for c in ("theta", "varphi", "Theta"))

    light = LightSource(azdeg=300, altdeg=70)  # nearly overhead: b = 0 falling and rising in theta shade alike
    style = dict(
        alpha=0.55, linewidth=0, antialiased=True, shade=True, lightsource=light, rasterized=True
    )  # vector text, raster surfaces: small SVG
    p0 = {k: np.asarray(v) for k, v in p0.items()}
    b0 = {k: np.asarray(v) for k, v in b0.items()}
    # painter's order for a view from above: the cylinder below b = 0, then b = 0, then the cylinder above it
    degenerate = (
        p0["part"].size and np.ptp(p0["theta"]) == 0
    )  # mu = mu_P: p = 0 only on the segment theta_P, varphi = -pi/2
    if degenerate:
        ax.plot(p0["theta"][:2], p0["varphi"][:2], [0, Theta_max], color=P_COLOR, lw=2.0)
    elif p0["part"].size:
        ax.plot_surface(*mesh(p0, "part", 0), color=P_COLOR, **style)
    for k in np.unique(b0["piece"]):
        ax.plot_surface(*mesh(b0, "piece", k), color=B_COLOR, **style)
    if p0["part"].size and not degenerate:
        ax.plot_surface(*mesh(p0, "part", 1), color=P_COLOR, **style)
    g = {k: np.asarray(v, float) for k, v in g.items()}
    for k in np.unique(g["curve"]):
        sel = g["curve"] == k
        if sel.sum() == 1:
            ax.scatter(
                g["theta"][sel],
                g["varphi"][sel],
                g["Theta"][sel],
                color="k",
                s=14 if labels else 6,
                zorder=10,
                depthshade=False,
            )
        else:
            ax.plot(g["theta"][sel], g["varphi"][sel], g["Theta"][sel], color="k", lw=1.8 if labels else 1.0, zorder=10)
    ax.set_xlim(0, np.pi / 2)
    ax.set_ylim(-np.pi, 0)
    ax.set_zlim(0, Theta_max)
    ax.view_init(elev=24, azim=-122)
    if labels:
        ax.set_xticks([0, np.pi / 4, np.pi / 2], ["0", "$\\pi/4$", "$\\pi/2$"])
        ax.set_yticks([-np.pi, -np.pi / 2, 0], ["$-\\pi$", "$-\\pi/2$", "0"])
        ax.set_zticks([0, 1, 2])
        ax.set_xlabel("$\\theta$", labelpad=-6)
        ax.set_ylabel("$\\varphi$", labelpad=-6)
        ax.set_zlabel("$\\Theta$", labelpad=-8)
        ax.tick_params(pad=-2, labelsize=7)
        ax.set_box_aspect(None, zoom=1.05)
    else:
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_zticks([])
        ax.set_box_aspect(None, zoom=1.15)


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
