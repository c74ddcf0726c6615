"""MuJoCo's friction-direction skew: predicted by its contact law, measured in its runs, and what removes it.

MuJoCo's friction is not anti-parallel to the slip off the planar section
(``crosscheck.engines.mujoco.studies.contact.friction_skew`` measures it).  Its
contact law (``crosscheck.engines.mujoco.law``) says why: on the cone's
surface the force is anti-parallel to

    u + a_t / B      (u: contact-point slip velocity, a_t = J_t qacc its
                      tangential acceleration under the force, B = 2 / (dmax tau_f))

because the friction rows' reference acceleration is aref_t = -B u.  So the
friction opposes the slip velocity extrapolated over 1/B, and a_t is not
along u: the Delassus operator's tangential block is anisotropic (the
contact point of a rod is far more mobile across the rod than along it) and
coupled to the normal row.  ``ablation`` removes those ingredients one by one
from the solved problem.

Three comparisons on the same random slipping states (section 2's variables,
alpha = 3), over the first ``duration`` of each run:

* ``measured``: MuJoCo's normal-force-weighted mean skew (exactly the numbers
  of ``mujoco_contact.friction_skew``), optionally with MuJoCo options that
  the engine's ``Options`` do not carry (impratio, a pyramidal cone, noslip
  iterations) set on the compiled model;
* ``predicted``: the same mean on the run of the continuous-time law (engine
  "mujoco_law"), and the closed form angle(u, u + a_t / B) on its rows;
* per |varphi + pi/2| band and per mu bin: medians of |skew| side by side.

Scaled units (section 2.1); angles in radians unless a key says degrees.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import mujoco
import numpy as np
from mujoco import rollout

from crosscheck.checks import ALPHA, MU, POSITIVE, check
from crosscheck.coordinates import to_generalized
from crosscheck.engines.base import n_steps
from crosscheck.engines.mujoco.law import accelerations, contact_problem, skew_angle, solve_cone
from crosscheck.engines.mujoco.model import SensorLayout, build_model, initial_state, record_from_sensordata
from crosscheck.engines.mujoco.model import model as cached_model
from crosscheck.engines.mujoco.ode import integrate, record
from crosscheck.engines.mujoco.options import Options
from crosscheck.engines.record import Record
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = [
    "BANDS",
    "MU_BINS",
    "VARIANTS",
    "random_states",
    "skew_of_record",
    "measured",
    "predicted",
    "ablation",
    "study",
    "option_effects",
    "REMOVES",
    "REDUCES",
]

#: What a MuJoCo option does to the skew, from the per-band medians against the default's: it removes it when every
#: band falls below REMOVES of the default, reduces it below REDUCES, and leaves it otherwise.
REMOVES, REDUCES = 0.2, 0.6

#: Bands of |varphi + pi/2| [rad]: near the planar section, intermediate, towards the rod's axis.
BANDS = ((0.0, math.pi / 6), (math.pi / 6, math.pi / 3), (math.pi / 3, math.pi / 2 + 1e-9))

#: Bins of mu for the skew against friction.
MU_BINS = ((0.3, 0.8), (0.8, 1.4), (1.4, 2.0))

#: MuJoCo variants measured (name -> model.opt settings); "default" is rod.xml's (elliptic, impratio 1, no noslip).
VARIANTS = {
    "default": {},
    "impratio 10": {"impratio": 10.0},
    "impratio 100": {"impratio": 100.0},
    "pyramidal cone": {"cone": int(mujoco.mjtCone.mjCONE_PYRAMIDAL)},
    "noslip 20": {"noslip_iterations": 20},
}


def random_states(n: int, rng: np.random.Generator) -> tuple[list[SlipState], np.ndarray]:
    """n random slipping states (as ``mujoco_contact.contact_acceleration`` draws them, psi = 0) and mu ~ U(0.3, 2)."""
    states = [
        SlipState(
            theta=rng.uniform(0.1, 1.45),
            varphi=-rng.uniform(0.05, 3.1),
            Theta=0.7 * rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.2, 3.0),
        )
        for _ in range(n)
    ]
    return states, rng.uniform(0.3, 2.0, n)


def skew_of_record(rec: Record, mu: float) -> tuple[float, float]:
    """(skew, saturation) of one run as ``mujoco_contact.friction_skew`` computes them (normal-force-weighted mean
    angle from -u to F_t over rows with F_z > 0, and sum |F_t| / (mu sum F_z)); NaN without a force."""
    Fz = rec.normal_force
    on = Fz > 0
    if not on.any():
        return math.nan, math.nan
    w = Fz[on]
    Ft, u = rec.force[on, :2], rec.slip_vel[on, :2]
    ang = np.angle(np.exp(1j * (np.arctan2(Ft[:, 1], Ft[:, 0]) - np.arctan2(-u[:, 1], -u[:, 0]))))
    return float(np.sum(w * ang) / w.sum()), float(np.sum(np.hypot(Ft[:, 0], Ft[:, 1])) / (mu * w.sum()))


def measured(
    states: Sequence[SlipState],
    mu,
    *,
    alpha: float = 3.0,
    duration: float = 0.1,
    model_options: dict | None = None,
    **options,
) -> dict[str, np.ndarray]:
    """MuJoCo's skew and saturation per state (B,), with ``model_options`` set on ``model.opt`` after compiling."""
    opts = Options.from_kwargs(options)
    rod = Rod.scaled(float(check("alpha", alpha, ALPHA)))
    states = list(states)
    mu = np.broadcast_to(check("mu", mu, MU), (len(states),)).astype(float)
    nstep = n_steps(float(check("duration", duration, POSITIVE)), opts.timestep)
    out = {k: np.full(len(states), np.nan) for k in ("skew", "saturation")}
    data = None  # one MjData for every run: the models differ in parameters only, and a rollout sets each run's whole state
    for i, (s, m) in enumerate(zip(states, mu)):
        # a model of its own where its options are changed after compiling; else the engine's kept one (never changed)
        model = build_model(rod, m, opts) if model_options else cached_model(rod, m, opts)
        for k, v in (model_options or {}).items():
            setattr(model.opt, k, v)
        layout = SensorLayout.from_model(model)
        data = mujoco.MjData(model) if data is None else data
        _, sd = rollout.rollout(model, data, initial_state(model, rod, s, opts.radius, data=data)[None], nstep=nstep)
        out["skew"][i], out["saturation"][i] = skew_of_record(
            record_from_sensordata(sd[0], layout, rod, opts.radius), m
        )
    return out


def predicted(
    states: Sequence[SlipState], mu, *, alpha: float = 3.0, duration: float = 0.1, **options
) -> dict[str, np.ndarray]:
    """The continuous-time law's skew per state (B,): ``skew`` from its run (as ``measured``); on its rows on the
    cone's surface, ``closed`` the force-weighted mean of angle(u, u + a_t / B) (a_t under the full contact force,
    u and a_t at MuJoCo's contact point) and ``solved`` the same mean of the solved force's angle from -u;
    ``exits``: theta left (0, pi/2) within the window (the law then misses MuJoCo's contact at the other end)."""
    opts = Options.from_kwargs(options)
    rod = Rod.scaled(float(check("alpha", alpha, ALPHA)))
    states = list(states)
    mu = np.broadcast_to(check("mu", mu, MU), (len(states),)).astype(float)
    nstep = n_steps(float(check("duration", duration, POSITIVE)), opts.timestep)
    times = np.arange(nstep) * opts.timestep / rod.omega
    out = {k: np.full(len(states), np.nan) for k in ("skew", "saturation", "closed", "solved")}
    out["exits"] = np.zeros(len(states), bool)
    for i, (s, m) in enumerate(zip(states, mu)):
        q0, v0 = to_generalized(rod, s, tip=(0.0, 0.0, opts.radius))
        traj = integrate(rod, q0, v0, m, opts, times=times)
        rec = record(rod, traj, opts)
        out["skew"][i], out["saturation"][i] = skew_of_record(rec, m)
        # theta leaves (0, pi/2): the rod lies flat and MuJoCo's capsule touches with its other end (a second contact
        # the law does not model), so the run is outside the comparison from there on
        out["exits"][i] = bool(np.any((rec.theta <= 0) | (rec.theta >= math.pi / 2)))
        # the closed form holds on the cone's surface (slipping rows); the run's own angle on the same rows beside it
        f = traj.force
        on = np.flatnonzero((f[:, 0] > 0) & (np.hypot(f[:, 1], f[:, 2]) >= (1 - 1e-9) * m * f[:, 0]))
        if not len(on) or m == 0:
            continue
        ang, solved = np.empty(len(on)), np.empty(len(on))
        for j, r in enumerate(on):
            qacc, _, pb = accelerations(rod, traj.q[r], traj.v[r], m, opts, contact=True)
            at = pb.J @ qacc
            ang[j] = skew_angle(pb.vel[1:], at[1:], pb.B[1])
            solved[j] = np.angle(np.exp(1j * (math.atan2(f[r, 2], f[r, 1]) - math.atan2(-pb.vel[2], -pb.vel[1]))))
        w = f[on, 0]
        out["closed"][i] = float(np.sum(w * ang) / w.sum())
        out["solved"][i] = float(np.sum(w * solved) / w.sum())
    return out


def ablation(rod: Rod, state: SlipState, mu: float, **options) -> dict[str, float]:
    """Skew [rad] of MuJoCo's force at a state's start (penetration 1e-9 l) with ingredients removed from its problem.

    Keys: "law" (the full problem); "decoupled" (A's normal-tangential
    coupling A_tn set to 0); "isotropic" (also A_tt replaced by its mean
    eigenvalue times I); "no free acceleration" (a0_t = 0, A kept); "neither"
    (isotropic, decoupled and a0_t = 0: exactly 0 by symmetry, the check that
    these are all the ingredients).
    """
    opts = Options.from_kwargs(options)
    q, v = to_generalized(rod, state, tip=(0.0, 0.0, opts.radius))
    q[2] -= 1e-9 * rod.length
    pb = contact_problem(rod, q, v, mu, opts)
    R = np.diag(pb.R)
    g = pb.a0 - pb.aref
    g_free = g.copy()
    g_free[1:] = -pb.aref[1:]
    A_dec = pb.A.copy()
    A_dec[0, 1:] = A_dec[1:, 0] = 0.0
    A_iso = A_dec.copy()
    A_iso[1:, 1:] = np.eye(2) * 0.5 * np.trace(pb.A[1:, 1:])

    def angle(A, gg):
        f = solve_cone(A + R, gg, mu)
        return float(np.angle(np.exp(1j * (math.atan2(f[2], f[1]) - math.atan2(-pb.vel[2], -pb.vel[1])))))

    return {
        "law": angle(pb.A, g),
        "decoupled": angle(A_dec, g),
        "isotropic": angle(A_iso, g),
        "no free acceleration": angle(pb.A, g_free),
        "neither": angle(A_iso, g_free),
    }


def _medians(x: np.ndarray, key: np.ndarray, bins) -> list[float]:
    out = []
    for lo, hi in bins:
        sel = (key >= lo) & (key < hi) & np.isfinite(x)
        out.append(float(np.degrees(np.median(np.abs(x[sel])))) if sel.any() else math.nan)
    return out


def study(
    n: int,
    rng: np.random.Generator,
    *,
    alpha: float = 3.0,
    duration: float = 0.1,
    variants: Mapping[str, dict] | Sequence[str] = tuple(VARIANTS),
    friction_timeconsts: Sequence[float] = (0.03, 0.01),
    n_ablation: int = 20,
    **options,
) -> dict:
    """The skew on n random states: measured (MuJoCo, each variant), predicted (law run and closed form), by band and mu bin.

    ``variants``: names of ``VARIANTS`` or a mapping name -> model.opt settings.
    ``friction_timeconsts``: MuJoCo runs with a shorter friction time constant
    (solreffriction).  Returns per-state arrays, per-band / per-mu-bin medians
    of |skew| [degrees], the median saturation |F_t| / (mu F_z) of each run
    kind, and the ablation's median |skew| [degrees].
    """
    variants = dict(variants) if isinstance(variants, Mapping) else {k: VARIANTS[k] for k in variants}
    states, mu = random_states(n, rng)
    offset = np.array([abs(s.varphi + math.pi / 2) for s in states])
    rod = Rod.scaled(alpha)
    out: dict = {
        "varphi_offset": offset,
        "mu": mu,
        "bands": [list(b) for b in BANDS],
        "mu_bins": [list(b) for b in MU_BINS],
    }
    law = predicted(states, mu, alpha=alpha, duration=duration, **options)
    out["predicted"], out["closed"], out["saturation_law"] = law["skew"], law["closed"], law["saturation"]
    runs = {}
    for name, settings in variants.items():
        runs[name] = measured(states, mu, alpha=alpha, duration=duration, model_options=settings, **options)
    for tf in friction_timeconsts:
        runs[f"friction timeconst {tf:g}"] = measured(
            states, mu, alpha=alpha, duration=duration, **{**options, "friction_timeconst": tf}
        )
    out["measured"] = {k: r["skew"] for k, r in runs.items()}
    out["saturation"] = {k: r["saturation"] for k, r in runs.items()}
    # compared: states where the law's run has a contact force and stays in theta in (0, pi/2); the others are counted:
    # "lifts off" (b > 0 at the start: the law has no force, MuJoCo's first step may apply one from its dJ/dt v / 2 term)
    # and "exits" (the rod lies flat within the window and MuJoCo's capsule touches with its other end)
    out["exits"], out["lifts_off"] = law["exits"], ~np.isfinite(law["skew"])
    compared = np.isfinite(law["skew"]) & ~law["exits"]
    d = np.abs(law["skew"] - runs["default"]["skew"])[compared] if "default" in runs else np.full(1, np.nan)
    out["n_compared"], out["n_exits"], out["n_lifts_off"] = (
        int(compared.sum()),
        int(law["exits"].sum()),
        int(out["lifts_off"].sum()),
    )
    out["max_abs_difference_deg"] = float(np.degrees(np.nanmax(d))) if d.size else math.nan
    # medians side by side on the same (compared) states
    table = {
        "predicted (law run)": law["skew"],
        "predicted (closed form)": law["closed"],
        **{f"MuJoCo {k}": r["skew"] for k, r in runs.items()},
    }
    out["band_median_deg"] = {k: _medians(np.where(compared, x, np.nan), offset, BANDS) for k, x in table.items()}
    out["mu_median_deg"] = {k: _medians(np.where(compared, x, np.nan), mu, MU_BINS) for k, x in table.items()}
    sat = {"law": law["saturation"], **{k: r["saturation"] for k, r in runs.items()}}
    out["saturation_median"] = {
        k: float(np.nanmedian(x[compared])) if compared.any() else math.nan for k, x in sat.items()
    }
    out["median_abs_difference_deg"] = float(np.degrees(np.nanmedian(d))) if d.size else math.nan
    abl = [ablation(rod, s, float(m), **options) for s, m in zip(states[:n_ablation], mu[:n_ablation])]
    out["ablation_median_deg"] = (
        {k: float(np.degrees(np.median(np.abs([a[k] for a in abl])))) for k in abl[0]} if abl else {}
    )
    return out


def option_effects(band_median_deg: Mapping[str, Sequence[float]]) -> dict[str, dict[str, list[float]]]:
    """Sort the measured MuJoCo variants of ``study``'s ``band_median_deg`` ("MuJoCo <name>" keys) by their effect on the skew.

    Returns {"removes": {name: medians}, "reduces": {...}, "leaves": {...}}:
    the largest ratio over the bands of a variant's median to the default's
    against REMOVES and REDUCES.
    """
    default = band_median_deg["MuJoCo default"]
    out: dict[str, dict[str, list[float]]] = {"removes": {}, "reduces": {}, "leaves": {}}
    for k, x in band_median_deg.items():
        if not k.startswith("MuJoCo ") or k == "MuJoCo default":
            continue
        r = max((a / m for a, m in zip(x, default) if m > 0), default=math.nan)
        kind = "removes" if r < REMOVES else "reduces" if r < REDUCES else "leaves"
        out[kind][k[len("MuJoCo ") :]] = list(x)
    return out
