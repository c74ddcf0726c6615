"""Dynamics terms: Pinocchio's rod (M, C, g, J, dJ, Delassus, b, p) against the analytic reference, state by state.

Part of ``crosscheck validate pinocchio`` (``crosscheck.studies.validate``).

Random rods (m, l, I0, g) and random slipping states (theta, varphi, Theta,
Psi, eta, psi, tip position) with random tip forces and friction are drawn;
each state goes to (q, v) through ``crosscheck.coordinates`` and Pinocchio
computes M, C, g, J, dJ and the tip acceleration by two routes.  Every quantity
is compared in the paper's scaled units (m = l = g = 1, forces in m g, time in
1/omega), so that one tolerance serves every rod:

* tip acceleration by ``aba`` and by G F + free acceleration, the Delassus
  matrix G and the free acceleration, against eq. linode2;
* M, C, g against the matrices of eqs. rotode and linode (``dynamics_reference.reference_terms``),
  and the identity C v + g = nonLinearEffects;
* b and p (eqs. b, p) and the LCP mode of section 3.1;
* mu_P found from Pinocchio's p alone against eq. mup2D.

An error is measured against an allowance ``atol * scale + rtol * |want|``,
with ``scale`` the size of the terms the quantity is summed from (its *term
scale*) times, for quantities that go through M^-1, the condition number
1/cos^2 theta of M (see ``crosscheck.engines.pinocchio.model``).  The tolerances and
their reasons are in the Pinocchio section of ``crosscheck.tolerances``.
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck import tolerances as tol
from crosscheck.coordinates import qv_of
from crosscheck.engines.pinocchio import model as pinrod
from crosscheck.engines.pinocchio import tolerances as pinocchio_tol
from crosscheck.engines.pinocchio.studies.dynamics_reference import Units, per_state, reference_chunk, units_of
from crosscheck.error_stats import ErrorStat, ValidationResult, error_stat
from crosscheck.rod import Rod
from crosscheck.theory import analytic
from crosscheck.theory.critical import mu_P as mu_P_closed_form

__all__ = ["DEFAULT_STATES", "ALPHAS_MU_P", "random_states", "validate"]

#: Number of random states of ``crosscheck validate pinocchio`` without ``--states``.
DEFAULT_STATES = 10_000

#: Values of alpha at which mu_P is found from Pinocchio's p (uniform rod alpha = 3 among them).
ALPHAS_MU_P = (0.5, 1.0, 3.0, 10.0, 20.0)

#: States are drawn for at most this many random rods (blocks of consecutive states share a rod).
MAX_RODS = 256


def random_states(n: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """n random rods-and-states, each entry an (n,) array (``F`` is (n, 3)).

    Rods: m, l log-uniform in [0.1, 10] kg, m; alpha log-uniform in [0.5, 20]
    (I0 = m l^2 / alpha); g uniform in [1, 20] m/s^2; ``rod`` numbers the rod of
    each state (min(n, MAX_RODS) rods, consecutive blocks).
    States (scaled): a third with theta uniform in (0, pi/2), a third near the
    horizontal rod (theta log-uniform in [1e-8, 1e-1]), a third near the vertical
    one (cos theta log-uniform in [1e-3, 1e-1]); varphi in (-pi, 0]; Theta, Psi in
    [-5, 5]; eta in [0, 3]; psi in [-pi, pi); tip (x, y) in [-2, 2]^2 on the plane.
    Forces F (scaled, units of m g) standard normal; mu uniform in [0, 5].
    """
    n_rods = min(n, MAX_RODS)
    rod = np.repeat(np.arange(n_rods), [len(b) for b in np.array_split(np.arange(n), n_rods)])
    m = 10.0 ** rng.uniform(-1, 1, n_rods)
    l = 10.0 ** rng.uniform(-1, 1, n_rods)
    alpha = 10.0 ** rng.uniform(math.log10(0.5), math.log10(20.0), n_rods)
    g = rng.uniform(1.0, 20.0, n_rods)
    kind = rng.integers(0, 3, n)
    theta = np.select(
        [kind == 0, kind == 1],
        [rng.uniform(0.0, math.pi / 2, n), 10.0 ** rng.uniform(-8, -1, n)],
        np.arccos(10.0 ** rng.uniform(-3, -1, n)),
    )
    theta = np.where(theta > 0.0, theta, 1e-8)  # uniform() may return the closed end 0
    return {
        "rod": rod,
        "m": m[rod],
        "l": l[rod],
        "I0": (m * l**2 / alpha)[rod],
        "g": g[rod],
        "alpha": alpha[rod],
        "theta": theta,
        "varphi": -math.pi * rng.uniform(0.0, 1.0, n),  # (-pi, 0]
        "Theta": rng.uniform(-5, 5, n),
        "Psi": rng.uniform(-5, 5, n),
        "eta": rng.uniform(0, 3, n),
        "psi": rng.uniform(-math.pi, math.pi, n),
        "x": rng.uniform(-2, 2, n),
        "y": rng.uniform(-2, 2, n),
        "F": rng.standard_normal((n, 3)),
        "mu": rng.uniform(0, 5, n),
    }


_TINY, _EPS = np.finfo(float).tiny, np.finfo(float).eps


class _ErrorStats:
    """``compare.error_stat``'s numbers for one quantity, its states given chunk by chunk in order (``add``), in fewer passes.

    With rtol = 0 (all of ``validate``'s tolerances) and finite errors the allowance atol + 0 |want| is
    atol and an entry's ratio fl(err / atol).  Division by atol > 0 keeps the order, so a chunk's largest
    ratio is fl(max err / atol), and its worst state (``error_stat``'s first state with the largest
    ratio) the first holding an entry whose ratio rounds to it: such entries lie within a few ulp of max
    err, and only those are divided.  The relative error is formed only in the columns whose reference is
    non-zero somewhere, the only ones holding ``error_stat``'s err[nz].  A chunk outside that case (rtol >
    0, a non-finite error, a subnormal ratio) takes ``error_stat``'s own steps.  Across chunks the
    largest values are kept (NaN kept as numpy's max keeps it) and the first worst state.
    """

    def __init__(self, quantity: str, tolerance):
        self.quantity, self.tolerance = quantity, tolerance
        self.n, self.worst, self.max_ratio = 0, 0, -math.inf
        self.max_abs = self.max_rel = None

    def add(self, got, want, scale=None) -> None:
        """The next chunk: ``_stat``'s got, want and scale (per state or entry; None: 1) of its states."""
        got, want = np.asarray(got, float), np.asarray(want, float)
        k = got.shape[0]
        if scale is not None:  # max_abs in the units of got; the rest on got / scale, want / scale
            scale = np.asarray(scale, float)
            scale = scale.reshape(scale.shape + (1,) * (want.ndim - scale.ndim))
            err = np.subtract(got, want)
            self.max_abs = _max(self.max_abs, np.abs(err, out=err).max())
            want_given = want
            got, want = np.divide(got, scale), np.divide(want, scale, out=err)
        err = np.subtract(got, want)
        err = np.abs(err, out=err).reshape(k, -1)
        max_err = err.max()
        if scale is None:
            self.max_abs = _max(self.max_abs, max_err)
        atol, rtol = self.tolerance.atol, self.tolerance.rtol
        ratio = max_err / atol if rtol == 0.0 and atol > 0.0 else math.nan
        abs_want = np.abs(want, out=want if scale is not None else None).reshape(
            k, -1
        )  # (want / scale is ours to overwrite)
        if np.isfinite(ratio) and (
            ratio == 0.0 or ratio >= _TINY
        ):  # (a subnormal ratio has fewer bits: more may round to it)
            flat = err.reshape(-1)
            near = np.flatnonzero(flat >= max_err * (1.0 - 4.0 * _EPS))
            i = int(near[np.flatnonzero(flat[near] / atol == ratio)[0]]) // err.shape[1]
            # got - want finite everywhere, so want is: a column holds a non-zero where its sum of |want| is > 0
            columns = np.einsum("ij->j", abs_want) > 0  # (a tenth of the time of abs_want.max(axis=0))
            if not columns.all():
                err, abs_want = err[:, columns], abs_want[:, columns]
            rel = np.divide(err, abs_want, out=np.zeros(err.shape), where=abs_want > 0).max() if columns.any() else None
        else:
            if scale is not None:
                want = want_given / scale
            per_state = self.tolerance.ratio(got, want).reshape(k, -1)
            per_state = np.where(np.isfinite(per_state), per_state, np.inf).max(axis=1)
            i = int(np.argmax(per_state))
            ratio = per_state[i]
            nz = abs_want > 0
            rel = (err[nz] / abs_want[nz]).max() if nz.any() else None
        if ratio > self.max_ratio:
            self.max_ratio, self.worst = ratio, self.n + i
        if rel is not None:
            self.max_rel = _max(self.max_rel, rel)
        self.n += k

    def result(self, states: dict) -> ErrorStat:
        """The ``ErrorStat`` of all states added, the worst one's entries read from ``states`` ((N,) arrays)."""
        worst = {k: float(np.asarray(v)[self.worst]) for k, v in states.items()}
        worst["index"] = self.worst
        return ErrorStat(
            quantity=self.quantity,
            n=self.n,
            max_abs=float(self.max_abs),
            max_rel=math.nan if self.max_rel is None else float(self.max_rel),
            max_ratio=float(self.max_ratio),
            worst_state=worst,
            tolerance=self.tolerance.as_dict(),
            passed=bool(self.max_ratio <= 1.0),
        )


def _max(a, b):
    """max(a, b) with NaN kept, as numpy's max keeps it; a None: b."""
    return b if a is None else np.maximum(a, b)


def _stat(quantity: str, got, want, tolerance, states: dict, *, scale=None) -> ErrorStat:
    """``error_stat`` with the allowance ``atol * scale + rtol * |want|`` (``scale`` per state or entry; None: 1).

    max_abs stays in the units of ``got`` (scaled units); max_rel is unchanged.
    """
    stat = _ErrorStats(quantity, tolerance)
    stat.add(got, want, scale)
    return stat.result(states)


def _by_decade(cos: np.ndarray, errors: dict[str, np.ndarray]) -> list[dict]:
    """Largest of each error per decade of cos theta: shows the 1/cos and 1/cos^2 growth."""
    decade = np.minimum(np.floor(np.log10(cos)).astype(int), -1)  # cos theta = 1.0 rounds into [0.1, 1]
    rows = []
    for d in range(int(decade.min()), 0):
        sel = decade == d
        if sel.any():
            rows.append(
                {
                    "cos_theta": [10.0**d, 10.0 ** (d + 1)],
                    "n": int(sel.sum()),
                    **{k: float(e[sel].max()) for k, e in errors.items()},
                }
            )
    return rows


def _row_max(x: np.ndarray) -> np.ndarray:
    """x.max(axis=1) of an (N, 3) array, column by column (max(axis=1) over rows of 3 is several times slower)."""
    return np.maximum(np.maximum(x[:, 0], x[:, 1]), x[:, 2])


def _mu_P_stat() -> ErrorStat:
    alphas = np.array(ALPHAS_MU_P)
    got = np.array([pinrod.mu_P(a) for a in alphas])
    want = mu_P_closed_form(alphas)
    return error_stat("mu_P from p", got, want, pinocchio_tol.PIN_MU_P, {"alpha": alphas})


def _rods(s: dict) -> tuple[list[slice], list[Rod]]:
    """The rods of the states ``s`` (``random_states``): each rod's block of consecutive states and its ``Rod``."""
    starts = np.flatnonzero(np.diff(s["rod"], prepend=-1))
    blocks = [slice(a, b) for a, b in zip(starts, [*starts[1:], len(s["rod"])])]
    rods = [
        Rod(mass=s["m"][b.start], length=s["l"][b.start], inertia=s["I0"][b.start], gravity=s["g"][b.start])
        for b in blocks
    ]
    return blocks, rods


#: ``validate`` takes whole rods (at least one) of at most this many states at a time through Pinocchio, the
#: reference and the statistics: every array of a chunk (<= 2 MB) is then reused from the heap, and mostly from
#: the caches, instead of being mapped afresh from the system (page faults took a tenth of the run on 100000
#: states at once) and read back from memory.
CHUNK_STATES = 8192


def _chunks(blocks: list[slice]) -> list[list[int]]:
    """The rods (their indices) in chunks of consecutive rods of at most CHUNK_STATES states (a larger rod alone)."""
    chunks, size = [[]], 0
    for r, block in enumerate(blocks):
        if chunks[-1] and size + (block.stop - block.start) > CHUNK_STATES:
            chunks.append([])
            size = 0
        chunks[-1].append(r)
        size += block.stop - block.start
    return chunks


#: The quantities compared chunk by chunk, in the order of the result.
_QUANTITIES = (
    ("tip acc, aba", pinocchio_tol.PIN_TIP_ACCELERATION),
    ("tip acc, G F + free", pinocchio_tol.PIN_THROUGH_MINV),
    ("Delassus G", pinocchio_tol.PIN_THROUGH_MINV),
    ("free tip acc", pinocchio_tol.PIN_THROUGH_MINV),
    ("M (crba)", pinocchio_tol.PIN_MATRICES),
    ("C (Coriolis matrix)", pinocchio_tol.PIN_MATRICES),
    ("g (gravity)", pinocchio_tol.PIN_MATRICES),
    ("C v + g = nle", pinocchio_tol.PIN_MATRICES),
)


def validate(n_states: int, rng: np.random.Generator, *, progress: bool = False) -> ValidationResult:
    """Compare Pinocchio with the analytic reference on ``n_states`` random states (see the module docstring)."""
    s = random_states(n_states, rng)
    n = n_states
    blocks, rods = _rods(s)
    of, l, ones = s["rod"], s["l"], np.ones(n)
    omega = per_state(of, rods, lambda r: r.omega)
    units = units_of(s, rods)
    L_rates, l_omega = np.stack((ones, ones, ones, l, l), axis=-1), (l * omega)[:, None]  # v_s = v L_rates / (l omega)
    factors = tuple(
        per_state(of, rods, lambda r, j=j: analytic.rod_factors(r)[j]) for j in range(5)
    )  # eq. linode2's, per state
    F = s["F"] * units.force_scale[:, None]
    tips = np.stack((s["x"], s["y"], np.zeros(n)), axis=-1)
    theta, Psi, Theta, alpha, mu = s["theta"], s["Psi"], s["Theta"], s["alpha"], s["mu"]
    rates_rad = (Psi * omega, Theta * omega)  # the reference reads rates in rad/s
    cos = np.cos(theta)
    kappa = 1.0 / cos**2  # condition number of M in its natural units diag(m, m, m, I0, I0)
    # Term scales (scaled units).  Eq. linode2 sums force terms with coefficients <= 1 + alpha, velocity
    # terms and gravity 1; Pinocchio's spatial algebra also forms products of the linear velocities
    # with the rates that cancel only in exact arithmetic, so the velocity terms are measured by
    # V = (1 + |v_s|_1)^2 over all five scaled velocities, not by Psi^2 + Theta^2 alone.
    rates, V, A = np.empty(n), np.empty(n), np.empty(n)
    alpha_1, F_1 = 1 + alpha, np.abs(s["F"]).sum(axis=1)  # A = (1 + alpha) |F|_1 + V
    pin_b, pin_p = np.empty(n), np.empty(n)
    tip_errors = {"aba": np.empty(n), "G F + free": np.empty(n)}  # largest tip acceleration error / A per state
    stats = {quantity: _ErrorStats(quantity, tolerance) for quantity, tolerance in _QUANTITIES}

    chunks = _chunks(blocks)
    most = max(blocks[c[-1]].stop - blocks[c[0]].start for c in chunks)
    # Pinocchio's raw terms of a chunk go to these arrays, reused chunk after chunk; one model, set to each rod in turn
    work = [np.empty((most,) + shape) for shape in ((5,), (5,), (5, 5), (5, 5), (6, 5), (6, 5), (5,), (5,), (3,))]
    rod_engine = pinrod.PinocchioRod(rods[0])
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n, desc="validate pinocchio", unit="state")
    for chunk in chunks:
        lo, hi = blocks[chunk[0]].start, blocks[chunk[-1]].stop
        k, now = hi - lo, slice(lo, hi)
        q, v, raw_M, raw_C, raw_J, raw_dJ, raw_g, raw_nle, raw_aba = raw = [x[:k] for x in work]
        rod_states = [
            (slice(blocks[r].start - lo, blocks[r].stop - lo), blocks[r], rods[r]) for r in chunk
        ]  # (in chunk, of all, rod)
        # every rod of the chunk in one call, each state with its rod's own floats (the arithmetic of a call per rod)
        q[...], v[...] = qv_of(
            l[now],
            omega[now],
            theta[now],
            s["varphi"][now],
            Theta[now],
            Psi[now],
            s["eta"][now],
            s["psi"][now],
            tips[now],
            0.0,
        )
        chunk_units = units.at(now)
        outer = chunk_units.outer()
        ref = reference_chunk(q, v, lo, s, rates_rad, F, chunk_units, outer, tuple(f[now] for f in factors))
        rates[now] = 1 + np.abs(v * L_rates[now] / l_omega[now]).sum(axis=1)
        V[now] = rates[now] ** 2
        A[now] = alpha_1[now] * F_1[now] + V[now]
        # Pinocchio rod by rod: the terms, then aba with tau = J^T F at the same states.
        for i, idx, rod in rod_states:
            _fill_rod(rod_engine, rod, F[idx], *(x[i] for x in raw))
            if bar is not None:
                bar.update(idx.stop - idx.start)
        terms = pinrod.RodTerms(
            v=v,
            M=pinrod.symmetrised(raw_M),
            C=raw_C,
            g=raw_g,
            nle=raw_nle,
            J=np.ascontiguousarray(raw_J[:, :3]),
            dJ=np.ascontiguousarray(raw_dJ[:, :3]),
        )
        pin, nle = _pinocchio_chunk(terms, raw_aba, F[now], chunk_units, outer)
        ref.update(nle)
        pin_b[now], pin_p[now] = pinrod.slip_coefficients_of(
            terms, s["psi"][now] + s["varphi"][now], mu[now], mass=chunk_units.mass, gravity=chunk_units.gravity
        )
        scales = _scales(A[now], cos[now], kappa[now], alpha_1[now], V[now], rates[now])
        for quantity, stat in stats.items():
            stat.add(pin[quantity], ref[quantity], scales[quantity])
        for route, quantity in (("aba", "tip acc, aba"), ("G F + free", "tip acc, G F + free")):
            tip_errors[route][now] = _row_max(np.abs(pin[quantity] - ref[quantity])) / A[now]
    if bar is not None:
        bar.close()

    return _result(s, stats, pin_b, pin_p, V, cos, tip_errors)


def _scales(A, cos, kappa, alpha_1, V, rates) -> dict:
    """Each quantity's term scale at a chunk's states (``validate``'s A, V, rates; kappa = 1/cos^2 theta for the
    quantities through M^-1; None: the quantity's own size)."""
    return {
        "tip acc, aba": A / cos,
        "tip acc, G F + free": kappa * A,
        "Delassus G": kappa * alpha_1,
        "free tip acc": kappa * V,
        "M (crba)": None,
        "C (Coriolis matrix)": rates,
        "g (gravity)": None,
        "C v + g = nle": V,
    }


def _fill_rod(rod_engine, rod: Rod, F, q, v, M, C, J, dJ, g, nle, aba) -> None:
    """Pinocchio's raw terms of one rod's states (q, v: (k, 5)) into the arrays M, C, g, nle, J, dJ, then aba's tip
    acceleration with tau = J^T F (F: (k, 3) tip forces) into ``aba``."""
    rod_engine.set_rod(rod)
    rod_engine.fill_terms(q, v, M, C, g, nle, J, dJ)
    tau = np.einsum("nij,ni->nj", np.ascontiguousarray(J[:, :3]), F)
    rod_engine.fill_aba_tip_acceleration(q, v, tau, aba)


def _result(s: dict, chunk_stats: dict, pin_b, pin_p, V, cos, tip_errors: dict) -> ValidationResult:
    """The ``ValidationResult`` of the states ``s``: the per-quantity statistics gathered chunk by chunk, eqs. b and p
    and the modes against the analytic reference, the mode confusion and the tip acceleration errors by decade of
    cos theta."""
    theta, Psi, Theta, alpha, mu = s["theta"], s["Psi"], s["Theta"], s["alpha"], s["mu"]
    ref_b = analytic.b(Psi, Theta, theta)
    ref_p = analytic.p(theta, s["varphi"], mu, alpha)
    where = {k: s[k] for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi", "alpha", "mu", "m", "l", "I0", "g")}
    stats = [stat.result(where) for stat in chunk_stats.values()]
    stats += [
        _stat("b", pin_b, ref_b, pinocchio_tol.PIN_SLIP, where, scale=V),
        _stat("p", pin_p, ref_p, pinocchio_tol.PIN_SLIP, where, scale=(1 + alpha) * (1 + mu)),
    ]
    # Modes: a state whose b or p is within its allowance of 0 is on a mode boundary, where the sign
    # is rounding; it is counted, not compared.
    pin_mode = np.asarray(pinrod.mode(pin_b, pin_p))
    ref_mode = np.asarray(analytic.mode(ref_b, ref_p))
    near_b = np.abs(ref_b) <= pinocchio_tol.PIN_SLIP.atol * V
    near_p = np.abs(ref_p) <= pinocchio_tol.PIN_SLIP.atol * (1 + alpha) * (1 + mu)
    boundary = near_b | near_p
    stats.append(_stat("mode", np.where(boundary, ref_mode, pin_mode), ref_mode, pinocchio_tol.PIN_MODE, where))
    stats.append(_mu_P_stat())
    confusion = np.zeros((4, 4), dtype=int)
    np.add.at(confusion, (ref_mode, pin_mode), 1)
    extra = {
        "units": "scaled (m = l = g = 1); allowance = atol * scale + rtol * |want|, scale = term scale "
        "(times 1/cos^2 theta for quantities through M^-1)",
        "rods": int(s["rod"].max()) + 1,
        "mode": {
            "names": [md.name for md in analytic.Mode],
            "confusion_reference_by_pinocchio": confusion.tolist(),
            "on_boundary": int(boundary.sum()),
            "disagree_off_boundary": int(((pin_mode != ref_mode) & ~boundary).sum()),
        },
        "min_cos_theta": float(cos.min()),
        "tip_acc_error_over_A_by_cos_theta": _by_decade(cos, tip_errors),
        "tolerances": {k: v for k, v in tol.named(pinocchio_tol).items() if k.startswith("PIN_")},
    }
    return ValidationResult(engine="pinocchio", stats=stats, extra=extra)


def _pinocchio_chunk(terms: pinrod.RodTerms, raw_aba, F, units: Units, outer) -> tuple[dict, dict]:
    """Pinocchio's quantities of one chunk of states in scaled units, and the want of C v + g = nle (nle, Pinocchio's too).

    ``terms`` and ``raw_aba`` (tip acceleration by aba) in physical units, F (N, 3) [N], ``units`` and ``outer`` the chunk's.
    """
    acc_scale = units.gravity[:, None]
    pin = {
        "tip acc, aba": raw_aba / acc_scale,
        "tip acc, G F + free": terms.tip_acceleration(F) / acc_scale,
        "Delassus G": terms.delassus() * units.mass[:, None, None],  # per unit scaled force m g, in units of g
        "free tip acc": terms.free_acceleration() / acc_scale,
    }
    # scaled_matrices' M * outer / ml2 (and so on), in place where the product is a fresh array
    for quantity, x, by, over in (
        ("M (crba)", terms.M, outer, units.ml2[:, None, None]),
        ("C (Coriolis matrix)", terms.C, outer, units.ml2_omega[:, None, None]),
        ("g (gravity)", terms.g, units.L, units.mgl[:, None]),
        ("C v + g = nle", terms.bias, units.L, units.mgl[:, None]),
        ("nle", terms.nle, units.L, units.mgl[:, None]),
    ):
        pin[quantity] = np.multiply(x, by)
        pin[quantity] /= over
    return pin, {"C v + g = nle": pin.pop("nle")}
