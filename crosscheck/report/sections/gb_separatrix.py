"""Fig. 20 (fig:my_ugly_simulations): two slipping trajectories near the separatrix, and the leading eigenvector along the GB manifold.

The two initial conditions of the figure (``crosscheck.theory.paper.FIG20_INITIAL_CONDITIONS``,
alpha = 3, mu = 1.4) are run to their first event by
``crosscheck.theory.gb.slip_until_event`` (the desingularised flow eq. f, time s with
eta p ds = dt, real time recovered); the orbit is then sampled densely by
integrating the same field ``crosscheck.theory.gb.slip_rhs`` over the run's s
interval.  Along the GB manifold at Psi = 0 (Theta > 0) the eigenvector of the
leading eigenvalue lambda_+ of K (eq. K), lifted to state space as A e_+
(eqs. matA, jacobian: J A e = A K e), gives the surface the paper draws in
green; the separatrix between orbits that reach p = 0 and orbits that lift
off is tangent to it.

Check: each orbit sampled densely ends where ``slip_until_event`` reports
its event (same field, same interval: a consistency check of the dense
re-integration used for the figure).
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.theory import analytic
from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS

SLUG = "gb_separatrix"


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        "mu": 1.4,
        "t_max": 10.0,
        "n_dense": 400 if quick else 2000,
        "n_manifold": 101 if quick else 401,
        "eigen_theta_range": [1.0, 1.2],
        "eigen_length": 0.08,
    }


def run(ctx: RunContext) -> None:
    from scipy.integrate import solve_ivp

    from crosscheck.state import SlipState
    from crosscheck.theory import gb

    P = ctx.params
    mu, alpha = P["mu"], P["alpha"]
    summary = []
    cols = {k: [] for k in ("run", "s", "eta", "varphi", "Psi", "theta", "Theta", "p", "b")}
    for i, ic in enumerate(FIG20_INITIAL_CONDITIONS):
        state = SlipState(**ic)
        res = gb.slip_until_event(state, mu, alpha, t_max=P["t_max"])
        s_end = float(res.s[-1])
        x0 = np.array([state.eta, state.varphi, state.psi, state.Psi, state.theta, state.Theta])
        sol = solve_ivp(
            lambda s, x: gb.slip_rhs(x, mu, alpha),
            (0.0, s_end),
            x0,
            method="DOP853",
            rtol=1e-11,
            atol=1e-13,
            t_eval=np.linspace(0.0, s_end, P["n_dense"]),
        )
        X = sol.y.T
        eta, varphi, _, Psi, theta, Theta = X.T
        for k, v in (
            ("run", np.full(len(eta), i)),
            ("s", sol.t),
            ("eta", eta),
            ("varphi", varphi),
            ("Psi", Psi),
            ("theta", theta),
            ("Theta", Theta),
            ("p", analytic._p(theta, varphi, mu, alpha)),
            ("b", analytic._b(Psi, Theta, theta)),
        ):
            cols[k] += list(v)
        end = res.x[-1]
        gap = float(np.max(np.abs(X[-1] - end)))
        summary.append(
            {
                "run": i,
                "initial": ic,
                "outcome": res.outcome.name,
                "reason": res.reason,
                "time": res.time,
                "s_end": s_end,
                "b_start": float(analytic.b(state.Psi, state.Theta, state.theta)),
                "p_start": float(analytic.p(state.theta, state.varphi, mu, alpha)),
                "b_end": res.b,
                "p_end": res.p,
                "state_end": res.state.as_dict(),
                "dense_end_gap": gap,
            }
        )
        ctx.store.write_json("runs", summary)
        ctx.check(
            f"run {i + 1}: the dense re-integration ends at the event of slip_until_event",
            gap <= 1e-6,
            value=gap,
            allowance=1e-6,
            detail=f"{res.outcome.name} ({res.reason}) at t = {res.time:.6g}",
        )
    ctx.store.write_table("orbits", cols)

    # leading eigenvector along the GB manifold (Psi = 0, Theta > 0), lifted to state space by A
    eta_ref = float(np.mean([ic["eta"] for ic in FIG20_INITIAL_CONDITIONS]))
    (curve,) = [c for c in gb.gb_manifold(mu, 0.0, alpha, n=P["n_manifold"]) if c.sign > 0]
    x = curve.x(eta_ref)
    lam, vec = gb.eigen(curve.K(eta_ref))
    A = gb.matrix_A(x, mu, alpha)  # (n, 6, 2)
    lead = np.real(np.einsum("nij,nj->ni", A, vec[:, :, 0]))  # A e_+ for lambda_+ (larger real part)
    d = lead[:, [4, 1, 5]]  # (theta, varphi, Theta) components
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    ctx.store.write_table(
        "manifold_eigen",
        {
            "theta": curve.theta,
            "varphi": curve.varphi,
            "Theta": curve.Theta,
            "lambda_plus": lam[:, 0].real,
            "d_theta": d[:, 0],
            "d_varphi": d[:, 1],
            "d_Theta": d[:, 2],
            "e_plus_p": vec[:, 0, 0].real,
            "e_plus_b": vec[:, 1, 0].real,
        },
    )
    ctx.store.write_json("eigen_eta", {"eta": eta_ref})


def render(ctx: RenderContext) -> list:
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    from crosscheck.report.plotting import LINE_COLORS, pb_plane, plt

    P = ctx.params
    runs = ctx.store.read_json("runs")
    o = ctx.store.read_table("orbits")
    m = ctx.store.read_table("manifold_eigen")
    fig = plt.figure(figsize=(11, 4.6))
    ax = fig.add_subplot(1, 2, 1)
    pb_plane(ax, 0.02, 0.25)
    for r in runs:
        s = o["run"] == r["run"]
        ax.plot(
            o["p"][s],
            o["b"][s],
            color=LINE_COLORS[r["run"]],
            lw=1.5,
            label=f"run {r['run'] + 1}: {r['outcome'].lower()} at t = {r['time']:.3g}",
        )
        ax.plot(o["p"][s][:1], o["b"][s][:1], "o", color=LINE_COLORS[r["run"]], ms=4)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title("(a) orbits in the (p, b) plane")
    ax3 = fig.add_subplot(1, 2, 2, projection="3d")
    ax3.plot(m["theta"], m["varphi"], m["Theta"], color="k", lw=1.0, label="GB manifold, $\\Psi$ = 0, $\\Theta$ > 0")
    lo, hi = P["eigen_theta_range"]
    sel = (m["theta"] >= lo) & (m["theta"] <= hi) & (m["varphi"] < -np.pi / 2)  # the branch the orbits start near
    L = P["eigen_length"]
    base = np.stack([m["theta"][sel], m["varphi"][sel], m["Theta"][sel]], axis=1)
    dirs = np.stack([m["d_theta"][sel], m["d_varphi"][sel], m["d_Theta"][sel]], axis=1)
    ax3.add_collection3d(
        Line3DCollection(np.stack([base - L * dirs, base + L * dirs], axis=1), colors=[(0.2, 0.7, 0.2, 0.6)], lw=1.0)
    )
    for r in runs:
        s = o["run"] == r["run"]
        ax3.plot(o["theta"][s], o["varphi"][s], o["Theta"][s], color=LINE_COLORS[r["run"]], lw=1.8)
        ax3.scatter(o["theta"][s][:1], o["varphi"][s][:1], o["Theta"][s][:1], color=LINE_COLORS[r["run"]], s=10)
    ax3.set_xlabel("$\\theta$")
    ax3.set_ylabel("$\\varphi$")
    ax3.set_zlabel("$\\Theta$")
    ax3.view_init(elev=20, azim=-70)
    ax3.set_title("(b) orbits, GB manifold and leading eigenvector (green)")
    eta = ctx.store.read_json("eigen_eta")["eta"]
    cap = (
        f"Fig. 20 recomputed (fig:my_ugly_simulations): the two initial conditions of the paper (alpha = {P['alpha']:g}, mu = {P['mu']:g}) integrated with the "
        "desingularised flow (eq. f) to their first event (crosscheck.theory.gb.slip_until_event). (a) the orbits in the (p, b) plane near the GB manifold "
        "(shading as Fig. 3a); (b) the orbits in (theta, varphi, Theta) with the GB manifold at Psi = 0 and, in green, the direction A e_+ of the leading "
        f"eigenvalue of K (eq. K, eta = {eta:.3g}) at its points: the separatrix between orbits that reach p = 0 and orbits that lift off is tangent to it."
    )
    blocks = [ctx.figure("fig20_separatrix", fig, cap, ["orbits.csv", "manifold_eigen.csv", "runs.json"])]
    rows = []
    for r in runs:
        ic = r["initial"]
        rows.append(
            [
                str(r["run"] + 1),
                ", ".join(f"{k}={v:g}" for k, v in ic.items()),
                f"{r['b_start']:.4f}",
                f"{r['p_start']:.4f}",
                r["outcome"],
                r["reason"],
                f"{r['time']:.6g}",
                f"{r['b_end']:.4f}",
                f"{r['p_end']:.2e}",
            ]
        )
    blocks.append(
        Table(
            caption="The runs: start (slipping: b < 0 < p), first event and where it happened. Nearby starts end on opposite sides of the separatrix.",
            header=["run", "initial condition", "b(0)", "p(0)", "outcome", "event", "t", "b at event", "p at event"],
            rows=rows,
            data=ctx.data("runs.json"),
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="Separatrix trajectories near the GB manifold",
    paper="Fig. 20 (fig:my_ugly_simulations); eqs. f, matA, K",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.theory.gb", "crosscheck.theory.slipping"),
)
