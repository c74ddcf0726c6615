"""MuJoCo's friction-direction skew: its contact law written out, predicted against measured, its cause and what removes it.

* The law (``crosscheck.engines.mujoco.law``) against MuJoCo's own solver
  arrays at random contacts (``crosscheck.engines.mujoco.studies.law_check``).
* MuJoCo's approach to the law integrated in continuous time (engine
  "mujoco_law") as its timestep shrinks: the order.
* The skew (``crosscheck.engines.mujoco.studies.friction_skew``): predicted by the law's
  run and by the closed form angle(u, u + a_t / B), measured in MuJoCo on the
  same random states, per |varphi + pi/2| band and per mu bin; the MuJoCo
  options that might remove it (impratio, a pyramidal cone, noslip
  iterations, a shorter friction time constant), measured in MuJoCo; and an
  ablation of the law's problem that names the ingredient.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text

SLUG = "friction_skew"


def params(quick: bool) -> dict:
    return {
        "alpha": 3.0,
        # (the full report's 200 states and 200 contacts took 20-27 s of section time; 100 of each, half)
        "n_states": 30 if quick else 100,
        "duration": 0.1,
        "timestep": 3e-4,
        "n_contacts": 16 if quick else 100,
        "n_ablation": 16 if quick else 60,
        "friction_timeconsts": [0.03, 0.01],
        "small_impratios": [0.01] if quick else [0.1, 0.01, 0.001],
        "order": {
            "state": {"theta": 0.8, "varphi": -1.2, "Theta": 0.3, "Psi": 1.0, "eta": 1.0},
            "mu": 0.3,
            "timesteps": [2e-4, 1e-4, 5e-5],
            "horizon": 0.4,
        },
    }


def run(ctx: RunContext) -> None:
    from crosscheck.engines.mujoco.studies import friction_skew as fs
    from crosscheck.engines.mujoco.studies.law_check import convergence_order, efc_agreement
    from crosscheck.engines.mujoco.tolerances import MUJOCO_LAW_FORCE, MUJOCO_LAW_ORDER, MUJOCO_LAW_SKEW
    from crosscheck.rod import Rod
    from crosscheck.state import SlipState

    P = ctx.params
    agree = efc_agreement(P["n_contacts"], ctx.rng)
    ctx.store.write_json("law_check", agree)
    ctx.check(
        "MuJoCo's contact law = mj_forward's efc_force",
        agree["force"] <= MUJOCO_LAW_FORCE.rtol,
        value=agree["force"],
        allowance=MUJOCO_LAW_FORCE.rtol,
        detail="crosscheck.engines.mujoco.tolerances.MUJOCO_LAW_FORCE",
    )

    O = P["order"]
    order = convergence_order(
        Rod.scaled(P["alpha"]), SlipState(**O["state"]), O["mu"], timesteps=O["timesteps"], horizon=O["horizon"]
    )
    ctx.store.write_json("order", {**order, **O})
    ctx.check(
        "MuJoCo -> continuous-time law at first order",
        MUJOCO_LAW_ORDER.ok(order["order"], 1.0),
        value=order["order"],
        allowance=f"1 +- {MUJOCO_LAW_ORDER.atol:g}",
        detail="crosscheck.engines.mujoco.tolerances.MUJOCO_LAW_ORDER",
        guard=True,
    )

    variants = dict(fs.VARIANTS)
    for r in P["small_impratios"]:
        variants[f"impratio {r:g}"] = {"impratio": r}
    s = fs.study(
        P["n_states"],
        ctx.rng,
        alpha=P["alpha"],
        duration=P["duration"],
        variants=variants,
        friction_timeconsts=P["friction_timeconsts"],
        n_ablation=P["n_ablation"],
        timestep=P["timestep"],
    )
    ctx.store.write_json(
        "skew",
        {
            k: s[k]
            for k in (
                "bands",
                "mu_bins",
                "band_median_deg",
                "mu_median_deg",
                "ablation_median_deg",
                "max_abs_difference_deg",
                "median_abs_difference_deg",
                "saturation_median",
                "n_compared",
                "n_exits",
                "n_lifts_off",
            )
        },
    )
    cols = {
        "varphi_offset": s["varphi_offset"],
        "mu": s["mu"],
        "predicted": s["predicted"],
        "closed": s["closed"],
        "exits": s["exits"].astype(float),
    }
    cols.update({f"measured {k}": v for k, v in s["measured"].items()})
    ctx.store.write_table("states", cols)
    d = math.radians(s["max_abs_difference_deg"])
    ctx.check(
        "predicted skew (law run) = MuJoCo's measured, per state",
        d <= MUJOCO_LAW_SKEW.atol,
        value=s["max_abs_difference_deg"],
        allowance=math.degrees(MUJOCO_LAW_SKEW.atol),
        detail="degrees; crosscheck.engines.mujoco.tolerances.MUJOCO_LAW_SKEW",
        guard=True,
    )


def _f(x, spec=".1f") -> str:
    return "-" if x is None or not math.isfinite(x) else format(x, spec)


def render(ctx: RenderContext) -> list:

    agree = ctx.store.read_json("law_check")
    order = ctx.store.read_json("order")
    s = ctx.store.read_json("skew")
    st = ctx.store.read_table("states")
    P = ctx.params
    blocks: list = [
        Text(
            "MuJoCo's contact force, written out (`crosscheck.engines.mujoco.law`): f = argmin over the elliptic cone |f_t| <= mu f_n of "
            "1/2 f^T (A + R) f + f^T (a0 - aref), with A = J M^-1 J^T at MuJoCo's contact point, a0 = J qacc_smooth (no dJ/dt v term), "
            "aref = -B J v - K d(dist) dist (B = 2/(dmax tau), K = 1/(dmax^2 tau^2 zeta^2), K = 0 on the friction rows), "
            "R = (1 - d)/d times the rod's translational body_invweight0 (1/m, not A's diagonal), R_t = R_n / impratio. "
            f"At {P['n_contacts']} random contacts (random alpha, mu, radius, solref, solreffriction, solimp, impratio, depth) it equals "
            f"mj_forward's efc_force to {agree['force']:.1e} relative (efc_R to {agree['R']:.1e}, efc_aref to {agree['aref']:.1e} of its terms). "
            f"Integrated in continuous time (engine `mujoco_law`), it is what MuJoCo converges to: the RMS tip error over "
            f"{order['horizon']:g} of time goes {', '.join(f'{e:.1e}' for e in order['rms'])} at timesteps "
            f"{', '.join(f'{t:g}' for t in order['timesteps'])}, order {order['order']:.2f}. A slipping capsule rides on the plane in a "
            "sliding mode (the law's force at dist = 0 would push it off: the elliptic cone raises f_n to carry the friction aref_t = -B u asks "
            "for), which MuJoCo realises as a chatter of contact and free steps."
        )
    ]
    rows = [[k] + [_f(x) for x in v] for k, v in s["band_median_deg"].items()]
    blocks.append(
        Table(
            caption=f"Median |skew| [degrees] of the friction from -slip per |varphi + pi/2| band ({P['n_states']} random slipping "
            f"states, alpha = {P['alpha']:g}, first {P['duration']:g} of each run, normal-force-weighted mean per run): "
            "predicted by the law (its run, and the closed form angle(u, u + a_t/B)) and measured in MuJoCo with its "
            "default and other options.",
            header=["", *(f"[{lo:.2f}, {min(hi, math.pi / 2):.2f})" for lo, hi in s["bands"])],
            rows=rows,
            data=ctx.data("skew.json", "states.csv"),
        )
    )
    rows = [[k] + [_f(x) for x in v] for k, v in s["mu_median_deg"].items()]
    blocks.append(
        Table(
            caption="The same per mu bin.",
            header=["", *(f"mu in [{lo:g}, {hi:g})" for lo, hi in s["mu_bins"])],
            rows=rows,
            data=ctx.data("skew.json"),
        )
    )
    ab = s["ablation_median_deg"]
    blocks.append(
        Table(
            caption="Which ingredient: median |skew| [degrees] of the law's force at the states' start with parts of its problem "
            "removed. Decoupled: A's normal-tangential block A_tn = 0; isotropic: also A_tt = its mean eigenvalue x I; no "
            "free acceleration: a0_t = 0; neither: isotropic, decoupled and a0_t = 0.",
            header=["problem", "median |skew| [deg]"],
            rows=[[k, _f(v, ".2f")] for k, v in ab.items()],
            data=ctx.data("skew.json"),
        )
    )
    from crosscheck.engines.mujoco.studies.friction_skew import REDUCES, REMOVES, option_effects

    sat = s["saturation_median"]
    effect = option_effects(s["band_median_deg"])

    def listed(kind: str) -> str:
        ks = effect[kind]
        return (
            ", ".join(
                f"{k} ({'/'.join(_f(v) for v in x)} degrees, median saturation {_f(sat.get(k, math.nan), '.2f')})"
                for k, x in ks.items()
            )
            or "none"
        )

    blocks.append(
        Text(
            f"Predicted and measured agree state by state: over the {s['n_compared']} states whose law run has a contact and keeps theta in "
            f"(0, pi/2) the largest difference is {s['max_abs_difference_deg']:.2f} degrees (median {s['median_abs_difference_deg']:.2f}); it "
            "shrinks with MuJoCo's timestep (its O(dt) discretisation of the sliding mode's chatter). Not compared: "
            f"{s['n_lifts_off']} states that lift off at the start (b > 0: no force in the law; MuJoCo's first step may still apply one, its "
            f"position update carrying only half of the dJ/dt v term) and {s['n_exits']} whose rod lies flat within the window (MuJoCo's capsule "
            "then touches with its other end, a contact the law does not model). "
            "The cause: on the cone's surface the force is anti-parallel to u + a_t/B, the slip extrapolated over the friction damping time; "
            "while slipping aref_t = -B u dominates and f grows like B, so the direction is that of the cone-constrained minimiser of "
            "1/2 f^T (A + R) f + B u . f_t, which is -u only when the tangential block of A + R is isotropic and decoupled from the normal row. "
            "At the rod's contact point A is neither (the point moves more easily across the rod, A_tt = (1 + alpha)/m, than along its "
            "horizontal projection, (1 + alpha (sin theta + r/l)^2)/m, and a push along the rod also moves it vertically, A_nt != 0): with A "
            "isotropic and "
            f"decoupled the median skew is {_f(ab.get('isotropic', math.nan), '.2f')} degrees instead of {_f(ab.get('law', math.nan), '.1f')}, "
            f"while removing the free tangential acceleration gives {_f(ab.get('no free acceleration', math.nan), '.1f')}. "
            f"Measured in MuJoCo (per band, against the default; removes: every band below {REMOVES:g} of the default, reduces: below "
            f"{REDUCES:g}): removes it: {listed('removes')}; reduces it: {listed('reduces')}; leaves it: "
            f"{', '.join(effect['leaves']) or 'none'}. R_t = R_n / impratio is isotropic, so only a regulariser larger than A's tangential "
            "block (impratio << 1) makes the metric isotropic, at the price of a softer friction that stops reaching mu F_n once R_t dominates "
            f"(median saturation |F_t| / (mu F_n) of the default: {_f(sat.get('default', math.nan), '.2f')}). Consequence: MuJoCo's slipping "
            "normal force is -b/p_eff with its own friction direction, not -b/p (`crosscheck.engines.mujoco.studies.contact.friction_skew`), which "
            "moves its events off the rigid theory's away from the planar section."
        )
    )
    blocks.append(_skew_figure(ctx, st))
    return blocks


def _skew_figure(ctx: RenderContext, st: dict):
    """The law's predicted skew against MuJoCo's, state by state, and |skew| against the distance from the planar
    section."""
    from crosscheck.report.plotting import plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    keep = st["exits"] == 0  # the rod lying flat within the window: MuJoCo's other end touches, outside the law
    meas = np.where(keep, st["measured default"], np.nan)
    ax[0].plot(np.degrees(meas), np.degrees(st["predicted"]), "o", ms=3)
    lim = np.nanmax(np.abs(np.degrees(meas))) if np.isfinite(meas).any() else 1.0
    ax[0].plot([-lim, lim], [-lim, lim], "k-", lw=0.6)
    ax[0].set_xlabel("measured skew in MuJoCo [deg]")
    ax[0].set_ylabel("predicted by the law [deg]")
    ax[1].plot(st["varphi_offset"], np.degrees(np.abs(meas)), "o", ms=3, label="MuJoCo default")
    ax[1].plot(st["varphi_offset"], np.degrees(np.abs(st["predicted"])), "x", ms=4, label="law (predicted)")
    for k in st:
        if k.startswith("measured impratio 0.01"):
            ax[1].plot(st["varphi_offset"], np.degrees(np.abs(st[k])), ".", ms=4, label="MuJoCo impratio 0.01")
    ax[1].set_xlabel("|varphi + pi/2| [rad]")
    ax[1].set_ylabel("|skew| [deg]")
    ax[1].legend(fontsize=8)
    return ctx.figure(
        "skew",
        fig,
        "Left: the friction skew predicted by MuJoCo's contact law (its continuous-time run) against MuJoCo's, "
        "state by state. Right: |skew| against the slip's distance from the planar section.",
        ["states.csv"],
    )


def finding(data: Path) -> list:
    """The findings line of MuJoCo's friction direction: measured and predicted skew, its cause, the options."""
    from crosscheck.report.finding import Finding, read_json

    out = []
    skew = read_json(data / "skew.json")
    if skew:
        bands = skew["band_median_deg"]
        pred, meas = bands["predicted (law run)"], bands["MuJoCo default"]
        ab = skew.get("ablation_median_deg", {})
        from crosscheck.engines.mujoco.studies.friction_skew import option_effects

        effect = option_effects(bands)
        options = "; ".join(
            f"{kind} it: "
            + ", ".join(
                k + (f" ({'/'.join(f'{v:.1f}' for v in x)})" if kind != "leaves" else "") for k, x in ks.items()
            )
            for kind, ks in effect.items()
            if ks
        )
        checks = read_json(data / "checks.json") or []
        ok = any("predicted skew" in c["name"] for c in checks) and all(
            c["passed"] for c in checks if "predicted skew" in c["name"]
        )
        out.append(
            Finding(
                "MuJoCo: friction direction",
                f"skewed from -slip by {'/'.join(f'{x:.1f}' for x in meas)} degrees (median per "
                f"|varphi + pi/2| band); MuJoCo's contact law predicts {'/'.join(f'{x:.1f}' for x in pred)} on the same states (worst "
                f"state {skew['max_abs_difference_deg']:.2f} degrees off). Cause: the friction minimises a quadratic in the metric A + R, "
                f"anisotropic and coupled to the normal row at the rod's contact point (made isotropic and decoupled: "
                f"{ab.get('isotropic', float('nan')):.2f} instead of {ab.get('law', float('nan')):.1f} degrees). MuJoCo options: {options}. "
                f"Consequence: MuJoCo slips with -b/p_eff, not -b/p",
                "explained" if ok else "not explained",
                SLUG,
            )
        )
    return out


SECTION = Section(
    slug=SLUG,
    title="MuJoCo's contact law: friction-direction skew predicted and measured",
    paper="eqs. friction, p, FZ",
    params=params,
    run=run,
    render=render,
    requires=(
        "crosscheck.engines.mujoco.law",
        "crosscheck.engines.mujoco.ode",
        "crosscheck.engines.mujoco.studies.friction_skew",
        "crosscheck.engines.mujoco.studies.law_check",
    ),
    finding=finding,
)
