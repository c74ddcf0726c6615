"""Trajectories, analytic vs MuJoCo, through a lift-off and through a jam: theta, eta, varphi, normal force, tip height.

The starts are picked, not hand-tuned: a grid of slipping candidates is run
analytically (``crosscheck.theory.gb.slip_until_event``), joined for the jam by
seeded Corollary 4.2 states (``crosscheck.theory.corollary.corollary_states``: the
theory's jams off the planar section, where MuJoCo's own p can reach 0), and,
for each event kind, the candidates whose analytic event time is nearest a
target time are run in MuJoCo (``crosscheck.engines.get("mujoco").simulate``)
until one shows the same event; if none does, the first candidate is shown
anyway and the disagreement is reported.

Analytic curves end at the event (the slipping equations hold only until
then); the normal force there is F_z = -b/p (eq. FZ), unbounded as p -> 0 at a
jam.  MuJoCo's normal force chatters (a soft contact on a slipping tip); it is
drawn raw (light) and averaged over the classifier's window (dark), the
average being what matches -b/p.  Tip height: MuJoCo's lowest capsule point
(the analytic tip stays at 0 while slipping).
"""

from __future__ import annotations

import itertools

import numpy as np

from crosscheck.outcome import Outcome
from crosscheck.report.section import RenderContext, RunContext, Section, Table
from crosscheck.state import SlipState
from crosscheck.theory import analytic

SLUG = "mujoco_trajectories"

KINDS = {"liftoff": Outcome.LIFTOFF, "jam": Outcome.JAM}


def params(quick: bool) -> dict:
    return {
        "engine": "mujoco",
        "alpha": 3.0,
        "horizon": 2.0,
        "target_time": {"liftoff": 0.3, "jam": 0.3},
        "min_time": 0.05,
        "tries": 4 if quick else 8,
        "candidates": {
            "theta": [0.4, 0.8, 1.0] if quick else [0.4, 0.6, 0.8, 1.0, 1.2],
            "varphi": [-2.3, -1.3, -0.8] if quick else [-2.3, -1.9, -1.3, -0.8],
            "Theta": [0.0, 0.5, 0.9] if quick else [-0.5, 0.0, 0.5, 0.9],
            "Psi": [0.0, 1.0] if quick else [0.0, 1.0, 1.5],
            "eta": [1.0],
        },
        # lift-off below mu_P (no paradox to compete with it), jams above
        "mu": {"liftoff": [0.5, 0.8], "jam": [1.4, 2.0]},
        # Corollary 4.2 jam candidates per mu of "jam" (seeded by the section's generator)
        "corollary_states": 4 if quick else 8,
        "n_points": 800 if quick else 3000,
    }


def _window_mean(x: np.ndarray, w: int) -> np.ndarray:
    c = np.concatenate([[0.0], np.cumsum(x)])
    out = np.full(x.shape, np.nan)
    out[w - 1 :] = (c[w:] - c[:-w]) / w
    return out


def _candidates(P: dict, rng) -> dict:
    """Each kind's slipping candidate starts (state, mu, ``slip_until_event``'s result): the grid of
    ``P["candidates"]`` at the kind's mu, and for "jam" Corollary 4.2's states too."""
    from crosscheck.theory import gb
    from crosscheck.theory.corollary import corollary_states

    alpha, horizon = P["alpha"], P["horizon"]
    c = P["candidates"]
    cands = {}
    for kind in KINDS:
        cands[kind] = []
        for th, vp, Th, Ps, mu, eta in itertools.product(
            c["theta"], c["varphi"], c["Theta"], c["Psi"], P["mu"][kind], c["eta"]
        ):
            s = SlipState(theta=th, varphi=vp, Theta=Th, Psi=Ps, eta=eta)
            if analytic.mode(analytic.b(Ps, Th, th), analytic.p(th, vp, mu, alpha)) != analytic.Mode.SLIP:
                continue  # a start that is not slipping has its event at t = 0: nothing to follow
            cands[kind].append((s, mu, gb.slip_until_event(s, mu, alpha, t_max=horizon)))
    for mu in P["mu"]["jam"]:
        for s in corollary_states(mu, P["corollary_states"], rng, alpha=alpha, horizon=horizon)[0]:
            cands["jam"].append((s, mu, gb.slip_until_event(s, mu, alpha, t_max=horizon)))
    return cands


def _write_tables(store, kind: str, r, m, mu: float, alpha: float, n_points: int) -> int:
    """The tables of ``kind``'s run: the analytic trajectory r up to its event and MuJoCo's run m (``n_points``
    rows); returns the rows of MuJoCo's window mean of the normal force."""
    # analytic trajectory (up to the event), real time
    eta, varphi, _, Psi, theta, Theta = r.x.T
    b, p = analytic._b(Psi, Theta, theta), analytic._p(theta, varphi, mu, alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        Fz = -b / p
    store.write_table(
        f"analytic_{kind}",
        {
            "t": r.t,
            "theta": theta,
            "eta": eta,
            "varphi": varphi,
            "Psi": Psi,
            "Theta": Theta,
            "b": b,
            "p": p,
            "normal_force": Fz,
            "tip_height": np.zeros_like(theta),
        },
    )
    rec = m.record
    w = m.thresholds.window_rows(m.options.timestep)
    keep = np.unique(np.linspace(0, rec.t.size - 1, n_points).astype(int))
    store.write_table(
        f"mujoco_{kind}",
        {
            "t": rec.t[keep],
            "theta": rec.theta[keep],
            "eta": rec.eta[keep],
            "varphi": rec.varphi[keep],
            "Psi": rec.Psi[keep],
            "Theta": rec.Theta[keep],
            "normal_force": rec.normal_force[keep],
            "normal_force_window_mean": _window_mean(rec.normal_force, w)[keep],
            "tip_height": rec.gap[keep],
        },
    )
    return w


def run(ctx: RunContext) -> None:
    from crosscheck import engines
    from crosscheck.rod import Rod

    P = ctx.params
    alpha, horizon = P["alpha"], P["horizon"]
    cands = _candidates(P, ctx.rng)
    rod = Rod.scaled(alpha)
    runs = []
    for kind, outcome in KINDS.items():
        pool = [(s, mu, r) for s, mu, r in cands[kind] if r.outcome == outcome and r.time >= P["min_time"]]
        if not pool:
            raise RuntimeError(f"no slipping candidate reaches {outcome.name} analytically after t = {P['min_time']}")
        pool.sort(key=lambda x: abs(x[2].time - P["target_time"][kind]))
        chosen = None
        for s, mu, r in pool[: P["tries"]]:
            m = engines.get(P["engine"]).simulate(rod, s, mu, horizon=horizon)
            if chosen is None or m.outcome == outcome:
                chosen = (s, mu, r, m)
            if m.outcome == outcome:
                break
        s, mu, r, m = chosen
        w = _write_tables(ctx.store, kind, r, m, mu, alpha, P["n_points"])
        runs.append(
            {
                "kind": kind,
                "state": s.as_dict(),
                "mu": mu,
                "alpha": alpha,
                "analytic_outcome": r.outcome.name,
                "analytic_time": r.time,
                "analytic_reason": r.reason,
                "mujoco_outcome": m.outcome.name,
                "mujoco_time": m.event_time,
                "window": w * m.options.timestep,
                "mujoco_options": {
                    k: getattr(m.options, k)
                    for k in ("timestep", "radius", "timeconst", "dampratio", "friction_timeconst")
                },
                "candidates_tried": min(P["tries"], len(pool)),
                "agree": m.outcome == outcome,
            }
        )
        ctx.store.write_json("runs", runs)
    ctx.store.write_json(
        "candidates",
        {
            kind: {
                "n": len(cs),
                "analytic_outcomes": {o.name: sum(1 for *_, r in cs if r.outcome == o) for o in Outcome},
            }
            for kind, cs in cands.items()
        },
    )


def render(ctx: RenderContext) -> list:
    from crosscheck.report.plotting import LINE_COLORS, plt

    runs = ctx.store.read_json("runs")
    fig, axes = plt.subplots(5, len(runs), figsize=(5.2 * len(runs), 10), sharex="col", squeeze=False)
    rows = [
        ("theta", "$\\theta$"),
        ("eta", "$\\eta$"),
        ("varphi", "$\\varphi$"),
        ("normal_force", "$F_z$ [m g]"),
        ("tip_height", "tip height [l]"),
    ]
    for j, r in enumerate(runs):
        a = ctx.store.read_table(f"analytic_{r['kind']}")
        m = ctx.store.read_table(f"mujoco_{r['kind']}")
        m_time = r["mujoco_time"] if r["mujoco_time"] is not None and np.isfinite(r["mujoco_time"]) else 0.0
        t_view = min(float(m["t"][-1]), 2.5 * max(r["analytic_time"], m_time, 0.1))
        m = {k: v[m["t"] <= t_view] for k, v in m.items()}  # axes scale to what is shown
        m["varphi"] = np.unwrap(m["varphi"])  # MuJoCo's heading is wrapped to (-pi, pi]
        for i, (key, label) in enumerate(rows):
            ax = axes[i, j]
            if key == "normal_force":
                ax.plot(
                    m["t"], m["normal_force"], color=LINE_COLORS[1], lw=0.4, alpha=0.35, label="MuJoCo, raw (decimated)"
                )
                ax.plot(
                    m["t"],
                    m["normal_force_window_mean"],
                    color=LINE_COLORS[1],
                    lw=1.3,
                    label=f"MuJoCo, mean over {r['window']:.3g}",
                )
                fin = a["normal_force"][np.isfinite(a["normal_force"])]
                wm = m["normal_force_window_mean"]
                top = max(3.0, 1.5 * float(np.nanmax(wm))) if np.any(np.isfinite(wm)) else 3.0
                ax.set_ylim(-0.2, max(top, min(3 * top, 1.1 * float(fin.max()))) if fin.size else top)
            else:
                ax.plot(m["t"], m[key], color=LINE_COLORS[1], lw=1.2, label="MuJoCo")
            ax.plot(a["t"], a[key], color=LINE_COLORS[0], lw=1.6, ls="--", label="analytic (to its event)")
            for t_ev, col in ((r["analytic_time"], LINE_COLORS[0]), (r["mujoco_time"], LINE_COLORS[1])):
                if t_ev is not None and np.isfinite(t_ev):
                    ax.axvline(t_ev, color=col, lw=0.8, ls=":")
            ax.set_ylabel(label)
            if i == 0:
                s = r["state"]
                ax.set_title(
                    f"{r['kind']}: $\\theta$={s['theta']:g}, $\\varphi$={s['varphi']:g}, $\\Theta$={s['Theta']:g}, $\\Psi$={s['Psi']:g}, $\\eta$={s['eta']:g}, $\\mu$={r['mu']:g}",
                    fontsize=8,
                )
            if i == 3:
                ax.legend(fontsize=6, loc="upper left")
        axes[-1, j].set_xlabel("t (scaled)")
        axes[-1, j].set_xlim(0, t_view)
    cap = (
        "Trajectories through a lift-off (left) and a jam (right): MuJoCo (solid) against the analytic slipping solution (dashed, up to its event). "
        "Dotted verticals: analytic (blue) and MuJoCo (red) event times. The normal force is MuJoCo's raw contact force (light) and its window mean (dark) "
        "against the rigid F_z = -b/p (eq. FZ)."
    )
    blocks = [
        ctx.figure(
            "trajectories",
            fig,
            cap,
            [f"{w}_{r['kind']}.csv" for r in runs for w in ("analytic", "mujoco")] + ["runs.json"],
        )
    ]
    rows = [
        [
            r["kind"],
            ", ".join(f"{k}={v:g}" for k, v in r["state"].items()),
            f"{r['mu']:g}",
            f"{r['analytic_outcome']} at {r['analytic_time']:.4g}",
            f"{r['mujoco_outcome']} at {r['mujoco_time']:.4g}"
            if r["mujoco_time"] is not None and np.isfinite(r["mujoco_time"])
            else r["mujoco_outcome"],
            "yes" if r["agree"] else "NO",
        ]
        for r in runs
    ]
    blocks.append(
        Table(
            caption="The runs drawn: start, analytic event, MuJoCo outcome.",
            header=["run", "start", "mu", "analytic", "MuJoCo", "same event"],
            rows=rows,
            data=ctx.data("runs.json"),
            row_class=["ok" if r["agree"] else "fail" for r in runs],
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="MuJoCo vs analytic: trajectories through a lift-off and a jam",
    paper="eqs. polareqs_varphi, FZ, f",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.engines.mujoco.engine", "crosscheck.theory.gb"),
)
