"""The run stage: compute every section's results and save them, one section at a time.

Each section runs in its own ``try``: a section that raises is recorded as
failed (error and traceback in its ``status.json``) and the next one runs.
Results a section saved before failing stay on disk.  A section whose process
was killed keeps ``status: running``, which the report shows as unfinished.

Resuming (``resume=True``): a section whose saved status is ``ok`` with the
same parameters, quick flag and seed, computed by the same code (the
sha256 of crosscheck's own source files and the versions of numpy, scipy,
MuJoCo and Pinocchio, so an edited work tree or an upgrade recomputes), is
kept as it is.  The sweep-heavy sections keep their engine runs in resumable stores
under ``<out>/sweeps/<section>`` (``crosscheck.sweeps``), so a section
killed half-way keeps its finished chunks too.
"""

from __future__ import annotations

import json
import sys
import time
import traceback
from pathlib import Path
from typing import Sequence

from crosscheck.report import integrity, provenance
from crosscheck.report.section import RunContext, Section, SkipSection, section_rng
from crosscheck.report.store import SectionStore

__all__ = ["run", "read_status", "read_provenance", "verified_status", "STATUS_FILE", "PROVENANCE_FILE"]

STATUS_FILE = "status"
PROVENANCE_FILE = "provenance"


def _progress_factory(enabled: bool):
    if not enabled:
        return lambda iterable, **_: iterable
    from tqdm.auto import tqdm

    def progress(iterable, *, desc: str = "", total: int | None = None, leave: bool = False):
        return tqdm(iterable, desc=desc, total=total, leave=leave, file=sys.stderr, dynamic_ncols=True)

    return progress


def read_status(out: Path, slug: str) -> dict | None:
    """The saved status of a section, None if it never ran in ``out``; ``DamagedResults`` if it is not one."""
    path = Path(out) / "data" / slug / f"{STATUS_FILE}.json"
    if not path.exists():
        return None
    return integrity.check_status(integrity.read_json(path, "the section status"), path)


def read_provenance(out: Path) -> dict | None:
    """The saved provenance of a report, None if there is none; ``DamagedResults`` if it is not one."""
    path = Path(out) / "data" / f"{PROVENANCE_FILE}.json"
    if not path.exists():
        return None
    return integrity.check_provenance(integrity.read_json(path, "the provenance"), path)


def verified_status(out: Path, slug: str) -> dict | None:
    """``read_status`` with the section's saved files checked against the manifest in it (``DamagedResults``)."""
    status = read_status(out, slug)
    if status is not None and status["status"] != "running":
        SectionStore(Path(out) / "data" / slug).verify(status["files"])
    return status


LOCK_FILE = ".lock"


def lock(out: Path):
    """Hold ``<out>/.lock`` (``crosscheck.locking.exclusive``) while a report is written into ``out``.

    A second ``crosscheck report`` into the same directory is refused with one
    line instead of interleaving its files with the first one's; a killed run
    never leaves the directory locked (``crosscheck.locking``).
    """
    from crosscheck.locking import exclusive, owner_text

    def refuse(holder: str) -> ValueError:
        return ValueError(f"out must be a report directory no other process is writing; {str(out)!r} is being written by {holder or 'another process'} "
                          "(wait for it, or choose another --out)")

    return exclusive(Path(out) / LOCK_FILE, owner_text(), refuse)


def code_digest() -> str:
    """sha256 of what computed a section: crosscheck's source (every .py and model file of the package, by
    relative path) and the versions of the libraries that compute (numpy, scipy and every engine's libraries)."""
    import hashlib

    import crosscheck

    root = Path(crosscheck.__file__).parent
    h = hashlib.sha256()
    from crosscheck import engines

    h.update(json.dumps(provenance.package_versions(("numpy", "scipy", *engines.libraries())), sort_keys=True).encode())
    for p in sorted(root.rglob("*")):
        if p.suffix in (".py", ".xml") and "__pycache__" not in p.parts:
            h.update(str(p.relative_to(root)).encode())
            h.update(p.read_bytes())
    return h.hexdigest()


def run(out: Path | str, sections: Sequence[Section], *, quick: bool, seed: int = 0, progress: bool = False, argv: list[str] | None = None,
        resume: bool = False, scheduler: str | None = None, workers: int | None = None, log: bool = False) -> dict[str, dict]:
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
        default; "local" or a Dask scheduler address).

    Returns:
      ``{slug: status}`` of the sections run; a status has ``status`` in
      {"ok", "skipped", "error"}, ``reason`` when skipped, ``error``/``traceback``
      when it failed, and ``seconds``.
    """
    out = Path(out)
    data = out / "data"
    data.mkdir(parents=True, exist_ok=True)
    params = {s.slug: s.params(quick) for s in sections}
    root = SectionStore(data)
    # A partial run (``--only``) keeps the parameters recorded for the sections it does not touch.
    try:
        previous = read_provenance(out) or {}
    except integrity.DamagedResults:
        previous = {}  # rewritten below; the sections' own parameters are in their statuses
    prov = provenance.collect(quick=quick, seed=seed, parameters={**previous.get("parameters", {}), **params}, argv=argv)
    prov["sections_run"] = [s.slug for s in sections]
    root.write_json(PROVENANCE_FILE, prov)
    bar = _progress_factory(progress)
    results: dict[str, dict] = {}
    t_all = time.perf_counter()
    outer = bar(sections, desc="report", total=len(sections), leave=True)
    version, code = provenance.package_versions(("crosscheck",))["crosscheck"], code_digest()
    for s in outer:
        if hasattr(outer, "set_postfix_str"):
            outer.set_postfix_str(s.slug)
        try:
            prev = verified_status(out, s.slug)
        except integrity.DamagedResults:
            prev = None  # damaged results are recomputed, never kept
        if (resume and prev is not None and prev.get("status") == "ok" and prev.get("quick") == quick and prev.get("seed") == seed
                and json.loads(json.dumps(prev.get("params"), default=str)) == json.loads(json.dumps(params[s.slug], default=str))
                and prev.get("code_sha256") == code):
            results[s.slug] = {**prev, "resumed": True}
            continue
        store = SectionStore(data / s.slug)
        store.reset()
        if log:
            sys.stderr.write(f"report: {s.slug}: started\n")
            sys.stderr.flush()
        status = {
            "slug": s.slug,
            "title": s.title,
            "status": "running",
            "quick": quick,
            "seed": seed,
            "params": params[s.slug],
            "requires": list(s.requires),
            "git": prov["git"],
            "crosscheck_version": version,
            "code_sha256": code,
            "date": provenance.now(),
        }
        store.write_json(STATUS_FILE, status)
        sweeps = {"store": out / "sweeps" / s.slug, "scheduler": scheduler, "workers": workers}
        def named(iterable, *, desc: str = "", _slug=s.slug, **kw):  # a section's bars say whose they are
            return bar(iterable, desc=f"{_slug}: {desc}" if desc else _slug, **kw)

        ctx = RunContext(slug=s.slug, params=params[s.slug], quick=quick, rng=section_rng(seed, s.slug), store=store, progress=named,
                         show_progress=progress, sweeps=sweeps)
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
        status["files"] = store.manifest()  # last: a section is finished only once its status lists what it wrote
        store.write_json(STATUS_FILE, status)
        if log:
            sys.stderr.write(f"report: {s.slug}: {status['status']} in {status['seconds']:.1f} s\n")
            sys.stderr.flush()
        results[s.slug] = status
    prov["seconds"] = time.perf_counter() - t_all
    prov["section_seconds"] = {k: v["seconds"] for k, v in results.items()}
    prov["sections_resumed"] = [k for k, v in results.items() if v.get("resumed")]
    root.write_json(PROVENANCE_FILE, prov)
    return results
