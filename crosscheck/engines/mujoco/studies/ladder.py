"""The ladder: a named cause for each start where MuJoCo's first event differs from the rigid theory's.

MuJoCo's capsule differs from the paper's rod in five ways at once: its
contact point C lies a radius r below the tip A, its contact is compliant,
its soft elliptic friction is not exactly opposite the slip, its normal force
feeds most of the rigid force forward at once (the impedance), and its time
is discretised.  The ladder removes them one at a time.  From one start
(``SlipState``, mu, alpha, MuJoCo's ``Options``) it runs six models, each
adding one of MuJoCo's differences to the one before:

====  ==============  =========================================================================
rung  name            model
====  ==============  =========================================================================
1     ``tip``         rigid rod, contact at A (the paper): ``crosscheck.theory.slipping.slip_until_event``
2     ``capsule``     rigid rod, contact at C: ``crosscheck.theory.capsule.slip_until_event(radius=r)``
3     ``compliant``   Kelvin-Voigt rod at C, exact Coulomb friction, MuJoCo-equivalent
                      (eps, xi) (``mujoco_equivalent``): ``crosscheck.engines.compliant.simulate``
4     ``spring_law``  MuJoCo's contact law at C in continuous time without its normal
                      force's feed-forward: MuJoCo's friction on its solref spring-damper
                      (``crosscheck.engines.mujoco.ode.simulate(feed_forward=False)``)
5     ``mujoco_law``  MuJoCo's contact law at C in continuous time:
                      ``crosscheck.engines.mujoco.ode.simulate``
6     ``mujoco``      MuJoCo at the run's timestep: ``crosscheck.engines.get("mujoco").simulate``
====  ==============  =========================================================================

The cause of a disagreement (rung 1's outcome differs from MuJoCo's) is the
rung from which every later rung's outcome equals MuJoCo's (the first rung of
the final stretch of matches): "geometry" (2), "compliance" (3), "friction
law" (4), "feed-forward" (5), "discretisation" (6).  Why not the first rung that matches: two of
MuJoCo's differences can each change the outcome, and a match that the next
rung undoes is not the difference MuJoCo keeps.  Near p = 0 the rigid rod at
the capsule point C jams where the rod at A lifts off (the offset r moves p
across 0), while the Kelvin-Voigt rod at C lifts off again and only MuJoCo's
law jams: the first match named geometry, yet a sixteen times thinner MuJoCo
capsule still jams and a smaller impratio or another impedance removes the
jam (``crosscheck.studies.interventions``).  Likewise a start where MuJoCo's
law in continuous time does what the rigid theory does while MuJoCo's steps
do not is discretisation, not compliance.  "friction law" is MuJoCo's
friction where rung 3 has Coulomb's: not opposite the slip, regularised (its
friction time constant, its soft stick) and coupled to the normal row by one
convex problem.  "feed-forward" is the rest of MuJoCo's law: its impedance
applies a fraction d (0.9-0.95 by default) of the rigid normal force at once,
where the matched spring, and rung 4's solref spring-damper, build the force
over the time constant (``crosscheck.engines.mujoco.law.contact_problem``).
Without rung 4 the two were one cause, and a ladder often went from the
theory's outcome to a third one at rung 3 (the spring's slower force: a slip
where the theory jams) and to MuJoCo's only at the law: rung 4 shows the
feed-forward as the step that ends such a detour (``detour``).  Rung 6 is MuJoCo itself at the
same options, so for a single start it always matches; a cause can only be
"unexplained" when MuJoCo's outcome is given from elsewhere (the agreement
study's label, ``run_ladder(reference=...)``) and the rerun differs from it.
A rung that cannot run (its module is missing, or it raised) is reported as
such and never skipped silently: a start whose first match comes after such a
rung gets the cause "undetermined", since the missing rung might have matched.

Outcomes compared like for like.  The agreement study
(``crosscheck.studies.agreement``) compares an engine with the theory only
up to the analytic *comparison time* T (rung 1's event time; its domain-exit
time for a censored SLIP; the horizon otherwise), extended for an analytic
event by the lag max(``LAG_TAU`` tau, ``LAG_STEPS`` dt) (tau = MuJoCo's
solref time constant): a later engine event counts as SLIP
(``comparison_labels``).  Every rung's outcome here goes through the same
relabelling with rung 1's T and the same lag, so rung 5's label is exactly
the study's label of MuJoCo and the rungs are compared on the same footing.
Since nothing after T + lag can change a label, rungs 2-6 run only to
min(T + lag, horizon) (plus the classifier's margin of two windows for the
engines, as the study adds), which is what the study's runs see up to that
time.

The MuJoCo-equivalent Kelvin-Voigt parameters of rung 3 are derived in
``crosscheck.engines.mujoco.studies.kelvin_voigt``; the study over many starts
is ``crosscheck.engines.mujoco.studies.ladder_study``.

All quantities are in the paper's scaled units (section 2.1).
"""

from __future__ import annotations

import importlib
import inspect
import json
import math
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from typing import Any

from crosscheck.checks import ALPHA, HORIZON, MU, check
from crosscheck.engines.base import n_steps_within_memory
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.mujoco.studies.kelvin_voigt import KelvinVoigtMatch, mujoco_equivalent
from crosscheck.error_stats import as_json
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState, check_timestep_within
from crosscheck.studies.agreement import DEFAULT_HORIZON
from crosscheck.studies.comparison import RATED, compared_label, run_comparison_window, run_stick_from, window_margin
from crosscheck.studies.ladder import detour, final_stretch_cause
from crosscheck.theory.slipping import slip_until_event

__all__ = [
    "RUNGS",
    "RUNG_TITLES",
    "CAUSES",
    "CAUSE_CODES",
    "NAMED_CAUSES",
    "RungResult",
    "Ladder",
    "run_ladder",
    "compliant_rung",
    "spring_law_rung",
    "law_rung",
]

#: The rungs, in order (rung k is RUNGS[k - 1]).
RUNGS = ("tip", "capsule", "compliant", "spring_law", "mujoco_law", "mujoco")

#: What each rung is, for tables and the CLI.
RUNG_TITLES = {
    "tip": "rigid rod, contact at the tip A (the paper)",
    "capsule": "rigid rod, contact at the capsule point C",
    "compliant": "Kelvin-Voigt rod at C, MuJoCo-equivalent eps, xi, exact Coulomb",
    "spring_law": "MuJoCo's contact law at C, continuous time, no normal feed-forward",
    "mujoco_law": "MuJoCo's contact law at C, continuous time",
    "mujoco": "MuJoCo at the run's timestep",
}

#: The difference from the theory that each rung from 2 on adds: the cause if it is the first to match MuJoCo.
CAUSE_OF_RUNG = {
    "capsule": "geometry",
    "compliant": "compliance",
    "spring_law": "friction law",
    "mujoco_law": "feed-forward",
    "mujoco": "discretisation",
}

#: The causes a ladder names (one per rung from 2 on), in rung order.
NAMED_CAUSES = tuple(CAUSE_OF_RUNG[r] for r in RUNGS[1:])

#: Every cause a start can get.  "agree": rung 1 already equals MuJoCo (not a disagreement);
#: "not rated": rung 1's outcome is GB or DIVERGED (the agreement study does not rate those);
#: "undetermined": the first match comes after a rung that could not run; "unexplained": no rung matches.
CAUSES = (*NAMED_CAUSES, "unexplained", "undetermined", "agree", "not rated")

#: Integer code of each cause (maps and CSV columns).
CAUSE_CODES = {c: i for i, c in enumerate(CAUSES)}

#: Bytes per record row of the hungriest engine rung (the compliant rod's records, 1200; MuJoCo's 768): a start whose
#: horizon / timestep would need more than ``MAX_RECORD_BYTES`` is refused before any rung runs.
ROW_BYTES = 1200

#: The module and function of each rung from 2 to 5 (rung 1 and 6 are always there).
_RUNG_CALLABLE = {
    "capsule": ("crosscheck.theory.capsule", "slip_until_event"),
    "compliant": ("crosscheck.engines.compliant", "simulate"),
    "spring_law": ("crosscheck.engines.mujoco.ode", "simulate"),
    "mujoco_law": ("crosscheck.engines.mujoco.ode", "simulate"),
}


# --------------------------------------------------------------------------
# One start through the five rungs
# --------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class RungResult:
    """One rung's run of one start.

    Attributes:
      rung: 1-6; name: ``RUNGS[rung - 1]``.
      status: "ok", "not available" (the rung's module or function is
        missing) or "failed" (it raised); ``detail`` says which and why.
      outcome: its own first event (``Outcome``; None unless ok).
      time: its event time (scaled; NaN for SLIP or when not ok).
      label: the outcome as compared (``comparison_labels`` with rung 1's
        comparison time and the study's lag); None unless ok.
      reason: the analytic rule that ended an analytic rung ("b=0", ...), "" for engines.
      p: eq. p (at A or C) at an analytic rung's stop, the engine's own p at a JAM otherwise (NaN if none).
      wall_time: seconds.
      result: the rung's own result object (SlipResult-like or ``Run``), kept only with ``keep=True``.
    """

    rung: int
    name: str
    status: str
    outcome: Outcome | None = None
    time: float = math.nan
    label: Outcome | None = None
    reason: str = ""
    p: float = math.nan
    detail: str = ""
    wall_time: float = 0.0
    result: Any = field(default=None, repr=False)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def as_dict(self) -> dict:
        return {
            "rung": self.rung,
            "name": self.name,
            "status": self.status,
            "outcome": self.outcome.name if self.outcome is not None else None,
            "time": self.time,
            "label": self.label.name if self.label is not None else None,
            "reason": self.reason,
            "p": self.p,
            "detail": self.detail,
            "wall_time": self.wall_time,
        }


@dataclass(frozen=True, eq=False)
class Ladder:
    """A start through the six rungs, and the cause of its disagreement.

    Attributes:
      state, mu, alpha: the start.
      options: MuJoCo's options (a dict of ``crosscheck.engines.mujoco.options.Options``' fields).
      match: the Kelvin-Voigt (eps, xi) of rung 3 (``mujoco_equivalent``).
      horizon: the study's horizon; until: rung 1's comparison time; lag: the
        extension of an analytic event's comparison; run_until: how far rungs 2-6 ran.
      rungs: six ``RungResult``s.
      reference: MuJoCo's label the cause is judged against (rung 6's own, or
        the agreement study's when given); reference_source: "rung 6" or "given".
      disagree: rung 1 is rated and its label differs from the reference.
      cause: one of ``CAUSES``.
      first_change: the first rung whose label differs from rung 1's (None if none).
      detour: (k, j) rung numbers of its first detour: rung k takes an outcome that is neither the theory's nor
        MuJoCo's, rung j is the first back on one of them (None if none; ``crosscheck.studies.ladder.detour``);
        None for a start that is not a disagreement.
    """

    state: SlipState
    mu: float
    alpha: float
    options: dict
    match: KelvinVoigtMatch
    horizon: float
    until: float
    lag: float
    run_until: float
    rungs: tuple
    reference: Outcome | None
    reference_source: str
    disagree: bool
    cause: str
    first_change: int | None

    def rung(self, name: str) -> RungResult:
        return self.rungs[RUNGS.index(name)]

    @property
    def detour(self) -> tuple[int, int | None] | None:
        if not self.disagree:
            return None
        d = detour([r.label if r.ok else None for r in self.rungs], self.reference)
        return None if d is None else (d[0] + 1, None if d[1] is None else d[1] + 1)

    @property
    def detour_ended_by(self) -> str | None:
        """The cause of the rung that ends the detour (None without one, or if no rung ends it)."""
        d = self.detour
        return None if d is None or d[1] is None else CAUSE_OF_RUNG[RUNGS[d[1] - 1]]

    @property
    def missing(self) -> list[str]:
        """Names of the rungs that did not run (not available or failed)."""
        return [r.name for r in self.rungs if not r.ok]

    def as_dict(self) -> dict:
        return as_json(
            {
                "state": self.state.as_dict(),
                "mu": self.mu,
                "alpha": self.alpha,
                "options": self.options,
                "match": self.match.as_dict(),
                "horizon": self.horizon,
                "comparison_time": self.until,
                "lag": self.lag,
                "run_until": self.run_until,
                "rungs": [r.as_dict() for r in self.rungs],
                "reference": self.reference.name if self.reference is not None else None,
                "reference_source": self.reference_source,
                "disagree": self.disagree,
                "cause": self.cause,
                "first_change": self.first_change,
                "missing": self.missing,
                "detour": self.detour,
                "detour_ended_by": self.detour_ended_by,
            }
        )

    def to_json(self) -> str:
        return json.dumps(self.as_dict(), indent=2, allow_nan=False)


def _rung_callable(name: str):
    """The function of rung ``name`` (2-5), or the reason it is not available."""
    module, attr = _RUNG_CALLABLE[name]
    try:
        mod = importlib.import_module(module)
    except ImportError as e:
        return None, f"{module} cannot be imported ({e})"
    fn = getattr(mod, attr, None)
    if fn is None:
        return None, f"{module} has no {attr}"
    return fn, ""


def _accepts(fn, name: str) -> bool:
    try:
        params = inspect.signature(fn).parameters
    except (TypeError, ValueError):
        return False
    return name in params or any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values())


def _analytic_rung(k: int, name: str, res, t0: float, keep: bool) -> RungResult:
    return RungResult(
        k,
        name,
        "ok",
        Outcome(int(res.outcome)),
        float(res.time),
        None,
        str(getattr(res, "reason", "")),
        float(getattr(res, "p", math.nan)),
        wall_time=time.perf_counter() - t0,
        result=res if keep else None,
    )


def _engine_rung(k: int, name: str, run, t0: float, keep: bool) -> RungResult:
    return RungResult(
        k,
        name,
        "ok",
        Outcome(int(run.outcome)),
        float(run.event_time),
        None,
        "",
        float(run.jam_p_eff),
        wall_time=time.perf_counter() - t0,
        result=run if keep else None,
    )


def _run_rung(
    k: int,
    name: str,
    *,
    state: SlipState,
    mu: float,
    alpha: float,
    rod: Rod,
    opts,
    th: Thresholds,
    match: KelvinVoigtMatch,
    t_analytic: float,
    t_engine: float,
    keep: bool,
) -> RungResult:
    """Rung k (2-6) of one start; never raises for a missing or failing rung (status says so)."""
    t0 = time.perf_counter()
    try:
        if name == "mujoco":
            from crosscheck import engines

            run = engines.get("mujoco").simulate(rod, state, mu, horizon=t_engine, thresholds=th, **opts.as_dict())
            return _engine_rung(k, name, run, t0, keep)
        fn, why = _rung_callable(name)
        if fn is None:
            return RungResult(k, name, "not available", detail=why)
        if name == "capsule":
            return _analytic_rung(k, name, fn(state, mu, alpha, radius=opts.radius, t_max=t_analytic), t0, keep)
        kw = {"horizon": t_engine}
        if _accepts(fn, "thresholds"):
            kw["thresholds"] = th
        if name == "compliant":
            if _accepts(fn, "timestep"):  # records at MuJoCo's timestep: the classifier's windows span the same rows
                kw["timestep"] = opts.timestep
            run = fn(rod, state, mu, eps=match.eps, xi=match.xi, radius=opts.radius, **kw)
        elif name == "spring_law":
            run = fn(rod, state, mu, feed_forward=False, **kw, **opts.as_dict())
        else:
            run = fn(rod, state, mu, **kw, **opts.as_dict())
        return _engine_rung(k, name, run, t0, keep)
    except Exception as e:  # noqa: BLE001 - a failing rung is reported as failed, the ladder goes on
        return RungResult(k, name, "failed", detail=f"{type(e).__name__}: {e}", wall_time=time.perf_counter() - t0)


def _cause(rungs: Sequence[RungResult], reference: Outcome | None) -> tuple[bool, str, int | None]:
    first = rungs[0]
    change = next((r.rung for r in rungs[1:] if r.ok and r.label != first.label), None)
    if first.label not in RATED or reference is None:
        return False, "not rated", change
    if first.label == reference:
        return False, "agree", change
    return True, final_stretch_cause(rungs[1:], reference, lambda r: CAUSE_OF_RUNG[r.name]), change


def run_ladder(
    state: SlipState,
    mu: float,
    *,
    alpha: float = 3.0,
    horizon: float = DEFAULT_HORIZON,
    thresholds: Thresholds | None = None,
    reference: Outcome | int | None = None,
    rungs: Sequence[str] = RUNGS,
    keep: bool = False,
    **options,
) -> Ladder:
    """Run the six rungs from ``state`` and name the cause of a disagreement (module docstring).

    Args:
      state: the start (``SlipState``, scaled units; the tip on the plane).
      mu: friction coefficient.
      alpha: m l^2 / I0 (``Rod.scaled(alpha)``).
      horizon: the comparison horizon of the agreement study (scaled).
      thresholds: the classifier's criteria for rungs 3-6 (``Thresholds()`` by default).
      reference: MuJoCo's label to judge the cause against (e.g. the
        agreement study's); None uses rung 6's own label.
      rungs: the rungs to run besides rung 1 (the others are reported
        "not available: not requested"); all by default.
      keep: keep each rung's own result object (``RungResult.result``).
      **options: MuJoCo's options (fields of ``crosscheck.engines.mujoco.options.Options``:
        timestep, radius, timeconst, dampratio, solimp, ...); rungs 2-5 use
        the same radius, solref and solimp.

    Returns:
      ``Ladder``.
    """
    from crosscheck.engines.mujoco.options import Options

    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state.check_start()
    mu = float(check("mu", mu, MU))
    alpha = float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, HORIZON))
    unknown = sorted(set(rungs) - set(RUNGS))
    if unknown:
        raise ValueError(f"rungs must each be one of {', '.join(RUNGS)}; got {unknown[0]!r}")
    opts = Options.from_kwargs(options)
    check_timestep_within(opts.timestep, horizon)  # as every engine's simulate
    th = thresholds or Thresholds()
    margin = window_margin(th, opts.timestep)
    # refuse a record no engine rung can hold before anything runs (a rung would only fail one by one)
    n_steps_within_memory(horizon + margin, opts.timestep, ROW_BYTES, what="a rung's record")
    if reference is not None:
        try:
            reference = Outcome(int(reference))
        except (TypeError, ValueError):
            raise ValueError(
                f"reference must be an Outcome ({', '.join(o.name for o in Outcome)}) or None; got {reference!r}"
            ) from None
    rod = Rod.scaled(alpha)
    match = mujoco_equivalent(state, alpha, timeconst=opts.timeconst, dampratio=opts.dampratio, solimp=opts.solimp)

    t0 = time.perf_counter()
    r1 = slip_until_event(state, mu, alpha, t_max=horizon)
    first = _analytic_rung(1, "tip", r1, t0, keep)
    # the agreement study's comparison time and lag (crosscheck.studies.comparison)
    until, lag, run_until = run_comparison_window(r1, horizon, mu, alpha, opts)
    # a STICK the classifier cannot tell from the theory's slip (crosscheck.studies.comparison.stick_from)
    since = run_stick_from(r1, until, th, opts)
    results = [first]
    for k, name in enumerate(RUNGS[1:], start=2):
        if name not in rungs:
            results.append(RungResult(k, name, "not available", detail="not requested"))
            continue
        results.append(
            _run_rung(
                k,
                name,
                state=state,
                mu=mu,
                alpha=alpha,
                rod=rod,
                opts=opts,
                th=th,
                match=match,
                t_analytic=run_until,
                t_engine=run_until + margin,
                keep=keep,
            )
        )
    labelled = tuple(
        r
        if not r.ok
        else RungResult(
            **{
                **{f.name: getattr(r, f.name) for f in fields(r)},
                "label": compared_label(r.outcome, r.time, until + lag, since),
            }
        )
        for r in results
    )
    if reference is not None:
        ref, source = Outcome(int(reference)), "given"
    else:
        last = labelled[-1]
        ref, source = (last.label if last.ok else None), "rung 6"
    disagree, cause, change = _cause(labelled, ref)
    for r in labelled:
        if r.status != "ok" and r.detail != "not requested":
            warnings.warn(f"ladder rung {r.rung} ({r.name}) {r.status}: {r.detail}", RuntimeWarning, stacklevel=2)
    return Ladder(
        state=state,
        mu=mu,
        alpha=alpha,
        options=opts.as_dict(),
        match=match,
        horizon=horizon,
        until=until,
        lag=lag,
        run_until=run_until,
        rungs=labelled,
        reference=ref,
        reference_source=source,
        disagree=disagree,
        cause=cause,
        first_change=change,
    )


def compliant_rung(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds, options):
    """Rung 3 as a declared rung (``crosscheck.studies.ladder``): the Kelvin-Voigt rod at C with MuJoCo-equivalent (eps, xi)."""
    from crosscheck import engines

    match = mujoco_equivalent(
        state, rod.alpha, timeconst=options.timeconst, dampratio=options.dampratio, solimp=options.solimp
    )
    return engines.get("compliant").simulate(
        rod,
        state,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        eps=match.eps,
        xi=match.xi,
        radius=options.radius,
        timestep=options.timestep,
    )


def spring_law_rung(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds, options):
    """Rung 4 as a declared rung: MuJoCo's contact law at C in continuous time without its normal force's feed-forward."""
    from crosscheck import engines

    return engines.get("mujoco_law").simulate(
        rod, state, mu, horizon=horizon, thresholds=thresholds, feed_forward=False, **options.as_dict()
    )


def law_rung(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds, options):
    """Rung 5 as a declared rung: MuJoCo's contact law at C in continuous time, at the run's options."""
    from crosscheck import engines

    return engines.get("mujoco_law").simulate(
        rod, state, mu, horizon=horizon, thresholds=thresholds, **options.as_dict()
    )
