"""Chunks filled by worker threads and read in order (``crosscheck.engines.mujoco.rollouts.in_order``): every chunk in its
order with the rows its worker wrote, a worker's error at its chunk, and no thread left once the reader stops."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from crosscheck.engines.mujoco.rollouts import in_order


def _workers(n: int, rng: np.random.Generator, fail_at: int | None = None):
    """n fills that write each state's index into its rows after a random pause (so chunks finish out of order)."""
    pauses = rng.uniform(0.0, 0.004, size=64)

    def fill(sl, rows):
        time.sleep(pauses[sl.start])
        if sl.start == fail_at:
            raise RuntimeError(f"rollout failed at state {sl.start}")
        rows[...] = np.arange(sl.start, sl.stop)[:, None]

    return [fill] * n


def _rollout_threads() -> list:
    return [t for t in threading.enumerate() if t.name.startswith("rollout ")]


@pytest.mark.parametrize("workers, buffers", [(2, 3), (2, 4), (3, 4)])
def test_every_chunk_is_read_in_order_with_the_rows_its_worker_wrote(workers, buffers):
    rng = np.random.default_rng(3)
    slices = [slice(a, min(a + 3, 40)) for a in range(0, 40, 3)]
    bufs = [np.full((3, 2), -1.0) for _ in range(buffers)]
    seen = []
    for sl, rows in in_order(slices, bufs, _workers(workers, rng)):
        assert rows.shape == (sl.stop - sl.start, 2)
        np.testing.assert_array_equal(rows[:, 0], np.arange(sl.start, sl.stop))  # not overwritten while read
        seen.append(sl)
    assert seen == slices
    assert not _rollout_threads()


def test_a_workers_error_is_raised_at_its_chunk_after_the_chunks_before_it():
    slices = [slice(a, a + 2) for a in range(0, 20, 2)]
    bufs = [np.zeros((2, 1)) for _ in range(3)]
    read = []
    with pytest.raises(RuntimeError, match="rollout failed at state 8"):
        for sl, _ in in_order(slices, bufs, _workers(2, np.random.default_rng(5), fail_at=8)):
            read.append(sl.start)
    assert read == [0, 2, 4, 6]
    assert not _rollout_threads()


def test_a_reader_that_stops_early_leaves_no_worker_running():
    slices = [slice(a, a + 1) for a in range(50)]
    bufs = [np.zeros((1, 1)) for _ in range(3)]
    chunks = in_order(slices, bufs, _workers(2, np.random.default_rng(7)))
    assert next(chunks)[0] == slice(0, 1)
    chunks.close()
    assert not _rollout_threads()
