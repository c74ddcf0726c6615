"""One start's cause confirmed on the engine: the intervention the ladder's cause implies, then pairs where it fails.

``crosscheck explain`` names a cause from a ladder (``crosscheck.studies.ladder``): the first model in between the
theory
and the engine that gives the engine's outcome.  ``confirm`` checks it on the engine itself for that one start, with
the interventions the engine declares (``EngineSpec.interventions``, run by ``crosscheck.studies.interventions``):

1. every cause's interventions, weakest first (``intervene``): the named cause is **confirmed** when one of its own
   removes the disagreement (the engine's label becomes the theory's);
2. where none of its own does, the strongest of each of its families joined to the strongest of each family of every
   other cause (a pair that sets one parameter two ways is skipped): **confirmed as a pair with** the causes whose
   pair removes it (an overdetermined disagreement: each difference alone gives the engine's outcome, as at IC2 on
   MuJoCo, where neither a capsule of radius r/16 nor solimp d = 0.01 alone removes the jam and the two together do);
3. otherwise **removed by another cause's intervention instead** when some other cause's single intervention removes
   it (the ladder's cause is then in doubt), and **not removed** when nothing does.

A pair is tried even where another cause alone removes the disagreement: the question is whether the named cause is
part of it.  Scaled units (section 2.1).
"""

from __future__ import annotations

from crosscheck import engines
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.spec import LADDER_CAUSES
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.studies.interventions import attempt_intervention, intervene
from crosscheck.theory.slipping import slip_until_event

__all__ = ["VERDICTS", "confirm", "strongest"]

#: What ``confirm`` can say, in order of precedence.
VERDICTS = (
    "confirmed",
    "confirmed as a pair",
    "removed by another cause's intervention instead",
    "not removed",
    "no intervention declared",
    "no disagreement",
)


def strongest(rows: list[dict]) -> list[dict]:
    """The last (strongest) intervention of each family among ``rows`` (``intervene``'s rows of one cause)."""
    last = {}
    for r in rows:
        last[r.get("family", "")] = r
    return list(last.values())


def confirm(
    engine: str,
    state: SlipState,
    mu: float,
    *,
    cause: str,
    reference=None,
    alpha: float = 3.0,
    horizon: float = 2.0,
    thresholds: Thresholds | None = None,
    **options,
) -> dict:
    """Confirm the ladder's ``cause`` for ``state`` on ``engine`` at the run's ``options`` (module docstring).

    Returns a dict: ``engine``, ``cause``, ``verdict`` (one of ``VERDICTS``), ``text`` (the line ``explain`` prints),
    ``theory`` (the label the interventions are judged against), ``confirmed_by`` (the named cause's interventions that
    remove it), ``pair_with`` (the other causes whose pair removes it), ``instead`` (cause -> the texts of the other
    causes' single interventions that remove it), ``singles`` (``intervene``'s rows per cause) and ``pairs`` (one row
    per
    pair tried, with ``with``).
    """
    spec = engines.get(engine)
    out = {
        "engine": engine,
        "cause": cause,
        "confirmed_by": [],
        "pair_with": [],
        "instead": {},
        "singles": {},
        "pairs": [],
    }
    if cause not in LADDER_CAUSES:
        return {**out, "verdict": "no disagreement", "text": f"nothing to confirm (the ladder says: {cause})"}
    if cause not in (spec.interventions or {}):
        return {
            **out,
            "verdict": "no intervention declared",
            "text": f"{spec.label} declares no intervention for {cause}",
        }
    th = thresholds or Thresholds()
    iv = intervene(engine, state, mu, alpha=alpha, horizon=horizon, thresholds=th, **options)
    out["theory"], out["singles"] = iv["theory"], iv["causes"]
    own = iv["causes"].get(cause) or []
    out["confirmed_by"] = [r["text"] for r in own if r["removes"]]
    out["instead"] = {
        c: [r["text"] for r in rows if r["removes"]]
        for c, rows in iv["causes"].items()
        if c != cause and any(r["removes"] for r in rows)
    }
    if not out["confirmed_by"]:
        out["pairs"] = _pairs(spec, state, mu, alpha, horizon, th, options, own, iv["causes"], cause)
        out["pair_with"] = list(dict.fromkeys(p["with"] for p in out["pairs"] if p["removes"]))
    out["verdict"], out["text"] = _verdict(out)
    return out


def _pairs(spec, state, mu, alpha, horizon, th, options, own, singles, cause) -> list[dict]:
    """The strongest of each family of ``cause`` joined to the strongest of each family of every other cause."""
    rod = Rod.scaled(alpha)
    first = slip_until_event(state, mu, alpha, t_max=horizon)
    base = spec.options(**options)
    given = {k: getattr(base, k) for k in base.__dataclass_fields__}
    rows = []
    for a in strongest(own):
        for other in (c for c in LADDER_CAUSES if c != cause and singles.get(c)):
            for b in strongest(singles[other]):
                if set(a["options"]) & set(b["options"]):  # one parameter set two ways: not a pair
                    continue
                r = attempt_intervention(
                    spec,
                    rod,
                    state,
                    mu,
                    first,
                    horizon,
                    th,
                    given,
                    f"{a['text']}; {b['text']}",
                    {**a["options"], **b["options"]},
                )
                rows.append({"with": other, **r})
    return rows


def _verdict(out: dict) -> tuple[str, str]:
    cause = out["cause"]
    instead = "; ".join(f"{c}: {', '.join(t)}" for c, t in out["instead"].items())
    if out["confirmed_by"]:
        return "confirmed", f"{cause}: confirmed ({out['confirmed_by'][0]} removes it)"
    if out["pair_with"]:
        also = f"; also removed alone by {instead}" if instead else ""
        return "confirmed as a pair", f"{cause}: confirmed as a pair with {', '.join(out['pair_with'])}{also}"
    if instead:
        return (
            "removed by another cause's intervention instead",
            f"{cause}: removed by another cause's intervention instead ({instead})",
        )
    return "not removed", f"{cause}: not removed (no intervention, alone or in a pair, removes the disagreement)"
