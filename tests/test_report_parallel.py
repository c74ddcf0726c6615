"""The report's sections run at the same time in forked processes: truly in parallel, in dependency order, with
results that do not depend on how many ran at once, and a section whose process dies recorded as failed."""

from __future__ import annotations

import json
import os
import time

import numpy as np
import pytest

from crosscheck.report import pipeline
from crosscheck.report.section import Section

#: Seconds a section waits for its partner before concluding that they do not run at the same time.
RENDEZVOUS = 30.0


def _section(slug: str, run, after=()) -> Section:
    return Section(
        slug=slug,
        title=slug,
        paper="",
        params=lambda quick: {"n": 3},
        run=run,
        render=lambda ctx: [],
        after=tuple(after),
    )


def _draws(ctx):
    ctx.store.write_json("draws", ctx.rng.normal(size=ctx.params["n"]).tolist())


def test_two_sections_run_at_the_same_time(tmp_path):
    """Each section waits for a file the other writes: only two sections running at once can both finish."""
    flags = tmp_path / "flags"
    flags.mkdir()

    def meet(me: str, other: str):
        def run(ctx):
            (flags / me).touch()
            deadline = time.time() + RENDEZVOUS
            while not (flags / other).exists():
                if time.time() > deadline:
                    raise RuntimeError(f"{other} never started while {me} ran")
                time.sleep(0.01)
            ctx.store.write_json("met", {"pid": os.getpid()})

        return run

    res = pipeline.run(
        tmp_path / "r", [_section("a", meet("a", "b")), _section("b", meet("b", "a"))], quick=True, jobs=2
    )
    assert {k: v["status"] for k, v in res.items()} == {"a": "ok", "b": "ok"}, res
    pids = {json.loads((tmp_path / "r" / "data" / s / "met.json").read_text())["pid"] for s in "ab"}
    assert len(pids) == 2 and os.getpid() not in pids


def test_a_section_starts_after_the_sections_it_reads(tmp_path):
    def slow_writer(ctx):
        time.sleep(0.5)
        ctx.store.write_json("value", 42)

    def reader(ctx):
        saved = tmp_path / "r" / "data" / "writer" / "value.json"
        ctx.store.write_json("read", json.loads(saved.read_text()))

    sections = [
        _section("reader", reader, after=("writer",)),
        _section("writer", slow_writer),
        _section("other", _draws),
    ]
    res = pipeline.run(tmp_path / "r", sections, quick=True, jobs=2)
    assert all(v["status"] == "ok" for v in res.values()), res
    assert list(res) == ["reader", "writer", "other"]  # reported in the declared order, whatever finished first
    assert json.loads((tmp_path / "r" / "data" / "reader" / "read.json").read_text()) == 42


def test_results_do_not_depend_on_how_many_sections_run_at_once(tmp_path):
    sections = [_section(f"s{i}", _draws) for i in range(4)]
    pipeline.run(tmp_path / "one", sections, quick=True, seed=7, jobs=1)
    pipeline.run(tmp_path / "two", sections, quick=True, seed=7, jobs=2)
    for i in range(4):
        one, two = (json.loads((tmp_path / d / "data" / f"s{i}" / "draws.json").read_text()) for d in ("one", "two"))
        np.testing.assert_array_equal(one, two)
    assert (
        len({tuple(json.loads((tmp_path / "two" / "data" / f"s{i}" / "draws.json").read_text())) for i in range(4)})
        == 4
    )


def test_a_section_whose_process_dies_is_failed_and_the_others_finish(tmp_path):
    def crash(ctx):
        ctx.store.write_json("partial", 1)
        os._exit(139)  # what a segmentation fault inside an engine's library looks like from outside

    res = pipeline.run(tmp_path / "r", [_section("crash", crash), _section("fine", _draws)], quick=True, jobs=2)
    assert res["fine"]["status"] == "ok"
    assert res["crash"]["status"] == "error" and "exit code 139" in res["crash"]["error"]
    saved = pipeline.read_status(tmp_path / "r", "crash")
    assert saved["status"] == "error"


@pytest.mark.parametrize("jobs", [0, -1, 1.5, True, "2"])
def test_jobs_must_be_a_positive_integer(tmp_path, jobs):
    with pytest.raises(ValueError, match=rf"^jobs must be an integer >= 1; got {jobs!r}$"):
        pipeline.run(tmp_path / "r", [_section("s", _draws)], quick=True, jobs=jobs)


def test_a_fresh_run_starts_the_heads_of_the_longest_chains_first_and_a_rerun_the_longest_known(tmp_path):
    """``start_order``: sections never run start by how many wait on them (an engine's maps, then its ladder, then its
    interventions), ties in the declared order; a section that ran before goes after them, longest first."""
    from crosscheck.report.schedule import start_order
    from crosscheck.report.store import SectionStore

    names = ["leaf", "maps", "ladder", "interventions", "other_maps", "other_ladder", "theory"]
    after = {"ladder": ["maps"], "interventions": ["ladder"], "other_ladder": ["other_maps"]}
    todo = [_section(n, _draws, after.get(n, ())) for n in names]
    assert [s.slug for s in start_order(todo, tmp_path)] == [
        "maps",  # two wait on it
        "ladder",
        "other_maps",  # one each, in the declared order
        "leaf",
        "interventions",
        "other_ladder",
        "theory",
    ]
    for slug, seconds in (("theory", 5.0), ("leaf", 9.0)):
        SectionStore(tmp_path / "data" / slug).write_json(
            "status", {"status": "ok", "seconds": seconds, "params": {}, "files": {}}
        )
    assert [s.slug for s in start_order(todo, tmp_path)][-2:] == ["leaf", "theory"]
