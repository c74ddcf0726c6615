"""The contact-engine interface: what an engine takes (a rod, slipping states, mu) and what it returns.

An engine simulates the paper's rod from slipping states and answers with a
``Run`` (one state) or a ``SweepResult`` (a batch), both classified by the one
classifier ``crosscheck.engines.classifier``.  Everything is in the paper's
scaled units (section 2.1): time in 1/omega, lengths in l, velocities in
l omega, accelerations in g, forces in m g; so are an engine's ``Options``.

An engine declares itself in a ``crosscheck.engines.spec.EngineSpec``, which has
the attributes of ``Engine``; register it with ``crosscheck.engines.register``
and every study and CLI command that takes an engine name can use it.  ``sweep_by_simulate`` gives an engine without a
batched path its ``sweep``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from typing import Any, Protocol, runtime_checkable

import numpy as np

from crosscheck.checks import MU, POSITIVE, check_timestep_within, real, real_scalar
from crosscheck.engines.classifier import Classification, Thresholds, classify
from crosscheck.engines.options import options_from_kwargs
from crosscheck.engines.record import Record
from crosscheck.outcome import Outcome
from crosscheck.progress import bar
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = [
    "Engine",
    "Run",
    "SweepResult",
    "SERIES",
    "SUMMARY",
    "STATE_KEYS",
    "MAX_RECORD_BYTES",
    "n_steps",
    "n_steps_within_memory",
    "options_from_kwargs",  # from crosscheck.engines.options
    "run_inputs",
    "check_states",
    "sweep_mu_workers",
    "summaries",
    "sweep_by_simulate",
    "unjudged_tail",
    "horizon_caveats",
]

#: Decimated time series kept per state by ``sweep`` (each (B, n_series)), scaled units:
#: t, eta and varphi of the contact point, theta, Theta, Psi, gap of the contact
#: point, and the normal force averaged over each decimation interval (the impulse
#: per unit time, which is what matches -b/p).
SERIES = ("t", "eta", "varphi", "theta", "Theta", "Psi", "gap", "normal_force")

#: Per-state scalars in ``SweepResult.summary`` (each (B,)): at the event row (or
#: the last row for SLIP): eta, varphi, theta, Theta, Psi, b and p of the engine's
#: state; the engine's own p and the normal impulse of a JAM (NaN otherwise); over the run: the largest normal force in
#: one row (the spikes), the largest window-mean normal force, the fraction of rows
#: with a contact, the largest gap.
SUMMARY = (
    "eta",
    "varphi",
    "theta",
    "Theta",
    "Psi",
    "b",
    "p",
    "jam_p_eff",
    "jam_impulse",
    "max_normal_force",
    "max_window_force",
    "active_fraction",
    "max_gap",
)

#: The ``SlipState`` fields a ``SweepResult`` keeps per state.
STATE_KEYS = ("theta", "varphi", "Theta", "Psi", "eta", "psi")


@runtime_checkable
class Engine(Protocol):
    """A contact engine for the paper's rod.

    Attributes:
      name: the registry name (``crosscheck.engines.get(name)``).
      Options: a frozen dataclass of the engine's parameters in scaled units,
        constructed from keyword arguments; it has the properties
        ``timestep`` (scaled time between record rows), ``contact_time`` (the
        time over which the contact force builds up: MuJoCo's solref time
        constant; 0 for a rigid contact) and ``friction_time`` (the friction
        time constant that sets the STICK threshold; 0 for a rigid contact).

    Methods:
      simulate(rod, state, mu, *, horizon, thresholds=None, **options) -> Run
      sweep(rod, states, mu, *, horizon, thresholds=None, progress=None, **options) -> SweepResult
        (mu: a scalar or one per state; the same outcome per state as simulate)
    """

    name: str
    Options: type

    def simulate(
        self, rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds | None = None, **options
    ) -> Run: ...

    def sweep(
        self,
        rod: Rod,
        states: Sequence[SlipState],
        mu,
        *,
        horizon: float,
        thresholds: Thresholds | None = None,
        progress: bool | None = None,
        **options,
    ) -> SweepResult: ...


def n_steps(horizon: float, timestep: float) -> int:
    """Steps needed to cover ``horizon`` (both scaled): ceil(horizon / timestep), at least 1."""
    ratio = horizon / timestep
    if not ratio <= 1e15:  # also inf and NaN: a step count no run can take (the engines bound it further by memory)
        raise ValueError(f"horizon / timestep must be at most 1e15 steps; got {horizon:g} / {timestep:g} = {ratio:g}")
    return max(1, int(math.ceil(ratio - 1e-9)))


#: The most memory the records of one run (or one chunk of runs) may take.
MAX_RECORD_BYTES = 4 * 2**30


def n_steps_within_memory(
    horizon: float, timestep: float, row_bytes: int, *, copies: int = 1, what: str = "a record", context: str = ""
) -> int:
    """``n_steps``, refused with the step limit before anything is allocated when ``copies`` records of
    ``row_bytes`` per row would exceed ``MAX_RECORD_BYTES`` (each engine measures its own bytes per row)."""
    n = n_steps(horizon, timestep)
    need = copies * n * row_bytes
    if need > MAX_RECORD_BYTES:
        raise ValueError(
            f"horizon / timestep must be at most {MAX_RECORD_BYTES // (copies * row_bytes)} steps{context} "
            f"({what} of {MAX_RECORD_BYTES / 2**30:g} GiB); got {horizon:g} / {timestep:g} = {n} steps ({need / 2**30:.3g} GiB)"
        )
    return n


def run_inputs(state, mu, horizon, options: dict, Options: type) -> tuple[float, float, Any]:
    """(mu, horizon, opts) of one run, checked as every time-stepping engine's ``simulate`` checks them: a ``SlipState``
    start, horizon > 0, ``Options.from_kwargs(options)`` (unknown or bad option -> ValueError naming it), a timestep not
    above the horizon, and mu in the friction range; one ValueError line naming the first that is not."""
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    horizon = real_scalar("horizon", horizon, POSITIVE)
    opts = Options.from_kwargs(options)
    check_timestep_within(opts.timestep, horizon)
    return real_scalar("mu", mu, MU), horizon, opts


def check_states(states: Sequence[SlipState]) -> list[SlipState]:
    """``states`` as a non-empty list of ``SlipState`` (ValueError naming the first that is not)."""
    states = list(states)
    for i, s in enumerate(states):
        if not isinstance(s, SlipState):
            raise ValueError(f"states[{i}] must be a SlipState; got {type(s).__name__}")
        try:
            s.check_start()
        except ValueError as e:
            raise ValueError(f"states[{i}].{e}") from None
    if not states:
        raise ValueError("states must contain at least one SlipState")
    return states


def unjudged_tail(horizon: float, options: Any, thresholds: Thresholds) -> float:
    """The scaled time at the end of a run of ``horizon`` in which an event can be missed: the JAM and LAUNCH rules
    read the window after a row (``Thresholds.window_rows`` at the run's timestep) and judge no row whose window
    passes the end, so a SLIP says less of that tail (the whole run when it is shorter than the window).  0 for a
    model without a timestep (the theory's own integration judges every event)."""
    dt = getattr(options, "timestep", None)
    if not dt:
        return 0.0
    return float(min(horizon, thresholds.window_rows(dt) * dt))


def horizon_caveats(horizon: float, options: Any, thresholds: Thresholds) -> tuple[str, ...]:
    """What the outcome of a run of ``horizon`` does not say: one sentence when the horizon is not longer than the
    classifier's window (``unjudged_tail``), where any event can be missed; () otherwise."""
    tail = unjudged_tail(horizon, options, thresholds)
    if tail <= 0.0 or tail < horizon:
        return ()
    return (
        f"the horizon {horizon:g} is not longer than the classifier's window ({tail:g} at timestep "
        f"{options.timestep:g}): an event in it is not judged (a JAM needs a whole window after it), so the "
        "outcome says little",
    )


class _Described:
    """What ``Run`` and ``SweepResult`` say about themselves beyond their outcomes: the rod and the horizon's caveat."""

    @property
    def unjudged_tail(self) -> float:
        """``unjudged_tail`` of this run's horizon, options and thresholds (scaled time)."""
        return unjudged_tail(self.horizon, self.options, self.thresholds)

    @property
    def caveats(self) -> tuple[str, ...]:
        """``horizon_caveats`` of this run: () unless the horizon is shorter than the classifier's window."""
        return horizon_caveats(self.horizon, self.options, self.thresholds)

    @property
    def rod_text(self) -> str:
        """The rod simulated, in one phrase (``Rod.describe``; the scaled rod of ``alpha`` when not given)."""
        return (self.rod if self.rod is not None else Rod.scaled(self.alpha)).describe()


@dataclass(frozen=True, eq=False)
class Run(_Described):
    """One simulated slipping state: the record, what happened first and when.

    Attributes:
      engine: the engine's registry name.
      outcome: ``Outcome`` (SLIP, LIFTOFF, STICK, JAM or DIVERGED) from
        ``crosscheck.engines.classifier``.
      event_time: scaled time of that event (NaN for SLIP).
      exit_time: scaled time theta left (0, pi/2) (NaN if never).
      diverged_time: scaled time the run diverged (NaN if never), even when
        another event came first.
      jam_p_eff, jam_impulse: the engine's own p and the normal impulse of a
        JAM [m g / omega] (NaN otherwise).
      record: the time series (``Record``, N rows).
      state, mu, alpha: the run's start and parameters.
      options, thresholds: the engine's parameters and the outcome criteria.
      horizon: scaled time simulated; nstep: steps taken.
      solver: the engine's solver statistics, if it has a solver (None otherwise).
      rod: the rod simulated (``Rod``; set by the registry's ``simulate``, None from an engine called directly).
      unjudged_tail, caveats, rod_text (properties): the end of the run where an event can be missed, what the
        outcome does not say (a horizon shorter than the classifier's window), and the rod in one phrase.
    """

    engine: str
    outcome: Outcome
    event_time: float
    exit_time: float
    diverged_time: float
    jam_p_eff: float
    jam_impulse: float
    record: Record = field(repr=False)
    state: SlipState
    mu: float
    alpha: float
    options: Any
    thresholds: Thresholds
    horizon: float
    nstep: int
    solver: Any = field(default=None, repr=False)
    rod: Rod | None = field(default=None, repr=False)

    @classmethod
    def from_classification(cls, engine: str, c: Classification, record: Record, **kw) -> Run:
        return cls(
            engine=engine,
            outcome=Outcome(int(c.outcome)),
            event_time=float(c.event_time),
            exit_time=float(c.exit_time),
            diverged_time=float(c.diverged_time),
            jam_p_eff=float(c.jam_p_eff),
            jam_impulse=float(c.jam_impulse),
            record=record,
            **kw,
        )


@dataclass(frozen=True, eq=False)
class SweepResult(_Described):
    """Outcomes of a batch of B states (an engine's ``sweep``).

    Attributes:
      engine: the engine's registry name.
      outcome: (B,) int8 ``Outcome`` values.
      event_time: (B,) scaled event times (NaN for SLIP).
      exit_time: (B,) scaled time theta left (0, pi/2) (NaN if never).
      diverged_time: (B,) scaled time the run diverged (NaN if never), also
        when an earlier event is its outcome.
      states: dict of (B,) arrays, keys ``STATE_KEYS`` (the starts).
      mu: (B,) friction coefficients.
      summary: dict of (B,) arrays, keys ``SUMMARY``.
      series: dict of (B, n_series) arrays, keys ``SERIES``.
      alpha, horizon, nstep: the rod's alpha, scaled horizon, steps per state.
      options, thresholds: the engine's parameters and the outcome criteria.
      wall_time: seconds spent in the sweep; steps_per_second: B nstep / wall_time.
      solver: for an engine with a solver (its runs' ``Run.solver``), a dict
        of (B,) arrays, one per field of its statistics; None otherwise.
      warnings: the engine's own warnings during the sweep, by kind (MuJoCo's
        "Nan, Inf or huge value in QACC": each resets one run, classified
        DIVERGED); empty when there were none or the engine has no such channel.
      rod: the rod simulated, as ``Run.rod``; unjudged_tail, caveats, rod_text: as ``Run``'s.
    """

    engine: str
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
    options: Any
    thresholds: Thresholds
    wall_time: float
    steps_per_second: float
    solver: dict | None = field(default=None, repr=False)
    warnings: dict = field(default_factory=dict)
    rod: Rod | None = field(default=None, repr=False)

    def __len__(self) -> int:
        return len(self.outcome)

    def to_pandas(self):
        """The sweep as a ``pandas.DataFrame``, one row per state: the start (``STATE_KEYS``), ``mu``, ``outcome`` as a
        categorical of ``Outcome`` names (every name a category, so counts list the outcomes that did not occur as 0),
        ``event_time``, ``exit_time``, ``diverged_time`` (scaled time) and the ``SUMMARY`` columns."""
        import pandas as pd

        names = [o.name for o in Outcome]
        df = pd.DataFrame(
            {**{k: np.asarray(v) for k, v in self.states.items()}, "mu": np.asarray(self.mu, dtype=float)}
        )
        df["outcome"] = pd.Categorical.from_codes(np.asarray(self.outcome, dtype=int), categories=names)
        for k in ("event_time", "exit_time", "diverged_time"):
            df[k] = np.asarray(getattr(self, k), dtype=float)
        for k, v in (self.summary or {}).items():
            if k not in df:
                df[k] = np.asarray(v)
        df.attrs.update(engine=self.engine, alpha=self.alpha, horizon=self.horizon)
        return df


def _decimate_mean(x: np.ndarray, m: int) -> np.ndarray:
    """Mean of consecutive blocks of m rows along the last axis (drops the remainder)."""
    n = (x.shape[-1] // m) * m
    return x[..., :n].reshape(x.shape[:-1] + (n // m, m)).mean(axis=-1)


def summaries(record: Record, c: Classification, mu: np.ndarray, alpha: float, every: int) -> tuple[dict, dict]:
    """Per-state scalars (``SUMMARY``) and series decimated to every ``every``-th row (``SERIES``) of a batch record."""
    n = len(record)
    at = record.at(np.where(c.event_row >= 0, c.event_row, n - 1))
    with np.errstate(invalid="ignore"):
        summary = {
            "eta": at.eta[..., 0],
            "varphi": at.varphi[..., 0],
            "theta": at.theta[..., 0],
            "Theta": at.Theta[..., 0],
            "Psi": at.Psi[..., 0],
            "b": at.b[..., 0],
            "p": at.p(mu, alpha)[..., 0],
            "jam_p_eff": c.jam_p_eff,
            "jam_impulse": c.jam_impulse,
            "max_normal_force": c.max_normal_force,
            "max_window_force": c.max_window_force,
            "active_fraction": c.active_fraction,
            "max_gap": c.max_gap,
        }
    m = n // every
    dec = record.rows(slice(0, m * every, every))
    series = {
        "t": dec.t,
        "eta": dec.eta,
        "varphi": dec.varphi,
        "theta": dec.theta,
        "Theta": dec.Theta,
        "Psi": dec.Psi,
        "gap": dec.gap,
        "normal_force": _decimate_mean(record.normal_force[..., : m * every], every),
    }
    return summary, series


def _simulate_chunk(
    engine: Engine, rod: Rod, states: list, mu: list, horizon: float, thresholds: Thresholds, options: dict
) -> list:
    return [engine.simulate(rod, s, m, horizon=horizon, thresholds=thresholds, **options) for s, m in zip(states, mu)]


def sweep_mu_workers(mu, n: int, workers) -> np.ndarray:
    """A sweep's ``mu`` (one number or one per state) as n floats, after checking ``workers`` (an integer >= 1)."""
    if not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers must be an integer >= 1; got {workers!r}")
    mu = real("mu", mu, MU)
    if mu.shape not in ((), (n,)):
        raise ValueError(f"mu must be one number or one per state (shape ({n},)), in {MU}; got shape {mu.shape}")
    return np.broadcast_to(mu, (n,)).astype(float)


def sweep_by_simulate(
    engine: Engine,
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    n_series: int = 200,
    progress: bool | None = None,
    workers: int = 1,
    **options,
) -> SweepResult:
    """An engine's ``sweep`` as one ``simulate`` per state (for engines without a batched path).

    Every state's record must have the same number of rows (a fixed timestep).
    ``workers`` > 1 runs chunks of states in that many forked processes (the
    runs and their order are the same as with one).
    """
    states = check_states(states)
    horizon = real_scalar("horizon", horizon, POSITIVE)
    mu = sweep_mu_workers(mu, len(states), workers)
    B = len(states)
    th = thresholds or Thresholds()
    t0 = time.perf_counter()
    if workers == 1 or B == 1:
        runs = [
            engine.simulate(rod, s, float(m), horizon=horizon, thresholds=th, **options)
            for s, m in bar(list(zip(states, mu)), progress=progress, desc=f"{engine.name} sweep", unit="state")
        ]
    else:
        from crosscheck.workers import pool as worker_pool

        size = max(1, math.ceil(B / (4 * workers)))  # a few chunks per worker keeps both busy to the end
        chunks = [(states[a : a + size], [float(m) for m in mu[a : a + size]]) for a in range(0, B, size)]
        with worker_pool(workers) as pool:
            futures = [
                pool.submit(_simulate_chunk, engine, rod, c_states, c_mu, horizon, th, options)
                for c_states, c_mu in chunks
            ]
            runs = [
                r
                for f in bar(futures, progress=progress, desc=f"{engine.name} sweep", unit="chunk")
                for r in f.result()
            ]
    lengths = {len(r.record) for r in runs}
    if len(lengths) != 1:
        raise ValueError(
            f"{engine.name} records have different lengths {sorted(lengths)}; sweep_by_simulate needs a fixed timestep"
        )
    record = Record(**{f.name: np.stack([getattr(r.record, f.name) for r in runs]) for f in fields(Record)})
    opts = runs[0].options
    # the one classifier again on the stacked records: the same rule and numbers as each run's own
    c = classify(
        record,
        mu=mu,
        alpha=rod.alpha,
        timestep=opts.timestep,
        friction_timeconst=opts.friction_time,
        rigid=opts.contact_time == 0.0,
        contact_time=opts.contact_time,
        radius=getattr(opts, "radius", 0.0),
        thresholds=th,
    )
    nstep = lengths.pop()
    summary, series = summaries(record, c, mu, rod.alpha, max(1, nstep // max(1, n_series)))
    solver = None
    if runs[0].solver is not None:
        solver = {f.name: np.array([getattr(r.solver, f.name) for r in runs]) for f in fields(runs[0].solver)}
    wall = time.perf_counter() - t0
    return SweepResult(
        engine=engine.name,
        outcome=c.outcome,
        event_time=c.event_time,
        exit_time=c.exit_time,
        diverged_time=c.diverged_time,
        states={k: np.array([getattr(s, k) for s in states]) for k in STATE_KEYS},
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
        solver=solver,
    )
