"""The run stage: compute every section's results and save them, as many sections at a time as there are cores.

Each section runs in its own forked process (``run``'s ``jobs``) and its own
``try``: a section that raises is recorded as failed (error and traceback in
its ``status.json``) and the others run; a section whose process dies (a
crash inside an engine's library) is recorded as failed with its exit code.
Results a section saved before failing stay on disk.  A section whose process
was killed keeps ``status: running``, which the report shows as unfinished.

Resuming (``resume=True``): a section whose saved status is ``ok`` with the
same parameters, quick flag and seed, computed by the same code (the
sha256 of crosscheck's own source files and the versions of numpy, scipy,
MuJoCo and Pinocchio, so an edited work tree or an upgrade recomputes), is
kept as it is.  The sweep-heavy sections keep their engine runs in resumable stores
under ``<out>/sweeps/<section>`` (``crosscheck.sweeps``), so a section
killed half-way keeps its finished chunks too.  Those stores, and the theory
the sections share there (``RunContext.shared``), are kept for the same code
only: ``<out>/sweeps/computed_by.json`` names the code that computed them, and
other code deletes them before any section runs (``_sweeps_of``), so that a
section recomputed after an edit or an upgrade never reads a chunk of the old.
"""

from __future__ import annotations

import importlib
import json
import os
import signal
import sys
import time
import traceback
from collections.abc import Sequence
from pathlib import Path

from crosscheck.report import provenance
from crosscheck.report import store as integrity  # the checks of saved results against what the run wrote
from crosscheck.report.schedule import start_order
from crosscheck.report.section import RunContext, Section, SkipSection, section_rng
from crosscheck.report.store import (  # the saved results, read back
    PROVENANCE_FILE,
    STATUS_FILE,
    SectionStore,
    read_provenance,
    read_status,
    verified_status,
)

__all__ = ["run", "read_status", "read_provenance", "verified_status", "STATUS_FILE", "PROVENANCE_FILE"]


def _progress_factory(enabled: bool):
    if not enabled:
        return lambda iterable, **_: iterable
    from tqdm.auto import tqdm

    def progress(iterable, *, desc: str = "", total: int | None = None, leave: bool = False):
        return tqdm(iterable, desc=desc, total=total, leave=leave, file=sys.stderr, dynamic_ncols=True)

    return progress


LOCK_FILE = ".lock"


def lock(out: Path):
    """Hold ``<out>/.lock`` (``crosscheck.locking.exclusive``) while a report is written into ``out``.

    A second ``crosscheck report`` into the same directory is refused with one
    line instead of interleaving its files with the first one's; a killed run
    never leaves the directory locked (``crosscheck.locking``).
    """
    from crosscheck.locking import exclusive, owner_text

    def refuse(holder: str) -> ValueError:
        return ValueError(
            f"out must be a report directory no other process is writing; {str(out)!r} is being written by {holder or 'another process'} "
            "(wait for it, or choose another --out)"
        )

    return exclusive(Path(out) / LOCK_FILE, owner_text(), refuse)


def code_files() -> list[Path]:
    """The package's source and model files (``.py``, ``.xml``) by relative path, through links too: a checkout links
    crosscheck/_models to models/, an installed package holds its copy, and both must give one digest."""
    import crosscheck

    root = Path(crosscheck.__file__).parent
    files = [Path(d, f).relative_to(root) for d, _, names in os.walk(root, followlinks=True) for f in names]
    return sorted(p for p in files if p.suffix in (".py", ".xml") and "__pycache__" not in p.parts)


def code_digest() -> str:
    """sha256 of what computed a section: crosscheck's source (``code_files``) and the versions of the libraries that
    compute (numpy, scipy and every engine's libraries)."""
    import hashlib

    import crosscheck
    from crosscheck import engines

    root = Path(crosscheck.__file__).parent
    h = hashlib.sha256()
    h.update(json.dumps(provenance.package_versions(("numpy", "scipy", *engines.libraries())), sort_keys=True).encode())
    for p in code_files():
        h.update(p.as_posix().encode())
        h.update((root / p).read_bytes())
    return h.hexdigest()


def _sweeps_of(out: Path, computed_by: dict, say: bool) -> None:
    """Keep ``<out>/sweeps`` only if the code ``computed_by`` (its sha256 and crosscheck's version) computed it: the
    engine sweeps' chunks and the shared theory there would otherwise be read by sections recomputed with other code.
    ``say``: one line on stderr when they are deleted."""
    import shutil

    from crosscheck.files import write_atomic
    from crosscheck.report.ownership import sweeps_owned

    root = out / "sweeps"
    stamp = root / "computed_by.json"
    if sweeps_owned(root):  # someone else's sweeps/ is one line, never deleted
        try:
            same = json.loads(stamp.read_bytes().decode()) == computed_by
        except (OSError, UnicodeDecodeError, ValueError):
            same = False  # an older report, or a damaged stamp: nothing proves what computed them
        if not same:
            if say:
                sys.stderr.write(
                    f"report: {root} was computed by other code or library versions; its sweeps are recomputed\n"
                )
            if root.is_dir():
                shutil.rmtree(root)
            else:
                root.unlink()
    root.mkdir(parents=True, exist_ok=True)
    write_atomic(stamp, (json.dumps(computed_by, sort_keys=True) + "\n").encode())


def _compute(s: Section, out: Path, status: dict, ctx: RunContext, log: bool) -> dict:
    """Run one section (this process) and save its status; returns the status."""
    if log:
        sys.stderr.write(f"report: {s.slug}: started\n")
        sys.stderr.flush()
    ctx.store.write_json(STATUS_FILE, status)
    t0 = time.perf_counter()
    try:
        s.run(ctx)
        status["status"] = "ok"
    except SkipSection as e:
        status["status"] = "skipped"
        status["reason"] = str(e)
    except Exception as e:  # noqa: BLE001  (a failing section must not stop the others)
        status["status"] = "error"
        status["error"] = f"{type(e).__name__}: {e}"
        status["traceback"] = traceback.format_exc()
    status["seconds"] = time.perf_counter() - t0
    status["checks_failed"] = [c["name"] for c in ctx.checks if not c["passed"] and not c["known_discrepancy"]]
    status["files"] = ctx.store.manifest()  # last: a section is finished only once its status lists what it wrote
    ctx.store.write_json(STATUS_FILE, status)
    if log:
        sys.stderr.write(f"report: {s.slug}: {status['status']} in {status['seconds']:.1f} s\n")
        sys.stderr.flush()
    return status


def _in_child(parent: int, job) -> None:
    """A forked section process: die with the report, drop its lock, run the section, exit.  It ignores SIGINT: a
    Ctrl-C reaches the whole process group, and the report alone answers it (it kills its sections, whose finished
    predecessors are kept), as the sweeps' workers do (``crosscheck.workers``)."""
    from crosscheck.workers import adopt

    adopt(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})  # blocked by the parent across the fork
    code = 0
    try:
        job()
    except BaseException:  # noqa: BLE001  (the status on disk says what happened; the exit code says it failed)
        code = 1
    finally:
        sys.stderr.flush()
        os._exit(code)


def _preload(sections: Sequence[Section]) -> None:
    """Import every section's ``requires`` here, before the sections are forked from this process: each inherits them.

    Otherwise each of the ~90 forked sections imports its own, and that was a large part of a short section's work
    (measured imports in a fresh process: Drake's engine 0.43 s, Pinocchio's 0.67 s, the compliant rod 0.54 s, the
    agreement study 0.48 s).  A module that fails to import here is left for its section, which reports it.
    """
    for s in sections:
        for name in s.requires:
            try:
                importlib.import_module(name)
            except Exception:  # noqa: BLE001 - the section's own run says what is wrong
                pass
    for spec in _engines_of(sections):
        try:
            spec.preload()  # Warp's kernel loads took 1-5 CPU s in each of the 25 Newton section processes
        except Exception:  # noqa: BLE001 - the section's own run says what is wrong
            pass
    from crosscheck.sweeps.store import import_libraries, versions

    versions()  # the installed versions every sweep store stamps, read once here (they are cached per process)
    import_libraries()


def _engines_of(sections: Sequence[Section]) -> list:
    """The registered engines whose module one of ``sections`` requires (an engine's sections require its module)."""
    from crosscheck import engines

    required = {name for s in sections for name in s.requires}
    return [spec for spec in engines.specs() if spec.module in required]


def engine_provenance(sections: Sequence[Section]) -> dict[str, dict]:
    """{engine: what its ``Execution.provenance`` says of this process's runs} for the engines of ``sections`` that say
    something (Newton's kernel compile seconds: measured in this process, by ``_preload`` or by its sections)."""
    out = {}
    for spec in _engines_of(sections):
        try:
            said = spec.provenance()
        except Exception:  # noqa: BLE001 - provenance never costs the report
            said = {}
        if said:
            out[spec.name] = said
    return out


def _run_parallel(jobs_of: dict, order: list[Section], jobs: int, outer, results: dict, out: Path) -> None:
    """Run the sections' jobs in up to ``jobs`` forked processes, each starting once its ``after`` sections are done."""
    import multiprocessing
    from multiprocessing.connection import wait

    ctx = multiprocessing.get_context("fork")
    pending = list(order)
    running: dict = {}  # sentinel -> (process, section)
    waiting_on = {s.slug for s in order}
    parent = os.getpid()
    try:
        while pending or running:
            ready = [s for s in pending if not (set(s.after) & waiting_on - {s.slug})]
            while ready and len(running) < jobs:
                s = ready.pop(0)
                pending.remove(s)
                proc = ctx.Process(target=_in_child, args=(parent, jobs_of[s.slug]), name=f"section {s.slug}")
                # SIGINT held across the fork: a Ctrl-C during it would raise inside the fork's handlers (logging's
                # lock release), which swallow it, and the report would go on; held, it is raised after the fork
                held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
                try:
                    proc.start()
                    running[proc.sentinel] = (proc, s)  # before the SIGINT can come: a running section is killed
                finally:
                    signal.pthread_sigmask(signal.SIG_SETMASK, held)
            if hasattr(outer, "set_postfix_str"):
                outer.set_postfix_str(", ".join(sec.slug for _, sec in running.values()))
            if not running:  # an ``after`` outside this run, or a cycle: run in the declared order
                waiting_on -= {s.slug for s in pending}
                continue
            for sentinel in wait(list(running)):
                proc, s = running.pop(sentinel)
                proc.join()
                waiting_on.discard(s.slug)
                try:
                    status = read_status(out, s.slug) or {}
                except integrity.DamagedResults as e:
                    status = {"status": "error", "error": str(e)}
                if status.get("status") in (None, "running"):  # killed, or a crash inside a library
                    status = {
                        **status,
                        "status": "error",
                        "seconds": status.get("seconds"),
                        "error": f"the section's process ended with exit code {proc.exitcode} before it finished",
                    }
                    store = SectionStore(out / "data" / s.slug)
                    status["files"] = store.manifest()  # what it saved before it died, kept as a failed section's are
                    store.write_json(STATUS_FILE, status)
                results[s.slug] = status
                if hasattr(outer, "update"):
                    outer.update(1)
    finally:
        for proc, _ in running.values():
            proc.kill()
            proc.join()


def _resumed(out: Path, s: Section, results: dict, params: dict, quick: bool, seed: int, code: str) -> bool:
    """Whether section ``s`` finished in ``out`` with the same code, parameters, seed and size (its results intact):
    then its status goes into ``results`` as resumed."""
    try:
        prev = verified_status(out, s.slug)
    except integrity.DamagedResults:
        return False  # damaged results are recomputed, never kept
    same = (
        prev is not None
        and prev.get("status") == "ok"
        and prev.get("quick") == quick
        and prev.get("seed") == seed
        and json.loads(json.dumps(prev.get("params"), default=str)) == json.loads(json.dumps(params, default=str))
        and prev.get("code_sha256") == code
    )
    if same:
        results[s.slug] = {**prev, "resumed": True}
    return same


def _job(s: Section, out: Path, params: dict, started: dict, sweeps: dict, inner, *, show_progress: bool, log: bool):
    """Section ``s`` made ready to run: its directory emptied, its status "running" written (a section killed before
    it started reads as unfinished, never as its old result) and its ``RunContext``; returns the call that runs it.

    ``started``: the status fields every section of this run shares (git, versions, code, quick, seed); ``sweeps``:
    the scheduler and workers of its engine sweeps; ``inner``: the progress factory of its own bars."""
    store = SectionStore(out / "data" / s.slug)
    store.reset()
    status = {
        "slug": s.slug,
        "title": s.title,
        "status": "running",
        "quick": started["quick"],
        "seed": started["seed"],
        "params": params,
        "requires": list(s.requires),
        "git": started["git"],
        "crosscheck_version": started["crosscheck_version"],
        "code_sha256": started["code_sha256"],
        "date": provenance.now(),
    }
    store.write_json(STATUS_FILE, status)

    def named(iterable, *, desc: str = "", **kw):  # a section's bars say whose they are
        return inner(iterable, desc=f"{s.slug}: {desc}" if desc else s.slug, **kw)

    ctx = RunContext(
        slug=s.slug,
        params=params,
        quick=started["quick"],
        rng=section_rng(started["seed"], s.slug),
        store=store,
        progress=named,
        show_progress=show_progress,
        sweeps={"store": out / "sweeps" / s.slug, **sweeps},
        seed=started["seed"],
    )
    return lambda: _compute(s, out, status, ctx, log)


def _start_provenance(out: Path, root: SectionStore, sections, params: dict, *, quick, seed, argv) -> dict:
    """The run's provenance, written before any section starts.  A partial run (``--only``) keeps the parameters
    recorded for the sections it does not touch."""
    try:
        previous = read_provenance(out) or {}
    except integrity.DamagedResults:
        previous = {}  # rewritten at the end; the sections' own parameters are in their statuses
    prov = provenance.collect(
        quick=quick, seed=seed, parameters={**previous.get("parameters", {}), **params}, argv=argv
    )
    prov["sections_run"] = [s.slug for s in sections]
    # the rod every section simulates: the paper's scaled rod, its alpha each section's (``parameters``); the
    # dynamics terms of Pinocchio's validation alone also use physical rods, which its own result names
    prov["rod"] = {"mass": 1.0, "length": 1.0, "gravity": 1.0, "units": "scaled: time 1/omega, lengths l, forces m g"}
    # what the engines said before (their hooks run at the end): a partial run keeps those of the engines it skips
    prov["engines"] = previous.get("engines", {})
    root.write_json(PROVENANCE_FILE, prov)
    return prov


def _run_serial(jobs_of: dict, order: list, outer, results: dict) -> None:
    """Run the sections' jobs one after the other in this process, in ``order``, each status into ``results``."""
    for s in order:
        if hasattr(outer, "set_postfix_str"):
            outer.set_postfix_str(s.slug)
        results[s.slug] = jobs_of[s.slug]()
        if hasattr(outer, "update"):
            outer.update(1)


def run(
    out: Path | str,
    sections: Sequence[Section],
    *,
    quick: bool,
    seed: int = 0,
    progress: bool = False,
    argv: list[str] | None = None,
    resume: bool = False,
    scheduler: str | None = None,
    workers: int | None = None,
    log: bool = False,
    jobs: int | None = None,
) -> dict[str, dict]:
    """Run ``sections`` and save their results under ``<out>/data``.

    Args:
      out: the report directory.
      sections: the sections to run, in order (others already in ``out`` are kept).
      quick: small grids and short horizons (the quick report).
      seed: master seed; each section draws from ``section_rng(seed, slug)``.
      progress: show tqdm progress bars on stderr.
      log: one line on stderr per section start and end, with its time (for a
        stderr that is not a terminal, where bars would leave stale lines).
      argv: the command line, recorded in the provenance.
      resume: keep sections already finished by the same code with the same
        parameters (module docstring).
      scheduler, workers: where the sweep-heavy sections run their engine
        sweeps (``crosscheck.sweeps.run``: None and the usable cores by
        default, shared among the sections that run at the same time;
        "local" or a Dask scheduler address).
      jobs: sections computed at the same time, each in its own forked
        process (default: the usable cores; 1 runs them one after the other in
        this process).  A section starts once the sections it reads
        (``Section.after``) have finished; the longest known run first.  Every
        section draws from its own generator and writes its own directory, so
        the results do not depend on ``jobs``.  With more than one job the
        sections' own progress bars are off and the report's bar names the
        sections running.

    Returns:
      ``{slug: status}`` of the sections run; a status has ``status`` in
      {"ok", "skipped", "error"}, ``reason`` when skipped, ``error``/``traceback``
      when it failed, and ``seconds``.
    """
    from crosscheck.report.ownership import claim
    from crosscheck.workers import default_workers

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    claim(out)  # a directory someone else wrote is refused before anything of theirs is touched
    data = out / "data"
    data.mkdir(parents=True, exist_ok=True)
    jobs = default_workers() if jobs is None else jobs
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs must be an integer >= 1; got {jobs!r}")
    params = {s.slug: s.params(quick) for s in sections}
    root = SectionStore(data)
    prov = _start_provenance(out, root, sections, params, quick=quick, seed=seed, argv=argv)
    bar = _progress_factory(progress)
    results: dict[str, dict] = {}
    t_all = time.perf_counter()
    version, code = provenance.package_versions(("crosscheck",))["crosscheck"], code_digest()
    _sweeps_of(out, {"code_sha256": code, "crosscheck_version": version}, say=log or progress)
    todo = [s for s in sections if not (resume and _resumed(out, s, results, params[s.slug], quick, seed, code))]
    parallel = jobs > 1 and len(todo) > 1
    inner = bar if not parallel else _progress_factory(False)
    order = start_order(todo, out) if parallel else todo
    if parallel and workers is None and scheduler is None:
        # Sections running side by side already keep the cores busy: a sweep's own pool would only add processes
        # competing for them, forked from a large process at every sweep (the quick report's 264 sweeps cost
        # 16 s of system time and 9 s of wall time that way).
        workers = max(1, default_workers() // min(jobs, len(todo)))
    started = {"git": prov["git"], "crosscheck_version": version, "code_sha256": code, "quick": quick, "seed": seed}
    sweeps = {"scheduler": scheduler, "workers": workers}
    jobs_of = {
        s.slug: _job(s, out, params[s.slug], started, sweeps, inner, show_progress=progress and not parallel, log=log)
        for s in order
    }
    outer = bar(range(len(todo)), desc="report", total=len(todo), leave=True)
    if parallel:
        _preload(todo)
        _run_parallel(jobs_of, order, min(jobs, len(todo)), outer, results, out)
    else:
        _run_serial(jobs_of, order, outer, results)
    if hasattr(outer, "close"):
        outer.close()
    results = {
        s.slug: results[s.slug] for s in sections if s.slug in results
    }  # the declared order, whatever finished first
    prov["seconds"] = time.perf_counter() - t_all
    prov["section_seconds"] = {k: v.get("seconds") for k, v in results.items()}
    prov["sections_resumed"] = [k for k, v in results.items() if v.get("resumed")]
    prov["jobs"] = jobs
    # a partial run keeps what the engines it did not run said before
    prov["engines"] = {**prov["engines"], **engine_provenance(todo)}
    prov["sweep_workers"] = workers if workers is not None else default_workers()
    root.write_json(PROVENANCE_FILE, prov)
    return results
