"""The theory's side of an event comparison: the analytic first event of every start, and its distance to an event boundary.

``analytic_events`` runs ``crosscheck.theory.slipping.slip_until_event`` on
every start of a grid; ``boundary_distance`` probes the analytic outcome with
random perturbations of the start (theta, varphi, Theta, Psi, eta; scaled
units) of growing size and returns the smallest size that changes it.
"""

from __future__ import annotations

import io
import math
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from crosscheck.checks import ALPHA, POSITIVE, check
from crosscheck.files import write_atomic
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.studies.comparison import EVENTS, floor_time, theory_jam_scale
from crosscheck.studies.grids import floats, initial_b_p, states_at
from crosscheck.theory.slipping import slip_until_event

__all__ = ["BOUNDARY_RADII", "AnalyticEvents", "analytic_events", "boundary_distance", "floor_times"]

#: Perturbation sizes of ``boundary_distance`` (scaled units, Euclidean in
#: (theta, varphi, Theta, Psi, eta)).
BOUNDARY_RADII = (0.01, 0.03, 0.1, 0.3)


@dataclass(frozen=True, eq=False)
class AnalyticEvents:
    """First events of the analytic slipping rod at N points (each field (N,)).

    outcome: int8 ``Outcome``; time: event (or stop) time; reason: the rule of
    ``slip_until_event`` that ended the run ("b=0", "p=0", "eta=0", "gb",
    "t_max", "varphi=0", "varphi=-pi", "theta=0", "theta=pi/2", "start", ...);
    b0, p0: eqs. b and p at the start; slipping: b0 < 0 < p0 (the studied
    states); until: comparison time T_i (module docstring); eta_min: the least
    slip speed along the run (``floor_times`` reads the theory at an engine's
    STICK floor from it); jam_scale: (k |b|)^(-1/5) at a JAM's state, NaN
    elsewhere (``crosscheck.studies.comparison.jam_scale``: the lag a spring
    contact is allowed there).
    """

    outcome: np.ndarray
    time: np.ndarray
    reason: np.ndarray
    b0: np.ndarray
    p0: np.ndarray
    slipping: np.ndarray
    until: np.ndarray
    eta_min: np.ndarray
    jam_scale: np.ndarray


def analytic_events(points: dict, *, alpha: float, horizon: float, progress: bool = False, kept=None) -> AnalyticEvents:
    """``slip_until_event`` (t_max = horizon) at every point of ``points`` (dict of (N,) arrays, keys ``AXES``).

    ``kept``: a .npz file keeping the events of these points, alpha and horizon (None: not kept), as
    ``boundary_distance``'s: read when it holds every field for N points and its b0, p0 are those of these points,
    else computed and written whole (a damaged or foreign file is computed again and replaced, never trusted).  The
    caller names the file by what the events depend on; engines mapping one grid then integrate the theory once.
    """
    alpha = float(check("alpha", alpha, ALPHA))
    horizon = float(check("horizon", horizon, POSITIVE))
    n = len(points["theta"])
    b0, p0 = initial_b_p(points, alpha)
    if kept is not None:
        read = _read_kept(Path(kept), n, b0, p0)
        if read is not None:
            return read
    outcome = np.empty(n, np.int8)
    t = np.empty(n)
    reason = np.empty(n, dtype=object)
    eta_min = np.empty(n)
    scale = np.full(n, np.nan)
    for i in tqdm(range(n), desc="analytic", unit="state", disable=not progress):
        s = states_at(points, [i])[0]
        r = slip_until_event(s, points["mu"][i], alpha, t_max=horizon)
        outcome[i], t[i], reason[i], eta_min[i] = int(r.outcome), r.time, r.reason, float(np.min(r.x[:, 0]))
        scale[i] = theory_jam_scale(r, points["mu"][i], alpha)
    until = np.where(outcome == Outcome.SLIP, np.minimum(t, horizon), np.where(np.isin(outcome, EVENTS), t, horizon))
    a = AnalyticEvents(outcome, t, reason.astype(str), b0, p0, (b0 < 0) & (p0 > 0), until, eta_min, scale)
    if kept is not None:
        _keep(kept, np.savez, **{f.name: getattr(a, f.name) for f in fields(AnalyticEvents)})
    return a


def _keep(path, save, *args, **kwargs) -> None:
    """Write what ``save`` (``np.save`` or ``np.savez``) makes of its arguments to ``path`` whole (``write_atomic``): a
    reader of a kept file never meets half of one."""
    buf = io.BytesIO()
    save(buf, *args, **kwargs)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    write_atomic(Path(path), buf.getvalue())


#: The dtype kind of each kept field (``_read_kept``): int8 outcomes, unicode reasons, a bool mask, floats.
_KINDS = {"outcome": "i", "reason": "U", "slipping": "b"}


def _read_kept(path: Path, n: int, b0: np.ndarray, p0: np.ndarray) -> AnalyticEvents | None:
    """The ``AnalyticEvents`` kept in ``path`` if it holds all of them for n points whose b0 and p0 are these, else None."""
    try:
        z = np.load(path, allow_pickle=False)
        if not isinstance(z, np.lib.npyio.NpzFile):  # a bare array: not a kept file
            return None
        with z:
            got = {f.name: z[f.name] for f in fields(AnalyticEvents)}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
        return None
    for k, v in got.items():
        if v.shape != (n,) or v.dtype.kind != _KINDS.get(k, "f"):
            return None
    if not (np.array_equal(got["b0"], b0) and np.array_equal(got["p0"], p0)):
        return None  # another grid's events under this name
    return AnalyticEvents(**got)


def floor_times(points: dict, index, a: AnalyticEvents, floor: float, *, alpha: float, horizon: float) -> np.ndarray:
    """For the points ``index`` whose theory SLIPs to its comparison time (the only ones ``comparison.stick_from`` reads):
    the first time its slip speed falls below ``floor`` (``comparison.floor_time``), NaN where it never does or the
    theory has an event; only the runs whose least slip speed is below the floor are integrated again."""
    out = np.full(len(index), np.nan)
    for j, i in enumerate(np.asarray(index)):
        if a.outcome[i] == Outcome.SLIP and a.eta_min[i] < floor:
            r = slip_until_event(states_at(points, [int(i)])[0], points["mu"][i], alpha, t_max=horizon)
            out[j] = floor_time(r.t, r.x[:, 0], floor)
    return out


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


def boundary_distance(
    points: dict,
    outcome: np.ndarray,
    *,
    alpha: float,
    horizon: float,
    rng: np.random.Generator,
    radii: Sequence[float] = BOUNDARY_RADII,
    directions: int = 6,
    mask: np.ndarray | None = None,
    progress: bool = False,
    kept=None,
) -> np.ndarray:
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
      kept: a .npy file keeping the distances of these points, ``rng`` and probe settings (None: not kept): read when
        it holds N floats, else probed and written whole (a damaged or foreign file is probed again and replaced,
        never trusted).  The caller names the file by what the distances depend on.

    Returns:
      (N,) distances (scaled units): one of ``radii``, inf or NaN.
    """
    radii = floats("radii", radii, POSITIVE)
    n = len(points["theta"])
    if kept is not None:
        try:
            x = np.load(kept, allow_pickle=False)
            if x.shape == (n,) and x.dtype == np.float64:
                return x
        except (OSError, ValueError):
            pass
    mask = np.ones(n, bool) if mask is None else np.asarray(mask, bool)
    out = np.full(n, np.nan)
    for i in tqdm(np.flatnonzero(mask), desc="boundary distance", unit="state", disable=not progress):
        out[i] = math.inf
        for r in sorted(radii):
            u = rng.normal(size=(directions, 5))
            u /= np.linalg.norm(u, axis=1, keepdims=True)
            if any(
                slip_until_event(_perturbed(points, i, r * d), points["mu"][i], alpha, t_max=horizon).outcome
                != outcome[i]
                for d in u
            ):
                out[i] = r
                break
    if kept is not None:
        _keep(kept, np.save, out, allow_pickle=False)
    return out
