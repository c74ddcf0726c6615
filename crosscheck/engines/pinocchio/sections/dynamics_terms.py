"""Pinocchio vs the analytic reference: error per quantity, and error against theta near the singular rods.

Two parts:

* ``crosscheck.engines.pinocchio.studies.dynamics_terms.validate`` on random states (the command
  ``crosscheck validate pinocchio``): the largest error of each quantity, in
  multiples of its tolerance, and the state where it occurs; its JSON is saved
  and shown as it is.
* a sweep of theta towards the two ends of (0, pi/2) for a uniform rod:
  Pinocchio's tip acceleration by both routes (``route="aba"`` and
  ``route="delassus"``, G F + free acceleration) and its b and p against eqs.
  linode2, b and p.  Near the vertical rod M_psipsi = I0 cos^2 theta, so
  anything solved through M^-1 in the psi direction loses accuracy like
  eps / cos^2 theta (``crosscheck.engines.pinocchio.model``'s docstring); the figure
  shows whether each route follows its expected growth.  Errors are in units
  of the term scale A = (1 + alpha) |F|_1 + (1 + |rates|)^2 (scaled units), the
  size of the terms eq. linode2 sums.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from crosscheck.report.section import Preformatted, RenderContext, RunContext, Section, Table, Text
from crosscheck.rod import Rod
from crosscheck.theory import analytic

SLUG = "pinocchio"


def params(quick: bool) -> dict:
    return {
        "n_states": 2000 if quick else 100_000,
        "n_theta": 40 if quick else 200,
        "draws_per_theta": 4 if quick else 16,
        "cos_theta_min": 1e-7,
        "theta_min": 1e-8,
        "rod": {"mass": 1.0, "length": 0.5, "inertia": 1.0 * 0.5**2 / 3.0, "gravity": 9.81},
    }


def run(ctx: RunContext) -> None:
    from crosscheck.engines.pinocchio import model as pinrod
    from crosscheck.engines.pinocchio.studies import dynamics_terms

    P = ctx.params
    result = dynamics_terms.validate(P["n_states"], ctx.rng, progress=ctx.show_progress)
    (ctx.store.root / "validate.json").write_text(result.to_json() + "\n")
    ctx.store.write_table(
        "errors_per_quantity",
        {
            "quantity": [s.quantity for s in result.stats],
            "n": [s.n for s in result.stats],
            "max_abs": [s.max_abs for s in result.stats],
            "max_rel": [s.max_rel for s in result.stats],
            "max_over_tolerance": [s.max_ratio for s in result.stats],
            "passed": [s.passed for s in result.stats],
            # six significant digits, not six decimals: the near-horizontal rods' theta (down to 1e-8) would read 0, outside (0, pi/2)
            "worst_state": [
                json.dumps({k: float(f"{v:.6g}") if isinstance(v, float) else v for k, v in s.worst_state.items()})
                for s in result.stats
            ],
        },
    )
    for s in result.stats:
        ctx.check(
            f"Pinocchio {s.quantity} within tolerance ({s.n} states)",
            s.passed,
            value=s.max_ratio,
            allowance=1.0,
            detail=f"max abs {s.max_abs:.2e}, max rel {s.max_rel:.2e} (ratio to allowance)",
        )

    rod = Rod(**P["rod"])
    alpha = rod.alpha
    om = rod.omega
    near_vertical = np.arccos(np.geomspace(P["cos_theta_min"], 0.9, P["n_theta"]))
    near_horizontal = np.geomspace(P["theta_min"], 0.7, P["n_theta"])
    cols = {k: [] for k in ("theta", "cos_theta", "end", "err_aba", "err_delassus", "err_b", "err_p")}
    for end, thetas in (("vertical", near_vertical), ("horizontal", near_horizontal)):
        for theta in ctx.progress(thetas, desc=f"pinocchio theta -> {end}"):
            k = P["draws_per_theta"]
            psi = ctx.rng.uniform(-np.pi, np.pi, k)
            Psi, Theta = ctx.rng.uniform(-3, 3, k), ctx.rng.uniform(-3, 3, k)
            F = ctx.rng.standard_normal((k, 3))  # scaled, units of m g
            varphi, mu = -np.pi * ctx.rng.uniform(0, 1, k), ctx.rng.uniform(0, 3, k)
            args = (rod, psi, np.full(k, theta), Psi * om, Theta * om, F * rod.mass * rod.gravity)
            want = analytic.tip_acceleration(*args) / rod.gravity
            A = (1 + alpha) * np.abs(F).sum(axis=1) + (1 + np.abs(Psi) + np.abs(Theta)) ** 2
            errs = {}
            for route in ("aba", "delassus"):
                got = pinrod.tip_acceleration(*args, route=route) / rod.gravity
                errs[route] = float(np.max(np.abs(got - want).max(axis=1) / A))
            eb = (
                np.abs(pinrod.b(Psi, Theta, theta) - analytic.b(Psi, Theta, theta))
                / (1 + np.abs(Psi) + np.abs(Theta)) ** 2
            )
            ep = np.abs(pinrod.p(theta, varphi, mu, alpha) - analytic.p(theta, varphi, mu, alpha)) / (
                (1 + alpha) * (1 + mu)
            )
            for key, v in (
                ("theta", theta),
                ("cos_theta", np.cos(theta)),
                ("end", end),
                ("err_aba", errs["aba"]),
                ("err_delassus", errs["delassus"]),
                ("err_b", float(eb.max())),
                ("err_p", float(ep.max())),
            ):
                cols[key].append(v)
        ctx.store.write_table("error_vs_theta", cols)


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, plt

    doc = json.loads(ctx.store.path("validate.json").read_text())
    t = ctx.store.read_table("errors_per_quantity", text=("quantity", "passed", "worst_state"))
    rows, cls = [], []
    for i in range(len(t["quantity"])):
        ok = t["passed"][i] == "True"
        worst = ", ".join(
            f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
            for k, v in json.loads(t["worst_state"][i]).items()
            if k != "index"
        )
        rows.append(
            [
                t["quantity"][i],
                f"{t['n'][i]:.0f}",
                f"{t['max_abs'][i]:.2e}",
                f"{t['max_rel'][i]:.2e}",
                f"{t['max_over_tolerance'][i]:.3f}",
                "ok" if ok else "FAIL",
                worst,
            ]
        )
        cls.append("ok" if ok else "fail")
    blocks = [
        Text(
            f"`crosscheck.engines.pinocchio.studies.dynamics_terms.validate` on {int(t['n'][0])} random rods and states ({doc['extra'].get('rods', '?')} rods): "
            f"{'every quantity within its tolerance' if doc['passed'] else 'SOME QUANTITIES EXCEED THEIR TOLERANCE'}. "
            f"Units: {doc['extra'].get('units', '')}."
        ),
        Table(
            caption="Error per quantity: largest absolute and relative error, largest ratio to the allowance (<= 1 passes) and the state where it occurs.",
            header=["quantity", "n", "max abs", "max rel", "/ tolerance", "result", "worst state"],
            rows=rows,
            data=ctx.data("errors_per_quantity.csv", "validate.json"),
            row_class=cls,
        ),
    ]
    by_decade = doc["extra"].get("tip_acc_error_over_A_by_cos_theta", [])
    if by_decade:
        keys = [k for k in by_decade[0] if k not in ("cos_theta", "n")]
        blocks.append(
            Table(
                caption="Largest tip-acceleration error / A per decade of cos theta (from the validation's random states).",
                header=["cos theta in", "n"] + keys,
                rows=[
                    [f"[{r['cos_theta'][0]:.0e}, {r['cos_theta'][1]:.0e})", str(r["n"])] + [f"{r[k]:.1e}" for k in keys]
                    for r in by_decade
                ],
                data=ctx.data("validate.json"),
            )
        )
    e = ctx.store.read_table("error_vs_theta", text=("end",))
    eps = np.finfo(float).eps
    floor = 1e-18  # exact agreement (error 0) is drawn at the floor of the log axis
    for k in ("err_aba", "err_delassus", "err_b", "err_p"):
        e[k] = np.maximum(e[k], floor)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.8))
    v = e["end"] == "vertical"
    c = e["cos_theta"][v]
    a1.loglog(c, e["err_aba"][v], "o-", ms=3, color=LINE_COLORS[0], label="tip acc., aba")
    a1.loglog(c, e["err_delassus"][v], "s-", ms=3, color=LINE_COLORS[1], label="tip acc., G F + free")
    a1.loglog(c, e["err_b"][v], "^-", ms=3, color=LINE_COLORS[2], label="b")
    a1.loglog(c, e["err_p"][v], "v-", ms=3, color=LINE_COLORS[3], label="p")
    a1.loglog(c, eps / c**2, "k--", lw=0.8, label="eps / cos$^2\\theta$")
    a1.loglog(c, eps / c, "k:", lw=0.8, label="eps / cos$\\theta$")
    a1.set_xlabel("cos $\\theta$ (rod towards vertical $\\rightarrow$)")
    a1.set_ylabel("max |Pinocchio - analytic| / A")
    a1.invert_xaxis()
    a1.legend(fontsize=7)
    a1.set_title("$\\theta \\rightarrow \\pi/2$")
    h = ~v
    th = e["theta"][h]
    a2.loglog(th, e["err_aba"][h], "o-", ms=3, color=LINE_COLORS[0], label="tip acc., aba")
    a2.loglog(th, e["err_delassus"][h], "s-", ms=3, color=LINE_COLORS[1], label="tip acc., G F + free")
    a2.loglog(th, e["err_b"][h], "^-", ms=3, color=LINE_COLORS[2], label="b")
    a2.loglog(th, e["err_p"][h], "v-", ms=3, color=LINE_COLORS[3], label="p")
    a2.axhline(eps, color="k", ls=":", lw=0.8, label="eps")
    a2.set_xlabel("$\\theta$ (rod towards horizontal $\\leftarrow$)")
    a2.set_title("$\\theta \\rightarrow 0$")
    a2.legend(fontsize=7)
    blocks.append(
        ctx.figure(
            "error_vs_theta",
            fig,
            "Pinocchio against eqs. linode2, b and p as the rod approaches the vertical (left, cos theta -> 0) and the horizontal (right, theta -> 0): "
            "largest error over random psi, rates, forces, slip directions and mu at each theta, in units of the term scale A. Dashed and dotted: "
            "eps / cos^2 theta (the condition number of M, expected for G F + free) and eps / cos theta. An error of exactly 0 is drawn at 1e-18.",
            ["error_vs_theta.csv"],
        )
    )
    blocks.append(Preformatted(json.dumps(doc, indent=1), title="validate JSON (crosscheck validate pinocchio --json)"))
    return blocks


def finding(data: Path) -> list:
    """The findings line of the dynamics terms: the worst error against the analytic terms as a fraction of its tolerance."""
    from crosscheck.report.finding import Finding, read_json

    out = []
    v = read_json(data / "validate.json")
    if v:
        worst = max(v["stats"], key=lambda s: s["max_ratio"])
        out.append(
            Finding(
                "Pinocchio dynamics terms",
                f"{len(v['stats'])} quantities; worst: {worst['quantity']} at {worst['max_ratio']:.2g} of its "
                f"tolerance (relative error {worst['max_rel']:.2g})",
                "agrees" if v["passed"] else "disagrees",
                SLUG,
            )
        )
    return out


SECTION = Section(
    slug=SLUG,
    title="Pinocchio vs analytic",
    paper="eqs. rotode, linode, linode2, b, p, mup2D",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.engines.pinocchio.studies.dynamics_terms", "crosscheck.engines.pinocchio.model"),
    finding=finding,
)
