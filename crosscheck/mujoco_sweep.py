"""Many slipping states through MuJoCo at once: ``mujoco.rollout`` in chunks, one classifier.

``sweep`` is ``crosscheck.mujoco_rod.simulate`` for a batch: the same model
(``build_model``), the same start (``initial_state``), the same record
(``record_from_sensordata``) and the same ``classify``, so a state gives the
same outcome and event time either way (tests assert equality).  The work is
done by a persistent ``mujoco.rollout.Rollout`` thread pool (``nthread``
threads, one ``MjData`` each) over chunks of states sized to a memory budget;
only sensors are recorded (``skip_checks=True`` so MuJoCo does not also copy
the full state of every step).  A tqdm bar counts chunks.

Per-state results come back as arrays ready for a report: outcome, event time,
domain exit time, a summary at the event, and decimated time series.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import mujoco
import numpy as np
from mujoco import rollout
from tqdm.auto import tqdm

from crosscheck.checks import MU, POSITIVE, check
from crosscheck.mujoco_rod import (
    Options,
    SensorLayout,
    Thresholds,
    build_model,
    classify,
    initial_state,
    n_steps,
    record_from_sensordata,
)
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["Batch", "SweepResult", "sweep", "SERIES", "SUMMARY"]

#: Decimated time series kept per state (each (B, n_series)), scaled units:
#: t, eta and varphi of the contact point, theta, Theta, Psi, gap of the
#: capsule's lowest point, and the normal force averaged over each decimation
#: interval (the impulse per unit time, which is what matches -b/p).
SERIES = ("t", "eta", "varphi", "theta", "Theta", "Psi", "gap", "normal_force")

#: Per-state scalars in ``SweepResult.summary`` (each (B,)):
#: at the event row (or the last row for SLIP): eta, varphi, theta, Theta, Psi,
#: b and p of MuJoCo's state; over the run: the largest normal force in one row
#: (the spikes), the largest window-mean normal force, the fraction of rows
#: with a MuJoCo contact, the largest gap.
SUMMARY = ("eta", "varphi", "theta", "Theta", "Psi", "b", "p", "max_normal_force", "max_window_force", "active_fraction", "max_gap")

#: Memory for one chunk's sensordata; sets the chunk size.
CHUNK_BYTES = 48 * 2**20


@dataclass(frozen=True, eq=False)
class SweepResult:
    """Outcomes of a batch of B states (``sweep``).

    Attributes:
      outcome: (B,) int8 ``Outcome`` values.
      event_time: (B,) scaled event times (NaN for SLIP).
      exit_time: (B,) scaled time theta left (0, pi/2) (NaN if never).
      diverged_time: (B,) scaled time the run diverged (NaN if never), also
        when an earlier event is its outcome.
      states: dict of (B,) arrays theta, varphi, Theta, Psi, eta, psi (the starts).
      mu: (B,) friction coefficients.
      summary: dict of (B,) arrays, keys ``SUMMARY``.
      series: dict of (B, n_series) arrays, keys ``SERIES``.
      alpha, horizon, nstep: the rod's alpha, scaled horizon, steps per state.
      options, thresholds: MuJoCo parameters and outcome criteria.
      wall_time: seconds spent in the sweep; steps_per_second: B nstep / wall_time.
    """

    outcome: np.ndarray
    event_time: np.ndarray
    exit_time: np.ndarray
    diverged_time: np.ndarray
    states: dict
    mu: np.ndarray
    summary: dict = field(repr=False)
    series: dict = field(repr=False)
    alpha: float
    horizon: float
    nstep: int
    options: Options
    thresholds: Thresholds
    wall_time: float
    steps_per_second: float

    def __len__(self) -> int:
        return len(self.outcome)


def _decimate_mean(x: np.ndarray, m: int) -> np.ndarray:
    """Mean of consecutive blocks of m rows along the last axis (drops the remainder)."""
    n = (x.shape[-1] // m) * m
    return x[..., :n].reshape(x.shape[:-1] + (n // m, m)).mean(axis=-1)


def _summaries(sd: np.ndarray, layout: SensorLayout, rod: Rod, radius: float, mu: np.ndarray, cls, every: int) -> tuple[dict, dict]:
    """Per-state scalars (``SUMMARY``) and decimated series (``SERIES``) of one chunk."""
    nb, n = sd.shape[:2]
    k = np.where(cls.event_row >= 0, cls.event_row, n - 1)
    at = record_from_sensordata(sd[np.arange(nb), k][:, None, :], layout, rod, radius)
    theta, Theta, Psi, varphi = at.theta[:, 0], at.Theta[:, 0], at.Psi[:, 0], at.varphi[:, 0]
    alpha = rod.alpha
    with np.errstate(invalid="ignore"):
        s, c = np.sin(theta), np.cos(theta)
        b = (Psi**2 * c**2 + Theta**2) * s - 1.0
        p = 1.0 + alpha + alpha * s * (mu * c * np.sin(varphi) - s)
    summary = {
        "eta": at.eta[:, 0],
        "varphi": varphi,
        "theta": theta,
        "Theta": Theta,
        "Psi": Psi,
        "b": b,
        "p": p,
        "max_normal_force": cls.max_normal_force,
        "max_window_force": cls.max_window_force,
        "active_fraction": cls.active_fraction,
        "max_gap": cls.max_gap,
    }
    m = n // every
    dec = record_from_sensordata(sd[:, : m * every : every], layout, rod, radius)
    series = {
        "t": dec.t,
        "eta": dec.eta,
        "varphi": dec.varphi,
        "theta": dec.theta,
        "Theta": dec.Theta,
        "Psi": dec.Psi,
        "gap": dec.gap,
        "normal_force": _decimate_mean(sd[:, : m * every, layout.force.start], every) / rod.force_scale,
    }
    return summary, series


@dataclass(frozen=True, eq=False)
class Batch:
    """A batch of slipping states compiled for ``mujoco.rollout``: models, starts, steps.

    The one implementation of the batched rollout, used by ``sweep`` and by
    ``crosscheck.mujoco_agreement.classified_rollout`` (which classifies the
    same records twice).  Build it with ``Batch.build``; ``chunks`` runs it.

    Attributes:
      models: one compiled model per distinct mu.
      layout: sensor layout (the same for every model).
      mu: (B,) friction of each state.
      x0: (B, nstate) MuJoCo start states (``initial_state``).
      nstep: steps per state; nthread: rollout threads.
    """

    models: dict
    layout: SensorLayout
    mu: np.ndarray
    x0: np.ndarray
    nstep: int
    nthread: int

    @classmethod
    def build(cls, rod: Rod, states: Sequence[SlipState], mu, *, horizon: float, options: Options, nthread: int = 2) -> "Batch":
        """Validate the inputs, compile one model per distinct mu and place every state."""
        states = list(states)
        for i, s in enumerate(states):
            if not isinstance(s, SlipState):
                raise ValueError(f"states[{i}] must be a SlipState; got {type(s).__name__}")
        B = len(states)
        if B == 0:
            raise ValueError("states must contain at least one SlipState")
        horizon = float(check("horizon", horizon, POSITIVE))
        if not (isinstance(nthread, int) and nthread >= 1):
            raise ValueError(f"nthread must be an integer >= 1; got {nthread!r}")
        mu = np.broadcast_to(check("mu", mu, MU), (B,)).astype(float)
        models = {m: build_model(rod, m, options) for m in np.unique(mu)}
        first = next(iter(models.values()))
        scratch = mujoco.MjData(first)  # all models share sizes; the state layout is the same
        x0 = np.stack([initial_state(first, rod, s, options.radius, data=scratch) for s in states])
        return cls(models, SensorLayout.from_model(first), mu, x0, n_steps(horizon, options.timestep), nthread)

    def chunks(self, *, progress: bool, desc: str = "mujoco sweep"):
        """Run the batch; yield (slice of states, (n, nstep, nsensordata) sensordata) per chunk.

        The sensordata buffer is reused between chunks: use it before the next one.
        """
        first = next(iter(self.models.values()))
        B, nsensor = len(self.mu), first.nsensordata
        chunk = int(max(self.nthread, min(B, CHUNK_BYTES // (self.nstep * nsensor * 8))))
        data = [mujoco.MjData(first) for _ in range(self.nthread)]
        buffer = np.empty((chunk, self.nstep, nsensor))
        with rollout.Rollout(nthread=self.nthread if self.nthread > 1 else 0) as pool:
            for a in tqdm(range(0, B, chunk), desc=desc, unit="chunk", disable=not progress):
                sl = slice(a, min(a + chunk, B))
                sd = buffer[: sl.stop - sl.start]
                pool.rollout(
                    [self.models[m] for m in self.mu[sl]],
                    data,
                    np.ascontiguousarray(self.x0[sl]),
                    skip_checks=True,
                    nstep=self.nstep,
                    sensordata=sd,
                    control_spec=mujoco.mjtState.mjSTATE_CTRL.value,
                )
                yield sl, sd


def sweep(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    nthread: int = 2,
    n_series: int = 200,
    progress: bool = True,
    **options,
) -> SweepResult:
    """Simulate every state in MuJoCo and classify it, batched through ``mujoco.rollout``.

    Args:
      rod: physical rod (``Rod.scaled(alpha)`` for the paper's units).
      states: B ``SlipState``s (validated by their constructor).
      mu: friction, a scalar or a (B,) array (one compiled model per distinct value).
      horizon: scaled time per state, > 0.
      thresholds: outcome criteria (``Thresholds()`` by default).
      nthread: rollout threads (2 on this machine's 2 cores).
      n_series: keep between n_series and 2 n_series decimated rows per state in
        ``series`` (every nstep // n_series-th row).
      progress: show a tqdm bar over chunks.
      **options: scaled MuJoCo parameters, as for ``simulate`` (unknown -> ValueError).

    Returns:
      ``SweepResult``.
    """
    states = list(states)
    opts = Options.from_kwargs(options)
    th = thresholds or Thresholds()
    t0 = time.perf_counter()
    batch = Batch.build(rod, states, mu, horizon=horizon, options=opts, nthread=nthread)
    B, mu, layout, nstep = len(states), batch.mu, batch.layout, batch.nstep
    every = max(1, nstep // max(1, n_series))

    outcome = np.empty(B, np.int8)
    event_time = np.empty(B)
    exit_time = np.empty(B)
    diverged_time = np.empty(B)
    summary = {k: np.empty(B) for k in SUMMARY}
    series = {k: np.empty((B, nstep // every)) for k in SERIES}
    for sl, sd in batch.chunks(progress=progress):
        cls = classify(sd, layout, rod=rod, mu=mu[sl], radius=opts.radius, timestep=opts.timestep, thresholds=th)
        outcome[sl], event_time[sl], exit_time[sl], diverged_time[sl] = cls.outcome, cls.event_time, cls.exit_time, cls.diverged_time
        summ, ser = _summaries(sd, layout, rod, opts.radius, mu[sl], cls, every)
        for k in SUMMARY:
            summary[k][sl] = summ[k]
        for k in SERIES:
            series[k][sl] = ser[k]
    wall = time.perf_counter() - t0
    return SweepResult(
        outcome=outcome,
        event_time=event_time,
        exit_time=exit_time,
        diverged_time=diverged_time,
        states={k: np.array([getattr(s, k) for s in states]) for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi")},
        mu=mu.copy(),
        summary=summary,
        series=series,
        alpha=rod.alpha,
        horizon=horizon,
        nstep=nstep,
        options=opts,
        thresholds=th,
        wall_time=wall,
        steps_per_second=B * nstep / wall,
    )
