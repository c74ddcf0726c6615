"""The compliant-limit section's runs: the studies of ``crosscheck.engines.compliant.studies.limit`` and their checks.

Each ``_run_*`` writes one part of the section's data (``limit`` renders it): the inconsistent starts and their
fitted slip-stop slopes, the restitution of the law against damping, the indeterminate boundary, the planar GB point
and the 3-D Corollary 4.2 jams.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.section import RunContext

__all__ = ["params", "run"]


def params(quick: bool) -> dict:
    if quick:
        return {
            "alpha": 3.0,
            "xi": 1.0,
            "inconsistent": [[2.0, "planar", 0.5], [2.0, "3d", [0.9, -1.2, 0.3, 0.8, 1.0]]],
            "eps": [1e-2, 1e-3, 1e-4],
            "xi_grid": [0.0, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0],
            "xi_post": {"case": [2.0, "3d", [0.9, -1.2, 0.3, 0.8, 1.0]], "eps": 1e-4, "xi": [0.3, 3.0]},
            "indeterminate": {
                "mu": 2.0,
                "state": [0.9, -1.2, 1.3, 0.8, 1.0],
                "eps": [1e-4],
                "D0": 2.0,
                "offsets": [-0.05, -0.02, 0.02, 0.05],
            },
            "gb": {
                "mu": 5.0 / 3.0,
                "theta0_deg": 31.0,
                "Theta0": 1.0,
                "scan": [0.0, 3.0, 31],
                "eps": [1e-3, 1e-4, 1e-5],
            },
            "corollary": {"mu": [1.7], "states": 2, "eps": [1e-3, 1e-4, 1e-5]},
        }
    return {
        "alpha": 3.0,
        "xi": 1.0,
        "inconsistent": [
            [2.0, "planar", 0.5],
            [1.4, "planar", 0.5],
            [2.0, "3d", [0.9, -1.2, 0.3, 0.8, 1.0]],
            [2.0, "3d", [0.9, -1.8, -0.4, -0.6, 1.5]],
        ],
        "eps": [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6],
        "xi_grid": [0.0, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0],
        "xi_post": {"case": [2.0, "3d", [0.9, -1.2, 0.3, 0.8, 1.0]], "eps": 1e-5, "xi": [0.0, 0.3, 1.0, 3.0, 10.0]},
        "indeterminate": {
            "mu": 2.0,
            "state": [0.9, -1.2, 1.3, 0.8, 1.0],
            "eps": [1e-3, 1e-4, 1e-5],
            "D0": 2.0,
            "offsets": [-0.2, -0.05, -0.02, -0.005, 0.005, 0.02, 0.05, 0.2],
        },
        "gb": {
            "mu": 5.0 / 3.0,
            "theta0_deg": 31.0,
            "Theta0": 1.0,
            "scan": [0.0, 3.0, 121],
            "eps": [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6],
        },
        "corollary": {"mu": [1.7, 6.0], "states": 5, "eps": [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6]},
    }


def _state(spec, mu, alpha):
    from crosscheck.engines.pinocchio.studies.rigid import planar_impasse
    from crosscheck.state import SlipState

    kind, x = spec
    return planar_impasse(mu, x, alpha) if kind == "planar" else SlipState(*x)


def run(ctx: RunContext) -> None:
    studies = _run_inconsistent(ctx)
    _run_xi_post(ctx)
    _run_restitution(ctx, studies)
    _run_indeterminate(ctx)
    _run_gb(ctx)
    _run_corollary(ctx)


def _run_inconsistent(ctx: RunContext) -> list:
    """Inconsistent starts: the eps ln(1/eps) law of the slip stop and the post-event state; returns the studies."""
    from crosscheck.engines.compliant.studies import limit as cl
    from crosscheck.engines.compliant.tolerances import COMPLIANT_LIMIT_POST_ORDER, COMPLIANT_LIMIT_SLIP_TIME

    P = ctx.params
    alpha, xi = P["alpha"], P["xi"]

    # inconsistent starts: the eps ln(1/eps) law and the post-event state
    studies, flat = [], {k: [] for k in ("case", "mu", "eps", "T", "predicted", "correction", "post_error", "seconds")}
    for k, (mu, *spec) in enumerate(ctx.progress(P["inconsistent"], desc="inconsistent starts")):
        d = cl.inconsistent_study(_state(spec, mu, alpha), mu, alpha, xi=xi, eps_values=P["eps"])
        studies.append(d)
        for r in d["rows"]:
            for key, v in zip(
                flat, (k, mu, r["eps"], r["T"], r["predicted"], r["correction"], r["errors"]["max"], r["seconds"])
            ):
                flat[key].append(v)
        ctx.store.write_json("inconsistent", studies)
    ctx.store.write_table("inconsistent", flat)
    ok_time = all(
        COMPLIANT_LIMIT_SLIP_TIME.ok(r["T"] - r["predicted"], r["correction"]) for d in studies for r in d["rows"]
    )
    worst = max(
        float(COMPLIANT_LIMIT_SLIP_TIME.ratio(r["T"] - r["predicted"], r["correction"]))
        for d in studies
        for r in d["rows"]
    )
    ctx.check(
        "inconsistent starts: t_stop/eps = ln(1/eps)/lambda + C + derived corrections",
        ok_time,
        value=worst,
        allowance=1.0,
        detail="ratio to the allowance; crosscheck.engines.compliant.tolerances.COMPLIANT_LIMIT_SLIP_TIME",
    )
    slopes = [
        [
            d["slope"],
            d["fast"]["coefficient"],
            cl.slope_bound(P["eps"], [r["correction"] for r in d["rows"]], COMPLIANT_LIMIT_SLIP_TIME),
        ]
        for d in studies
    ]
    ctx.check(
        "inconsistent starts: fitted slope of t_stop/eps against ln(1/eps) = 1/lambda",
        all(abs(a - b) <= c for a, b, c in slopes),
        value=[[a, b] for a, b, _ in slopes],
        allowance=[c for _, _, c in slopes],
        detail="[fitted, 1/lambda]; allowance: the corrections and their allowance carried through the fit (compliant_limit.slope_bound)",
    )
    orders = [[d["post_order"], d["t_end_order"]] for d in studies]
    ctx.check(
        "inconsistent starts: post-event state -> limit impact at the order of the impulse's end time t_end = O(eps ln(1/eps))",
        all(COMPLIANT_LIMIT_POST_ORDER.ok(a, b) for a, b in orders),
        value=orders,
        allowance=f"+- {COMPLIANT_LIMIT_POST_ORDER.atol}",
        detail="[post-event error order, t_end order]; crosscheck.engines.compliant.tolerances.COMPLIANT_LIMIT_POST_ORDER",
    )
    return studies


def _run_xi_post(ctx: RunContext) -> None:
    """The post-event state follows the restitution of its own xi."""
    from crosscheck.engines.compliant.studies import limit as cl
    from crosscheck.theory import compliant_limit as asymptotics

    P = ctx.params
    alpha = P["alpha"]

    # the post-event state follows the restitution of its own xi (the 3-D inconsistent start, at the smallest eps of the quick list)
    X = P["xi_post"]
    s3, mu3 = _state(X["case"][1:], X["case"][0], alpha), X["case"][0]
    xrows = []
    for x in X["xi"]:
        f = asymptotics.fast_limit(s3, mu3, alpha, xi=x)
        r = cl.limit_run(s3, mu3, alpha, eps=X["eps"], xi=x, horizon=0.05)
        xrows.append(
            {
                "xi": x,
                "restitution": f.restitution,
                "iwc_w": f.impact.w,
                "iwc_Theta": f.impact.Theta,
                "iwc_Psi": f.impact.Psi,
                "w": None if r.post is None else r.post["w"],
                "Theta": None if r.post is None else r.post["Theta"],
                "Psi": None if r.post is None else r.post["Psi"],
                "error": cl.post_errors(r, f.impact)["max"],
            }
        )
    ctx.store.write_json("xi_post", {"case": X["case"], "eps": X["eps"], "rows": xrows})
    ws = [r["iwc_w"] for r in xrows]
    spread = max(ws) - min(ws)
    ctx.check(
        "post-event state follows e(xi): |compliant - limit impact at its own xi| < 5 % of the spread of the limit impacts over xi",
        all(r["error"] < 0.05 * spread for r in xrows),
        value=[r["error"] for r in xrows],
        allowance=0.05 * spread,
    )


def _run_restitution(ctx: RunContext, studies: list) -> None:
    """The law's restitution e(xi) of each inconsistent start (the fast problem only)."""
    from crosscheck.state import SlipState
    from crosscheck.theory import compliant_limit as asymptotics
    from crosscheck.theory.impact.darboux_keller import delassus

    P = ctx.params
    alpha = P["alpha"]

    # the law's restitution e(xi), per state (fast problem only)
    rest = {"xi": P["xi_grid"]}
    for k, d in enumerate(studies):
        mu = d["mu"]
        s = SlipState(**d["state"])
        rest[f"e_{k}"] = [asymptotics.fast_limit(s, mu, alpha, xi=x).restitution for x in P["xi_grid"]]
        G = delassus(s, alpha)
        S = float(G[2, 2] - G[2, :2] @ np.linalg.solve(G[:2, :2], G[:2, 2]))
        rest[f"tail_{k}"] = [1.0 / (S * x * x) if x > 0 else math.nan for x in P["xi_grid"]]
    ctx.store.write_table("restitution", rest)


def _run_indeterminate(ctx: RunContext) -> None:
    """Indeterminate starts: lift-off or impact as the slipping force's stable manifold predicts."""
    from crosscheck.engines.compliant.studies import limit as cl
    from crosscheck.state import SlipState

    P = ctx.params
    alpha, xi = P["alpha"], P["xi"]

    # indeterminate boundary
    I = P["indeterminate"]
    ind = [
        cl.indeterminate_study(
            SlipState(*I["state"]), I["mu"], alpha, xi=xi, eps=eps, D0=I["D0"], offsets=I["offsets"], horizon=0.05
        )
        for eps in ctx.progress(I["eps"], desc="indeterminate")
    ]
    ctx.store.write_json("indeterminate", ind)
    flips = [r["outcome"] == r["predicted"] for d in ind for r in d["rows"]]
    ctx.check(
        "indeterminate starts: lift-off / impact as the stable manifold of the slipping force predicts",
        all(flips),
        value=f"{sum(flips)} of {len(flips)}",
        allowance="all",
    )


def _run_gb(ctx: RunContext) -> None:
    """The planar GB point: the slip stop tends to the rigid arrival, the post-event state to the plastic impact."""
    from crosscheck.engines.compliant.studies import limit as cl
    from crosscheck.state import SlipState
    from crosscheck.theory import compliant_limit as asymptotics

    P = ctx.params
    alpha, xi = P["alpha"], P["xi"]

    # the planar GB point
    g = P["gb"]
    theta0 = math.radians(g["theta0_deg"])
    Theta0, outcome = asymptotics.gb_reaching_rates(
        g["mu"], alpha, theta0, Theta_range=(g["scan"][0], g["scan"][1]), n=g["scan"][2]
    )
    ctx.store.write_table("gb_scan", {"Theta0": Theta0, "outcome": outcome})
    gb = cl.jam_study(
        SlipState(theta=theta0, varphi=-math.pi / 2, Theta=g["Theta0"], Psi=0.0, eta=1.0),
        g["mu"],
        alpha,
        xi=xi,
        eps_values=g["eps"],
    )
    ctx.store.write_json("gb", gb)
    err = _finite([r["errors"]["max"] for r in gb["rows"]])
    lag = _finite([r["lag"] for r in gb["rows"]])
    ctx.check(
        "planar GB point: slip stop -> the rigid arrival, post-event state -> the plastic impact (rates measured)",
        all(a > b for a, b in zip(err, err[1:])) and all(a > b > 0 for a, b in zip(lag, lag[1:])),
        value={"lag_order": gb["lag_order"], "post_order": gb["post_order"]},
        allowance="monotone decrease",
    )


def _run_corollary(ctx: RunContext) -> None:
    """Corollary 4.2 jams in 3-D: the slip-stop lag ~ eps^(4/5) and the post-event state tending to the limit impact."""
    from crosscheck.engines.compliant.studies import limit as cl
    from crosscheck.engines.compliant.tolerances import COMPLIANT_LIMIT_JAM_LAG_ORDER
    from crosscheck.theory.corollary import corollary_states

    P = ctx.params
    alpha, xi = P["alpha"], P["xi"]

    # Corollary 4.2 jams in 3-D
    C = P["corollary"]
    cor = []
    table = {
        k: []
        for k in (
            "mu",
            "state",
            "eps",
            "t_jam",
            "t_stop",
            "lag",
            "restitution",
            "Theta",
            "Theta_iwc",
            "Psi",
            "Psi_iwc",
            "w",
            "w_iwc",
            "post_error",
            "seconds",
        )
    }
    for mu in C["mu"]:
        states, _, _ = corollary_states(mu, C["states"], ctx.rng, alpha=alpha)
        for k, s in enumerate(ctx.progress(states, desc=f"Corollary 4.2, mu = {mu}")):
            d = cl.jam_study(s, mu, alpha, xi=xi, eps_values=C["eps"])
            cor.append(d)
            ctx.store.write_json("corollary", cor)
            for r in d["rows"]:
                post = r["post"] or {}
                vals = (
                    mu,
                    k,
                    r["eps"],
                    d["t_jam"],
                    r["t_stop"],
                    r["lag"],
                    d["restitution"],
                    post.get("Theta", math.nan),
                    d["iwc"]["Theta"],
                    post.get("Psi", math.nan),
                    d["iwc"]["Psi"],
                    post.get("w", math.nan),
                    d["iwc"]["w"],
                    r["errors"]["max"],
                    r["seconds"],
                )
                for key, v in zip(table, vals):
                    table[key].append(v)
    ctx.store.write_table("corollary", table)
    lag_orders = [d["lag_order"] for d in cor]
    ctx.check(
        "Corollary 4.2 jams: slip-stop lag t_stop - t_jam ~ eps^(4/5)",
        all(COMPLIANT_LIMIT_JAM_LAG_ORDER.ok(o, 0.8) for o in lag_orders),
        value=lag_orders,
        allowance=f"0.8 +- {COMPLIANT_LIMIT_JAM_LAG_ORDER.atol}",
        detail="crosscheck.engines.compliant.tolerances.COMPLIANT_LIMIT_JAM_LAG_ORDER",
    )
    conv = [
        all(a > b for a, b in zip(e, e[1:])) for e in (_finite([r["errors"]["max"] for r in d["rows"]]) for d in cor)
    ]
    ctx.check(
        "Corollary 4.2 jams: post-event state -> the limit impact (the law's restitution) as eps decreases",
        all(conv),
        value=[d["post_order"] for d in cor],
        allowance="monotone decrease (orders shown are measured)",
    )


def _finite(xs) -> list:
    """The finite numbers of ``xs`` in order (a run the compliant solver could not finish has none)."""
    return [x for x in xs if x is not None and math.isfinite(x)]
