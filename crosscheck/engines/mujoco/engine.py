"""The MuJoCo engine: the capsule rod of ``models/rod.xml`` stepped by MuJoCo, one state or a batch.

``simulate`` runs one slipping state, ``sweep`` a batch through
``mujoco.rollout`` over chunks of states sized to a memory budget; only
sensors are recorded (``skip_checks=True`` so MuJoCo does not also copy the
full state of every step).  With more than one thread each thread rolls out
small chunks on its own, taking the next one as it finishes
(``crosscheck.engines.mujoco.rollouts``), while this thread turns the chunks
into records and classifies them in order, in blocks of a few states whose
arrays stay in the CPU's cache (``BLOCK_BYTES``).  Both go through ``Batch``, so a state gives the same numbers
either way (tests assert equality), and both classify with the one classifier
``crosscheck.engines.classifier``, with the STICK threshold following the run's
friction time constant.  The model, its start and its sensors are in
``crosscheck.engines.mujoco.model``.

Units.  Everything this module takes and returns is in the paper's scaled
units (section 2.1): time in 1/omega, lengths in l, velocities in l omega,
accelerations in g, forces in m g; so are all the options (``timestep`` is
omega dt, ``radius`` is r / l, ...).  ``Rod`` supplies m, l, I0, g.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Sequence
from contextlib import contextmanager
from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from crosscheck.checks import MU, POSITIVE, check_timestep_within, real, real_scalar
from crosscheck.engines.base import (
    SERIES,
    STATE_KEYS,
    SUMMARY,
    Run,
    SweepResult,
    check_states,
    n_steps_within_memory,
    summaries,
)
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.mujoco import rollouts
from crosscheck.engines.mujoco import warning_counts as mujoco_warnings
from crosscheck.engines.mujoco.model import SensorLayout, initial_state, model, record_from_sensordata
from crosscheck.engines.mujoco.options import Options
from crosscheck.progress import bar
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["NAME", "Options", "Batch", "simulate", "sweep", "CHUNK_BYTES"]

#: The engine's registry name.
NAME = "mujoco"

# MuJoCo's warnings are counted, not printed (nor logged to MUJOCO_LOG.TXT in the user's directory).
mujoco_warnings.install()

#: Memory for the sensordata of the chunks in flight (nthread + 2 on several threads: one filling per thread, one read, one
#: filled ahead); sets the chunk size.
CHUNK_BYTES = 48 * 2**20

#: Steps per chunk of a sweep on several rollout threads (``rollouts.in_order``; fewer when ``CHUNK_BYTES`` says so):
#: the threads wait on each other at the batch's end for at most one chunk, and each chunk costs its handoff to the
#: reader and a reading of its own (~0.3 ms that the Record, the classifier and the summaries cost at any size).
THREAD_CHUNK_STEPS = 10_000

#: Sensordata of the states read together (record, classifier, summaries): their arrays then stay in the
#: cache, where the elementwise passes over a whole 48 MiB chunk ran from memory (64 states x 3334 rows: 140 ms
#: in one block, 73-80 ms in blocks of 4-8 states of 0.75 MiB each).
BLOCK_BYTES = 4 * 2**20

#: Bytes per state and row of a run (sensordata, the Record, the classifier's temporaries): the peak
#: resident memory of a 2e5-step run grew by 500 bytes per row; 1.5 x that as a margin.
ROW_BYTES = 768


@dataclass(frozen=True, eq=False)
class Batch:
    """A batch of slipping states compiled for ``mujoco.rollout``: models, starts, steps.

    The one implementation of the MuJoCo rollout, used by ``simulate`` and
    ``sweep``.  Build it with ``Batch.build``; ``records`` runs it.

    Attributes:
      models: one compiled model per distinct mu.
      layout: sensor layout (the same for every model).
      mu: (B,) friction of each state.
      rod: the rod; states: the B slipping states, placed chunk by chunk (``starts``).
      nstep: steps per state; nthread: rollout threads.
      radius: the capsule radius r / l (the contact point's offset below A).
    """

    models: dict
    layout: SensorLayout
    mu: np.ndarray
    rod: Rod
    states: list
    nstep: int
    nthread: int
    radius: float

    @classmethod
    def build(
        cls, rod: Rod, states: Sequence[SlipState], mu, *, horizon: float, options: Options, nthread: int = 2
    ) -> Batch:
        """Validate the inputs and compile one model per distinct mu (the states are placed by ``starts``)."""
        states = check_states(states)
        B = len(states)
        horizon = real_scalar("horizon", horizon, POSITIVE)
        if not (isinstance(nthread, int) and not isinstance(nthread, bool) and nthread >= 1):
            raise ValueError(f"nthread must be an integer >= 1; got {nthread!r}")
        mu = real("mu", mu, MU)
        if mu.ndim > 1 or mu.ndim == 1 and len(mu) not in (1, B):
            raise ValueError(f"mu must be one number or one per state ({B}); got an array of shape {mu.shape}")
        mu = np.broadcast_to(mu, (B,)).astype(float)
        # refuse what cannot fit before allocating it: with several threads, nthread + 2 chunks of a state or more
        # are in flight (``chunks``)
        nstep = n_steps_within_memory(
            horizon,
            options.timestep,
            ROW_BYTES,
            copies=1 if nthread == 1 else nthread + 2,
            what="records",
            context=f" with nthread = {nthread}",
        )
        models = {m: model(rod, m, options) for m in np.unique(mu)}  # compiled once per setting (``model``'s cache)
        first = next(iter(models.values()))
        return cls(models, SensorLayout.from_model(first), mu, rod, states, nstep, nthread, options.radius)

    def starts(self, sl: slice, scratch: mujoco.MjData | None = None) -> np.ndarray:
        """(n, nstate) MuJoCo start states of ``states[sl]`` (``initial_state``).

        Placed per chunk, in the thread that rolls the chunk out: only the first chunk's states then wait before
        the first rollout (placing one takes ~0.2 ms; placing all of them first was 3 % of a default sweep).
        ``scratch``: an ``MjData`` of these models to place them in (reset for each state; a new one if None).
        """
        first = next(iter(self.models.values()))
        scratch = (
            mujoco.MjData(first) if scratch is None else scratch
        )  # all models share sizes; the state layout is the same
        return np.stack([initial_state(first, self.rod, s, self.radius, data=scratch) for s in self.states[sl]])

    def chunks(self, *, progress: bool | None, desc: str = "mujoco sweep"):
        """Run the batch; yield (slice of states, (n, nstep, nsensordata) sensordata) per chunk, in order.

        With more than one rollout thread and more than one chunk, each thread rolls out its own chunks and takes the
        next one as it finishes (``rollouts.in_order``) while the caller reads the chunks in order: use a chunk's
        sensordata before asking for the next one, whose buffer may be the one it lent.
        """
        first = next(iter(self.models.values()))
        B = len(self.mu)
        per_state = self.nstep * first.nsensordata * 8
        threads = self.nthread > 1
        if threads:
            # small chunks: the threads wait on each other only at the batch's end, for at most one chunk
            chunk = max(1, min(-(-THREAD_CHUNK_STEPS // self.nstep), CHUNK_BYTES // (self.nthread + 2) // per_state))
        else:
            chunk = max(1, min(B, CHUNK_BYTES // per_state))
        slices = [slice(a, min(a + chunk, B)) for a in range(0, B, chunk)]
        # With one rollout thread the batch keeps to one core (the sweeps layer runs one such process per core).  One
        # chunk (simulate, a small sweep) has nothing to overlap: it runs here, on the rollout's own threads, as a thread's
        # start and handoff cost ~10 ms on a loaded machine (simulate at horizon 0.01: 5 ms inline, 18 ms through a thread).
        if not threads or len(slices) < 2:
            with _lent_data(first, self.nthread + 1) as lent:
                yield from _counted(self._inline(lent, slices), len(slices), progress, desc)
            return
        with _lent_data(first, 2 * self.nthread) as lent, contextlib.ExitStack() as pools:
            most = max(sl.stop - sl.start for sl in slices)
            buffers = [
                np.empty((most, self.nstep, first.nsensordata)) for _ in range(min(len(slices), self.nthread + 2))
            ]
            workers = [
                self._worker(pools.enter_context(rollout.Rollout(nthread=0)), lent[2 * i], lent[2 * i + 1])
                for i in range(self.nthread)
            ]
            yield from _counted(rollouts.in_order(slices, buffers, workers), len(slices), progress, desc)

    def _rollout(self, pool, data: list, sl: slice, sd: np.ndarray, scratch: mujoco.MjData) -> None:
        """The states of ``sl`` rolled out by ``pool`` in ``data`` (one ``MjData`` per pool thread), their sensors into ``sd``."""
        pool.rollout(
            [self.models[m] for m in self.mu[sl]],
            data,
            self.starts(sl, scratch),
            skip_checks=True,
            nstep=self.nstep,
            sensordata=sd,
            control_spec=mujoco.mjtState.mjSTATE_CTRL.value,
        )

    def _worker(self, pool, data: mujoco.MjData, scratch: mujoco.MjData):
        """A rollout thread's fill(sl, sd): its own single-threaded pool, ``MjData`` and ``MjData`` to place starts in."""
        return lambda sl, sd: self._rollout(pool, [data], sl, sd, scratch)

    def _inline(self, lent: list, slices: list):
        """Each of ``slices`` rolled out here in turn, by the rollout's own ``nthread`` threads, into one buffer."""
        nsensor = next(iter(self.models.values())).nsensordata
        data, scratch = lent[:-1], lent[-1]
        sd = np.empty((max(sl.stop - sl.start for sl in slices), self.nstep, nsensor))
        with rollout.Rollout(nthread=self.nthread if self.nthread > 1 else 0) as pool:
            for sl in slices:
                rows = sd[: sl.stop - sl.start]
                self._rollout(pool, data, sl, rows, scratch)
                yield sl, rows

    def records(self, rod: Rod, *, progress: bool | None, desc: str = "mujoco sweep"):
        """Run the batch; yield (slice of states, ``Record`` of those states) per block of states (``BLOCK_BYTES``)."""
        block = max(1, BLOCK_BYTES // (self.nstep * next(iter(self.models.values())).nsensordata * 8))
        for sl, sd in self.chunks(progress=progress, desc=desc):
            for a in range(0, len(sd), block):
                yield (
                    slice(sl.start + a, min(sl.start + a + block, sl.stop)),
                    record_from_sensordata(sd[a : a + block], self.layout, rod, self.radius),
                )


def _counted(chunks, n: int, progress, desc: str):
    """Yield from ``chunks`` (n of them) under a progress bar, and close it here when the caller stops early (its
    ``finally`` then runs now, not whenever the generator is collected)."""
    try:
        for _ in bar(range(n), progress=progress, desc=desc, unit="chunk"):
            yield next(chunks)
    finally:
        chunks.close()


#: Spare ``MjData`` kept per model layout (``_lent_data``).
SPARE_DATA = 4

_spare: dict = {}  # model layout (_layout) -> [spare MjData]
_spare_lock = threading.Lock()


def _layout(compiled: mujoco.MjModel) -> tuple:
    """What an ``MjData`` of ``compiled`` is sized by: models of one file at other options (mu, radius, solref,
    timestep) share it, as the models of one rollout share its data."""
    return tuple(
        int(getattr(compiled, k))
        for k in (
            "nq",
            "nv",
            "nu",
            "na",
            "nbody",
            "njnt",
            "ngeom",
            "nsite",
            "nsensor",
            "nsensordata",
            "npair",
            "nkey",
            "nmocap",
            "nuserdata",
            "nbuffer",
            "narena",
        )
    )


@contextmanager
def _lent_data(compiled: mujoco.MjModel, n: int):
    """``n`` ``MjData`` for one batch of ``compiled`` (spares of earlier batches when there are some, kept again afterwards).

    Making one costs ~1 ms (its 13 MiB arena), 2 ms of a short ``simulate``, and the ladder and the interventions run
    thousands.  A spare's contents never reach a run: ``initial_state`` resets the data it places a start in, and
    the rollout sets each run's whole physics state and warmstart, as it does for the runs of one sweep that share a
    thread's data (tests/test_engine_mujoco.py compares runs in fresh and used data).  Each batch has its own: two
    batches at once (threads) never share one.
    """
    key = _layout(compiled)
    with _spare_lock:
        free = _spare.setdefault(key, [])
        lent = [free.pop() for _ in range(min(n, len(free)))]
    lent += [mujoco.MjData(compiled) for _ in range(n - len(lent))]
    try:
        yield lent
    finally:
        with _spare_lock:
            free = _spare.setdefault(key, [])
            free.extend(lent[: max(0, SPARE_DATA - len(free))])


def simulate(
    rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds | None = None, **options
) -> Run:
    """Run one slipping state in MuJoCo and classify its first event.

    The capsule starts touching the plane (z_A = r) with the velocities of
    ``state`` (``crosscheck.coordinates``); MuJoCo steps
    ``ceil(horizon / timestep)`` times through ``mujoco.rollout`` (the same
    path as ``sweep``, so a state gives the same numbers either way).

    Args:
      rod: physical rod (``Rod.scaled(alpha)`` for the paper's units).
      state: the paper's scaled slipping state.
      mu: friction coefficient >= 0.
      horizon: scaled time to simulate, > 0.
      thresholds: outcome criteria (``Thresholds()`` by default).
      **options: scaled MuJoCo parameters, the fields of ``Options``:
        timestep, radius, timeconst, dampratio, friction_timeconst, solimp,
        solver_tolerance, model_file.  An unknown name raises ``ValueError``
        naming it.

    Returns:
      ``crosscheck.engines.Run`` with the record, outcome and event time.
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    horizon = real_scalar("horizon", horizon, POSITIVE)
    opts = Options.from_kwargs(options)
    check_timestep_within(opts.timestep, horizon)  # one step past the horizon records nothing to judge
    mu = real_scalar("mu", mu, MU)
    th = thresholds or Thresholds()
    batch = Batch.build(rod, [state], mu, horizon=horizon, options=opts, nthread=1)
    ((_, record),) = batch.records(rod, progress=False)
    one = record.run(0)
    c = classify(
        one,
        mu=mu,
        alpha=rod.alpha,
        timestep=opts.timestep,
        friction_timeconst=opts.friction_time,
        contact_time=opts.contact_time,
        radius=opts.radius,
        thresholds=th,
    )
    return Run.from_classification(
        NAME,
        c,
        one,
        state=state,
        mu=mu,
        alpha=rod.alpha,
        options=opts,
        thresholds=th,
        horizon=horizon,
        nstep=batch.nstep,
    )


def sweep(
    rod: Rod,
    states: Sequence[SlipState],
    mu,
    *,
    horizon: float,
    thresholds: Thresholds | None = None,
    nthread: int = 2,
    n_series: int = 200,
    progress: bool | None = None,
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
      progress: a tqdm bar over chunks: None (default) on a terminal only, True always, False never (``crosscheck.progress``).
      **options: scaled MuJoCo parameters, as for ``simulate`` (unknown -> ValueError).

    Returns:
      ``crosscheck.engines.SweepResult``.
    """
    states = check_states(states)
    opts = Options.from_kwargs(options)
    th = thresholds or Thresholds()
    t0 = time.perf_counter()
    warned_before = mujoco_warnings.counts()
    batch = Batch.build(rod, states, mu, horizon=horizon, options=opts, nthread=nthread)
    B, mu, nstep = len(states), batch.mu, batch.nstep
    every = max(1, nstep // max(1, n_series))

    outcome = np.empty(B, np.int8)
    event_time = np.empty(B)
    exit_time = np.empty(B)
    diverged_time = np.empty(B)
    summary = {k: np.empty(B) for k in SUMMARY}
    series = {k: np.empty((B, nstep // every)) for k in SERIES}
    for sl, record in batch.records(rod, progress=progress):
        c = classify(
            record,
            mu=mu[sl],
            alpha=rod.alpha,
            timestep=opts.timestep,
            friction_timeconst=opts.friction_time,
            contact_time=opts.contact_time,
            radius=opts.radius,
            thresholds=th,
        )
        outcome[sl], event_time[sl], exit_time[sl], diverged_time[sl] = (
            c.outcome,
            c.event_time,
            c.exit_time,
            c.diverged_time,
        )
        summ, ser = summaries(record, c, mu[sl], rod.alpha, every)
        for k in SUMMARY:
            summary[k][sl] = summ[k]
        for k in SERIES:
            series[k][sl] = ser[k]
    wall = time.perf_counter() - t0
    return SweepResult(
        engine=NAME,
        outcome=outcome,
        event_time=event_time,
        exit_time=exit_time,
        diverged_time=diverged_time,
        states={k: np.array([getattr(s, k) for s in states]) for k in STATE_KEYS},
        mu=mu.copy(),
        summary=summary,
        series=series,
        alpha=rod.alpha,
        horizon=float(horizon),
        nstep=nstep,
        options=opts,
        thresholds=th,
        wall_time=wall,
        steps_per_second=B * nstep / wall,
        warnings=mujoco_warnings.since(warned_before),
    )
