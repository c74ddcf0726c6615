"""Fig. 3a and the slices of the 3D pictures (Figs. 3b, 4, 5, 6 and 7 of section 3.3): the four LCP modes.

b (eq. b) does not depend on varphi and p (eq. p) does not depend on Theta or
Psi, so the paper's 3D pictures in (theta, varphi, Theta) are fixed by two
plane sections, which is what is drawn for each Psi:

* (theta, Theta) at varphi = -pi/2, Theta >= 0: there p = 0 is the two lines
  theta = theta_1, theta_2 and b = 0 the curve Theta^2 = 1/sin theta - Psi^2 cos^2 theta
  (the paper's 2D sections, Figs. 3a, 5a, 6a, 7a);
* (theta, varphi) at Theta = 0: b is smallest at Theta = 0, so this section
  shows every mode that exists at Theta = 0, and inconsistency exists
  anywhere (for some Theta) exactly when it exists here.

Psi enters b only through Psi^2: every map holds for +Psi and -Psi.

Checks: the paper's statements about each Psi of section 3.3 (Psi = 1.56: no
lift-off at Theta = 0; 1.7: lift-off at Theta = 0; 2.2: indeterminacy at
Theta = 0; 5: no inconsistent region), read off the computed maps, and the
kinematic case of ``crosscheck.theory.critical.kinematic_case`` against the modes
the maps show.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import analytic, critical
from crosscheck.theory.analytic import Mode

SLUG = "mode_maps"

#: Section 3.3's statements about the modes at Theta = 0, as (Psi, predicate name, text).
PAPER_STATEMENTS = {
    1.56: ("no_liftoff_at_Theta0", "Psi = 1.56 < Psi_L: no lift-off at Theta = 0 (Fig. 4a)"),
    1.7: ("liftoff_at_Theta0", "Psi = 1.7 > Psi_L: lift-off possible at Theta = 0 (Fig. 4b)"),
    2.2: ("indeterminate_at_Theta0", "Psi = 2.2: indeterminacy possible at Theta = 0 (Fig. 4c)"),
    5.0: ("no_inconsistent", "Psi = 5: the inconsistent region has ceased to exist (Fig. 4d)"),
}

#: Modes at Theta = 0 and anywhere that define each kinematic case of mechanism II (section 3.4).
CASE_MODES = {
    3: dict(liftoff_at_Theta0=False, indeterminate_at_Theta0=False, inconsistent=True),
    4: dict(liftoff_at_Theta0=True, indeterminate_at_Theta0=False, inconsistent=True),
    6: dict(liftoff_at_Theta0=True, indeterminate_at_Theta0=True, inconsistent=True),
    7: dict(inconsistent=False),
}


def params(quick: bool) -> dict:
    n = 120 if quick else 360
    return {
        "mu": 1.4,
        "alpha": 3.0,
        "Psi": [0.0, 1.56, 1.7, 2.2, 5.0],
        "Psi_named": ["Psi_L", "Psi_1", "Psi_2"],
        "Theta_max": 2.2,
        "n_theta": n,
        "n_Theta": n,
        "n_varphi": n,
        "n_curve": 1000 if quick else 4000,
    }


def _Theta_on_b0(Psi, theta):
    # b = 0 (eq. b): Theta^2 = 1/sin theta - Psi^2 cos^2 theta; NaN where b > 0 already at Theta = 0
    t2 = 1.0 / np.sin(theta) - Psi**2 * np.cos(theta) ** 2
    with np.errstate(invalid="ignore"):
        return np.where(t2 >= 0, np.sqrt(np.maximum(t2, 0.0)), np.nan)


def run(ctx: RunContext) -> None:
    P = ctx.params
    mu, alpha = P["mu"], P["alpha"]
    cv = critical.critical_values(mu, alpha)
    ctx.store.write_json("critical_values", cv)
    named = {"Psi_L": cv.Psi_L, "Psi_1": cv.Psi_1, "Psi_2": cv.Psi_2}
    slices = sorted([(float(v), f"{v:g}") for v in P["Psi"]] + [(named[k], k) for k in P["Psi_named"]])
    theta = cell_centres(0.0, np.pi / 2, P["n_theta"])
    Theta = cell_centres(0.0, P["Theta_max"], P["n_Theta"])
    varphi = cell_centres(-np.pi, 0.0, P["n_varphi"])
    p_planar = analytic.p(theta, -np.pi / 2, mu, alpha)
    p_plane = analytic.p(theta[None, :], varphi[:, None], mu, alpha)
    theta_curve = cell_centres(0.0, np.pi / 2, P["n_curve"])  # b = 0 drawn finer than the maps
    curves = {"theta": theta_curve}
    summary = []
    for i, (Psi, label) in enumerate(ctx.progress(slices, desc="mode maps")):
        a = analytic.mode(analytic.b(Psi, Theta[:, None], theta[None, :]), p_planar[None, :])
        ctx.store.write_grid(f"theta_Theta_{i}", ("theta", theta), ("Theta", Theta), ("mode", a))
        b0 = analytic.b(Psi, 0.0, theta)
        m = analytic.mode(np.broadcast_to(b0[None, :], p_plane.shape), p_plane)
        ctx.store.write_grid(f"theta_varphi_{i}", ("theta", theta), ("varphi", varphi), ("mode", m))
        curves[f"Theta_b0_{i}"] = _Theta_on_b0(Psi, theta_curve)
        present = {Mode(k).name for k in np.unique(m)}
        summary.append(
            {
                "index": i,
                "label": label,
                "Psi": Psi,
                "kinematic_case": critical.kinematic_case(mu, Psi, alpha),
                "modes_theta_Theta": sorted(Mode(k).name for k in np.unique(a)),
                "modes_at_Theta0": sorted(present),
                "liftoff_at_Theta0": "LIFTOFF" in present,
                "indeterminate_at_Theta0": "INDETERMINATE" in present,
                "inconsistent": "INCONSISTENT" in present,
            }
        )
        ctx.store.write_json("slices", summary)
    ctx.store.write_table("b_zero", curves)
    th = np.linspace(cv.theta_1, cv.theta_2, 201)
    vm, vp = critical.varphi_pm(th, mu, alpha)
    ctx.store.write_table("p_zero", {"theta": th, "varphi_minus": vm, "varphi_plus": vp})
    Theta_P = float(np.sqrt(1.0 / np.sin(cv.theta_1)))
    Theta_Q = float(np.sqrt(1.0 / np.sin(cv.theta_2)))
    ctx.store.write_json(
        "gb_points_planar",
        {"P+": {"theta": cv.theta_1, "Theta": Theta_P}, "Q+": {"theta": cv.theta_2, "Theta": Theta_Q}},
    )

    for s in summary:
        if s["Psi"] in PAPER_STATEMENTS:
            key, text = PAPER_STATEMENTS[s["Psi"]]
            got = {
                "no_liftoff_at_Theta0": not s["liftoff_at_Theta0"],
                "liftoff_at_Theta0": s["liftoff_at_Theta0"],
                "indeterminate_at_Theta0": s["indeterminate_at_Theta0"],
                "no_inconsistent": not s["inconsistent"],
            }[key]
            ctx.check(
                f"paper: {text}", got, detail=f"modes at Theta = 0 on the grid: {', '.join(s['modes_at_Theta0'])}"
            )
        want = CASE_MODES.get(s["kinematic_case"])
        if want is not None and s["label"] not in named:  # on a threshold the case boundary is measure-zero on a grid
            ok = all(s[k] == v for k, v in want.items())
            ctx.check(
                f"Psi = {s['label']}: kinematic case {s['kinematic_case']} matches the modes on the maps",
                ok,
                detail=", ".join(f"{k}={s[k]}" for k in want),
            )
    a0 = ctx.store.read_grid("theta_Theta_0")[2]
    ctx.check(
        "Psi = 0 (Fig. 3a): all four modes occur in the (theta, Theta) section",
        len(np.unique(a0)) == 4,
        detail=", ".join(summary[0]["modes_theta_Theta"]),
    )


def render(ctx: RenderContext) -> list:
    from matplotlib.lines import Line2D

    from crosscheck.report.plotting import B_COLOR, P_COLOR, mode_image, mode_legend, plt

    cv = ctx.store.read_json("critical_values")
    slices = ctx.store.read_json("slices")
    curves = ctx.store.read_table("b_zero")
    gbp = ctx.store.read_json("gb_points_planar")
    Theta_max = ctx.params["Theta_max"]
    blocks = []
    lines = [Line2D([], [], color=B_COLOR, label="b = 0"), Line2D([], [], color=P_COLOR, label="p = 0")]

    def planar(ax, i, *, labels=True):
        x, y, z, _ = ctx.store.read_grid(f"theta_Theta_{i}")
        mode_image(ax, x, y, z)
        ax.plot(curves["theta"], curves[f"Theta_b0_{i}"], color=B_COLOR, lw=1.2)
        for t in (cv["theta_1"], cv["theta_2"]):
            ax.axvline(t, color=P_COLOR, lw=1.2)
        ax.set_xlim(0, np.pi / 2)
        ax.set_ylim(0, Theta_max)
        if labels:
            ax.set_xlabel("$\\theta$")
            ax.set_ylabel("$\\Theta$")

    zero = next(s for s in slices if s["Psi"] == 0.0)
    fig, ax = plt.subplots(figsize=(5.6, 4.4))
    planar(ax, zero["index"])
    for name, pt in gbp.items():
        ax.plot(pt["theta"], pt["Theta"], "ko", ms=5)
        ax.annotate(
            name,
            (pt["theta"], pt["Theta"]),
            textcoords="offset points",
            xytext=(-16 if name == "P+" else 6, 6),
            fontsize=10,
        )
    ax.set_xticks(
        [0, np.pi / 4, cv["theta_1"], cv["theta_2"], np.pi / 2],
        ["0", "$\\pi/4$", "$\\theta_1$", "$\\theta_2$", "$\\pi/2$"],
    )
    ax.set_title(f"$\\varphi=-\\pi/2$, $\\Psi$ = 0, $\\alpha$ = {cv['alpha']:g}, $\\mu$ = {cv['mu']:g}")
    mode_legend(ax, extra=lines, loc="upper left", fontsize=7)
    blocks.append(
        ctx.figure(
            "fig3a_modes_planar",
            fig,
            f"Fig. 3a recomputed: the four modes of the LCP (slipping yellow, lift-off orange, inconsistent lime, indeterminate purple) "
            f"in (theta, Theta) for the planar problem (varphi = -pi/2, Psi = 0). b = 0 (red) and p = 0 (blue) meet at "
            f"P+ = ({gbp['P+']['theta']:.4f}, {gbp['P+']['Theta']:.4f}) and Q+ = ({gbp['Q+']['theta']:.4f}, {gbp['Q+']['Theta']:.4f}), Theta = sqrt(csc theta).",
            [f"theta_Theta_{zero['index']}.json", "b_zero.csv", "gb_points_planar.json", "critical_values.json"],
        )
    )

    n = len(slices)
    cols = 4
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 2.5 * rows), sharex=True, sharey=True, squeeze=False)
    for ax, s in zip(axes.flat, slices):
        planar(ax, s["index"], labels=False)
        ax.set_title(_slice_title(s))
    for ax in axes[-1]:
        ax.set_xlabel("$\\theta$")
    for ax in axes[:, 0]:
        ax.set_ylabel("$\\Theta$")
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    mode_legend(axes.flat[0], extra=lines, loc="upper left", fontsize=6)
    blocks.append(
        ctx.figure(
            "slices_theta_Theta",
            fig,
            f"Sections at varphi = -pi/2 of the 3D pictures of section 3.3 (Figs. 3b, 4, 5a, 6a, 7a) as Psi grows, alpha = {cv['alpha']:g}, mu = {cv['mu']:g}: "
            f"lift-off reaches Theta = 0 from Psi_L = {cv['Psi_L']:.4f}, b = 0 touches p = 0 at theta_1 at Psi_1 = {cv['Psi_1']:.4f} and at theta_2 at "
            f"Psi_2 = {cv['Psi_2']:.4f}. Each panel holds for +Psi and -Psi (b depends on Psi^2).",
            [f"theta_Theta_{s['index']}.json" for s in slices] + ["b_zero.csv", "slices.json"],
        )
    )

    blocks.append(_theta_varphi_figure(ctx, slices, rows, cols))
    blocks.append(_modes_table(ctx, slices))
    return blocks


def _slice_title(s: dict) -> str:
    """A slice's panel title: its Psi (a critical value by name) and its kinematic case."""
    if s["label"].startswith("Psi_"):
        return f"$\\Psi_{{{s['label'][4:]}}}$ = $\\pm${s['Psi']:.4f} (case {s['kinematic_case']})"
    sign = "" if s["Psi"] == 0 else "$\\pm$"
    return f"$\\Psi$ = {sign}{s['label']} (case {s['kinematic_case']})"


def _theta_varphi_figure(ctx: RenderContext, slices: list, rows: int, cols: int):
    """The sections at Theta = 0 of the slices, with p = 0."""
    from crosscheck.report.plotting import P_COLOR, mode_image, plt

    n = len(slices)
    pz = ctx.store.read_table("p_zero")
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 2.5 * rows), sharex=True, sharey=True, squeeze=False)
    for ax, s in zip(axes.flat, slices):
        x, y, z, _ = ctx.store.read_grid(f"theta_varphi_{s['index']}")
        mode_image(ax, x, y, z)
        ax.plot(pz["theta"], pz["varphi_minus"], color=P_COLOR, lw=1.0)
        ax.plot(pz["theta"], pz["varphi_plus"], color=P_COLOR, lw=1.0)
        ax.set_title(_slice_title(s))
        ax.set_xlim(0, np.pi / 2)
        ax.set_ylim(-np.pi, 0)
        ax.set_yticks([-np.pi, -np.pi / 2, 0], ["$-\\pi$", "$-\\pi/2$", "0"])
    for ax in axes[-1]:
        ax.set_xlabel("$\\theta$")
    for ax in axes[:, 0]:
        ax.set_ylabel("$\\varphi$")
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return ctx.figure(
        "slices_theta_varphi",
        fig,
        "Sections at Theta = 0 of the same 3D pictures: every mode possible with no polar motion. The p = 0 cylinder of Fig. 3b is the "
        "boundary of the lime/purple disc; the lift-off band (orange) appears at Psi_L, enters the disc (indeterminate, purple) past Psi_1 "
        "and covers it past Psi_2 (no inconsistent state left).",
        [f"theta_varphi_{s['index']}.json" for s in slices] + ["p_zero.csv", "slices.json"],
    )


def _modes_table(ctx: RenderContext, slices: list) -> Table:
    """The modes at Theta = 0 and the kinematic case of each slice."""
    rows_t = [
        [
            s["label"],
            f"{s['Psi']:.4f}",
            str(s["kinematic_case"]),
            ", ".join(m.lower() for m in s["modes_at_Theta0"]),
            "yes" if s["inconsistent"] else "no",
        ]
        for s in slices
    ]
    return Table(
        caption="Modes present at Theta = 0 (any theta, varphi) for each Psi, and the kinematic case of section 3.4 (crosscheck.theory.critical.kinematic_case).",
        header=["Psi", "value", "case", "modes at Theta = 0", "inconsistent exists"],
        rows=rows_t,
        data=ctx.data("slices.json"),
    )


SECTION = Section(
    slug=SLUG,
    title="The four modes: Fig. 3a and the slices of the 3D picture",
    paper="Figs. 3a, 3b, 4, 5, 6, 7 (section 3.3); eqs. b, p, psil, psi1, psi2",
    params=params,
    run=run,
    render=render,
)
