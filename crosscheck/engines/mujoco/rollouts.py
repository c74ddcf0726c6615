"""Chunks of a batch filled by worker threads that each take the next chunk as they finish, read in order.

A batched rollout split over threads inside one ``mujoco.rollout`` call ends
every call at a barrier: its last state runs on one thread while the others
wait, and the call after it starts only then.  A sweep of 64 states read
while the next chunk rolls out paid that tail at every chunk (a state is
~8 ms of rollout: ~4 ms of a core per chunk, against ~8 ms of reading).  Here
each thread runs its own single-threaded rollouts (MuJoCo releases the GIL)
and takes the next chunk as soon as it has filled one, so the threads only
wait on each other at the batch's end, and the reader, in this thread, reads
the chunks in their order while the threads fill the next ones.
"""

from __future__ import annotations

import itertools
import queue
import threading
from collections.abc import Callable, Iterator, Sequence

import numpy as np

__all__ = ["in_order"]


def in_order(
    slices: Sequence[slice], buffers: Sequence[np.ndarray], workers: Sequence[Callable[[slice, np.ndarray], None]]
) -> Iterator[tuple[slice, np.ndarray]]:
    """Yield (slice, its rows) for each of ``slices`` in order, each filled by one of ``workers`` in its own thread.

    ``workers[i](sl, rows)`` fills ``rows`` (the first sl.stop - sl.start rows of a buffer) for the states of ``sl``;
    each runs in one thread and may hold that thread's own resources.  A worker takes a free buffer, then the next
    slice, so every slice taken has a buffer and the reader never waits on a slice that no buffer is left for.  A
    chunk's buffer is free again when the reader asks for the next chunk (use a chunk's rows before that).  ``buffers``:
    at least one more than the workers, or the workers wait for the reader.  A worker's error is raised here at its
    chunk; when the reader stops early the workers finish the chunk they are filling and stop.
    """
    n = len(slices)
    free: queue.SimpleQueue = queue.SimpleQueue()
    for b in range(len(buffers)):
        free.put(b)
    taken = itertools.count()  # next() of a count is atomic under the GIL
    filled: dict = {}  # chunk -> (buffer, error or None)
    ready = threading.Condition()
    stop = threading.Event()

    def work(fill) -> None:
        while True:
            b = free.get()
            if b is None or stop.is_set():
                return
            k = next(taken)
            if k >= n:
                free.put(b)  # another worker may still need it to finish
                return
            sl = slices[k]
            try:
                fill(sl, buffers[b][: sl.stop - sl.start])
                got = (b, None)
            except BaseException as e:  # noqa: BLE001 - raised in the reader at this chunk
                got = (b, e)
            with ready:
                filled[k] = got
                ready.notify()

    threads = [
        threading.Thread(target=work, args=(w,), name=f"rollout {i}", daemon=True) for i, w in enumerate(workers)
    ]
    for t in threads:
        t.start()
    try:
        for k in range(n):
            with ready:
                while k not in filled:
                    ready.wait()
                b, error = filled.pop(k)
            if error is not None:
                raise error
            sl = slices[k]
            yield sl, buffers[b][: sl.stop - sl.start]
            free.put(b)
    finally:
        stop.set()
        for _ in threads:
            free.put(None)  # wakes a worker waiting for a buffer
        for t in threads:
            t.join()
