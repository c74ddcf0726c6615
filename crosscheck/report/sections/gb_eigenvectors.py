"""Figs. 12 and 13: the eigenvectors of K in the (p, b) plane at the paper's points around the GB manifold.

At each point (theta_GB, varphi_GB) of ``crosscheck.theory.paper.GB_POINTS`` (eta =
1, Psi = 0, Theta_GB = sqrt(csc theta_GB), alpha = 3, mu = 1.4 and 1.7) the
point is put exactly on p = 0 (the printed varphi has four digits: the root
varphi_-+(theta) nearest to it; the printed P+, Q+ are theta_1, theta_2 at
varphi = -pi/2) and K (eq. K) gives eigenvalues, eigenvectors (strong: the
larger |lambda|, blue; weak: red, as the paper) and the type of the point.
Orbits of the linearised flow (p, b)' = K (p, b) (eq. p3a3) are drawn in
the desingularised time s, which reverses t where p < 0 (so orbits in the
first three quadrants are artefacts, as the paper's footnote says).

Checks (section 4): P+ is a stable node and Q+ a saddle; for mu = 1.4 < mu_C
the strong eigenvector of P+ is on the b axis and the weak one in the first
and third quadrants, for mu = 1.7 > mu_C the other way round; (b) is a
stable node and (d) a saddle; the zero of det K along the manifold between
them (``crosscheck.theory.gb.det_K_zeros``) is the printed point (c) to its printed
digits.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import critical
from crosscheck.theory.paper import GB_POINTS

SLUG = "gb_eigenvectors"


def params(quick: bool) -> dict:
    return {"alpha": 3.0, "eta": 1.0, "Psi": 0.0, "n_orbits": 12 if quick else 24, "n_s": 60 if quick else 200}


def _snap(mu, alpha, theta_s, varphi_s):
    """The point of the GB manifold the printed digits stand for: (theta, varphi) exactly on p = 0."""
    th, vp = float(theta_s), float(varphi_s)
    if vp > 0:  # Fig. 13(d)'s sign typo, documented in crosscheck.theory.paper
        vp = -vp
    if varphi_s == "-1.5708":  # P+ / Q+: theta_1 or theta_2 at varphi = -pi/2
        th1, th2 = critical.theta_12(mu, alpha)
        return (float(th1) if abs(th - th1) < abs(th - th2) else float(th2)), -math.pi / 2
    roots = np.array(critical.varphi_pm(th, mu, alpha), dtype=float)
    return th, float(roots[np.nanargmin(np.abs(roots - vp))])


def run(ctx: RunContext) -> None:
    from crosscheck.theory import gb

    P = ctx.params
    alpha, eta, Psi = P["alpha"], P["eta"], P["Psi"]
    points = []
    orbits = {k: [] for k in ("point", "orbit", "s", "p", "b")}
    for i, (mu, th_s, vp_s, where) in enumerate(GB_POINTS):
        theta, varphi = _snap(mu, alpha, th_s, vp_s)
        Theta = math.sqrt(1 / math.sin(theta))
        Km = gb.K(theta, varphi, Psi, Theta, eta, mu, alpha)
        lam, vec = gb.eigen(Km)
        kind = gb.gb_type(Km)
        strong = int(np.argmax(np.abs(lam)))
        quads = [gb.quadrant(vec[:, k], atol=1e-12).name for k in range(2)]
        points.append(
            {
                "index": i,
                "where": where,
                "mu": mu,
                "theta": theta,
                "varphi": varphi,
                "Theta": Theta,
                "Psi": Psi,
                "eta": eta,
                "K": Km,
                "lambda": [[float(l.real), float(l.imag)] for l in lam],
                "e_plus": [float(v.real) for v in vec[:, 0]],
                "e_minus": [float(v.real) for v in vec[:, 1]],
                "type": kind.name,
                "strong": "plus" if strong == 0 else "minus",
                "quadrant_plus": quads[0],
                "quadrant_minus": quads[1],
                "quadrant_strong": quads[strong],
                "quadrant_weak": quads[1 - strong],
            }
        )
        ctx.store.write_json("points", points)
        # orbits of the linear flow from a circle, forward and backward in s; time scale 1/max|lambda|
        s, ys = gb.linear_orbits(Km, n_orbits=P["n_orbits"], n_s=P["n_s"])
        for j, y in enumerate(ys):
            for k, v in (
                ("point", np.full(s.size, i)),
                ("orbit", np.full(s.size, j)),
                ("s", s),
                ("p", y[:, 0]),
                ("b", y[:, 1]),
            ):
                orbits[k] += list(v)
    ctx.store.write_table("orbits", orbits)

    by = {p["where"]: p for p in points}
    for mu, fig in ((1.4, "12"), (1.7, "13")):
        _check_figure(ctx, by, mu, fig)


def _check_figure(ctx: RunContext, by: dict, mu: float, fig: str) -> None:
    """Section 4's checks of Fig. ``fig`` (at ``mu``) on its points ``by`` their place: the types of P+, Q+, (b) and
    (d), the eigenvectors' quadrants (eq. evecK2D and the figure's text), and the zero of det K at (c)."""
    from crosscheck.theory import gb

    P = ctx.params
    alpha, eta, Psi = P["alpha"], P["eta"], P["Psi"]

    def expect(where, name, ok, detail):
        ctx.check(f"{where}: {name}", ok, detail=detail)

    a, e = (
        by[next(w for w in by if w.startswith(f"Fig. {fig}(a)"))],
        by[next(w for w in by if w.startswith(f"Fig. {fig}(e)"))],
    )
    expect(a["where"], "P+ is a stable node", a["type"] == "STABLE_NODE", a["type"])
    expect(e["where"], "Q+ is a saddle", e["type"] == "SADDLE", e["type"])
    # eq. evecK2D: e_1 = (3 tan^2 theta - (1 + alpha), 1) for lambda_1 = K11, e_2 = (0, 1) for lambda_2 = K22;
    # section 4's summary: e_1 in quadrants I/III for mu < mu_C, II/IV for mu > mu_C; e_2 on the b axis.
    e1_quadrant = "I_III" if mu < critical.mu_C(alpha) else "II_IV"
    e1, e2 = (
        (a["quadrant_strong"], a["quadrant_weak"])
        if a["quadrant_strong"] != "B_AXIS"
        else (a["quadrant_weak"], a["quadrant_strong"])
    )
    expect(
        a["where"],
        f"eq. evecK2D: e_1 in quadrants {e1_quadrant.replace('_', '/')}, e_2 on the b axis",
        e1 == e1_quadrant and e2 == "B_AXIS",
        f"e_1 {e1}, e_2 {e2}; strong {a['quadrant_strong']}, weak {a['quadrant_weak']}",
    )
    if mu < critical.mu_C(alpha):
        expect(
            a["where"],
            "text of Fig. 12: strong direction on the b axis, weak in quadrants I/III",
            a["quadrant_strong"] == "B_AXIS" and a["quadrant_weak"] == "I_III",
            f"strong {a['quadrant_strong']}, weak {a['quadrant_weak']}",
        )
    else:
        ok = a["quadrant_strong"] == "I_III" and a["quadrant_weak"] == "B_AXIS"
        ctx.check(
            f"{a['where']}: text of Fig. 13: strong direction in quadrants I/III, weak on the b axis",
            ok,
            detail=f"strong {a['quadrant_strong']}, weak {a['quadrant_weak']}",
            known=""
            if ok
            else (
                "the paper contradicts itself: its eq. evecK2D gives e_1 = (3 tan^2 theta_1 - (1 + alpha), 1), negative first "
                "component for mu > mu_C (its own summary: 'e_1 in the second and fourth quadrants'); the strong "
                "eigenvector here is e_1, so it lies in quadrants II/IV, not I/III as the text of Fig. 13 says"
            ),
        )
    b_, d_ = (
        by[next(w for w in by if w.startswith(f"Fig. {fig}(b)"))],
        by[next(w for w in by if w.startswith(f"Fig. {fig}(d)"))],
    )
    expect(b_["where"], "a stable node before the bifurcation", b_["type"] == "STABLE_NODE", b_["type"])
    expect(d_["where"], "a saddle after the bifurcation", d_["type"] == "SADDLE", d_["type"])
    c_where = next(w for w in by if w.startswith(f"Fig. {fig}(c)"))
    th_c, vp_c = next((float(t), float(v)) for m, t, v, w in GB_POINTS if w == c_where)
    curves = [c for c in gb.gb_manifold(mu, Psi, alpha, n=401) if c.sign > 0]
    zeros = np.vstack([gb.det_K_zeros(c, eta) for c in curves])
    z = zeros[np.argmin(np.hypot(zeros[:, 0] - th_c, zeros[:, 1] - vp_c))]
    err = max(abs(z[0] - th_c), abs(z[1] - vp_c))
    ctx.check(
        f"{c_where}: the zero of det K along the manifold (lambda_+ = 0) is the printed point",
        err <= 0.5e-4,
        value=err,
        allowance=0.5e-4,
        detail=f"det K = 0 at theta = {z[0]:.6f}, varphi = {z[1]:.6f}; printed ({th_c}, {vp_c})",
    )
    ctx.store.write_json(f"det_zero_fig{fig}", {"theta": z[0], "varphi": z[1], "Theta": z[2], "printed": [th_c, vp_c]})


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import pb_eigenvectors, pb_orbits, pb_plane, plt, strong_weak_colors

    points = ctx.store.read_json("points")
    orb = ctx.store.read_table("orbits")
    blocks = []
    for mu, fig_no in ((1.4, "12"), (1.7, "13")):
        pts = [p for p in points if p["mu"] == mu]
        fig, axes = plt.subplots(1, len(pts), figsize=(2.6 * len(pts), 2.7))
        for ax, p in zip(axes, pts):
            pb_plane(ax, 1.0, 1.0)
            sel = orb["point"] == p["index"]
            pb_orbits(ax, orb["p"][sel], orb["b"][sel], orb["orbit"][sel])
            lam = [complex(*l) for l in p["lambda"]]
            pb_eigenvectors(ax, p["e_plus"], p["e_minus"], strong_weak_colors(p["strong"]))
            ax.set_title(
                f"{p['where'].split(',')[0].replace('Fig. ', '')}: {p['type'].lower().replace('_', ' ')}", fontsize=8
            )
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
            f"Fig. {fig_no} recomputed: eigenvectors of K (eq. K) in the (p, b) plane at the points of Fig. {fig_no} (alpha = 3, mu = {mu:g}, eta = 1, Psi = 0, "
            "Theta = sqrt(csc theta)); strong eigenvector (larger |lambda|) blue, weak red; grey: orbits of (p, b)' = K (p, b) in the desingularised time s. "
            "Shading as Fig. 3a: slipping (p > 0, b < 0) yellow, lift-off orange, inconsistent lime, indeterminate purple. Not to scale."
        )
        blocks.append(ctx.figure(f"fig{fig_no}_eigenvectors", fig, cap, ["points.json", "orbits.csv"]))
    rows = []
    for p in points:
        lam = [complex(*l) for l in p["lambda"]]
        rows.append(
            [
                p["where"],
                f"{p['mu']:g}",
                f"{p['theta']:.5f}",
                f"{p['varphi']:.5f}",
                f"{p['Theta']:.4f}",
                p["type"].lower(),
                f"{lam[0].real:.4g}" + (f"{lam[0].imag:+.3g}i" if lam[0].imag else ""),
                f"{lam[1].real:.4g}" + (f"{lam[1].imag:+.3g}i" if lam[1].imag else ""),
                p["quadrant_strong"],
                p["quadrant_weak"],
            ]
        )
    blocks.append(
        Table(
            caption="The points, their type and eigenvectors' quadrants (I_III: first and third; II_IV: second and fourth; B_AXIS: along b).",
            header=["point", "mu", "theta", "varphi", "Theta", "type", "lambda_+", "lambda_-", "strong e", "weak e"],
            rows=rows,
            data=ctx.data("points.json"),
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="Eigenvectors of K at the paper's GB points",
    paper="Figs. 12 (fig:planesmu1p4_w_traj) and 13 (fig:planesmu1p7_w_traj); eqs. K, evalK2D, evecK2D",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.theory.gb",),
)
