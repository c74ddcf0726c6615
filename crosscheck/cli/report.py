"""``crosscheck report [--out DIR] [--quick] [--engines A,B] [--from-results] [--seed S] [--only SECTION ...] [--fresh] [--scheduler ADDRESS]``.

Runs every section of the report and saves its results under ``DIR/data``,
then renders ``DIR/index.html`` and ``DIR/report.md`` from the saved results.
A rerun into the same DIR resumes: sections finished by the same code with
the same parameters are kept, and the engine sweeps of the others resume
their finished chunks (``DIR/sweeps``, kept only for the same code and library
versions); ``--fresh`` recomputes everything,
``--only`` recomputes the sections named.  ``--scheduler`` sends the engine
sweeps to a Dask cluster ("local" starts one for the run).
``--engines a,b`` runs the theory's sections and those engines' only; an engine
whose library is not installed has its sections skipped, one line each.
``--from-results`` skips the run stage (rebuilds the report without
re-simulating).  Exits 1 when any section failed or any check failed (known
misprints of the paper excepted), after writing everything that succeeded.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from crosscheck.checks import integer
from crosscheck.cli.options import ascii_number, directory


def _run(args) -> int:
    from crosscheck import report
    from crosscheck.report.ownership import claim
    from crosscheck.report.sections import all_sections, skipped_engines

    names = _engine_names(args.engines)
    # every section (the module's SECTIONS, which a caller may set) unless --engines names some
    sections = list(report.SECTIONS if names is None else all_sections(names))
    selected = sections
    if args.only:
        selected = [report.section_by_slug(s, sections) for s in args.only]  # ValueError names an unknown section
    if args.out is not None and not args.out.strip():
        raise ValueError(f"out must be a writable directory path; got {args.out!r}")
    out = Path(args.out) if args.out is not None else report.default_out(args.quick)
    if args.from_results and not _saved(out):
        raise ValueError(
            f"out must hold saved results with --from-results; {str(out / 'data')!r} has none "
            f"(run `crosscheck report --out {out}` without --from-results first)"
        )
    seed = integer("seed", args.seed, 0, 2**63 - 1)
    workers = None if args.workers is None else integer("workers", args.workers, 1, 1024)
    jobs = None if args.jobs is None else integer("jobs", args.jobs, 1, 1024)
    from crosscheck.sweeps.runner import check_reachable, check_scheduler

    # reached before any section starts: an address with nothing listening would fail each engine section in turn
    scheduler = check_scheduler(args.scheduler) if args.from_results else check_reachable(args.scheduler)
    out = directory("out", out)  # before anything runs: a long run never fails at its first write
    for line in skipped_engines(names):
        print(line)
    with report.lock(out):
        claim(out, beside=args.beside_files)  # nothing of a directory crosscheck did not write is replaced
        try:
            return _locked(args, report, out, sections, selected, seed, workers, scheduler, jobs)
        except OSError as e:  # a full disk under a writer that does not say so itself (the render's pages and figures)
            from crosscheck.files import NO_SPACE, no_space

            if e.errno not in NO_SPACE:
                raise
            raise ValueError(no_space(Path(e.filename).parent if e.filename else out, None, e)) from None


def _engine_names(text: str | None) -> tuple[str, ...] | None:
    """The engines of ``--engines a,b`` (None: every engine); one line naming an unknown, broken or missing one."""
    if text is None:
        return None
    from crosscheck import engines

    names = tuple(n.strip() for n in text.split(",") if n.strip())
    if not names:
        raise ValueError(f"engines must be a comma-separated list of {', '.join(engines.names())}; got {text!r}")
    for n in names:
        try:
            spec = engines.get(n)
        except engines.EngineUnavailable:
            raise
        except ValueError:
            raise ValueError(f"engines must be among {', '.join(engines.names())}; got {n!r}") from None
        if spec.unavailable():
            raise engines.EngineUnavailable(spec.unavailable())
    return names


def _saved(out: Path) -> bool:
    """Whether ``out`` holds a report's saved results (a path the file system refuses is one line naming --out)."""
    try:
        return (out / "data" / "provenance.json").is_file()
    except OSError as e:
        raise ValueError(f"out must be a report directory; cannot use {str(out)[:60]!r}: {e.strerror or e}") from None


def _locked(args, report, out: Path, sections, selected, seed: int, workers, scheduler, jobs=None) -> int:
    from crosscheck.report.ownership import sweeps_owned

    progress = not args.no_progress and sys.stderr.isatty()
    t0 = time.perf_counter()
    if not args.from_results:
        if args.fresh and sweeps_owned(out / "sweeps"):
            import shutil

            shutil.rmtree(out / "sweeps")
        results = report.run(
            out,
            selected,
            quick=args.quick,
            seed=seed,
            progress=progress,
            argv=["crosscheck", *sys.argv[1:]],
            resume=not (args.fresh or args.only),
            scheduler=scheduler,
            workers=workers,
            jobs=jobs,
            log=not args.no_progress and not sys.stderr.isatty(),
        )
        kept = [k for k, v in results.items() if v.get("resumed")]
        if kept:
            print(f"kept {len(kept)} finished sections ({', '.join(kept)}); --fresh recomputes them")
    t1 = time.perf_counter()
    if args.only:  # a partial run into a new directory renders what it has, not the sections it was not asked for
        from crosscheck.report.store import read_status

        sections = [s for s in sections if s in selected or read_status(out, s.slug) is not None]
    summary = report.render(out, sections, progress=progress)
    t2 = time.perf_counter()
    print(f"report: {summary.html}  (markdown: {summary.markdown})")
    print(f"run {t1 - t0:.1f} s, render {t2 - t1:.1f} s")
    for f in summary.failures:
        print(f"  FAILED {f}")
    return 1 if summary.failures else 0


def _section_slugs() -> list[str]:
    from crosscheck.report.sections import SECTIONS

    return [s.slug for s in SECTIONS]


def register(sub) -> None:
    r = sub.add_parser("report", help="run every comparison and write an HTML + Markdown report with figures and data")
    r.add_argument(
        "--out",
        default=None,
        help="report directory (default: reports/latest; the committed reference is written only with --out reports/quick)",
    )
    r.add_argument("--quick", action="store_true", help="small grids (about 3.5 minutes on 2 cores)")
    r.add_argument(
        "--from-results", action="store_true", help="rebuild the report from DIR/data without running anything"
    )
    r.add_argument(
        "--seed",
        type=ascii_number,
        default="0",
        help="master seed of numpy.random.default_rng, >= 0 (each section derives its own; default 0)",
    )
    r.add_argument(
        "--only",
        action="append",
        metavar="SECTION",
        help=f"run only this section (repeatable); the others keep their saved results. SECTION is one of: {', '.join(_section_slugs())}",
    )
    r.add_argument(
        "--engines",
        default=None,
        metavar="A,B",
        help="the theory's sections and these engines' only (comma-separated names, `crosscheck engines` lists them)",
    )
    r.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bars (nor, when stderr is not a terminal, the log line per section)",
    )
    r.add_argument(
        "--beside-files",
        action="store_true",
        help="write into a non-empty directory crosscheck did not write, beside its files: refused if one of the "
        "report's names (data, figures, sweeps, index.html, report.md) is there; nothing of theirs is deleted or "
        "overwritten (default: such a directory is refused)",
    )
    r.add_argument(
        "--fresh", action="store_true", help="recompute every section (default: keep those finished by the same code)"
    )
    r.add_argument(
        "--scheduler",
        default=None,
        help="run the engine sweeps on a Dask cluster: 'local' or a scheduler address tcp://host:8786",
    )
    r.add_argument(
        "--workers",
        type=ascii_number,
        default=None,
        help="processes (or local Dask workers) for the engine sweeps; default: the usable cores",
    )
    r.add_argument(
        "--jobs",
        type=ascii_number,
        default=None,
        help="sections computed at the same time, each in its own process; default: the usable cores "
        "(the results do not depend on it)",
    )
    r.set_defaults(func=_run)
