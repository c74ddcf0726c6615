"""``crosscheck validate mujoco``: MuJoCo's rod against the analytic reference (issue 4, item 5).

Four checks, each an ``ErrorStat`` with its tolerance from the MuJoCo section
of ``crosscheck.tolerances`` (the command exits 1 when one fails):

5a  Instantaneous tip acceleration.  Random slipping states are put 1e-4 l
    into the plane (contact active) and MuJoCo computes its contact force and
    tip acceleration (``mj_forward``, solver run to its iteration limit);
    eq. linode2 with that force applied at the capsule's contact point
    (``crosscheck.mujoco_rod.capsule_tip_acceleration``) must give the same
    acceleration, in units of the term scale g (1 + alpha |F|_1 / (m g)).
5b  Lift-off onset.  At theta_L, Theta = 0, varphi = -pi/2 and mu = 0.3, 1, 2
    the smallest Psi at which MuJoCo lifts off at t = 0 (bisection over
    batched sweeps) must be Psi_L (eq. psil).
5c  Event agreement.  Random slipping states and mu in [0.3, 6] are run to
    their first event analytically (``slip_until_event``) and in MuJoCo
    (``crosscheck.mujoco_agreement``); the fraction whose MuJoCo outcome
    differs from the analytic one, and the median |t_MuJoCo - t_analytic| of
    the shared events, must stay within their tolerances.  The confusion
    matrices (both classifiers) are in ``extra``.
5d  Jams.  Below mu_P no MuJoCo run may jam (``classify_effective``), asserted
    for the mu of ``MUS_BELOW`` at which the JAM rule can tell a jam from a hard
    slip: the rule accepts an effective p up to ``P_EFF_JAM`` = 0.2, and p can be
    as small as ``p_min(mu)`` = 1 + alpha/2 - (alpha/2) sqrt(1 + mu^2) while the
    rod slips, so only mu with p_min(mu) > P_EFF_JAM (mu < 1.162 at alpha = 3)
    are decidable.  mu = 1.3 (p_min = 0.04) is run and reported in ``extra``,
    not asserted: there MuJoCo's hard slips and landings of a hopping tip with
    p_eff < 0.2 look like jams to the rule (measured: 1 of 60 at seed 0);
    above it, MuJoCo's slip must end (JAM, STICK or LIFTOFF) within 0.15 of
    the analytic jam time of the Corollary 4.2 states (theory: p -> 0 with
    b < 0, off the planar section; fraction pooled over mu = 1.4, 1.7, 6).  Part A's own JAM counts are in ``extra``.

Everything is in the paper's scaled units (m = l = g = 1, time 1/omega).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from crosscheck import tolerances as tol
from crosscheck.compare import ErrorStat, ValidationResult, error_stat
from crosscheck.critical import Psi_L, p_min, theta_L
from crosscheck.mujoco_agreement import DEFAULT_HORIZON, P_EFF_JAM, agreement_study, convergence_table, jam_check
from crosscheck.mujoco_rod import Options, SensorLayout, build_model, capsule_tip_acceleration, initial_state, record_from_sensordata
from crosscheck.mujoco_sweep import sweep
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["DEFAULT_STATES", "ALPHA", "MUS_ONSET", "random_event_points", "contact_acceleration", "liftoff_onset", "validate"]

#: Random states of 5c without ``--states`` (~1 min on 2 cores for the whole command).
DEFAULT_STATES = 300

#: alpha of the validation rod (uniform rod).
ALPHA = 3.0

#: Friction coefficients of the lift-off onset check (5b).
MUS_ONSET = (0.3, 1.0, 2.0)


def random_event_points(n: int, rng: np.random.Generator, *, alpha: float = ALPHA) -> dict[str, np.ndarray]:
    """n random slipping starts (b < 0 < p) for 5c, each key of ``AXES`` an (n,) array.

    theta ~ U(0.1, 1.45), varphi ~ -U(0, pi) (clipped into (-pi, 0]), Theta ~
    U(-1, 1), Psi ~ U(-3, 3), eta ~ U(0.3, 2), mu ~ U(0.3, 6).
    """
    out = {k: [] for k in ("theta", "varphi", "Theta", "Psi", "mu", "eta")}
    while len(out["theta"]) < n:
        m = 4 * (n - len(out["theta"])) + 8
        th, vp = rng.uniform(0.1, 1.45, m), -rng.uniform(0.0, math.pi * (1 - 1e-9), m)
        Th, Ps, eta, mu = rng.uniform(-1, 1, m), rng.uniform(-3, 3, m), rng.uniform(0.3, 2.0, m), rng.uniform(0.3, 6.0, m)
        s, c = np.sin(th), np.cos(th)
        ok = ((Ps**2 * c**2 + Th**2) * s - 1 < 0) & (1 + alpha + alpha * s * (mu * c * np.sin(vp) - s) > 0)
        for k, v in zip(out, (th, vp, Th, Ps, mu, eta)):
            out[k].extend(v[ok].tolist())
    return {k: np.array(v[:n]) for k, v in out.items()}


def contact_acceleration(rod: Rod, n: int, rng: np.random.Generator, *, radius: float = 0.02, depth: float = 1e-4) -> dict[str, np.ndarray]:
    """5a: MuJoCo's tip acceleration with an active contact against eq. linode2 at the contact point.

    n random slipping states (psi random too), the capsule ``depth`` (scaled)
    into the plane, ``mj_forward`` with the solver run to its iteration limit
    (solver_tolerance 0) and mu ~ U(0, 2).  Returns (n,) / (n, 3) arrays:
    ``got`` and ``want`` tip accelerations and ``scale`` (all / g), the state
    variables and mu.
    """
    got, want, scale = np.empty((n, 3)), np.empty((n, 3)), np.empty(n)
    states = {k: np.empty(n) for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi", "mu")}
    for i in range(n):
        s = SlipState(theta=rng.uniform(0.1, 1.45), varphi=-rng.uniform(0.05, 3.1), Theta=0.7 * rng.normal(), Psi=rng.normal(), eta=rng.uniform(0.2, 3), psi=rng.uniform(-3, 3))
        mu = rng.uniform(0.0, 2.0)
        model = build_model(rod, mu, Options(radius=radius, solver_tolerance=0.0))
        data = mujoco.MjData(model)
        layout = SensorLayout.from_model(model)
        mujoco.mj_setState(model, data, initial_state(model, rod, s, radius), mujoco.mjtState.mjSTATE_FULLPHYSICS)
        data.qpos[2] -= depth * rod.length
        mujoco.mj_forward(model, data)
        rec = record_from_sensordata(data.sensordata, layout, rod, radius)
        F = rec.force * rod.force_scale
        dist = data.sensordata[layout.dist]
        q, v = data.qpos[3:], data.qvel[3:]
        got[i] = rec.tip_acc
        want[i] = capsule_tip_acceleration(rod, q[0], q[1], v[0], v[1], F, radius * rod.length + dist / 2) / rod.gravity
        scale[i] = 1 + rod.alpha * np.abs(F).sum() / rod.force_scale
        for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi"):
            states[k][i] = getattr(s, k)
        states["mu"][i] = mu
    return {"got": got, "want": want, "scale": scale, **states}


def liftoff_onset(rod: Rod, mu: float, *, timestep: float = Options().timestep, rounds: int = 5, n: int = 33, half_width: float = 1e-3) -> tuple[float, float]:
    """5b: smallest Psi at which MuJoCo lifts off at t = 0 from theta_L, Theta = 0, varphi = -pi/2.

    Bisection on grids of n values of Psi (``rounds`` times), starting from
    Psi_L +- ``half_width``.  Returns (onset, resolution): the first grid
    value that lifts off and the final grid spacing.

    Raises:
      ValueError: no single threshold in the bracket (LIFTOFF at the lower end,
        none at the upper end, or islands).
    """
    lo, hi = float(Psi_L) - half_width, float(Psi_L) + half_width
    for _ in range(rounds):
        Ps = np.linspace(lo, hi, n)
        states = [SlipState(theta=float(theta_L), varphi=-math.pi / 2, Theta=0.0, Psi=P, eta=1.0) for P in Ps]
        r = sweep(rod, states, mu, horizon=0.03, timestep=timestep, progress=False)
        lift = (r.outcome == Outcome.LIFTOFF) & (r.event_time == 0.0)
        k = int(np.argmax(lift))
        if lift[0] or not lift[-1] or not lift[k:].all():
            raise ValueError(f"no single lift-off threshold in Psi in [{lo}, {hi}] at mu = {mu}")
        lo, hi = Ps[k - 1], Ps[k]
    return float(hi), float(hi - lo)


#: mu < mu_P(3) = 4/3 of the 5d "no jam below mu_P" runs; see the module docstring for
#: which of them are asserted (p_min(mu) > P_EFF_JAM).
MUS_BELOW = (0.5, 1.0, 1.15, 1.3)


def _count_stat(quantity: str, got, tolerance, states: dict) -> ErrorStat:
    got = np.asarray(got, float)
    return error_stat(quantity, got, np.zeros_like(got), tolerance, states)


def validate(n_states: int, rng: np.random.Generator, *, progress: bool = False) -> ValidationResult:
    """Run the four checks of the module docstring; 5c on ``n_states`` random states."""
    if n_states < 1:
        raise ValueError(f"n_states must be >= 1; got {n_states}")
    rod = Rod.scaled(ALPHA)
    stats: list[ErrorStat] = []
    extra: dict = {"units": "scaled (m = l = g = 1, time 1/omega)", "alpha": ALPHA}

    # 5a
    ca = contact_acceleration(rod, min(n_states, 100), rng)
    where = {k: ca[k] for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi", "mu")}
    stats.append(error_stat("5a tip acc with contact", ca["got"] / ca["scale"][:, None], ca["want"] / ca["scale"][:, None],
                            tol.MUJOCO_CONTACT_ACCELERATION, where))

    # 5b
    onsets = [liftoff_onset(rod, m) for m in MUS_ONSET]
    stats.append(error_stat("5b lift-off onset Psi", [o for o, _ in onsets], [float(Psi_L)] * len(onsets), tol.MUJOCO_LIFTOFF_ONSET,
                            {"mu": np.array(MUS_ONSET), "resolution": np.array([r for _, r in onsets])}))

    # 5c
    points = random_event_points(n_states, rng)
    study = agreement_study(points, alpha=ALPHA, horizon=DEFAULT_HORIZON, rng=rng, boundary_directions=0, progress=progress)
    eff = next(r for r in study.runs if r.classifier == "effective")
    where_c = {"n_rated": np.array([eff.n_rated])}
    stats.append(error_stat("5c event disagreement", [1.0 - eff.agreement_jam_as_stop], [0.0], tol.MUJOCO_EVENT_DISAGREEMENT, where_c))
    stats.append(error_stat("5c median |event time diff|", [eff.median_abs_time_difference], [0.0], tol.MUJOCO_EVENT_TIME, where_c))
    extra["event_agreement"] = {
        "n_states": n_states,
        "horizon": DEFAULT_HORIZON,
        "analytic_outcomes": {o.name: int((study.analytic.outcome[study.index] == o).sum()) for o in Outcome},
        "runs": [{k: v for k, v in r.summary().items() if k not in ("time_difference", "time_difference_outcome", "by_distance")}
                 for r in study.runs],
        "convergence_row": convergence_table(study),
    }

    # 5d
    jc = jam_check(mus_below=MUS_BELOW, n_below=max(20, n_states // 5), n_above=max(30, n_states // 10), rng=rng, progress=progress)
    decidable = [row for row in jc.below if p_min(row["mu"], ALPHA) > P_EFF_JAM]
    stats.append(_count_stat("5d jams below mu_P", [row["effective"]["n_jam"] for row in decidable], tol.MUJOCO_NO_JAM_BELOW_MU_P,
                             {"mu": np.array([row["mu"] for row in decidable]), "n": np.array([row["n"] for row in decidable])}))
    # pooled over the mu values: the fraction is a binomial estimate, sd ~0.05 at 90 states
    n_above = sum(row["n"] for row in jc.above)
    ended = sum(row["n"] * row["effective"]["ended_near_fraction"] for row in jc.above)
    stats.append(error_stat("5d Cor. 4.2 slip not ended", [1.0 - ended / n_above], [0.0], tol.MUJOCO_COROLLARY_STOP, {"n": np.array([n_above])}))
    extra["jams"] = jc.to_dict()
    extra["jams"]["asserted_below"] = [row["mu"] for row in decidable]
    extra["jams"]["near_mu_P_not_asserted"] = {
        "why": f"p_min(mu) <= P_EFF_JAM = {P_EFF_JAM}: the JAM rule cannot tell a jam from a hard slip there",
        "rows": [{"mu": row["mu"], "p_min": float(p_min(row["mu"], ALPHA)), "n": row["n"], "effective_jams": row["effective"]["n_jam"]}
                 for row in jc.below if row not in decidable],
    }
    extra["tolerances"] = {k: v for k, v in tol.all_tolerances().items() if k.startswith("MUJOCO_")}
    return ValidationResult(engine="mujoco", stats=stats, extra=extra)
