"""``crosscheck validate mujoco``: the MuJoCo engine's checks, their table and JSON.

``crosscheck.studies.validate.validate`` on ``n_states`` random slipping
states: the tip acceleration with an active contact against eq. linode2 at
the capsule's contact point, the lift-off onset against Psi_L, the event
agreement (disagreement fraction and median event-time difference), no jam
below mu_P and the Corollary 4.2 states stopping above it.  Each is an
``ErrorStat`` against its tolerance in ``crosscheck.tolerances``; the report
shows the table, the jam counts and the whole JSON.
"""

from __future__ import annotations

import json

from crosscheck.report.format import engine_label
from crosscheck.report.section import Preformatted, RenderContext, RunContext, Section, SkipSection, Table, Text

SLUG = "mujoco_validate"


def params(quick: bool) -> dict:
    # The statistical tolerances of the event agreement and the jams were measured at
    # crosscheck.studies.validate.DEFAULT_STATES = 300 states; the quick report cannot afford that
    # (~1 min) and a smaller sample would test noise.
    return {"engine": "mujoco", "n_states": None if quick else 300}


def run(ctx: RunContext) -> None:
    from crosscheck.studies import validate as validation

    engine = ctx.params["engine"]
    if ctx.params["n_states"] is None:
        raise SkipSection(
            "full report only: the statistical tolerances of the event-agreement and jam checks hold for "
            f"crosscheck.studies.validate.DEFAULT_STATES = {validation.DEFAULT_STATES} random states (about a minute on 2 cores), "
            f"beyond the quick report's budget. Run `crosscheck report` (full) or `crosscheck validate {engine}`. The quick report's "
            "other MuJoCo sections cover the lift-off onset and the event agreement (maps, convergence) on small grids."
        )
    result = validation.validate(engine, ctx.params["n_states"], ctx.rng, progress=ctx.show_progress)
    (ctx.store.root / "validate.json").write_text(result.to_json() + "\n")
    ctx.store.write_table(
        "checks_per_quantity",
        {
            "quantity": [s.quantity for s in result.stats],
            "n": [s.n for s in result.stats],
            "max_abs": [s.max_abs for s in result.stats],
            "max_over_tolerance": [s.max_ratio for s in result.stats],
            "passed": [s.passed for s in result.stats],
            "tolerance": [json.dumps(s.tolerance) for s in result.stats],
            "worst_state": [
                json.dumps({k: round(v, 6) if isinstance(v, float) else v for k, v in s.worst_state.items()})
                for s in result.stats
            ],
        },
    )
    for s in result.stats:
        ctx.check(
            f"{engine_label(engine)} {s.quantity} within tolerance",
            s.passed,
            value=s.max_ratio,
            allowance=1.0,
            detail=f"max abs {s.max_abs:.3g}; {s.tolerance.get('why', '')}",
            guard=bool(s.tolerance.get("guard")),
        )


def render(ctx: RenderContext) -> list:
    doc = json.loads(ctx.store.path("validate.json").read_text())
    t = ctx.store.read_table("checks_per_quantity", text=("quantity", "passed", "tolerance", "worst_state"))
    rows, cls = [], []
    for i in range(len(t["quantity"])):
        ok = t["passed"][i] == "True"
        tol = json.loads(t["tolerance"][i])
        worst = ", ".join(
            f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
            for k, v in json.loads(t["worst_state"][i]).items()
            if k != "index"
        )
        rows.append(
            [
                t["quantity"][i],
                f"{t['n'][i]:.0f}",
                f"{t['max_abs'][i]:.3g}",
                f"{t['max_over_tolerance'][i]:.3f}",
                "ok" if ok else "FAIL",
                f"atol {tol.get('atol')}: {tol.get('why', '')}",
                worst,
            ]
        )
        cls.append("ok" if ok else "fail")
    name = engine_label(ctx.params["engine"])
    blocks = [
        Text(
            f"`crosscheck.studies.validate.validate` ({name}) with {ctx.params['n_states']} random slipping states for the event agreement: "
            f"{'every check within its tolerance' if doc['passed'] else 'SOME CHECKS EXCEED THEIR TOLERANCE'}."
        ),
        Table(
            caption="The checks: largest value, its ratio to the allowance (<= 1 passes), the tolerance and the worst state.",
            header=["check", "n", "max", "/ tolerance", "result", "tolerance", "worst state"],
            rows=rows,
            data=ctx.data("checks_per_quantity.csv", "validate.json"),
            row_class=cls,
        ),
    ]
    jams = doc.get("extra", {}).get("jams")
    if jams:
        rows = []
        for r in jams.get("below", []):
            rows.append(
                [
                    f"{r['mu']:g} (below mu_P)",
                    str(r["n"]),
                    ", ".join(f"{k.lower()}: {v}" for k, v in r["outcomes"].items()),
                    str(r["n_jam"]),
                    "",
                ]
            )
        for r in jams.get("above", []):
            ended = r.get("ended_near_fraction")
            near = ", ".join(f"{k.lower()} {100 * v:.0f}%" for k, v in r.get("near_fraction", {}).items())
            rows.append(
                [
                    f"{r['mu']:g} (Cor. 4.2 states)",
                    str(r["n"]),
                    ", ".join(f"{k.lower()}: {v}" for k, v in r["outcomes"].items()),
                    f"{100 * r['jam_fraction']:.0f}%",
                    "" if ended is None else f"{100 * ended:.0f}% ({near})",
                ]
            )
        blocks.append(
            Table(
                caption=f"Jams: {name} outcomes below mu_P = {jams['mu_P']:.4f} (random slipping states: no jam allowed) and above it (states the "
                "theory sends to p = 0 with b < 0, Corollary 4.2): jams, and how often the slip ends (by any event) near the analytic jam time.",
                header=["mu", "n", f"{name} outcomes", "jams", "slip ended near the analytic jam"],
                rows=rows,
                data=ctx.data("validate.json"),
            )
        )
    blocks.append(
        Preformatted(
            json.dumps(doc, indent=1), title=f"validate JSON (crosscheck validate {ctx.params['engine']} --json)"
        )
    )
    return blocks


SECTION = Section(
    slug=SLUG,
    title="MuJoCo: validate (contact acceleration, onset, event agreement, jams)",
    paper="eqs. linode2, psil, FZ; Corollary 4.2",
    params=params,
    run=run,
    render=render,
    requires=("crosscheck.studies.validate", "crosscheck.engines.mujoco.engine"),
)
