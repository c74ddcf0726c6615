"""The ladder: a named cause for each start where MuJoCo's first event differs from the rigid theory's.

MuJoCo's capsule differs from the paper's rod in four ways at once: its
contact point C lies a radius r below the tip A, its contact is compliant,
its soft elliptic friction is not exactly opposite the slip, and its time is
discretised.  The ladder removes them one at a time.  From one start
(``SlipState``, mu, alpha, MuJoCo's ``Options``) it runs five models, each
adding one of MuJoCo's differences to the one before:

====  ==============  =========================================================================
rung  name            model
====  ==============  =========================================================================
1     ``tip``         rigid rod, contact at A (the paper): ``crosscheck.slipping.slip_until_event``
2     ``capsule``     rigid rod, contact at C: ``crosscheck.capsule.slip_until_event(radius=r)``
3     ``compliant``   Kelvin-Voigt rod at C, exact Coulomb friction, MuJoCo-equivalent
                      (eps, xi) (``mujoco_equivalent``): ``crosscheck.engines.compliant.simulate``
4     ``mujoco_law``  MuJoCo's contact law at C in continuous time:
                      ``crosscheck.engines.mujoco.law.simulate``
5     ``mujoco``      MuJoCo at the run's timestep: ``crosscheck.engines.get("mujoco").simulate``
====  ==============  =========================================================================

The cause of a disagreement (rung 1's outcome differs from MuJoCo's) is the
first rung whose outcome equals MuJoCo's: "geometry" (2), "compliance" (3),
"friction law" (4), "discretisation" (5).  "friction law" stands for all of
MuJoCo's contact law that rung 3 lacks: its friction not opposite the slip
and regularised (its friction time constant), and its normal force's
feed-forward of the free acceleration (below).  Rung 5 is MuJoCo itself at the
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
Since nothing after T + lag can change a label, rungs 2-5 run only to
min(T + lag, horizon) (plus the classifier's margin of two windows for the
engines, as the study adds), which is what the study's runs see up to that
time.

MuJoCo-equivalent Kelvin-Voigt parameters (rung 3).  MuJoCo's Computation
chapter prescribes for a constraint with violation r (the contact's signed
distance, < 0 in penetration) and velocity v = r' the reference acceleration

    aref = -B v - k r,   B = 2 / (dmax timeconst),   k = d(r) K,   K = 1 / (dmax^2 timeconst^2 dampratio^2),

with the impedance d(r) of solimp = (d0, dmax, width, midpoint, power)
(``impedance``), and the solver's constraint force, with the regulariser
R = (1 - d)/d A_nn, is f = (d / A_nn)(aref - a0) for an isolated normal row
(A_nn: the row's Delassus entry, a0: its free acceleration).  The gap then
obeys

    r'' = (1 - d) a0 - d B r' - d^2 K r          (an acceleration law),

while the Kelvin-Voigt law of ``crosscheck.engines.compliant`` is a force law,
F_n = -r / eps^2 - (xi / eps) r', so that r'' = a0 + A_nn F_n.  Matching the
stiffness and damping of the two (the coefficients of r and r') gives

    A_nn / eps^2 = d^2 K   ->   eps = (dmax / d) timeconst dampratio sqrt(A_nn),
    A_nn xi / eps = d B    ->   xi  = 2 dampratio / sqrt(A_nn),

i.e. the same natural frequency d / (dmax timeconst dampratio) and the same
damping ratio (dampratio) of the gap.  In the paper's scaled units (timeconst
in 1/omega, width in l, force in m g) the normal Delassus entry of the rod is
the frictionless eq. p,

    A_nn = p(mu = 0) = 1 + alpha cos^2 theta,

the same at C as at A: a force along the normal K applied at C = A - r K has
the moment of the same force at A (r K x K = 0).  The impedance is taken at
the operating penetration, MuJoCo's static balance of the normal row under
the start's free normal acceleration a0 = b (eq. b; the same at C as at A,
z_C = z_A - r): 0 = (1 - d) b - d^2 K r, i.e. |r| = (1 - d(r)) |b| / (d(r)^2 K),
solved for r (``operating_penetration``).  Limits of the match:

* it holds for the normal row alone.  While the rod slips, friction couples
  into the normal row and the gap's acceleration per unit normal force
  becomes eq. p, not A_nn: the Kelvin-Voigt gap then rings at sqrt(p)/eps,
  slower as p -> 0 (the compliant Painleve regime), while MuJoCo's
  regulariser R stays scaled by A_nn.  That difference is rung 4's business;
* MuJoCo's force also has the feed-forward term -d a0 / A_nn (the
  impedance blends the free acceleration out), which a spring-damper has
  not.  It is the largest difference: MuJoCo delivers the fraction d (~0.9)
  of the rigid normal force at once, at zero penetration, while the spring
  builds its force over ~ eps / sqrt(A_nn) ~ timeconst (and the static
  penetrations differ by the factor (1 - d)/d ~ 0.1, MuJoCo's being the
  smaller).  The match is of the spring and damper about a penetration,
  not of the force's response to the free acceleration; that response is
  part of MuJoCo's law, rung 4;
* d(r) varies with the penetration (from d0 at r = 0 to dmax at r >= width):
  the match uses its value at the operating penetration, so eps is right to
  within the spread of dmax / d over the run (at most dmax / d0 - 1, 5.6 %
  for MuJoCo's default solimp);
* it is evaluated at the start state (theta sets A_nn): a rod that rotates
  far changes A_nn by up to the factor 1 + alpha.

All quantities are in the paper's scaled units (section 2.1).
"""

from __future__ import annotations

import importlib
import inspect
import json
import math
import time
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np
from tqdm.auto import tqdm

from crosscheck.checks import ALPHA, HORIZON, MU, POSITIVE, check
from crosscheck.compare import as_json
from crosscheck.engines.base import n_steps_within_memory
from crosscheck.engines.classifier import Thresholds
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.slipping import slip_until_event
from crosscheck.state import SlipState
from crosscheck.studies.agreement import DEFAULT_HORIZON, EVENTS, LAG_STEPS, LAG_TAU, RATED, comparison_labels, window_margin

__all__ = [
    "RUNGS",
    "RUNG_TITLES",
    "CAUSES",
    "CAUSE_CODES",
    "impedance",
    "operating_penetration",
    "KelvinVoigtMatch",
    "mujoco_equivalent",
    "RungResult",
    "Ladder",
    "run_ladder",
    "LadderStudy",
    "ladder_study",
    "disagreements",
    "trajectories",
]

#: The rungs, in order (rung k is RUNGS[k - 1]).
RUNGS = ("tip", "capsule", "compliant", "mujoco_law", "mujoco")

#: What each rung is, for tables and the CLI.
RUNG_TITLES = {
    "tip": "rigid rod, contact at the tip A (the paper)",
    "capsule": "rigid rod, contact at the capsule point C",
    "compliant": "Kelvin-Voigt rod at C, MuJoCo-equivalent eps, xi, exact Coulomb",
    "mujoco_law": "MuJoCo's contact law at C, continuous time",
    "mujoco": "MuJoCo at the run's timestep",
}

#: The difference from the theory that each rung from 2 on adds: the cause if it is the first to match MuJoCo.
CAUSE_OF_RUNG = {"capsule": "geometry", "compliant": "compliance", "mujoco_law": "friction law", "mujoco": "discretisation"}

#: Every cause a start can get.  "agree": rung 1 already equals MuJoCo (not a disagreement);
#: "not rated": rung 1's outcome is GB or DIVERGED (the agreement study does not rate those);
#: "undetermined": the first match comes after a rung that could not run; "unexplained": no rung matches.
CAUSES = ("geometry", "compliance", "friction law", "discretisation", "unexplained", "undetermined", "agree", "not rated")

#: Integer code of each cause (maps and CSV columns).
CAUSE_CODES = {c: i for i, c in enumerate(CAUSES)}

#: Bytes per record row of the hungriest engine rung (the compliant rod's records, 1200; MuJoCo's 768): a start whose
#: horizon / timestep would need more than ``MAX_RECORD_BYTES`` is refused before any rung runs.
ROW_BYTES = 1200

#: The module and function of each rung from 2 to 4 (rung 1 and 5 are always there).
_RUNG_CALLABLE = {
    "capsule": ("crosscheck.capsule", "slip_until_event"),
    "compliant": ("crosscheck.engines.compliant", "simulate"),
    "mujoco_law": ("crosscheck.engines.mujoco.law", "simulate"),
}


# --------------------------------------------------------------------------
# MuJoCo's impedance and the equivalent Kelvin-Voigt contact
# --------------------------------------------------------------------------


def impedance(r, solimp: Sequence[float]) -> np.ndarray:
    """MuJoCo's impedance d(r) of solimp = (d0, dmax, width, midpoint, power) at the violation r (scaled by l).

    x = |r| / width; d = dmax for x >= 1; else d = d0 + y(x) (dmax - d0) with
    the sigmoid y = x^power / midpoint^(power - 1) for x <= midpoint and
    y = 1 - (1 - x)^power / (1 - midpoint)^(power - 1) above (MuJoCo's
    Computation chapter, "Solver parameters").  Vectorised in r.
    """
    d0, dmax, width, mid, power = (float(v) for v in solimp)
    x = np.abs(np.asarray(r, dtype=float)) / width
    xc = np.clip(x, 0.0, 1.0)
    low = xc ** power / mid ** (power - 1.0)
    high = 1.0 - (1.0 - xc) ** power / (1.0 - mid) ** (power - 1.0)
    y = np.where(xc <= mid, low, high)
    return np.where(x >= 1.0, dmax, d0 + y * (dmax - d0))


def _stiffness(timeconst: float, dampratio: float, dmax: float) -> tuple[float, float]:
    """MuJoCo's (B, K) of solref (timeconst, dampratio): B = 2/(dmax tc), K = 1/(dmax^2 tc^2 dampratio^2); k = d(r) K."""
    return 2.0 / (dmax * timeconst), 1.0 / (dmax * dmax * timeconst * timeconst * dampratio * dampratio)


def operating_penetration(b: float, *, timeconst: float, dampratio: float, solimp: Sequence[float]) -> float:
    """MuJoCo's static penetration |r| of an isolated normal row under the free normal acceleration b (< 0).

    Solves |r| = (1 - d(r)) |b| / (d(r)^2 K) (module docstring) by bisection:
    the right side falls with |r| (d grows with |r|) and the left rises, so
    the root is unique.  Returns 0 for b >= 0 (nothing presses the contact).
    """
    if b >= 0.0:
        return 0.0
    _, K = _stiffness(timeconst, dampratio, float(solimp[1]))

    def excess(r):
        d = float(impedance(r, solimp))
        return r - (1.0 - d) * (-b) / (d * d * K)

    lo, hi = 0.0, 1.0
    while excess(hi) < 0.0:  # an upper bracket: |r| = 1 is far beyond any width, unless b is huge
        hi *= 2.0
    for _ in range(200):  # bisection to the last bit (excess is monotone, a few evaluations each)
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        lo, hi = (mid, hi) if excess(mid) < 0.0 else (lo, mid)
    return hi


@dataclass(frozen=True)
class KelvinVoigtMatch:
    """MuJoCo's normal row matched by a Kelvin-Voigt contact at the start state (module docstring).

    Attributes:
      eps, xi: the Kelvin-Voigt compliance and damping of ``crosscheck.engines.compliant``
        (F_n = -gap/eps^2 - (xi/eps) gap' in m g, gap in l, time in 1/omega).
      A_nn: the normal Delassus entry 1 + alpha cos^2 theta (frictionless eq. p).
      b: eq. b at the start (the free normal acceleration a0).
      penetration: the operating penetration |r| (scaled by l).
      d: the impedance at it; B, K: MuJoCo's solref damping and stiffness
        (MuJoCo's k = d K); frequency: the gap's natural frequency
        d / (dmax timeconst dampratio) (scaled), the same for both laws.
      timeconst, dampratio, solimp: the MuJoCo options matched.
    """

    eps: float
    xi: float
    A_nn: float
    b: float
    penetration: float
    d: float
    B: float
    K: float
    frequency: float
    timeconst: float
    dampratio: float
    solimp: tuple

    def as_dict(self) -> dict:
        return {f.name: (list(getattr(self, f.name)) if f.name == "solimp" else getattr(self, f.name)) for f in fields(self)}


def mujoco_equivalent(state: SlipState, alpha: float, *, timeconst: float, dampratio: float, solimp: Sequence[float]) -> KelvinVoigtMatch:
    """Kelvin-Voigt (eps, xi) with MuJoCo's normal stiffness and damping at ``state`` (module docstring).

    eps = (dmax / d) timeconst dampratio sqrt(A_nn), xi = 2 dampratio / sqrt(A_nn),
    A_nn = 1 + alpha cos^2 theta, d = ``impedance`` at ``operating_penetration``.
    """
    alpha = float(check("alpha", alpha, ALPHA))
    timeconst = float(check("timeconst", timeconst, POSITIVE))
    dampratio = float(check("dampratio", dampratio, POSITIVE))
    solimp = tuple(float(v) for v in solimp)
    st, ct = math.sin(state.theta), math.cos(state.theta)
    b = (state.Psi ** 2 * ct * ct + state.Theta ** 2) * st - 1.0  # eq. b
    A_nn = 1.0 + alpha * ct * ct
    dmax = solimp[1]
    B, K = _stiffness(timeconst, dampratio, dmax)
    pen = operating_penetration(b, timeconst=timeconst, dampratio=dampratio, solimp=solimp)
    d = float(impedance(pen, solimp))
    eps = (dmax / d) * timeconst * dampratio * math.sqrt(A_nn)
    xi = 2.0 * dampratio / math.sqrt(A_nn)
    return KelvinVoigtMatch(eps=eps, xi=xi, A_nn=A_nn, b=b, penetration=pen, d=d, B=B, K=K, frequency=d / (dmax * timeconst * dampratio),
                            timeconst=timeconst, dampratio=dampratio, solimp=solimp)


# --------------------------------------------------------------------------
# One start through the five rungs
# --------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class RungResult:
    """One rung's run of one start.

    Attributes:
      rung: 1-5; name: ``RUNGS[rung - 1]``.
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
        return {"rung": self.rung, "name": self.name, "status": self.status, "outcome": self.outcome.name if self.outcome is not None else None,
                "time": self.time, "label": self.label.name if self.label is not None else None, "reason": self.reason, "p": self.p,
                "detail": self.detail, "wall_time": self.wall_time}


@dataclass(frozen=True, eq=False)
class Ladder:
    """A start through the five rungs, and the cause of its disagreement.

    Attributes:
      state, mu, alpha: the start.
      options: MuJoCo's options (a dict of ``crosscheck.engines.mujoco.engine.Options``' fields).
      match: the Kelvin-Voigt (eps, xi) of rung 3 (``mujoco_equivalent``).
      horizon: the study's horizon; until: rung 1's comparison time; lag: the
        extension of an analytic event's comparison; run_until: how far rungs 2-5 ran.
      rungs: five ``RungResult``s.
      reference: MuJoCo's label the cause is judged against (rung 5's own, or
        the agreement study's when given); reference_source: "rung 5" or "given".
      disagree: rung 1 is rated and its label differs from the reference.
      cause: one of ``CAUSES``.
      first_change: the first rung whose label differs from rung 1's (None if none).
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
    def missing(self) -> list[str]:
        """Names of the rungs that did not run (not available or failed)."""
        return [r.name for r in self.rungs if not r.ok]

    def as_dict(self) -> dict:
        return as_json({"state": self.state.as_dict(), "mu": self.mu, "alpha": self.alpha, "options": self.options, "match": self.match.as_dict(),
                        "horizon": self.horizon, "comparison_time": self.until, "lag": self.lag, "run_until": self.run_until,
                        "rungs": [r.as_dict() for r in self.rungs],
                        "reference": self.reference.name if self.reference is not None else None, "reference_source": self.reference_source,
                        "disagree": self.disagree, "cause": self.cause, "first_change": self.first_change, "missing": self.missing})

    def to_json(self) -> str:
        return json.dumps(self.as_dict(), indent=2, allow_nan=False)


def _label(outcome: Outcome, t: float, until: float) -> Outcome:
    return Outcome(int(comparison_labels(np.array([int(outcome)], np.int8), np.array([t if math.isfinite(t) else math.inf]), np.array([until]))[0]))


def _rung_callable(name: str):
    """The function of rung ``name`` (2-4), or the reason it is not available."""
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
    return RungResult(k, name, "ok", Outcome(int(res.outcome)), float(res.time), None, str(getattr(res, "reason", "")), float(getattr(res, "p", math.nan)),
                      wall_time=time.perf_counter() - t0, result=res if keep else None)


def _engine_rung(k: int, name: str, run, t0: float, keep: bool) -> RungResult:
    return RungResult(k, name, "ok", Outcome(int(run.outcome)), float(run.event_time), None, "", float(run.jam_p_eff),
                      wall_time=time.perf_counter() - t0, result=run if keep else None)


def _run_rung(k: int, name: str, *, state: SlipState, mu: float, alpha: float, rod: Rod, opts, th: Thresholds, match: KelvinVoigtMatch,
              t_analytic: float, t_engine: float, keep: bool) -> RungResult:
    """Rung k (2-5) of one start; never raises for a missing or failing rung (status says so)."""
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
        else:
            run = fn(rod, state, mu, **kw, **opts.as_dict())
        return _engine_rung(k, name, run, t0, keep)
    except Exception as e:  # noqa: BLE001 - a failing rung is reported as failed, the ladder goes on
        return RungResult(k, name, "failed", detail=f"{type(e).__name__}: {e}", wall_time=time.perf_counter() - t0)


def _cause(rungs: Sequence[RungResult], reference: Outcome | None) -> tuple[bool, str, int | None]:
    first = rungs[0]
    labels = [r.label if r.ok else None for r in rungs]
    change = next((r.rung for r in rungs[1:] if r.ok and r.label != first.label), None)
    if first.label not in RATED or reference is None:
        return False, "not rated", change
    if first.label == reference:
        return False, "agree", change
    for r in rungs[1:]:
        if not r.ok:
            # the missing rung might have matched: any later match cannot be attributed
            return True, "undetermined", change
        if labels[r.rung - 1] == reference:
            return True, CAUSE_OF_RUNG[r.name], change
    return True, "unexplained", change


def run_ladder(state: SlipState, mu: float, *, alpha: float = 3.0, horizon: float = DEFAULT_HORIZON, thresholds: Thresholds | None = None,
               reference: Outcome | int | None = None, rungs: Sequence[str] = RUNGS, keep: bool = False, **options) -> Ladder:
    """Run the five rungs from ``state`` and name the cause of a disagreement (module docstring).

    Args:
      state: the start (``SlipState``, scaled units; the tip on the plane).
      mu: friction coefficient.
      alpha: m l^2 / I0 (``Rod.scaled(alpha)``).
      horizon: the comparison horizon of the agreement study (scaled).
      thresholds: the classifier's criteria for rungs 3-5 (``Thresholds()`` by default).
      reference: MuJoCo's label to judge the cause against (e.g. the
        agreement study's); None uses rung 5's own label.
      rungs: the rungs to run besides rung 1 (the others are reported
        "not available: not requested"); all by default.
      keep: keep each rung's own result object (``RungResult.result``).
      **options: MuJoCo's options (fields of ``crosscheck.engines.mujoco.engine.Options``:
        timestep, radius, timeconst, dampratio, solimp, ...); rungs 2-4 use
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
    th = thresholds or Thresholds()
    margin = window_margin(th, opts.timestep)
    # refuse a record no engine rung can hold before anything runs (a rung would only fail one by one)
    n_steps_within_memory(horizon + margin, opts.timestep, ROW_BYTES, what="a rung's record")
    if reference is not None:
        try:
            reference = Outcome(int(reference))
        except (TypeError, ValueError):
            raise ValueError(f"reference must be an Outcome ({', '.join(o.name for o in Outcome)}) or None; got {reference!r}") from None
    rod = Rod.scaled(alpha)
    match = mujoco_equivalent(state, alpha, timeconst=opts.timeconst, dampratio=opts.dampratio, solimp=opts.solimp)

    t0 = time.perf_counter()
    r1 = slip_until_event(state, mu, alpha, t_max=horizon)
    first = _analytic_rung(1, "tip", r1, t0, keep)
    outcome1 = first.outcome
    # the agreement study's comparison time and lag (crosscheck.studies.agreement.analytic_events and _rate)
    until = min(first.time, horizon) if outcome1 == Outcome.SLIP else (first.time if outcome1 in EVENTS else horizon)
    lag = max(LAG_TAU * opts.contact_time, LAG_STEPS * opts.timestep) if outcome1 in EVENTS else 0.0
    run_until = max(min(until + lag, horizon), opts.timestep)
    results = [first]
    for k, name in enumerate(RUNGS[1:], start=2):
        if name not in rungs:
            results.append(RungResult(k, name, "not available", detail="not requested"))
            continue
        results.append(_run_rung(k, name, state=state, mu=mu, alpha=alpha, rod=rod, opts=opts, th=th, match=match, t_analytic=run_until,
                                 t_engine=run_until + margin, keep=keep))
    labelled = tuple(r if not r.ok else RungResult(**{**{f.name: getattr(r, f.name) for f in fields(r)}, "label": _label(r.outcome, r.time, until + lag)})
                     for r in results)
    if reference is not None:
        ref, source = Outcome(int(reference)), "given"
    else:
        five = labelled[-1]
        ref, source = (five.label if five.ok else None), "rung 5"
    disagree, cause, change = _cause(labelled, ref)
    for r in labelled:
        if r.status != "ok" and r.detail != "not requested":
            warnings.warn(f"ladder rung {r.rung} ({r.name}) {r.status}: {r.detail}", RuntimeWarning, stacklevel=2)
    return Ladder(state=state, mu=mu, alpha=alpha, options=opts.as_dict(), match=match, horizon=horizon, until=until, lag=lag, run_until=run_until,
                  rungs=labelled, reference=ref, reference_source=source, disagree=disagree, cause=cause, first_change=change)


# --------------------------------------------------------------------------
# Many starts
# --------------------------------------------------------------------------


def disagreements(points: Mapping[str, np.ndarray], analytic_outcome, mujoco_label) -> np.ndarray:
    """Indices of the agreement study's disagreements: rated analytic outcome (SLIP/LIFTOFF/STICK/JAM) and MuJoCo's label different.

    ``points``: dict of (N,) arrays; ``analytic_outcome``, ``mujoco_label``: (N,) Outcome codes (the study's ``analytic.outcome``
    and ``AgreementRun.label`` placed on the points; anything not compared, e.g. a negative code, is skipped).
    """
    a, m = np.asarray(analytic_outcome, int), np.asarray(mujoco_label, int)
    if a.shape != m.shape or a.shape != np.shape(points["theta"]):
        raise ValueError("analytic_outcome and mujoco_label must have one entry per point")
    return np.flatnonzero(np.isin(a, [int(o) for o in RATED]) & (m >= 0) & (m != a))


@dataclass(frozen=True, eq=False)
class LadderStudy:
    """The ladder at many starts.

    Attributes:
      ladders: one ``Ladder`` per start.
      counts: starts per cause (every ``CAUSES`` entry).
      n_disagree: the starts that disagree (rung 1 rated, its label != MuJoCo's).
      attributed: the fraction of them with a named cause (geometry,
        compliance, friction law, discretisation); NaN if none disagree.
      missing: per rung, how many starts it could not run.
      reference_mismatch: starts where rung 5's rerun label differs from the
        given reference (rung 5 is MuJoCo at the same options).
      rounding_decided: those of them where a start 1-2 ulp of theta away
        gives the reference (``decided_by_rounding``): the same start but for
        its last bits.  A mismatch that is not is unexplained.
    """

    ladders: list
    counts: dict
    n_disagree: int
    attributed: float
    missing: dict
    reference_mismatch: int
    rounding_decided: int = 0

    def fractions(self) -> dict:
        """Fraction of the disagreements per cause."""
        n = max(self.n_disagree, 1)
        return {c: self.counts[c] / n for c in CAUSES[:6]} if self.n_disagree else {c: math.nan for c in CAUSES[:6]}

    def summary(self) -> dict:
        wall = {name: float(sum(ld.rung(name).wall_time for ld in self.ladders)) for name in RUNGS}  # seconds per rung, over all starts
        return as_json({"n": len(self.ladders), "n_disagree": self.n_disagree, "attributed": self.attributed, "counts": self.counts,
                        "fractions": self.fractions(), "missing": self.missing, "reference_mismatch": self.reference_mismatch,
                        "rounding_decided": self.rounding_decided, "wall_time": wall})


#: Units in the last place by which ``decided_by_rounding`` moves theta.
ROUNDING_ULPS = (-2, -1, 1, 2)


def decided_by_rounding(ladder: "Ladder", label: Outcome, *, thresholds: Thresholds | None = None) -> bool:
    """Whether MuJoCo gives ``label`` at a start 1 or 2 units in the last place of theta away from ``ladder``'s.

    MuJoCo's capsule starts touching the plane, its lowest point at z = 0 up to
    rounding (``crosscheck.engines.mujoco.model.initial_state``), so whether its
    contact is active in the first row is decided by the last bits of the
    start, and near p = 0 that decides the outcome (a start of the maps
    jams at t = 0.0027 or lifts off at t = 0.0186 as theta moves by one ulp).
    The agreement study builds its starts as arrays, whose sine and cosine
    take numpy's SIMD paths, the ladder one by one: a rerun that differs from
    the study's label at such a start is the same start in all but its last
    bits.  Labelled as the ladder labels rung 5 (the study's comparison time
    plus lag).
    """
    from crosscheck import engines

    th = thresholds or Thresholds()
    opts = ladder.options
    margin = window_margin(th, opts["timestep"])
    for k in ROUNDING_ULPS:
        theta = ladder.state.theta
        for _ in range(abs(k)):
            theta = float(np.nextafter(theta, math.inf if k > 0 else -math.inf))
        state = SlipState(**{**ladder.state.as_dict(), "theta": theta})
        run = engines.get("mujoco").simulate(Rod.scaled(ladder.alpha), state, ladder.mu, horizon=ladder.run_until + margin, thresholds=th, **opts)
        if _label(run.outcome, run.event_time, ladder.until + ladder.lag) == label:
            return True
    return False


def ladder_study(states: Sequence[SlipState], mu, *, alpha: float = 3.0, horizon: float = DEFAULT_HORIZON, references=None,
                 thresholds: Thresholds | None = None, progress: bool = False, desc: str = "ladder", keep: bool = False, **options) -> LadderStudy:
    """``run_ladder`` at every start (a plain loop with a tqdm bar ``desc``: each rung is one run of one state).

    Args:
      states, mu: the starts and their friction (mu a scalar or one per start).
      references: MuJoCo's labels to judge against (one per start, e.g. the
        agreement study's), or None for rung 5's own.
      other arguments: as ``run_ladder``.
    """
    states = list(states)
    mu = np.broadcast_to(np.asarray(mu, float), (len(states),))
    refs = [None] * len(states) if references is None else [int(r) for r in references]
    if len(refs) != len(states):
        raise ValueError(f"references must have one label per state ({len(states)}); got {len(refs)}")
    ladders = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # missing rungs are counted below and reported by the caller
        for s, m, ref in tqdm(list(zip(states, mu, refs)), desc=desc, unit="state", disable=not progress):
            ladders.append(run_ladder(s, float(m), alpha=alpha, horizon=horizon, thresholds=thresholds, reference=ref, keep=keep, **options))
    counts = {c: sum(ld.cause == c for ld in ladders) for c in CAUSES}
    n_dis = sum(ld.disagree for ld in ladders)
    named = sum(counts[c] for c in CAUSES[:4])
    missing = {name: sum(not ld.rung(name).ok for ld in ladders) for name in RUNGS}
    mismatched = [ld for ld in ladders if ld.reference_source == "given" and ld.rung("mujoco").ok and ld.rung("mujoco").label != ld.reference]
    rounding = sum(decided_by_rounding(ld, ld.reference, thresholds=thresholds) for ld in mismatched)
    if any(missing.values()):
        warnings.warn("ladder rungs that could not run: " + ", ".join(f"{k} at {v} starts" for k, v in missing.items() if v), RuntimeWarning,
                      stacklevel=2)
    return LadderStudy(ladders=ladders, counts=counts, n_disagree=n_dis, attributed=named / n_dis if n_dis else math.nan, missing=missing,
                       reference_mismatch=len(mismatched), rounding_decided=rounding)


def trajectories(ladder: Ladder) -> dict:
    """Time series of each rung that ran with ``keep=True``: {name: {"t", "eta", "normal_force"}} (scaled).

    Analytic rungs: eta along the slip and the rigid normal force -b/p (eq. FZ)
    at A (rung 1) or C (rung 2, where its result gives the series); engine
    rungs: the record's contact-point slip speed and normal force.
    """
    from crosscheck import analytic

    out = {}
    for r in ladder.rungs:
        res = r.result
        if not r.ok or res is None:
            continue
        if r.name in ("tip", "capsule"):
            t = np.asarray(getattr(res, "t", []), float)
            x = np.asarray(getattr(res, "x", np.empty((0, 6))), float)
            if t.size == 0 or x.ndim != 2 or x.shape[1] < 6:
                continue
            eta, varphi, Psi, theta, Theta = x[:, 0], x[:, 1], x[:, 3], x[:, 4], x[:, 5]
            if r.name == "tip":
                force = analytic.normal_force(Psi, Theta, theta, varphi, ladder.mu, ladder.alpha)
            else:
                force = _capsule_force(res, Psi, Theta, theta, varphi, ladder)
            out[r.name] = {"t": t, "eta": eta, "normal_force": np.asarray(force, float)}
        else:
            rec = res.record
            out[r.name] = {"t": np.asarray(rec.t, float), "eta": np.asarray(rec.eta, float), "normal_force": np.asarray(rec.normal_force, float)}
    return out


def _capsule_force(res, Psi, Theta, theta, varphi, ladder: Ladder) -> np.ndarray:
    """-b/p at C along an analytic capsule run (NaN where its result does not say)."""
    force = getattr(res, "normal_force", None)
    if force is not None:
        return np.asarray(force, float)
    try:
        from crosscheck import capsule

        return -np.asarray(capsule.b(Psi, Theta, theta)) / np.asarray(capsule.p(theta, varphi, ladder.mu, ladder.alpha, ladder.options["radius"]))
    except (ImportError, AttributeError, TypeError, ValueError):
        return np.full(np.shape(theta), np.nan)
