"""An agreement study's engine runs through the resumable sweep store (``crosscheck.sweeps``): the chunks, the spec, the table read back."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crosscheck.engines.base import n_steps
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod

__all__ = ["STORE_CHUNK", "store_chunk", "sweep_through_store"]


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


def sweep_through_store(E, rod: Rod, states_cols: dict, mu: np.ndarray, horizon: float, given: dict, opts, store, scheduler, workers,
                        progress: bool):
    """The engine's runs through ``crosscheck.sweeps`` (resumable chunks in ``store``): outcome, event_time, jam_p_eff, wall, solver."""
    from crosscheck import sweeps

    doc = {"sweep": {"engine": E.name, "horizon": horizon, "seed": 0, "chunk": store_chunk(E)},
           "states": {"zip": True, **{k: [float(x) for x in v] for k, v in states_cols.items()}, "mu": [float(x) for x in mu]},
           "parameters": {"alpha": float(rod.alpha)}, "options": dict(given)}
    spec = sweeps.parse_spec(doc)
    summary = sweeps.run(spec, Path(store) / f"{E.name}-{spec.digest[:16]}", workers=workers, scheduler=scheduler, progress=progress)
    if summary.failed:
        raise RuntimeError(f"{len(summary.failed)} chunks of the {E.name} sweep failed; first: {next(iter(summary.failed.values()))}")
    df = sweeps.load(summary.out)
    outcome = np.array([Outcome[o] for o in df["outcome"]], np.int8)
    solver = {c: df[f"solver_{c}"].to_numpy() for c in E.solver_columns} or None
    wall = float(df["wall_time"].sum())
    warned = sweeps.Store(summary.out).warnings()
    return (outcome, df["event_time"].to_numpy(), df["jam_p_eff"].to_numpy(), wall, len(df) * n_steps(horizon, opts.timestep) / wall, solver,
            warned)
