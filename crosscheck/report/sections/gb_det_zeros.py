"""Fig. 18: where det K = 0 (a zero eigenvalue) on the GB manifold, Psi against cos varphi (alpha = 3, mu = 1.7, eta = 10).

Computed as the paper does: for varphi across (varphi_1, varphi_2) the two
points of p = 0, theta_+(varphi) and theta_-(varphi) (eq. thetastar), and at
each the real roots Psi of the quartic eq. Psiquartic with their Theta (eqs.
detK0, B; ``crosscheck.theory.gb.psi_quartic_roots``), keeping Theta > 0.

Checks: the zeros found independently along the GB manifold at fixed Psi
(``crosscheck.theory.gb.det_K_zeros``, bisection of det K) lie on the quartic's
curve; at Psi = 0 they satisfy eq. ghastly; and the section Psi = 1.0620 of
fig:pandora has four critical points on its Theta > 0 part.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import critical

SLUG = "gb_det_zeros"


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        "mu": 1.7,
        "eta": 10.0,
        "Psi_max": 4.4121,
        "n_varphi": 300 if quick else 2000,
        "Psi_check": [0.0, 0.5, 1.062, 2.0, 3.0],
        "Psi_pandora": 1.062,
        "n_curve": 201 if quick else 801,
    }


def run(ctx: RunContext) -> None:
    from crosscheck.theory import gb

    P = ctx.params
    alpha, mu, eta = P["alpha"], P["mu"], P["eta"]
    cv = critical.critical_values(mu, alpha)
    ctx.store.write_json("critical_values", cv)
    # open interval: at varphi_1,2 the two branches meet at theta_P (a double root)
    u = (np.arange(P["n_varphi"]) + 0.5) / P["n_varphi"]
    varphi = cv.varphi_1 + (cv.varphi_2 - cv.varphi_1) * u
    th_minus, th_plus = critical.theta_pm(varphi, mu, alpha)
    cols = {k: [] for k in ("varphi", "cos_varphi", "branch", "theta", "Psi", "Theta")}
    for branch, ths in (("theta_+", th_plus), ("theta_-", th_minus)):
        for vp, th in zip(varphi, ths):
            if not np.isfinite(th):
                continue
            Psi, Theta = gb.psi_quartic_roots(th, vp, eta, mu, alpha)
            for ps, Th in zip(Psi, Theta):
                if Th > 0 and 0 <= ps <= P["Psi_max"]:
                    for k, v in (
                        ("varphi", vp),
                        ("cos_varphi", math.cos(vp)),
                        ("branch", branch),
                        ("theta", th),
                        ("Psi", ps),
                        ("Theta", Th),
                    ):
                        cols[k].append(v)
    ctx.store.write_table("det_zeros_quartic", cols)

    # independent route: bisection of det K along the manifold at fixed Psi
    ind = {k: [] for k in ("Psi", "theta", "varphi", "Theta", "quartic_distance")}
    worst = 0.0
    for Psi in P["Psi_check"]:
        for c in gb.gb_manifold(mu, Psi, alpha, n=P["n_curve"]):
            for th, vp, Th in gb.det_K_zeros(c, eta):
                roots, thetas = gb.psi_quartic_roots(th, vp, eta, mu, alpha)
                dist = float(np.min(np.abs(roots - Psi) + np.abs(thetas - Th))) if roots.size else math.inf
                worst = max(worst, dist)
                for k, v in (("Psi", Psi), ("theta", th), ("varphi", vp), ("Theta", Th), ("quartic_distance", dist)):
                    ind[k].append(v)
    ctx.store.write_table("det_zeros_bisection", ind)
    ctx.check(
        "zeros of det K found by bisection along the manifold lie on the quartic (eq. Psiquartic)",
        worst <= 1e-6,
        value=worst,
        allowance=1e-6,
        detail=f"{len(ind['Psi'])} zeros at Psi in {P['Psi_check']}; distance |Psi - root| + |Theta - root| (bisection to ~1e-15 in theta)",
    )
    at0 = np.asarray(ind["Psi"]) == 0.0
    if at0.any():
        th0, vp0, Th0 = (np.asarray(ind[k])[at0] for k in ("theta", "varphi", "Theta"))
        lhs = alpha * mu * np.cos(vp0) ** 2
        rhs = np.array([gb.ghastly(t, eta, alpha, sign=1 if T > 0 else -1) for t, T in zip(th0, Th0)])
        err = float(np.max(np.abs(lhs - rhs)))
        ctx.check(
            "at Psi = 0 the zeros satisfy eq. ghastly",
            err <= 1e-9,
            value=err,
            allowance=1e-9,
            detail=f"{int(at0.sum())} zeros",
        )
    sel = (np.asarray(ind["Psi"]) == P["Psi_pandora"]) & (np.asarray(ind["Theta"]) > 0)
    n_pandora = int(np.sum(sel))
    ctx.check(
        f"Psi = {P['Psi_pandora']}: four critical points on the GB manifold with Theta > 0 (fig:pandora: (d), (h), (j), (l))",
        n_pandora == 4,
        value=n_pandora,
        allowance=4,
        detail="the figure shows the Theta > 0 part (Theta from 0.8 to 1)",
    )
    _pandora(ctx)


def _pandora(ctx: RunContext) -> None:
    """Fig. 19: K's eigenvectors along the Theta > 0 GB curve at Psi = Psi_pandora, at each zero of det K and between them.

    The paper does not print its panels' points; here a panel sits at every zero of det K (bisected) and at the
    sample halfway (in curve order) between consecutive zeros, so that each change of type is shown from both sides.
    """
    from crosscheck.theory import gb

    P = ctx.params
    alpha, mu, eta, Psi = P["alpha"], P["mu"], P["eta"], P["Psi_pandora"]
    curve = next(c for c in gb.gb_manifold(mu, Psi, alpha, n=P["n_curve"]) if c.sign > 0)
    zeros = gb.det_K_zeros(curve, eta)
    d = gb.det_K(curve.theta, curve.varphi, curve.Psi, curve.Theta, eta, mu, alpha)
    cross = np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0)  # the samples each zero was bracketed between
    picks = [("zero", tuple(z)) for z in zeros]
    bounds = [0, *[int(i) + 1 for i in cross], len(curve.theta)]
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a > 2:
            m = (a + b) // 2
            picks.append(("between", (float(curve.theta[m]), float(curve.varphi[m]), float(curve.Theta[m]))))

    # in curve order: by the position along the curve (the nearest sample)
    def order(pick):
        th, vp, Th = pick[1]
        return int(np.argmin(np.abs(curve.theta - th) + np.abs(curve.varphi - vp) + np.abs(curve.Theta - Th)))

    points = []
    for where, (th, vp, Th) in sorted(picks, key=order):
        Km = gb.K(th, vp, Psi, Th, eta, mu, alpha)
        lam, vec = gb.eigen(Km)
        points.append(
            {
                "where": where,
                "theta": th,
                "varphi": vp,
                "Theta": Th,
                "det_K": float(np.linalg.det(Km)),
                "lambda": [[float(l.real), float(l.imag)] for l in lam],
                "e_plus": [float(v.real) for v in vec[:, 0]],
                "e_minus": [float(v.real) for v in vec[:, 1]],
                "type": gb.gb_type(Km).name,
                "strong": "plus" if np.abs(lam[0]) >= np.abs(lam[1]) else "minus",
            }
        )
    ctx.store.write_json("pandora_points", points)
    # Physics: a zero of det K is an eigenvalue through 0, so on its two sides the type is a saddle on one, not on the other
    between = [p for p in points if p["where"] == "between"]
    changes = sum((a["type"] == "SADDLE") != (b["type"] == "SADDLE") for a, b in zip(between, between[1:]))
    ctx.check(
        f"Psi = {Psi}: the type changes saddle <-> non-saddle across each zero of det K inside the curve",
        changes == len(between) - 1,
        value=changes,
        allowance=len(between) - 1,
        detail=", ".join(p["type"].lower() for p in between),
    )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, plt

    P = ctx.params
    cv = ctx.store.read_json("critical_values")
    q = ctx.store.read_table("det_zeros_quartic", text=("branch",))
    ind = ctx.store.read_table("det_zeros_bisection")
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for branch, color in (("theta_+", LINE_COLORS[0]), ("theta_-", LINE_COLORS[1])):
        s = q["branch"] == branch
        ax.plot(
            q["cos_varphi"][s],
            q["Psi"][s],
            ".",
            ms=2.5,
            color=color,
            rasterized=True,
            label=f"det K = 0 on $\\theta_{branch[-1]}$, $\\Theta$ > 0 (eq. Psiquartic)",
        )
    s = ind["Theta"] > 0
    ax.plot(np.cos(ind["varphi"][s]), ind["Psi"][s], "kx", ms=5, label="bisection of det K along the manifold")
    ax.axhline(cv["Psi_1"], color=LINE_COLORS[2], ls="--", lw=1, label=f"$\\Psi_1$ = {cv['Psi_1']:.4f}")
    ax.axhline(cv["Psi_2"], color=LINE_COLORS[3], ls="--", lw=1, label=f"$\\Psi_2$ = {cv['Psi_2']:.4f}")
    ax.axhline(P["Psi_pandora"], color="k", ls="--", lw=1, label=f"$\\Psi$ = {P['Psi_pandora']}")
    lim = math.cos(cv["varphi_2"])
    ax.set_xlim(-lim, lim)
    ax.set_ylim(0, P["Psi_max"])
    ax.set_xlabel("cos $\\varphi$")
    ax.set_ylabel("$\\Psi$")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    cap = (
        f"Fig. 18 recomputed: positions of the zeros of det K on the GB manifold with Theta > 0, alpha = {P['alpha']:g}, mu = {P['mu']:g}, eta = {P['eta']:g} "
        f"(Psi_1 = {cv['Psi_1']:.4f}, Psi_2 = {cv['Psi_2']:.4f}). The asymmetry in cos varphi is the effect of Psi != 0 (eq. group: K is symmetric under "
        "varphi -> -pi - varphi together with Psi -> -Psi only). Crosses: the same zeros found independently by bisection along the manifold."
    )
    blocks = [
        ctx.figure(
            "fig18_det_zeros", fig, cap, ["det_zeros_quartic.csv", "det_zeros_bisection.csv", "critical_values.json"]
        )
    ]
    blocks += _render_pandora(ctx)
    rows = [
        [
            f"{ind['Psi'][i]:g}",
            f"{ind['theta'][i]:.6f}",
            f"{ind['varphi'][i]:.6f}",
            f"{ind['Theta'][i]:.6f}",
            f"{ind['quartic_distance'][i]:.1e}",
        ]
        for i in range(len(ind["Psi"]))
    ]
    blocks.append(
        Table(
            caption="Zeros of det K found by bisection along the GB manifold (both signs of Theta) and their distance to the quartic's roots.",
            header=["Psi", "theta", "varphi", "Theta", "distance to quartic"],
            rows=rows,
            data=ctx.data("det_zeros_bisection.csv"),
        )
    )
    return blocks


def _render_pandora(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import pb_eigenvectors, pb_plane, plt, strong_weak_colors

    if not ctx.store.exists("pandora_points.json"):
        return []
    P = ctx.params
    pts = ctx.store.read_json("pandora_points")
    cols = min(len(pts), 5)
    rows_ = -(-len(pts) // cols)
    fig, axes = plt.subplots(rows_, cols, figsize=(2.3 * cols, 2.4 * rows_), squeeze=False)
    for ax in axes.flat[len(pts) :]:
        ax.set_visible(False)
    for k, (ax, p) in enumerate(zip(axes.flat, pts)):
        pb_plane(ax, 1.0, 1.0)
        pb_eigenvectors(ax, p["e_plus"], p["e_minus"], strong_weak_colors(p["strong"]))
        lam = [complex(*l) for l in p["lambda"]]
        label = "det K = 0" if p["where"] == "zero" else p["type"].lower().replace("_", " ")
        ax.set_title(f"({chr(ord('a') + k)}) {label}", fontsize=8)
        ax.text(
            0.03,
            0.03,
            f"$\\theta$={p['theta']:.4f}\n$\\varphi$={p['varphi']:.4f}\n$\\lambda$={lam[0].real:.3g}, {lam[1].real:.3g}",
            transform=ax.transAxes,
            fontsize=6,
            va="bottom",
        )
        ax.set_xticks([])
        ax.set_yticks([])
    cap = (
        f"Fig. 19 recomputed: eigenvectors of K in the (p, b) plane along the GB manifold with Theta > 0 at alpha = {P['alpha']:g}, mu = {P['mu']:g}, "
        f"eta = {P['eta']:g}, Psi = {P['Psi_pandora']}, in curve order: at each of the four zeros of det K (where an eigenvalue passes through 0) and "
        "halfway between them. Strong eigenvector (larger |lambda|) blue, weak red; shading as Fig. 3a. The paper's own panel points are not printed, "
        "so its panels (b)-(m) are matched by kind, not by position."
    )
    return [ctx.figure("fig19_eigenvectors", fig, cap, ["pandora_points.json"])]


SECTION = Section(
    slug=SLUG,
    title="Zeros of det K on the GB manifold",
    paper="Figs. 18 (fig:determinant_bif) and 19 (fig:pandora); eqs. detK, detK0, B, Psiquartic, ghastly",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.theory.gb",),
)
