"""MuJoCo Warp (Newton, float32) against MuJoCo in C (float64) at the same settings, and Warp's kernel loads.

The two run the same model: the capsule rod of ``models/rod.xml``, Euler, Newton's method, elliptic cone, the same
solref, solimp, impratio, condim and timestep (``crosscheck.engines.newton.model``); MuJoCo Warp runs it in float32 on
Warp's CPU device, MuJoCo in C in float64.  From seeded random slipping starts this section runs both and counts
the starts whose first event is the same, and how far apart the event times are.  Where they differ the rounding of
float32 (~6e-8 relative per operation) is the only difference of model: the section lists those starts.  One
mechanism is the start itself: placed touching (z_A = r, the capsule at distance 0 from the plane), its float32
copy can sit ~1e-8 l inside the plane, and MuJoCo's contact at margin 0 exists iff the distance is negative, so
MuJoCo Warp can take a contact step that MuJoCo in C does not (a lift-off one step late).  It also
records the CPU seconds this report's process spent in each Newton solver's first step (Warp compiles the solver's
kernels there when its disk cache is cold, else loads them), kept out of every per-step cost.

Scaled units (section 2.1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text

SLUG = "newton_mujoco_c"


def params(quick: bool) -> dict:
    return {
        "n": 16 if quick else 64,
        "alpha": 3.0,
        "horizon": 1.0,
        "timestep": 3e-3 if quick else 1e-3,
        "mu": [0.2, 1.5],
    }


def run(ctx: RunContext) -> None:
    from crosscheck import Rod, SlipState, engines
    from crosscheck.engines.newton.model import compile_seconds

    P = ctx.params
    rng = ctx.rng
    states = [
        SlipState(
            theta=rng.uniform(0.05, 1.5),
            varphi=-rng.uniform(0.0, 3.1),
            Theta=rng.normal(),
            Psi=2 * rng.normal(),
            eta=rng.uniform(0, 2),
            psi=rng.uniform(-np.pi, np.pi),
        )
        for _ in range(P["n"])
    ]
    mu = rng.uniform(*P["mu"], P["n"])
    rod = Rod.scaled(P["alpha"])
    opts = {"timestep": P["timestep"]}
    warp = engines.get("newton_mujoco").sweep(rod, states, mu, horizon=P["horizon"], progress=False, **opts)
    c = engines.get("mujoco").sweep(rod, states, mu, horizon=P["horizon"], progress=False, **opts)
    cols = {k: [getattr(s, k) for s in states] for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi")}
    ctx.store.write_table(
        "starts",
        {
            **cols,
            "mu": mu,
            "warp_outcome": warp.outcome,
            "warp_time": warp.event_time,
            "c_outcome": c.outcome,
            "c_time": c.event_time,
        },
    )
    ctx.store.write_json("first_steps", compile_seconds())


def render(ctx: RenderContext) -> list:
    from crosscheck.outcome import Outcome

    P = ctx.params
    x = ctx.store.read_table("starts")
    same = x["warp_outcome"] == x["c_outcome"]
    both = same & np.isfinite(x["c_time"])
    dt = np.abs(x["warp_time"] - x["c_time"])[both]
    first = ctx.store.read_json("first_steps") or {}
    differ = np.flatnonzero(~same)
    return [
        Text(
            f"{len(same)} random slipping starts (mu in [{P['mu'][0]:g}, {P['mu'][1]:g}], horizon {P['horizon']:g}, "
            f"timestep {P['timestep']:g}): MuJoCo Warp in float32 makes MuJoCo in C's first event at "
            f"{int(same.sum())} of them; where both have an event, the times differ by at most "
            f"{(dt.max() if dt.size else 0.0):.3g} (median {(np.median(dt) if dt.size else 0.0):.3g})."
        ),
        Table(
            caption="Starts whose first event differs between MuJoCo Warp (float32) and MuJoCo in C (float64).",
            header=["theta", "varphi", "Theta", "Psi", "eta", "mu", "MuJoCo Warp", "MuJoCo C"],
            rows=[
                [
                    *(f"{x[k][i]:.3f}" for k in ("theta", "varphi", "Theta", "Psi", "eta", "mu")),
                    f"{Outcome(int(x['warp_outcome'][i])).name} {x['warp_time'][i]:.3f}",
                    f"{Outcome(int(x['c_outcome'][i])).name} {x['c_time'][i]:.3f}",
                ]
                for i in differ
            ],
            data=ctx.data("starts.csv"),
        ),
        Text(
            "CPU seconds of each Newton solver's first step in this report's process (Warp's kernel compilation "
            "when its cache was cold, else loading them; no per-step cost includes it): "
            + (", ".join(f"{k} {v:.2f}" for k, v in sorted(first.items())) or "none recorded")
            + ".  From an empty cache: python benchmarks/bench_newton.py --cold."
        ),
    ]


def finding(data: Path) -> list:
    """The findings line: MuJoCo Warp's first events against MuJoCo in C's."""
    from crosscheck.report.finding import Finding
    from crosscheck.report.store import SectionStore

    try:
        x = SectionStore(data).read_table("starts")
    except FileNotFoundError:  # no saved results: no line
        return []
    same = x["warp_outcome"] == x["c_outcome"]
    return [
        Finding(
            "Newton: MuJoCo Warp against MuJoCo in C",
            f"MuJoCo Warp in float32 makes MuJoCo in C's first event at {int(same.sum())} of {len(same)} random "
            "slipping starts at the same settings",
            "agrees" if same.all() else "disagrees",
            SLUG,
            why="disagrees when any start's first event differs: the model is the same, float32 the only difference",
        )
    ]


SECTION = Section(
    slug=SLUG,
    title="Newton: MuJoCo Warp (float32) against MuJoCo in C (float64), and Warp's kernel loads",
    paper="",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.engines.newton.model",),
    finding=finding,
)
