"""The report's findings: one line per leg with its headline number and a verdict, read from the saved results alone.

Lines (each only when its section's results are there):

* the multibody model's dynamics terms (section ``pinocchio``): the worst
  error against the analytic terms as a fraction of its tolerance; verdict
  *agrees* when every term is within its tolerance;
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
* MuJoCo's friction-direction skew (section ``friction_skew``): measured
  and predicted by its contact law per band, the ingredient and the option
  that removes it; verdict *explained* when the law's prediction is within
  the section's allowance of the measurement on every state;
* MuJoCo's friction direction (section ``friction_skew``): the measured skew
  beside the skew MuJoCo's own contact law predicts, its cause and the
  options that do or do not remove it;
* the compliant rod's eps -> 0 limit (section ``compliant_limit``): its
  physics checks and the measured rates;
* the causes of MuJoCo's disagreements (section ``ladder``): the share
  attributed to geometry, compliance, the friction law or discretisation;
* the paper's misprints found (checks marked as known discrepancies).
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Finding", "findings", "CONVERGED", "NOT_CONVERGED"]

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


def _json(path: Path):
    return json.loads(path.read_text()) if path.is_file() else None


def _engine_name(status: dict | None) -> str:
    """The engine's label, marked rigid for an engine without contact compliance (``Options().contact_time == 0``)."""
    from crosscheck import engines
    from crosscheck.engines.base import engine_label

    name = (status or {}).get("params", {}).get("engine", "?")
    try:
        rigid = engines.get(name).Options().contact_time == 0.0
    except ValueError:  # an engine no longer registered: its saved results still have a line
        rigid = False
    return f"{engine_label(name)} (rigid engine)" if rigid else engine_label(name)


def findings(data: Path) -> list[Finding]:
    """The findings of the report whose saved results are in ``data`` (``<out>/data``)."""
    from crosscheck.sweeps.compare import wilson_interval

    data = Path(data)
    out: list[Finding] = []
    v = _json(data / "pinocchio" / "validate.json")
    if v:
        worst = max(v["stats"], key=lambda s: s["max_ratio"])
        out.append(Finding("Pinocchio dynamics terms", f"{len(v['stats'])} quantities; worst: {worst['quantity']} at {worst['max_ratio']:.2g} of its "
                           f"tolerance (relative error {worst['max_rel']:.2g})", "agrees" if v["passed"] else "disagrees", "pinocchio"))
    for maps in sorted(data.glob("*/maps.json")):
        slug, status = maps.parent.name, _json(maps.parent / "status.json")
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
        name = _engine_name(_json(conv.parent / "status.json"))
        rows.sort(key=lambda r: -float(r["timestep"]))
        first, last = float(rows[0]["agreement"]), float(rows[-1]["agreement"])
        verdict = "converges" if last >= CONVERGED and last >= first else "does not converge" if last < NOT_CONVERGED or last < first else "inconclusive"
        trend = " -> ".join(f"{100 * float(r['agreement']):.0f} %" for r in rows)
        pl = rows[-1].get("agreement_planar") or "nan"
        off = rows[-1].get("agreement_off_plane") or "nan"
        out.append(Finding(f"{name}: convergence in timestep", f"agreement {trend} as the timestep goes {float(rows[0]['timestep']):g} -> "
                           f"{float(rows[-1]['timestep']):g}; at the finest {100 * float(pl):.0f} % on the planar section, {100 * float(off):.0f} % off it",
                           verdict, slug))
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
    skew = _json(data / "friction_skew" / "skew.json")
    if skew:
        bands = skew["band_median_deg"]
        pred, meas = bands["predicted (law run)"], bands["MuJoCo default"]
        ab = skew.get("ablation_median_deg", {})
        from crosscheck.studies.friction_skew import option_effects

        effect = option_effects(bands)
        options = "; ".join(f"{kind} it: " + ", ".join(k + (f" ({'/'.join(f'{v:.1f}' for v in x)})" if kind != "leaves" else "") for k, x in ks.items())
                            for kind, ks in effect.items() if ks)
        checks = _json(data / "friction_skew" / "checks.json") or []
        ok = any("predicted skew" in c["name"] for c in checks) and all(c["passed"] for c in checks if "predicted skew" in c["name"])
        out.append(Finding("MuJoCo: friction direction", f"skewed from -slip by {'/'.join(f'{x:.1f}' for x in meas)} degrees (median per "
                           f"|varphi + pi/2| band); MuJoCo's contact law predicts {'/'.join(f'{x:.1f}' for x in pred)} on the same states (worst "
                           f"state {skew['max_abs_difference_deg']:.2f} degrees off). Cause: the friction minimises a quadratic in the metric A + R, "
                           f"anisotropic and coupled to the normal row at the rod's contact point (made isotropic and decoupled: "
                           f"{ab.get('isotropic', float('nan')):.2f} instead of {ab.get('law', float('nan')):.1f} degrees). MuJoCo options: {options}. "
                           f"Consequence: MuJoCo slips with -b/p_eff, not -b/p", "explained" if ok else "not explained", "friction_skew"))
    limit = _json(data / "compliant_limit" / "checks.json")
    if limit:
        physics = [c for c in limit if c.get("kind") == "physics"]
        ok = sum(c["passed"] for c in physics)
        slopes = next((c["value"] for c in limit if "fitted slope" in c["name"]), [])
        lag = next((c["value"] for c in limit if "slip-stop lag" in c["name"]), [])
        gb_rates = next((c["value"] for c in limit if "planar GB point" in c["name"]), {})
        text = (f"{ok} of {len(physics)} physics checks of the eps -> 0 limit hold: an inconsistent start stops slipping after "
                f"(eps/lambda) ln(1/eps) (fitted slopes {', '.join(f'{a:.3f}' for a, _ in slopes)} against 1/lambda "
                f"{', '.join(f'{b:.3f}' for _, b in slopes)}) and its post-event state tends to the rigid impact without collision with the "
                f"restitution its damping implies; the lift-off / impact boundary of an indeterminate start holds")
        if lag:
            text += f"; at Corollary 4.2 jams the slip stop lags the rigid jam as eps^{min(lag):.2f}-eps^{max(lag):.2f} (derived eps^0.8)"
        if gb_rates:
            text += f"; at the planar GB point convergence is slow (lag order {gb_rates['lag_order']:.2f}, post-event order {gb_rates['post_order']:.2f})"
        out.append(Finding("compliant rod: eps -> 0", text, "agrees" if ok == len(physics) else "disagrees", "compliant_limit"))
    ladder = _json(data / "ladder" / "summary.json")
    if ladder and ladder.get("n_disagree"):
        counts, n = ladder["counts"], ladder["n_disagree"]
        causes = ", ".join(f"{k} {counts[k]}" for k in ("geometry", "compliance", "friction law", "discretisation", "unexplained", "undetermined")
                           if counts.get(k))
        ic2 = _json(data / "ladder" / "ic2.json") or {}
        text = (f"{n} MuJoCo-theory disagreements laddered (of {ladder.get('n_disagreements_on_maps', n)} on the maps), "
                f"{100 * ladder['attributed']:.0f} % attributed to a named cause: {causes}")
        if ic2.get("cause"):
            text += f"; the paper's IC2 (theory lifts off, MuJoCo jams): {ic2['cause']}"
        verdict = "explained" if ladder["attributed"] >= 0.9 else "partly explained"
        out.append(Finding("MuJoCo: causes of disagreement", text, verdict, "ladder"))
    known = [(p.parent.name, c) for p in sorted(data.glob("*/checks.json")) for c in json.loads(p.read_text()) if c.get("known_discrepancy")]
    if known:
        where = sorted({s for s, _ in known})
        out.append(Finding("the paper", f"{len(known)} known discrepancies between what the paper prints and its own model (misprints, a caption "
                           f"that does not fit its figure's numbers), shown in {', '.join(where)}", "known", known[0][0]))
    return out
