"""The engine table that heads the findings: every registered engine at every setting the report ran, against the theory.

One row per engine and setting, read from the saved results of the engine's
generated sections alone (``<slug>_maps``, ``<slug>_convergence``,
``<slug>_liftoff``, ``<slug>_contact`` and a ladder whose parameters name the
engine), so ``--from-results`` rebuilds it:

* agreement: the share of rated slipping starts whose first event is the
  theory's (``crosscheck.studies.comparison``), with its Wilson 95 % interval;
  then the same share among the starts where the theory slips, lifts off and
  jams (the rows of the confusion matrix);
* LAUNCH: the share of rated starts the engine throws off the plane while
  the theory's b < 0 (``crosscheck.outcome.Outcome.LAUNCH``);
* onset: the worst |onset - Psi_L| of its lift-off onset section;
* convergence: the verdict of its convergence section per parameter, the others held fixed
  (``findings.convergence_trends``);
* friction: the median angle between its friction force and -slip, and the
  worst cone violation, from its contact-quality section;
* causes: the split of its disagreements by the ladder;
* confirmed: the share of those its own cause's intervention on the engine removes (``<slug>_interventions``), and how
  many more only its and another cause's together remove (overdetermined);
* rounding: the starts of its maps whose outcome changes within 2 ulp of theta (``<slug>_rounding``);
* cost: microseconds per engine step (or per record row of a continuous
  engine) and runs per second on this machine, from the maps' wall time.

A cell whose section did not run reads "-".
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

__all__ = ["engine_table", "HEADER", "CAPTION", "table_block"]

HEADER = [
    "engine",
    "setting",
    "agreement (95 % CI)",
    "theory slips",
    "theory lifts off",
    "theory jams",
    "LAUNCH",
    "onset |Psi - Psi_L|",
    "convergence",
    "friction skew, cone violation",
    "causes (ladder)",
    "causes confirmed (intervention)",
    "outcome moves within 2 ulp",
    "|Theta+ - theory| after its jams",
    "us/step",
    "runs/s",
]

_NONE = "-"
_WORDS = {"timestep": "timestep", "timeconst": "time constant"}


def _read(path: Path):
    return json.loads(path.read_text()) if path.is_file() else None


def _share(k: int, n: int) -> str:
    return f"{100 * k / n:.0f} % ({k}/{n})" if n else _NONE


def _setting(options: dict, defaults: dict) -> str:
    """The timestep and the options that differ from the engine's defaults, compactly (lists and tuples compare equal)."""

    def same(a, b):
        return list(a) == list(b) if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)) else a == b

    shown = {
        k: v for k, v in options.items() if k == "timestep" or (k != "approximation" and not same(defaults.get(k), v))
    }
    return ", ".join(f"{k} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in sorted(shown.items()))


def _confusion_cells(runs: list[dict]) -> list[str]:
    """Agreement with CI, per theory row, LAUNCH share, from the summed confusion of ``runs`` (one map each)."""
    from crosscheck.outcome import Outcome
    from crosscheck.sweeps.store_diff import wilson_interval

    conf, labels = None, runs[0]["labels"]
    for r in runs:
        c = r["confusion"]
        conf = c if conf is None else [[a + b for a, b in zip(r1, r2)] for r1, r2 in zip(conf, c)]
    rated = [labels.index(o.name) for o in (Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM)]
    n = sum(conf[i][j] for i in rated for j in range(len(labels)))
    k = sum(conf[i][i] for i in rated)
    lo, hi = wilson_interval(k, n)
    cells = [f"{100 * k / n:.0f} % [{100 * lo:.0f}-{100 * hi:.0f}]" if n else _NONE]
    for o in (Outcome.SLIP, Outcome.LIFTOFF, Outcome.JAM):
        i = labels.index(o.name)
        cells.append(_share(conf[i][i], sum(conf[i])))
    launch = sum(conf[i][labels.index("LAUNCH")] for i in rated) if "LAUNCH" in labels else 0
    cells.append(_share(launch, n))
    return cells


def _cost(runs: list[dict]) -> tuple[str, str]:
    wall = sum(r.get("wall_time") or 0.0 for r in runs)
    steps = sum((r.get("steps_per_second") or 0.0) * (r.get("wall_time") or 0.0) for r in runs)
    n = sum(sum(map(sum, r["confusion"])) for r in runs)
    if not wall or not steps:
        return _NONE, _NONE
    return f"{1e6 * wall / steps:.3g}", f"{n / wall:.3g}"


def _onset(data: Path, slug: str) -> str:
    path = data / f"{slug}_liftoff" / "onset.csv"
    if not path.is_file():
        return _NONE
    rows = list(csv.DictReader(path.open()))
    errs = [abs(float(r["onset_minus_Psi_L"])) for r in rows if r.get("onset_minus_Psi_L") not in (None, "", "nan")]
    return f"{max(errs):.2g}" if errs else _NONE


def _convergence(data: Path, slug: str) -> str:
    from crosscheck.report.finding import convergence_trends

    path = data / f"{slug}_convergence" / "convergence.csv"
    if not path.is_file():
        return _NONE
    rows = list(csv.DictReader(path.open()))
    if not rows:
        return _NONE
    trends = convergence_trends(rows)  # one verdict per parameter, the others held fixed, as the findings read it
    if len(trends) == 1:
        return f"{_WORDS[trends[0].parameter]}: {trends[0].verdict}"
    return "; ".join(f"{_WORDS[t.parameter]}: {t.verdict}" for t in trends)


def _friction(data: Path, slug: str) -> str:
    q = _read(data / f"{slug}_contact" / "quality.json")
    if not q:
        return _NONE
    skew, cone = q.get("median_skew_deg"), q.get("max_cone_violation")
    if (
        skew is None or cone is None or (isinstance(skew, float) and math.isnan(skew))
    ):  # no sliding contact row (JSON null)
        return _NONE
    return f"{skew:.2g} deg, {cone:.2g}"


def _causes(data: Path, name: str) -> str:
    for status_path in sorted(data.glob("*/status.json")):
        status = _read(status_path) or {}
        if status.get("params", {}).get("ladder_engine") != name:
            continue
        summary = _read(status_path.parent / "summary.json")
        if summary and summary.get("n_disagree"):
            from crosscheck.studies.ladder import CAUSES

            counts = summary["counts"]
            return ", ".join(f"{k} {counts[k]}" for k in CAUSES if k not in ("agree", "not rated") and counts.get(k))
    return _NONE


def _confirmed(data: Path, slug: str) -> str:
    s = _read(data / f"{slug}_interventions" / "summary.json")
    if not s or not s.get("attributed"):
        return _NONE
    joint = f", {s['jointly']} more jointly" if s.get("jointly") else ""
    return f"{100 * s['confirmed_share']:.0f} % ({s['confirmed']}/{s['attributed']}{joint})"


def _impact(data: Path, slug: str) -> str:
    """Median |Theta+ - Theta+_theory| over the theory's jam starts the engine also jams (``<slug>_impact``)."""
    s = _read(data / f"{slug}_impact" / "summary.json")
    if not s or not s.get("n"):
        return _NONE
    m = s.get("median_abs_Theta_plus_error_jammed")
    return f"{m:.2g} ({s['n_jammed']}/{s['n']} jam)" if m is not None else f"- (0/{s['n']} jam)"


def _rounding(data: Path, slug: str) -> str:
    s = _read(data / f"{slug}_rounding" / "summary.json")
    return _NONE if not s else f"{s['changed']} of {s['n']}"


def engine_table(data: Path) -> tuple[list[str], list[list[str]], list[dict]]:
    """(header, rows, records) of the engine table from the saved results in ``data`` (``<out>/data``).

    ``records`` are the rows as dicts keyed by ``HEADER`` (for the table's JSON file).  Engines whose map section
    has not run are left out.
    """
    from crosscheck import engines

    data = Path(data)
    rows = []
    for spec in engines.specs():
        maps = _read(data / f"{spec.slug}_maps" / "maps.json")
        if not maps:
            continue
        try:
            defaults = {k: getattr(spec.options(), k) for k in spec.Options.__dataclass_fields__}
        except ValueError:
            defaults = {}
        runs = [mp["runs"][0] for mp in maps]
        label = f"{spec.label} (rigid)" if "rigid" in spec.tags else spec.label
        onset, conv, friction, causes = (
            _onset(data, spec.slug),
            _convergence(data, spec.slug),
            _friction(data, spec.slug),
            _causes(data, spec.name),
        )
        rows.append(
            [
                label,
                _setting(runs[0]["options"], defaults) + " (maps)",
                *_confusion_cells(runs),
                onset,
                conv,
                friction,
                causes,
                _confirmed(data, spec.slug),
                _rounding(data, spec.slug),
                _impact(data, spec.slug),
                *_cost(runs),
            ]
        )
        study = _read(data / f"{spec.slug}_convergence" / "study.json")
        for r in (study or {}).get("runs", []):
            rows.append(
                [
                    label,
                    _setting(r["options"], defaults),
                    *_confusion_cells([r]),
                    "",
                    "",
                    "",
                    "",
                    "",
                    "",
                    "",
                    *_cost([r]),
                ]
            )
    return HEADER, rows, [dict(zip(HEADER, r)) for r in rows]


#: What the engine table measures and the rules behind its cells (shown as its caption).
CAPTION = (
    "Every engine at every setting the report ran, against the rigid theory (`crosscheck.report.engine_table`). "
    "Agreement: the share of rated slipping starts whose first event is the theory's, compared up to the theory's comparison time "
    "(an engine event may come 2 contact times or 3 timesteps late; a spring contact's jam (Drake's point contact) "
    "s* (eps^4 / (k |b|))^(1/5) late, the slip stop's lag behind the rigid jam, s* = 3.919 the pole of Painleve I: "
    "`crosscheck.theory.jam_lag`; an engine STICK where the theory slips on, slower than the engine's STICK floor, counts as that slip: "
    "`crosscheck.studies.comparison.stick_from`) "
    "(Wilson 95 % interval), first on the engine's outcome maps, then on its convergence grid per setting; "
    "theory slips / lifts off / jams: the same share among the starts with that analytic event; "
    "LAUNCH: the share the engine throws off the plane while b < 0; onset: the worst lift-off onset error against Psi_L; "
    "convergence: per parameter with the others held fixed, by the rule under the findings; friction: median angle between the friction force and -slip, and the worst "
    "cone violation max(0, |F_t| - mu F_n) / (m g), while slipping; causes: the ladder's split of the disagreements; "
    "confirmed: the share of those removed by their own cause's intervention on the engine itself (and how many more only "
    "jointly with another cause's: overdetermined); rounding: the starts of its maps "
    "whose outcome changes when theta moves by up to 2 ulp; "
    "|Theta+ - theory|: the median over the theory's jam starts of its maps and IC1 that the engine also jams of its Theta "
    "once its contact settles against the impact without collision's Theta+ (`crosscheck.studies.jam_impact`); "
    "cost: engine microseconds per step (per record row for a continuous engine) and runs per second on this machine (one core). "
    "Grids were chosen by each engine's cost; '-' where a section did not run."
)


def table_block(out: Path):
    """The engine table from the saved results of the report in ``out``, as the report shows it (a ``Table`` with
    ``CAPTION``; None when no engine section ran), its JSON written beside the report's data (derived, not computed)."""
    from crosscheck.report.section import Table

    header, rows, records = engine_table(out / "data")
    if not rows:
        return None
    (out / "data" / "engine_table.json").write_text(json.dumps(records, indent=1) + "\n")
    return Table(caption=CAPTION, header=header, rows=rows, data=["data/engine_table.json"])
