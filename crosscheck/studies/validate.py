"""``crosscheck validate ENGINE``: an engine's checks against the analytic reference, one entry point for all.

An engine is validated by up to two sets of checks, each a list of
``ErrorStat`` with a tolerance from ``crosscheck.tolerances``:

* dynamics terms (the engine's ``EngineSpec.dynamics``): a multibody model's
  M, C, g, Jacobians and Delassus operator against the paper's equations,
  state by state (``crosscheck.engines.pinocchio.studies.dynamics_terms`` for Pinocchio);
* contact events, for every engine that declares an event-tolerance profile
  (``EngineSpec.tolerances``):

  - lift-off onset: at theta_L, Theta = 0, varphi = -pi/2 and mu in
    ``MUS_ONSET`` the smallest Psi at which the engine lifts off at t = 0
    (``crosscheck.studies.onset``) must be Psi_L (eq. psil);
  - event agreement: random slipping states with mu in [0.3, 6] are run to
    their first event analytically (``slip_until_event``) and in the engine
    (``crosscheck.studies.agreement``); the fraction whose outcome differs
    (an analytic JAM met by a STICK counting as agreement) and the median
    |t_engine - t_analytic| of the shared events must stay within their
    tolerances;
  - jams (``crosscheck.studies.jams``): below mu_P no run may jam, asserted
    for the mu of ``MUS_BELOW`` at which the JAM rule can tell a jam from a
    hard slip: it accepts the engine's own p up to ``Thresholds.jam_p_eff``
    = 0.2, and p can be as small as ``p_min(mu)`` = 1 + alpha/2 -
    (alpha/2) sqrt(1 + mu^2) while the rod slips, so only mu with
    p_min(mu) > 0.2 (mu < 1.162 at alpha = 3) are decidable; mu = 1.3
    (p_min = 0.04) is run and reported in ``extra``, not asserted.  Above
    mu_P the engine's slip must end (JAM, STICK or LIFTOFF) within 0.15 of
    the analytic jam time of the Corollary 4.2 states (fraction pooled over
    mu = 1.4, 1.7, 6);

  For a rigid engine (``Options.contact_time == 0``) the window is
  ``RIGID_JAM_WINDOW`` instead of 0.15, and the fraction of the slips that
  end with a JAM (the impulse itself) in it is reported in ``extra`` as
  ``corollary_jam_fraction``: at large mu the discrete slip can run out in
  the last steps of the square-root approach to p = 0 (a STICK at the jam
  row) instead of ending with a one-row impulse.

  plus the engine's own checks (``EngineSpec.checks``): for MuJoCo, its tip
  acceleration with an active contact against eq. linode2 at the capsule's
  contact point (``crosscheck.engines.mujoco.studies.contact``); for the rigid
  engine (``crosscheck.engines.pinocchio.studies.rigid``), one step's normal impulse against
  eq. FZ, the order of convergence of a slipping trajectory, and the order
  of convergence of its state after a jam to the impact without collision
  (``crosscheck.theory.impact.darboux_keller``), with the Corollary 4.2 states' aftermath in ``extra``.

An engine with a dynamics-terms check takes ``n_states`` for that check and
min(n_states, ``DEFAULT_STATES``) for its event agreement.

Everything is in the paper's scaled units (m = l = g = 1, time 1/omega).
"""

from __future__ import annotations

import importlib
import math

import numpy as np

from crosscheck import engines
from crosscheck.engines.classifier import Thresholds
from crosscheck.error_stats import ErrorStat, ValidationResult, error_stat
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.studies.agreement import DEFAULT_HORIZON, agreement_study, convergence_table
from crosscheck.studies.grids import random_event_points
from crosscheck.studies.jams import jam_check
from crosscheck.studies.onset import liftoff_onset
from crosscheck.theory.critical import Psi_L, p_min

__all__ = [
    "names",
    "default_states",
    "validate",
    "contact_events",
    "DEFAULT_STATES",
    "ALPHA",
    "MUS_ONSET",
    "MUS_BELOW",
    "RIGID_JAM_WINDOW",
    "PARTS",
    "parts_of",
]

#: Random states of the event agreement without ``--states`` (~1 min on 2 cores for MuJoCo's whole validation).
DEFAULT_STATES = 300

#: alpha of the validation rod (uniform rod).
ALPHA = 3.0

#: Friction coefficients of the lift-off onset check.
MUS_ONSET = (0.3, 1.0, 2.0)

#: mu < mu_P(3) = 4/3 of the "no jam below mu_P" runs; see the module docstring for
#: which of them are asserted (p_min(mu) > Thresholds.jam_p_eff).
MUS_BELOW = (0.5, 1.0, 1.15, 1.3)

#: How close to the analytic jam a rigid engine's JAM must be (scaled time): its jam comes early by
#: O(sqrt(dt)) (the square-root approach to p = 0, crosscheck.tolerances), 0.03 at dt = 1e-3; 0.05
#: leaves a margin and is a third of the soft contact's 0.15.
RIGID_JAM_WINDOW = 0.05


def names() -> list[str]:
    """Names ``validate`` accepts: engines with dynamics terms or event tolerances."""
    return sorted(e.name for e in engines.specs() if e.dynamics is not None or e.tolerances is not None)


def default_states(name: str) -> int:
    """Random states of ``validate`` without ``--states``: the dynamics check's if it has one, else ``DEFAULT_STATES``."""
    _known(name)
    dynamics = engines.get(name).dynamics
    return importlib.import_module(dynamics).DEFAULT_STATES if dynamics else DEFAULT_STATES


def _known(name: str) -> None:
    if name not in names():
        raise ValueError(
            f"engine must be one of {', '.join(names())} (engines with validation tolerances); got {name!r}"
        )


def _count_stat(quantity: str, got, tolerance, states: dict) -> ErrorStat:
    got = np.asarray(got, float)
    return error_stat(quantity, got, np.zeros_like(got), tolerance, states)


def contact_events(
    engine: str,
    n_states: int,
    rng: np.random.Generator,
    *,
    progress: bool = False,
    jam_states: tuple[int, int] | None = None,
) -> ValidationResult:
    """The contact-event checks of the module docstring for ``engine``; the event agreement on ``n_states`` random states.

    ``jam_states``: (random states per mu below mu_P, Corollary 4.2 states per mu above it); by default
    (max(20, n_states // 5), max(30, n_states // 10)).
    """
    if n_states < 1:
        raise ValueError(f"n_states must be >= 1; got {n_states}")
    judged = sorted(e.name for e in engines.specs() if e.tolerances is not None)
    if engine not in judged:
        raise ValueError(f"engine must be one of {', '.join(judged)} (engines with event tolerances); got {engine!r}")
    E = engines.get(engine)
    T = E.tolerances
    rod = Rod.scaled(ALPHA)
    stats: list[ErrorStat] = []
    extra: dict = {"units": "scaled (m = l = g = 1, time 1/omega)", "alpha": ALPHA}

    if E.checks is not None:
        stats.extend(E.checks(rod, n_states, rng))

    onsets = [liftoff_onset(rod, m, engine=engine) for m in MUS_ONSET]
    stats.append(
        error_stat(
            "lift-off onset Psi",
            [o for o, _ in onsets],
            [float(Psi_L)] * len(onsets),
            T["liftoff_onset"],
            {"mu": np.array(MUS_ONSET), "resolution": np.array([r for _, r in onsets])},
        )
    )

    agreement_stats, extra["event_agreement"] = _agreement_checks(engine, n_states, rng, T, progress=progress)
    stats += agreement_stats
    jam_stats, extra["corollary_jam_fraction"], extra["jams"] = _jam_checks(E, n_states, rng, T, jam_states, progress)
    stats += jam_stats
    extra["tolerances"] = {k: v.as_dict() for k, v in T.items()}
    return ValidationResult(engine=engine, stats=stats, extra=extra)


def _agreement_checks(engine: str, n_states: int, rng, T: dict, *, progress: bool) -> tuple[list[ErrorStat], dict]:
    """The event agreement on ``n_states`` random slipping states: its statistics (the disagreement, and the median
    |event time difference| where an event is shared) and its ``extra`` entry."""
    stats: list[ErrorStat] = []
    points = random_event_points(n_states, rng)
    study = agreement_study(
        points, engine=engine, alpha=ALPHA, horizon=DEFAULT_HORIZON, rng=rng, boundary_directions=0, progress=progress
    )
    run = study.runs[0]
    where_c = {"n_rated": np.array([run.n_rated])}
    stats.append(
        error_stat("event disagreement", [1.0 - run.agreement_jam_as_stop], [0.0], T["event_disagreement"], where_c)
    )
    if math.isfinite(run.median_abs_time_difference):  # a median of no shared event (one state) is not a failure
        stats.append(
            error_stat(
                "median |event time difference|", [run.median_abs_time_difference], [0.0], T["event_time"], where_c
            )
        )
    return stats, {
        "median_abs_time_difference": run.median_abs_time_difference
        if math.isfinite(run.median_abs_time_difference)
        else "not measured: no event shared with the theory",
        "n_states": n_states,
        "horizon": DEFAULT_HORIZON,
        "analytic_outcomes": {o.name: int((study.analytic.outcome[study.index] == o).sum()) for o in Outcome},
        "runs": [
            {
                k: v
                for k, v in r.summary().items()
                if k not in ("time_difference", "time_difference_outcome", "by_distance")
            }
            for r in study.runs
        ],
        "convergence_row": convergence_table(study),
    }


def _jam_checks(E, n_states: int, rng, T: dict, jam_states, progress: bool) -> tuple[list[ErrorStat], float, dict]:
    """The jam checks of the engine ``E`` (module docstring): their statistics, the fraction of the Corollary 4.2
    slips that end with a JAM near the analytic jam, and the ``extra`` entry of the jams."""
    stats: list[ErrorStat] = []
    rigid = E.options().contact_time == 0.0
    n_below, n_above = jam_states or (max(20, n_states // 5), max(30, n_states // 10))
    jc = jam_check(
        engine=E.name,
        mus_below=MUS_BELOW,
        n_below=n_below,
        n_above=n_above,
        rng=rng,
        near_window=RIGID_JAM_WINDOW if rigid else 0.15,
        progress=progress,
    )
    p_jam = Thresholds().jam_p_eff
    decidable = [row for row in jc.below if p_min(row["mu"], ALPHA) > p_jam]
    stats.append(
        _count_stat(
            "jams below mu_P",
            [row["n_jam"] for row in decidable],
            T["no_jam_below_mu_P"],
            {"mu": np.array([row["mu"] for row in decidable]), "n": np.array([row["n"] for row in decidable])},
        )
    )
    # pooled over the mu values: the fraction is a binomial estimate, sd ~0.05 at 90 states
    n_above = sum(row["n"] for row in jc.above)
    ended = sum(row["n"] * row["ended_near_fraction"] for row in jc.above)
    stats.append(
        error_stat(
            "Corollary 4.2 slip not ended",
            [1.0 - ended / n_above],
            [0.0],
            T["corollary_stop"],
            {"n": np.array([n_above])},
        )
    )
    jam_fraction = sum(row["n"] * row["near_fraction"]["JAM"] for row in jc.above) / n_above
    jams = jc.to_dict()
    jams["asserted_below"] = [row["mu"] for row in decidable]
    jams["near_mu_P_not_asserted"] = {
        "why": f"p_min(mu) <= jam_p_eff = {p_jam}: the JAM rule cannot tell a jam from a hard slip there",
        "rows": [
            {"mu": row["mu"], "p_min": float(p_min(row["mu"], ALPHA)), "n": row["n"], "jams": row["n_jam"]}
            for row in jc.below
            if row not in decidable
        ],
    }
    return stats, jam_fraction, jams


#: The parts ``validate`` can run: the dynamics terms and the contact events (``checks=``; all by default).
PARTS = ("dynamics", "events")


def parts_of(name: str) -> tuple[str, ...]:
    """The parts of ``PARTS`` engine ``name`` has."""
    E = engines.get(name)
    return tuple(p for p in PARTS if (p == "dynamics" and E.dynamics) or (p == "events" and E.tolerances is not None))


def validate(
    name: str, n_states: int, rng: np.random.Generator, *, progress: bool = False, checks=PARTS
) -> ValidationResult:
    """Every check ``name`` has among ``checks`` (dynamics terms, then contact events), as one ``ValidationResult``."""
    _known(name)
    checks = tuple(checks)
    for c in checks:
        if c not in PARTS:
            raise ValueError(f"checks must be among {', '.join(PARTS)}; got {c!r}")
    parts = []
    E = engines.get(name)
    if E.dynamics and "dynamics" in checks:
        parts.append(importlib.import_module(E.dynamics).validate(n_states, rng, progress=progress))
    if E.tolerances is not None and "events" in checks:
        parts.append(
            contact_events(name, min(n_states, DEFAULT_STATES) if E.dynamics else n_states, rng, progress=progress)
        )
    if not parts:
        raise ValueError(
            f"checks must include a part {name} has ({', '.join(parts_of(name))}); got {', '.join(checks) or 'none'}"
        )
    if len(parts) == 1:
        return parts[0]
    extra = {}
    for p in parts:
        extra.update(p.extra)
    return ValidationResult(engine=name, stats=[s for p in parts for s in p.stats], extra=extra)
