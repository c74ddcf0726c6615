"""The ladder over many starts: the disagreements of an agreement study laddered, their rounding probe, trajectories to draw."""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from tqdm.auto import tqdm

from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.mujoco.studies.ladder import CAUSES, NAMED_CAUSES, RUNGS, Ladder, run_ladder
from crosscheck.error_stats import as_json
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.studies.agreement import DEFAULT_HORIZON
from crosscheck.studies.comparison import RATED, compared_label, window_margin

__all__ = ["LadderStudy", "ladder_study", "disagreements", "decided_by_rounding", "trajectories"]


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
      attributed: the fraction of them with a named cause (``NAMED_CAUSES``); NaN if none disagree.
      missing: per rung, how many starts it could not run.
      reference_mismatch: starts where rung 6's rerun label differs from the
        given reference (rung 6 is MuJoCo at the same options).
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
        n, causes = max(self.n_disagree, 1), [c for c in CAUSES if c not in ("agree", "not rated")]
        return {c: self.counts[c] / n for c in causes} if self.n_disagree else {c: math.nan for c in causes}

    def detours(self) -> dict:
        """Disagreements whose ladder takes a detour (``Ladder.detour``): their number, and per cause of the rung that
        ends it (the cause named "none" when no rung does)."""
        ended = [ld.detour_ended_by or "none" for ld in self.ladders if ld.detour is not None]
        return {"n": len(ended), "ended_by": {c: ended.count(c) for c in dict.fromkeys(ended)}}

    def summary(self) -> dict:
        wall = {
            name: float(sum(ld.rung(name).wall_time for ld in self.ladders)) for name in RUNGS
        }  # seconds per rung, over all starts
        return as_json(
            {
                "n": len(self.ladders),
                "n_disagree": self.n_disagree,
                "attributed": self.attributed,
                "counts": self.counts,
                "fractions": self.fractions(),
                "missing": self.missing,
                "reference_mismatch": self.reference_mismatch,
                "rounding_decided": self.rounding_decided,
                "detours": self.detours(),
                "wall_time": wall,
            }
        )


#: Units in the last place by which ``decided_by_rounding`` moves theta.
ROUNDING_ULPS = (-2, -1, 1, 2)


def decided_by_rounding(ladder: Ladder, label: Outcome, *, thresholds: Thresholds | None = None) -> bool:
    """Whether MuJoCo gives ``label`` at a start 1 or 2 units in the last place of theta away from ``ladder``'s.

    When MuJoCo's capsule started exactly on the plane, whether its contact was
    active in the first row was decided by the last bits of the start, and near
    p = 0 that decided the outcome (a start of the maps jammed at t = 0.0027 or
    lifted off at t = 0.0186 as theta moved by one ulp).  The start is now a
    hair above the plane (``crosscheck.engines.mujoco.model.START_GAP``) and
    the probe is the check that no such start is left.
    The agreement study builds its starts as arrays, whose sine and cosine
    take numpy's SIMD paths, the ladder one by one: a rerun that differs from
    the study's label at such a start is the same start in all but its last
    bits.  Labelled as the ladder labels rung 6 (the study's comparison time
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
        run = engines.get("mujoco").simulate(
            Rod.scaled(ladder.alpha), state, ladder.mu, horizon=ladder.run_until + margin, thresholds=th, **opts
        )
        if compared_label(run.outcome, run.event_time, ladder.until + ladder.lag) == label:
            return True
    return False


def ladder_study(
    states: Sequence[SlipState],
    mu,
    *,
    alpha: float = 3.0,
    horizon: float = DEFAULT_HORIZON,
    references=None,
    thresholds: Thresholds | None = None,
    progress: bool = False,
    desc: str = "ladder",
    keep: bool = False,
    **options,
) -> LadderStudy:
    """``run_ladder`` at every start (a plain loop with a tqdm bar ``desc``: each rung is one run of one state).

    Args:
      states, mu: the starts and their friction (mu a scalar or one per start).
      references: MuJoCo's labels to judge against (one per start, e.g. the
        agreement study's), or None for rung 6's own.
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
            ladders.append(
                run_ladder(
                    s,
                    float(m),
                    alpha=alpha,
                    horizon=horizon,
                    thresholds=thresholds,
                    reference=ref,
                    keep=keep,
                    **options,
                )
            )
    counts = {c: sum(ld.cause == c for ld in ladders) for c in CAUSES}
    n_dis = sum(ld.disagree for ld in ladders)
    named = sum(counts[c] for c in NAMED_CAUSES)
    missing = {name: sum(not ld.rung(name).ok for ld in ladders) for name in RUNGS}
    mismatched = [
        ld
        for ld in ladders
        if ld.reference_source == "given" and ld.rung("mujoco").ok and ld.rung("mujoco").label != ld.reference
    ]
    rounding = sum(decided_by_rounding(ld, ld.reference, thresholds=thresholds) for ld in mismatched)
    if any(missing.values()):
        warnings.warn(
            "ladder rungs that could not run: " + ", ".join(f"{k} at {v} starts" for k, v in missing.items() if v),
            RuntimeWarning,
            stacklevel=2,
        )
    return LadderStudy(
        ladders=ladders,
        counts=counts,
        n_disagree=n_dis,
        attributed=named / n_dis if n_dis else math.nan,
        missing=missing,
        reference_mismatch=len(mismatched),
        rounding_decided=rounding,
    )


def trajectories(ladder: Ladder) -> dict:
    """Time series of each rung that ran with ``keep=True``: {name: {"t", "eta", "normal_force"}} (scaled).

    Analytic rungs: eta along the slip and the rigid normal force -b/p (eq. FZ)
    at A (rung 1) or C (rung 2, where its result gives the series); engine
    rungs: the record's contact-point slip speed and normal force.
    """
    from crosscheck.theory import analytic

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
            out[r.name] = {
                "t": np.asarray(rec.t, float),
                "eta": np.asarray(rec.eta, float),
                "normal_force": np.asarray(rec.normal_force, float),
            }
    return out


def _capsule_force(res, Psi, Theta, theta, varphi, ladder: Ladder) -> np.ndarray:
    """-b/p at C along an analytic capsule run (NaN where its result does not say)."""
    force = getattr(res, "normal_force", None)
    if force is not None:
        return np.asarray(force, float)
    try:
        from crosscheck.theory import capsule

        return -np.asarray(capsule.b(Psi, Theta, theta)) / np.asarray(
            capsule.p(theta, varphi, ladder.mu, ladder.alpha, ladder.options["radius"])
        )
    except (ImportError, AttributeError, TypeError, ValueError):
        return np.full(np.shape(theta), np.nan)
