"""An engine across the paper's critical values of Psi: its jams at slipping starts across Psi_2 and its choice at
indeterminate starts above Psi_1 (``crosscheck.studies.psi_critical``).

Slipping starts (b < 0 < p) at mu = 1.4 with |Psi| spread over (1.5, 5), the same for every engine (drawn from the
report's seed), run on the engine at its maps' options and by the theory's slipping flow to ``horizon``: their
outcomes by |Psi| (the figure is ``psi_engines``'), the jams in each band of ``BANDS`` and the jams with |Psi| > Psi_2
at the jam row, which the paper's theorem rules out.  Indeterminate starts at Theta = 0 (p < 0 < b, |Psi| in (Psi_1,
5)) run at the maps' options and at each of the engine's convergence settings: what it chooses (lift-off or an
impulsive stop) and whether the choice stays as the timestep and the contact time shrink, beside the compliant theory's
prediction for a contact that starts untouched.  One section per engine with maps (``<slug>_psi``).  Scaled units.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table

#: Starts by cost (measured 15-40 ms per engine run at the maps' options, horizon 0.5; 8 engines share 2 cores): quick
#: 24 slipping and 4 indeterminate starts (~1-2 s per engine, 5 at most while the other sections run), full 120 and 12
#: (~5-8 s per engine; the full report's eight sections add ~30 s of its wall time on 2 cores).
#: These are an engine's at the default map size; an engine with smaller maps gets its share (``_scaled``).
N_STARTS = {"quick": {"slipping": 24, "indeterminate": 4}, "full": {"slipping": 120, "indeterminate": 12}}


def _scaled(engine: str, key: str) -> dict:
    """``N_STARTS`` times the engine's cost scale (``engine_impact.cost_scale``), at least 4 slipping and 1
    indeterminate."""
    from crosscheck.report.sections.engine_impact import cost_scale

    k = cost_scale(engine, key)
    n = N_STARTS[key]
    return {"slipping": max(4, round(n["slipping"] * k)), "indeterminate": max(1, round(n["indeterminate"] * k))}


def params(quick: bool, engine: str, options: dict, convergence: list | None) -> dict:
    key = "quick" if quick else "full"
    return {
        "engine": engine,
        "alpha": 3.0,
        "mu": 1.4,
        "horizon": 0.5,
        "indeterminate_horizon": 0.1,
        "abs_Psi": [1.5, 5.0],  # from just below Psi_L: most starts in the bands around Psi_1 and Psi_2
        "options": dict(options),
        "settings": [dict(options), *[dict(s) for s in convergence or () if dict(s) != dict(options)]],
        **_scaled(engine, key),
    }


def run(ctx: RunContext) -> None:
    from crosscheck import engines
    from crosscheck.outcome import Outcome
    from crosscheck.rod import Rod
    from crosscheck.studies import psi_critical as pc
    from crosscheck.theory import critical

    P = ctx.params
    spec, rod, mu, alpha = engines.get(P["engine"]), Rod.scaled(P["alpha"]), P["mu"], P["alpha"]
    cv = critical.critical_values(mu=mu, alpha=alpha)
    rng = pc.starts_rng(ctx.seed)
    S = pc.slipping_starts(P["slipping"], rng, mu, alpha, abs_Psi=tuple(P["abs_Psi"]))
    th = pc.theory_events(S, mu, alpha, horizon=P["horizon"])
    en = pc.engine_events(spec, rod, S, mu, horizon=P["horizon"], options=P["options"])
    cols = {k: [getattr(s, k) for s in S] for k in ("theta", "varphi", "Theta", "Psi", "eta")}
    cols.update({f"theory_{k}": v for k, v in th.items()})
    cols.update({f"engine_{k}": v for k, v in en.items()})
    ctx.store.write_table("slipping", cols)
    ruled_out = pc.ruled_out_jams(en["outcome"], en["Psi_event"], mu, alpha)
    ctx.check(
        f"the theory's slipping flow never jams with |Psi| > Psi_2 = {cv.Psi_2:.4f}",
        not pc.ruled_out_jams(th["outcome"], th["Psi_event"], mu, alpha).any(),
        value=int(pc.ruled_out_jams(th["outcome"], th["Psi_event"], mu, alpha).sum()),
        allowance=0,
        detail="section 3.3: for |Psi| >= Psi_2 no state has p < 0 with b < 0",
    )
    aP = np.abs(np.array(cols["Psi"]))
    bands = []
    for lo, hi in pc.BANDS:
        m = (aP > lo) & (aP < hi)
        bands.append(
            {
                "lo": lo,
                "hi": hi,
                "n": int(m.sum()),
                "theory_jams": int((th["outcome"][m] == Outcome.JAM).sum()),
                "engine_jams": int((en["outcome"][m] == Outcome.JAM).sum()),
            }
        )
    I = pc.indeterminate_starts(P["indeterminate"], rng, mu, alpha)
    icols = {k: [getattr(s, k) for s in I] for k in ("theta", "varphi", "Psi", "eta")}
    icols["compliant_prediction"] = [pc.compliant_prediction(s, mu, alpha) for s in I]
    settings = []
    for j, opts in enumerate(P["settings"]):
        e = pc.engine_events(spec, rod, I, mu, horizon=P["indeterminate_horizon"], options=opts)
        icols[f"choice_{j}"] = [Outcome(int(o)).name for o in e["outcome"]]
        o = spec.options(**opts)
        settings.append(
            {
                "options": opts,
                "contact_time": float(o.contact_time),
                "timestep": float(o.timestep),
                "choices": {c: icols[f"choice_{j}"].count(c) for c in sorted(set(icols[f"choice_{j}"]))},
            }
        )
    ctx.store.write_table("indeterminate", icols)
    ctx.store.write_json("summary", _summary(spec, cv, bands, ruled_out, en, cols, icols, settings))


def _summary(spec, cv, bands, ruled_out, en, cols, icols, settings) -> dict:
    finest = sorted(range(len(settings)), key=lambda j: (settings[j]["contact_time"], settings[j]["timestep"]))[:2]
    same = None
    if len(finest) == 2 and icols["theta"]:
        a, b = icols[f"choice_{finest[0]}"], icols[f"choice_{finest[1]}"]
        same = sum(x == y for x, y in zip(a, b)) / len(a)
    compliant = "compliant" in spec.tags
    agree = None
    if compliant and icols["theta"]:
        agree = sum(c == p for c, p in zip(icols["choice_0"], icols["compliant_prediction"])) / len(icols["theta"])
    return {
        "engine": spec.name,
        "Psi_L": cv.Psi_L,
        "Psi_1": cv.Psi_1,
        "Psi_2": cv.Psi_2,
        "n_slipping": len(cols["theta"]),
        "bands": bands,
        "ruled_out_jams": int(ruled_out.sum()),
        "ruled_out": [
            {"Psi_start": float(cols["Psi"][i]), "Psi_jam": float(en["Psi_event"][i]), "t": float(en["time"][i])}
            for i in np.flatnonzero(ruled_out)
        ],
        "n_indeterminate": len(icols["theta"]),
        "settings": settings,
        "same_choice_two_finest": same,
        "compliant_prediction_applies": compliant,
        "compliant_prediction_agreement": agree,
    }


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label

    P = ctx.params
    name = engine_label(P["engine"])
    s = ctx.store.read_json("summary")
    rows = [
        [f"|Psi| in ({b['lo']:g}, {b['hi']:g})", str(b["n"]), str(b["theory_jams"]), str(b["engine_jams"])]
        for b in s["bands"]
    ]
    blocks = [
        Table(
            caption=(
                f"{name}'s jams at {s['n_slipping']} slipping starts (b < 0 < p, mu = {P['mu']:g}, horizon "
                f"{P['horizon']:g}) "
                f"across Psi_2 = {s['Psi_2']:.4f}, against the theory's slipping flow. Jams with |Psi| > Psi_2 at the "
                "jam row, "
                f"which the paper's theorem rules out (no inconsistent state exists there): {s['ruled_out_jams']}."
            ),
            header=["band", "starts", "theory jams", f"{name} jams"],
            rows=rows,
            data=ctx.data("slipping.csv", "summary.json"),
        )
    ]
    same = s["same_choice_two_finest"]
    pred = (
        f"; the compliant theory predicts LIFTOFF at every one for a contact that starts untouched, and {name} agrees "
        "at "
        f"{100 * s['compliant_prediction_agreement']:.0f} %"
        if s["compliant_prediction_applies"] and s["compliant_prediction_agreement"] is not None
        else ""
    )
    blocks.append(
        Table(
            caption=(
                f"{name} at {s['n_indeterminate']} indeterminate starts (Theta = 0, p < 0 < b, |Psi| in (Psi_1 = "
                f"{s['Psi_1']:.4f}, 5)), where the rigid theory allows both a lift-off and an impulsive stop: its "
                "choices "
                "per setting"
                + (
                    ""
                    if same is None
                    else f"; the same choice at its two finest settings at {100 * same:.0f} % of them"
                )
                + pred
                + "."
            ),
            header=["setting", "contact time", "timestep", "choices"],
            rows=[
                [
                    str(x["options"]),
                    f"{x['contact_time']:.3g}",
                    f"{x['timestep']:.3g}",
                    ", ".join(f"{k} {v}" for k, v in x["choices"].items()),
                ]
                for x in s["settings"]
            ],
            data=ctx.data("indeterminate.csv", "summary.json"),
        )
    )
    return blocks


def section(spec, options: dict) -> Section:
    """The section ``<slug>_psi`` of the engine ``spec`` at its maps' ``options`` ({"quick": ..., "full": ...})."""
    plan = spec.report
    conv = None if plan is None else plan.convergence
    return Section(
        slug=f"{spec.slug}_psi",
        title=f"{spec.label}: the critical values Psi_1 and Psi_2",
        paper="section 3.3, eqs. psi1, psi2",
        params=lambda quick: params(
            quick,
            spec.name,
            options["quick" if quick else "full"],
            None if conv is None else conv["quick" if quick else "full"],
        ),
        run=run,
        render=render,
        requires=("crosscheck.studies.psi_critical", spec.module or "crosscheck.engines"),
    )
