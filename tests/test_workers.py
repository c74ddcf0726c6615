"""Forked workers leave the objects they inherit to their parent's collector (``crosscheck.workers.adopt``): a collection
in a worker then scans, and so writes to and copies, none of the parent's pages.

Real forked processes of each kind crosscheck starts: a ``pool`` (concurrent.futures), a ``process_pool``
(multiprocessing) and a report's section process.
"""

from __future__ import annotations

import gc
import multiprocessing

from crosscheck.workers import adopt, pool, process_pool

#: An object of this process in a reference cycle (tracked by the cyclic collector), made before any worker is forked.
_INHERITED: list = []
_INHERITED.append(_INHERITED)


def _seen_by_collector() -> tuple[bool, int]:
    """(whether the collector of this process tracks ``_INHERITED``, the number of objects it has frozen)."""
    return any(o is _INHERITED for o in gc.get_objects()), gc.get_freeze_count()


def test_the_parent_keeps_collecting_its_own_objects():
    assert _seen_by_collector() == (True, 0)


def test_a_worker_of_either_pool_does_not_scan_what_it_inherited():
    with pool(1) as p:
        tracked, frozen = p.submit(_seen_by_collector).result()
    assert not tracked and frozen > 0
    with process_pool(1) as p:
        tracked, frozen = p.apply(_seen_by_collector)
    assert not tracked and frozen > 0
    assert _seen_by_collector() == (True, 0)  # the parent's own collector is untouched


def _section_process(parent: int, out) -> None:
    adopt(parent)  # as crosscheck.report.pipeline's section processes start
    out.send(_seen_by_collector())


def test_a_section_process_does_not_scan_what_it_inherited():
    import os

    mine, theirs = multiprocessing.Pipe()
    proc = multiprocessing.get_context("fork").Process(target=_section_process, args=(os.getpid(), theirs))
    proc.start()
    tracked, frozen = mine.recv()
    proc.join()
    assert not tracked and frozen > 0
