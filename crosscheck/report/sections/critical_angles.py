"""Fig. 10: the critical polar angles theta_L, theta_1, theta_2 against mu (alpha = 3).

Curves from eqs. thetal and theta12.  Checks: theta_1 = theta_2 = theta_P at
mu_P (eq. thetap), theta_1 = theta_L at mu_L (eq. mul), and the paper's
statement theta_2 > theta_L for all alpha and mu, on an (alpha, mu) sample.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section
from crosscheck.theory import critical
from crosscheck.tolerances import CLOSED_FORM

SLUG = "critical_angles"


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        "mu_max": 3.0,
        "n_curve": 400 if quick else 2000,
        "alpha_sample": [0.1, 0.5, 1.0, 3.0, 10.0, 100.0],
        "n_mu_sample": 200 if quick else 2000,
    }


def run(ctx: RunContext) -> None:
    P = ctx.params
    alpha = P["alpha"]
    mu_P, mu_L = float(critical.mu_P(alpha)), float(critical.mu_L(alpha))
    m = np.concatenate([[mu_P], np.linspace(mu_P * (1 + 1e-9), P["mu_max"], P["n_curve"] - 1)])
    th1, th2 = critical.theta_12(m, alpha)
    ctx.store.write_table("theta_curves", {"mu": m, "theta_1": th1, "theta_2": th2})
    consts = {
        "alpha": alpha,
        "mu_P": mu_P,
        "mu_L": mu_L,
        "theta_L": critical.theta_L,
        "theta_P": float(critical.theta_P(alpha)),
        "mu_max": P["mu_max"],
    }
    ctx.store.write_json("constants", consts)

    cvP, cvL = critical.critical_values(mu_P, alpha), critical.critical_values(mu_L, alpha)
    for name, got, want in (
        ("theta_1(mu_P) = theta_P", cvP.theta_1, consts["theta_P"]),
        ("theta_2(mu_P) = theta_P", cvP.theta_2, consts["theta_P"]),
        ("theta_1(mu_L) = theta_L", cvL.theta_1, critical.theta_L),
    ):
        err = abs(got - want)
        allow = float(CLOSED_FORM.allowance(want))
        ctx.check(name, err <= allow, value=err, allowance=allow, detail=f"{got:.12g} vs {want:.12g}")
    worst = np.inf
    for a in P["alpha_sample"]:
        mus = np.geomspace(float(critical.mu_P(a)), 1e3, P["n_mu_sample"])
        worst = min(worst, float(np.min(critical.theta_12(mus, a)[1] - critical.theta_L)))
    ctx.check(
        "theta_2 > theta_L for all sampled alpha, mu >= mu_P (section 3.4)",
        worst > 0,
        value=worst,
        allowance=0.0,
        detail=f"alpha in {P['alpha_sample']}, mu in [mu_P, 1000]",
    )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, plt

    cur = ctx.store.read_table("theta_curves")
    c = ctx.store.read_json("constants")
    fig, ax = plt.subplots(figsize=(5.2, 4.2))
    ax.axhline(c["theta_L"], color=LINE_COLORS[2], lw=1.4, label="$\\theta_L$ (eq. thetal)")
    ax.plot(cur["mu"], cur["theta_1"], color=LINE_COLORS[0], lw=1.4, label="$\\theta_1$ (eq. theta12)")
    ax.plot(cur["mu"], cur["theta_2"], color=LINE_COLORS[1], lw=1.4, label="$\\theta_2$ (eq. theta12)")
    ax.plot([c["mu_P"]], [c["theta_P"]], "ko", ms=4)
    ax.annotate("$\\theta_P$", (c["mu_P"], c["theta_P"]), textcoords="offset points", xytext=(-18, 2))
    ax.plot([c["mu_L"]], [c["theta_L"]], "ks", ms=4)
    for xv in (c["mu_P"], c["mu_L"]):
        ax.axvline(xv, color="0.4", lw=0.6, ls=":")
    ax.set_xticks([0, 1, c["mu_P"], 2, c["mu_L"], 3], ["0", "1", "$\\mu_P$", "2", "$\\mu_L$", "3"])
    ax.set_yticks([0, np.pi / 4, np.pi / 2], ["0", "$\\pi/4$", "$\\pi/2$"])
    ax.set_xlim(0, c["mu_max"])
    ax.set_ylim(0, np.pi / 2)
    ax.set_xlabel("$\\mu$")
    ax.set_ylabel("$\\theta$")
    ax.legend(loc="center right", fontsize=8)
    caption = (
        f"Fig. 10 recomputed: theta_L = {c['theta_L']:.4f}, theta_1(mu) and theta_2(mu) for alpha = {c['alpha']:g}. theta_1 = theta_2 = theta_P = "
        f"{c['theta_P']:.4f} at mu_P = {c['mu_P']:.4f} (dot); theta_1 = theta_L at mu_L = {c['mu_L']:.4f} (square)."
    )
    return [ctx.figure("fig10_critical_angles", fig, caption, ["theta_curves.csv", "constants.json"])]


SECTION = Section(
    slug=SLUG,
    title="Critical angles theta_L, theta_1, theta_2 against mu",
    paper="Fig. 10 (fig:Psistheta); eqs. thetal, theta12, thetap",
    params=params,
    run=run,
    render=render,
)
