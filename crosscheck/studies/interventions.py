"""Interventions: a ladder's cause confirmed on the engine itself, by changing the engine the way the cause names.

A ladder (``crosscheck.studies.ladder``) names a cause when a model in
between the theory and the engine first agrees with the engine.  That is
evidence, not proof: the model in between is not the engine.  Here the engine
itself is changed in the way each cause names (its ``EngineSpec.interventions``:
a thinner capsule for geometry, a stiffer contact for compliance, a closer
friction law, a smaller timestep, the step without its relaxation) and rerun
from the same start.  An intervention removes the disagreement when the
engine's label equals the theory's (rung 1's: the paper's rod from the same
start), both relabelled as the agreement study does
(``crosscheck.studies.comparison``) with the comparison window of the
intervened engine's own options.

A cause is **confirmed** when one of its interventions removes the
disagreement.  Not necessarily the strongest: a much stiffer MuJoCo contact,
or a friction time constant far below the normal one, can throw the tip off
the plane in the first step (a LAUNCH or LIFTOFF of its own), so the summary
also counts the starts removed at a weaker step but not at the strongest.
Every cause's interventions
run on every start, so the study also finds where another cause's
intervention removes it instead (a misattribution to look into) and the
starts where none does.

Scaled units (section 2.1).
"""

from __future__ import annotations

import math
import time

import numpy as np

from crosscheck import engines
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.spec import LADDER_CAUSES
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.studies.comparison import (
    RATED,
    compared_label,
    engine_floor,
    floor_time,
    run_comparison_window,
    run_stick_from,
    window_margin,
)
from crosscheck.theory.slipping import slip_until_event

__all__ = ["intervene", "attempt_intervention", "summarise", "causes_with_interventions"]


def causes_with_interventions(engine: str) -> list[str]:
    """The causes of ``engine``'s ladder it declares interventions for, in ladder order."""
    spec = engines.get(engine)
    return [c for c in LADDER_CAUSES if c in (spec.interventions or {})]


def intervene(
    engine: str,
    state: SlipState,
    mu: float,
    *,
    alpha: float = 3.0,
    horizon: float = 2.0,
    thresholds: Thresholds | None = None,
    causes=None,
    named: str | None = None,
    reference=None,
    **options,
) -> dict:
    """``state`` through every intervention ``engine`` declares (or those of ``causes``), at the run's ``options``.

    Returns a dict: ``theory`` (rung 1's label), ``theory_time``, what the theory's slip looks like to the run
    (``theory_against_floor``: ``theory_eta_min``, ``theory_p_min``, ``stick_floor``, ``theory_below_floor_time``), and ``causes``:
    cause -> list of {text, options, status, outcome, time, label, removes} per
    intervention, weakest first; ``removes`` is whether the engine's label equals
    the theory's.  An intervention that raises is ``status: failed`` with the error.

    ``named``: the cause the ladder named.  Where no single intervention removes the disagreement, ``joint`` holds its
    strongest intervention combined with the strongest of each other cause of the ladder (``LADDER_CAUSES`` order; a
    pair that sets one parameter two ways is not combined): the rows of an overdetermined disagreement, which each of
    the two differences produces on its own (``summarise``).  Not only the later causes: near p = 0 a difference whose
    rung did not give the engine's outcome alone (a friction skewed off the slip, with the capsule's offset) still
    gives it in the engine, where every other difference is present.

    ``reference``: the engine's label the ladder judged (an ``Outcome`` or its name).  With ``named`` geometry,
    ``without_offset`` holds the ladder's later models rerun with the thin capsule
    (``crosscheck.studies.ladder.without_capsule_offset``): its ``also`` is the cause that gives the engine's outcome
    without the capsule's offset, the ladder's own prediction that the disagreement is overdetermined.
    """
    spec = engines.get(engine)
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    th = thresholds or Thresholds()
    base = spec.options(**options)
    rod = Rod.scaled(alpha)
    first = slip_until_event(state, mu, alpha, t_max=horizon)
    o1, t1 = Outcome(int(first.outcome)), float(first.time)
    out = {
        "theory": compared_label(o1, t1, t1).name,
        "theory_time": t1,
        **theory_against_floor(first, mu, alpha, th, base),
        "causes": {},
    }
    given = {k: getattr(base, k) for k in base.__dataclass_fields__}

    def attempt(text: str, changed: dict) -> dict:
        return attempt_intervention(spec, rod, state, mu, first, horizon, th, given, text, changed)

    for cause in causes if causes is not None else causes_with_interventions(engine):
        out["causes"][cause] = [
            {**attempt(iv.text, iv.options), **({"family": iv.family} if iv.family else {})}
            for iv in spec.interventions_for(cause, base, p_min=out["theory_p_min"])
        ]
    if named == "geometry" and reference is not None:
        from crosscheck.studies.ladder import without_capsule_offset

        ref = Outcome[reference] if isinstance(reference, str) else Outcome(int(reference))
        try:
            out["without_offset"] = without_capsule_offset(
                engine, state, mu, ref, alpha=alpha, horizon=horizon, thresholds=th, **given
            )
        except Exception as e:  # noqa: BLE001 - the ladder's question left open is reported, the interventions stand
            out["without_offset"] = {"also": None, "status": "failed", "detail": f"{type(e).__name__}: {e}"}
    own = out["causes"].get(named) or []
    if own and not any(
        _fixes(out, c) for c in out["causes"]
    ):  # (one that another cause removes alone is a misattribution)
        # an overdetermined disagreement: the named difference and another one each produce the engine's outcome alone
        strongest = own[-1]["options"]
        out["joint"] = []
        for c in (c for c in LADDER_CAUSES if c != named):
            rows = out["causes"].get(c) or []
            if not rows or _fixes(out, c) or set(strongest) & set(rows[-1]["options"]):
                continue
            out["joint"].append(
                {"with": c, **attempt(f"{own[-1]['text']}; {rows[-1]['text']}", {**strongest, **rows[-1]["options"]})}
            )
    return out


def attempt_intervention(
    spec,
    rod: Rod,
    state: SlipState,
    mu: float,
    first,
    horizon: float,
    th: Thresholds,
    given: dict,
    text: str,
    changed: dict,
) -> dict:
    """One intervention on ``spec`` from ``state``: the run's options ``given`` with ``changed`` over them, judged against
    the theory's slip ``first`` (``slip_until_event``'s result) as ``intervene`` judges every row: {text, options,
    status, outcome, time, label, removes, wall_time}; an intervention the engine refuses is ``status: failed``."""
    alpha = rod.alpha
    o1, t1 = Outcome(int(first.outcome)), float(first.time)
    opts_kw = {**given, **changed}
    t0 = time.perf_counter()
    try:
        opts = spec.options(**opts_kw)
        until, lag, run_until = run_comparison_window(first, horizon, mu, alpha, opts)
        # a STICK the classifier cannot tell from the theory's slip, at the intervened run's own STICK floor
        since = run_stick_from(first, until, th, opts)
        o, t = spec.first_event(
            rod, state, mu, horizon=run_until + window_margin(th, opts.timestep), thresholds=th, **opts_kw
        )
        theory, label = compared_label(o1, t1, until + lag), compared_label(o, t, until + lag, since)
        return {
            "text": text,
            "options": dict(changed),
            "status": "ok",
            "outcome": o.name,
            "time": t,
            "label": label.name,
            "removes": label == theory and theory in RATED,
            "wall_time": time.perf_counter() - t0,
        }
    except Exception as e:  # noqa: BLE001 - an intervention the engine refuses is reported, the others go on
        return {
            "text": text,
            "options": dict(changed),
            "status": "failed",
            "detail": f"{type(e).__name__}: {e}",
            "removes": False,
            "wall_time": time.perf_counter() - t0,
        }


def theory_against_floor(first, mu: float, alpha: float, th: Thresholds, opts) -> dict:
    """What the theory's slip looks like to the engine's run: its least slip speed and least eq. p along the slip, the
    run's STICK floor (``comparison.engine_floor``) and the first time the theory's slip speed falls below it (NaN if
    never; an engine STICK from then on, less an event's lag, is compared as the theory's slip: ``comparison.stick_from``).
    A least p near 0: the slip passes close to the Genot-Brogliato point, where a time step cannot tell a lift-off from
    a jam."""
    from crosscheck.theory import analytic

    floor = engine_floor(th, opts)
    p = analytic.p(first.x[:, 4], first.x[:, 1], mu, alpha)
    return {
        "theory_eta_min": float(first.x[:, 0].min()),
        "theory_p_min": float(np.min(p)),
        "stick_floor": float(floor),
        "theory_below_floor_time": floor_time(first.t, first.x[:, 0], floor),
    }


def _fixes(result: dict, cause: str) -> bool:
    """Whether one of ``cause``'s interventions removes the disagreement."""
    return any(r["removes"] for r in result["causes"].get(cause) or [])


def _not_at_strongest(result: dict, cause: str) -> bool:
    """Removed by one of the cause's interventions, but by the strongest (last) of none of its families."""
    rows = result["causes"].get(cause) or []
    last = {r.get("family", ""): r for r in rows}  # each family's last row
    return _fixes(result, cause) and not any(r["removes"] for r in last.values())


def _jointly(result: dict) -> list[str]:
    """The other causes whose strongest intervention, joined to the named cause's strongest, removes the disagreement
    (``intervene``'s ``joint``: neither removes it alone)."""
    return [r["with"] for r in result.get("joint") or [] if r["removes"]]


def summarise(results: list[dict], *, p_band: float | None = None) -> dict:
    """Per cause named by the ladder: how many its own interventions confirm (and of those, how many only at a weaker step),
    how many each of its interventions removes (``by_intervention``, text -> count, out of ``tried``, text -> the starts
    that got it: fewer than all for a step only some starts get, as at the theory's closest approach to p = 0; a cause
    whose interventions change different parts of the engine, such as MuJoCo's friction direction and its impedance's
    feed-forward, says which part acts), how many another cause's remove instead, how many only the named cause's and
    another cause's interventions together remove (``jointly``, other cause -> count: overdetermined, each difference alone giving the engine's
    outcome, so that neither intervention alone can remove it; not counted as confirmed), how many none does; and over
    all of them (``removed_by_any``) how many some cause's intervention removes, whatever the ladder named.

    Where the ladder itself finds the disagreement overdetermined (geometry named, and its later models without the
    capsule's offset still giving the engine's outcome through a cause ``also``: ``intervene``'s ``without_offset``),
    the ladder's cause is the pair, and it is confirmed when the two interventions together remove the disagreement
    and neither alone does: counted as confirmed, and apart in ``overdetermined`` (also -> count).  ``pairs`` says how
    every such prediction fared: confirmed; refuted by the capsule's offset removing it alone (then geometry is
    confirmed as before), by another cause's intervention alone, or by the two together failing.  ``by_other`` counts
    per cause that removes a start instead (a start may count under several), ``by_other_starts`` and
    ``misattributed`` each such start once.

    ``by_p``: the attributed disagreements and those confirmed, apart for the starts whose theory slip enters the band
    eq. p <= ``p_band`` (default: the classifier's ``Thresholds.jam_p_eff``, where a slip stop under a force beyond
    the slipping -b/p_eff reads as a JAM) and for those whose slip keeps above it.  In the band the rigid normal force
    -b/p is at least |b| / p_band and grows without bound toward p = 0, and each difference of an engine (the capsule's
    offset r below the tip, a friction skewed off the slip, a force that builds up over a contact time) moves its own
    p_eff by as much as the theory's p is away from 0: removing one difference leaves another to jam or lift off.
    Measured on the full report: 127 of 137 (93 %) confirmed above the band, 178 of 242 (74 %) in it.

    ``by_distance``: the same two counts by the start's distance to the theory's own event boundary as the engine's map
    section probed it (``crosscheck.studies.analytic_events.boundary_distance``: the first probe radius, of a few
    random directions each, at which the perturbed start's theory outcome differs, an upper bound on the distance; a
    start's ``boundary_distance``, "inf" where no probe changed it, None where not probed, as in the quick report): a
    list of {distance, attributed, confirmed} in increasing distance, empty when no start was probed, and
    ``unprobed`` the attributed starts without a distance beside probed ones.  Each engine difference moves the
    engine's rod by some distance of its own; where the theory's outcome turns within 0.01 of the start, any of them
    may turn it, and removing one leaves the others.  Measured on the full report: 25 of 43 confirmed at 0.01, 50 of
    51 where no probe up to 0.3 changes the outcome.

    ``results``: one dict per laddered disagreement with ``cause`` (the ladder's), ``interventions``
    (``intervene``'s result, with ``theory_p_min``) and optionally ``boundary_distance``.  Only the causes of
    ``LADDER_CAUSES`` count as attributed.
    """
    band = Thresholds().jam_p_eff if p_band is None else float(p_band)
    tally = _Tally(band)
    for r in results:
        tally.add(r)
    return tally.summary(len(results))


def _cause_row() -> dict:
    """A cause's empty row of ``summarise``'s ``per_cause``."""
    return {
        "n": 0,
        "confirmed": 0,
        "not_at_strongest": 0,
        "overdetermined": {},
        "by_other": {},
        "by_other_starts": 0,
        "jointly": {},
        "none": 0,
        "no_intervention": 0,
        "by_intervention": {},
        "tried": {},
    }


def _pair_verdict(cause: str, fixing: list[str], both: bool) -> str:
    """How the ladder's overdetermined pair fared (``summarise``'s ``pairs``)."""
    if both:
        return "confirmed"
    return "geometry alone" if cause in fixing else "another alone" if fixing else "joint failed"


class _Tally:
    """``summarise``'s counts as they grow, one laddered disagreement at a time."""

    def __init__(self, band: float):
        self.per: dict = {}
        self.by_p = {
            "p_band": band,
            "in_band": {"attributed": 0, "confirmed": 0},
            "above": {"attributed": 0, "confirmed": 0},
        }
        self.by_distance: dict = {}
        self.pairs = {"predicted": 0, "confirmed": 0, "geometry alone": 0, "another alone": 0, "joint failed": 0}
        self.attributed = self.confirmed = self.removed = self.jointly = self.misattributed = self.unprobed = 0

    def add(self, r: dict) -> None:
        """Count one disagreement ``r`` (``summarise``'s ``results``)."""
        cause, iv = r["cause"], r["interventions"]
        fixing = [c for c in iv["causes"] if _fixes(iv, c)]
        joint = _jointly(iv)
        self.removed += bool(fixing or joint)
        row = self.per.setdefault(cause, _cause_row())
        also = (iv.get("without_offset") or {}).get("also")
        both = (
            bool(also) and not fixing and also in joint
        )  # the ladder's overdetermined pair, removed by the two together
        if also and cause in LADDER_CAUSES:  # how the ladder's prediction fared: only "confirmed" counts the pair
            self.pairs["predicted"] += 1
            self.pairs[_pair_verdict(cause, fixing, both)] += 1
        row["n"] += 1
        # what, of the cause's own interventions, removes it: which part of the cause acts
        for x in iv["causes"].get(cause) or []:
            row["by_intervention"][x["text"]] = row["by_intervention"].get(x["text"], 0) + bool(x["removes"])
            # (a step some starts get, as at p near 0: fewer than n)
            row["tried"][x["text"]] = row["tried"].get(x["text"], 0) + 1
        if cause in LADDER_CAUSES:
            self._attributed(r, row, fixing, both, also)
        if cause not in fixing:
            for c in fixing:
                row["by_other"][c] = row["by_other"].get(c, 0) + 1
            if fixing:  # (a start another cause's intervention removes, counted once however many causes' do)
                row["by_other_starts"] += 1
                self.misattributed += cause in LADDER_CAUSES
            elif joint and not both:
                row["jointly"][joint[0]] = row["jointly"].get(joint[0], 0) + 1
                self.jointly += 1
            elif not both:
                row["none"] += 1

    def _attributed(self, r: dict, row: dict, fixing: list[str], both: bool, also) -> None:
        """Count the disagreement ``r`` the ladder attributes to one of ``LADDER_CAUSES``: confirmed or not, by eq. p's
        band and by the start's distance to the theory's event boundary."""
        cause, iv = r["cause"], r["interventions"]
        side = self.by_p["in_band" if iv.get("theory_p_min", math.inf) <= self.by_p["p_band"] else "above"]
        d = r.get("boundary_distance")
        probed = d is not None and float(d) == float(d)  # (None: not probed; NaN likewise)
        self.unprobed += not probed
        tallies = [side]
        if probed:
            tallies.append(
                self.by_distance.setdefault(float(d), {"distance": float(d), "attributed": 0, "confirmed": 0})
            )
        ok = cause in iv["causes"] and (_fixes(iv, cause) or both)
        for tally in tallies:
            tally["attributed"] += 1
            tally["confirmed"] += ok
        self.attributed += 1
        self.confirmed += ok
        if cause not in iv["causes"]:
            row["no_intervention"] += 1
        elif ok:
            row["confirmed"] += 1
            row["not_at_strongest"] += _not_at_strongest(iv, cause)
            if both:
                row["overdetermined"][also] = row["overdetermined"].get(also, 0) + 1

    def summary(self, n: int) -> dict:
        """``summarise``'s result over the n disagreements counted."""
        return {
            "per_cause": self.per,
            "attributed": self.attributed,
            "confirmed": self.confirmed,
            "confirmed_share": self.confirmed / self.attributed if self.attributed else None,
            "jointly": self.jointly,
            "misattributed": self.misattributed,
            "pairs": self.pairs,
            "by_p": self.by_p,
            "by_distance": [self.by_distance[d] for d in sorted(self.by_distance)],
            "unprobed": self.unprobed if self.by_distance else 0,
            # whatever the ladder named: the disagreements some cause's intervention on the engine removes
            "n": n,
            "removed_by_any": self.removed,
        }
