"""Fig. 2b: the region p < 0 in the (theta, varphi) plane, bounded by theta_1, theta_2, varphi_1, varphi_2.

Recomputed from eq. p on a grid, with the closed-form boundary varphi_-+(theta)
(eq. varphistar) drawn over it.  Checks: the grid's region p < 0 spans
(theta_1, theta_2) x (varphi_1, varphi_2) to within one grid cell (eqs.
theta12, varphi12), and the closed-form boundary lies on p = 0.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import analytic, critical
from crosscheck.tolerances import ROOT_RESIDUAL

SLUG = "p_region"


def params(quick: bool) -> dict:
    n = 121 if quick else 401
    return {"mu": 1.4, "alpha": 3.0, "n_theta": n, "n_varphi": n, "n_boundary": 201}


def run(ctx: RunContext) -> None:
    P = ctx.params
    mu, alpha = P["mu"], P["alpha"]
    theta = cell_centres(0.0, np.pi / 2, P["n_theta"])
    varphi = cell_centres(-np.pi, 0.0, P["n_varphi"])
    p = analytic.p(theta[None, :], varphi[:, None], mu, alpha)
    ctx.store.write_grid("p_grid", ("theta", theta), ("varphi", varphi), ("p", p))
    cv = critical.critical_values(mu, alpha)
    ctx.store.write_json("critical_values", cv)

    th = np.linspace(cv.theta_1, cv.theta_2, P["n_boundary"])
    vm, vp = critical.varphi_pm(th, mu, alpha)
    ctx.store.write_table("p_zero", {"theta": th, "varphi_minus": vm, "varphi_plus": vp})

    neg = p < 0
    cols, rows = np.any(neg, axis=0), np.any(neg, axis=1)
    dth, dvp = theta[1] - theta[0], varphi[1] - varphi[0]
    extent = {
        "theta_min": theta[cols].min(),
        "theta_max": theta[cols].max(),
        "varphi_min": varphi[rows].min(),
        "varphi_max": varphi[rows].max(),
    }
    ctx.store.write_json("grid_extent", extent)
    for key, want, cell in (
        ("theta_min", cv.theta_1, dth),
        ("theta_max", cv.theta_2, dth),
        ("varphi_min", cv.varphi_1, dvp),
        ("varphi_max", cv.varphi_2, dvp),
    ):
        ctx.check(
            f"p<0 grid {key} vs closed form",
            abs(extent[key] - want) <= cell,
            value=abs(extent[key] - want),
            allowance=cell,
            detail=f"grid {extent[key]:.5f}, closed form {want:.5f} (one cell = {cell:.2e})",
        )
    resid = np.nanmax(np.abs(analytic.p(np.concatenate([th, th]), np.concatenate([vm, vp]), mu, alpha)))
    ctx.check(
        "p = 0 on the closed-form boundary varphi_-+(theta)",
        resid <= ROOT_RESIDUAL.atol,
        value=float(resid),
        allowance=ROOT_RESIDUAL.atol,
        detail="eq. varphistar, tolerance ROOT_RESIDUAL",
    )


def render(ctx: RenderContext) -> list:
    from matplotlib.colors import ListedColormap

    from crosscheck.report.plotting import P_COLOR, plt

    theta, varphi, p, _ = ctx.store.read_grid("p_grid")
    cv = ctx.store.read_json("critical_values")
    bnd = ctx.store.read_table("p_zero")
    fig, ax = plt.subplots(figsize=(5.2, 4.2))
    ax.imshow(
        (p < 0).astype(float),
        origin="lower",
        aspect="auto",
        extent=[0, np.pi / 2, -np.pi, 0],
        cmap=ListedColormap(["white", (0.55, 0.72, 0.95)]),
        vmin=0,
        vmax=1,
    )
    ax.plot(bnd["theta"], bnd["varphi_minus"], color=P_COLOR, lw=1.2, label="p = 0 (eq. varphistar)")
    ax.plot(bnd["theta"], bnd["varphi_plus"], color=P_COLOR, lw=1.2)
    for t in (cv["theta_1"], cv["theta_2"]):
        ax.axvline(t, color="k", ls="--", lw=0.6)
    for v in (cv["varphi_1"], cv["varphi_2"], -np.pi / 2):
        ax.axhline(v, color="k", ls="--", lw=0.6)
    ax.set_xticks(
        [0, np.pi / 4, cv["theta_1"], cv["theta_2"], np.pi / 2],
        ["0", "$\\pi/4$", "$\\theta_1$", "$\\theta_2$", "$\\pi/2$"],
    )
    ax.set_yticks(
        [-np.pi, cv["varphi_1"], -np.pi / 2, cv["varphi_2"], 0],
        ["$-\\pi$", "$\\varphi_1$", "$-\\pi/2$", "$\\varphi_2$", "0"],
    )
    ax.set_xlabel("$\\theta$")
    ax.set_ylabel("$\\varphi$")
    ax.set_xlim(0, np.pi / 2)
    ax.set_ylim(-np.pi, 0)
    ax.set_title(f"p < 0 (blue), $\\alpha$ = {cv['alpha']:g}, $\\mu$ = {cv['mu']:g}")
    ax.legend(loc="lower left", fontsize=8)
    caption = (
        f"Fig. 2b recomputed: region p < 0 (eq. p) for alpha = {cv['alpha']:g}, mu = {cv['mu']:g}. "
        f"theta_1 = {cv['theta_1']:.4f}, theta_2 = {cv['theta_2']:.4f} (eq. theta12); varphi_1 = {cv['varphi_1']:.4f}, "
        f"varphi_2 = {cv['varphi_2']:.4f} at theta_P = {cv['theta_P']:.4f} (eqs. varphi12, thetap). "
        "Grid of p, closed-form boundary and critical values are in the data files."
    )
    fig_block = ctx.figure("fig2b_p_region", fig, caption, ["p_grid.json", "p_zero.csv", "critical_values.json"])
    rows = [[k, f"{cv[k]:.6f}"] for k in ("theta_1", "theta_2", "theta_P", "varphi_1", "varphi_2")]
    return [
        _physical(ctx, theta, varphi, p, cv),
        fig_block,
        Table(
            caption="Bounds of the region p < 0 (closed forms).",
            header=["quantity", "value"],
            rows=rows,
            data=ctx.data("critical_values.json"),
        ),
    ]


def _physical(ctx: RenderContext, theta, varphi, p, cv):
    """Fig. 2a: the same grid as rod directions in space, in the frame where the tip slips along +x.

    By eq. tipfromcentre the rod points from the tip A to B along (-cos theta sin psi, cos theta cos psi, sin theta):
    horizontally at heading psi + pi/2, which is pi/2 - varphi from the slip heading beta = psi + varphi.  In the
    slip frame the direction is (cos theta sin varphi, cos theta cos varphi, sin theta); varphi = -pi/2 is the
    planar section (B straight behind A).  Only the saved half varphi in (-pi, 0] is drawn; on the other half
    sin varphi > 0 and p > 0 everywhere (eq. p)."""
    from crosscheck.report.plotting import plt

    TH, VP = np.meshgrid(theta, varphi)
    X, Y, Z = np.cos(TH) * np.sin(VP), np.cos(TH) * np.cos(VP), np.sin(TH)
    fig = plt.figure(figsize=(5.6, 4.6))
    ax = fig.add_subplot(projection="3d")
    ax.plot_wireframe(
        X, Y, Z, rstride=12, cstride=12, color="0.75", lw=0.4
    )  # the hemisphere of directions, for reference
    bad = p < 0
    ax.plot_surface(
        np.where(bad, X, np.nan),
        np.where(bad, Y, np.nan),
        np.where(bad, Z, np.nan),
        color=(0.85, 0.25, 0.2),
        linewidth=0,
        shade=True,
    )
    ax.quiver(0, 0, 0, 0.9, 0, 0, color="k", lw=1.5, arrow_length_ratio=0.15)
    ax.text(0.6, 0, 0.08, "slip of A", fontsize=7)
    ax.scatter([0], [0], [0], color="k", s=12)
    ax.set_xlabel("x (slip)")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_zlim(0, 1)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(plt.MaxNLocator(3))
    ax.set_box_aspect((2, 2, 1))
    ax.view_init(elev=25, azim=-150)  # from behind the tip, where the region is (x < 0: sin varphi < 0)
    ax.set_title(f"rod directions AB with p < 0 (red), $\\alpha$ = {cv['alpha']:g}, $\\mu$ = {cv['mu']:g}", fontsize=9)
    cap = (
        f"Fig. 2a recomputed: the directions of the rod from its tip A (the dot) to B for which p < 0 (red), on the unit hemisphere, in the frame where A "
        f"slips along +x: elevation theta, heading pi/2 - varphi from the slip (eq. tipfromcentre; alpha = {cv['alpha']:g}, mu = {cv['mu']:g}). p < 0 only "
        "with B behind A (sin varphi < 0), steep, around the planar section varphi = -pi/2 (y = 0). The same grid as Fig. 2b, mapped to space; the "
        "other half (sin varphi > 0, B ahead of A) has p > 0 everywhere (eq. p)."
    )
    return ctx.figure("fig2a_p_region_space", fig, cap, ["p_grid.json", "critical_values.json"])


SECTION = Section(
    slug=SLUG,
    title="Region p < 0 in (theta, varphi)",
    paper="Figs. 2a and 2b (fig:rod_orientations, fig:badregion); eqs. p, thetastar, varphistar, theta12, varphi12",
    params=params,
    run=run,
    render=render,
)
