"""Figs. 11 and 17: the GB manifold b = p = 0 at fixed Psi for mu = 1.4 and mu = 6, with the type of each point.

For each mu (alpha = 3) the manifold is drawn at Psi = 0, (Psi_L + Psi_1)/2 and
(Psi_1 + Psi_2)/2 (``crosscheck.theory.gb.gb_manifold``), coloured by Psi (Fig. 11)
and by the type of the point as an equilibrium of eq. f, from the eigenvalues
of K (eq. K) at eta (Fig. 17).

Checks: the topology of section 3.5 (number of closed curves and whether
they cross Theta = 0: mechanism II, mu = 1.4: cases 3, 4, 6 give two
curves, two curves, one curve crossing Theta = 0; mechanism III, mu = 6:
cases 3, 5, 6 give two curves, two curves each crossing Theta = 0, one curve
crossing), and Theorem 4.1 on every sampled point: for Theta < 0 no stable
node or focus; for Theta > 0 (off varphi = -pi/2) the eigenvectors' first
components have opposite signs (eq. offdiagonals: their product is -K12/K21).
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import critical

SLUG = "gb_manifold"

#: Expected (number of curves, crossing Theta = 0 for each) per (mu, kinematic case).
TOPOLOGY = {
    (1.4, 3): (2, [False, False]),
    (1.4, 4): (2, [False, False]),
    (1.4, 6): (1, [True]),
    (6.0, 3): (2, [False, False]),
    (6.0, 5): (2, [True, True]),
    (6.0, 6): (1, [True]),
}


def _tag(mu: float) -> str:
    return f"{mu:g}".replace(".", "p")


def params(quick: bool) -> dict:
    return {"alpha": 3.0, "mu": [1.4, 6.0], "eta": 1.0, "n": 101 if quick else 401}


def run(ctx: RunContext) -> None:
    from crosscheck.theory import gb

    P = ctx.params
    alpha, eta = P["alpha"], P["eta"]
    summary = []
    for mu in P["mu"]:
        cv = critical.critical_values(mu, alpha)
        cols = {
            k: []
            for k in (
                "Psi_label",
                "Psi",
                "curve",
                "theta",
                "varphi",
                "Theta",
                "type",
                "eig_re_plus",
                "eig_re_minus",
                "e_plus_p",
                "e_minus_p",
            )
        }
        for label, Psi in (
            ("0", 0.0),
            ("(Psi_L+Psi_1)/2", (cv.Psi_L + cv.Psi_1) / 2),
            ("(Psi_1+Psi_2)/2", (cv.Psi_1 + cv.Psi_2) / 2),
        ):
            curves = gb.gb_manifold(mu, Psi, alpha, n=P["n"])
            case = critical.kinematic_case(mu, Psi, alpha)
            summary.append(
                {
                    "mu": mu,
                    "Psi_label": label,
                    "Psi": Psi,
                    "case": case,
                    "curves": len(curves),
                    "crosses_zero": [bool(c.crosses_zero) for c in curves],
                }
            )
            for j, c in enumerate(curves):
                Kc = c.K(eta)
                lam, vec = gb.eigen(Kc)
                n = c.theta.size
                for k, v in (
                    ("Psi_label", [label] * n),
                    ("Psi", np.full(n, Psi)),
                    ("curve", np.full(n, j)),
                    ("theta", c.theta),
                    ("varphi", c.varphi),
                    ("Theta", c.Theta),
                    ("type", c.types(eta)),
                    ("eig_re_plus", lam[:, 0].real),
                    ("eig_re_minus", lam[:, 1].real),
                    ("e_plus_p", vec[:, 0, 0].real),
                    ("e_minus_p", vec[:, 0, 1].real),
                ):
                    cols[k] += list(v)
            ctx.store.write_json("topology", summary)
        ctx.store.write_table(f"manifold_mu{_tag(mu)}", cols)
        ctx.store.write_json(f"critical_mu{_tag(mu)}", cv)

        t = {k: np.asarray(v) for k, v in cols.items() if k != "Psi_label"}
        neg = t["Theta"] < 0
        bad = np.isin(t["type"], [gb.GBType.STABLE_NODE, gb.GBType.STABLE_FOCUS]) & neg
        ctx.check(
            f"mu = {mu:g}: no stable node or focus for Theta < 0 (Theorem 4.1)",
            not bad.any(),
            value=int(bad.sum()),
            allowance=0,
            detail=f"{int(neg.sum())} sampled points with Theta < 0",
        )
        real = (
            np.isfinite(t["e_plus_p"]) & (t["type"] != gb.GBType.STABLE_FOCUS) & (t["type"] != gb.GBType.UNSTABLE_FOCUS)
        )
        pos = (t["Theta"] > 0) & (np.abs(np.cos(t["varphi"])) > 1e-6) & real
        wrong = pos & (t["e_plus_p"] * t["e_minus_p"] >= 0)
        ctx.check(
            f"mu = {mu:g}: for Theta > 0 the eigenvectors lie in different quadrants (eq. offdiagonals)",
            not wrong.any(),
            value=int(wrong.sum()),
            allowance=0,
            detail=f"{int(pos.sum())} sampled points with Theta > 0 off varphi = -pi/2",
        )
    for s in summary:
        want = TOPOLOGY.get((s["mu"], s["case"]))
        if want is not None:
            ok = s["curves"] == want[0] and s["crosses_zero"] == want[1]
            ctx.check(
                f"mu = {s['mu']:g}, Psi = {s['Psi_label']} (case {s['case']}): {want[0]} curve(s), crossing Theta = 0: {want[1]}",
                ok,
                detail=f"got {s['curves']} curve(s), crossing: {s['crosses_zero']}",
            )


def render(ctx: RenderContext) -> list:
    from matplotlib.lines import Line2D

    from crosscheck.report.plotting import GB_TYPE_COLORS, LINE_COLORS, plt
    from crosscheck.theory import gb

    P = ctx.params
    psi_colors = {
        "0": LINE_COLORS[1],
        "(Psi_L+Psi_1)/2": LINE_COLORS[2],
        "(Psi_1+Psi_2)/2": LINE_COLORS[4],
    }  # md2, md3, md5 as the paper
    topo = ctx.store.read_json("topology")
    blocks = []
    for kind in ("psi", "type"):
        fig = plt.figure(figsize=(11, 4.8))
        for i, mu in enumerate(P["mu"]):
            ax = fig.add_subplot(1, len(P["mu"]), i + 1, projection="3d")
            t = ctx.store.read_table(f"manifold_mu{_tag(mu)}", text=("Psi_label",))
            cv = ctx.store.read_json(f"critical_mu{_tag(mu)}")
            for label in psi_colors:
                for j in np.unique(t["curve"][t["Psi_label"] == label]):
                    sel = (t["Psi_label"] == label) & (t["curve"] == j)
                    if kind == "psi":
                        ax.plot(t["theta"][sel], t["varphi"][sel], t["Theta"][sel], color=psi_colors[label], lw=1.6)
                    else:
                        ax.plot(t["theta"][sel], t["varphi"][sel], t["Theta"][sel], color="0.8", lw=0.6)
                        ax.scatter(
                            t["theta"][sel],
                            t["varphi"][sel],
                            t["Theta"][sel],
                            c=[GB_TYPE_COLORS[int(k)] for k in t["type"][sel]],
                            s=4,
                            depthshade=False,
                            rasterized=True,
                        )
            ax.set_xlabel("$\\theta$")
            ax.set_ylabel("$\\varphi$")
            ax.set_zlabel("$\\Theta$")
            ax.view_init(elev=18, azim=-62)
            ax.set_title(f"$\\mu$ = {mu:g} (mechanism {'II' if mu <= cv['mu_L'] else 'III'})")
        if kind == "psi":
            handles = [Line2D([], [], color=c, label=f"$\\Psi$ = {lab}") for lab, c in psi_colors.items()]
        else:
            handles = [
                Line2D([], [], marker="o", ls="", color=GB_TYPE_COLORS[int(g)], label=g.name.lower().replace("_", " "))
                for g in gb.GBType
            ]
        fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize=8)
        vals = "; ".join(
            f"mu = {s['mu']:g}: Psi = {s['Psi_label']} = {s['Psi']:.4f} (case {s['case']}, {s['curves']} curve(s))"
            for s in topo
        )
        if kind == "psi":
            cap = (
                f"Fig. 11 recomputed: the GB manifold b = p = 0 projected to (theta, varphi, Theta) at three values of Psi, alpha = {P['alpha']:g} "
                f"(crosscheck.theory.gb.gb_manifold). {vals}."
            )
            name = "fig11_gb_manifolds"
        else:
            cap = (
                f"Fig. 17 recomputed: the same manifolds coloured by the type of each point as an equilibrium of eq. f (eigenvalues of K, eq. K, at eta = {P['eta']:g}): "
                "stable node blue, saddle red, unstable node yellow, unstable focus green (stable focus grey, degenerate black: not expected)."
            )
            name = "fig17_gb_stability"
        blocks.append(ctx.figure(name, fig, cap, [f"manifold_mu{_tag(mu)}.csv" for mu in P["mu"]] + ["topology.json"]))
    rows = []
    for mu in P["mu"]:
        t = ctx.store.read_table(f"manifold_mu{_tag(mu)}", text=("Psi_label",))
        for label in psi_colors:
            sel = t["Psi_label"] == label
            counts = {g.name.lower().replace("_", " "): int(np.sum(t["type"][sel] == g)) for g in gb.GBType}
            rows.append([f"{mu:g}", label, ", ".join(f"{k}: {v}" for k, v in counts.items() if v)])
    blocks.append(
        Table(
            caption=f"Types of the sampled GB points (eta = {P['eta']:g}).",
            header=["mu", "Psi", "sampled points by type"],
            rows=rows,
            data=ctx.data(*[f"manifold_mu{_tag(mu)}.csv" for mu in P["mu"]]),
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="GB manifolds and their stability",
    paper="Figs. 11 (fig:GBs_bif3) and 17 (fig:stabilty_on_GB); eq. K, Theorem 4.1",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.theory.gb",),
)
