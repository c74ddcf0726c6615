"""``crosscheck validate mujoco``: the MuJoCo leg's four checks (issue 4 item 5), their table and JSON.

``crosscheck.validate_mujoco.validate`` on ``n_states`` random slipping
states: 5a the tip acceleration with an active contact against eq. linode2,
5b the lift-off onset against Psi_L, 5c the event agreement (disagreement
fraction and median event-time difference), 5d no jam below mu_P and the
Corollary 4.2 states stopping above it.  Each is an ``ErrorStat`` against
its tolerance in ``crosscheck.tolerances``; the report shows the table, the
jam counts of 5d and the whole JSON.
"""

from __future__ import annotations

import json

from crosscheck.report.section import Preformatted, RenderContext, RunContext, Section, SkipSection, Table, Text

SLUG = "mujoco_validate"


def params(quick: bool) -> dict:
    # The statistical tolerances of 5c and 5d were measured at validate_mujoco.DEFAULT_STATES = 300
    # states; the quick report cannot afford that (~1 min) and a smaller sample would test noise.
    return {"n_states": None if quick else 300}


def run(ctx: RunContext) -> None:
    from crosscheck import validate_mujoco

    if ctx.params["n_states"] is None:
        raise SkipSection("full report only: the statistical tolerances of checks 5c and 5d hold for validate_mujoco.DEFAULT_STATES = "
                          f"{validate_mujoco.DEFAULT_STATES} random states (about a minute on 2 cores), beyond the quick report's budget. "
                          "Run `crosscheck report` (full) or `crosscheck validate mujoco`. The quick report's other MuJoCo sections cover "
                          "5b (lift-off onset) and 5c (agreement maps, convergence) on small grids.")
    result = validate_mujoco.validate(ctx.params["n_states"], ctx.rng, progress=ctx.show_progress)
    (ctx.store.root / "validate.json").write_text(result.to_json() + "\n")
    ctx.store.write_table("checks_per_quantity", {
        "quantity": [s.quantity for s in result.stats], "n": [s.n for s in result.stats], "max_abs": [s.max_abs for s in result.stats],
        "max_over_tolerance": [s.max_ratio for s in result.stats], "passed": [s.passed for s in result.stats],
        "tolerance": [json.dumps(s.tolerance) for s in result.stats],
        "worst_state": [json.dumps({k: round(v, 6) if isinstance(v, float) else v for k, v in s.worst_state.items()}) for s in result.stats]})
    for s in result.stats:
        ctx.check(f"MuJoCo {s.quantity} within tolerance", s.passed, value=s.max_ratio, allowance=1.0, detail=f"max abs {s.max_abs:.3g}; {s.tolerance.get('why', '')}")


def render(ctx: RenderContext) -> list:
    doc = json.loads(ctx.store.path("validate.json").read_text())
    t = ctx.store.read_table("checks_per_quantity", text=("quantity", "passed", "tolerance", "worst_state"))
    rows, cls = [], []
    for i in range(len(t["quantity"])):
        ok = t["passed"][i] == "True"
        tol = json.loads(t["tolerance"][i])
        worst = ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in json.loads(t["worst_state"][i]).items() if k != "index")
        rows.append([t["quantity"][i], f"{t['n'][i]:.0f}", f"{t['max_abs'][i]:.3g}", f"{t['max_over_tolerance'][i]:.3f}", "ok" if ok else "FAIL",
                     f"atol {tol.get('atol')}: {tol.get('why', '')}", worst])
        cls.append("ok" if ok else "fail")
    blocks = [Text(f"`crosscheck.validate_mujoco.validate` with {ctx.params['n_states']} random slipping states for 5c: "
                   f"{'every check within its tolerance' if doc['passed'] else 'SOME CHECKS EXCEED THEIR TOLERANCE'}."),
              Table(caption="The checks: largest value, its ratio to the allowance (<= 1 passes), the tolerance and the worst state.",
                    header=["check", "n", "max", "/ tolerance", "result", "tolerance", "worst state"], rows=rows, data=ctx.data("checks_per_quantity.csv", "validate.json"),
                    row_class=cls)]
    jams = doc.get("extra", {}).get("jams")
    if jams:
        rows = []
        for r in jams.get("below", []):
            for c in ("part_a", "effective"):
                rows.append([f"{r['mu']:g} (below mu_P)", c, str(r["n"]), ", ".join(f"{k.lower()}: {v}" for k, v in r[c]["outcomes"].items()), str(r[c]["n_jam"]), ""])
        for r in jams.get("above", []):
            for c in ("part_a", "effective"):
                ended = r[c].get("ended_near_fraction")
                near = ", ".join(f"{k.lower()} {100 * v:.0f}%" for k, v in r[c].get("near_fraction", {}).items())
                rows.append([f"{r['mu']:g} (Cor. 4.2 states)", c, str(r["n"]), ", ".join(f"{k.lower()}: {v}" for k, v in r[c]["outcomes"].items()),
                             f"{100 * r[c]['jam_fraction']:.0f}%", "" if ended is None else f"{100 * ended:.0f}% ({near})"])
        blocks.append(Table(caption=f"5d: MuJoCo outcomes below mu_P = {jams['mu_P']:.4f} (random slipping states: no jam allowed) and above it (states the theory sends to "
                                    "p = 0 with b < 0, Corollary 4.2): jams, and how often MuJoCo's slipping ends (by any event) near the analytic jam time.",
                            header=["mu", "classifier", "n", "MuJoCo outcomes", "jams", "slip ended near the analytic jam"], rows=rows, data=ctx.data("validate.json")))
    blocks.append(Preformatted(json.dumps(doc, indent=1), title="validate JSON (crosscheck validate mujoco --json)"))
    return blocks


SECTION = Section(slug=SLUG, title="MuJoCo: validate (contact acceleration, onset, event agreement, jams)", paper="eqs. linode2, psil, FZ; Corollary 4.2; issue 4 item 5",
                  params=params, run=run, render=render, requires=("crosscheck.validate_mujoco", "crosscheck.mujoco_agreement"))
