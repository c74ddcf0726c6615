"""Compare every number of two report data trees (``DIR/data``): JSON and CSV, ignoring timings and provenance.

Numbers are equal when |a - b| <= atol + rtol |a|: the default allows the
last-digit differences of an ODE integration on another machine, nothing
more; strings, labels and counts must be identical.  A few quantities are
decided by the last bits of the machine's floating point and are compared
with wider allowances (``ACROSS_MACHINES``): numpy's transcendental functions
take other SIMD paths on other CPUs (the committed report was made on an AMD
EPYC, CI may run on an Intel Xeon with AVX-512), OpenBLAS runs another kernel
(chosen by the CPU or by ``OPENBLAS_CORETYPE``, which some machines set:
scipy's Runge-Kutta steps sum their stages through it; the provenance's
"machine: BLAS" names it), and an adaptive integrator's
steps, an iterative solver's iteration count at its tolerance and a measured
rounding error all follow those bits.  Used by the test that
keeps the committed reference report ``reports/quick`` current, and by
``python tools/compare_report_data.py OLD/data NEW/data``.
"""

from __future__ import annotations

import csv
import fnmatch
import json
import math
from pathlib import Path

__all__ = ["compare", "IGNORED", "IGNORED_FILES", "RTOL", "ATOL", "ACROSS_MACHINES"]

#: Relative and absolute allowance of a number: rounding of the saved 12 digits and of an integration's last digits.
RTOL, ATOL = 1e-9, 1e-12

#: Wider allowances for what depends on the machine's last bits: (pattern, rtol, atol, why).  ``pattern`` is
#: a JSON key or CSV column name, or a data file's path (fnmatch) whose every number it covers.  Each is a
#: regression guard set from a measured spread (the quick report on an AMD EPYC and on an Intel Xeon), not
#: a physics bound: the numbers behind it are checked against their physics tolerances by their sections.
ACROSS_MACHINES = (
    # rows at the accepted steps of solve_ivp (rtol 1e-10): a last-bit change in sin/cos moves the steps;
    # measured 1.5e-6 in t and up to 2e-6 in the rates, 1e-4 of b where b ~ 1e-3 passes through 0
    (
        "mujoco_trajectories/analytic_*.csv",
        1e-5,
        1e-6,
        "adaptive integrator steps follow the CPU's last bits (measured 2e-6)",
    ),
    (
        "rigid_engine/trajectory_analytic.csv",
        1e-5,
        1e-6,
        "adaptive integrator steps follow the CPU's last bits (measured 2e-6)",
    ),
    # the same integration from the paper's two starts: OpenBLAS's Haswell kernel against its SkylakeX one, measured 1.8e-7 in the normal force
    (
        "*_ic/analytic_ic*.csv",
        1e-5,
        1e-6,
        "adaptive integrator steps follow the BLAS kernel's last bits (measured 1.8e-7)",
    ),
    # the NCP is solved to 1e-13 m g x dt, i.e. forces to ~1e-10 / dt: measured 3.6e-9 relative at dt 1e-3
    (
        "rigid_engine/trajectory_*.csv",
        1e-8,
        1e-9,
        "NCP solved to 1e-13 m g dt: forces to ~1e-10 m g (measured 3.6e-9 relative)",
    ),
    # a measured rounding error is itself the last bits (measured 1.7e-3 relative between the two CPUs)
    ("max_rel", 0.05, 0.0, "a measured rounding error is the CPU's last bits (measured 1.7e-3 relative)"),
    # PGS iterations and the steps that miss its tolerance, at the tolerance's edge (measured 255 vs 245)
    ("unconverged_steps", 0.1, 0.0, "PGS steps missing its tolerance at the edge (measured 4 % between CPUs)"),
    ("mean_iterations", 0.01, 0.0, "PGS mean iteration count (measured 3e-5 relative)"),
    # MuJoCo's contact law against mj_forward: measured rounding errors (~1e-13) are the CPU's last bits; the law's runs are
    # solve_ivp DOP853 at rtol 1e-10 sampled on dense output, whose steps follow them (as the analytic trajectories above;
    # not measured across CPUs for this section)
    (
        "friction_skew/law_check.json",
        1.0,
        1e-12,
        "measured rounding errors of the law against efc_force / efc_R / efc_aref (~1e-13)",
    ),
    ("friction_skew/checks.json", 1e-5, 1e-12, "a rounding error (~1e-13) and the law's adaptive integrator steps"),
    (
        "friction_skew/*",
        1e-5,
        1e-6,
        "adaptive integrator steps follow the CPU's last bits (as the analytic trajectories)",
    ),
    # the compliant rod (Radau with events, rtol 1e-10) and the ladder's rungs (DOP853, Radau, MuJoCo's law) are adaptive
    # integrations too: the same allowance as the analytic trajectories (not yet measured across CPUs for these sections)
    (
        "compliant_limit/*",
        1e-5,
        1e-6,
        "adaptive implicit integration with events follows the CPU's last bits (as the analytic trajectories)",
    ),
    (
        "mujoco_ladder/*",
        1e-5,
        1e-6,
        "event times of adaptive integrations follow the CPU's last bits (as the analytic trajectories)",
    ),
    # Drake's continuous plant: an error-controlled integrator whose accepted steps (and counts of steps, derivative
    # evaluations and step shrinkages) follow the CPU's last bits, as solve_ivp's; not yet measured across CPUs
    (
        "drake_continuous_*/*",
        1e-5,
        1e-6,
        "error-controlled integration follows the CPU's last bits (as the analytic trajectories)",
    ),
    (
        "derivative_evaluations",
        0.1,
        0.0,
        "an error-controlled integrator's evaluation count follows the CPU's last bits",
    ),
    ("error_shrinkages", 0.1, 0.0, "an error-controlled integrator's rejected steps follow the CPU's last bits"),
)

#: Keys that hold timings or provenance, not results.
IGNORED = {
    "wall_time",
    "steps_per_second",
    "seconds",
    "date",
    "git",
    "revision",
    "dirty",
    "describe",
    "requires",
    "machine",
    "versions",
    "code_sha256",
    "crosscheck_version",
    "files",  # (files: the checksums, which change with the last digit)
    "us/step",
    "runs/s",
    "us_per_step",
    "runs_per_s",
    "wall_time_s",
    "pareto_agreement_cost",  # the first figure's Pareto frontiers: which settings are on them follows the runs/s
    "pareto_error_cost",
}  # the engine table's cost columns (and the first figure's, which draws them)

#: Data files that hold only timings: Newton's kernel loads (CPU seconds of each solver's first step in the process
#: that ran it; which solvers a process met follows the scheduling of the sections).
IGNORED_FILES = {"provenance.json", "first_steps.json"}


def _number(x):
    if isinstance(x, bool):
        return None
    if isinstance(x, (int, float)):
        return float(x)
    if isinstance(x, str):
        try:
            return float(x)
        except ValueError:
            return None
    return None


def _same(a, b, rtol: float, atol: float) -> bool:
    x, y = _number(a), _number(b)
    if x is None or y is None:
        return a == b
    if math.isnan(x) and math.isnan(y):
        return True
    if math.isinf(x) or math.isinf(y):
        return x == y
    return abs(x - y) <= atol + rtol * abs(x)


def _allowance(name: str, rtol: float, atol: float) -> tuple[float, float]:
    """The allowance of a key, column or file: the wider of the default and its ``ACROSS_MACHINES`` entry."""
    for pattern, r, a, _ in ACROSS_MACHINES:
        if fnmatch.fnmatch(name, pattern):
            return max(rtol, r), max(atol, a)
    return rtol, atol


def _walk(a, b, path: str, out: list, rtol: float, atol: float, rename: dict) -> None:
    if isinstance(a, dict) and isinstance(b, dict):
        a = {rename.get(k, k): v for k, v in a.items()}
        for k in sorted(set(a) | set(b)):
            if k in IGNORED:
                continue
            if k not in a:
                out.append(f"{path}/{k}: only in new")
            elif k not in b:
                out.append(f"{path}/{k}: only in old")
            else:
                _walk(a[k], b[k], f"{path}/{k}", out, *_allowance(k, rtol, atol), rename)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: length {len(a)} (old) vs {len(b)} (new)")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            _walk(x, y, f"{path}[{i}]", out, rtol, atol, rename)
    elif not _same(a, b, rtol, atol):
        out.append(f"{path}: {a!r} (old) vs {b!r} (new)")


def _csv(path: Path, rename: dict) -> dict[str, list[str]]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    head = [rename.get(h, h) for h in rows[0]]
    return {h: [r[i] if i < len(r) else "<missing>" for r in rows[1:]] for i, h in enumerate(head)}


def compare(
    old: Path, new: Path, *, rtol: float = RTOL, atol: float = ATOL, rename: dict | None = None
) -> dict[str, list[str]]:
    """{file: differences} of two data trees (files equal in every number map to []); provenance.json is skipped."""
    old, new, rename = Path(old), Path(new), rename or {}
    files = sorted(
        {p.relative_to(old) for p in old.rglob("*") if p.suffix in (".json", ".csv")}
        | {p.relative_to(new) for p in new.rglob("*") if p.suffix in (".json", ".csv")}
    )
    result: dict[str, list[str]] = {}
    for rel in files:
        if rel.name in IGNORED_FILES:
            continue
        a, b = old / rel, new / rel
        out: list[str] = []
        f_rtol, f_atol = _allowance(str(rel), rtol, atol)
        if not a.exists() or not b.exists():
            out.append(f"only in {'new' if b.exists() else 'old'}")
        elif rel.suffix == ".json":
            _walk(json.loads(a.read_text()), json.loads(b.read_text()), "", out, f_rtol, f_atol, rename)
        else:
            ca, cb = _csv(a, rename), _csv(b, rename)
            for col in sorted((set(ca) | set(cb)) - IGNORED):
                if col not in ca or col not in cb:
                    out.append(f"column {col}: only in {'new' if col in cb else 'old'}")
                elif len(ca[col]) != len(cb[col]):
                    out.append(f"column {col}: {len(ca[col])} rows (old) vs {len(cb[col])} (new)")
                else:
                    c_rtol, c_atol = _allowance(col, f_rtol, f_atol)
                    bad = [i for i, (x, y) in enumerate(zip(ca[col], cb[col])) if not _same(x, y, c_rtol, c_atol)]
                    if bad:
                        out.append(
                            f"column {col}: {len(bad)} rows differ, first row {bad[0]}: {ca[col][bad[0]]} (old) vs {cb[col][bad[0]]} (new)"
                        )
        result[str(rel)] = out
    return result
