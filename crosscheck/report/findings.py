"""The report's findings: one line per leg with its headline number and a verdict, read from the saved results alone.

Lines (each only when its section's results are there):

* per engine with outcome maps (every section that saved ``maps.json``, so
  an engine added later gets its line): the share of rated slipping starts
  whose first event is the analytic one, with its Wilson 95 % interval, and
  what the engine does where the theory jams;
* per engine with a convergence table (``convergence.csv``): one line per
  parameter its settings vary (the timestep, the contact time constant), the
  agreement from its coarsest to its finest value with the other held fixed
  (``convergence_trends``), on and off the planar section; verdict
  *converges* when the finest agrees on >= 95 % and at least as much as the
  coarsest, *does not converge* when the finest is below 90 % or below the
  coarsest, *inconclusive* otherwise.  For a compliant engine the timestep's
  line says what its limit is: dt -> 0 at a fixed contact time constant
  tends to the compliant model, not to the rigid theory;
* lift-off onset checks (every section whose checks name the onset): how
  many hold;
* the lines of the sections an engine owns (``Section.finding``, read from the
  section's own data directory): for example the multibody model's dynamics
  terms, MuJoCo's friction-direction skew, the compliant rod's eps -> 0 limit
  and the causes of MuJoCo's disagreements;
* the paper's misprints found (checks marked as known discrepancies).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

from crosscheck.report.finding import (
    CONFIRMED_SHARE,
    CONVERGED,
    NOT_CONVERGED,
    PARAMETER_WORDS,
    Finding,
    Trend,
    convergence_trends,
    convergence_verdict,
    read_json,
)

__all__ = [
    "Finding",
    "Trend",
    "findings",
    "convergence_verdict",
    "convergence_trends",
    "read_json",
    "RULES",
    "CONVERGED",
    "NOT_CONVERGED",
]

_OUTCOMES = ("SLIP", "LIFTOFF", "STICK", "JAM")


#: The rules behind the verdicts, shown where the verdicts are (the report's findings).
RULES = (
    (
        "first event",
        f"agrees when the lower end of the Wilson 95 % interval of the agreement is >= {100 * CONVERGED:.0f} %; disagrees when its "
        f"upper end is < {100 * NOT_CONVERGED:.0f} %; inconclusive otherwise (the interval reaches below {100 * CONVERGED:.0f} % and above "
        f"{100 * NOT_CONVERGED:.0f} %: these starts neither show agreement nor rule it out)",
    ),
    (
        "convergence",
        f"per parameter, the others held fixed: converges when the finest value agrees on >= {100 * CONVERGED:.0f} % and not less than "
        f"the coarsest; does not converge when the finest is below {100 * NOT_CONVERGED:.0f} % or below the coarsest; inconclusive "
        "otherwise. The rigid theory is the limit of a compliant engine only as its contact time constant goes to 0 (with "
        "the timestep below it); at a fixed time constant, timestep -> 0 tends to the compliant model",
    ),
    ("lift-off onset", "agrees when every onset check against Psi_L holds within its allowance, disagrees otherwise"),
    (
        "causes of disagreement",
        "explained when the ladder attributes >= 90 % of the laddered disagreements to a named cause, "
        "partly explained otherwise",
    ),
    (
        "causes confirmed on the engine",
        f"confirmed when >= {100 * CONFIRMED_SHARE:.0f} % of the attributed disagreements are removed by one of their own "
        "cause's interventions on the engine itself, partly confirmed otherwise",
    ),
    (
        "outcomes against rounding",
        "agrees when no start of the engine's maps changes outcome as theta moves by up to 2 ulp, disagrees otherwise",
    ),
    (
        "friction direction",
        "explained when MuJoCo's contact law, run on the same states, predicts the measured skew within its "
        "check's allowance; not explained otherwise",
    ),
    (
        "a section's own line",
        "agrees when every physics check of the section holds (regression guards do not count), disagrees otherwise",
    ),
    (
        "the paper",
        "known: a discrepancy between what the paper prints and its own model, shown, not counted as a failure",
    ),
)


def _engine_name(status: dict | None) -> str:
    """The engine's label, marked rigid for an engine without contact compliance (``Options().contact_time == 0``)."""
    from crosscheck import engines
    from crosscheck.report.format import engine_label

    name = (status or {}).get("params", {}).get("engine", "?")
    try:
        rigid = engines.get(name).has("rigid")
    except ValueError:  # an engine no longer registered: its saved results still have a line
        rigid = False
    return f"{engine_label(name)} (rigid engine)" if rigid else engine_label(name)


def _compliant(status: dict | None) -> bool:
    """Whether the engine named in a section's parameters has a compliant contact (``EngineSpec.tags``)."""
    from crosscheck import engines

    try:
        return engines.get((status or {}).get("params", {}).get("engine", "?")).has("compliant")
    except ValueError:
        return False


def _convergence_findings(rows: list[dict], name: str, slug: str, *, compliant: bool) -> list[Finding]:
    out = []
    for t in convergence_trends(rows):
        word = PARAMETER_WORDS[t.parameter]
        at = ", ".join(f"{PARAMETER_WORDS[o]} {v:g}" for o, v in t.fixed.items())
        seq = " -> ".join(f"{float(r[t.parameter]):g}" for r in t.rows)
        trend = " -> ".join(f"{100 * float(r['agreement']):.1f} %" for r in t.rows)
        pl = t.rows[-1].get("agreement_planar") or "nan"
        off = t.rows[-1].get("agreement_off_plane") or "nan"
        a = [float(r["agreement"]) for r in t.rows]
        shape = (
            "rises"
            if all(y >= x for x, y in zip(a, a[1:]))
            else "falls"
            if all(y <= x for x, y in zip(a, a[1:]))
            else "moves"
        )
        text = (
            f"agreement {shape} {trend} as the {word} goes {seq}"
            + (f" at {at}" if at else "")
            + f"; at the finest {100 * float(pl):.0f} % on the planar section, {100 * float(off):.0f} % off it"
        )
        if compliant and t.parameter == "timestep":
            text += (
                ". At a fixed contact stiffness the timestep's limit is the compliant model, not the rigid theory: the theory is "
                "approached only as the contact time constant goes to 0 too"
            )
        elif compliant and t.parameter == "timeconst":
            text += ". The rigid theory is the limit of a contact time constant going to 0 (with the timestep below it)"
        out.append(Finding(f"{name}: convergence in {word}" + (f" ({at})" if at else ""), text, t.verdict, slug, t.why))
    return out


def findings(data: Path) -> list[Finding]:
    """The findings of the report whose saved results are in ``data`` (``<out>/data``)."""
    from crosscheck.sweeps.store_diff import wilson_interval

    data = Path(data)
    out: list[Finding] = []
    for maps in sorted(data.glob("*/maps.json")):
        slug, status = maps.parent.name, read_json(maps.parent / "status.json")
        name = _engine_name(status)
        saved = json.loads(maps.read_text())
        conf = None
        for mp in saved:
            c = mp["runs"][0]["confusion"]
            conf = c if conf is None else [[a + b for a, b in zip(r1, r2)] for r1, r2 in zip(conf, c)]
        labels = saved[0]["runs"][0]["labels"]
        ix = [labels.index(o) for o in _OUTCOMES]
        n = sum(conf[i][j] for i in ix for j in range(len(labels)))
        k = sum(conf[i][i] for i in ix)
        lo, hi = wilson_interval(k, n)
        jam = conf[labels.index("JAM")]
        at_jams = ", ".join(f"{jam[j]} {labels[j].lower()}" for j in range(len(labels)) if jam[j])
        verdict = "agrees" if lo >= CONVERGED else "disagrees" if hi < NOT_CONVERGED else "inconclusive"
        why = (
            f"lower end {100 * lo:.1f} % {'>=' if lo >= CONVERGED else '<'} {100 * CONVERGED:.0f} %, "
            f"upper end {100 * hi:.1f} % {'<' if hi < NOT_CONVERGED else '>='} {100 * NOT_CONVERGED:.0f} %"
        )
        out.append(
            Finding(
                f"{name}: first event",
                f"same as the analytic one in {k} of {n} rated slipping starts ({100 * k / n:.0f} %, 95 % interval "
                f"{100 * lo:.0f}-{100 * hi:.0f} %); at the theory's jams: {at_jams or 'none'}",
                verdict,
                slug,
                why,
            )
        )
    for conv in sorted(data.glob("*/convergence.csv")):
        slug = conv.parent.name
        rows = list(csv.DictReader(conv.open()))
        if not rows:
            continue
        status = read_json(conv.parent / "status.json")
        out.extend(_convergence_findings(rows, _engine_name(status), slug, compliant=_compliant(status)))
    onset = [
        (p.parent.name, c)
        for p in sorted(data.glob("*/checks.json"))
        for c in json.loads(p.read_text())
        if "onset" in c["name"]
    ]
    for slug in sorted({s for s, _ in onset}):
        cs = [c for s, c in onset if s == slug]
        ok = sum(c["passed"] for c in cs)
        sized = [
            c
            for c in cs
            if isinstance(c.get("value"), (int, float))
            and isinstance(c.get("allowance"), (int, float))
            and c["allowance"] > 0
        ]
        worst = max(sized, key=lambda c: abs(c["value"]) / c["allowance"], default=None)
        if worst is None:
            how = ""
        elif (
            worst["allowance"] == 1.0 and "within tolerance" in worst["name"]
        ):  # a validate statistic: its value is already a ratio
            how = f"; worst at {abs(worst['value']):.2g} of its tolerance"
        else:
            how = f"; worst |onset - Psi_L| = {abs(worst['value']):.2g} against its allowance {worst['allowance']:.2g} ({worst['name'].split(':')[0]})"
        out.append(
            Finding(
                f"lift-off onset ({slug})",
                f"{ok} of {len(cs)} onset checks against Psi_L hold{how}",
                "agrees" if ok == len(cs) else "disagrees",
                slug,
            )
        )
    from crosscheck.report.sections import all_sections

    for section in all_sections():  # the lines an engine's own sections give (dynamics terms, friction skew, ...)
        if section.finding is not None and (data / section.slug).is_dir():
            out.extend(section.finding(data / section.slug))
    out.extend(_interventions_overall(data))
    known = [
        (p.parent.name, c)
        for p in sorted(data.glob("*/checks.json"))
        for c in json.loads(p.read_text())
        if c.get("known_discrepancy")
    ]
    if known:
        where = sorted({s for s, _ in known})
        out.append(
            Finding(
                "the paper",
                f"{len(known)} known discrepancies between what the paper prints and its own model (misprints, a caption "
                f"that does not fit its figure's numbers), shown in {', '.join(where)}",
                "known",
                known[0][0],
            )
        )
    return out


def _interventions_overall(data: Path) -> list[Finding]:
    """One line over every engine's interventions section: the attributed disagreements their own cause's intervention
    removes, all engines together, and the engine with the lowest share (each engine's own line comes from its section)."""
    from crosscheck.report.format import engine_label
    from crosscheck.report.sections.engine_interventions import pairs_confirmed

    summaries = [(p.parent.name, read_json(p)) for p in sorted(data.glob("*_interventions/summary.json"))]
    summaries = [(slug, s) for slug, s in summaries if s and s.get("attributed")]
    if len(summaries) < 2:
        return []
    n, k = sum(s["attributed"] for _, s in summaries), sum(s["confirmed"] for _, s in summaries)
    pairs = sum(pairs_confirmed(r) for _, s in summaries for r in s["per_cause"].values())
    jointly = sum(s.get("jointly", 0) for _, s in summaries)
    low_slug, low = min(summaries, key=lambda x: x[1]["confirmed"] / x[1]["attributed"])
    met = k >= CONFIRMED_SHARE * n  # (counts, not a rounded share)
    return [
        Finding(
            "every engine: causes confirmed on the engine",
            f"{k} of {n} attributed disagreements ({100 * k / n:.1f} %) over "
            f"{len(summaries)} engines removed by their own cause's intervention on the engine"
            + (
                f" ({pairs} of them overdetermined pairs the ladder named, removed by both interventions together)"
                if pairs
                else ""
            )
            + (f"; {jointly} more only jointly with another cause's, not found by the ladder" if jointly else "")
            + f"; lowest {engine_label(low['engine'])}, {low['confirmed']} of {low['attributed']} "
            f"({100 * low['confirmed'] / low['attributed']:.0f} %)",
            "confirmed" if met else "partly confirmed",
            low_slug,
            why=f"{k} of {n} {'>=' if met else '<'} {100 * CONFIRMED_SHARE:.0f} % of {n} = {CONFIRMED_SHARE * n:g}",
        )
    ]
