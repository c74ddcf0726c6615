"""``crosscheck simulate --engine NAME --theta ... --mu ...``: one slipping state through a contact engine."""

from __future__ import annotations

import json
import math
import os
import sys

from crosscheck import engines
from crosscheck.checks import ALPHA, ETA, MU, POSITIVE, RATE, THETA, VARPHI
from crosscheck.checks import number as _num
from crosscheck.cli.options import add_alpha, add_state, ascii_number, interrupted_line
from crosscheck.progress import ticking
from crosscheck.rod import Rod
from crosscheck.state import SlipState


def _simulate(args) -> int:
    engine = engines.get(args.engine)
    state = SlipState(
        theta=_num("theta", args.theta, THETA),
        varphi=_num("varphi", args.varphi, VARPHI),
        Theta=_num("Theta", args.Theta, RATE),
        Psi=_num("Psi", args.Psi, RATE),
        eta=_num("eta", args.eta, ETA),
    )
    mu, alpha = _num("mu", args.mu, MU), _num("alpha", args.alpha, ALPHA)
    options = {} if args.timestep is None else {"timestep": _num("timestep", args.timestep, POSITIVE)}
    paths = _output_paths(args)  # before the run: a path that cannot be written never costs the run
    horizon = _num("horizon", args.horizon, POSITIVE)
    with ticking(f"simulating {engine.name} to t = {horizon:g}", progress=None, interrupted=interrupted_line()):
        run = engine.simulate(Rod.scaled(alpha), state, mu, horizon=horizon, **options)
    fin = lambda x: x if math.isfinite(x) else None  # noqa: E731
    out = {
        "engine": run.engine,
        **state.as_dict(),
        "mu": mu,
        "alpha": alpha,
        "horizon": run.horizon,
        "outcome": run.outcome.name,
        "event_time": fin(run.event_time),
        "exit_time": fin(run.exit_time),
        "diverged_time": fin(run.diverged_time),
        "jam_p_eff": fin(run.jam_p_eff),
        "nstep": run.nstep,
        "unjudged_tail": run.unjudged_tail,
        "rod": {"mass": run.rod.mass, "length": run.rod.length, "inertia": run.rod.inertia, "gravity": run.rod.gravity},
        "caveats": list(run.caveats),
    }
    written = _write_outputs(run, paths)
    if args.json:
        print(json.dumps({**out, **({"files": written} if written else {})}, indent=2))
    else:
        when = "" if math.isnan(run.event_time) else f" at t = {run.event_time:.6g}"
        tail = out["unjudged_tail"]
        if run.caveats:
            caveat = "; shorter than the classifier's window: any event can be missed"
        else:
            caveat = (
                f"; an event in its last {tail:.3g} can be missed (the classifier's window)"
                if run.outcome.name == "SLIP"
                else ""
            )
        print(f"{run.engine}: {run.outcome.name}{when}  (horizon {run.horizon:g}, {run.nstep} steps{caveat})")
        # the rod on standard error, as a note: the result line above stays the one line a script reads
        print(f"rod: {run.rod_text}; the numbers above in its scaled units (time in 1/omega)", file=sys.stderr)
        for f in written:
            print(f"wrote {f}")
    return 0


#: The figure formats of --plot (matplotlib's, by suffix); a name without a suffix is written as PNG.
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


def _output_paths(args) -> dict:
    """The files --csv and --plot will write, checked before the run (``crosscheck.checks.writable_file``):
    ``csv`` (--csv, or FILE's .csv beside the figure), ``plot`` (FILE, .png added to a name without a suffix) and
    ``theory`` (FILE's _theory.csv).  Two of them naming one file is refused: one would replace the other."""
    from pathlib import Path

    from crosscheck.checks import writable_file

    paths = {}
    if getattr(args, "plot", None) is not None:
        plot = Path(args.plot) if str(args.plot).strip() else args.plot
        if str(plot).strip() and not Path(plot).suffix and not Path(plot).is_dir():
            plot = Path(plot).with_name(Path(plot).name + ".png")  # what matplotlib writes for a bare name
        paths["plot"] = writable_file("plot", plot, suffixes=PLOT_SUFFIXES)
        paths["theory"] = writable_file("plot", paths["plot"].with_name(paths["plot"].stem + "_theory.csv"))
        paths["csv"] = paths["plot"].with_suffix(".csv")
    if getattr(args, "csv", None) is not None:
        paths["csv"] = writable_file("csv", args.csv)
    elif "csv" in paths:
        paths["csv"] = writable_file("plot", paths["csv"])
    real = {k: os.path.realpath(v) for k, v in paths.items()}
    what = {"plot": "the figure --plot writes", "theory": "the theory's CSV --plot writes beside the figure"}
    for other in ("plot", "theory"):
        if other in real and real["csv"] == real[other]:
            raise ValueError(
                f"csv must be a file other than {what[other]}; both are {str(paths['csv'])!r}, and one would "
                "replace the other"
            )
    return paths


def _write_outputs(run, paths: dict) -> list[str]:
    """The run's record as columns to ``paths["csv"]``; with ``paths["plot"]``, the run against the theory
    (crosscheck.report.trajectory_plot) and the theory's columns to ``paths["theory"]``; returns the files written."""
    written = []
    if paths:
        from crosscheck.report import trajectory_plot as tp

        if "plot" in paths:
            fig = tp.plot_run(run, path=paths["plot"])
            written.append(str(paths["plot"]))
            import matplotlib.pyplot as plt

            plt.close(fig)
        written.append(str(tp.write_csv(paths["csv"], tp.run_columns(run))))
        if "plot" in paths:
            th = tp.theory_trajectory(run.state, run.mu, run.alpha, run.horizon)
            columns = {
                "t": th.t,
                "theta": th.theta,
                "Theta": th.Theta,
                "Psi": th.Psi,
                "eta": th.eta,
                "varphi": th.varphi,
                "b": th.b,
                "p": th.p,
                "minus_b_over_p": th.normal_force,
            }
            written.append(str(tp.write_csv(paths["theory"], columns)))
    return written


def register(sub) -> None:
    s = sub.add_parser("simulate", help="one slipping state through a contact engine (scaled units)")
    s.add_argument("--engine", default="mujoco", help=f"contact engine ({', '.join(engines.names())}; default mujoco)")
    add_state(s)
    add_alpha(s)
    s.add_argument(
        "--horizon",
        type=ascii_number,
        default="2",
        help="scaled time to simulate, > 0, at most what a record of 4 GiB holds (default 2); a long run shows its "
        "seconds on a terminal, and Ctrl-C stops it",
    )
    s.add_argument("--timestep", type=ascii_number, default=None, help="scaled timestep, > 0 (default: the engine's)")
    s.add_argument("--json", action="store_true", help="print the result as JSON")
    s.add_argument(
        "--plot",
        metavar="FILE",
        default=None,
        help="draw the run against the theory (theta, Theta, Psi, slip speed, contact "
        "height, normal force and -b/p, event times) to FILE (.png, .svg or .pdf), with FILE's .csv and _theory.csv beside it",
    )
    s.add_argument(
        "--csv",
        metavar="FILE",
        default=None,
        help="write the run's record (t, theta, Theta, psi, Psi, eta, varphi, gap, "
        "normal_force, active, b, p, -b/p; scaled units) to FILE",
    )
    s.set_defaults(func=_simulate)
