"""The rigid engine (Pinocchio's NCP solvers) through lift-off onset and jams: onset per timestep, jams and their aftermath against the IWC, a trajectory through a jam.

* Lift-off onset at theta_L, Theta = 0, varphi = -pi/2
  (``crosscheck.studies.onset``): a rigid contact decides lift-off in one
  step, so the onset should be Psi_L at every timestep.
* Jams: Corollary 4.2 states (``crosscheck.theory.corollary.corollary_states``)
  and planar impasses (p < 0, b < 0 at t = 0) through
  ``crosscheck.engines.pinocchio.studies.rigid.jam_aftermath``: does the engine jam, when,
  with which impulse, and does its state one row after the jam tend to the
  impact without collision (``crosscheck.theory.impact.darboux_keller.impact``) as dt -> 0?
* A trajectory through a jam: the analytic slip (``slip_until_event``) and
  its IWC (``crosscheck.theory.impact.continuation``), the rigid engine and MuJoCo from the same
  Corollary 4.2 state, on one plot.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text

SLUG = "rigid_engine"

TEX = {"theta": r"$\theta$", "eta": r"$\eta$", "Theta": r"$\Theta$", "Psi": r"$\Psi$"}


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        "onset_mu": [0.5, 1.4],
        "onset_timesteps": [3e-3, 1e-3] if quick else [3e-3, 1e-3, 3e-4, 1e-4],
        "jam_mu": [1.4, 1.7, 6.0],
        "jam_states": 2 if quick else 12,
        "jam_timesteps": [1e-3, 3e-4] if quick else [1e-3, 3e-4, 1e-4],
        "impasses": [[1.4, 0.5], [1.4, -0.3], [2.0, 0.5]],
        "trajectory": {"mu": 1.7, "after": 0.3, "mujoco_timestep": 3e-4},
    }


def run(ctx: RunContext) -> None:
    from crosscheck import engines
    from crosscheck.engines.pinocchio.studies import rigid
    from crosscheck.rod import Rod
    from crosscheck.studies.onset import liftoff_onset
    from crosscheck.theory.corollary import corollary_states
    from crosscheck.theory.critical import Psi_L
    from crosscheck.theory.impact import continuation as hybrid

    P = ctx.params
    rod = Rod.scaled(P["alpha"])
    rows = {"mu": [], "timestep": [], "onset": [], "onset_minus_Psi_L": [], "resolution": []}
    for mu in ctx.progress(P["onset_mu"], desc="rigid onset"):
        for dt in P["onset_timesteps"]:
            onset, res = liftoff_onset(
                rod, mu, engine="pinocchio", timestep=dt, rounds=6, n=33, half_width=1e-3, horizon=12 * dt
            )
            for k, v in zip(rows, (mu, dt, onset, onset - float(Psi_L), res)):
                rows[k].append(v)
    ctx.store.write_table("onset", rows)
    ok = all(abs(d) <= 1e-9 + r for d, r in zip(rows["onset_minus_Psi_L"], rows["resolution"]))
    ctx.check(
        "rigid lift-off onset = Psi_L at every timestep",
        ok,
        value=max(abs(d) for d in rows["onset_minus_Psi_L"]),
        allowance=1e-9,
        detail="crosscheck.engines.pinocchio.tolerances.RIGID_LIFTOFF_ONSET",
    )

    jams = {}
    for mu in ctx.progress(P["jam_mu"], desc="rigid jams"):
        states, t_jam, _ = corollary_states(mu, P["jam_states"], ctx.rng, alpha=P["alpha"])
        a = rigid.jam_aftermath(rod, states, mu, timesteps=P["jam_timesteps"])
        jams[str(mu)] = {**a.as_dict(), "t_jam": t_jam.tolist()}
        ctx.store.write_json("jams", jams)
    impasses = []
    for mu, Theta in P["impasses"]:
        a = rigid.jam_aftermath(rod, [rigid.planar_impasse(mu, Theta, P["alpha"])], mu, timesteps=P["jam_timesteps"])
        impasses.append({"mu": mu, "Theta": Theta, **a.as_dict()})
    ctx.store.write_json("impasses", impasses)
    orders = [x["orders"][0] for x in impasses]
    ctx.check(
        "planar impasse: post-jam rates -> IWC at first order",
        all(abs(o - 1.0) <= 0.05 for o in orders),
        value=orders,
        allowance="1 +- 0.05",
        detail="crosscheck.engines.pinocchio.tolerances.RIGID_IWC_ORDER",
    )

    # one trajectory through a jam: the first Corollary 4.2 state at the trajectory's mu
    T = P["trajectory"]
    (s,), (t_jam,), _ = corollary_states(T["mu"], 1, ctx.rng, alpha=P["alpha"])
    horizon = float(t_jam) + T["after"]
    h = hybrid.run(s, T["mu"], P["alpha"], horizon=horizon)
    seg = h.segments[0]
    x = seg.slip.x
    from crosscheck.theory.slipping import X_STATE

    col = {k: x[:, i] for i, k in enumerate(X_STATE)}
    ctx.store.write_table(
        "trajectory_analytic",
        {
            "t": seg.slip.t,
            "theta": col["theta"],
            "eta": col["eta"],
            "Theta": col["Theta"],
            "Psi": col["Psi"],
            "varphi": col["varphi"],
        },
    )
    traj = {"state": s.as_dict(), "mu": T["mu"], "t_jam": float(t_jam), "hybrid": h.as_dict()}
    ctx.store.write_json("trajectory", traj)
    for name, opts in (("pinocchio", {}), ("mujoco", {"timestep": T["mujoco_timestep"]})):
        r = engines.get(name).simulate(rod, s, T["mu"], horizon=horizon, **opts)
        R = r.record
        every = max(1, len(R) // 3000)
        ctx.store.write_table(
            f"trajectory_{name}",
            {
                "t": R.t[::every],
                "theta": R.theta[::every],
                "eta": R.eta[::every],
                "Theta": R.Theta[::every],
                "Psi": R.Psi[::every],
                "normal_force": R.normal_force[::every],
            },
        )
        info = {
            "outcome": r.outcome.name,
            "event_time": r.event_time,
            "jam_impulse": r.jam_impulse,
            "options": r.options.as_dict(),
        }
        if r.solver is not None:
            info["solver"] = {
                k: getattr(r.solver, k)
                for k in ("contact_steps", "max_iterations", "mean_iterations", "unconverged_steps")
            }
        traj[name] = info
        ctx.store.write_json("trajectory", traj)


def _fmt(x, spec=".3g") -> str:
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, spec)


def render(ctx: RenderContext) -> list:
    return [_onset_table(ctx), *_jam_blocks(ctx), *_trajectory_blocks(ctx)]


def _onset_table(ctx: RenderContext) -> Table:
    """The rigid lift-off onset against Psi_L, per timestep."""
    on = ctx.store.read_table("onset")
    return Table(
        caption="Rigid lift-off onset at theta_L, Theta = 0, varphi = -pi/2: the smallest Psi that lifts off at t = 0, minus Psi_L "
        "(eq. psil), per timestep; resolution is the bisection's last grid spacing. A rigid contact has no soft-contact delay.",
        header=["mu", "timestep", "onset - Psi_L", "resolution"],
        rows=[
            [
                f"{on['mu'][i]:g}",
                f"{on['timestep'][i]:g}",
                f"{on['onset_minus_Psi_L'][i]:.2e}",
                f"{on['resolution'][i]:.1e}",
            ]
            for i in range(len(on["mu"]))
        ],
        data=ctx.data("onset.csv"),
    )


def _jam_blocks(ctx: RenderContext) -> list:
    """Jams against the theory: the errors' figure, the Corollary 4.2 table and the planar impasses' table."""
    from crosscheck.report.plotting import LINE_COLORS, plt

    blocks: list = []
    jams = ctx.store.read_json("jams")
    rows = []
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    for k, (mu, j) in enumerate(jams.items()):
        dts = np.asarray(j["timesteps"])
        jammed = np.asarray(j["jammed"], bool)
        te, re, ie = (np.asarray(j[n], float) for n in ("time_error", "rate_error", "impulse_error"))
        lead = np.asarray(j.get("stop_lead") or [np.nan] * jammed.shape[1], float)
        admits = f"{int(np.isfinite(lead).sum())} of {len(lead)}" + (
            f", median {np.nanmedian(lead):.3g}" if np.isfinite(lead).any() else ""
        )
        for i, dt in enumerate(dts):
            n = jammed.shape[1]
            rows.append(
                [
                    mu,
                    f"{dt:g}",
                    f"{int(jammed[i].sum())} of {n}",
                    _fmt(float(np.nanmedian(np.abs(te[i]))) if jammed[i].any() else None),
                    _fmt(float(np.nanmax(np.abs(te[i]))) if jammed[i].any() else None),
                    _fmt(float(np.nanmedian(np.abs(ie[i]))) if jammed[i].any() else None),
                    _fmt(float(np.nanmedian(re[i])) if jammed[i].any() else None),
                    admits if i == 0 else "",
                ]
            )
        med_t = [np.nanmedian(np.abs(te[i])) if jammed[i].any() else np.nan for i in range(len(dts))]
        med_r = [np.nanmedian(re[i]) if jammed[i].any() else np.nan for i in range(len(dts))]
        ax[0].loglog(dts, med_t, "o-", color=LINE_COLORS[k % 7], label=f"Corollary 4.2, $\\mu$ = {mu}")
        ax[1].loglog(dts, med_r, "o-", color=LINE_COLORS[k % 7], label=f"Corollary 4.2, $\\mu$ = {mu}")
    imp = ctx.store.read_json("impasses")
    for k, x in enumerate(imp):
        re = np.asarray(x["rate_error"], float)[:, 0]
        ax[1].loglog(
            x["timesteps"],
            re,
            "s--",
            color=LINE_COLORS[(k + 3) % 7],
            label=f"planar impasse $\\mu$ = {x['mu']}, $\\Theta$ = {x['Theta']}",
        )
    for a in ax:
        a.set_xlabel("rigid engine timestep (scaled)")
        a.invert_xaxis()
        a.legend(fontsize=6)
    ax[0].set_ylabel("median |t_jam engine - t_jam analytic|")
    ax[1].set_ylabel("median post-jam |rates - IWC| ($\\Theta$, $\\Psi$, $\\eta$)")
    blocks.append(
        ctx.figure(
            "jams",
            fig,
            "Jams of the rigid engine against the theory: jam-time error (left) and the state one row after the jam against the "
            "impact without collision (crosscheck.theory.impact.darboux_keller) at the analytic jam (right), as the timestep shrinks. Planar impasses start in "
            "p < 0, b < 0 (the step is the impulse problem plus O(dt) terms: first order); Corollary 4.2 states meet p = 0 along "
            "p ~ (t_jam - t)^(1/2), which a first-order step meets early by up to O(sqrt(dt)).",
            ["jams.json", "impasses.json"],
        )
    )
    blocks.append(
        Table(
            caption="Corollary 4.2 states in the rigid engine: how many jam (the classifier's one-row impulse JAM), their jam-time errors, the "
            "normal impulse against the IWC's, the post-jam rates against the IWC's, and how many of the theory's slips reach "
            "states whose time step has a second solution before the jam: the tip stopped by one impulse (the sticking impulse "
            "-G^-1 u inside the cone), with the median lead before the jam (at least: read at the theory's integration rows). "
            "From there on the step's contact problem is not unique and PGS may return the stop: a jam then comes early by up to "
            "that lead, with post-jam rates off the IWC, and need not converge as dt shrinks.",
            header=[
                "mu",
                "timestep",
                "JAM",
                "median |dt jam|",
                "max |dt jam|",
                "median |impulse - IWC|",
                "median |rates - IWC|",
                "step admits a stop before the jam",
            ],
            rows=rows,
            data=ctx.data("jams.json"),
        )
    )
    blocks.append(_impasse_table(ctx, imp))
    return blocks


def _impasse_table(ctx: RenderContext, imp: list) -> Table:
    """Planar impasses: the post-jam rates against Keller's two-phase impact, and their order."""
    return Table(
        caption="Planar impasses (p < 0, b < 0 at t = 0 on varphi = -pi/2, Psi = 0): the engine's post-jam rates against Keller's "
        "two-phase impact, and the observed order of convergence.",
        header=["mu", "Theta", "timesteps", "|rates - IWC|", "order"],
        rows=[
            [
                f"{x['mu']:g}",
                f"{x['Theta']:g}",
                ", ".join(f"{d:g}" for d in x["timesteps"]),
                ", ".join(f"{e[0]:.2e}" for e in x["rate_error"]),
                _fmt(x["orders"][0], ".4f"),
            ]
            for x in imp
        ],
        data=ctx.data("impasses.json"),
    )


def _trajectory_blocks(ctx: RenderContext) -> list:
    """One Corollary 4.2 run through its jam: the analytic slip, the engines and the state after the IWC."""
    from crosscheck.report.plotting import LINE_COLORS, plt

    blocks: list = []
    traj = ctx.store.read_json("trajectory")
    a = ctx.store.read_table("trajectory_analytic")
    eng = {n: ctx.store.read_table(f"trajectory_{n}") for n in ("pinocchio", "mujoco") if n in traj}
    hy = traj["hybrid"]
    fig, axes = plt.subplots(1, 4, figsize=(13, 3.4), sharex=True)
    labels = {"pinocchio": "rigid engine (Pinocchio)", "mujoco": "MuJoCo"}
    colors = {"pinocchio": LINE_COLORS[1], "mujoco": LINE_COLORS[2]}
    for ax_, key in zip(axes, ("theta", "eta", "Theta", "Psi")):
        ax_.plot(a["t"], a[key], "k-", lw=2, label="analytic slip")
        for n, e in eng.items():
            ax_.plot(e["t"], e[key], "-", color=colors[n], lw=1, label=labels[n])
        ax_.axvline(traj["t_jam"], color="0.5", ls=":", lw=1)
        seg = hy["segments"][0]
        if seg["impact"] is not None:
            after = seg["impact"]["after"]
            if key in after:
                ax_.plot([traj["t_jam"]], [after[key]], "k*", ms=10, label="after the IWC")
            elif key == "theta":
                ax_.plot([traj["t_jam"]], [a["theta"][-1]], "k*", ms=10, label="after the IWC")
        ax_.set_title(TEX[key])
        ax_.set_xlabel("t (scaled)")
    axes[0].legend(fontsize=6)
    s = traj["state"]
    cap = (
        f"Through a jam: the Corollary 4.2 state theta = {s['theta']:.3f}, varphi = {s['varphi']:.3f}, Theta = {s['Theta']:.3f}, Psi = {s['Psi']:.3f}, "
        f"eta = {s['eta']:.3f} at mu = {traj['mu']:g}. The analytic slip ends at p = 0 (t = {traj['t_jam']:.3f}, dotted); the star is the state after the "
        f"impact without collision there (ends: {hy['outcome'].lower()}). Rigid engine: {traj['pinocchio']['outcome']} at {_fmt(traj['pinocchio']['event_time'])}; "
        f"MuJoCo: {traj['mujoco']['outcome']} at {_fmt(traj['mujoco']['event_time'])}."
    )
    blocks.append(
        ctx.figure(
            "trajectory_jam",
            fig,
            cap,
            ["trajectory.json", "trajectory_analytic.csv"] + [f"trajectory_{n}.csv" for n in eng],
        )
    )
    sol = traj["pinocchio"].get("solver", {})
    blocks.append(
        Text(
            f"Solver health of that rigid run: {sol.get('contact_steps', 0)} steps in contact, mean {sol.get('mean_iterations', 0):.0f} and at most "
            f"{sol.get('max_iterations', 0)} PGS iterations, {sol.get('unconverged_steps', 0)} steps missing the tolerance after every retry."
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="Rigid engine: lift-off onset, jams and the impact without collision",
    paper="eq. psil, Corollary 4.2, section 6",
    params=params,
    run=run,
    render=render,
    requires=(
        "crosscheck.engines.pinocchio.studies.rigid",
        "crosscheck.engines.pinocchio.stepper",
        "crosscheck.theory.impact.darboux_keller",
        "crosscheck.theory.impact.continuation",
    ),
)
