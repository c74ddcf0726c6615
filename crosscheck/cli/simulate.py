"""``crosscheck simulate --engine NAME --theta ... --mu ...``: one slipping state through a contact engine."""

from __future__ import annotations

import json
import math

from crosscheck import engines
from crosscheck.checks import ALPHA, ETA, MU, POSITIVE, RATE, THETA, VARPHI
from crosscheck.checks import number as _num
from crosscheck.cli.options import add_alpha, add_state, ascii_number
from crosscheck.rod import Rod
from crosscheck.state import SlipState


def _simulate(args) -> int:
    engine = engines.get(args.engine)
    state = SlipState(theta=_num("theta", args.theta, THETA), varphi=_num("varphi", args.varphi, VARPHI),
                      Theta=_num("Theta", args.Theta, RATE), Psi=_num("Psi", args.Psi, RATE), eta=_num("eta", args.eta, ETA))
    mu, alpha = _num("mu", args.mu, MU), _num("alpha", args.alpha, ALPHA)
    options = {} if args.timestep is None else {"timestep": _num("timestep", args.timestep, POSITIVE)}
    run = engine.simulate(Rod.scaled(alpha), state, mu, horizon=_num("horizon", args.horizon, POSITIVE), **options)
    fin = lambda x: x if math.isfinite(x) else None  # noqa: E731
    out = {"engine": run.engine, **state.as_dict(), "mu": mu, "alpha": alpha, "horizon": run.horizon, "outcome": run.outcome.name,
           "event_time": fin(run.event_time), "exit_time": fin(run.exit_time), "diverged_time": fin(run.diverged_time),
           "jam_p_eff": fin(run.jam_p_eff), "nstep": run.nstep}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        when = "" if math.isnan(run.event_time) else f" at t = {run.event_time:.6g}"
        print(f"{run.engine}: {run.outcome.name}{when}  (horizon {run.horizon:g}, {run.nstep} steps)")
    return 0


def register(sub) -> None:
    s = sub.add_parser("simulate", help="one slipping state through a contact engine (scaled units)")
    s.add_argument("--engine", default="mujoco", help=f"contact engine ({', '.join(engines.names())}; default mujoco)")
    add_state(s)
    add_alpha(s)
    s.add_argument("--horizon", type=ascii_number, default="2", help="scaled time to simulate, > 0, at most what a record of 4 GiB holds (default 2)")
    s.add_argument("--timestep", type=ascii_number, default=None, help="scaled timestep, > 0 (default: the engine's)")
    s.add_argument("--json", action="store_true", help="print the result as JSON")
    s.set_defaults(func=_simulate)
