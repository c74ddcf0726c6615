"""Event agreement: any engine's first event against the analytic slipping rod's, state by state.

The analytic side is ``crosscheck.theory.slipping.slip_until_event``: the rigid rod
slips with F_z = -b/p (eq. FZ) until its first event (LIFTOFF: b -> 0 with
p > 0; JAM: p -> 0 with b < 0; STICK: eta -> 0; GB: b = p = 0).  The engine
side is the engine's ``sweep`` of the same starts, classified by the one
classifier ``crosscheck.engines.classifier``.  This module lines the two up
state by state and summarises where they agree; the engine is named
(``engine=NAME``) and looked up in ``crosscheck.engines``.  The comparison
rule is ``crosscheck.studies.comparison``; the analytic side
``crosscheck.studies.analytic_events``; one setting's rated engine run
``crosscheck.studies.agreement_run``.

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
from dataclasses import dataclass, field

import numpy as np

from crosscheck import engines
from crosscheck.checks import ALPHA, POSITIVE, check
from crosscheck.engines.base import options_from_kwargs
from crosscheck.engines.classifier import Thresholds
from crosscheck.error_stats import as_json
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.studies.agreement_run import run_setting
from crosscheck.studies.analytic_events import (
    BOUNDARY_RADII,
    AnalyticEvents,
    analytic_events,
    boundary_distance,
)
from crosscheck.studies.comparison import (
    LAG_STEPS,
    LAG_TAU,
    RATED,
    comparison_labels,
    window_margin,
)
from crosscheck.studies.grids import AXES, EventGrid

__all__ = [
    "DEFAULT_HORIZON",
    "LAG_TAU",
    "LAG_STEPS",
    "window_margin",
    "BOUNDARY_RADII",
    "AnalyticEvents",
    "analytic_events",
    "boundary_distance",
    "comparison_labels",
    "AgreementResult",
    "agreement_study",
    "as_json",
]

#: Scaled horizon of the study (see the module docstring).
DEFAULT_HORIZON = 2.0


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
        run_setting(
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
