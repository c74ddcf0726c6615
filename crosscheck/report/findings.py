"""The report's findings: one line per leg with its headline number and a verdict, read from the saved results alone.

Lines (each only when its section's results are there):

* per engine with outcome maps (every section that saved ``maps.json``, so
  an engine added later gets its line): the share of rated slipping starts
  whose first event is the analytic one, with its Wilson 95 % interval, and
  what the engine does where the theory jams;
* per engine with a convergence table (``convergence.csv``): the agreement
  from the coarsest to the finest timestep, on and off the planar section;
  verdict *converges* when the finest agrees on >= 95 % and at least as much
  as the coarsest, *does not converge* when the finest is below 90 % or
  below the coarsest, *inconclusive* otherwise;
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
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Finding", "findings", "convergence_verdict", "read_json", "CONVERGED", "NOT_CONVERGED"]

#: Agreement at the finest timestep above which (and not below the coarsest) a convergence table "converges".
CONVERGED = 0.95
#: ... and below which it "does not converge".
NOT_CONVERGED = 0.90

_OUTCOMES = ("SLIP", "LIFTOFF", "STICK", "JAM")


@dataclass(frozen=True)
class Finding:
    """One line: the leg, what was found, the verdict, and the section it comes from (its anchor)."""

    leg: str
    text: str
    verdict: str
    slug: str


def read_json(path: Path):
    """The JSON file at ``path``, or None when it is absent."""
    return json.loads(path.read_text()) if path.is_file() else None


def _engine_name(status: dict | None) -> str:
    """The engine's label, marked rigid for an engine without contact compliance (``Options().contact_time == 0``)."""
    from crosscheck import engines
    from crosscheck.engines.base import engine_label

    name = (status or {}).get("params", {}).get("engine", "?")
    try:
        rigid = engines.get(name).has("rigid")
    except ValueError:  # an engine no longer registered: its saved results still have a line
        rigid = False
    return f"{engine_label(name)} (rigid engine)" if rigid else engine_label(name)


def convergence_verdict(rows: list[dict]) -> tuple[str, str]:
    """(verdict, trend) of a convergence table's rows (coarsest setting first): *converges* when the finest agrees on
    >= ``CONVERGED`` and at least as much as the coarsest, *does not converge* when it is below ``NOT_CONVERGED`` or below
    the coarsest, *inconclusive* otherwise."""
    first, last = float(rows[0]["agreement"]), float(rows[-1]["agreement"])
    verdict = "converges" if last >= CONVERGED and last >= first else "does not converge" if last < NOT_CONVERGED or last < first else "inconclusive"
    return verdict, " -> ".join(f"{100 * float(r['agreement']):.0f} %" for r in rows)


def findings(data: Path) -> list[Finding]:
    """The findings of the report whose saved results are in ``data`` (``<out>/data``)."""
    from crosscheck.sweeps.compare import wilson_interval

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
        out.append(Finding(f"{name}: first event", f"same as the analytic one in {k} of {n} rated slipping starts ({100 * k / n:.0f} %, 95 % interval "
                           f"{100 * lo:.0f}-{100 * hi:.0f} %); at the theory's jams: {at_jams or 'none'}", verdict, slug))
    for conv in sorted(data.glob("*/convergence.csv")):
        slug = conv.parent.name
        rows = list(csv.DictReader(conv.open()))
        if not rows:
            continue
        name = _engine_name(read_json(conv.parent / "status.json"))
        rows.sort(key=lambda r: -float(r["timestep"]))
        verdict, trend = convergence_verdict(rows)
        pl = rows[-1].get("agreement_planar") or "nan"
        off = rows[-1].get("agreement_off_plane") or "nan"
        # name what the settings vary: the timestep, the contact's time constant (its stiffness), or both
        varied = [k for k, word in (("timestep", "timestep"), ("timeconst", "contact time constant")) if len({r.get(k) for r in rows}) > 1]
        words = " and ".join({"timestep": "timestep", "timeconst": "contact time constant"}[k] for k in varied) or "setting"
        seq = " -> ".join(", ".join(f"{k} {float(r[k]):g}" for k in varied) for r in rows) if varied else f"timestep {float(rows[0]['timestep']):g}"
        out.append(Finding(f"{name}: convergence in {words}", f"agreement {trend} over the settings {seq}; at the last "
                           f"{100 * float(pl):.0f} % on the planar section, {100 * float(off):.0f} % off it", verdict, slug))
    onset = [(p.parent.name, c) for p in sorted(data.glob("*/checks.json")) for c in json.loads(p.read_text()) if "onset" in c["name"]]
    for slug in sorted({s for s, _ in onset}):
        cs = [c for s, c in onset if s == slug]
        ok = sum(c["passed"] for c in cs)
        sized = [c for c in cs if isinstance(c.get("value"), (int, float)) and isinstance(c.get("allowance"), (int, float)) and c["allowance"] > 0]
        worst = max(sized, key=lambda c: abs(c["value"]) / c["allowance"], default=None)
        if worst is None:
            how = ""
        elif worst["allowance"] == 1.0 and "within tolerance" in worst["name"]:  # a validate statistic: its value is already a ratio
            how = f"; worst at {abs(worst['value']):.2g} of its tolerance"
        else:
            how = f"; worst |onset - Psi_L| = {abs(worst['value']):.2g} against its allowance {worst['allowance']:.2g} ({worst['name'].split(':')[0]})"
        out.append(Finding(f"lift-off onset ({slug})", f"{ok} of {len(cs)} onset checks against Psi_L hold{how}", "agrees" if ok == len(cs) else "disagrees", slug))
    from crosscheck.report.sections import all_sections

    for section in all_sections():  # the lines an engine's own sections give (dynamics terms, friction skew, ...)
        if section.finding is not None and (data / section.slug).is_dir():
            out.extend(section.finding(data / section.slug))
    known = [(p.parent.name, c) for p in sorted(data.glob("*/checks.json")) for c in json.loads(p.read_text()) if c.get("known_discrepancy")]
    if known:
        where = sorted({s for s, _ in known})
        out.append(Finding("the paper", f"{len(known)} known discrepancies between what the paper prints and its own model (misprints, a caption "
                           f"that does not fit its figure's numbers), shown in {', '.join(where)}", "known", known[0][0]))
    return out
