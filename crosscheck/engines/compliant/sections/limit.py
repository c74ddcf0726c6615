"""The compliant rod as eps -> 0: slip stops after inconsistent starts, the law's restitution, the indeterminate boundary, the planar GB point and 3-D Corollary 4.2 jams, against the rigid impact without collision.

All from ``crosscheck.engines.compliant.studies.limit`` (its module docstring has the
derivations) with the compliant rod of ``crosscheck.engines.compliant``
(Kelvin-Voigt law, stiffness 1/eps^2, damping xi/eps, exact Coulomb
friction):

* inconsistent starts (p < 0, b < 0): t_stop/eps against
  ln(1/eps)/lambda + C (+ the derived corrections), and the state after the
  impulse against the limit impact;
* the restitution e(xi) the Kelvin-Voigt law implies (the fast problem; the
  planar closed form and its 1/(S xi^2) tail);
* the indeterminate boundary (p < 0 < b): starts either side of the stable
  manifold of the slipping force;
* the planar GB point P+ (Genot-Brogliato's alpha = 3, mu = 5/3, theta0 = 31
  degrees): slip stop against the rigid arrival and the plastic impact;
* Corollary 4.2 jams in 3-D: slip stop against the rigid jam time (lag
  ~ eps^(4/5)) and the post-event state against the limit impact.

The runs: ``limit_runs``; here the figures, tables and findings line.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from crosscheck.engines.compliant.sections.limit_runs import params, run
from crosscheck.report.section import RenderContext, Section, Table, Text

SLUG = "compliant_limit"


def _fmt(x, spec=".3g") -> str:
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, spec)


def render(ctx: RenderContext) -> list:
    inc = ctx.store.read_json("inconsistent")
    return [
        *_inconsistent_blocks(ctx, inc),
        *_restitution_blocks(ctx, inc),
        *_indeterminate_blocks(ctx),
        *_gb_blocks(ctx),
    ]


def _inconsistent_blocks(ctx: RenderContext, inc: list) -> list:
    """Inconsistent starts: the compliant rod's slip stop and impulse against the IWC's as eps -> 0."""
    from crosscheck.report.plotting import LINE_COLORS, plt

    blocks: list = []
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    rows = []
    for k, d in enumerate(inc):
        eps = np.array([r["eps"] for r in d["rows"]])
        T = np.array([r["T"] for r in d["rows"]])
        pred = np.array([r["predicted"] for r in d["rows"]])
        corr = np.array([r["correction"] for r in d["rows"]])
        c = LINE_COLORS[k % 7]
        x = np.log(1 / eps)
        ax[0].plot(x, T, "o", color=c, label=f"case {k}: compliant")
        ax[0].plot(x, pred, "-", color=c, lw=1, label=f"case {k}: ln(1/eps)/lambda + C")
        ax[1].loglog(eps, np.abs(T - pred), "o-", color=c, label=f"case {k}: |t/eps - law|")
        ax[1].loglog(eps, np.abs(corr), "--", color=c, lw=1, label=f"case {k}: C1 eps T + C2 eps T^2")
        s = d["state"]
        f = d["fast"]
        rows.append(
            [
                str(k),
                f"{d['mu']:g}",
                f"theta={s['theta']:.3f} varphi={s['varphi']:.3f} Theta={s['Theta']:.3f} Psi={s['Psi']:.3f} eta={s['eta']:.3f}",
                f"{f['p']:.4f}",
                f"{f['b']:.4f}",
                f"{f['lambda']:.4f}",
                f"{f['coefficient']:.4f}",
                f"{d['slope']:.4f}",
                f"{f['offset']:.4f}",
                f"{d['C1']:.3g}, {d['C2']:.3g}",
                f"{f['restitution']:.4f}",
                f"{_fmt(d['post_order'], '.3f')} ({_fmt(d['t_end_order'], '.3f')})",
            ]
        )
    ax[0].set_xlabel("ln(1/eps)")
    ax[0].set_ylabel("t_stop / eps")
    ax[1].set_xlabel("eps")
    ax[1].invert_xaxis()
    for a in ax:
        a.legend(fontsize=6)
    blocks.append(
        ctx.figure(
            "slip_stop_time",
            fig,
            "Inconsistent starts (p < 0, b < 0): the compliant rod's slip-stop time over eps (left, dots) against the "
            "derived law t_stop/eps = ln(1/eps)/lambda + C (lines; lambda^2 - |p| xi lambda - |p| = 0, C from the fast problem); right: "
            "the departure from the law against the derived first corrections (drift of the slip speed and of lambda along the formal "
            "slipping flow).",
            ["inconsistent.json", "inconsistent.csv"],
        )
    )
    blocks.append(
        Table(
            caption="Inconsistent starts: derived and measured coefficients (xi as in the parameters). slope: least-squares slope of "
            "t_stop/eps against ln(1/eps) over the eps of this report; e: the restitution the law implies in the limit; order: "
            "observed order of the post-event error against the limit impact, and in brackets that of the impulse's end time t_end = "
            "O(eps ln(1/eps)), its derived scale.",
            header=[
                "case",
                "mu",
                "state",
                "p",
                "b",
                "lambda",
                "1/lambda",
                "slope",
                "C",
                "C1, C2",
                "e(xi)",
                "post order",
            ],
            rows=rows,
            data=ctx.data("inconsistent.json", "inconsistent.csv"),
        )
    )

    return blocks


def _restitution_blocks(ctx: RenderContext, inc: list) -> list:
    """The restitution the compliant contact gives after the impulse, and the post-impact state against xi."""
    from crosscheck.report.plotting import LINE_COLORS, plt

    blocks: list = []
    rest = ctx.store.read_table("restitution")
    fig, ax = plt.subplots(figsize=(5, 3.6))
    xi = np.asarray(rest["xi"], float)
    for k in range(len(inc)):
        c = LINE_COLORS[k % 7]
        ax.plot(xi[xi > 0], np.asarray(rest[f"e_{k}"], float)[xi > 0], "o-", color=c, label=f"case {k}: fast problem")
        ax.plot(
            xi[xi > 0], np.asarray(rest[f"tail_{k}"], float)[xi > 0], ":", color=c, lw=1, label=f"case {k}: 1/(S xi^2)"
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("xi")
    ax.set_ylabel("e = P_f / P_c - 1")
    ax.legend(fontsize=6)
    blocks.append(
        ctx.figure(
            "restitution",
            fig,
            "The restitution the Kelvin-Voigt law implies in the eps -> 0 limit, by state: not a constant of xi, since "
            "the slip phase (normal 'mass' 1/p < 0) sets the penetration rate the stick phase (Schur complement S) starts from; at "
            "xi = 0 e < 1 all the same. For large xi e ~ 1/(S xi^2) (dotted): the plastic impact.",
            ["restitution.csv"],
        )
    )

    xp = ctx.store.read_json("xi_post")
    blocks.append(
        Table(
            caption=f"The post-event state depends on xi as the law's restitution predicts: the 3-D inconsistent start (mu = "
            f"{xp['case'][0]:g}) at eps = {xp['eps']:g}, the compliant state at the contact end against the limit impact "
            "with e(xi) (compliant / limit).",
            header=["xi", "e(xi)", "w", "Theta", "Psi", "max error"],
            rows=[
                [
                    f"{r['xi']:g}",
                    f"{r['restitution']:.4f}",
                    f"{_fmt(r['w'], '.5f')} / {r['iwc_w']:.5f}",
                    f"{_fmt(r['Theta'], '.5f')} / {r['iwc_Theta']:.5f}",
                    f"{_fmt(r['Psi'], '.5f')} / {r['iwc_Psi']:.5f}",
                    _fmt(r["error"]),
                ]
                for r in xp["rows"]
            ],
            data=ctx.data("xi_post.json"),
        )
    )

    return blocks


def _indeterminate_blocks(ctx: RenderContext) -> list:
    """Indeterminate starts (p < 0, b > 0)."""
    blocks: list = []
    ind = ctx.store.read_json("indeterminate")
    rows = [
        [
            f"{d['eps']:g}",
            f"{r['offset']:+g}",
            f"{r['gap_rate']:.6g}",
            r["predicted"],
            r["outcome"],
            _fmt(r["t_stop"]),
            _fmt(r["t_end"]),
        ]
        for d in ind
        for r in d["rows"]
    ]
    d0 = ind[0]
    blocks.append(
        Table(
            caption=f"Indeterminate start (p = {d0['p']:.4f} < 0 < b = {d0['b']:.4f}, mu = {d0['mu']:g}): gap = -eps^2 D0 with D0 = "
            f"{d0['D0']:g} (the slipping force D* = b/|p| = {d0['b'] / abs(d0['p']):.4f}), gap rates a relative offset from the "
            f"boundary eps |lambda_2| (D0 - D*) (lambda_2 = {d0['lambda_2']:.4f}): inwards the force grows into an impact without "
            "collision, outwards the tip lifts off.",
            header=["eps", "offset", "gap rate", "predicted", "compliant", "slip stop", "contact end"],
            rows=rows,
            data=ctx.data("indeterminate.json"),
        )
    )

    return blocks


def _gb_blocks(ctx: RenderContext) -> list:
    """Starts that slip into the GB point and Corollary 4.2 jams: the compliant rod against the theory."""
    from crosscheck.report.plotting import plt

    blocks: list = []
    gb = ctx.store.read_json("gb")
    cor = ctx.store.read_json("corollary")
    scan = ctx.store.read_table("gb_scan")
    reach = np.asarray(scan["Theta0"], float)[np.asarray(scan["outcome"], int) == 5]
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    for k, d in enumerate([gb] + cor):
        eps = np.array([r["eps"] for r in d["rows"]])
        lag = np.abs(np.array([r["lag"] for r in d["rows"]], float))
        err = np.array([r["errors"]["max"] for r in d["rows"]], float)
        label = "planar GB point" if k == 0 else f"Corollary 4.2, mu = {d['mu']:g}, #{k - 1}"
        style = "s-" if k == 0 else "o-"
        color = "k" if k == 0 else plt.cm.tab20((k - 1) % 20)
        ax[0].loglog(eps, lag, style, color=color, lw=1, ms=3, label=label)
        ax[1].loglog(eps, err, style, color=color, lw=1, ms=3, label=label)
    if cor:
        e_ref = np.array([r["eps"] for r in cor[0]["rows"]])
        ax[0].loglog(
            e_ref,
            np.abs(cor[0]["rows"][0]["lag"]) * (e_ref / e_ref[0]) ** 0.8,
            ":",
            color="0.4",
            lw=1.5,
            label="eps^(4/5)",
        )
    ax[0].set_ylabel("|t_stop - t_jam| (rigid)")
    ax[1].set_ylabel("max |post-event - limit impact| (Theta, Psi, tip velocity)")
    for a in ax:
        a.set_xlabel("eps")
        a.invert_xaxis()
        a.legend(fontsize=5)
    blocks.append(
        ctx.figure(
            "jam_convergence",
            fig,
            "Slips into p = 0: the compliant rod's slip-stop lag behind the rigid jam (left) and its state at the "
            "contact end against the limit impact (right), per state, as eps -> 0. Corollary 4.2 jams (3-D, b < 0): the limit impact "
            "is crosscheck.theory.impact.darboux_keller with the restitution the law implies (the fast problem from its self-similar start), the lag is "
            "derived ~ eps^(4/5). Planar GB point P+ (alpha = 3, mu = 5/3, theta0 = 31 degrees): against the plastic impact at P+; "
            "its rates are measured, not derived.",
            ["gb.json", "gb_scan.csv", "corollary.json", "corollary.csv"],
        )
    )
    blocks.append(_gb_table(ctx, gb, cor))
    failed = [
        (("GB P+" if k == 0 else f"mu={d['mu']:g} #{k - 1}"), r["eps"], r["kinds"][-1] if r["kinds"] else "-")
        for k, d in enumerate([gb] + cor)
        for r in d["rows"]
        if r["post"] is None
    ]
    if failed:
        blocks.append(
            Text(
                "Compliant runs that did not reach a contact end (left out of the fits and of the convergence checks): "
                + "; ".join(f"{n} at eps = {e:g} ({why})" for n, e, why in failed)
                + "."
            )
        )
    blocks.append(
        Text(
            f"Planar starts at theta0 = {gb['state']['theta']:.4f} (31 degrees), varphi = -pi/2, Psi = 0, eta = 1 that slip into P+: Theta0 in "
            f"[{reach.min():.3f}, {reach.max():.3f}] on the scanned grid ({len(reach)} of {len(scan['Theta0'])} points; data gb_scan.csv)."
            if len(reach)
            else "No scanned planar start reached P+."
        )
    )
    return blocks


def _gb_table(ctx: RenderContext, gb: dict, cor: list) -> Table:
    """The GB start and the Corollary 4.2 starts, eps by eps: the compliant rod against the theory's IWC."""
    rows = []
    for k, d in enumerate([gb] + cor):
        name = "GB P+" if k == 0 else f"mu={d['mu']:g} #{k - 1}"
        for r in d["rows"]:
            post = r["post"] or {}
            rows.append(
                [
                    name,
                    f"{r['eps']:g}",
                    f"{d['t_jam']:.6f}",
                    _fmt(r["t_stop"], ".6f"),
                    _fmt(r["lag"]),
                    f"{_fmt(post.get('Theta'), '.5f')} / {d['iwc']['Theta']:.5f}",
                    f"{_fmt(post.get('Psi'), '.5f')} / {d['iwc']['Psi']:.5f}",
                    f"{_fmt(post.get('w'), '.4g')} / {d['iwc']['w']:.4g}",
                    _fmt(r["errors"]["max"]),
                    f"{d['restitution']:.4f}",
                    f"{_fmt(d['lag_order'], '.3f')}, {_fmt(d['post_order'], '.3f')}",
                ]
            )
    return Table(
        caption="Slips into p = 0, per state and eps: the compliant slip stop against the rigid jam (GB arrival) time, the post-event rates "
        "and the tip's normal velocity w against the limit impact (compliant / rigid), the restitution e the law implies there, "
        "and the fitted orders of the lag and of the post-event error over eps.",
        header=[
            "state",
            "eps",
            "t_jam",
            "t_stop",
            "lag",
            "Theta",
            "Psi",
            "w",
            "post error",
            "e",
            "orders (lag, post)",
        ],
        rows=rows,
        data=ctx.data("gb.json", "corollary.json", "corollary.csv"),
    )


def finding(data: Path) -> list:
    """The findings line of the compliant rod's eps -> 0 limit: its physics checks and measured rates."""
    from crosscheck.report.finding import Finding, read_json

    out = []
    limit = read_json(data / "checks.json")
    if limit:
        physics = [c for c in limit if c.get("kind") == "physics"]
        ok = sum(c["passed"] for c in physics)
        slopes = next((c["value"] for c in limit if "fitted slope" in c["name"]), [])
        lag = next((c["value"] for c in limit if "slip-stop lag" in c["name"]), [])
        gb_rates = next((c["value"] for c in limit if "planar GB point" in c["name"]), {})
        text = (
            f"{ok} of {len(physics)} physics checks of the eps -> 0 limit hold: an inconsistent start stops slipping after "
            f"(eps/lambda) ln(1/eps) (fitted slopes {', '.join(f'{a:.3f}' for a, _ in slopes)} against 1/lambda "
            f"{', '.join(f'{b:.3f}' for _, b in slopes)}) and its post-event state tends to the rigid impact without collision with the "
            f"restitution its damping implies; the lift-off / impact boundary of an indeterminate start holds"
        )
        if lag:
            text += f"; at Corollary 4.2 jams the slip stop lags the rigid jam as eps^{min(lag):.2f}-eps^{max(lag):.2f} (derived eps^0.8)"
        if gb_rates:
            text += f"; at the planar GB point convergence is slow (lag order {gb_rates['lag_order']:.2f}, post-event order {gb_rates['post_order']:.2f})"
        out.append(Finding("compliant rod: eps -> 0", text, "agrees" if ok == len(physics) else "disagrees", SLUG))
    return out


SECTION = Section(
    slug=SLUG,
    title="Compliant rod: the eps -> 0 limit against the impact without collision",
    paper="eqs. b, p, FZ, Corollary 4.2, section 6",
    params=params,
    run=run,
    render=render,
    requires=(
        "crosscheck.engines.compliant",
        "crosscheck.engines.compliant.studies.limit",
        "crosscheck.theory.impact.darboux_keller",
        "crosscheck.theory.corollary",
    ),
    finding=finding,
)
