"""The engine table's numbers: one record per registered engine and setting the report ran, against the theory.

Read from the saved results of each engine's generated sections alone (``<slug>_maps``, ``<slug>_convergence``,
``<slug>_liftoff``, ``<slug>_contact``, ``<slug>_rounding``, ``<slug>_interventions`` and the ladder whose parameters
name the engine), so ``--from-results`` rebuilds it.  A record holds numbers (floats and ints, units in the names);
every string the report shows is derived from them here (``summary_table`` one row per engine, ``settings_table``
every setting of one engine).  Written beside the report's data as ``data/engine_table.json`` and, tidy, one row per
engine and setting, ``data/engine_table.csv``.

* agreement: the share of rated slipping starts whose first event is the theory's (``crosscheck.studies.comparison``),
  ``ci_low``/``ci_high`` its Wilson 95 % interval; ``agree_theory_<outcome>`` of ``n_theory_<outcome>``: the same among
  the starts where the theory slips, lifts off or jams (the rows of the confusion matrix);
* ``n_launch``: rated starts the engine throws off the plane while the theory's b < 0 (``Outcome.LAUNCH``);
* cost: ``runs_per_s`` (rated starts over the sweep's wall time, one core) and ``us_per_step`` (per record row of a
  continuous engine); ``median_abs_event_time_error``: the median |engine event time - theory's| in scaled time;
* the map row alone: onset, friction, ladder causes, causes confirmed by intervention, rounding, the Theta after its
  jams against the impact without collision's (``<slug>_impact``), convergence verdicts.
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

from crosscheck import engines
from crosscheck.outcome import Outcome
from crosscheck.report.findings import convergence_trends, read_json
from crosscheck.report.section import Table
from crosscheck.studies.ladder import CAUSES
from crosscheck.sweeps.store_diff import wilson_interval

__all__ = ["engine_records", "write_engine_data", "summary_table", "settings_table", "FOOTNOTES", "pct", "JSON", "CSV"]

#: Where the records go, under the report directory.
JSON, CSV = Path("data") / "engine_table.json", Path("data") / "engine_table.csv"

_RATED = (Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM)
_THEORY = {"slip": Outcome.SLIP, "liftoff": Outcome.LIFTOFF, "jam": Outcome.JAM}
_LADDER = [c for c in CAUSES if c not in ("agree", "not rated")]


def _key(cause: str) -> str:
    """A ladder cause's column: ``ladder_friction_law``."""
    return "ladder_" + cause.replace(" ", "_")


_NONE = "-"


def pct(x: float | None) -> str:
    """A share as the report prints it: '83 %', '-' when there is none."""
    return _NONE if x is None or (isinstance(x, float) and math.isnan(x)) else f"{100 * x:.0f} %"


def _setting(options: dict, defaults: dict) -> str:
    """The timestep and the options that differ from the engine's defaults (lists and tuples compare equal)."""

    def same(a, b):
        return list(a) == list(b) if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)) else a == b

    shown = {
        k: v for k, v in options.items() if k == "timestep" or (k != "approximation" and not same(defaults.get(k), v))
    }
    return ", ".join(f"{k} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in sorted(shown.items()))


def _confusion_numbers(runs: list[dict]) -> dict:
    """Agreement, its interval, per theory row and LAUNCH, from the summed confusion of ``runs`` (one sweep each)."""
    conf, labels = None, runs[0]["labels"]
    for r in runs:
        c = r["confusion"]
        conf = c if conf is None else [[a + b for a, b in zip(r1, r2)] for r1, r2 in zip(conf, c)]
    rated = [labels.index(o.name) for o in _RATED]
    n = sum(conf[i][j] for i in rated for j in range(len(labels)))
    k = sum(conf[i][i] for i in rated)
    lo, hi = wilson_interval(k, n) if n else (math.nan, math.nan)
    out = {"n_rated": n, "n_agree": k, "agreement": k / n if n else math.nan, "ci_low": lo, "ci_high": hi}
    for word, o in _THEORY.items():
        i = labels.index(o.name)
        out[f"n_theory_{word}"], out[f"agree_theory_{word}"] = sum(conf[i]), conf[i][i]
    out["n_launch"] = sum(conf[i][labels.index("LAUNCH")] for i in rated) if "LAUNCH" in labels else 0
    return out


def _cost(runs: list[dict]) -> dict:
    wall = sum(r.get("wall_time") or 0.0 for r in runs)
    steps = sum((r.get("steps_per_second") or 0.0) * (r.get("wall_time") or 0.0) for r in runs)
    n = sum(sum(map(sum, r["confusion"])) for r in runs)
    errors = [r.get("median_abs_time_difference") for r in runs]
    errors = [e for e in errors if e is not None and not math.isnan(e)]
    return {
        "wall_time_s": wall,
        "runs_per_s": n / wall if wall else math.nan,
        "us_per_step": 1e6 * wall / steps if wall and steps else math.nan,
        "median_abs_event_time_error": sorted(errors)[len(errors) // 2] if errors else math.nan,
    }


def _engine_extras(data: Path, spec) -> dict:
    """The map row's engine-level numbers: onset, friction, ladder causes, interventions, rounding, convergence."""
    out: dict = {"onset_max_abs_error_Psi": math.nan, "friction_skew_median_deg": math.nan}
    out["cone_violation_max_mg"] = math.nan
    onset = data / f"{spec.slug}_liftoff" / "onset.csv"
    if onset.is_file():
        errs = [abs(float(r["onset_minus_Psi_L"])) for r in csv.DictReader(onset.open())]
        errs = [e for e in errs if not math.isnan(e)]
        out["onset_max_abs_error_Psi"] = max(errs) if errs else math.nan
    q = read_json(data / f"{spec.slug}_contact" / "quality.json") or {}
    if q.get("median_skew_deg") is not None and q.get("max_cone_violation") is not None:
        out["friction_skew_median_deg"], out["cone_violation_max_mg"] = q["median_skew_deg"], q["max_cone_violation"]
    counts = _ladder_counts(data, spec)
    out.update({_key(c): counts.get(c, 0) for c in _LADDER})
    s = read_json(data / f"{spec.slug}_interventions" / "summary.json") or {}
    top = max(s.get("per_cause") or {}, key=lambda c: s["per_cause"][c]["n"], default="")
    row = (s.get("per_cause") or {}).get(top, {})
    out.update(
        attributed=s.get("attributed", 0),
        confirmed=s.get("confirmed", 0),
        confirmed_jointly=s.get("jointly", 0),
        top_cause=top,
        top_cause_n=row.get("n", 0),
        top_cause_confirmed=row.get("confirmed", 0) + sum((row.get("overdetermined") or {}).values()),
    )
    r = read_json(data / f"{spec.slug}_rounding" / "summary.json") or {}
    out["rounding_changed"], out["rounding_n"] = r.get("changed", 0), r.get("n", 0)
    # after its jams: |Theta+ - the impact without collision's| over the theory's jams it also jams (<slug>_impact)
    i = read_json(data / f"{spec.slug}_impact" / "summary.json") or {}
    m = i.get("median_abs_Theta_plus_error_jammed")
    out["impact_median_abs_Theta_plus_error"] = math.nan if m is None else m
    out["impact_n_jammed"], out["impact_n"] = i.get("n_jammed", 0), i.get("n", 0)
    conv = data / f"{spec.slug}_convergence" / "convergence.csv"
    rows = list(csv.DictReader(conv.open())) if conv.is_file() else []
    out["convergence"] = {t.parameter: t.verdict for t in convergence_trends(rows)} if rows else {}
    return out


def _ladder_counts(data: Path, spec) -> dict:
    """The causes counted by the engine's ladder section (``<slug>_ladder``, its ``ladder_engine`` the engine's)."""
    d = data / f"{spec.slug}_ladder"
    if (read_json(d / "status.json") or {}).get("params", {}).get("ladder_engine") != spec.name:
        return {}
    return (read_json(d / "summary.json") or {}).get("counts", {})


def _defaults(spec) -> dict:
    try:
        return {k: getattr(spec.options(), k) for k in spec.Options.__dataclass_fields__}
    except ValueError:
        return {}


def engine_records(data: Path) -> list[dict]:
    """One record per engine and setting from the saved results in ``data`` (``<out>/data``): the map setting first
    (``role`` "map", the engine's outcome maps summed), then each convergence setting (``role`` "convergence", its
    own grid).  Engines whose map section has not run are left out; registry order."""
    data = Path(data)
    out = []
    for spec in engines.specs():
        maps = read_json(data / f"{spec.slug}_maps" / "maps.json")
        if not maps:
            continue
        defaults = _defaults(spec)
        base = {"engine": spec.name, "label": spec.label or spec.name, "slug": spec.slug, "rigid": spec.has("rigid")}
        runs = [mp["runs"][0] for mp in maps]
        settings = [("map", runs[0]["options"], runs)]
        study = read_json(data / f"{spec.slug}_convergence" / "study.json") or {}
        settings += [("convergence", r["options"], [r]) for r in study.get("runs", [])]
        for role, options, rs in settings:
            rec = {**base, "role": role, "setting": _setting(options, defaults), "timestep": options.get("timestep")}
            rec.update(_confusion_numbers(rs))
            rec.update(_cost(rs))
            rec["options"] = json.loads(json.dumps(options, default=str))
            if role == "map":
                rec.update(_engine_extras(data, spec))
            out.append(rec)
    return out


def _finite(v):
    return None if isinstance(v, float) and not math.isfinite(v) else v


def write_engine_data(out: Path, records: list[dict]) -> None:
    """``data/engine_table.json`` (the records, NaN as null) and the tidy ``data/engine_table.csv`` (one row per engine
    and setting; the map row's engine-level columns empty on the others; options as JSON)."""
    out = Path(out)
    clean = [{k: _finite(v) for k, v in r.items()} for r in records]
    (out / JSON).write_text(json.dumps(clean, indent=1) + "\n")
    columns = list(dict.fromkeys(k for r in clean for k in r))
    buf = io.StringIO()
    w = csv.DictWriter(buf, columns, lineterminator="\n")
    w.writeheader()
    for r in clean:
        w.writerow({k: json.dumps(v) if isinstance(v, dict) else v for k, v in r.items()})
    (out / CSV).write_text(buf.getvalue())


# ---------------------------------------------------------------- display ---


def interval(r: dict) -> str:
    """'83 % [76-88]' from a record's agreement and interval."""
    if not r["n_rated"]:
        return _NONE
    return f"{100 * r['agreement']:.0f} % [{100 * r['ci_low']:.0f}-{100 * r['ci_high']:.0f}]"


def _share(k: int, n: int) -> str:
    return f"{100 * k / n:.0f} % ({k}/{n})" if n else _NONE


def _cause(r: dict) -> str:
    if not r.get("top_cause_n"):
        return _NONE
    return f"{r['top_cause']} {r['top_cause_n']}/{r['attributed']}, {r['top_cause_confirmed']} confirmed"


def _number(x: float) -> str:
    return _NONE if x is None or not math.isfinite(x) else f"{x:.3g}"


def best_setting(records: list[dict], name: str) -> dict | None:
    """The engine's convergence setting with the highest agreement (ties: the cheaper), None without one."""
    conv = [r for r in records if r["engine"] == name and r["role"] == "convergence" and r["n_rated"]]
    return max(conv, key=lambda r: (r["agreement"], r["runs_per_s"]), default=None)


def _setting_cell(records: list[dict], m: dict) -> str:
    best = best_setting(records, m["engine"])
    cell = m["setting"]
    if best is not None and best["options"] != m["options"]:
        cell += f"; best: {_setting(best['options'], m['options'])}, {interval(best)} (convergence grid)"
    return cell


#: The summary table's columns and their one-line definitions (shown as footnotes under it).
FOOTNOTES = (
    ("engine", "the registered engine; (rigid): no contact compliance"),
    ("setting", "its outcome maps' options; best: its convergence setting of highest agreement, where that differs"),
    ("agreement", "share of rated slipping starts whose first event is the theory's, Wilson 95 % interval in brackets"),
    ("slips / lifts off / jams", "the same share among the starts where the theory slips, lifts off, jams"),
    ("LAUNCH", "share of rated starts thrown off the plane while the theory's b < 0 (a relaxation's gliding)"),
    ("main cause", "the ladder's most named cause / disagreements laddered; confirmed: removed by its intervention"),
    ("runs/s", "rated starts per second of one core over the maps' sweeps (2 scaled time units each)"),
)


def summary_table(records: list[dict]) -> Table:
    """One row per engine at its map setting, at most 9 columns, definitions as footnotes."""
    rows = []
    for m in (r for r in records if r["role"] == "map"):
        rows.append(
            [
                m["label"] + (" (rigid)" if m["rigid"] else ""),
                _setting_cell(records, m),
                interval(m),
                " / ".join(
                    pct(m[f"agree_theory_{w}"] / m[f"n_theory_{w}"] if m[f"n_theory_{w}"] else None) for w in _THEORY
                ),
                _share(m["n_launch"], m["n_rated"]),
                _cause(m),
                _number(m["runs_per_s"]),
            ]
        )
    return Table(
        caption="One row per engine at its map setting (every setting: the engine's page and data/engine_table.csv).",
        header=["engine", "setting", "agreement", "slips / lifts off / jams", "LAUNCH", "main cause", "runs/s"],
        rows=rows,
        data=[str(CSV), str(JSON)],
        notes=[f"{k}: {v}" for k, v in FOOTNOTES],
    )


def settings_table(records: list[dict], name: str) -> Table:
    """Every setting of engine ``name``: its maps' and its convergence grid's."""
    rows = [
        [
            r["role"],
            r["setting"],
            interval(r),
            *(_share(r[f"agree_theory_{w}"], r[f"n_theory_{w}"]) for w in _THEORY),
            _share(r["n_launch"], r["n_rated"]),
            _number(r["median_abs_event_time_error"]),
            _number(r["us_per_step"]),
            _number(r["runs_per_s"]),
        ]
        for r in records
        if r["engine"] == name
    ]
    return Table(
        caption="Every setting the report ran: its outcome maps' (map) and its convergence grid's, one row each.",
        header=["grid", "setting", "agreement", "slips", "lifts off", "jams", "LAUNCH", "event-time error", "us/step"]
        + ["runs/s"],
        rows=rows,
        data=[str(CSV)],
        notes=[
            "event-time error: median |engine event time - theory's| over agreeing starts, scaled time (1/omega)",
            "us/step: microseconds of one core per engine step (per record row for a continuous engine)",
        ],
    )


def engine_facts(r: dict) -> list[str]:
    """The map row's engine-level numbers as lines for the engine's page."""
    conv = "; ".join(f"{k}: {v}" for k, v in (r.get("convergence") or {}).items()) or _NONE
    ladder = ", ".join(f"{c} {r[_key(c)]}" for c in _LADDER if r[_key(c)])
    return [
        f"lift-off onset: worst |onset - Psi_L| {_number(r['onset_max_abs_error_Psi'])}",
        f"friction: median skew {_number(r['friction_skew_median_deg'])} deg, worst cone violation "
        f"{_number(r['cone_violation_max_mg'])} m g",
        f"convergence: {conv}",
        f"causes (ladder): {ladder or 'none'}; confirmed by intervention: {r['confirmed']} of {r['attributed']}"
        + (f", {r['confirmed_jointly']} more jointly" if r["confirmed_jointly"] else ""),
        f"outcome moves within 2 ulp of theta: {r['rounding_changed']} of {r['rounding_n']} starts",
        f"after its jams: median |Theta+ - the impact without collision's Theta+| "
        f"{_number(r['impact_median_abs_Theta_plus_error'])} over the {r['impact_n_jammed']} of {r['impact_n']} "
        "theory's jam starts it also jams",
    ]
