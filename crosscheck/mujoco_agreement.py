"""Event agreement between the analytic slipping rod and MuJoCo (issue 4, items 5c and 5d).

The analytic side is ``crosscheck.slipping.slip_until_event``: the rigid rod
slips with F_z = -b/p (eq. FZ) until its first event (LIFTOFF: b -> 0 with
p > 0; JAM: p -> 0 with b < 0; STICK: eta -> 0; GB: b = p = 0).  The MuJoCo
side is a batched ``mujoco.rollout`` of part A's model (the same model,
start and records as ``crosscheck.mujoco_sweep.sweep``) classified twice: by
part A's ``crosscheck.mujoco_rod.classify`` and by ``classify_effective``,
whose JAM rule measures the force against MuJoCo's own friction direction.  This module lines the two up state by
state and summarises where they agree.

Censoring and lag.  The analytic run also stops, with outcome SLIP, when the state
leaves the paper's domain: varphi reaches 0 or -pi (about half of the states
of a grid do, the slip direction turning perpendicular to the rod) or theta
reaches 0 or pi/2.  Nothing is known analytically after that time, so each
state is compared only up to its *comparison time* T_i: the analytic event
time for an event, the domain-exit time for such a SLIP, the horizon
otherwise.  A MuJoCo event later than T_i counts as SLIP (still slipping when
the comparison ends); a DIVERGED run is never relabelled.  For an analytic
event the comparison extends by ``LAG_TAU`` contact time constants: the soft
contact builds its force over ~tau and STICK is read at eta = tau_f, so
MuJoCo meets a rigid event up to ~2 tau late.  States that do not
start slipping (b >= 0 or p <= 0 at t = 0) are not part of the study.

Horizon.  ``DEFAULT_HORIZON`` = 2 scaled time units (2/omega, 0.64 s for a
1 m rod).  On ``DEFAULT_GRID`` 99 % of the analytic first events happen
before t = 1.4 (median 0.19) and 98 % of all states are decided (event or
domain exit) before t = 2; a longer horizon adds MuJoCo steps to states
that have already left the comparison.  MuJoCo runs ``horizon + 2 W``
(W the classifier's window) so that an event near the horizon can still be
judged by the windowed criteria.

Stick threshold.  MuJoCo's soft friction lets a stuck contact creep at
v ~ a_t dmax tau_f / 2 (a_t the tangential acceleration friction has to
cancel, O(1) g; tau_f the friction time constant): measured 0.024, 0.008 and
0.002 for tau = 0.06, 0.02, 0.006 (0.4 tau).  Part A's default
``stick_speed`` 1e-2 is below the creep at the default tau = 0.06, so stuck
rods read as SLIP.  ``study_thresholds`` sets stick_speed = tau_f (2.5x the
measured creep), the default of this module; the event time is then early by
at most tau_f / |eta'|, |eta'| = O(mu F_z).

Boundary distance.  ``boundary_distance`` probes the analytic outcome with
random perturbations of the initial state (theta, varphi, Theta, Psi, eta;
scaled units) of growing size and returns the smallest size that changes it:
the distance to the analytic event boundary that the study bins disagreement
by.  Disagreement is also binned by the analytic comparison time in units of
the contact time constant (a soft contact needs ~tau to build up the rigid
force) and by |varphi0 + pi/2| (``friction_skew``: off the planar section
MuJoCo's friction is not anti-parallel to the slip).

All times, rates and forces are in the paper's scaled units (section 2.1).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from typing import NamedTuple

import mujoco
import numpy as np
from mujoco import rollout
from tqdm.auto import tqdm

from crosscheck.checks import ALPHA, ETA, FINITE, MU, POSITIVE, THETA, VARPHI, check
from crosscheck.critical import mu_P, theta_L
from crosscheck.mujoco_rod import (  # _window_sum: both classifiers use the same window sums
    Classification,
    Options,
    SensorLayout,
    Thresholds,
    build_model,
    classify,
    initial_state,
    n_steps,
    record_from_sensordata,
    _window_sum,
)
from crosscheck.mujoco_sweep import Batch
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.slipping import slip_until_event
from crosscheck.state import SlipState

__all__ = [
    "AXES",
    "DEFAULT_HORIZON",
    "LAG_TAU",
    "P_EFF_JAM",
    "BOUNDARY_RADII",
    "EventGrid",
    "DEFAULT_GRID",
    "SMALL_GRID",
    "AnalyticEvents",
    "analytic_events",
    "boundary_distance",
    "study_thresholds",
    "EffectiveClassification",
    "classify_effective",
    "classified_rollout",
    "mujoco_labels",
    "AgreementRun",
    "AgreementResult",
    "agreement_study",
    "convergence_table",
    "corollary_states",
    "JamCheck",
    "jam_check",
    "friction_skew",
]

#: Axes of an ``EventGrid``, in the order of its shape.
AXES = ("theta", "varphi", "Theta", "Psi", "mu", "eta")

#: Scaled horizon of the study (see the module docstring).
DEFAULT_HORIZON = 2.0

#: Perturbation sizes of ``boundary_distance`` (scaled units, Euclidean in
#: (theta, varphi, Theta, Psi, eta)).
BOUNDARY_RADII = (0.01, 0.03, 0.1, 0.3)

#: Outcomes an analytic run is compared on (GB and DIVERGED rows are counted, not rated).
_RATED = (Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM)
_EVENTS = (Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM)
_NAMES = [o.name for o in Outcome]


def _floats(name: str, values, interval) -> tuple[float, ...]:
    arr = np.atleast_1d(check(name, values, interval)).astype(float)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D sequence of numbers in {interval}; got {values!r}")
    return tuple(float(x) for x in arr)


@dataclass(frozen=True)
class EventGrid:
    """A product grid of initial slipping states and friction coefficients (scaled units).

    Every combination of the axes is one state; ``points()`` lists them in C
    order of ``AXES`` (theta slowest, eta fastest).  psi = 0 (cyclic).

    Attributes: one non-empty tuple per axis of ``AXES``: theta in (0, pi/2),
    varphi in (-pi, 0], Theta and Psi finite, mu >= 0, eta >= 0.
    """

    theta: tuple
    varphi: tuple
    Theta: tuple
    Psi: tuple
    mu: tuple
    eta: tuple = (1.0,)

    def __post_init__(self) -> None:
        intervals = {"theta": THETA, "varphi": VARPHI, "Theta": FINITE, "Psi": FINITE, "mu": MU, "eta": ETA}
        for name in AXES:
            object.__setattr__(self, name, _floats(name, getattr(self, name), intervals[name]))

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(getattr(self, a)) for a in AXES)

    def __len__(self) -> int:
        return int(np.prod(self.shape))

    def points(self) -> dict[str, np.ndarray]:
        """(N,) arrays, one per axis, N = len(grid), C order of ``AXES``."""
        mesh = np.meshgrid(*(np.array(getattr(self, a)) for a in AXES), indexing="ij")
        return {a: m.ravel() for a, m in zip(AXES, mesh)}

    def as_dict(self) -> dict[str, list[float]]:
        return {a: list(getattr(self, a)) for a in AXES}


#: The report's grid: 5616 states, of which ~2400 start slipping (b < 0 < p).
#: Psi over both signs with varphi on one side of -pi/2 covers all
#: directions: (varphi, Psi) -> (-pi - varphi, -Psi) maps analytic runs onto
#: each other (mirror in the rod's vertical plane; checked to 1e-11 in time).
#: mu from well below mu_P(3) = 4/3 to 6 (the paper's 1.4, 1.7, 6 included).
DEFAULT_GRID = EventGrid(
    theta=(0.3, float(theta_L), 0.9, 1.2),
    varphi=(-math.pi / 2, -3 * math.pi / 8, -math.pi / 4, -math.pi / 8),
    Theta=(-0.5, 0.0, 0.5),
    Psi=tuple(np.linspace(-3.0, 3.0, 13)),
    mu=(0.3, 0.6, 1.0, 1.3, 1.4, 1.7, 2.5, 4.0, 6.0),
)

#: A grid for tests: 2 x 2 x 1 x 4 x 3 = 48 states.
SMALL_GRID = EventGrid(theta=(0.3, 0.9), varphi=(-math.pi / 2, -math.pi / 4), Theta=(0.0,), Psi=(-1.5, -0.5, 0.5, 1.5), mu=(0.6, 1.4, 4.0))


# --------------------------------------------------------------------------
# Analytic side
# --------------------------------------------------------------------------


def _bp(points: dict, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    th, vp, Th, Ps, mu = (points[k] for k in ("theta", "varphi", "Theta", "Psi", "mu"))
    s, c = np.sin(th), np.cos(th)
    b = (Ps**2 * c**2 + Th**2) * s - 1.0  # eq. b
    p = 1.0 + alpha + alpha * s * (mu * c * np.sin(vp) - s)  # eq. p
    return b, p


def _states(points: dict, idx) -> list[SlipState]:
    return [SlipState(theta=points["theta"][i], varphi=points["varphi"][i], Theta=points["Theta"][i], Psi=points["Psi"][i], eta=points["eta"][i]) for i in idx]


@dataclass(frozen=True, eq=False)
class AnalyticEvents:
    """First events of the analytic slipping rod at N points (each field (N,)).

    outcome: int8 ``Outcome``; time: event (or stop) time; reason: the rule of
    ``slip_until_event`` that ended the run ("b=0", "p=0", "eta=0", "gb",
    "t_max", "varphi=0", "varphi=-pi", "theta=0", "theta=pi/2", "start", ...);
    b0, p0: eqs. b and p at the start; slipping: b0 < 0 < p0 (the studied
    states); until: comparison time T_i (module docstring).
    """

    outcome: np.ndarray
    time: np.ndarray
    reason: np.ndarray
    b0: np.ndarray
    p0: np.ndarray
    slipping: np.ndarray
    until: np.ndarray


def analytic_events(points: dict, *, alpha: float, horizon: float, progress: bool = False) -> AnalyticEvents:
    """``slip_until_event`` (t_max = horizon) at every point of ``points`` (dict of (N,) arrays, keys ``AXES``)."""
    alpha = float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, POSITIVE))
    n = len(points["theta"])
    b0, p0 = _bp(points, alpha)
    outcome = np.empty(n, np.int8)
    t = np.empty(n)
    reason = np.empty(n, dtype=object)
    for i in tqdm(range(n), desc="analytic", unit="state", disable=not progress):
        s = _states(points, [i])[0]
        r = slip_until_event(s, points["mu"][i], alpha, t_max=horizon)
        outcome[i], t[i], reason[i] = int(r.outcome), r.time, r.reason
    until = np.where(outcome == Outcome.SLIP, np.minimum(t, horizon), np.where(np.isin(outcome, _EVENTS), t, horizon))
    return AnalyticEvents(outcome, t, reason.astype(str), b0, p0, (b0 < 0) & (p0 > 0), until)


def _perturbed(points: dict, i: int, delta: np.ndarray) -> SlipState:
    """Point i moved by delta in (theta, varphi, Theta, Psi, eta), clipped into the paper's ranges."""
    lo = 1e-3
    return SlipState(
        theta=float(np.clip(points["theta"][i] + delta[0], lo, math.pi / 2 - lo)),
        varphi=float(np.clip(points["varphi"][i] + delta[1], -math.pi + lo, 0.0)),
        Theta=points["Theta"][i] + delta[2],
        Psi=points["Psi"][i] + delta[3],
        eta=float(max(points["eta"][i] + delta[4], lo)),
    )


def boundary_distance(points: dict, outcome: np.ndarray, *, alpha: float, horizon: float, rng: np.random.Generator,
                      radii: Sequence[float] = BOUNDARY_RADII, directions: int = 6, mask: np.ndarray | None = None,
                      progress: bool = False) -> np.ndarray:
    """Distance of each point to the analytic event boundary, probed by perturbation.

    For r in ``radii`` (increasing), ``directions`` random unit vectors u in
    the 5-D space (theta, varphi, Theta, Psi, eta) are drawn and the analytic
    first event of the state moved by r u is computed (mu unchanged); the
    distance is the first r at which some probe's outcome differs from
    ``outcome`` (the unperturbed one), +inf if none does up to the largest r.
    Outcomes compared are the ``Outcome`` labels (a SLIP that leaves the
    domain equals one that reaches the horizon).

    Args:
      points: dict of (N,) arrays, keys ``AXES``.
      outcome: (N,) analytic outcomes of the points.
      alpha, horizon: as ``analytic_events``.
      rng: seeded generator of the probe directions.
      radii, directions: probe sizes and count per size.
      mask: (N,) points to probe (others get NaN); default all.

    Returns:
      (N,) distances (scaled units): one of ``radii``, inf or NaN.
    """
    radii = _floats("radii", radii, POSITIVE)
    n = len(points["theta"])
    mask = np.ones(n, bool) if mask is None else np.asarray(mask, bool)
    out = np.full(n, np.nan)
    for i in tqdm(np.flatnonzero(mask), desc="boundary distance", unit="state", disable=not progress):
        out[i] = math.inf
        for r in sorted(radii):
            u = rng.normal(size=(directions, 5))
            u /= np.linalg.norm(u, axis=1, keepdims=True)
            if any(slip_until_event(_perturbed(points, i, r * d), points["mu"][i], alpha, t_max=horizon).outcome != outcome[i] for d in u):
                out[i] = r
                break
    return out


# --------------------------------------------------------------------------
# MuJoCo side
# --------------------------------------------------------------------------


def study_thresholds(options: Options, base: Thresholds | None = None) -> Thresholds:
    """Part A's criteria with stick_speed = the friction time constant (creep; module docstring)."""
    base = base or Thresholds()
    tau_f = options.friction_timeconst if options.friction_timeconst is not None else options.timeconst
    return replace(base, stick_speed=max(base.stick_speed, tau_f))


class EffectiveClassification(NamedTuple):
    """What ``classify_effective`` returns; each field has the batch shape (B,).

    outcome, event_time, event_row: the first event with the p_eff JAM
      criterion (int8 ``Outcome``, scaled time, row; NaN / -1 for SLIP).
    jam_p_eff: window p_eff at the JAM row (NaN if not JAM).
    part_a: part A's ``Classification`` of the same rows (its own JAM rule).
    """

    outcome: np.ndarray
    event_time: np.ndarray
    event_row: np.ndarray
    jam_p_eff: np.ndarray
    part_a: Classification


#: JAM needs MuJoCo's own p_eff (force-weighted over the window) at or below
#: this: 5 % of the range 1 + alpha = 4 of eq. p for the uniform rod, i.e. the
#: slipping force -b/p_eff is already >= 5 |b| m g.  Measured: the jams of
#: Corollary 4.2 states that MuJoCo reproduces have p_eff 0.088-0.093; landings
#: of a hopping (chattering) tip at mu = 1.3 < mu_P that pass the force and
#: slip-loss tests have p_eff 0.45.
P_EFF_JAM = 0.2


def classify_effective(sensordata: np.ndarray, layout: SensorLayout, *, rod: Rod, mu, radius: float, timestep: float,
                       thresholds: Thresholds | None = None, p_jam: float = P_EFF_JAM) -> EffectiveClassification:
    """Part A's classifier with a JAM rule that measures the force against MuJoCo's own friction.

    MuJoCo's friction is not anti-parallel to the slip off the planar
    section (``friction_skew``), so while it slips its window-mean normal
    force is -b/p_eff, not -b/p: p_eff is the vertical tip acceleration per
    unit normal force with MuJoCo's actual force (eq. linode2),

        p_eff = 1 + alpha - alpha sin^2 theta - alpha sin theta cos theta (F_t . e) / F_z,

    e = (-sin psi, cos psi), equal to eq. p when F_t = -mu F_z u/|u|.  Part A's
    rule compares with -b/p and fires on that slipping force at high mu eta
    (window means 3-7x -b/p, 1.0-1.6x -b/p_eff, MuJoCo's own p 0.5-2.8).  Here
    JAM needs, in a window of W rows (``Thresholds.window_rows``):

      mean F_z >= jam_force, mean F_z >= jam_ratio * mean max(0, -b) / p_eff_W
      (p_eff_W the force-weighted window mean of p_eff; taken as 0 when
      p_eff_W <= 0: slipping with MuJoCo's friction cannot hold the tip
      there; b clipped per row, as part A clips -b/p per row, so rows after a
      lift-off inside the window (b > 0) do not cancel the slipping force
      needed before it), a slip-speed loss >= jam_slip_loss within the window, and
      p_eff_W <= ``p_jam`` (``P_EFF_JAM``): MuJoCo's rod is at its own p = 0,
      where the theory's jam happens (landings of a hopping tip are not),

    before theta leaves (0, pi/2) and before any other event of part A's
    classifier run without its JAM rule (same window, thresholds and
    precedence otherwise).  Below mu_P no friction direction makes p_eff
    vanish (p_eff >= min over varphi of eq. p > 0), so this rule cannot mistake
    a mere direction change for a jam.

    Args: as ``crosscheck.mujoco_rod.classify`` (sensordata (..., N, nsensordata)).
    """
    th = thresholds or Thresholds()
    part_a = classify(sensordata, layout, rod=rod, mu=mu, radius=radius, timestep=timestep, thresholds=th)
    nojam = classify(sensordata, layout, rod=rod, mu=mu, radius=radius, timestep=timestep, thresholds=replace(th, jam_force=math.inf))
    sd = np.asarray(sensordata, dtype=float)
    n = sd.shape[-2]
    w = th.window_rows(timestep)
    alpha = rod.alpha
    fc = np.moveaxis(sd[..., layout.force], -1, 0)
    normal = np.moveaxis(sd[..., layout.normal], -1, 0)
    tangent = np.moveaxis(sd[..., layout.tangent], -1, 0)
    bitangent = np.stack([normal[1] * tangent[2] - normal[2] * tangent[1], normal[2] * tangent[0] - normal[0] * tangent[2],
                          normal[0] * tangent[1] - normal[1] * tangent[0]])
    F = (fc[0] * normal + fc[1] * tangent + fc[2] * bitangent) / rod.force_scale  # (3, ..., N) world, m g
    psi, theta = sd[..., layout.psi], sd[..., layout.theta]
    Psi, Theta = sd[..., layout.psi_dot] / rod.omega, sd[..., layout.theta_dot] / rod.omega
    lw = rod.length * rod.omega
    ux = sd[..., layout.tip_vel.start] / lw - radius * Theta * np.sin(psi)
    uy = sd[..., layout.tip_vel.start + 1] / lw + radius * Theta * np.cos(psi)
    eta = np.hypot(ux, uy)
    st, ct = np.sin(theta), np.cos(theta)
    Fz = np.where(F[2] > 0, F[2], 0.0)
    Fe = np.where(F[2] > 0, -np.sin(psi) * F[0] + np.cos(psi) * F[1], 0.0)
    b = (Psi * Psi * ct * ct + Theta * Theta) * st - 1.0
    with np.errstate(invalid="ignore", divide="ignore"):
        sF = _window_sum(Fz, w)
        p_eff = (_window_sum(Fz * (1 + alpha - alpha * st * st), w) - alpha * _window_sum(st * ct * Fe, w)) / sF
        Fbar = sF / w
        # -b clipped per row: a window mean of b itself is pulled to 0 by the b > 0 rows of a lift-off
        # later in the window, and then the rigid force of a slip at small p_eff (15-20 m g at mu = 1.3,
        # p_eff ~0.05) passed for 3x the rigid force (below mu_P: tests NEAR_JAM_SLIP_BELOW_MU_P).
        rigid = np.where(p_eff > 0, _window_sum(np.maximum(0.0, -b), w) / w / p_eff, 0.0)
        eta_end = np.full(eta.shape, np.nan)
        eta_end[..., : n - w + 1] = eta[..., w - 1 :]
        jam = (Fbar >= th.jam_force) & (Fbar >= th.jam_ratio * rigid) & (eta - eta_end >= th.jam_slip_loss * eta) & (p_eff <= p_jam)
    rows = np.arange(n)
    outside = ~((theta > 0.0) & (theta < math.pi / 2))
    exit_row = np.where(outside.any(axis=-1), outside.argmax(axis=-1), n)
    # The window must end before the domain exit (as in part A's rule) and start no later than
    # the other event's row: part A's precedence DIVERGED > JAM > LIFTOFF > STICK on ties.
    last_start = np.full(np.shape(exit_row), n, dtype=np.int64)
    ev = np.isin(nojam.outcome, (Outcome.STICK, Outcome.LIFTOFF))
    last_start = np.where(ev, nojam.event_row, last_start)
    last_start = np.where(nojam.outcome == Outcome.DIVERGED, nojam.event_row - 1, last_start)
    ok = jam & (rows + w <= np.asarray(exit_row)[..., None]) & (rows <= np.asarray(last_start)[..., None])
    has = ok.any(axis=-1)
    k = np.where(has, ok.argmax(axis=-1), -1)
    t = sd[..., layout.clock] * rod.omega
    t_jam = np.where(has, np.take_along_axis(t, np.maximum(k, 0)[..., None], axis=-1)[..., 0], np.nan)
    pj = np.where(has, np.take_along_axis(p_eff, np.maximum(k, 0)[..., None], axis=-1)[..., 0], np.nan)
    outcome = np.where(has, np.int8(Outcome.JAM), nojam.outcome).astype(np.int8)
    return EffectiveClassification(
        outcome=outcome,
        event_time=np.where(has, t_jam, nojam.event_time),
        event_row=np.where(has, k, nojam.event_row),
        jam_p_eff=pj,
        part_a=part_a,
    )


def _p_at(sd_rows: np.ndarray, layout: SensorLayout, rod: Rod, radius: float, mu: np.ndarray) -> np.ndarray:
    """Eq. p on MuJoCo's state of one row per run, sd_rows (B, nsensordata)."""
    R = record_from_sensordata(sd_rows[:, None, :], layout, rod, radius)
    th, vp = R.theta[:, 0], R.varphi[:, 0]
    with np.errstate(invalid="ignore"):
        return 1 + rod.alpha + rod.alpha * np.sin(th) * (mu * np.cos(th) * np.sin(vp) - np.sin(th))


def classified_rollout(rod: Rod, states: Sequence[SlipState], mu, *, horizon: float, thresholds: Thresholds | None = None,
                       nthread: int = 2, progress: bool = False, **options) -> dict[str, np.ndarray]:
    """Run states through ``mujoco_sweep.Batch`` (as ``sweep`` does) and classify each twice.

    Returns a dict of (B,) arrays: ``outcome_a``, ``time_a``, ``p_a`` (part
    A's ``classify``: outcome, event time, eq. p on MuJoCo's state at the
    event row or the last row), ``outcome_e``, ``time_e``, ``p_eff_e``
    (``classify_effective``), and the scalars ``wall_time`` [s] and
    ``steps_per_second``.  Same model, start and records as ``sweep``, so
    ``outcome_a`` equals ``sweep(...).outcome``.
    """
    opts = Options.from_kwargs(options)
    th = thresholds or Thresholds()
    t0 = time.perf_counter()
    batch = Batch.build(rod, states, mu, horizon=horizon, options=opts, nthread=nthread)
    B, mu, layout, nstep = len(batch.mu), batch.mu, batch.layout, batch.nstep
    out = {k: np.empty(B) for k in ("time_a", "p_a", "time_e", "p_eff_e")}
    out["outcome_a"] = np.empty(B, np.int8)
    out["outcome_e"] = np.empty(B, np.int8)
    for sl, sd in batch.chunks(progress=progress, desc="mujoco"):
        c = classify_effective(sd, layout, rod=rod, mu=mu[sl], radius=opts.radius, timestep=opts.timestep, thresholds=th)
        out["outcome_a"][sl], out["time_a"][sl] = c.part_a.outcome, c.part_a.event_time
        row = np.where(c.part_a.event_row >= 0, c.part_a.event_row, nstep - 1)
        out["p_a"][sl] = _p_at(sd[np.arange(sd.shape[0]), row], layout, rod, opts.radius, mu[sl])
        out["outcome_e"][sl], out["time_e"][sl], out["p_eff_e"][sl] = c.outcome, c.event_time, c.jam_p_eff
    wall = time.perf_counter() - t0
    out["wall_time"] = wall
    out["steps_per_second"] = B * nstep / wall
    return out


def mujoco_labels(outcome: np.ndarray, event_time: np.ndarray, until: np.ndarray) -> np.ndarray:
    """MuJoCo's outcome as compared: an event after the comparison time ``until`` counts as SLIP.

    DIVERGED is kept whatever its time (a diverged run is never relabelled).
    """
    outcome = np.asarray(outcome)
    keep = (outcome == Outcome.DIVERGED) | (np.asarray(event_time) <= np.asarray(until))
    return np.where(keep, outcome, np.int8(Outcome.SLIP)).astype(np.int8)


def _confusion(a: np.ndarray, m: np.ndarray) -> np.ndarray:
    c = np.zeros((len(Outcome), len(Outcome)), dtype=int)
    np.add.at(c, (np.asarray(a, int), np.asarray(m, int)), 1)
    return c


def _binned(values: np.ndarray, agree: np.ndarray, edges: Sequence[float], name: str) -> list[dict]:
    rows = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (values >= lo) & ((values < hi) | (math.isinf(hi) & np.isinf(values)))
        rows.append({name: [float(lo), float(hi)], "n": int(sel.sum()), "agreement": float(agree[sel].mean()) if sel.any() else math.nan})
    return rows


#: MuJoCo may meet an analytic event up to LAG_TAU contact time constants late (see ``_rate``).
LAG_TAU = 2.0

#: Bin edges of the disagreement tables.
DISTANCE_EDGES = (0.0, 0.02, 0.05, 0.2, 1.0, math.inf)
TIME_EDGES_TAU = (0.0, 1.0, 3.0, 10.0, math.inf)
OFFPLANE_EDGES = (0.0, 0.05, 0.5, 1.0, 1.6)


@dataclass(frozen=True, eq=False)
class AgreementRun:
    """MuJoCo against the analytic first events at one (timestep, timeconst).

    classifier: "part_a" (``crosscheck.mujoco_rod.classify``) or "effective"
      (``classify_effective``: JAM judged against MuJoCo's own friction).
    Per-state fields are over the M studied states (``AgreementResult.index``):
      outcome, event_time: MuJoCo's raw classification (int8, scaled time).
      label: MuJoCo's outcome as compared (``mujoco_labels``).
      p_event: "part_a": eq. p on MuJoCo's own state at the event row (last
        row for SLIP); "effective": window p_eff at a JAM (NaN otherwise).
    Summaries:
      confusion: (6, 6) counts, rows analytic outcome, columns MuJoCo label,
        both indexed by ``Outcome`` values (``labels`` = their names).
      n_rated, agreement: states with analytic outcome SLIP/LIFTOFF/STICK/JAM
        and the fraction of them whose MuJoCo label is the same.
      agreement_jam_as_stop: the same, counting an analytic JAM met by a
        MuJoCo STICK as agreement (the slip ends where the theory jams; the
        soft contact stops the tip instead of delivering an impulse).
      time_difference: t_MuJoCo - t_analytic for every rated state where both
        report the same event, with ``time_difference_outcome`` its outcome.
      median_abs_time_difference: median |time_difference| (NaN if none).
      by_distance / by_time / by_offplane: agreement in bins of
        ``boundary_distance``, of the comparison time / timeconst, and of
        |varphi0 + pi/2| (lists of {bin, n, agreement}).
      options, thresholds: the MuJoCo options and criteria used (dicts).
      wall_time [s], steps_per_second: of the sweep.
    """

    classifier: str
    timestep: float
    timeconst: float
    outcome: np.ndarray = field(repr=False)
    event_time: np.ndarray = field(repr=False)
    label: np.ndarray = field(repr=False)
    p_event: np.ndarray = field(repr=False)
    confusion: np.ndarray
    n_rated: int
    agreement: float
    agreement_jam_as_stop: float
    time_difference: np.ndarray = field(repr=False)
    time_difference_outcome: np.ndarray = field(repr=False)
    median_abs_time_difference: float
    by_distance: list = field(repr=False)
    by_time: list = field(repr=False)
    by_offplane: list = field(repr=False)
    options: dict = field(repr=False)
    thresholds: dict = field(repr=False)
    wall_time: float
    steps_per_second: float

    labels = tuple(_NAMES)

    def summary(self) -> dict:
        """JSON-able summary (no per-state arrays except the time differences)."""
        td = self.time_difference
        pct = {str(q): float(np.percentile(td, q)) for q in (5, 25, 50, 75, 95)} if td.size else {}
        per_outcome = {}
        for o in _EVENTS:
            sel = self.time_difference_outcome == o
            per_outcome[o.name] = {"n": int(sel.sum()), "median": float(np.median(td[sel])) if sel.any() else math.nan,
                                   "median_abs": float(np.median(np.abs(td[sel]))) if sel.any() else math.nan}
        return {
            "classifier": self.classifier,
            "timestep": self.timestep,
            "timeconst": self.timeconst,
            "labels": list(self.labels),
            "confusion": self.confusion.tolist(),
            "n_rated": self.n_rated,
            "agreement": self.agreement,
            "agreement_jam_as_stop": self.agreement_jam_as_stop,
            "median_abs_time_difference": self.median_abs_time_difference,
            "time_difference_percentiles": pct,
            "time_difference_by_outcome": per_outcome,
            "time_difference": td.tolist(),
            "time_difference_outcome": [_NAMES[int(o)] for o in self.time_difference_outcome],
            "jam_p_event": _quantiles(self.p_event[self.outcome == Outcome.JAM]),
            "by_distance": self.by_distance,
            "by_time_over_timeconst": self.by_time,
            "by_offplane": self.by_offplane,
            "options": self.options,
            "thresholds": self.thresholds,
            "wall_time": self.wall_time,
            "steps_per_second": self.steps_per_second,
        }


def _quantiles(x: np.ndarray) -> dict:
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    if not x.size:
        return {"n": 0}
    return {"n": int(x.size), "min": float(x.min()), "median": float(np.median(x)), "max": float(x.max())}


def _json(x):
    """Standard JSON values: numpy -> python, non-finite floats -> None."""
    if isinstance(x, dict):
        return {str(k): _json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_json(v) for v in x]
    if isinstance(x, np.ndarray):
        return _json(x.tolist())
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, (np.integer, np.bool_)):
        return x.item()
    return x


@dataclass(frozen=True, eq=False)
class AgreementResult:
    """Everything ``agreement_study`` measured; ``to_json()`` for the report.

    Attributes:
      grid: the ``EventGrid`` (None when points were given directly).
      alpha, horizon: the rod's alpha and the scaled comparison horizon.
      points: dict of (N,) arrays, every grid point (keys ``AXES``).
      analytic: ``AnalyticEvents`` of all N points.
      index: (M,) indices of the studied points (slipping at t = 0).
      distance: (M,) ``boundary_distance`` of the studied points.
      runs: two ``AgreementRun`` per (timestep, timeconst), classifiers
        "part_a" and "effective", in that order.
    """

    grid: EventGrid | None
    alpha: float
    horizon: float
    points: dict = field(repr=False)
    analytic: AnalyticEvents = field(repr=False)
    index: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)
    runs: list = field(default_factory=list)

    def to_dict(self) -> dict:
        a = self.analytic
        rated = np.isin(a.outcome[self.index], _RATED)
        counts = {o.name: int((a.outcome[self.index] == o).sum()) for o in Outcome}
        reasons = {r: int((a.reason[self.index] == r).sum()) for r in np.unique(a.reason[self.index])}
        return _json({
            "grid": self.grid.as_dict() if self.grid is not None else None,
            "alpha": self.alpha,
            "horizon": self.horizon,
            "n_points": len(a.outcome),
            "n_slipping": int(self.index.size),
            "n_rated": int(rated.sum()),
            "analytic_outcomes": counts,
            "analytic_reasons": reasons,
            "boundary_radii": list(BOUNDARY_RADII),
            "runs": [r.summary() for r in self.runs],
            "convergence_table": convergence_table(self),
        })

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2, allow_nan=False)


def _rate(*, classifier: str, opts: Options, th: Thresholds, outcome, event_time, p_event, a: AnalyticEvents, idx, distance,
          offplane, wall_time: float, steps_per_second: float) -> AgreementRun:
    until = a.until[idx]
    # A soft contact answers the rigid force with a lag ~ tau (its force builds up over tau; STICK is
    # read at eta = tau_f): an analytic event may be met up to LAG_TAU tau later.  Censored SLIPs get no
    # lag: nothing is known analytically after the domain exit.
    lag = np.where(np.isin(a.outcome[idx], _EVENTS), LAG_TAU * opts.timeconst, 0.0)
    label = mujoco_labels(outcome, event_time, until + lag)
    ao = a.outcome[idx]
    rated = np.isin(ao, _RATED)
    agree = label == ao
    same_event = rated & agree & np.isin(ao, _EVENTS)
    td = event_time[same_event] - a.time[idx][same_event]
    stop = agree | ((ao == Outcome.JAM) & (label == Outcome.STICK))
    return AgreementRun(
        classifier=classifier,
        timestep=opts.timestep,
        timeconst=opts.timeconst,
        outcome=outcome,
        event_time=event_time,
        label=label,
        p_event=p_event,
        confusion=_confusion(ao, label),
        n_rated=int(rated.sum()),
        agreement=float(agree[rated].mean()) if rated.any() else math.nan,
        agreement_jam_as_stop=float(stop[rated].mean()) if rated.any() else math.nan,
        time_difference=td,
        time_difference_outcome=ao[same_event],
        median_abs_time_difference=float(np.median(np.abs(td))) if td.size else math.nan,
        by_distance=_binned(distance[rated], agree[rated], DISTANCE_EDGES, "distance"),
        by_time=_binned(until[rated] / opts.timeconst, agree[rated], TIME_EDGES_TAU, "time_over_timeconst"),
        by_offplane=_binned(offplane[rated], agree[rated], OFFPLANE_EDGES, "offplane"),
        options={f.name: getattr(opts, f.name) for f in fields(Options)},
        thresholds={f.name: getattr(th, f.name) for f in fields(Thresholds)},
        wall_time=wall_time,
        steps_per_second=steps_per_second,
    )


def _runs(base: dict, *, rod: Rod, timestep: float, timeconst: float, thresholds: Thresholds | None, progress: bool,
          nthread: int, options: dict) -> list[AgreementRun]:
    """Both classifiers' ``AgreementRun`` at one (timestep, timeconst), from one batched rollout."""
    points, a, idx, distance, horizon = (base[k] for k in ("points", "analytic", "index", "distance", "horizon"))
    opts = Options.from_kwargs({**options, "timestep": timestep, "timeconst": timeconst})
    th = thresholds if thresholds is not None else study_thresholds(opts)
    margin = 2.0 * th.window_rows(opts.timestep) * opts.timestep
    r = classified_rollout(rod, _states(points, idx), points["mu"][idx], horizon=horizon + margin, thresholds=th, nthread=nthread,
                           progress=progress, **{f.name: getattr(opts, f.name) for f in fields(Options)})
    common = dict(opts=opts, th=th, a=a, idx=idx, distance=distance, offplane=np.abs(points["varphi"][idx] + math.pi / 2),
                  wall_time=r["wall_time"], steps_per_second=r["steps_per_second"])
    return [
        _rate(classifier="part_a", outcome=r["outcome_a"], event_time=r["time_a"], p_event=r["p_a"], **common),
        _rate(classifier="effective", outcome=r["outcome_e"], event_time=r["time_e"], p_event=r["p_eff_e"], **common),
    ]


def agreement_study(grid: EventGrid | dict, *, timesteps: Sequence[float] = (3e-4,), timeconsts: Sequence[float] = (0.06,),
                    alpha: float = 3.0, horizon: float = DEFAULT_HORIZON, rng: np.random.Generator | None = None,
                    thresholds: Thresholds | None = None, boundary_radii: Sequence[float] = BOUNDARY_RADII,
                    boundary_directions: int = 6, nthread: int = 2, progress: bool = False, **options) -> AgreementResult:
    """Event agreement, analytic vs MuJoCo, over ``grid`` at several (timestep, timeconst).

    Args:
      grid: the initial states and friction coefficients: an ``EventGrid``
        or a dict of (N,) arrays with the keys ``AXES`` (e.g. random states).
      timesteps, timeconsts: equal-length sequences; run i uses
        (timesteps[i], timeconsts[i]) (scaled omega dt, omega tau).
      alpha: m l^2 / I0 of the rod (``Rod.scaled(alpha)``).
      horizon: scaled comparison horizon (``DEFAULT_HORIZON``).
      rng: generator of ``boundary_distance``'s probes (default seed 0).
      thresholds: MuJoCo outcome criteria; None uses ``study_thresholds``
        (part A's with stick_speed = the friction time constant).
      boundary_radii, boundary_directions: as ``boundary_distance``;
        boundary_directions = 0 skips the probing (distances NaN).
      nthread: MuJoCo rollout threads.
      progress: tqdm bars.
      **options: further MuJoCo ``Options`` (radius, friction_timeconst, ...).

    Returns:
      ``AgreementResult``.
    """
    timesteps = _floats("timesteps", timesteps, POSITIVE)
    timeconsts = _floats("timeconsts", timeconsts, POSITIVE)
    if len(timesteps) != len(timeconsts):
        raise ValueError(f"timesteps and timeconsts must have the same length; got {len(timesteps)} and {len(timeconsts)}")
    for key in ("timestep", "timeconst"):
        if key in options:
            raise ValueError(f"give {key} through {key}s, not as an option")
    Options.from_kwargs(options)  # unknown option -> ValueError before any work
    alpha = float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, POSITIVE))
    rng = rng if rng is not None else np.random.default_rng(0)
    if isinstance(grid, EventGrid):
        points = grid.points()
    else:
        missing = [k for k in AXES if k not in grid]
        if missing:
            raise ValueError(f"points lack the keys {missing}; need {list(AXES)}")
        points = {k: np.asarray(grid[k], dtype=float).ravel() for k in AXES}
        if len({v.size for v in points.values()}) != 1:
            raise ValueError("points must be (N,) arrays of one length N")
        grid = None
    a = analytic_events(points, alpha=alpha, horizon=horizon, progress=progress)
    idx = np.flatnonzero(a.slipping)
    if idx.size == 0:
        raise ValueError("the grid has no slipping state (b < 0 < p at t = 0)")
    mask = np.zeros(len(a.outcome), bool)
    mask[idx] = True
    if boundary_directions > 0:
        dist = boundary_distance(points, a.outcome, alpha=alpha, horizon=horizon, rng=rng, radii=boundary_radii,
                                 directions=boundary_directions, mask=mask, progress=progress)[idx]
    else:
        dist = np.full(idx.size, np.nan)
    base = {"points": points, "analytic": a, "index": idx, "distance": dist, "horizon": horizon}
    rod = Rod.scaled(alpha)
    runs = [run for dt, tc in zip(timesteps, timeconsts)
            for run in _runs(base, rod=rod, timestep=dt, timeconst=tc, thresholds=thresholds, progress=progress, nthread=nthread, options=options)]
    return AgreementResult(grid=grid, alpha=alpha, horizon=horizon, points=points, analytic=a, index=idx, distance=dist, runs=runs)


def convergence_table(result: AgreementResult) -> list[dict]:
    """One row per run: classifier, timestep, timeconst, n_rated, agreement, median |t_MuJoCo - t_analytic|, planar/3-D split.

    ``planar`` rows are the studied states starting on the planar section
    varphi = -pi/2 with Psi = 0 (they stay on it); ``off_plane`` the rest.
    """
    idx = result.index
    a = result.analytic
    ao = a.outcome[idx]
    rated = np.isin(ao, _RATED)
    planar = (np.abs(result.points["varphi"][idx] + math.pi / 2) < 1e-12) & (result.points["Psi"][idx] == 0.0)
    rows = []
    for r in result.runs:
        agree = r.label == ao
        row = {
            "classifier": r.classifier,
            "timestep": r.timestep,
            "timeconst": r.timeconst,
            "n_rated": r.n_rated,
            "agreement": r.agreement,
            "agreement_jam_as_stop": r.agreement_jam_as_stop,
            "median_abs_time_difference": r.median_abs_time_difference,
            "steps_per_second": r.steps_per_second,
        }
        for name, sel in (("planar", planar), ("off_plane", ~planar)):
            s = rated & sel
            row[f"n_{name}"] = int(s.sum())
            row[f"agreement_{name}"] = float(agree[s].mean()) if s.any() else math.nan
        rows.append(row)
    return rows


# --------------------------------------------------------------------------
# 5d: no jam below mu_P; Corollary 4.2 jams above
# --------------------------------------------------------------------------


def _backward_from(x_event: np.ndarray, mu: float, alpha: float, t_back: float):
    """Integrate the slipping flow (eq. f, with dt/ds = eta p) backwards from ``x_event`` for real time ``t_back``.

    Returns the state (eta, varphi, psi, Psi, theta, Theta) at t = -t_back, or
    None when the backward run meets b = 0, eta -> 0 or a domain boundary
    first (then the forward run would not slip all the way to the event).
    """
    from scipy.integrate import solve_ivp

    from crosscheck.slipping import slip_rhs

    def rhs(_, y):
        eta, varphi, theta = y[0], y[1], y[4]
        st, ct = math.sin(theta), math.cos(theta)
        p = 1.0 + alpha + alpha * st * (mu * ct * math.sin(varphi) - st)
        return np.append(-slip_rhs(y[:6], mu, alpha), eta * p)  # s reversed; y[6] = real time run backwards

    def event(fn):
        fn.terminal = True
        return fn

    def b_of(y):
        st, ct = math.sin(y[4]), math.cos(y[4])
        return (y[3] ** 2 * ct * ct + y[5] ** 2) * st - 1.0

    events = [event(lambda s, y: y[6] - t_back), event(lambda s, y: b_of(y)), event(lambda s, y: y[0] - 1e-3),
              event(lambda s, y: y[1]), event(lambda s, y: y[1] + math.pi), event(lambda s, y: y[4] - 1e-3),
              event(lambda s, y: math.pi / 2 - 1e-3 - y[4])]
    sol = solve_ivp(rhs, (0.0, 1e4), np.append(x_event, 0.0), method="DOP853", rtol=1e-10, atol=1e-12, events=events)
    if sol.status != 1 or not len(sol.t_events[0]) or any(len(te) for te in sol.t_events[1:]):
        return None
    return sol.y_events[0][0][:6]


def corollary_states(mu: float, n: int, rng: np.random.Generator, *, alpha: float = 3.0, horizon: float = DEFAULT_HORIZON,
                     t_range: tuple[float, float] = (0.2, 1.5), min_offplane: float = 0.1, max_b: float = -0.1,
                     max_tries: int = 20_000) -> tuple[list[SlipState], np.ndarray, np.ndarray]:
    """Slipping states the theory sends to p = 0 with b < 0 (Corollary 4.2), away from varphi = -pi/2.

    Built from the event backwards: a point of p = 0 (theta = theta_-+(varphi),
    eq. thetastar) with |varphi + pi/2| >= ``min_offplane`` (the 3-D mechanism:
    on varphi = -pi/2, p = 0 is crossed only at b = 0), Theta ~ U(-2, 2),
    Psi ~ U(-3, 3), eta ~ U(0.3, 3) and b <= ``max_b`` (clear of the GB
    manifold); by eq. pdotarg every such point is crossed from p > 0 into
    p < 0.  The slipping flow is run backwards for a time ~ U(t_range) (after
    the soft contact's build-up, before the horizon), and the start is kept
    when ``slip_until_event`` from it ends in JAM in ``t_range`` with the same
    conditions at its event.

    Returns:
      (states, analytic jam times (n,), varphi at the jam (n,)).

    Raises:
      ValueError: mu <= mu_P*(varphi) for every allowed varphi, or fewer than
        n states in ``max_tries`` attempts.
    """
    from crosscheck.critical import theta_pm

    mu = float(check("mu", mu, MU))
    alpha = float(check("alpha", alpha, ALPHA))
    ratio = 2.0 * math.sqrt(1.0 + alpha) / (alpha * mu)  # |sin varphi| must exceed this (eq. mup)
    half = math.acos(ratio) if ratio < 1 else 0.0
    if half <= min_offplane:
        raise ValueError(f"no p = 0 crossing with |varphi + pi/2| >= {min_offplane} at mu = {mu:g} (mu_P = {float(mu_P(alpha)):.4g})")
    found, times, varphis = [], [], []
    for _ in range(max_tries):
        off = rng.uniform(min_offplane, half) * rng.choice((-1.0, 1.0))
        varphi = -math.pi / 2 + off
        theta = float(theta_pm(varphi, mu, alpha)[int(rng.integers(2))])
        Theta, Psi, eta = rng.uniform(-2, 2), rng.uniform(-3, 3), rng.uniform(0.3, 3.0)
        if not (1e-3 < theta < math.pi / 2 - 1e-3) or (Psi**2 * math.cos(theta) ** 2 + Theta**2) * math.sin(theta) - 1 > max_b:
            continue
        x0 = _backward_from(np.array([eta, varphi, 0.0, Psi, theta, Theta]), mu, alpha, rng.uniform(*t_range))
        if x0 is None:
            continue
        s = SlipState(theta=x0[4], varphi=x0[1], Theta=x0[5], Psi=x0[3], eta=x0[0])
        r = slip_until_event(s, mu, alpha, t_max=horizon)
        if r.outcome == Outcome.JAM and t_range[0] <= r.time <= t_range[1] and r.b <= max_b and abs(r.state.varphi + math.pi / 2) >= min_offplane:
            found.append(s)
            times.append(r.time)
            varphis.append(r.state.varphi)
            if len(found) == n:
                return found, np.array(times), np.array(varphis)
    raise ValueError(f"found only {len(found)} of {n} Corollary 4.2 states at mu = {mu:g} in {max_tries} attempts")


def _random_slipping(mu: float, n: int, rng: np.random.Generator, alpha: float) -> list[SlipState]:
    out = []
    while len(out) < n:
        s = SlipState(theta=rng.uniform(0.05, 1.5), varphi=-rng.uniform(0.0, math.pi * (1 - 1e-9)), Theta=rng.uniform(-1.5, 1.5), Psi=rng.uniform(-2.5, 2.5), eta=rng.uniform(0.2, 3))
        st, ct = math.sin(s.theta), math.cos(s.theta)
        if (s.Psi**2 * ct**2 + s.Theta**2) * st - 1 < 0 and 1 + alpha + alpha * st * (mu * ct * math.sin(s.varphi) - st) > 0:
            out.append(s)
    return out


@dataclass(frozen=True, eq=False)
class JamCheck:
    """What ``jam_check`` measured (5d); ``to_dict()`` is JSON-able.

    below: one dict per mu < mu_P: n random slipping states; for each
      classifier ("part_a", "effective") the MuJoCo outcome counts and n_jam;
      analytic_jams (must be 0: p > 0 everywhere below mu_P).
    above: one dict per mu > mu_P: n Corollary 4.2 states; per classifier the
      outcome counts, jam_fraction, median (t_MuJoCo - t_analytic) of its
      JAMs, near_fraction: per event (JAM, STICK, LIFTOFF) the fraction of
      states whose MuJoCo run ends with it within ``near_window`` of the
      analytic jam time, ended_near_fraction: their sum (MuJoCo's slipping
      ends where the theory says slipping becomes impossible),
      time_difference: quantiles of t_MuJoCo - t_jam per event, p_at_jam: p
      (part_a: eq. p on MuJoCo's state; effective: window p_eff) at its JAM
      rows; |varphi + pi/2| of the analytic jam for the states MuJoCo jams
      and for the others.
    """

    mu_P: float
    below: list
    above: list
    options: dict
    thresholds: dict

    def to_dict(self) -> dict:
        return _json({"mu_P": self.mu_P, "below": self.below, "above": self.above, "options": self.options, "thresholds": self.thresholds})


def _counts(outcome: np.ndarray) -> dict:
    return {o.name: int((outcome == o).sum()) for o in Outcome if (outcome == o).any()}


def jam_check(*, mus_below: Sequence[float] = (0.5, 1.0, 1.3), mus_above: Sequence[float] = (1.4, 1.7, 6.0), n_below: int = 100,
              n_above: int = 40, rng: np.random.Generator, alpha: float = 3.0, horizon: float = DEFAULT_HORIZON,
              thresholds: Thresholds | None = None, near_window: float = 0.15, nthread: int = 2, progress: bool = False,
              **options) -> JamCheck:
    """5d: MuJoCo never jams below mu_P; above it, do the theory's jam states jam in MuJoCo?

    Below mu_P: ``n_below`` random slipping states per mu (theta in (0.05,
    1.5), varphi over (-pi, 0], |Theta| <= 1.5, |Psi| <= 2.5, eta in [0.2, 3]).
    Above: ``n_above`` ``corollary_states`` per mu.  ``near_window`` (0.15,
    2.5 tau at the default tau = 0.06: the soft contact's lag ``LAG_TAU`` tau
    plus margin) is how close to the analytic jam a MuJoCo event must be to
    count as the end of the same slip.  Every state runs once
    (``classified_rollout``, ``study_thresholds`` unless ``thresholds``) and
    is classified by part A's rule and by ``classify_effective``.
    """
    alpha = float(check("alpha", alpha, ALPHA))
    muP = float(mu_P(alpha))
    for m in mus_below:
        if not m < muP:
            raise ValueError(f"mus_below must be < mu_P = {muP:.6g}; got {m!r}")
    for m in mus_above:
        if not m > muP:
            raise ValueError(f"mus_above must be > mu_P = {muP:.6g}; got {m!r}")
    opts = Options.from_kwargs(options)
    th = thresholds if thresholds is not None else study_thresholds(opts)
    kw = {f.name: getattr(opts, f.name) for f in fields(Options)}
    rod = Rod.scaled(alpha)
    below = []
    for m in mus_below:
        states = _random_slipping(m, n_below, rng, alpha)
        r = classified_rollout(rod, states, m, horizon=horizon, thresholds=th, nthread=nthread, progress=progress, **kw)
        analytic_jams = sum(slip_until_event(s, m, alpha, t_max=horizon).outcome == Outcome.JAM for s in states)
        row = {"mu": m, "n": len(states), "analytic_jams": int(analytic_jams)}
        for c in ("a", "e"):
            name = "part_a" if c == "a" else "effective"
            row[name] = {"outcomes": _counts(r[f"outcome_{c}"]), "n_jam": int((r[f"outcome_{c}"] == Outcome.JAM).sum())}
        below.append(row)
    above = []
    for m in mus_above:
        states, t_a, varphi_a = corollary_states(m, n_above, rng, alpha=alpha, horizon=horizon)
        r = classified_rollout(rod, states, m, horizon=horizon, thresholds=th, nthread=nthread, progress=progress, **kw)
        off = np.abs(varphi_a + math.pi / 2)
        row = {"mu": m, "n": len(states)}
        for c, p_key in (("a", "p_a"), ("e", "p_eff_e")):
            name = "part_a" if c == "a" else "effective"
            o, t = r[f"outcome_{c}"], r[f"time_{c}"]
            jam = o == Outcome.JAM
            near = np.abs(t - t_a) <= near_window
            row[name] = {"outcomes": _counts(o), "jam_fraction": float(jam.mean()),
                         "median_jam_time_difference": float(np.median(t[jam] - t_a[jam])) if jam.any() else math.nan,
                         "near_fraction": {e.name: float(((o == e) & near).mean()) for e in _EVENTS},
                         "ended_near_fraction": float((np.isin(o, _EVENTS) & near).mean()),
                         "time_difference": {e.name: _quantiles(t[o == e] - t_a[o == e]) for e in _EVENTS},
                         "p_at_jam": _quantiles(r[p_key][jam]),
                         "offplane_at_event_jam": _quantiles(off[jam]), "offplane_at_event_other": _quantiles(off[~jam])}
        above.append(row)
    return JamCheck(mu_P=muP, below=below, above=above, options=kw, thresholds={f.name: getattr(th, f.name) for f in fields(Thresholds)})


# --------------------------------------------------------------------------
# Why: MuJoCo's friction direction off the planar section
# --------------------------------------------------------------------------


def friction_skew(states: Sequence[SlipState], mu, *, alpha: float = 3.0, duration: float = 0.1, **options) -> dict[str, np.ndarray]:
    """MuJoCo's friction force against the rigid Coulomb law, over the first ``duration`` of each run.

    For every row with a normal force, the friction force F_t (world frame,
    horizontal) is compared with the slip velocity u of the contact point:
    the rigid law (eq. friction) has F_t = -mu F_z u/|u|.  Returned, per state
    (each (B,), normal-force weighted means over the rows):

      skew: signed angle [rad] from -u to F_t (counter-clockwise positive);
        0 on the planar section by symmetry.
      saturation: |F_t| / (mu F_z) (1 = slipping on the cone's surface).
      p, p_eff: eq. p on MuJoCo's states, and the vertical tip acceleration
        per unit normal force with MuJoCo's actual force, from eq. linode2:
        p_eff = 1 + alpha - alpha sin^2 theta - alpha sin theta cos theta
        (F_t . e) / F_z, e = (-sin psi, cos psi) the rod's horizontal direction
        (equal to p when F_t = -mu F_z u/|u|).
      force, rigid_force, rigid_force_eff: window-mean normal force over the
        duration, -b/p and -b/p_eff (b of eq. b, row means) [m g].

    Args:
      states: B slipping states; mu: scalar or (B,); alpha: the rod's.
      duration: scaled time simulated (default 0.1, before the state changes much).
      **options: MuJoCo ``Options``.
    """
    opts = Options.from_kwargs(options)
    rod = Rod.scaled(float(check("alpha", alpha, ALPHA)))
    states = list(states)
    mu = np.broadcast_to(check("mu", mu, MU), (len(states),)).astype(float)
    nstep = n_steps(float(check("duration", duration, POSITIVE)), opts.timestep)
    out = {k: np.full(len(states), np.nan) for k in ("skew", "saturation", "p", "p_eff", "force", "rigid_force", "rigid_force_eff")}
    for i, (s, m) in enumerate(zip(states, mu)):
        model = build_model(rod, m, opts)
        layout = SensorLayout.from_model(model)
        x0 = initial_state(model, rod, s, opts.radius)
        _, sd = rollout.rollout(model, mujoco.MjData(model), x0[None], nstep=nstep)
        R = record_from_sensordata(sd[0], layout, rod, opts.radius)
        Fz = R.normal_force
        on = Fz > 0
        if not on.any():
            continue
        w = Fz[on]
        Ft = R.force[on, :2]
        u = R.slip_vel[on, :2]
        ang = np.arctan2(Ft[:, 1], Ft[:, 0]) - np.arctan2(-u[:, 1], -u[:, 0])
        ang = np.angle(np.exp(1j * ang))
        st, ct = np.sin(R.theta), np.cos(R.theta)
        e = np.stack([-np.sin(R.psi[on]), np.cos(R.psi[on])], axis=-1)
        p_eff_rows = 1 + rod.alpha - rod.alpha * st[on] ** 2 - rod.alpha * st[on] * ct[on] * (Ft * e).sum(-1) / w
        p_rows = 1 + rod.alpha + rod.alpha * st * (m * ct * np.sin(R.varphi) - st)
        b_rows = (R.Psi**2 * ct**2 + R.Theta**2) * st - 1
        out["skew"][i] = np.sum(w * ang) / w.sum()
        out["saturation"][i] = np.sum(np.hypot(Ft[:, 0], Ft[:, 1])) / (m * w.sum())
        out["p"][i] = np.sum(w * p_rows[on]) / w.sum()
        out["p_eff"][i] = np.sum(w * p_eff_rows) / w.sum()
        out["force"][i] = Fz.mean()
        out["rigid_force"][i] = -b_rows.mean() / out["p"][i]
        out["rigid_force_eff"][i] = -b_rows.mean() / out["p_eff"][i]
    return out
