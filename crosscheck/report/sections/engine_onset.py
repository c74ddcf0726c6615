"""An engine's lift-off onset against Psi_L (eq. psil) at the options of its outcome maps.

At theta = theta_L, Theta = 0, varphi = -pi/2 (eta = 1) the free acceleration
b changes sign at Psi = Psi_L for every mu: below it the rigid rod slips, above
it lifts off at once.  ``crosscheck.studies.onset.liftoff_onset`` bisects on
Psi for the smallest value at which the engine reports LIFTOFF at t = 0.  One
section per registered engine with maps (``<slug>_liftoff``) unless the engine
declares its own (MuJoCo's, over its timestep).  Where the engine declares an
event-tolerance profile its ``liftoff_onset`` allowance is checked; otherwise
the error is reported and not judged.  An engine with no single threshold in
the bracket (it lifts off below Psi_L - width, never lifts off at t = 0, or
alternates) is reported as such.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table


def params(quick: bool, engine: str, options: dict) -> dict:
    return {
        "engine": engine,
        "options": dict(options),
        "alpha": 3.0,
        "mu": [0.5, 1.4] if quick else [0.3, 0.5, 1.0, 1.4, 3.0],
        "half_width": 0.05,
        "n_per_round": 17 if quick else 33,
        "rounds": 4 if quick else 5,
    }


def run(ctx: RunContext) -> None:
    from crosscheck import engines
    from crosscheck.rod import Rod
    from crosscheck.studies.onset import liftoff_onset
    from crosscheck.theory import critical

    P = ctx.params
    spec = engines.get(P["engine"])
    rod = Rod.scaled(P["alpha"])
    cols = {k: [] for k in ("mu", "timestep", "onset", "resolution", "onset_minus_Psi_L")}
    notes = {}
    timestep = spec.options(**P["options"]).timestep
    for mu in ctx.progress(P["mu"], desc="lift-off onset"):
        try:
            onset, res = liftoff_onset(
                rod,
                mu,
                engine=spec.name,
                rounds=P["rounds"],
                n=P["n_per_round"],
                half_width=P["half_width"],
                **P["options"],
            )
        except ValueError as e:  # no single threshold in the bracket: reported, not hidden
            onset, res = math.nan, math.nan
            notes[f"{mu:g}"] = str(e)
        for k, v in (
            ("mu", mu),
            ("timestep", timestep),
            ("onset", onset),
            ("resolution", res),
            ("onset_minus_Psi_L", onset - critical.Psi_L),
        ):
            cols[k].append(v)
        tol = (spec.tolerances or {}).get("liftoff_onset")
        if tol is not None:
            err = onset - critical.Psi_L
            ctx.check(
                f"mu = {mu:g}: {spec.label}'s lift-off onset = Psi_L = {critical.Psi_L:.7f}",
                bool(-res <= err <= tol.atol + res),
                value=err,
                allowance=tol.atol + res,
                detail=f"onset {onset:.9f}, grid resolution {res:.1e}; {tol.why}",
            )
    ctx.store.write_table("onset", cols)
    ctx.store.write_json("notes", notes)


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.theory import critical

    P = ctx.params
    name = engine_label(P["engine"])
    t = ctx.store.read_table("onset")
    notes = ctx.store.read_json("notes")
    rows = [
        [
            f"{t['mu'][i]:g}",
            f"{t['timestep'][i]:g}",
            f"{t['onset'][i]:.10f}" if np.isfinite(t["onset"][i]) else "no single threshold",
            f"{t['resolution'][i]:.1e}",
            f"{t['onset_minus_Psi_L'][i]:+.2e}",
        ]
        for i in range(len(t["mu"]))
    ]
    caption = (
        f"{name}: the smallest Psi at which it reports LIFTOFF at t = 0 from theta_L, Theta = 0, varphi = -pi/2, eta = 1, against "
        f"Psi_L = {critical.Psi_L:.10f} (eq. psil), options {P['options']}, bisected from Psi_L +- {P['half_width']:g} "
        f"({P['rounds']} rounds of {P['n_per_round']} runs)."
    )
    if notes:
        caption += " No single threshold at mu = " + "; ".join(f"{mu}: {why}" for mu, why in notes.items()) + "."
    return [
        Table(
            caption=caption,
            header=["mu", "timestep", "onset", "resolution", "onset - Psi_L"],
            rows=rows,
            data=ctx.data("onset.csv", "notes.json"),
        )
    ]


def section(spec, options: dict) -> Section:
    """The onset section ``<slug>_liftoff`` of the engine ``spec`` at ``options`` ({"quick": ..., "full": ...})."""
    return Section(
        slug=f"{spec.slug}_liftoff",
        title=f"{spec.label}: lift-off onset against Psi_L",
        paper="eqs. thetal, psil (section 3.3)",
        params=lambda quick: params(quick, spec.name, options["quick" if quick else "full"]),
        run=run,
        render=render,
        requires=("crosscheck.studies.onset", spec.module or "crosscheck.engines"),
    )
