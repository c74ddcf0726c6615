"""One engine run rated against the analytic first events: ``AgreementRun`` and how a setting's sweep becomes one.

``run_setting`` sweeps the studied states at one setting of the engine's options (``agreement_store.engine_runs``)
and rates them (``_rate``): the engine's labels as compared (``comparison.comparison_labels``, with the lag of the
engine's contact and its STICK floor), the confusion matrix, the agreement overall and in bins, the event-time
differences and the solver's health.  The study over settings: ``crosscheck.studies.agreement``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields

import numpy as np

from crosscheck import engines
from crosscheck.engines.base import options_from_kwargs
from crosscheck.engines.classifier import Thresholds
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.studies.agreement_store import engine_runs
from crosscheck.studies.analytic_events import AnalyticEvents, floor_times
from crosscheck.studies.comparison import (
    EVENTS,
    RATED,
    comparison_labels,
    engine_floor,
    event_lag,
    event_lags,
    stick_from,
    window_margin,
)

__all__ = [
    "AgreementRun",
    "run_setting",
    "solver_health",
    "quantiles",
    "DISTANCE_EDGES",
    "TIME_EDGES_TAU",
    "OFFPLANE_EDGES",
]

_NAMES = [o.name for o in Outcome]


# --------------------------------------------------------------------------
# Engine side, rated against the analytic side
# --------------------------------------------------------------------------


def _confusion(a: np.ndarray, m: np.ndarray) -> np.ndarray:
    c = np.zeros((len(Outcome), len(Outcome)), dtype=int)
    np.add.at(c, (np.asarray(a, int), np.asarray(m, int)), 1)
    return c


def _binned(values: np.ndarray, agree: np.ndarray, edges: Sequence[float], name: str) -> list[dict]:
    rows = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (values >= lo) & ((values < hi) | (math.isinf(hi) & np.isinf(values)))
        rows.append(
            {
                name: [float(lo), float(hi)],
                "n": int(sel.sum()),
                "agreement": float(agree[sel].mean()) if sel.any() else math.nan,
            }
        )
    return rows


#: Bin edges of the disagreement tables.
DISTANCE_EDGES = (0.0, 0.02, 0.05, 0.2, 1.0, math.inf)
TIME_EDGES_TAU = (0.0, 1.0, 3.0, 10.0, math.inf)
OFFPLANE_EDGES = (0.0, 0.05, 0.5, 1.0, 1.6)


@dataclass(frozen=True, eq=False)
class AgreementRun:
    """An engine against the analytic first events at one setting of its options.

    Per-state fields are over the M studied states (``AgreementResult.index``):
      outcome, event_time: the engine's classification (int8, scaled time).
      label: the engine's outcome as compared (``comparison_labels``).
      p_event: the engine's own p (window p_eff) at a JAM (NaN otherwise).
    Summaries:
      engine: the engine's name; timestep, timeconst: its timestep and
        contact time constant (``Options.contact_time``; 0 for a rigid contact).
      confusion: (6, 6) counts, rows analytic outcome, columns engine label,
        both indexed by ``Outcome`` values (``labels`` = their names).
      n_rated, agreement: states with analytic outcome SLIP/LIFTOFF/STICK/JAM
        and the fraction of them whose engine label is the same.
      agreement_jam_as_stop: the same, counting an analytic JAM met by an
        engine STICK as agreement (the slip ends where the theory jams; a soft
        contact stops the tip instead of delivering an impulse).
      time_difference: t_engine - t_analytic for every rated state where both
        report the same event, with ``time_difference_outcome`` its outcome.
      median_abs_time_difference: median |time_difference| (NaN if none).
      by_distance / by_time / by_offplane: agreement in bins of
        ``boundary_distance``, of the comparison time / timeconst (empty for
        a rigid contact), and of |varphi0 + pi/2| (lists of {bin, n, agreement}).
      options, thresholds: the engine's options and the criteria used (dicts;
        ``stick_threshold`` is the STICK speed of this run's friction time constant).
      wall_time [s], steps_per_second: of the sweep.
      engine_warnings: the engine's own warnings during the runs, by kind
        (``SweepResult.warnings``; MuJoCo's instability warnings, each a run
        reset and classified DIVERGED).
      solver_health: for an engine with a solver (``SweepResult.solver``):
        states, steps in contact, steps and states that missed the solver's
        tolerance, the largest iteration count; None otherwise.
      stick_floor: the engine's STICK floor (``comparison.engine_floor``);
        stick_as_slip: how many engine STICKs were compared as the theory's
        SLIP, its slip speed having fallen below that floor (``comparison.stick_from``).
    """

    engine: str
    timestep: float
    timeconst: float
    outcome: np.ndarray = field(repr=False)
    event_time: np.ndarray = field(repr=False)
    label: np.ndarray = field(repr=False)
    p_event: np.ndarray = field(repr=False)
    confusion: np.ndarray
    n_rated: int
    agreement: float
    agreement_jam_as_stop: float
    time_difference: np.ndarray = field(repr=False)
    time_difference_outcome: np.ndarray = field(repr=False)
    median_abs_time_difference: float
    by_distance: list = field(repr=False)
    by_time: list = field(repr=False)
    by_offplane: list = field(repr=False)
    options: dict = field(repr=False)
    thresholds: dict = field(repr=False)
    wall_time: float
    steps_per_second: float
    solver_health: dict | None = None
    engine_warnings: dict = field(default_factory=dict)
    stick_floor: float = math.nan
    stick_as_slip: int = 0

    labels = tuple(_NAMES)

    def summary(self) -> dict:
        """JSON-able summary (no per-state arrays except the time differences)."""
        td = self.time_difference
        pct = {str(q): float(np.percentile(td, q)) for q in (5, 25, 50, 75, 95)} if td.size else {}
        per_outcome = {}
        for o in EVENTS:
            sel = self.time_difference_outcome == o
            per_outcome[o.name] = {
                "n": int(sel.sum()),
                "median": float(np.median(td[sel])) if sel.any() else math.nan,
                "median_abs": float(np.median(np.abs(td[sel]))) if sel.any() else math.nan,
            }
        return {
            "engine": self.engine,
            "timestep": self.timestep,
            "timeconst": self.timeconst,
            "labels": list(self.labels),
            "confusion": self.confusion.tolist(),
            "n_rated": self.n_rated,
            "agreement": self.agreement,
            "agreement_jam_as_stop": self.agreement_jam_as_stop,
            "median_abs_time_difference": self.median_abs_time_difference,
            "time_difference_percentiles": pct,
            "time_difference_by_outcome": per_outcome,
            "time_difference": td.tolist(),
            "time_difference_outcome": [_NAMES[int(o)] for o in self.time_difference_outcome],
            "jam_p_event": quantiles(self.p_event[self.outcome == Outcome.JAM]),
            "by_distance": self.by_distance,
            "by_time_over_timeconst": self.by_time,
            "by_offplane": self.by_offplane,
            "options": self.options,
            "thresholds": self.thresholds,
            "stick_floor": self.stick_floor,
            "stick_as_slip": self.stick_as_slip,
            "wall_time": self.wall_time,
            "steps_per_second": self.steps_per_second,
            "solver_health": self.solver_health,
            "engine_warnings": self.engine_warnings,
        }


def solver_health(solver: dict | None, columns: Sequence[str]) -> dict | None:
    """Totals of a sweep's per-state solver statistics (``SweepResult.solver``) over the engine's declared ``columns``: the
    number of states, each column's sum (its maximum for a ``max_`` column) and, for ``unconverged_steps``, the states with
    any; None for an engine without solver statistics."""
    if solver is None or not columns:
        return None
    out = {"states": int(np.asarray(solver[columns[0]]).size)}
    for c in columns:
        x = np.asarray(solver[c])
        out[c] = int(np.max(x)) if c.startswith("max_") else int(np.sum(x))
        if c == "unconverged_steps":
            out["unconverged_states"] = int((x > 0).sum())
    return out


def quantiles(x: np.ndarray) -> dict:
    """{n, min, median, max} of the finite entries of ``x`` ({n: 0} if none)."""
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    if not x.size:
        return {"n": 0}
    return {"n": int(x.size), "min": float(x.min()), "median": float(np.median(x)), "max": float(x.max())}


def _rate(
    *,
    engine: str,
    opts,
    th: Thresholds,
    outcome,
    event_time,
    p_event,
    a: AnalyticEvents,
    idx,
    distance,
    offplane,
    wall_time: float,
    steps_per_second: float,
    solver: dict | None = None,
    warnings: dict | None = None,
    points: dict,
    alpha: float,
    horizon: float,
) -> AgreementRun:
    until = a.until[idx]
    ao = a.outcome[idx]
    tau = float(opts.contact_time)
    # A soft contact answers the rigid force with a lag ~ tau (its force builds up over tau; STICK is
    # read at eta = tau_f): an analytic event may be met up to LAG_TAU tau later, and never less than
    # LAG_STEPS timesteps later (a record resolves time to its rows and a first-order integrator moves
    # an event by O(dt): this is what a rigid contact gets).  Censored
    # SLIPs get no lag: nothing is known analytically after the domain exit.
    # at a Corollary 4.2 jam a spring contact lags by s* (eps^4 / (k |b|))^(1/5) (crosscheck.theory.jam_lag)
    lag = event_lags(ao, a.jam_scale[idx], opts)
    # an engine STICK the classifier cannot tell from the theory's slip, slower there than the engine's STICK floor
    floor = engine_floor(th, opts)
    since = stick_from(
        ao,
        until,
        floor_times(points, idx, a, floor, alpha=alpha, horizon=horizon),
        event_lag(tau, float(opts.timestep)),
    )
    label = comparison_labels(outcome, event_time, until + lag, since)
    rated = np.isin(ao, RATED)
    agree = label == ao
    same_event = rated & agree & np.isin(ao, EVENTS)
    td = event_time[same_event] - a.time[idx][same_event]
    stop = agree | ((ao == Outcome.JAM) & (label == Outcome.STICK))
    return AgreementRun(
        engine=engine,
        timestep=float(opts.timestep),
        timeconst=tau,
        outcome=outcome,
        event_time=event_time,
        label=label,
        p_event=p_event,
        confusion=_confusion(ao, label),
        n_rated=int(rated.sum()),
        agreement=float(agree[rated].mean()) if rated.any() else math.nan,
        agreement_jam_as_stop=float(stop[rated].mean()) if rated.any() else math.nan,
        time_difference=td,
        time_difference_outcome=ao[same_event],
        median_abs_time_difference=float(np.median(np.abs(td))) if td.size else math.nan,
        by_distance=_binned(distance[rated], agree[rated], DISTANCE_EDGES, "distance"),
        by_time=_binned(until[rated] / tau, agree[rated], TIME_EDGES_TAU, "time_over_timeconst") if tau > 0 else [],
        by_offplane=_binned(offplane[rated], agree[rated], OFFPLANE_EDGES, "offplane"),
        options={f.name: getattr(opts, f.name) for f in fields(opts)},
        thresholds={**th.as_dict(), "stick_threshold": th.stick_threshold(opts.friction_time)},
        wall_time=wall_time,
        steps_per_second=steps_per_second,
        solver_health=solver_health(solver, engines.get(engine).solver_columns),
        engine_warnings=dict(warnings or {}),
        stick_floor=float(floor),
        stick_as_slip=int(
            ((label == Outcome.SLIP) & (comparison_labels(outcome, event_time, until + lag) == Outcome.STICK)).sum()
        ),
    )


def run_setting(
    base: dict,
    *,
    engine: str,
    rod: Rod,
    setting: Mapping,
    thresholds: Thresholds | None,
    progress: bool,
    options: dict,
    store=None,
    scheduler: str | None = None,
    workers: int | None = None,
) -> AgreementRun:
    """One engine sweep of the studied states at one setting of its options, rated.

    With ``store`` (and the default thresholds and scalar options) the sweep goes
    through ``crosscheck.sweeps``: chunks kept in ``store`` (a rerun resumes),
    on this machine's cores or on a Dask ``scheduler``; the runs are the same.
    """
    points, a, idx, distance, horizon = (base[k] for k in ("points", "analytic", "index", "distance", "horizon"))
    E = engines.get(engine)
    given = {**options, **setting}
    opts = options_from_kwargs(E.Options, given, E.label)
    th = thresholds or Thresholds()
    margin = window_margin(th, opts.timestep)
    offplane = np.abs(points["varphi"][idx] + math.pi / 2)
    # each state runs only as far as its comparison sees (crosscheck.studies.agreement_store): T + lag, plus the margin
    needed = a.until[idx] + event_lags(a.outcome[idx], a.jam_scale[idx], opts)
    cols = {k: points[k][idx] for k in ("theta", "varphi", "Theta", "Psi", "eta")}
    through = store is not None and thresholds is None and not any(isinstance(v, (list, tuple)) for v in given.values())
    r = engine_runs(
        E,
        rod,
        cols,
        points["mu"][idx],
        needed,
        horizon,
        margin,
        given,
        opts,
        th,
        progress,
        store=store if through else None,
        scheduler=scheduler,
        workers=workers,
    )
    return _rate(
        engine=engine,
        opts=opts,
        th=th,
        outcome=r.outcome,
        event_time=r.event_time,
        p_event=r.p_event,
        a=a,
        idx=idx,
        distance=distance,
        offplane=offplane,
        wall_time=r.wall_time,
        steps_per_second=r.steps_per_second,
        solver=r.solver,
        warnings=r.warnings,
        points=points,
        alpha=rod.alpha,
        horizon=horizon,
    )
