"""One chunk of a sweep: its runs through the engine (or the analytic first event), as columns of one table.

A chunk is the unit of work (one task on a worker) and of storage (one
Parquet file).  It depends only on the spec and its id: nothing in it is
random (random states are drawn when the spec is read), and an engine runs
on one core inside a chunk (its ``EngineSpec.one_core``: the parallelism is over chunks), so
a chunk's table is the same whichever worker computes it and in whatever
order chunks finish.
"""

from __future__ import annotations

import math
import time

import numpy as np

from crosscheck.sweeps.spec import ANALYTIC, AXES, Spec

__all__ = ["compute_chunk", "RESULT_COLUMNS", "result_columns"]

#: Per-run result columns (besides the inputs) of every engine: the outcome's name, times (scaled; NaN
#: where none), the JAM's own p and impulse, and the wall time per run (the chunk's engine time over its
#: runs; the one column that differs between runs).
RESULT_COLUMNS = (
    "engine",
    "outcome",
    "event_time",
    "exit_time",
    "diverged_time",
    "jam_p_eff",
    "jam_impulse",
    "chunk",
    "wall_time",
)


def result_columns(engine: str) -> tuple[str, ...]:
    """``RESULT_COLUMNS`` and, for an engine with solver statistics, ``solver_<field>`` per declared field (integers)."""
    from crosscheck import engines

    solver = engines.get(engine).solver_columns if engine != ANALYTIC else ()
    return RESULT_COLUMNS[:-2] + tuple(f"solver_{c}" for c in solver) + RESULT_COLUMNS[-2:]


def _state(cols: dict, i: int):
    """The ``SlipState`` of run ``i`` of a chunk's columns."""
    from crosscheck.state import SlipState

    return SlipState(**{a: float(cols[a][i]) for a in (*AXES, "psi")})


def _analytic(cols: dict, horizon: float) -> dict:
    """The paper's first event (``slip_until_event``); with the option hybrid, the hybrid flow's last outcome
    (``crosscheck.theory.impact.continuation.run``: through impacts without collision) and the first impact's normal impulse."""
    from crosscheck.outcome import Outcome
    from crosscheck.theory.impact import continuation as hybrid
    from crosscheck.theory.slipping import slip_until_event

    n = len(cols["run"])
    out = {
        "outcome": np.empty(n, object),
        "event_time": np.full(n, np.nan),
        "exit_time": np.full(n, np.nan),
        "jam_impulse": np.full(n, np.nan),
    }
    for i in range(n):
        s = _state(cols, i)
        mu, alpha = float(cols["mu"][i]), float(cols["alpha"][i])
        if "hybrid" in cols and bool(cols["hybrid"][i]):
            e = float(cols["restitution"][i]) if "restitution" in cols else 0.0
            h = hybrid.run(s, mu, alpha, horizon=horizon, restitution=e)
            outcome, t, reason = h.outcome, h.time, h.reason
            if h.impacts:
                out["jam_impulse"][i] = h.impacts[0].normal_impulse
        else:
            r = slip_until_event(s, mu, alpha, t_max=horizon)
            outcome, t, reason = r.outcome, r.time, r.reason
        out["outcome"][i] = outcome.name
        if outcome != Outcome.SLIP:
            out["event_time"][i] = t
        elif reason.startswith("theta"):
            out["exit_time"][i] = t
    return out


def _engine(spec: Spec, cols: dict, warnings: dict) -> dict:
    from crosscheck import engines
    from crosscheck.outcome import Outcome
    from crosscheck.rod import Rod

    E = engines.get(spec.engine)
    n = len(cols["run"])
    out = {k: np.full(n, np.nan) for k in ("event_time", "exit_time", "diverged_time", "jam_p_eff", "jam_impulse")}
    out["outcome"] = np.empty(n, object)
    for c in E.solver_columns:
        out[f"solver_{c}"] = np.full(n, -1, np.int64)
    # one engine sweep per (alpha, option combination) in the chunk; mu may differ run by run
    keys = ["alpha", *spec.options]
    groups: dict[tuple, list[int]] = {}
    for i in range(n):
        groups.setdefault(tuple(cols[k][i] for k in keys), []).append(i)
    for key, idx in groups.items():
        alpha, opts = float(key[0]), dict(zip(keys[1:], key[1:]))
        opts = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in opts.items()}
        states = [_state(cols, i) for i in idx]
        r = E.sweep(
            Rod.scaled(alpha),
            states,
            np.asarray(cols["mu"], float)[idx],
            horizon=spec.horizon,
            progress=False,
            **opts,
            **E.one_core,
        )
        out["outcome"][idx] = [Outcome(int(o)).name for o in r.outcome]
        for kind, count in r.warnings.items():
            warnings[kind] = warnings.get(kind, 0) + int(count)
        for k in ("event_time", "exit_time", "diverged_time"):
            out[k][idx] = getattr(r, k)
        out["jam_p_eff"][idx] = r.summary["jam_p_eff"]
        out["jam_impulse"][idx] = r.summary["jam_impulse"]
        for c in E.solver_columns:
            out[f"solver_{c}"][idx] = r.solver[c]
    return out


def compute_chunk(spec: Spec, chunk_id: int, *, warnings: dict | None = None) -> dict[str, np.ndarray]:
    """The table of chunk ``chunk_id``: its input columns (``Spec.runs``) and ``result_columns``, one row per run.

    ``warnings``: a dict that receives the engine's own warnings during the chunk, by kind (``SweepResult.warnings``).
    """
    if not (0 <= chunk_id < spec.n_chunks):
        raise ValueError(f"chunk_id must be in [0, {spec.n_chunks - 1}]; got {chunk_id}")
    cols = spec.runs(chunk_id)
    n = len(cols["run"])
    t0 = time.perf_counter()
    res = (
        _analytic(cols, spec.horizon)
        if spec.engine == ANALYTIC
        else _engine(spec, cols, {} if warnings is None else warnings)
    )
    wall = (time.perf_counter() - t0) / max(n, 1)
    out = dict(cols)
    out["engine"] = np.full(n, spec.engine, object)
    for k in result_columns(spec.engine)[1:]:
        if k in res:
            out[k] = res[k]
        elif k not in ("chunk", "wall_time"):
            out[k] = np.full(n, math.nan)
    out["chunk"] = np.full(n, chunk_id, np.int64)
    out["wall_time"] = np.full(n, wall)
    return out
