"""An engine's contact-force quality while the rod slips: Signorini, the cone, maximum dissipation, the friction skew, eq. FZ.

``crosscheck.studies.contact_quality`` on seeded random slipping starts below
mu_P, through the engine at the options of its outcome maps; one section per
registered engine with maps (``<slug>_contact``).  Its summary feeds the
engine table's friction column.  Scaled units (section 2.1).
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table

#: Metric -> (table label, unit, what the rigid Coulomb contact gives).
LABELS = {
    "signorini": ("Signorini |lambda_n v_n|", "m g l omega", "0"),
    "cone_violation": ("cone violation max(0, |lambda_t| - mu lambda_n)", "m g", "0"),
    "dissipation_ratio": ("|lambda_t| / (mu lambda_n)", "-", "1 (sliding)"),
    "skew_deg": ("angle(lambda_t, -slip)", "degrees", "0"),
    "force_over_FZ": ("window-mean lambda_n / (-b/p)", "-", "1 (eq. FZ)"),
}


def params(quick: bool, engine: str, options: dict) -> dict:
    return {
        "engine": engine,
        "options": dict(options),
        "alpha": 3.0,
        "n_starts": 12 if quick else 60,
        "horizon": 0.3,
        "mu_range": [0.3, 1.2],
    }


def run(ctx: RunContext) -> None:
    from crosscheck.studies.contact_quality import METRICS, contact_quality

    P = ctx.params
    res = contact_quality(
        P["engine"],
        P["n_starts"],
        ctx.rng,
        alpha=P["alpha"],
        horizon=P["horizon"],
        mu_range=tuple(P["mu_range"]),
        options=P["options"],
        progress=ctx.show_progress,
    )
    ctx.store.write_json("quality", res["summary"])
    ctx.store.write_table(
        "per_run", {"mu": res["mu"], "outcome": res["outcomes"], **{k: res["per_run"][k] for k in METRICS}}
    )


def _fmt(x) -> str:
    """A saved statistic (None where no row counted: JSON has no NaN)."""
    return "-" if x is None else f"{x:.3g}"


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.report.plotting import LINE_COLORS, plt

    P = ctx.params
    name = engine_label(P["engine"])
    q = ctx.store.read_json("quality")
    per_run = ctx.store.read_table("per_run", text=("outcome",))
    rows = [
        [LABELS[k][0], LABELS[k][1], LABELS[k][2], *(_fmt(q[k][s]) for s in ("median", "p95", "max"))] for k in LABELS
    ]
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.2))
    for ax, k in zip(axes, ("skew_deg", "dissipation_ratio", "force_over_FZ")):
        x = per_run[k][np.isfinite(per_run[k])]
        if len(x):
            ax.hist(x, bins=min(20, max(5, len(x))), color=LINE_COLORS[0], edgecolor="k", lw=0.3)
        ax.set_xlabel(f"{LABELS[k][0]} ({LABELS[k][1]})" if LABELS[k][1] != "-" else LABELS[k][0])
        ax.set_ylabel("starts (median over each run's rows)")
        ax.axvline({"skew_deg": 0.0, "dissipation_ratio": 1.0, "force_over_FZ": 1.0}[k], color="k", lw=0.8, ls=":")
    caption = (
        f"{name}: per start, the median over its sliding contact rows of the friction skew, the dissipation ratio and the normal force "
        f"against eq. FZ, on {len(per_run['mu'])} random slipping starts with mu in [{P['mu_range'][0]:g}, {P['mu_range'][1]:g}] "
        f"(options {P['options']}); dotted: the rigid Coulomb contact."
    )
    return [
        ctx.figure("contact_quality", fig, caption, ["per_run.csv", "quality.json"]),
        Table(
            caption=f"{name}: contact-force quality over {q['rows']} sliding contact rows (ContactBench's metrics; rows before the first event).",
            header=["metric", "unit", "rigid Coulomb", "median", "95th percentile", "max"],
            rows=rows,
            data=ctx.data("quality.json", "per_run.csv"),
        ),
    ]


def section(spec, options: dict) -> Section:
    """The contact-quality section ``<slug>_contact`` of the engine ``spec`` at ``options`` ({"quick": ..., "full": ...})."""
    return Section(
        slug=f"{spec.slug}_contact",
        title=f"{spec.label}: contact-force quality while slipping",
        paper="eqs. friction, FZ",
        params=lambda quick: params(quick, spec.name, options["quick" if quick else "full"]),
        run=run,
        render=render,
        requires=("crosscheck.studies.contact_quality", spec.module or "crosscheck.engines"),
    )
