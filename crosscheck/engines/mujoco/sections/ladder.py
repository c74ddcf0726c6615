"""The ladder: a named cause (geometry, compliance, friction law, feed-forward, discretisation) for each MuJoCo-theory disagreement.

The starts are those of the MuJoCo outcome maps (``mujoco_maps``: (Psi, mu)
and two (theta, Theta) slices), compared by
``crosscheck.studies.agreement.agreement_study``; the full report reads that
section's saved results when they were made with the same maps and options
(else recomputes them), the quick report recomputes coarser maps and ladders
a few of their disagreements.  Every start where MuJoCo's label differs from
the analytic first event goes through ``crosscheck.engines.mujoco.studies.ladder``: the
rigid rod at the tip A, the rigid rod at the capsule point C, the
Kelvin-Voigt rod at C with MuJoCo-equivalent (eps, xi), MuJoCo's contact law
in continuous time without and with its normal force's feed-forward, and
MuJoCo at its timestep; the cause is the first rung of the final stretch whose
outcomes (relabelled by the study's comparison rule) equal MuJoCo's label in
the study.  A ladder's detours (rungs whose outcome is neither the theory's
nor MuJoCo's) are counted with the rung that ends each.  The paper's Fig. 20
initial condition IC2 is followed through all six rungs on one figure.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from crosscheck.engines.mujoco import tolerances as mujoco_tol
from crosscheck.report.grids import cell_centres
from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text

SLUG = "ladder"

#: Map code of a start that does not slip at t = 0 (as ``mujoco_maps``), of a rated start that agrees,
#: and of a disagreement the quick report did not run through the ladder.
NOT_SLIPPING, AGREE, NOT_RUN = -2, -3, -4

#: The maps' colours of the causes (and of the three codes above); every one used appears in the legend.
CAUSE_COLORS = {
    "geometry": (0.12, 0.47, 0.71),
    "compliance": (1.0, 0.5, 0.05),
    "friction law": (0.17, 0.63, 0.17),
    "feed-forward": (0.55, 0.34, 0.29),
    "discretisation": (0.58, 0.4, 0.74),
    "unexplained": (0.84, 0.15, 0.16),
    "undetermined": (0.5, 0.5, 0.5),
    "agree": (0.96, 0.96, 0.96),
    "not rated": (0.75, 0.75, 0.6),
}


def params(quick: bool) -> dict:
    from crosscheck import engines
    from crosscheck.report.sections import engine_maps
    from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS

    spec = engines.get("mujoco")
    base = engine_maps.params(quick, spec.name, spec.report.maps["quick" if quick else "full"])
    maps = [dict(m) for m in base["maps"]]
    if quick:  # coarser maps and a few of their disagreements: the ladder's cost is its rungs 3 to 5, ~1 s a start
        for m in maps:
            m["n"] = 8
    # ladder_engine: whose disagreements these are (the engine table reads the causes of each engine from it)
    return {
        "ladder_engine": spec.name,
        "alpha": base["alpha"],
        "horizon": base["horizon"],
        "options": base["options"],
        "maps": maps,
        "reuse": None if quick else f"{spec.slug}_maps",
        "max_states": 8 if quick else None,
        "ic2": dict(FIG20_INITIAL_CONDITIONS[1]),
        "ic2_mu": 1.4,
    }


def _grid(m: dict):
    from crosscheck.studies.grids import EventGrid

    x, y = cell_centres(*m["x_range"], m["n"]), cell_centres(*m["y_range"], m["n"])
    axes = {k: (v,) for k, v in m["fixed"].items()}
    axes[m["x"]], axes[m["y"]] = tuple(x), tuple(y)
    return EventGrid(**axes), x, y


def _saved_maps(ctx: RunContext) -> dict | None:
    """The ``mujoco_maps`` section's saved event tables, if that section ran ok with this section's maps and options."""
    P = ctx.params
    found = ctx.finished(P["reuse"]) if P["reuse"] else None
    if found is None:
        return None
    status, store = found
    theirs = status.get("params", {})
    if any(theirs.get(k) != P[k] for k in ("alpha", "horizon", "options", "maps")) or theirs.get("engine") != "mujoco":
        return None
    return {m["name"]: store.read_table(f"events_{m['name']}", text=("analytic_reason",)) for m in P["maps"]}


def _events(ctx: RunContext) -> tuple[dict, str]:
    """Per map: the starts, the analytic outcome and MuJoCo's label as compared (NOT_SLIPPING where not compared)."""
    from crosscheck.studies.agreement import agreement_study

    P = ctx.params
    saved = _saved_maps(ctx)
    if saved is not None:
        return {
            name: {
                k: np.asarray(t[k])
                for k in ("theta", "varphi", "Theta", "Psi", "mu", "eta", "analytic_outcome", "slipping", "mujoco")
            }
            for name, t in saved.items()
        }, f"the saved results of the {P['reuse']} section"
    out = {}
    for m in P["maps"]:
        grid, _, _ = _grid(m)
        sweeps = (
            {} if ctx.sweeps is None else {**ctx.sweeps, "store": ctx.sweeps["store"] / m["name"]}
        )  # resumable, as mujoco_maps
        res = agreement_study(
            grid,
            engine="mujoco",
            settings=(P["options"],),
            alpha=P["alpha"],
            horizon=P["horizon"],
            rng=ctx.rng,
            boundary_directions=0,
            progress=ctx.show_progress,
            **sweeps,
        )
        pts, a = res.points, res.analytic
        label = np.full(len(a.outcome), NOT_SLIPPING)
        label[res.index] = res.runs[0].label
        out[m["name"]] = {
            **{k: pts[k] for k in ("theta", "varphi", "Theta", "Psi", "mu", "eta")},
            "analytic_outcome": a.outcome.astype(int),
            "slipping": a.slipping.astype(int),
            "mujoco": label,
        }
    return out, "a fresh agreement study on these maps"


def run(ctx: RunContext) -> None:
    from crosscheck.engines.mujoco.studies.ladder import CAUSE_CODES, NAMED_CAUSES, RUNGS, run_ladder
    from crosscheck.engines.mujoco.studies.ladder_study import disagreements as find_disagreements
    from crosscheck.engines.mujoco.studies.ladder_study import ladder_study, trajectories
    from crosscheck.state import SlipState

    P = ctx.params
    events, source = _events(ctx)
    chosen = []  # (map name, index in the map)
    for name, e in events.items():
        ctx.store.write_table(f"events_{name}", e)
        chosen += [(name, int(i)) for i in find_disagreements(e, e["analytic_outcome"], e["mujoco"])]
    n_all = len(chosen)
    if (
        P["max_states"] is not None and n_all > P["max_states"]
    ):  # evenly spread over the maps' disagreements, deterministic
        chosen = [chosen[int(k)] for k in np.linspace(0, n_all - 1, P["max_states"]).round().astype(int)]
    states = [
        SlipState(**{k: float(events[n][k][i]) for k in ("theta", "varphi", "Theta", "Psi", "eta")}) for n, i in chosen
    ]
    mus = [float(events[n]["mu"][i]) for n, i in chosen]
    refs = [int(events[n]["mujoco"][i]) for n, i in chosen]
    study = ladder_study(
        states,
        mus,
        alpha=P["alpha"],
        horizon=P["horizon"],
        references=refs,
        progress=ctx.show_progress,
        desc=SLUG,
        **P["options"],
    )
    cols = {"map": [n for n, _ in chosen], "index": [i for _, i in chosen]}
    for k in ("theta", "varphi", "Theta", "Psi", "eta"):
        cols[k] = [getattr(s, k) for s in states]
    cols["mu"] = mus
    cols["analytic"] = [ld.rungs[0].label.name for ld in study.ladders]
    cols["mujoco_study"] = [ld.reference.name for ld in study.ladders]
    for j, name in enumerate(RUNGS):
        cols[f"{name}_status"] = [ld.rungs[j].status for ld in study.ladders]
        cols[f"{name}_outcome"] = [ld.rungs[j].outcome.name if ld.rungs[j].ok else "" for ld in study.ladders]
        cols[f"{name}_time"] = [ld.rungs[j].time for ld in study.ladders]
        cols[f"{name}_label"] = [ld.rungs[j].label.name if ld.rungs[j].ok else "" for ld in study.ladders]
    cols["cause"] = [ld.cause for ld in study.ladders]
    cols["cause_code"] = [CAUSE_CODES[ld.cause] for ld in study.ladders]
    cols["first_change"] = [ld.first_change if ld.first_change is not None else 0 for ld in study.ladders]
    cols["detour_from"] = [ld.detour[0] if ld.detour is not None else 0 for ld in study.ladders]
    cols["detour_ended_by"] = [ld.detour_ended_by or ("none" if ld.detour is not None else "") for ld in study.ladders]
    cols["eps"] = [ld.match.eps for ld in study.ladders]
    cols["xi"] = [ld.match.xi for ld in study.ladders]
    ctx.store.write_table("ladder", cols)
    # the laddered starts in the format every ladder section publishes (``crosscheck.report.sections.engine_ladder``),
    # read by the engine's interventions section
    ctx.store.write_json(
        "ladders",
        [
            {
                "map": n,
                "state": {k: getattr(s, k) for k in ("theta", "varphi", "Theta", "Psi", "eta")},
                "mu": float(m),
                "cause": ld.cause,
                "reference": ld.reference.name,
            }
            for (n, _), s, m, ld in zip(chosen, states, mus, study.ladders)
        ],
    )
    failures = sorted({f"{r.name}: {r.detail}" for ld in study.ladders for r in ld.rungs if not r.ok})
    summary = {**study.summary(), "n_disagreements_on_maps": n_all, "source": source, "failures": failures[:20]}
    ctx.store.write_json("summary", summary)

    # IC2 through all six rungs, with each rung's time series
    ic2 = SlipState(**P["ic2"])
    ld = run_ladder(ic2, P["ic2_mu"], alpha=P["alpha"], horizon=P["horizon"], keep=True, **P["options"])
    ctx.store.write_json("ic2", ld.as_dict())
    series = trajectories(ld)
    rows = {"rung": [], "t": [], "eta": [], "normal_force": []}
    for name, s in series.items():
        rows["rung"] += [name] * len(s["t"])
        for k in ("t", "eta", "normal_force"):
            rows[k] += list(s[k])
    ctx.store.write_table("ic2_series", rows)

    # Checks
    ctx.check(
        "every rung ran at every start (none missing or failed)",
        not any(study.missing.values()),
        value=study.missing,
        allowance=0,
        detail="; ".join(failures[:5]),
    )
    ctx.check(
        "rung 6 (MuJoCo rerun at the same options) reproduces the agreement study's MuJoCo label at every disagreement, "
        "or 1-2 ulp of theta away (MuJoCo's first-row contact decided by rounding)",
        study.reference_mismatch == study.rounding_decided,
        value=study.reference_mismatch - study.rounding_decided,
        allowance=0,
        detail=f"{study.n_disagree} disagreements laddered; the rerun runs only to the comparison time + lag, as the study compares; "
        f"{study.reference_mismatch} reruns differ, {study.rounding_decided} of them decided by the start's last bits",
    )
    one = ld.rungs[0]
    ctx.check(
        "IC2: rung 1 (the paper's rod) lifts off at t = 0.01654",
        one.outcome is not None
        and one.outcome.name == "LIFTOFF"
        and mujoco_tol.LADDER_QUOTED_TIME.ok(one.time, 0.01654),
        value=one.time,
        allowance=mujoco_tol.LADDER_QUOTED_TIME.atol,
        detail=f"{one.outcome.name if one.outcome is not None else one.status} at p = {one.p:.4g}",
    )
    att = study.attributed
    goal = 1.0 - mujoco_tol.LADDER_ATTRIBUTED.atol
    ctx.check(
        f"at least {100 * goal:.0f}% of the disagreements attributed to a named cause",
        bool(math.isfinite(att) and att >= goal),
        value=att,
        allowance=goal,
        guard=True,
        detail=", ".join(
            f"{c} {study.counts[c]}" for c in (*NAMED_CAUSES, "unexplained", "undetermined") if study.counts[c]
        )
        + f" of {study.n_disagree}",
    )


def render(ctx: RenderContext) -> list:
    from matplotlib.patches import Patch

    from crosscheck.engines.mujoco.studies.ladder import CAUSE_CODES, CAUSES, NAMED_CAUSES, RUNG_TITLES, RUNGS
    from crosscheck.report.plotting import LINE_COLORS, categorical_image, plt

    P = ctx.params
    summary = ctx.store.read_json("summary")
    lad = ctx.store.read_table(
        "ladder",
        text=tuple(
            ["map", "analytic", "mujoco_study", "cause", "detour_ended_by"]
            + [f"{r}_{k}" for r in RUNGS for k in ("status", "outcome", "label")]
        ),
    )
    shown = (*NAMED_CAUSES, "unexplained", "undetermined")
    n = summary["n_disagree"]
    blocks = [
        Text(
            f"Starts from {summary['source']} (alpha = {P['alpha']:g}, horizon {P['horizon']:g}, MuJoCo "
            + ", ".join(f"{k} {v:g}" for k, v in P["options"].items())
            + f"). {summary['n_disagreements_on_maps']} starts disagree with "
            f"the analytic first event; {summary['n']} went through the ladder"
            + (
                " (the quick report ladders an even spread of them)"
                if summary["n"] < summary["n_disagreements_on_maps"]
                else ""
            )
            + ". A cause is the rung from which every later rung's outcome, relabelled by the agreement study's comparison rule (an "
            "event after the analytic comparison time plus the lag counts as SLIP), equals MuJoCo's label in the study: the first rung "
            "of the final stretch of matches. A match that the next rung undoes is not the difference MuJoCo keeps (near p = 0 the "
            "rigid rod at C jams where the Kelvin-Voigt rod at C does not, and only MuJoCo's law jams again). "
            f"Attributed to a named cause: {100 * summary['attributed']:.1f}% of {n} (goal: at least 90%)."
        )
    ]
    ic2 = ctx.store.read_json("ic2")
    mt = ic2["match"]
    blocks.append(
        Text(
            "Rung 3's Kelvin-Voigt contact (F_n = -gap/eps^2 - (xi/eps) gap') is matched to MuJoCo's normal row: MuJoCo's reference "
            "acceleration aref = -B v - d K r (B = 2/(dmax timeconst), K = 1/(dmax^2 timeconst^2 dampratio^2), d the solimp impedance), "
            "blended by d, makes the gap obey r'' = (1 - d) a0 - d B r' - d^2 K r; the spring-damper gives r'' = a0 + A_nn F_n with "
            "A_nn = 1 + alpha cos^2 theta (the frictionless eq. p, the same at C as at A). Equal stiffness and damping: "
            "eps = (dmax/d) timeconst dampratio sqrt(A_nn), xi = 2 dampratio / sqrt(A_nn), with d at MuJoCo's static penetration "
            f"of the start (IC2: A_nn = {mt['A_nn']:.4g}, d = {mt['d']:.4g}, eps = {mt['eps']:.4g}, xi = {mt['xi']:.4g}). The match is of the "
            "normal row alone and of the spring about a penetration: MuJoCo's force also feeds forward d of the free acceleration "
            "(d ~ 0.9 of the rigid force at once), which the spring builds only over ~timeconst, and friction changes the gap's "
            "inverse mass from A_nn to p. Rung 4 is MuJoCo's law with its friction but without that feed-forward (the normal row "
            "at the impedance 0.001: its solref spring-damper alone), so rung 4 adds MuJoCo's friction law to the spring "
            "('friction law') and rung 5 the feed-forward ('feed-forward')."
        )
    )
    if any(summary["missing"].values()):
        blocks.append(
            Text(
                "RUNGS THAT DID NOT RUN: "
                + "; ".join(f"{k} at {v} starts" for k, v in summary["missing"].items() if v)
                + ". A start whose first match would come after such a rung is counted 'undetermined'. "
                + " | ".join(summary["failures"][:5])
            )
        )
    rows = [[c, str(summary["counts"][c]), f"{100 * summary['fractions'][c]:.1f}%" if n else "-"] for c in shown]
    blocks.append(
        Table(
            caption="Disagreements per cause (fractions of the laddered disagreements).",
            header=["cause", "starts", "fraction"],
            rows=rows,
            data=ctx.data("summary.json", "ladder.csv"),
        )
    )
    blocks.append(
        Text(
            "What the attributed fraction means: rung 6 is MuJoCo itself at the same options, rerun to the comparison time plus "
            "the lag, so it reproduces the study's label whenever the rerun is faithful "
            f"({summary['reference_mismatch']} of {n} did not; of those, {summary.get('rounding_decided', 0)} give the study's label "
            "1-2 units in the last place of theta away: MuJoCo's contact in the first row, and with it the outcome, is decided by "
            "the start's last bits there, which the study's array-built starts and the ladder's one-by-one starts round differently), "
            "and then every disagreement gets some named cause. The information is in "
            "the split: which of MuJoCo's differences from the paper's rod is the first to produce its outcome."
        )
    )
    # the ladder need not be monotone: an outcome may change at one rung and reach MuJoCo's only at a later one, or match it and leave it again
    changes = sorted({int(v) for v in lad["first_change"]})
    named = [c for c in shown if summary["counts"][c]]
    blocks.append(
        Table(
            caption="First rung at which the outcome differs from rung 1's (rows) against the cause (columns): off the diagonal "
            "the outcome changed first to something MuJoCo does not do.",
            header=["first change \\ cause"] + named,
            rows=[
                [f"rung {k}" if k else "none"]
                + [str(int(np.sum((lad["first_change"] == k) & (lad["cause"] == c)))) for c in named]
                for k in changes
            ],
            data=ctx.data("ladder.csv"),
        )
    )
    det = summary.get("detours", {"n": 0, "ended_by": {}})
    ends = [c for c in (*NAMED_CAUSES, "none") if det["ended_by"].get(c)]
    blocks.append(
        Table(
            caption=f"Detours: {det['n']} of {n} ladders pass through an outcome that is neither the theory's nor MuJoCo's (a "
            "ladder without one is monotone: each rung keeps the theory's outcome or takes MuJoCo's). Per cause named "
            "(rows), the rung whose difference ends the detour (columns; 'none': no later rung does).",
            header=["cause \\ detour ended by"] + ends,
            rows=[
                [c] + [str(int(np.sum((lad["cause"] == c) & (lad["detour_ended_by"] == e)))) for e in ends]
                for c in named
            ]
            if ends
            else [["no detour"]],
            data=ctx.data("summary.json", "ladder.csv"),
        )
    )

    # maps coloured by cause
    for m in P["maps"]:
        e = ctx.store.read_table(f"events_{m['name']}")
        x, y = cell_centres(*m["x_range"], m["n"]), cell_centres(*m["y_range"], m["n"])
        xi = np.abs(e[m["x"]][:, None] - x[None, :]).argmin(axis=1)
        yi = np.abs(e[m["y"]][:, None] - y[None, :]).argmin(axis=1)
        code = np.where(
            e["slipping"] == 1, np.where(e["analytic_outcome"] == e["mujoco"], AGREE, NOT_RUN), NOT_SLIPPING
        ).astype(float)
        sel = lad["map"] == m["name"]
        code[lad["index"][sel].astype(int)] = lad["cause_code"][sel]
        img = np.full((y.size, x.size), np.nan)
        img[yi, xi] = code
        colors = {CAUSE_CODES[c]: CAUSE_COLORS[c] for c in CAUSES}
        colors.update({NOT_SLIPPING: (0.8, 0.8, 0.8), AGREE: (0.96, 0.96, 0.96), NOT_RUN: (0.3, 0.3, 0.3)})
        names = {CAUSE_CODES[c]: c for c in CAUSES}
        names.update(
            {
                NOT_SLIPPING: "not slipping at t = 0 (not compared)",
                AGREE: "MuJoCo agrees with the theory",
                NOT_RUN: "disagrees, not laddered",
            }
        )
        fig, ax = plt.subplots(figsize=(5.2, 4.4), layout="constrained")
        categorical_image(ax, x, y, img, colors)
        ax.set_xlabel(f"$\\{m['x']}$")
        ax.set_ylabel(f"$\\{m['y']}$")
        used = sorted(set(int(c) for c in code))
        fig.legend(
            handles=[Patch(color=colors[c], label=names[c]) for c in used],
            loc="outside right center",
            fontsize=7,
            frameon=False,
        )
        fixed = ", ".join(f"{k} = {v:g}" for k, v in m["fixed"].items())
        nd = int(sel.sum())
        blocks.append(
            ctx.figure(
                f"causes_{m['name']}",
                fig,
                f"Cause of each MuJoCo-theory disagreement over ({m['x']}, {m['y']}) at {fixed}: "
                f"{nd} laddered disagreements on this map.",
                [f"events_{m['name']}.csv", "ladder.csv"],
            )
        )

    # unexplained and undetermined states
    bad = np.flatnonzero(np.isin(lad["cause"], ["unexplained", "undetermined"]))
    header = (
        ["map", "theta", "varphi", "Theta", "Psi", "eta", "mu", "cause"]
        + [f"{k + 1} {r}" for k, r in enumerate(RUNGS)]
        + ["MuJoCo (study)"]
    )
    trows = []
    for i in bad:
        trows.append(
            [str(lad["map"][i])]
            + [f"{lad[k][i]:.4g}" for k in ("theta", "varphi", "Theta", "Psi", "eta", "mu")]
            + [str(lad["cause"][i])]
            + [str(lad[f"{r}_label"][i]) or str(lad[f"{r}_status"][i]) for r in RUNGS]
            + [str(lad["mujoco_study"][i])]
        )
    blocks.append(
        Table(
            caption=f"Unexplained (no rung matches MuJoCo's label) and undetermined (a rung before the first match did not run) starts: {len(bad)}.",
            header=header,
            rows=trows or [["none"] + [""] * (len(header) - 1)],
            data=ctx.data("ladder.csv"),
        )
    )

    # IC2 through the rungs
    s = ctx.store.read_table("ic2_series", text=("rung",))
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 5.6), sharex=True, layout="constrained")
    handles = []
    for k, name in enumerate(RUNGS):
        r = ic2["rungs"][k]
        sel = s["rung"] == name
        label = f"{k + 1} {name}: " + (
            f"{r['outcome']}" + (f" at t = {r['time']:.4g}" if r["time"] is not None else "")
            if r["status"] == "ok"
            else r["status"].upper()
        )
        if sel.any():
            (line,) = a1.plot(s["t"][sel], s["eta"][sel], color=LINE_COLORS[k % 7], lw=1.2, label=label)
            a2.plot(s["t"][sel], s["normal_force"][sel], color=LINE_COLORS[k % 7], lw=1.0)
            handles.append(line)
        else:
            handles.append(Patch(color="white", label=label + " (no series)"))
    a1.set_ylabel("slip speed eta of the contact point")
    a2.set_ylabel("normal force F_z [m g]")
    a2.set_yscale("symlog", linthresh=1.0)
    a2.set_xlabel("t (scaled)")
    fig.legend(handles=handles, loc="outside right center", fontsize=7, frameon=False)
    st = ic2["state"]
    blocks.append(
        ctx.figure(
            "ic2_rungs",
            fig,
            f"IC2 of Fig. 20 (theta {st['theta']:g}, varphi {st['varphi']:g}, Theta {st['Theta']:g}, Psi {st['Psi']:g}, "
            f"eta {st['eta']:g}, mu {ic2['mu']:g}) through the six rungs, up to each rung's first event or t = {ic2['run_until']:.3g}: "
            f"cause {ic2['cause']}. Rung 3's Kelvin-Voigt contact has eps = {ic2['match']['eps']:.4g}, xi = {ic2['match']['xi']:.4g}.",
            ["ic2_series.csv", "ic2.json"],
        )
    )
    blocks.append(
        Table(
            caption="IC2 through the ladder (labels as the agreement study compares them).",
            header=["rung", "model", "status", "outcome", "t", "label"],
            rows=[
                [
                    str(r["rung"]),
                    RUNG_TITLES[r["name"]],
                    r["status"],
                    r["outcome"] or "-",
                    "-" if r["time"] is None else f"{r['time']:.5g}",
                    r["label"] or "-",
                ]
                for r in ic2["rungs"]
            ],
            data=ctx.data("ic2.json"),
        )
    )
    return blocks


def finding(data: Path) -> list:
    """The findings line of the ladder: the share of MuJoCo's disagreements attributed to each cause."""
    from crosscheck.engines.mujoco.studies.ladder import NAMED_CAUSES
    from crosscheck.report.finding import Finding, read_json

    out = []
    ladder = read_json(data / "summary.json")
    if ladder and ladder.get("n_disagree"):
        counts, n = ladder["counts"], ladder["n_disagree"]
        causes = ", ".join(f"{k} {counts[k]}" for k in (*NAMED_CAUSES, "unexplained", "undetermined") if counts.get(k))
        ic2 = read_json(data / "ic2.json") or {}
        text = (
            f"{n} MuJoCo-theory disagreements laddered (of {ladder.get('n_disagreements_on_maps', n)} on the maps), "
            f"{100 * ladder['attributed']:.0f} % attributed to a named cause: {causes}"
        )
        if ic2.get("cause"):
            text += f"; the paper's IC2 (theory lifts off, MuJoCo jams): {ic2['cause']}"
        verdict = "explained" if ladder["attributed"] >= 0.9 else "partly explained"
        out.append(Finding("MuJoCo: causes of disagreement", text, verdict, SLUG))
    return out


SECTION = Section(
    slug=SLUG,
    title="The ladder: a named cause for each MuJoCo-theory disagreement",
    paper="Fig. 20 (IC2); sections 2, 4",
    params=params,
    run=run,
    render=render,
    requires=(
        "crosscheck.engines.mujoco.studies.ladder",
        "crosscheck.theory.capsule",
        "crosscheck.engines.compliant",
        "crosscheck.engines.mujoco.law",
        "crosscheck.engines.mujoco.ode",
        "crosscheck.engines.mujoco.engine",
    ),
    finding=finding,
    after=("mujoco_maps",),
)  # the full report ladders that section's saved disagreements
