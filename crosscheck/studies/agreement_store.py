"""An agreement study's engine runs: each state only as far as its comparison can see, in a few horizons, directly or through the
resumable sweep store (``crosscheck.sweeps``).

Nothing an engine does after a state's comparison time plus its lag
(``crosscheck.studies.comparison``) can change that state's label: a later
event counts as SLIP.  And the classifier judges an event from the rows up to
at most a window and a few rows after it (``classifier.first_event_final``), so
a run that goes two windows (``window_margin``) past that time labels the
state exactly as a run to the study's horizon does.  Each state therefore runs
to the smallest of horizon / 2^k (k = 0 .. ``HORIZON_HALVINGS``) that reaches
min(horizon, T + lag), plus the margin: states of one such horizon make one
sweep.  Labels are those of runs to the horizon (tests compare them); what a
run to the horizon also saw after that time is not kept: a later event's time
and its jam force, a divergence after the comparison (a rod that fell flat, an
engine's artefact after the theory's domain exit), warnings and solver
statistics of steps that could not change a label.  On the full report's
MuJoCo maps the states need 31 % of the steps of runs to the horizon.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from crosscheck.engines.base import n_steps
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod

__all__ = [
    "STORE_CHUNK",
    "HORIZON_HALVINGS",
    "store_chunk",
    "sweep_through_store",
    "run_horizons",
    "EngineRuns",
    "engine_runs",
]

#: How many times the study's horizon is halved for the states whose comparison ends early: a state runs to the smallest
#: of horizon / 2^k, k = 0 .. HORIZON_HALVINGS, past its comparison (at most twice the steps it needs, or horizon / 16).
HORIZON_HALVINGS = 4


#: Runs per chunk when an agreement study goes through a sweep store, for an engine that declares no
#: ``EngineSpec.sweep_chunk`` of its own.
STORE_CHUNK = 32


def store_chunk(E) -> int:
    """Runs per chunk of engine ``E``'s sweeps through a store: its own ``sweep_chunk``, else ``STORE_CHUNK``.

    The chunk is part of the sweep's spec, hence of its digest and of the store's directory name: a
    store written with another chunk size is never resumed into (a rerun after the chunk size changed
    starts its own store beside the old one), and the doc's ``chunk`` is the one the chunks are cut by.
    """
    return STORE_CHUNK if E.sweep_chunk is None else E.sweep_chunk


def sweep_through_store(
    E,
    rod: Rod,
    states_cols: dict,
    mu: np.ndarray,
    horizon: float,
    given: dict,
    store,
    scheduler,
    workers,
    progress: bool,
):
    """The engine's runs through ``crosscheck.sweeps`` (resumable chunks in ``store``): outcome, event_time, jam_p_eff, wall, solver,
    warnings."""
    from crosscheck import sweeps

    doc = {
        "sweep": {"engine": E.name, "horizon": horizon, "seed": 0, "chunk": store_chunk(E)},
        "states": {
            "zip": True,
            **{k: [float(x) for x in v] for k, v in states_cols.items()},
            "mu": [float(x) for x in mu],
        },
        "parameters": {"alpha": float(rod.alpha)},
        "options": dict(given),
    }
    spec = sweeps.parse_spec(doc)
    summary = sweeps.run(
        spec, Path(store) / f"{E.name}-{spec.digest[:16]}", workers=workers, scheduler=scheduler, progress=progress
    )
    if summary.failed:
        raise RuntimeError(
            f"{len(summary.failed)} chunks of the {E.name} sweep failed; first: {next(iter(summary.failed.values()))}"
        )
    df = sweeps.load(summary.out)
    outcome = np.array([Outcome[o] for o in df["outcome"]], np.int8)
    solver = {c: df[f"solver_{c}"].to_numpy() for c in E.solver_columns} or None
    wall = float(df["wall_time"].sum())
    warned = sweeps.Store(summary.out).warnings()
    return outcome, df["event_time"].to_numpy(), df["jam_p_eff"].to_numpy(), wall, solver, warned


def run_horizons(needed, horizon: float) -> np.ndarray:
    """Per state, the horizon its run goes to (before the margin): the smallest horizon / 2^k (k = 0 .. ``HORIZON_HALVINGS``)
    that is at least ``needed`` (its comparison time plus lag, at most ``horizon``)."""
    needed = np.minimum(np.asarray(needed, float), horizon)
    levels = horizon / 2.0 ** np.arange(HORIZON_HALVINGS, -1, -1)  # increasing, the last one the horizon itself
    return levels[np.searchsorted(levels, needed, side="left").clip(max=len(levels) - 1)]


@dataclass(frozen=True)
class EngineRuns:
    """The engine's runs of a study's states, in the states' order: outcome, event_time, jam_p_eff (B,), wall seconds, steps per
    second over every step taken, solver statistics (dict of (B,) arrays or None), warnings by kind."""

    outcome: np.ndarray
    event_time: np.ndarray
    p_event: np.ndarray
    wall_time: float
    steps_per_second: float
    solver: dict | None
    warnings: dict


def engine_runs(
    E,
    rod: Rod,
    states_cols: dict,
    mu: np.ndarray,
    needed: np.ndarray,
    horizon: float,
    margin: float,
    given: dict,
    opts,
    thresholds,
    progress: bool,
    store=None,
    scheduler=None,
    workers=None,
) -> EngineRuns:
    """Every state run to its ``run_horizons`` horizon plus ``margin`` (module docstring), one sweep per horizon: through the
    sweep store when ``store`` is given (``sweep_through_store``, its spec holding the options as ``given``), else by the
    engine's ``sweep`` at every field of ``opts``."""
    from crosscheck.studies.grids import states_at

    B = len(mu)
    every = {f.name: getattr(opts, f.name) for f in fields(opts)}
    runs_to = run_horizons(needed, horizon)
    outcome, event_time, p_event = np.empty(B, np.int8), np.full(B, np.nan), np.full(B, np.nan)
    solver, warned, wall, steps = None, {}, 0.0, 0
    for h in np.unique(runs_to):
        sel = np.flatnonzero(runs_to == h)
        cols = {k: np.asarray(v)[sel] for k, v in states_cols.items()}
        if store is not None:
            o, t, p, w, sv, wn = sweep_through_store(
                E, rod, cols, mu[sel], float(h) + margin, given, store, scheduler, workers, progress
            )
        else:
            r = E.sweep(
                rod,
                states_at(cols, np.arange(len(sel))),
                mu[sel],
                horizon=float(h) + margin,
                thresholds=thresholds,
                progress=progress,
                **every,
            )
            o, t, p, w, sv, wn = r.outcome, r.event_time, r.summary["jam_p_eff"], r.wall_time, r.solver, r.warnings
        outcome[sel], event_time[sel], p_event[sel] = o, t, p
        if sv is not None:
            solver = solver if solver is not None else {k: np.zeros(B, np.asarray(v).dtype) for k, v in sv.items()}
            for k, v in sv.items():
                solver[k][sel] = v
        for k, n in (wn or {}).items():
            warned[k] = warned.get(k, 0) + int(n)
        wall += float(w)
        steps += len(sel) * n_steps(float(h) + margin, opts.timestep)
    return EngineRuns(outcome, event_time, p_event, wall, steps / wall if wall > 0 else float("nan"), solver, warned)
