"""Fig. 9a: the kinematic cases 1-7 of section 3.4 in the (mu, Psi) plane, with Psi_L, Psi_1, Psi_2 and Psi_P.

The map is ``crosscheck.theory.critical.kinematic_case`` on a grid; the curves are
eqs. psil, psi1, psi2 and the point (mu_P, Psi_P) of eq. psip.  Checks: the
curves meet where the paper says they do (Psi_1 = Psi_2 = Psi_P at mu_P,
Psi_1 = Psi_L at mu_L) and Psi_1 >= Psi_L for every mu >= mu_P.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import critical
from crosscheck.tolerances import CLOSED_FORM

SLUG = "kinematic_cases"


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        "mu_max": 8.0,
        "Psi_max": 6.0,
        "n_mu": 160 if quick else 480,
        "n_Psi": 120 if quick else 360,
        "n_curve": 400 if quick else 2000,
    }


def run(ctx: RunContext) -> None:
    P = ctx.params
    alpha = P["alpha"]
    mu = cell_centres(0.0, P["mu_max"], P["n_mu"])
    Psi = cell_centres(0.0, P["Psi_max"], P["n_Psi"])
    cases = critical.kinematic_case(mu[None, :], Psi[:, None], alpha)
    ctx.store.write_grid("cases", ("mu", mu), ("Psi", Psi), ("case", cases))
    mu_P, mu_L = float(critical.mu_P(alpha)), float(critical.mu_L(alpha))
    # the curves start exactly at mu_P, where Psi_1 = Psi_2 = Psi_P (a double root, eq. psip)
    m = np.concatenate([[mu_P], np.geomspace(mu_P * (1 + 1e-6), P["mu_max"], P["n_curve"] - 1)])
    th1, th2 = critical.theta_12(m, alpha)
    ctx.store.write_table("Psi_curves", {"mu": m, "Psi_1": critical.Psi_on_b0(th1), "Psi_2": critical.Psi_on_b0(th2)})
    consts = {
        "alpha": alpha,
        "mu_P": mu_P,
        "mu_L": mu_L,
        "Psi_L": critical.Psi_L,
        "Psi_P": float(critical.Psi_P(alpha)),
    }
    ctx.store.write_json("constants", consts)

    cvP, cvL = critical.critical_values(mu_P, alpha), critical.critical_values(mu_L, alpha)
    for name, got, want in (
        ("Psi_1(mu_P) = Psi_P (eq. psip)", cvP.Psi_1, consts["Psi_P"]),
        ("Psi_2(mu_P) = Psi_P (eq. psip)", cvP.Psi_2, consts["Psi_P"]),
        ("Psi_1(mu_L) = Psi_L (eq. mul)", cvL.Psi_1, critical.Psi_L),
    ):
        err = abs(got - want)
        allow = float(CLOSED_FORM.allowance(want))
        ctx.check(name, err <= allow, value=err, allowance=allow, detail=f"{got:.12g} vs {want:.12g}")
    psi1 = critical.Psi_on_b0(th1)
    worst = float(np.min(psi1 - critical.Psi_L))
    ctx.check(
        "Psi_1 >= Psi_L for every sampled mu >= mu_P",
        worst >= -CLOSED_FORM.atol,
        value=worst,
        allowance=-CLOSED_FORM.atol,
        detail="min over the curve of Psi_1 - Psi_L (0 at mu_L)",
    )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, categorical_image, plt

    mu, Psi, cases, _ = ctx.store.read_grid("cases")
    c = ctx.store.read_json("constants")
    cur = ctx.store.read_table("Psi_curves")
    colors = {k: tuple(0.55 + 0.45 * np.array(LINE_COLORS[k - 1])) for k in range(1, 8)}
    fig, ax = plt.subplots(figsize=(6.0, 4.6))
    categorical_image(ax, mu, Psi, cases, colors)
    ax.axhline(c["Psi_L"], color="k", lw=1.0, ls="--")
    ax.plot(cur["mu"], cur["Psi_1"], color="k", lw=1.2)
    ax.plot(cur["mu"], cur["Psi_2"], color="k", lw=1.2)
    ax.plot([c["mu_P"]], [c["Psi_P"]], "ko", ms=4)
    for xv in (c["mu_P"], c["mu_L"]):
        ax.axvline(xv, color="0.3", lw=0.6, ls=":")
    for k in range(1, 8):  # label each case at the median of its cells
        jj, ii = np.nonzero(cases == k)
        if ii.size:
            ax.text(
                np.median(mu[ii]),
                np.median(Psi[jj]),
                str(k),
                ha="center",
                va="center",
                fontsize=11,
                fontweight="bold",
                bbox=dict(boxstyle="circle,pad=0.2", fc="white", ec="k", lw=0.8),
            )
    ax.annotate("$\\Psi_L$", (mu[-1], c["Psi_L"]), textcoords="offset points", xytext=(-18, 3), fontsize=8)
    ax.annotate("$\\Psi_1$", (cur["mu"][-1], cur["Psi_1"][-1]), textcoords="offset points", xytext=(-20, 4), fontsize=8)
    ax.annotate("$\\Psi_P$", (c["mu_P"], c["Psi_P"]), textcoords="offset points", xytext=(-22, 2), fontsize=8)
    ax.set_xticks([0, c["mu_P"], c["mu_L"], 4, 8], ["0", "$\\mu_P$", "$\\mu_L$", "4", "8"])
    ax.set_xlim(0, mu[-1] + (mu[1] - mu[0]) / 2)
    ax.set_ylim(0, Psi[-1] + (Psi[1] - Psi[0]) / 2)
    ax.set_xlabel("$\\mu$")
    ax.set_ylabel("$\\Psi$")
    ax.set_title(f"kinematic cases, $\\alpha$ = {c['alpha']:g}")
    caption = (
        f"Fig. 9a recomputed: the kinematic cases 1-7 of section 3.4 (crosscheck.theory.critical.kinematic_case) for alpha = {c['alpha']:g}, Psi >= 0. "
        f"Dashed: Psi_L = {c['Psi_L']:.4f} (eq. psil); solid: Psi_1(mu) below, Psi_2(mu) above (eqs. psi1, psi2), meeting at "
        f"(mu_P, Psi_P) = ({c['mu_P']:.4f}, {c['Psi_P']:.4f}) (eq. psip); dotted: mu_P and mu_L = {c['mu_L']:.4f} (eq. mul)."
    )
    fig_block = ctx.figure("fig9a_cases", fig, caption, ["cases.json", "Psi_curves.csv", "constants.json"])
    rows = [[k, f"{v:.6f}" if isinstance(v, float) else str(v)] for k, v in c.items()]
    return [
        fig_block,
        Table(
            caption="Constants drawn in the figure.",
            header=["quantity", "value"],
            rows=rows,
            data=ctx.data("constants.json"),
        ),
    ]


SECTION = Section(
    slug=SLUG,
    title="Kinematic cases 1-7 in (mu, Psi)",
    paper="Fig. 9a (fig:muPsicases); eqs. psil, psi1, psi2, psip, mul",
    params=params,
    run=run,
    render=render,
)
