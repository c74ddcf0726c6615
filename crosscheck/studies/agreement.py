"""Event agreement: any engine's first event against the analytic slipping rod's, state by state.

The analytic side is ``crosscheck.theory.slipping.slip_until_event``: the rigid rod
slips with F_z = -b/p (eq. FZ) until its first event (LIFTOFF: b -> 0 with
p > 0; JAM: p -> 0 with b < 0; STICK: eta -> 0; GB: b = p = 0).  The engine
side is the engine's ``sweep`` of the same starts, classified by the one
classifier ``crosscheck.engines.classifier``.  This module lines the two up
state by state and summarises where they agree; the engine is named
(``engine=NAME``) and looked up in ``crosscheck.engines``.  The comparison
rule is ``crosscheck.studies.comparison``; the analytic side
``crosscheck.studies.analytic_events``.

Censoring and lag.  The analytic run also stops, with outcome SLIP, when the
state leaves the paper's domain: varphi reaches 0 or -pi (about half of the
states of a grid do, the slip direction turning perpendicular to the rod) or
theta reaches 0 or pi/2.  Nothing is known analytically after that time, so
each state is compared only up to its *comparison time* T_i: the analytic
event time for an event, the domain-exit time for such a SLIP, the horizon
otherwise.  An engine event later than T_i counts as SLIP (still slipping when
the comparison ends); a DIVERGED run is never relabelled, but an engine runs
only two windows past the comparison (below), so a divergence later than
that is not seen (one Bullet run of the full report's convergence table at
timestep 0.003 diverged at t = 1.13, a second after the theory's slip left
the domain at 0.12: it now agrees as a SLIP).  For an analytic
event the comparison extends by ``LAG_TAU`` contact time constants (the
engine's ``Options.contact_time``), and at least by ``LAG_STEPS`` timesteps
(the engine's records resolve time to their rows and a first-order
integrator shifts events by O(dt); for a rigid contact this is the whole
lag): a soft contact builds its force over ~tau and STICK is read at
eta = tau_f, so it meets a rigid event up to ~2 tau late.  States that do not start slipping (b >= 0 or
p <= 0 at t = 0) are not part of the study.

Horizon.  ``DEFAULT_HORIZON`` = 2 scaled time units (2/omega, 0.64 s for a
1 m rod).  On ``DEFAULT_GRID`` 99 % of the analytic first events happen
before t = 1.4 (median 0.19) and 98 % of all states are decided (event or
domain exit) before t = 2; a longer horizon adds engine steps to states that
have already left the comparison.  An engine runs each state to its own
comparison time plus lag (rounded up to horizon / 2^k) plus ``2 W`` (W the
classifier's window), so that an event near that time can still be judged by
the windowed criteria: nothing later can change the label
(``crosscheck.studies.agreement_store``).

Boundary distance.  ``boundary_distance`` probes the analytic outcome with
random perturbations of the initial state (theta, varphi, Theta, Psi, eta;
scaled units) of growing size and returns the smallest size that changes it:
the distance to the analytic event boundary that the study bins disagreement
by.  Disagreement is also binned by the analytic comparison time in units of
the contact time constant (a soft contact needs ~tau to build up the rigid
force) and by |varphi0 + pi/2| (off the planar section MuJoCo's friction is
not anti-parallel to the slip: ``crosscheck.engines.mujoco.studies.contact``).

All times, rates and forces are in the paper's scaled units (section 2.1).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields

import numpy as np

from crosscheck import engines
from crosscheck.checks import ALPHA, POSITIVE, check
from crosscheck.engines.base import options_from_kwargs
from crosscheck.engines.classifier import Thresholds
from crosscheck.error_stats import as_json
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.studies.agreement_store import engine_runs
from crosscheck.studies.analytic_events import (
    BOUNDARY_RADII,
    AnalyticEvents,
    analytic_events,
    boundary_distance,
    floor_times,
)
from crosscheck.studies.comparison import (
    EVENTS,
    LAG_STEPS,
    LAG_TAU,
    RATED,
    comparison_labels,
    engine_floor,
    event_lag,
    event_lags,
    stick_from,
    window_margin,
)
from crosscheck.studies.grids import AXES, EventGrid

__all__ = [
    "DEFAULT_HORIZON",
    "LAG_TAU",
    "LAG_STEPS",
    "window_margin",
    "solver_health",
    "BOUNDARY_RADII",
    "AnalyticEvents",
    "analytic_events",
    "boundary_distance",
    "comparison_labels",
    "AgreementRun",
    "AgreementResult",
    "agreement_study",
    "as_json",
    "quantiles",
]

#: Scaled horizon of the study (see the module docstring).
DEFAULT_HORIZON = 2.0

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


@dataclass(frozen=True, eq=False)
class AgreementResult:
    """Everything ``agreement_study`` measured; ``to_json()`` for the report.

    Attributes:
      engine: the engine's name.
      grid: the ``EventGrid`` (None when points were given directly).
      alpha, horizon: the rod's alpha and the scaled comparison horizon.
      points: dict of (N,) arrays, every grid point (keys ``AXES``).
      analytic: ``AnalyticEvents`` of all N points.
      index: (M,) indices of the studied points (slipping at t = 0).
      distance: (M,) ``boundary_distance`` of the studied points.
      runs: one ``AgreementRun`` per setting of the engine's options.
    """

    engine: str
    grid: EventGrid | None
    alpha: float
    horizon: float
    points: dict = field(repr=False)
    analytic: AnalyticEvents = field(repr=False)
    index: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)
    runs: list = field(default_factory=list)

    def to_dict(self) -> dict:
        a = self.analytic
        rated = np.isin(a.outcome[self.index], RATED)
        counts = {o.name: int((a.outcome[self.index] == o).sum()) for o in Outcome}
        reasons = {r: int((a.reason[self.index] == r).sum()) for r in np.unique(a.reason[self.index])}
        return as_json(
            {
                "engine": self.engine,
                "grid": self.grid.as_dict() if self.grid is not None else None,
                "alpha": self.alpha,
                "horizon": self.horizon,
                "n_points": len(a.outcome),
                "n_slipping": int(self.index.size),
                "n_rated": int(rated.sum()),
                "analytic_outcomes": counts,
                "analytic_reasons": reasons,
                "boundary_radii": list(BOUNDARY_RADII),
                "runs": [r.summary() for r in self.runs],
                "convergence_table": convergence_table(self),
            }
        )

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2, allow_nan=False)


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


def _run_setting(
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


def _settings(E, settings: Sequence[Mapping], options: dict) -> list[dict]:
    """The settings as dicts, each checked with the shared ``options`` against the engine ``E``'s options: an unknown
    or invalid option is a ValueError before anything runs."""
    settings = [dict(s) for s in settings]
    if not settings:
        raise ValueError("settings must hold at least one dict of engine options")
    for s in settings:
        options_from_kwargs(E.Options, {**options, **s}, E.label)
    return settings


def _studied(points: dict, *, alpha: float, horizon: float, progress: bool, kept):
    """(a, idx): the analytic first events of the points (``analytic_events``) and the indices of the slipping
    ones, the states studied (a ValueError if there is none)."""
    a = analytic_events(points, alpha=alpha, horizon=horizon, progress=progress, kept=kept)
    idx = np.flatnonzero(a.slipping)
    if idx.size == 0:
        raise ValueError("the grid has no slipping state (b < 0 < p at t = 0)")
    return a, idx


def _points(grid: EventGrid | dict) -> tuple[dict, EventGrid | None]:
    """(points, grid): the (N,) arrays of ``AXES`` of ``grid`` (an ``EventGrid`` or a dict of them), and the grid
    itself if it is an ``EventGrid`` (else None)."""
    if isinstance(grid, EventGrid):
        return grid.points(), grid
    missing = [k for k in AXES if k not in grid]
    if missing:
        raise ValueError(f"points lack the keys {missing}; need {list(AXES)}")
    points = {k: np.asarray(grid[k], dtype=float).ravel() for k in AXES}
    if len({v.size for v in points.values()}) != 1:
        raise ValueError("points must be (N,) arrays of one length N")
    return points, None


def _boundary_distances(points: dict, a, idx, *, alpha, horizon, rng, radii, directions: int, progress, kept):
    """``boundary_distance`` of the studied points ``idx`` (the others are not probed); NaN everywhere when
    ``directions`` = 0."""
    if directions <= 0:
        return np.full(idx.size, np.nan)
    mask = np.zeros(len(a.outcome), bool)
    mask[idx] = True
    return boundary_distance(
        points,
        a.outcome,
        alpha=alpha,
        horizon=horizon,
        rng=rng,
        radii=radii,
        directions=directions,
        mask=mask,
        progress=progress,
        kept=kept,
    )[idx]


def agreement_study(
    grid: EventGrid | dict,
    *,
    engine: str = engines.DEFAULT,
    settings: Sequence[Mapping] = ({},),
    alpha: float = 3.0,
    horizon: float = DEFAULT_HORIZON,
    rng: np.random.Generator | None = None,
    thresholds: Thresholds | None = None,
    boundary_radii: Sequence[float] = BOUNDARY_RADII,
    boundary_directions: int = 6,
    progress: bool = False,
    store=None,
    scheduler: str | None = None,
    workers: int | None = None,
    boundary_cache=None,
    analytic_cache=None,
    **options,
) -> AgreementResult:
    """Event agreement, analytic vs an engine, over ``grid`` at one or more settings of the engine's options.

    Args:
      grid: the initial states and friction coefficients: an ``EventGrid``
        or a dict of (N,) arrays with the keys ``AXES`` (e.g. random states).
      engine: the engine's name in ``crosscheck.engines``.
      settings: one dict of engine options per run (e.g.
        ``[{"timestep": 3e-4, "timeconst": 0.06}, {"timestep": 1e-4, "timeconst": 0.02}]``
        for a convergence study); ``({},)`` runs the engine's defaults once.
      alpha: m l^2 / I0 of the rod (``Rod.scaled(alpha)``).
      horizon: scaled comparison horizon (``DEFAULT_HORIZON``).
      rng: generator of ``boundary_distance``'s probes (default seed 0).
      thresholds: outcome criteria (``Thresholds()`` by default).
      boundary_radii, boundary_directions: as ``boundary_distance``;
        boundary_directions = 0 skips the probing (distances NaN).
      progress: tqdm bars.
      store, scheduler, workers: run the engine's sweeps through
        ``crosscheck.sweeps`` with their chunks kept under the directory
        ``store`` (a rerun resumes them), on ``workers`` processes or a Dask
        ``scheduler`` ("local" or an address); None (default) calls the
        engine's ``sweep`` directly.  The runs are the same either way.
      boundary_cache: a file (.npy) keeping the boundary distances of these
        points, ``rng`` and probe settings: read if it holds them, written
        otherwise (the caller keys the name by what the distances depend on;
        a file of another shape is computed again and replaced).
      analytic_cache: a file (.npz) keeping the analytic first events of these
        points, alpha and horizon, as ``boundary_cache`` (``analytic_events``'s
        ``kept``).
      **options: engine options shared by every setting (radius, ...).

    Returns:
      ``AgreementResult``.
    """
    E = engines.get(engine)
    settings = _settings(E, settings, options)
    alpha = float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, POSITIVE))
    rng = rng if rng is not None else np.random.default_rng(0)
    points, grid = _points(grid)
    a, idx = _studied(points, alpha=alpha, horizon=horizon, progress=progress, kept=analytic_cache)
    dist = _boundary_distances(
        points,
        a,
        idx,
        alpha=alpha,
        horizon=horizon,
        rng=rng,
        radii=boundary_radii,
        directions=boundary_directions,
        progress=progress,
        kept=boundary_cache,
    )
    base = {"points": points, "analytic": a, "index": idx, "distance": dist, "horizon": horizon}
    rod = Rod.scaled(alpha)
    runs = [
        _run_setting(
            base,
            engine=E.name,
            rod=rod,
            setting=s,
            thresholds=thresholds,
            progress=progress,
            options=options,
            store=store,
            scheduler=scheduler,
            workers=workers,
        )
        for s in settings
    ]
    return AgreementResult(
        engine=E.name,
        grid=grid,
        alpha=alpha,
        horizon=horizon,
        points=points,
        analytic=a,
        index=idx,
        distance=dist,
        runs=runs,
    )


def convergence_table(result: AgreementResult) -> list[dict]:
    """One row per run: engine, timestep, timeconst, n_rated, agreement, median |t_engine - t_analytic|, planar/3-D split.

    ``planar`` rows are the studied states starting on the planar section
    varphi = -pi/2 with Psi = 0 (they stay on it); ``off_plane`` the rest.
    """
    idx = result.index
    a = result.analytic
    ao = a.outcome[idx]
    rated = np.isin(ao, RATED)
    planar = (np.abs(result.points["varphi"][idx] + math.pi / 2) < 1e-12) & (result.points["Psi"][idx] == 0.0)
    rows = []
    for r in result.runs:
        agree = r.label == ao
        row = {
            "engine": r.engine,
            "timestep": r.timestep,
            "timeconst": r.timeconst,
            "n_rated": r.n_rated,
            "agreement": r.agreement,
            "agreement_jam_as_stop": r.agreement_jam_as_stop,
            "median_abs_time_difference": r.median_abs_time_difference,
            "steps_per_second": r.steps_per_second,
            "engine_warnings": int(sum(r.engine_warnings.values())),
        }
        for name, sel in (("planar", planar), ("off_plane", ~planar)):
            s = rated & sel
            row[f"n_{name}"] = int(s.sum())
            row[f"agreement_{name}"] = float(agree[s].mean()) if s.any() else math.nan
        if r.solver_health is not None and "unconverged_steps" in r.solver_health:  # an iterative solver's health
            row["unconverged_steps"] = r.solver_health["unconverged_steps"]
            row["unconverged_states"] = r.solver_health["unconverged_states"]
        rows.append(row)
    return rows
