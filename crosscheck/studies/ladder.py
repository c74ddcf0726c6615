"""The ladder of any engine: the models between the theory and the engine, each adding one of its differences, and the cause of a disagreement.

An engine declares its ladder in its ``EngineSpec.ladder``: cause -> rung, in
the order of ``LADDER_CAUSES`` (geometry, compliance, friction law, feed-forward,
discretisation, relaxation, pyramid cone, friction bound, position projection,
float32).  A rung is

* ``"capsule"``: the rigid rod with its contact at the capsule point C = A - r K
  (``crosscheck.theory.capsule``, r the engine's ``Options.radius``): geometry;
* ``"engine"``: the engine itself at the run's options (discretisation for a
  time-stepping engine; for a continuous one its own regularised law);
* ``"module:function"``: a model in between, ``function(rod, state, mu, *,
  horizon, thresholds, options) -> Run`` (``options`` the engine's ``Options``),
  for example the compliant rod with the engine's normal law, or the engine's
  law in continuous time.

From one start, rung 1 is the paper's rod (``slip_until_event``); each rung
after it runs to rung 1's comparison time plus the agreement study's lag
(``crosscheck.studies.comparison``), and every outcome is relabelled as the
agreement study does, so the last rung's label is the study's label of the
engine.  The cause of a disagreement is the rung from which every later rung's
label equals the engine's (the first rung of the final stretch of matches: a
match that the next rung undoes is not the difference the engine keeps;
``crosscheck.engines.mujoco.studies.ladder`` says why); "unexplained" if the
last rung differs, "undetermined" when the last rung or the one before the
stretch could not run.  A ladder's detour (``detour``) is a stretch of rungs on
neither the theory's outcome nor the engine's.  Where the engine rerun here
differs from the agreement study's label, ``decided_by_rounding`` asks whether
the start 1 or 2 ulp of theta away gives that label (the study builds its
starts as arrays, the ladder one by one).

A ladder is one order of adding the differences, so it names the first
that gives the engine's outcome and cannot see a later one that gives it
alone.  The capsule's offset is the one difference every model rung can
drop (its radius): ``without_capsule_offset`` reruns the models after
geometry with the capsule as thin as the engine's strongest geometry
intervention makes it.  Where they still give the engine's outcome, the
disagreement is overdetermined, and the ladder's cause is the pair
(``crosscheck.studies.interventions`` confirms it by the two
interventions together).

Scaled units (section 2.1).
"""

from __future__ import annotations

import importlib
import math
import time
from dataclasses import dataclass

import numpy as np

from crosscheck import engines
from crosscheck.checks import ALPHA, HORIZON, MU, check
from crosscheck.engines.base import n_steps_within_memory
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.spec import LADDER_CAUSES
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState, check_timestep_within
from crosscheck.studies.agreement import DEFAULT_HORIZON
from crosscheck.studies.comparison import RATED, compared_label, run_comparison_window, run_stick_from, window_margin
from crosscheck.theory.slipping import slip_until_event

__all__ = [
    "Rung",
    "EngineLadder",
    "rungs_of",
    "run_ladder",
    "without_capsule_offset",
    "final_stretch_cause",
    "detour",
    "decided_by_rounding",
    "CAUSES",
    "ROUNDING_ULPS",
]

#: Every cause a start can get (as MuJoCo's ladder): the four rungs' causes, "unexplained", "undetermined",
#: "agree" (rung 1 already equals the engine) and "not rated" (rung 1 is GB or DIVERGED).
CAUSES = (*LADDER_CAUSES, "unexplained", "undetermined", "agree", "not rated")

#: Bytes per record row of the hungriest rung (the compliant rod's records, 1200; MuJoCo's 768): a start whose
#: horizon / timestep would need more than ``MAX_RECORD_BYTES`` is refused before any rung runs.
ROW_BYTES = 1200

#: Units in the last place by which ``decided_by_rounding`` moves theta.
ROUNDING_ULPS = (-2, -1, 1, 2)


@dataclass(frozen=True)
class Rung:
    """One rung's outcome from one start: its name, the cause it stands for, status, outcome, event time, label as compared."""

    rung: int
    name: str
    cause: str | None
    status: str
    outcome: Outcome | None = None
    time: float = math.nan
    label: Outcome | None = None
    detail: str = ""
    wall_time: float = 0.0

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def as_dict(self) -> dict:
        return {
            "rung": self.rung,
            "name": self.name,
            "cause": self.cause,
            "status": self.status,
            "outcome": None if self.outcome is None else self.outcome.name,
            "time": self.time,
            "label": None if self.label is None else self.label.name,
            "detail": self.detail,
            "wall_time": self.wall_time,
        }


@dataclass(frozen=True)
class EngineLadder:
    """One start through an engine's ladder: the rungs, the reference (the engine's label) and the cause."""

    engine: str
    state: SlipState
    mu: float
    until: float
    lag: float
    rungs: tuple
    reference: Outcome | None
    cause: str
    run_until: float = math.nan
    alpha: float = 3.0

    @property
    def disagree(self) -> bool:
        """Rung 1 is rated and differs from the reference (the cause is then a rung's, "unexplained" or "undetermined")."""
        return self.cause not in ("agree", "not rated")

    @property
    def first_change(self) -> int | None:
        """The first rung whose label differs from rung 1's (None if none)."""
        return next((r.rung for r in self.rungs[1:] if r.ok and r.label != self.rungs[0].label), None)

    @property
    def detour(self) -> tuple[int, int | None] | None:
        """(k, j) rung numbers of the first detour of a disagreement (``detour``); None without one or if it agrees."""
        if not self.disagree:
            return None
        d = detour([r.label if r.ok else None for r in self.rungs], self.reference)
        return None if d is None else (d[0] + 1, None if d[1] is None else d[1] + 1)

    @property
    def detour_ended_by(self) -> str | None:
        """The cause of the rung that ends the detour (None without one, or if no rung ends it)."""
        d = self.detour
        return None if d is None or d[1] is None else self.rungs[d[1] - 1].cause

    @property
    def missing(self) -> list[str]:
        """Names of the rungs that could not run."""
        return [r.name for r in self.rungs if not r.ok]

    def as_dict(self) -> dict:
        return {
            "engine": self.engine,
            "state": self.state.as_dict(),
            "mu": self.mu,
            "comparison_time": self.until,
            "lag": self.lag,
            "rungs": [r.as_dict() for r in self.rungs],
            "reference": None if self.reference is None else self.reference.name,
            "cause": self.cause,
            "first_change": self.first_change,
            "detour": None if self.detour is None else list(self.detour),
            "detour_ended_by": self.detour_ended_by,
        }


def rungs_of(engine: str) -> list[tuple[str, str]]:
    """(cause, rung) of ``engine``'s declared ladder in rung order; ValueError for an engine without one."""
    spec = engines.get(engine)
    if spec.ladder is None:
        have = [s.name for s in engines.specs() if s.ladder is not None]
        raise ValueError(f"engine must be one of {', '.join(have)} (engines that declare a ladder); got {engine!r}")
    return [(c, spec.ladder[c]) for c in LADDER_CAUSES if c in spec.ladder]


def _run(
    rung: str,
    *,
    spec,
    rod: Rod,
    state: SlipState,
    mu: float,
    alpha: float,
    opts,
    th: Thresholds,
    t_analytic: float,
    t_engine: float,
):
    """(outcome, time) of one rung (raises what the rung raises)."""
    if rung == "capsule":
        from crosscheck.theory import capsule

        r = capsule.slip_until_event(state, mu, alpha, radius=opts.radius, t_max=t_analytic)
        return Outcome(int(r.outcome)), float(r.time)
    if rung == "engine":
        given = {k: getattr(opts, k) for k in opts.__dataclass_fields__}
        return spec.first_event(rod, state, mu, horizon=t_engine, thresholds=th, **given)
    module, _, attr = rung.partition(":")
    run = getattr(importlib.import_module(module), attr)(rod, state, mu, horizon=t_engine, thresholds=th, options=opts)
    return Outcome(int(run.outcome)), float(run.event_time)


def run_ladder(
    engine: str,
    state: SlipState,
    mu: float,
    *,
    alpha: float = 3.0,
    horizon: float = DEFAULT_HORIZON,
    thresholds: Thresholds | None = None,
    reference: Outcome | int | None = None,
    **options,
) -> EngineLadder:
    """``state`` through the ladder ``engine`` declares, at the engine's ``options``; the cause of its disagreement (module docstring).

    ``reference``: the engine's label to judge against (the agreement study's); None uses the last rung's (the engine's own).
    A rung that raises is reported "failed" and the causes after it are "undetermined".
    """
    spec = engines.get(engine)
    ladder = rungs_of(engine)
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, HORIZON))
    opts = spec.options(**options)
    check_timestep_within(opts.timestep, horizon)  # as every engine's simulate
    th = thresholds or Thresholds()
    # refuse a record no rung can hold before anything runs (the rungs would only fail one by one)
    n_steps_within_memory(horizon + window_margin(th, opts.timestep), opts.timestep, ROW_BYTES, what="a rung's record")
    if reference is not None:
        try:
            reference = Outcome(int(reference))
        except (TypeError, ValueError):
            raise ValueError(
                f"reference must be an Outcome ({', '.join(o.name for o in Outcome)}) or None; got {reference!r}"
            ) from None
    until, lag, rungs, run_until = _climb(spec, ladder, state, mu, alpha, horizon, opts, th)
    ref = reference if reference is not None else (rungs[-1].label if rungs[-1].ok else None)
    return EngineLadder(engine, state, mu, until, lag, tuple(rungs), ref, _cause(rungs, ref), run_until, alpha)


def decided_by_rounding(
    engine: str, ladder: EngineLadder, label: Outcome, *, thresholds: Thresholds | None = None, **options
) -> bool:
    """Whether ``engine`` gives ``label`` at a start 1 or 2 units in the last place of theta away from ``ladder``'s.

    When MuJoCo's capsule started exactly on the plane, whether its contact was active in the first row was decided
    by the last bits of the start, and near p = 0 that decided the outcome (a start of the maps jammed at t = 0.0027
    or lifted off at t = 0.0186 as theta moved by one ulp).  The agreement study builds its starts as arrays, whose
    sine and cosine take numpy's SIMD paths, the ladder one by one: a rerun that differs from the study's label at
    such a start is the same start in all but its last bits.  Labelled as the ladder labels its last rung (the
    study's comparison time plus lag); ``options`` the engine's, as ``run_ladder``.
    """
    spec = engines.get(engine)
    th = thresholds or Thresholds()
    opts = spec.options(**options)
    given = {k: getattr(opts, k) for k in opts.__dataclass_fields__}
    horizon = ladder.run_until + window_margin(th, opts.timestep)
    for k in ROUNDING_ULPS:
        theta = ladder.state.theta
        for _ in range(abs(k)):
            theta = float(np.nextafter(theta, math.inf if k > 0 else -math.inf))
        state = SlipState(**{**ladder.state.as_dict(), "theta": theta})
        o, t = spec.first_event(Rod.scaled(ladder.alpha), state, ladder.mu, horizon=horizon, thresholds=th, **given)
        if compared_label(o, t, ladder.until + ladder.lag) == label:
            return True
    return False


def without_capsule_offset(
    engine: str,
    state: SlipState,
    mu: float,
    reference: Outcome | int,
    *,
    alpha: float = 3.0,
    horizon: float = DEFAULT_HORIZON,
    thresholds: Thresholds | None = None,
    **options,
) -> dict | None:
    """The ladder's models rerun with the capsule as thin as the engine's strongest geometry intervention makes it.

    The capsule's offset is the one difference every model rung can drop (its radius).  Where the ladder names
    geometry, the rung that first gives the engine's outcome is the rigid capsule; if the later models still give the
    engine's outcome without the offset, another difference produces it on its own: the disagreement is
    overdetermined, and removing the offset alone leaves it.  The thin rigid capsule runs first: where it still gives
    the engine's outcome the intervention is not thin enough to tell, and nothing is predicted.  ``also`` is the cause
    of the final stretch of these rungs equal to ``reference`` (``final_stretch_cause``) when that is a later cause;
    None where the stretch starts at the thin capsule, where the last model leaves the engine's outcome (the offset
    is needed), or where a rung that decides it could not run ("undetermined").

    Returns None when the engine has no geometry intervention or no model rung after geometry; else
    {"radius": the thin radius, "rungs": [{cause, label}], "also": cause or None}.  ``options`` as ``run_ladder``.
    """
    spec = engines.get(engine)
    thin = spec.interventions_for("geometry", spec.options(**options))
    models = [(c, r) for c, r in rungs_of(engine) if r != "engine"]
    if not thin or not any(c != "geometry" for c, _ in models) or models[0] != ("geometry", "capsule"):
        return None
    opts = spec.options(**{**options, **thin[-1].options})
    _, _, rungs, _ = _climb(spec, models, state, mu, alpha, horizon, opts, thresholds or Thresholds())
    rungs = rungs[1:]  # (rung 1, the paper's rod, has no cause)
    also = final_stretch_cause(rungs, Outcome(int(reference)), lambda r: r.cause)
    return {
        "radius": opts.radius,
        "rungs": [{"cause": r.cause, "label": None if r.label is None else r.label.name} for r in rungs],
        "also": also if also in LADDER_CAUSES and also != "geometry" else None,
    }


def _climb(
    spec, ladder, state: SlipState, mu: float, alpha: float, horizon: float, opts, th: Thresholds
) -> tuple[float, float, list, float]:
    """(comparison time, lag, rungs, run_until) of ``state`` up ``ladder`` ((cause, rung) pairs, rungs 2, 3, ...) at
    ``opts``: rung 1 the paper's rod, each label the agreement study's; a rung that raises is "failed" and the climb
    goes on; the analytic rungs run to ``run_until``, the engines two classifier windows further."""
    rod = Rod.scaled(alpha)
    first = slip_until_event(state, mu, alpha, t_max=horizon)
    o1, t1 = Outcome(int(first.outcome)), float(first.time)
    until, lag, run_until = run_comparison_window(first, horizon, mu, alpha, opts)
    # a STICK the classifier cannot tell from the theory's slip (``crosscheck.studies.comparison.stick_from``)
    since = run_stick_from(first, until, th, opts)

    def label(o: Outcome, t: float) -> Outcome:
        return compared_label(o, t, until + lag, since)

    rungs = [Rung(1, "tip", None, "ok", o1, t1, label(o1, t1))]
    for k, (cause, rung) in enumerate(ladder, start=2):
        t0 = time.perf_counter()
        try:
            o, t = _run(
                rung,
                spec=spec,
                rod=rod,
                state=state,
                mu=mu,
                alpha=alpha,
                opts=opts,
                th=th,
                t_analytic=run_until,
                t_engine=run_until + window_margin(th, opts.timestep),
            )
            rungs.append(
                Rung(k, rung.rpartition(":")[2], cause, "ok", o, t, label(o, t), wall_time=time.perf_counter() - t0)
            )
        except Exception as e:  # noqa: BLE001 - a failing rung is reported, the ladder goes on
            rungs.append(
                Rung(
                    k,
                    rung.rpartition(":")[2],
                    cause,
                    "failed",
                    detail=f"{type(e).__name__}: {e}",
                    wall_time=time.perf_counter() - t0,
                )
            )
    return until, lag, rungs, run_until


def _cause(rungs, reference: Outcome | None) -> str:
    first = rungs[0]
    if first.label not in RATED or reference is None:
        return "not rated"
    if first.label == reference:
        return "agree"
    return final_stretch_cause(rungs[1:], reference, lambda r: r.cause)


def final_stretch_cause(later, reference, cause_of) -> str:
    """The cause of a disagreement: the first rung of the final stretch of rungs that all equal ``reference``.

    ``later``: rungs 2, 3, ... (each with ``ok`` and ``label``); ``cause_of(rung)``
    its cause.  "unexplained" when the last rung differs from the reference;
    "undetermined" when the last rung, or the rung just before the stretch,
    could not run (it might have extended the stretch or ended it).
    """
    if not later or not later[-1].ok:
        return "undetermined"
    if later[-1].label != reference:
        return "unexplained"
    k = len(later) - 1
    while k > 0 and later[k - 1].ok and later[k - 1].label == reference:
        k -= 1
    if k > 0 and not later[k - 1].ok:
        return "undetermined"
    return cause_of(later[k])


def detour(labels, reference) -> tuple[int, int | None] | None:
    """The first detour of a ladder: (k, j), rung indexes into ``labels`` (rung 1 at 0), or None.

    A detour is a stretch of rungs whose labels are neither rung 1's (the
    theory's) nor ``reference`` (the engine's): a difference added at rung k
    took the outcome somewhere the engine does not go, and rung j is the
    first after it back on the theory's or the engine's label (None if no
    rung is).  A ladder without a detour is monotone: each rung either keeps
    the theory's outcome or takes the engine's.  Labels of rungs that could
    not run (None) are passed over.
    """
    first = labels[0]
    for k in range(1, len(labels)):
        if labels[k] is not None and labels[k] not in (first, reference):
            j = next(
                (i for i in range(k + 1, len(labels)) if labels[i] is not None and labels[i] in (first, reference)),
                None,
            )
            return k, j
    return None
