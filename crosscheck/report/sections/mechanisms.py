"""Fig. 9b: the mechanisms I, II, III of section 3.4 in the (alpha, mu) plane, bounded by mu_P(alpha) and mu_L(alpha).

The map is ``crosscheck.theory.critical.mechanism`` on a grid; the curves are eqs.
mup2D and mul.  Check: mu_L > mu_P for every alpha (mechanism II always
exists, as the figure shows), on the sampled alphas.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section
from crosscheck.theory import critical

SLUG = "mechanisms"


def params(quick: bool) -> dict:
    return {"alpha_max": 10.0, "mu_max": 5.0, "n_alpha": 150 if quick else 450, "n_mu": 120 if quick else 360}


def run(ctx: RunContext) -> None:
    P = ctx.params
    alpha = cell_centres(0.0, P["alpha_max"], P["n_alpha"])
    mu = cell_centres(0.0, P["mu_max"], P["n_mu"])
    mech = critical.mechanism(mu[:, None], alpha[None, :])
    ctx.store.write_grid("mechanisms", ("alpha", alpha), ("mu", mu), ("mechanism", mech))
    a = np.geomspace(alpha[0], P["alpha_max"], 400)
    muP, muL = critical.mu_P(a), critical.mu_L(a)
    ctx.store.write_table("mu_curves", {"alpha": a, "mu_P": muP, "mu_L": muL})
    gap = float(np.min(muL - muP))
    ctx.check(
        "mu_L(alpha) > mu_P(alpha) on every sampled alpha",
        gap > 0,
        value=gap,
        allowance=0.0,
        detail="min of mu_L - mu_P over the curve",
    )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, categorical_image, plt

    alpha, mu, mech, _ = ctx.store.read_grid("mechanisms")
    cur = ctx.store.read_table("mu_curves")
    colors = {1: (0.85, 0.92, 1.0), 2: (1.0, 0.9, 0.75), 3: (0.88, 0.97, 0.85)}
    fig, ax = plt.subplots(figsize=(5.4, 4.4))
    categorical_image(ax, alpha, mu, mech, colors)
    ax.plot(cur["alpha"], cur["mu_P"], color=LINE_COLORS[0], lw=1.4, label="$\\mu_P(\\alpha)$ (eq. mup2D)")
    ax.plot(cur["alpha"], cur["mu_L"], color=LINE_COLORS[1], lw=1.4, label="$\\mu_L(\\alpha)$ (eq. mul)")
    for k, name in ((1, "I"), (2, "II"), (3, "III")):
        jj, ii = np.nonzero(mech == k)
        if ii.size:
            ax.text(
                np.median(alpha[ii]), np.median(mu[jj]), name, ha="center", va="center", fontsize=13, fontweight="bold"
            )
    ax.axvline(3.0, color="0.4", lw=0.6, ls=":")
    ax.set_xlim(0, alpha[-1] + (alpha[1] - alpha[0]) / 2)
    ax.set_ylim(0, mu[-1] + (mu[1] - mu[0]) / 2)
    ax.set_xlabel("$\\alpha$")
    ax.set_ylabel("$\\mu$")
    ax.legend(loc="upper right", fontsize=8)
    caption = (
        "Fig. 9b recomputed: mechanisms I (mu <= mu_P, no paradox), II (mu_P < mu <= mu_L) and III (mu > mu_L) of section 3.4 "
        "(crosscheck.theory.critical.mechanism) in (alpha, mu). Dotted: the uniform rod, alpha = 3."
    )
    return [ctx.figure("fig9b_mechanisms", fig, caption, ["mechanisms.json", "mu_curves.csv"])]


SECTION = Section(
    slug=SLUG,
    title="Mechanisms I-III in (alpha, mu)",
    paper="Fig. 9b (fig:alphamumech); eqs. mup2D, mul",
    params=params,
    run=run,
    render=render,
)
