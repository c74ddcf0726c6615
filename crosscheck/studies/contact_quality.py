"""Contact-force quality of any engine, row by row, with the metrics of ContactBench (Le Lidec et al. 2024).

While the rod slips, the rigid theory's contact force obeys Signorini's
condition (a normal force only with the contact point on the plane and not
moving off it: lambda_n v_n = 0), Coulomb's cone (|lambda_t| <= mu lambda_n),
the maximum-dissipation principle while sliding (|lambda_t| = mu lambda_n,
lambda_t anti-parallel to the slip) and, in the paper's model, eq. FZ
(lambda_n = -b/p).  An engine's record (``crosscheck.engines.Record``) holds
its own force and velocities per row, so each principle is one number per
row:

* Signorini: |lambda_n v_n| [m g l omega], v_n the contact point's normal velocity;
* cone violation: max(0, |lambda_t| - mu lambda_n) [m g];
* dissipation ratio |lambda_t| / (mu lambda_n) (1 while sliding);
* friction skew: the angle between lambda_t and -v_slip [degrees];
* normal force against eq. FZ: the window-mean lambda_n over the window-mean
  of the theory's -b/p on the engine's own states (1 for a rigid slip; a
  soft contact's chatter averages to it over the classifier's window).

Rows counted: before the run's first event (the whole run for SLIP), with a
positive normal force and the contact point sliding (slip speed above the
classifier's STICK threshold).  Starts: seeded random slipping states below
mu_P (no jam, so the theory's slip has a finite -b/p throughout).  Scaled
units (section 2.1).
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck import engines
from crosscheck.engines.classifier import Thresholds, window_sum
from crosscheck.rod import Rod
from crosscheck.studies.grids import states_at

__all__ = ["METRICS", "row_metrics", "contact_quality", "summary"]

#: The per-row metrics, in table order.
METRICS = ("signorini", "cone_violation", "dissipation_ratio", "skew_deg", "force_over_FZ")


def row_metrics(
    record, mu: float, alpha: float, *, last_row: int, slip_floor: float, window: int
) -> dict[str, np.ndarray]:
    """The metrics of ``METRICS`` on the counted rows of one run's record (each a 1D array; empty when no row counts)."""
    n = min(last_row, len(record))
    F = record.force[:n]
    Fn = np.maximum(F[:, 2], 0.0)
    Ft = F[:, :2]
    u = record.slip_vel[:n, :2]
    eta = np.hypot(u[:, 0], u[:, 1])
    ft = np.hypot(Ft[:, 0], Ft[:, 1])
    keep = (Fn > 0.0) & (eta > slip_floor)
    vn = record.tip_vel[:n, 2]
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = -(Ft[:, 0] * u[:, 0] + Ft[:, 1] * u[:, 1]) / (ft * eta)
        skew = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
        ratio = ft / (mu * Fn)
        rec = record.rows(slice(0, n))
        b, p = rec.b, rec.p(mu, alpha)
        fz = np.where(p > 0, np.maximum(-b, 0.0) / p, np.nan)
        w = min(window, n)
        force = window_sum(record.normal_force[:n], w) / np.where(
            np.isfinite(window_sum(fz, w)), window_sum(fz, w), np.nan
        )
    return {
        "signorini": np.abs(Fn * vn)[keep],
        "cone_violation": np.maximum(0.0, ft - mu * Fn)[keep],
        "dissipation_ratio": ratio[keep & (mu > 0)],
        "skew_deg": skew[keep & (ft > 0)],
        "force_over_FZ": force[keep & np.isfinite(force)],
    }


def contact_quality(
    engine: str,
    n: int,
    rng: np.random.Generator,
    *,
    alpha: float = 3.0,
    horizon: float = 0.3,
    mu_range=(0.3, 1.2),
    options: dict | None = None,
    thresholds: Thresholds | None = None,
    progress: bool = False,
) -> dict:
    """``n`` seeded slipping starts (mu uniform in ``mu_range``, below mu_P) through ``engine``; the metrics of every counted row.

    Returns a dict: ``rows`` (metric -> 1D array over all counted rows of all runs), ``per_run`` (metric -> (n,) medians,
    NaN for a run with no counted row), ``outcomes`` (n,) names, ``mu`` (n,), and ``summary`` (``summary(rows)``).
    """
    from crosscheck.studies.grids import random_event_points

    E = engines.get(engine)
    opts = E.options(**(options or {}))
    th = thresholds or Thresholds()
    pts = random_event_points(4 * n, rng, alpha=alpha)
    pick = np.flatnonzero((pts["mu"] >= mu_range[0]) & (pts["mu"] <= mu_range[1]))
    if len(pick) < n:  # draw more: about a sixth of random_event_points' mu in [0.3, 6] lie in [0.3, 1.2]
        extra = random_event_points(40 * n, rng, alpha=alpha)
        pts = {k: np.concatenate([pts[k][pick], extra[k]]) for k in pts}
        pick = np.flatnonzero((pts["mu"] >= mu_range[0]) & (pts["mu"] <= mu_range[1]))
    idx = pick[:n]
    rod = Rod.scaled(alpha)
    rows = {k: [] for k in METRICS}
    per_run = {k: np.full(len(idx), math.nan) for k in METRICS}
    outcomes = []
    from tqdm.auto import tqdm

    given = {k: getattr(opts, k) for k in opts.__dataclass_fields__}
    starts = states_at(pts, idx)
    # one call for all the starts (a batched engine steps them together: the same runs, record for record)
    runs = E.simulate_each(rod, starts, [float(mu) for mu in pts["mu"][idx]], horizon=horizon, thresholds=th, **given)
    for j, (run, mu) in enumerate(
        tqdm(list(zip(runs, pts["mu"][idx])), desc=f"{engine} contact quality", disable=not progress)
    ):
        outcomes.append(run.outcome.name)
        last = (
            len(run.record) if not np.isfinite(run.event_time) else int(np.searchsorted(run.record.t, run.event_time))
        )
        floor = (
            th.rigid_stick_steps * opts.timestep if opts.contact_time == 0 else th.stick_threshold(opts.friction_time)
        )
        m = row_metrics(
            run.record, float(mu), alpha, last_row=last, slip_floor=floor, window=th.window_rows(opts.timestep)
        )
        for k in METRICS:
            rows[k].append(m[k])
            if len(m[k]):
                per_run[k][j] = float(np.median(m[k]))
    rows = {k: np.concatenate(v) if v else np.zeros(0) for k, v in rows.items()}
    return {"rows": rows, "per_run": per_run, "outcomes": outcomes, "mu": pts["mu"][idx], "summary": summary(rows)}


def summary(rows: dict[str, np.ndarray]) -> dict:
    """Rows counted, and per metric its median, 95th percentile and maximum (NaN where no row counts)."""
    out = {"rows": int(len(rows["cone_violation"]))}
    for k in METRICS:
        x = rows[k]
        out[k] = {
            "median": float(np.median(x)) if len(x) else math.nan,
            "p95": float(np.percentile(x, 95)) if len(x) else math.nan,
            "max": float(np.max(x)) if len(x) else math.nan,
        }
    out["median_skew_deg"] = out["skew_deg"]["median"]
    out["max_cone_violation"] = out["cone_violation"]["max"]
    return out
