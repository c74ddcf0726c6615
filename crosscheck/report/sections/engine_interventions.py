"""An engine's interventions: each laddered disagreement rerun with the engine changed the way each cause names.

The starts are those of the engine's ladder section (``<slug>_ladder``, or
MuJoCo's own ``ladder``): every disagreement it laddered, at the options,
alpha and horizon it used.  Each runs through every intervention the engine
declares (``crosscheck.studies.interventions``).  One section per engine with
a ladder section and declared interventions (``<slug>_interventions``), after
that ladder.  Scaled units (section 2.1).  The runs: ``engine_intervention_runs``; here the figures, tables and
findings line.
"""

from __future__ import annotations

from pathlib import Path

from crosscheck.report.finding import CONFIRMED_SHARE
from crosscheck.report.section import RenderContext, Section, Table, Text
from crosscheck.report.sections.engine_intervention_runs import params, run

#: A least eq. p below 1, to ask an engine what it adds near p = 0 (``_near_p0``).
_EXAMPLE_P = 0.01


def _near_p0(spec, cause: str, base) -> str:
    """What a cause adds for a start whose theory slip passes close to p = 0 (``EngineSpec.interventions_for``'s p_min)."""
    given = spec.interventions_for(cause, base)
    extra = spec.interventions_for(cause, base, p_min=_EXAMPLE_P)[len(given) :]
    if not extra:
        return ""
    return ", then, where the theory's slip passes closer to p = 0 than p = 1, " + "; ".join(iv.text for iv in extra)


def _mark(rows: list[dict]) -> str:
    """Each intervention's label, weakest first, "removes" after those that bring the theory's outcome."""
    return " / ".join(
        "failed" if r["status"] != "ok" else r["label"].lower() + (" (removes)" if r["removes"] else "") for r in rows
    )


def _figure(ctx: RenderContext, name: str, summary: dict):
    """Per cause the ladder named: starts confirmed by their own intervention, removed by another's, by none (stacked bars)."""
    import matplotlib.pyplot as plt

    causes = list(summary["per_cause"])
    over = [pairs_confirmed(summary["per_cause"][c]) for c in causes]
    parts = [
        (
            "confirmed by its own intervention",
            [summary["per_cause"][c]["confirmed"] - k for c, k in zip(causes, over)],
            "#2a9d4b",
        ),
        ("confirmed overdetermined (the ladder's pair, by both together)", over, "#8fd19e"),
        ("removed by another cause's instead", [other_starts(summary["per_cause"][c]) for c in causes], "#e9a23b"),
        (
            "removed only jointly with another cause's",
            [sum(summary["per_cause"][c].get("jointly", {}).values()) for c in causes],
            "#6c8ebf",
        ),
        ("removed by none", [summary["per_cause"][c]["none"] for c in causes], "#c0392b"),
    ]
    fig, ax = plt.subplots(figsize=(7.0, 0.9 + 0.55 * len(causes)), layout="constrained")
    left = [0] * len(causes)
    for label, counts, colour in parts:
        ax.barh(causes, counts, left=left, color=colour, label=label)
        left = [a + b for a, b in zip(left, counts)]
    ax.invert_yaxis()
    ax.set_xlabel("laddered disagreements")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, fontsize=8, frameon=False)
    return ctx.figure(
        "interventions",
        fig,
        f"{name}: per cause the ladder named, its disagreements removed by the cause's own "
        "intervention on the engine; where the ladder found them overdetermined, by its pair's two "
        "interventions together; by another cause's; only by the cause's and another cause's together "
        "where the ladder did not find that; or by none.",
        ["summary.json"],
    )


def render(ctx: RenderContext) -> list:
    from crosscheck import engines
    from crosscheck.report.format import engine_label

    P = ctx.params
    name = engine_label(P["engine"])
    summary, results = ctx.store.read_json("summary"), ctx.store.read_json("interventions")
    spec = engines.get(P["engine"])
    base = spec.options(**summary["options"])
    what = "; ".join(
        f"{c}: " + ", then ".join(iv.text for iv in spec.interventions_for(c, base)) + _near_p0(spec, c, base)
        for c in summary["causes"]
    )
    blocks = [
        Text(
            f"{name} changed the way each cause names, from the laddered starts: {what}. A cause is confirmed when one of its "
            f"interventions brings {name}'s outcome (compared as the agreement study compares) to the theory's; the table counts "
            "those confirmed at a weaker step but not at the strongest (the stronger one brings an artefact of its own, such as a "
            "launch in the first step)."
        )
    ]
    rows = _cause_rows(summary)
    if summary["per_cause"]:
        blocks.append(_figure(ctx, name, summary))
    head = _headline(summary)
    blocks.append(
        Table(
            caption=f"{name}: {head} Per cause named by the ladder: starts, confirmed by its own intervention, removed by "
            "another cause's interventions instead (a misattribution to look into), removed only jointly with "
            "another cause of the ladder, removed by none.",
            header=[
                "cause (ladder)",
                "starts",
                "confirmed",
                "removed by another cause instead",
                "removed only jointly",
                "removed by none",
            ],
            rows=rows or [["(no laddered disagreement)", "0", "0", "-", "-", "0"]],
            data=ctx.data("summary.json"),
        )
    )
    blocks += _detail_tables(ctx, name, summary, results)
    return blocks


def _cause_rows(summary: dict) -> list[list[str]]:
    """One row per cause the ladder named: starts, confirmed (with notes), removed by another cause, jointly, by none."""
    rows = []
    for cause, r in summary["per_cause"].items():
        other = ", ".join(f"{c} {n}" for c, n in sorted(r["by_other"].items())) or "-"
        joint = ", ".join(f"with {c} {n}" for c, n in sorted((r.get("jointly") or {}).items())) or "-"
        notes = (
            [f"{r['not_at_strongest']} removed at a weaker step but not at the strongest"]
            if r["not_at_strongest"]
            else []
        )
        notes += [
            f"{k} overdetermined with {c}, by both together" for c, k in sorted((r.get("overdetermined") or {}).items())
        ]
        rows.append(
            [
                cause,
                str(r["n"]),
                (f"{r['confirmed']} ({'; '.join(notes)})" if notes else str(r["confirmed"]))
                if cause in summary["causes"]
                else "no intervention",
                other,
                joint,
                str(r["none"]),
            ]
        )
    return rows


def _headline(summary: dict) -> str:
    """The caption's first sentences: the share confirmed, what any intervention removes, the overdetermined pairs."""
    share = summary["confirmed_share"]
    head = (
        f"{summary['confirmed']} of {summary['attributed']} attributed disagreements ({100 * share:.0f} %) confirmed by their own cause's "
        "intervention."
        if share is not None
        else "No attributed disagreement to confirm."
    )
    if summary.get("n"):
        head += (
            f" Whatever the ladder named, {summary['removed_by_any']} of the {summary['n']} laddered disagreements are removed by some "
            "cause's intervention on the engine."
        )
    pairs = summary.get("pairs") or {}
    if pairs.get("predicted"):
        head += (
            f" Where the ladder named geometry, it reran its models with the capsule as thin as the geometry intervention makes it: "
            f"for {pairs['predicted']} the thin rigid capsule left the engine's outcome and a later model still gave it, an "
            f"overdetermined pair; {pairs['confirmed']} confirmed (the two causes' interventions together remove it, neither "
            f"alone does, counted as confirmed), {pairs['geometry alone']} removed by the thinner capsule alone after all, "
            f"{pairs['another alone']} by another cause's alone, {pairs['joint failed']} by neither together."
        )
    if summary.get("jointly"):
        head += (
            f" {summary['jointly']} more are removed only by the cause's strongest intervention joined to another cause's, neither "
            "removing it alone: overdetermined, each difference giving the engine's outcome on its own, where the ladder did "
            "not find that (not counted as confirmed)."
        )
    head += _by_p_sentence(summary)
    clause = _by_distance_clause(summary)
    head += f" {clause[:1].upper()}{clause[1:]}." if clause else ""
    return head


def _detail_tables(ctx: RenderContext, name: str, summary: dict, results: list) -> list:
    """The tables below the summary: by distance to the theory's boundary, by intervention, and start by start."""
    blocks = []
    if summary.get("by_distance"):
        blocks.append(
            Table(
                caption=f"{name}: the attributed disagreements and those confirmed, by the start's distance to the theory's own "
                "event boundary as the map section probed it: the first probe radius (scaled, in (theta, varphi, Theta, Psi, "
                "eta); a few random directions at each) at which a perturbed start's theory outcome differs, an upper bound "
                "on the distance. Where a perturbation of 0.01 turns the theory's outcome, each of the engine's differences "
                "may turn it, and removing one leaves the others."
                + (
                    f" {summary['unprobed']} attributed starts have no probed distance."
                    if summary.get("unprobed")
                    else ""
                ),
                header=["distance to the theory's boundary", "attributed", "confirmed"],
                rows=[
                    [
                        _distance(b["distance"]),
                        str(b["attributed"]),
                        _share({"attributed": b["attributed"], "confirmed": b["confirmed"]}),
                    ]
                    for b in summary["by_distance"]
                ],
                data=ctx.data("summary.json"),
            )
        )
    per_iv = [
        [cause, text, f"{k} of {(r.get('tried') or {}).get(text, r['n'])}"]
        for cause, r in summary["per_cause"].items()
        for text, k in (r.get("by_intervention") or {}).items()
    ]
    if per_iv:
        blocks.append(
            Table(
                caption=f"{name}: what removes each cause's disagreements, intervention by intervention (a start may be removed by "
                "several). Where one cause's interventions change different parts of the engine, this says which part acts.",
                header=["cause (ladder)", "intervention", "removes (of the starts that got it)"],
                rows=per_iv,
                data=ctx.data("summary.json"),
            )
        )
    if results:
        causes = summary["causes"]
        detail = []
        for r in results:
            s = r["state"]
            detail.append(
                [
                    r["map"],
                    f"theta {s['theta']:.3g}, varphi {s['varphi']:.3g}, Theta {s['Theta']:.3g}, Psi {s['Psi']:.3g}",
                    f"{r['mu']:.3g}",
                    r["interventions"]["theory"].lower(),
                    str(r["reference"]).lower(),
                    _cause_cell(r),
                    *[_mark(r["interventions"]["causes"].get(c, [])) for c in causes],
                    _joint_cell(r["interventions"]),
                    _floor_cell(r["interventions"]),
                    _fmt(r["interventions"].get("theory_p_min")),
                ]
            )
        blocks.append(
            Table(
                caption=f"Each start: the theory's outcome, {name}'s, the ladder's cause, {name}'s outcome under each cause's "
                "interventions, weakest first, the named cause's strongest joined to each other cause's strongest "
                "where neither removes it alone, the theory's least slip speed eta against the engine's STICK floor "
                "(and when it falls below it: an engine STICK from then on, less an event's lag, is compared as the "
                "theory's slip, which the classifier cannot tell it from), and the theory's "
                "least eq. p along its slip (near 0: the slip passes close to the Genot-Brogliato point, where a time "
                "step cannot tell a lift-off from a jam).",
                header=[
                    "map",
                    "start",
                    "mu",
                    "theory",
                    name,
                    "cause",
                    *causes,
                    "joined",
                    "theory eta min (floor)",
                    "theory p min",
                ],
                rows=detail,
                data=ctx.data("interventions.json"),
            )
        )
    return blocks


def _share(side: dict) -> str:
    n, k = side["attributed"], side["confirmed"]
    return f"{k} of {n}" + (f" ({100 * k / n:.0f} %)" if n else "")


def _by_p_sentence(summary: dict) -> str:
    """Where the confirmed ones are: the starts whose theory slip keeps eq. p above the classifier's jam band, and the rest."""
    by_p = summary.get("by_p")
    if not by_p or not summary.get("attributed"):
        return ""
    band = by_p["p_band"]
    return (
        f" Confirmed where the theory's slip keeps eq. p above {band:g} (the classifier's jam band): {_share(by_p['above'])}; where "
        f"it enters the band, {_share(by_p['in_band'])}. In the band the rigid normal force -b/p is at least |b| / {band:g} and "
        "each of the engine's differences (the capsule's offset, a friction skewed off the slip, a force built over a contact "
        "time) moves its own p across 0, so that removing one leaves another to jam or lift off."
    )


def other_starts(row: dict) -> int:
    """A summary's per-cause row: the starts another cause's intervention removes, each once (summaries saved before the
    count: one per cause)."""
    return row["by_other_starts"] if "by_other_starts" in row else sum(row["by_other"].values())


def pairs_confirmed(row: dict) -> int:
    """A summary's per-cause row: its starts confirmed as an overdetermined pair the ladder named (by both together)."""
    return sum((row.get("overdetermined") or {}).values())


def _cause_cell(r: dict) -> str:
    """The ladder's cause, with the cause its models give without the capsule's offset where they still give the engine's outcome."""
    also = (r["interventions"].get("without_offset") or {}).get("also")
    return f"{r['cause']} (and {also} without the offset)" if also else r["cause"]


def _distance(d) -> str:
    return "beyond the largest probe" if float(d) == float("inf") else f"{float(d):g}"


def _by_distance_clause(summary: dict) -> str:
    """The confirmed share at the smallest probed distance to the theory's event boundary and beyond the largest probe
    ("where ...", no full stop; "" when no start was probed)."""
    rows = summary.get("by_distance") or []
    if not rows:
        return ""
    near, far = rows[0], rows[-1]
    if float(near["distance"]) == float("inf"):
        return f"where no probe up to the largest turns the theory's own outcome, {_share(near)} are confirmed"
    out = f"where a probe of {_distance(near['distance'])} turns the theory's own outcome, {_share(near)} are confirmed"
    if far is not near:
        out += (
            f"; where none up to the largest probe does, {_share(far)}"
            if float(far["distance"]) == float("inf")
            else f"; at distance {_distance(far['distance'])}, {_share(far)}"
        )
    return out


def _joint_cell(iv: dict) -> str:
    """The joined interventions' labels: "with compliance: slip (removes)"; "-" where none ran."""
    return "; ".join(f"with {r['with']}: " + _mark([r]) for r in iv.get("joint") or []) or "-"


def _fmt(x) -> str:
    return "-" if x is None else f"{x:.2g}"


def _floor_cell(iv: dict) -> str:
    """The theory's least eta against the engine's STICK floor: "2.6e-03 (< 0.01 at t 0.78)" or "0.18 (0.01)"."""
    if iv.get("theory_eta_min") is None:
        return "-"
    t = iv.get("theory_below_floor_time")
    below = t is not None and t == t  # None once through JSON (no NaN there); NaN in memory
    return f"{iv['theory_eta_min']:.2g} ({'< ' if below else ''}{iv['stick_floor']:.2g}{f' at t {t:.3g}' if below else ''})"


def finding(data: Path) -> list:
    """The findings line: the share of the engine's attributed disagreements its own cause's intervention removes."""
    from crosscheck.report.finding import Finding, read_json
    from crosscheck.report.format import engine_label

    summary = read_json(data / "summary.json")
    if not summary or not summary.get("attributed"):
        return []
    name, share = engine_label(summary["engine"]), summary["confirmed_share"]
    none = sum(r["none"] for r in summary["per_cause"].values())
    other = sum(other_starts(r) for r in summary["per_cause"].values())
    over = sum(pairs_confirmed(r) for r in summary["per_cause"].values())
    pairs = (
        f" ({over} of them overdetermined pairs the ladder named, removed by both causes' interventions together)"
        if over
        else ""
    )
    clause = _by_distance_clause(summary)
    return [
        Finding(
            f"{name}: causes confirmed on the engine",
            f"{summary['confirmed']} of {summary['attributed']} attributed disagreements "
            f"({100 * share:.0f} %) removed by their own cause's intervention on {name} itself{pairs}; {other} removed by another cause's "
            f"instead, {summary.get('jointly', 0)} only jointly with another cause's (overdetermined, not found by the ladder), {none} by none; {summary.get('removed_by_any', '-')} of {summary.get('n', '-')} removed by some intervention"
            + (
                f"; above eq. p {summary['by_p']['p_band']:g} along the theory's slip {_share(summary['by_p']['above'])}, in that band "
                f"{_share(summary['by_p']['in_band'])}"
                if summary.get("by_p")
                else ""
            )
            + (f"; {clause}" if clause else ""),
            "confirmed" if share >= CONFIRMED_SHARE else "partly confirmed",
            data.name,
            why=f"confirmed when at least {100 * CONFIRMED_SHARE:.0f} % are removed by one of their own cause's interventions "
            "(both causes' together where the ladder named an overdetermined pair)",
        )
    ]


def section(spec, ladder: Section) -> Section:
    """The interventions section ``<slug>_interventions`` of the engine ``spec`` on the starts of its ladder section ``ladder``."""
    return Section(
        slug=f"{spec.slug}_interventions",
        title=f"{spec.label}: each cause confirmed by an intervention on the engine itself",
        paper="sections 2, 4",
        params=lambda quick: params(quick, spec.name, ladder),
        run=run,
        render=render,
        requires=("crosscheck.studies.interventions", spec.module or "crosscheck.engines"),
        finding=finding,
        after=(ladder.slug, *((f"{spec.slug}_maps",) if spec.report and spec.report.maps else ())),
    )
