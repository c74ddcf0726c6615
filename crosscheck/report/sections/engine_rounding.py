"""An engine's outcomes against the last bits of its starts: the slipping starts of its maps rerun 1 and 2 ulp of theta away.

The starts are those of the engine's outcome maps (``engine_maps``'s grids at
its sizes) that slip at t = 0 (b < 0 < p, the starts the maps compare), an
even spread of at most ``max_starts`` of them; each is rerun with theta moved
by -2, -1, +1 and +2 units in the last place (``crosscheck.studies.rounding``)
and the starts whose outcome changes are counted and listed.  An outcome that
hangs on the last bit of a start is not the engine's answer to the start.
One section per engine with maps (``<slug>_rounding``).  Scaled units (section 2.1).
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table, Text

#: The most starts rerun, an even spread over the maps' slipping starts: each costs 5 runs, and a Drake run ~0.1-0.3 s
#: (measured: 108 starts x 5 runs of Drake SAP at the quick maps' options took 46 s on 2 shared cores; 30 starts of
#: Drake continuous took 37 s of section time in the full report, Lagged's 18 s, MuJoCo Warp's 11 s: 12 keep each
#: under ~15 s).
MAX_STARTS = {"quick": 12, "full": 12}


def params(quick: bool, engine: str, options: dict, n: dict | None) -> dict:
    from crosscheck.report.sections import engine_maps

    key = "quick" if quick else "full"
    base = engine_maps.params(quick, engine, options, n=None if n is None else n[key])
    return {
        "engine": engine,
        "alpha": base["alpha"],
        "horizon": base["horizon"],
        "options": base["options"],
        "maps": base["maps"],
        "max_starts": MAX_STARTS[key],
    }


def _starts(P: dict):
    from crosscheck.report.sections.engine_maps import _grid
    from crosscheck.state import SlipState
    from crosscheck.theory import analytic

    keys = ("theta", "varphi", "Theta", "Psi", "eta", "mu")
    states, mus, where = [], [], []
    for m in P["maps"]:
        _, x, y = _grid(m)
        axes = {k: (m["fixed"][k],) if k in m["fixed"] else None for k in keys}
        axes[m["x"]], axes[m["y"]] = tuple(x), tuple(y)
        for combo in itertools.product(*(axes[k] for k in keys)):
            d = dict(zip(keys, (float(c) for c in combo)))
            mu = d.pop("mu")
            if analytic.b(d["Psi"], d["Theta"], d["theta"]) < 0 < analytic.p(d["theta"], d["varphi"], mu, P["alpha"]):
                states.append(SlipState(**d))
                mus.append(mu)
                where.append(m["name"])
    if len(states) > P["max_starts"]:
        keep = np.linspace(0, len(states) - 1, P["max_starts"]).round().astype(int)
        states, mus, where = [states[k] for k in keep], [mus[k] for k in keep], [where[k] for k in keep]
    return states, mus, where


def run(ctx: RunContext) -> None:
    from crosscheck.studies.rounding import ULPS, ulp_sensitivity

    P = ctx.params
    states, mus, where = _starts(P)
    r = ulp_sensitivity(P["engine"], states, mus, alpha=P["alpha"], horizon=P["horizon"], **P["options"])
    rows = {
        "map": [where[i] for i in r["changed_index"]],
        "mu": [mus[i] for i in r["changed_index"]],
        **{k: [getattr(states[i], k) for i in r["changed_index"]] for k in ("theta", "varphi", "Theta", "Psi", "eta")},
        **{f"ulp_{k}": [r["outcomes"][str(k)][i] for i in r["changed_index"]] for k in (0, *ULPS)},
    }
    ctx.store.write_table("changed", rows)
    ctx.store.write_json("summary", {"engine": P["engine"], "n": r["n"], "changed": r["changed"], "ulps": list(ULPS)})


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.studies.rounding import ULPS

    P = ctx.params
    name = engine_label(P["engine"])
    s = ctx.store.read_json("summary")
    t = ctx.store.read_table("changed", text=("map", *(f"ulp_{k}" for k in (0, *ULPS))))
    blocks = [
        Text(
            f"{name}: {s['changed']} of {s['n']} slipping starts of its maps change outcome when theta moves by "
            f"{', '.join(f'{k:+d}' for k in ULPS)} ulp."
        )
    ]
    if s["changed"]:
        rows = [
            [
                t["map"][i],
                f"theta {t['theta'][i]:.17g}, varphi {t['varphi'][i]:.3g}, Theta {t['Theta'][i]:.3g}, Psi {t['Psi'][i]:.3g}",
                f"{t['mu'][i]:.3g}",
                *[str(t[f"ulp_{k}"][i]).lower() for k in (-2, -1, 0, 1, 2)],
            ]
            for i in range(len(t["map"]))
        ]
        blocks.append(
            Table(
                caption=f"The starts whose {name} outcome hangs on the last bits of theta.",
                header=["map", "start", "mu", "-2 ulp", "-1 ulp", "at theta", "+1 ulp", "+2 ulp"],
                rows=rows,
                data=ctx.data("changed.csv"),
            )
        )
    return blocks


def finding(data: Path) -> list:
    """The findings line: the count of the engine's map starts whose outcome moves with the last bits of theta."""
    from crosscheck.report.finding import Finding, read_json
    from crosscheck.report.format import engine_label

    s = read_json(data / "summary.json")
    if not s:
        return []
    name = engine_label(s["engine"])
    return [
        Finding(
            f"{name}: outcomes against rounding",
            f"{s['changed']} of {s['n']} slipping starts of its maps change outcome within 2 ulp of theta",
            "agrees" if s["changed"] == 0 else "disagrees",
            data.name,
            why="agrees when no start's outcome changes as theta moves by up to 2 ulp",
        )
    ]


def section(spec, options: dict, n: dict | None) -> Section:
    """The rounding section ``<slug>_rounding`` of the engine ``spec`` at its maps' ``options`` and sizes ``n``."""
    return Section(
        slug=f"{spec.slug}_rounding",
        title=f"{spec.label}: outcomes that hang on the last bits of a start",
        paper="",
        params=lambda quick: params(quick, spec.name, options["quick" if quick else "full"], n),
        run=run,
        render=render,
        requires=("crosscheck.studies.rounding", spec.module or "crosscheck.engines"),
        finding=finding,
    )
