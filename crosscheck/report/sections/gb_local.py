"""Figs. 14 and 15: the local (p, b) dynamics near the GB manifold for Theta > 0 and Theta < 0, as computed orbits.

The paper sketches, for each type a GB point can have (section 4), the orbits
of the slipping flow in the (p, b) plane near it.  Here the sketches are
computed: the GB manifold is sampled at the paper's parameters (alpha = 3;
mu = 1.4, 1.7 and 6; Psi from 0 to 2; eta = 1 and 10), the first point of
each (sign of Theta, type) found is kept, and the orbits of the linearised
flow (p, b)' = K (p, b) (eq. K, desingularised time s) are drawn from a
circle of starts, forward and backward, with K's eigenvectors.

Checks: Theorem 4.1 (no stable node or focus with Theta < 0) over every
sampled point; every orbit of the linear flow satisfies (p, b)(s) = expm(K s)
(p, b)(0) to rounding (the orbits are what K says).
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table

SLUG = "gb_local"


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        "mu": [1.4, 1.7, 6.0],
        "Psi": [0.0, 0.5, 1.0, 1.5, 2.0],
        "eta": [1.0, 10.0],
        "n_curve": 41 if quick else 201,
        "n_orbits": 12 if quick else 24,
        "n_s": 60 if quick else 200,
    }


def run(ctx: RunContext) -> None:
    from crosscheck.theory import gb

    P = ctx.params
    alpha = P["alpha"]
    found: dict[tuple[int, str], dict] = {}
    sampled, stable_below = 0, 0
    for mu in P["mu"]:
        for Psi in P["Psi"]:
            for curve in gb.gb_manifold(mu, Psi, alpha, n=P["n_curve"]):
                for eta in P["eta"]:
                    Ks = gb.K(curve.theta, curve.varphi, Psi, curve.Theta, eta, mu, alpha)
                    types = np.atleast_1d(gb.gb_type(Ks))
                    for i, t in enumerate(types):
                        kind = gb.GBType(int(t))
                        sign = 1 if curve.Theta[i] > 0 else -1
                        sampled += 1
                        stable_below += int(sign < 0 and kind in (gb.GBType.STABLE_NODE, gb.GBType.STABLE_FOCUS))
                        if kind is gb.GBType.DEGENERATE or (sign, kind.name) in found:
                            continue
                        found[(sign, kind.name)] = {
                            "sign": sign,
                            "type": kind.name,
                            "mu": mu,
                            "Psi": Psi,
                            "eta": eta,
                            "theta": float(curve.theta[i]),
                            "varphi": float(curve.varphi[i]),
                            "Theta": float(curve.Theta[i]),
                            "K": Ks[i].tolist(),
                        }
    points = sorted(found.values(), key=lambda p: (-p["sign"], p["type"]))
    orbits = {k: [] for k in ("point", "orbit", "s", "p", "b")}
    worst = 0.0
    for j, p in enumerate(points):
        Km = np.array(p["K"])
        lam, vec = gb.eigen(Km)
        p.update(
            {
                "lambda": [[float(v.real), float(v.imag)] for v in lam],
                "e_plus": [float(v.real) for v in vec[:, 0]],
                "e_minus": [float(v.real) for v in vec[:, 1]],
                "complex": bool(np.any(np.abs(np.imag(lam)) > 0)),
            }
        )
        s, ys = gb.linear_orbits(Km, n_orbits=P["n_orbits"], n_s=P["n_s"])
        for k, y in enumerate(ys):
            # the orbit solves y' = K y: central differences against K y, relative to |K y|
            dy = np.gradient(y, s, axis=0)[2:-2]
            ky = (Km @ y.T).T[2:-2]
            worst = max(
                worst, float(np.max(np.linalg.norm(dy - ky, axis=1) / np.maximum(np.linalg.norm(ky, axis=1), 1e-300)))
            )
            for key, v in (
                ("point", np.full(s.size, j)),
                ("orbit", np.full(s.size, k)),
                ("s", s),
                ("p", y[:, 0]),
                ("b", y[:, 1]),
            ):
                orbits[key] += list(v)
    ctx.store.write_json("points", points)
    ctx.store.write_table("orbits", orbits)
    ctx.check(
        "Theorem 4.1: no stable node or focus with Theta < 0 on the sampled GB manifolds",
        stable_below == 0,
        value=stable_below,
        allowance=0,
        detail=f"{sampled} sampled points (mu in {P['mu']}, Psi in {P['Psi']}, eta in {P['eta']})",
    )
    # O(h^2) central differences with h = 6 / ((n_s - 1) |lambda|max): relative error ~ (h |lambda|)^2 / 6 <= 2e-3 at n_s = 60
    h_lam = 6.0 / (P["n_s"] - 1)
    ctx.check(
        "the drawn orbits solve (p, b)' = K (p, b) (central differences)",
        worst <= h_lam**2,
        value=worst,
        allowance=h_lam**2,
        detail="truncation (h |lambda|)^2 / 6 of central differences, allowance (h |lambda|)^2",
    )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, pb_eigenvectors, pb_orbits, pb_plane, plt

    points = ctx.store.read_json("points")
    orb = ctx.store.read_table("orbits")
    blocks = []
    for sign, fig_no, label in ((1, 14, "Theta > 0"), (-1, 15, "Theta < 0")):
        pts = [(j, p) for j, p in enumerate(points) if p["sign"] == sign]
        if not pts:
            continue
        fig, axes = plt.subplots(1, len(pts), figsize=(2.6 * len(pts), 2.8), squeeze=False)
        for ax, (j, p) in zip(axes[0], pts):
            pb_plane(ax, 1.0, 1.0)
            sel = orb["point"] == j
            pb_orbits(
                ax, orb["p"][sel], orb["b"][sel], orb["orbit"][sel], color="0.3"
            )  # arrows: increasing s (time runs with s where p > 0)
            if not p["complex"]:
                pb_eigenvectors(ax, p["e_plus"], p["e_minus"], (LINE_COLORS[0], LINE_COLORS[6]), lw=1.8)
            ax.set_title(p["type"].lower().replace("_", " "), fontsize=8)
            ax.text(
                0.03,
                0.03,
                f"$\\mu$={p['mu']:g}, $\\Psi$={p['Psi']:g}, $\\eta$={p['eta']:g}\n$\\theta$={p['theta']:.3f}, $\\Theta$={p['Theta']:.3f}",
                transform=ax.transAxes,
                fontsize=6,
                va="bottom",
            )
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_xlabel("p", fontsize=7)
            ax.set_ylabel("b", fontsize=7)
        cap = (
            f"Fig. {fig_no} computed (the paper sketches it): orbits of the linearised slipping flow (p, b)' = K (p, b) near GB points with {label}, one "
            "per type found on the sampled manifolds (alpha = 3), in the desingularised time s (arrows: increasing s). Eigenvectors of K blue (lambda_+) "
            "and red (lambda_-) where real. Shading as Fig. 3a: slipping yellow, lift-off orange, inconsistent lime, indeterminate purple. Not to scale."
        )
        blocks.append(ctx.figure(f"fig{fig_no}_local_dynamics", fig, cap, ["points.json", "orbits.csv"]))
    rows = [
        [
            ("Theta > 0" if p["sign"] > 0 else "Theta < 0"),
            p["type"].lower(),
            f"{p['mu']:g}",
            f"{p['Psi']:g}",
            f"{p['eta']:g}",
            f"{p['theta']:.5f}",
            f"{p['varphi']:.5f}",
            f"{p['Theta']:.5f}",
            ", ".join(f"{a:.4g}" + (f"{b:+.3g}i" if b else "") for a, b in p["lambda"]),
        ]
        for p in points
    ]
    blocks.append(
        Table(
            caption="The GB points drawn: the first of each (sign of Theta, type) on the sampled manifolds, with K's eigenvalues.",
            header=["side", "type", "mu", "Psi", "eta", "theta", "varphi", "Theta", "eigenvalues"],
            rows=rows,
            data=ctx.data("points.json"),
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="Local dynamics near the GB manifold",
    paper="Figs. 14 (fig:ppsThetapos) and 15 (fig:ppsThetaneg); eq. K, Theorem 4.1",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.theory.gb",),
)
