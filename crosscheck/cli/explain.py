"""``crosscheck explain --theta ... --mu ...``: one start through an engine's ladder, and the cause of its disagreement with the theory."""

from __future__ import annotations

import math

from crosscheck.checks import ALPHA, ETA, HORIZON, MU, RATE, THETA, VARPHI
from crosscheck.checks import number as _num
from crosscheck.cli.json_text import json_text
from crosscheck.cli.options import add_alpha, add_state, ascii_number


def _fmt_time(t: float) -> str:
    return "" if not math.isfinite(t) else f" at t = {t:.6g}"


def _laddered() -> list[str]:
    """The engines that declare a ladder (the models between them and the theory)."""
    from crosscheck import engines

    return [s.name for s in engines.specs() if s.ladder is not None]


def _start(args):
    """(state, mu, alpha, horizon) of the command line, each checked (one line naming a bad one)."""
    from crosscheck.state import SlipState

    state = SlipState(
        theta=_num("theta", args.theta, THETA),
        varphi=_num("varphi", args.varphi, VARPHI),
        Theta=_num("Theta", args.Theta, RATE),
        Psi=_num("Psi", args.Psi, RATE),
        eta=_num("eta", args.eta, ETA),
    )
    return state, _num("mu", args.mu, MU), _num("alpha", args.alpha, ALPHA), _num("horizon", args.horizon, HORIZON)


def _plot(args, ladder, name: str, state, mu: float, alpha: float) -> None:
    """--plot FILE: every rung of the ladder on one figure (``crosscheck.report.trajectory_plot.plot_ladder``), with its JSON beside it."""
    if not getattr(args, "plot", None):
        return
    import sys
    from pathlib import Path

    import matplotlib.pyplot as plt

    from crosscheck.report.trajectory_plot import plot_ladder

    path = Path(args.plot)
    title = (
        f"{name}'s ladder from theta {state.theta:g}, varphi {state.varphi:g}, Theta {state.Theta:g}, Psi {state.Psi:g}, eta {state.eta:g}; "
        f"mu {mu:g}, alpha {alpha:g}: cause {ladder.cause}"
    )
    plt.close(plot_ladder(ladder, path=path, title=title))
    path.with_suffix(".json").write_text(json_text(ladder.as_dict(), indent=1) + "\n")
    print(f"wrote {path} and {path.with_suffix('.json')}", file=sys.stderr if args.json else sys.stdout)


def _confirmation(args, engine: str, state, mu: float, alpha: float, horizon: float, cause: str, reference, options):
    """The ladder's cause checked on the engine for this start (``crosscheck.studies.confirm``); None with --no-confirm."""
    if getattr(args, "no_confirm", False):
        return None
    from crosscheck import engines
    from crosscheck.error_stats import as_json
    from crosscheck.studies.confirm import confirm

    fields = engines.get(engine).Options.__dataclass_fields__
    ref = getattr(reference, "name", reference)
    kept = {k: v for k, v in options.items() if k in fields}
    return as_json(confirm(engine, state, mu, cause=cause, reference=ref, alpha=alpha, horizon=horizon, **kept))


def _print_confirmation(c) -> None:
    """Each intervention's outcome, each pair's, and the verdict line."""
    if c is None:
        return
    for cause, rows in c["singles"].items():
        for r in rows:
            got = r.get("label") or r["status"].upper()
            print(f"intervention {cause:<15} {r['text']}: {got}{' (removes it)' if r['removes'] else ''}")
    for r in c["pairs"]:
        got = r.get("label") or r["status"].upper()
        print(f"pair with    {r['with']:<15} {r['text']}: {got}{' (removes it)' if r['removes'] else ''}")
    print(f"confirmation: {c['text']}")


def _explain(args) -> int:
    """One start through an engine's declared ladder (``crosscheck.studies.ladder``), at its default options and ``--timestep``."""
    from crosscheck.report.format import engine_label
    from crosscheck.studies.ladder import run_ladder

    if args.engine not in _laddered():
        raise ValueError(
            f"engine must be one of {', '.join(_laddered())} (engines that declare a ladder); got {args.engine!r}"
        )
    state, mu, alpha, horizon = _start(args)
    options = {}
    if args.timestep is not None:
        options["timestep"] = _num("timestep", args.timestep, HORIZON)
    if args.radius is not None:
        from crosscheck.theory.slipping import RADIUS

        options["radius"] = _num("radius", args.radius, RADIUS)
    ld = run_ladder(args.engine, state, mu, alpha=alpha, horizon=horizon, **options)
    name = engine_label(args.engine)
    _plot(args, ld, name, state, mu, alpha)
    conf = _confirmation(args, args.engine, state, mu, alpha, horizon, ld.cause, ld.reference, options)
    if args.json:
        print(json_text({**ld.as_dict(), "confirmation": conf}))
        return 0
    print(
        f"start: theta {state.theta:g}, varphi {state.varphi:g}, Theta {state.Theta:g}, Psi {state.Psi:g}, eta {state.eta:g}; mu {mu:g}, alpha {alpha:g}"
    )
    print(f"compared up to t = {ld.until + ld.lag:.6g} (comparison time {ld.until:.6g} + lag {ld.lag:.6g})")
    width = max(11, *(len(r.name) for r in ld.rungs))  # the rung names in one column
    for r in ld.rungs:
        what = "the theory" if r.cause is None else r.cause
        if r.ok:
            relabel = "" if r.label == r.outcome else f" -> {r.label.name} as compared"
            print(f"{r.rung} {r.name:<{width}} {what:<15} {r.outcome.name}{_fmt_time(r.time)}{relabel}")
        else:
            print(f"{r.rung} {r.name:<{width}} {what:<15} {r.status.upper()}: {r.detail}")
    ref = ld.reference.name if ld.reference is not None else "-"
    print(f"cause: {ld.cause} ({name} {ref}, theory {ld.rungs[0].label.name})")
    _print_confirmation(conf)
    return 0


def register(sub) -> None:
    s = sub.add_parser(
        "explain",
        help="run one start through an engine's ladder (the models between the theory and the engine, one "
        "cause apart) and name the cause of a disagreement with the theory",
    )
    add_state(s)
    add_alpha(s)
    s.add_argument(
        "--engine", default="mujoco", help="the engine whose ladder to climb (engines that declare one; default mujoco)"
    )
    s.add_argument(
        "--timestep",
        type=ascii_number,
        default=None,
        metavar="DT",
        help="the engine's scaled timestep (default: the engine's own); MuJoCo's in (0, 0.03], at most half its "
        "time constant 0.06 (default 3e-4)",
    )
    s.add_argument(
        "--radius",
        type=ascii_number,
        default=None,
        metavar="R",
        help="capsule radius r / l, in (0, 0.5) (default 0.01)",
    )
    s.add_argument(
        "--horizon",
        type=ascii_number,
        default="2",
        help="scaled comparison horizon, in (0, 10000] (default 2, the agreement study's)",
    )
    s.add_argument("--json", action="store_true", help="print the ladder (and the confirmation) as JSON")
    s.add_argument(
        "--no-confirm",
        action="store_true",
        help="do not check the cause on the engine (by default its interventions run for this start, then pairs where "
        "they fail: confirmed, confirmed as a pair with ..., removed by another cause's intervention instead, not removed)",
    )
    s.add_argument(
        "--plot",
        metavar="FILE",
        default=None,
        help="draw every rung (its outcome and event time against the comparison "
        "window) on one figure in FILE (.png, .svg or .pdf), with FILE's .json beside it",
    )
    s.set_defaults(func=_explain)
