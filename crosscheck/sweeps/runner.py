"""Running a sweep: the chunks not yet in the store, on this machine's cores or on a Dask cluster, each written as it finishes.

Executors (``run``'s ``workers`` / ``scheduler``):

* ``workers=1``: in this process, chunk after chunk;
* ``workers=N`` (default: the usable cores): a pool of N forked processes;
* ``scheduler="local"``: a Dask ``LocalCluster`` of ``workers`` single-threaded
  worker processes, started for the run and closed after it;
* ``scheduler="tcp://host:8786"``: a running Dask distributed scheduler.

Only this process writes the store (workers return tables), so a worker on
another machine needs no access to ``out``.  A chunk that raises is recorded
in the manifest with its error and the others go on; re-running the same
command computes only what is missing or failed.
"""

from __future__ import annotations

import re
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from crosscheck.sweeps.chunk import compute_chunk
from crosscheck.sweeps.spec import Spec, load_spec
from crosscheck.sweeps.store import Store
from crosscheck.workers import default_workers

__all__ = ["run", "SweepSummary", "LOG_EVERY"]

#: Without a terminal, one progress line per this many chunks (and at the end).
LOG_EVERY = 10


@dataclass
class SweepSummary:
    """What ``run`` did: chunks in the spec, reused from the store, computed now, failed (id -> error), and the time."""

    out: Path
    n_chunks: int
    n_runs: int
    reused: list = field(default_factory=list)
    computed: list = field(default_factory=list)
    failed: dict = field(default_factory=dict)
    seconds: float = 0.0

    computed_runs: int = 0
    caveats: tuple = ()  # what the outcomes do not say (``Spec.caveats``, also in the store's manifest)

    @property
    def runs_per_second(self) -> float:
        """Runs computed now per second of the whole call."""
        return self.computed_runs / self.seconds if self.seconds > 0 else float("nan")

    def __str__(self) -> str:
        s = (
            f"sweep {self.out}: {self.n_chunks} chunks ({self.n_runs} runs): {len(self.reused)} reused, {len(self.computed)} computed, "
            f"{len(self.failed)} failed, {self.seconds:.1f} s"
        )
        for cid, err in sorted(self.failed.items())[:5]:
            s += f"\n  chunk {cid} failed: {err}"
        if len(self.failed) > 5:
            s += f"\n  ... and {len(self.failed) - 5} more (manifest.json lists them)"
        return s + "".join(f"\ncaveat: {c}" for c in self.caveats)


def _timed_chunk(spec: Spec, chunk_id: int):
    """(table, seconds, the engine's warnings by kind) of one chunk, measured in the process that computes it."""
    warned: dict[str, int] = {}
    t0 = time.perf_counter()
    table = compute_chunk(spec, chunk_id, warnings=warned)
    return table, time.perf_counter() - t0, warned


class _Progress:
    """A tqdm bar over chunks (runs/s and ETA) on a terminal; one log line per LOG_EVERY chunks otherwise."""

    def __init__(self, total: int, runs_per_chunk: float, enabled: bool | None):
        self.total, self.rpc, self.done, self.t0 = total, runs_per_chunk, 0, time.perf_counter()
        tty = sys.stderr.isatty()
        self.enabled = True if enabled is None else enabled
        self.bar = None
        if self.enabled and tty and total:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=total, desc="sweep", unit="chunk", file=sys.stderr, dynamic_ncols=True)

    def update(self) -> None:
        self.done += 1
        rate = self.done * self.rpc / max(time.perf_counter() - self.t0, 1e-9)
        if self.bar is not None:
            self.bar.update(1)
            self.bar.set_postfix_str(f"{rate:.0f} runs/s")
        elif self.enabled and (self.done % LOG_EVERY == 0 or self.done == self.total):
            eta = (self.total - self.done) * self.rpc / rate if rate > 0 else float("nan")
            sys.stderr.write(f"sweep: {self.done}/{self.total} chunks, {rate:.0f} runs/s, ETA {eta:.0f} s\n")

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


#: A Dask scheduler address this package can reach: [tcp://]host:port, host a name, an IPv4 address or an [IPv6]
#: address (tls:// needs a security context and ucx:// the UCX libraries, neither of which crosscheck sets up).
_ADDRESS = re.compile(r"^(?:tcp://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9](?:[A-Za-z0-9.-]*[A-Za-z0-9])?):(\d{1,5})$")

#: Seconds to wait for a scheduler before calling it unreachable.
CONNECT_TIMEOUT = 10.0


def check_scheduler(scheduler) -> str | None:
    """``scheduler`` if it is None, "local" or a Dask scheduler address tcp://host:port; ValueError naming it otherwise."""
    if scheduler is None or scheduler == "local":
        return scheduler
    m = _ADDRESS.match(scheduler) if isinstance(scheduler, str) else None
    if m is None or not 1 <= int(m.group(2)) <= 65535:
        shown = repr(scheduler) if not isinstance(scheduler, str) or len(scheduler) <= 80 else f"{scheduler[:60]!r}..."
        raise ValueError(
            f"scheduler must be 'local' or a Dask scheduler address tcp://host:port (host a name, an IPv4 or an [IPv6] "
            f"address, port in [1, 65535]); got {shown}"
        )
    return scheduler


def check_reachable(scheduler: str | None, timeout: float = CONNECT_TIMEOUT) -> str | None:
    """``check_scheduler``, and for an address, that something accepts a connection there (ValueError naming it otherwise)."""
    import socket

    if check_scheduler(scheduler) in (None, "local"):
        return scheduler
    host, port = _ADDRESS.match(scheduler).groups()
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=timeout):
            pass
    except OSError as e:
        raise ValueError(
            f"scheduler must be a reachable Dask scheduler; nothing accepts connections at {scheduler!r} "
            f"({e.strerror or e or 'no answer'}; waited at most {timeout:g} s)"
        ) from None
    return scheduler


def _client(target, scheduler: str):
    from distributed import Client

    try:
        return Client(target, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as e:
        raise ValueError(
            f"scheduler must be a reachable Dask scheduler; cannot connect to {scheduler!r} in {CONNECT_TIMEOUT:g} s ({e})"
        ) from None


def _results(spec: Spec, todo: list[int], workers: int, scheduler: str | None):
    """Yield (chunk_id, (table, seconds) or exception) as chunks finish."""
    if scheduler is not None:
        from distributed import LocalCluster, as_completed

        cluster = (
            LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
            if scheduler == "local"
            else None
        )
        try:
            with _client(cluster if cluster is not None else scheduler, scheduler) as client:
                spec_f = client.scatter(spec, broadcast=True)
                futures = {
                    client.submit(_timed_chunk, spec_f, c, pure=False, key=f"chunk-{spec.digest[:8]}-{c}"): c
                    for c in todo
                }
                for fut in as_completed(futures):
                    c = futures[fut]
                    try:
                        yield c, fut.result()
                    except Exception as e:  # noqa: BLE001  (a failing chunk is recorded; the others go on)
                        yield c, e
        finally:
            if cluster is not None:
                cluster.close()
        return
    if workers == 1:
        for c in todo:
            try:
                yield c, _timed_chunk(spec, c)
            except Exception as e:  # noqa: BLE001
                yield c, e
        return
    from concurrent.futures import as_completed as done

    from crosscheck.workers import pool as worker_pool
    from crosscheck.workers import stop

    with worker_pool(workers, deaf=True) as pool:
        try:
            futures = {pool.submit(_timed_chunk, spec, c): c for c in todo}
            for fut in done(futures):
                c = futures[fut]
                try:
                    yield c, fut.result()
                except Exception as e:  # noqa: BLE001
                    yield c, e
        except BaseException:  # Ctrl-C (or the caller stopped): the chunks written stay, the running ones are killed
            stop(pool)
            raise


def run(
    spec: Spec | str | Path,
    out: str | Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    fresh: bool = False,
    progress: bool | None = None,
) -> SweepSummary:
    """Run the sweep ``spec`` (a ``Spec`` or a TOML path) into the store ``out``, resuming what is there.

    ``progress``: None or True shows a bar over chunks (runs/s, ETA) on a
    terminal and one line per ``LOG_EVERY`` chunks on stderr otherwise; False
    is silent.

    Raises ``SpecError`` / ``StoreError`` (both ``ValueError``) before any work
    for a bad spec, another writer, or another sweep in ``out`` (unless
    ``fresh``).
    """
    if not isinstance(spec, Spec):
        spec = load_spec(spec)
    if workers is None:
        workers = default_workers()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1; got {workers!r}")
    check_scheduler(scheduler)
    store = Store(out)
    t0 = time.perf_counter()
    with store.writer():
        m = store.open(spec, fresh=fresh)
        done = store.verified(m)
        todo = [c for c in range(spec.n_chunks) if c not in done]
        summary = SweepSummary(
            out=store.root, n_chunks=spec.n_chunks, n_runs=spec.n_runs, reused=sorted(done), caveats=spec.caveats
        )
        bar = _Progress(len(todo), spec.n_runs / spec.n_chunks, progress)
        try:
            for c, res in _results(spec, todo, workers, scheduler):
                if isinstance(res, Exception):
                    err = f"{type(res).__name__}: {res}"
                    store.record_failure(m, c, err)
                    summary.failed[c] = err
                else:
                    table, seconds, warned = res
                    store.write_chunk(m, c, table, seconds, warnings=warned)
                    summary.computed.append(c)
                    summary.computed_runs += len(table["run"])
                bar.update()
        finally:
            bar.close()
    summary.seconds = time.perf_counter() - t0
    return summary
