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
* M, C, g against the matrices of eqs. rotode and linode (``reference_terms``),
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

from crosscheck.engines.pinocchio import tolerances as pinocchio_tol
from crosscheck.theory import analytic
from crosscheck.engines.pinocchio import model as pinrod
from crosscheck import tolerances as tol
from crosscheck.compare import ErrorStat, ValidationResult, error_stat
from crosscheck.coordinates import paper_to_qv
from crosscheck.theory.critical import mu_P as mu_P_closed_form
from crosscheck.rod import Rod

__all__ = ["DEFAULT_STATES", "ALPHAS_MU_P", "random_states", "reference_terms", "scaled_matrices", "validate"]

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


def reference_terms(rod: Rod, q, v) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C, g of the rod written from eqs. rotode and linode (physical units).

    Eq. linode is m (X'', Y'', Z'') = F - m g e_z; eq. rotode multiplied by
    I0 cos^2 theta (psi) and I0 (theta) is
      I0 cos^2 theta psi'' - 2 I0 sin theta cos theta psi' theta' = l cos theta (cos psi F_x + sin psi F_y),
      I0 theta'' + I0 sin theta cos theta psi'^2 = -l (sin psi sin theta F_x - cos psi sin theta F_y + cos theta F_z),
    whose right-hand sides are J^T F.  So M = diag(m, m, m, I0 cos^2 theta, I0),
    g = (0, 0, m g, 0, 0), and C is the Christoffel matrix of M (the only C
    linear in v with C v as above and M' - 2C skew-symmetric):
    C[psi, psi] = -I0 s c theta', C[psi, theta] = -I0 s c psi', C[theta, psi] = I0 s c psi'.

    q, v: (N, 5).  Returns M (N, 5, 5), C (N, 5, 5), g (N, 5).
    """
    q = np.asarray(q, float)
    v = np.asarray(v, float)
    n = q.shape[0]
    theta = q[:, 4]
    psi_dot, theta_dot = v[:, 3], v[:, 4]
    i0 = rod.inertia
    sc = np.sin(theta) * np.cos(theta)
    M = np.zeros((n, 5, 5))
    M[:, [0, 1, 2], [0, 1, 2]] = rod.mass
    M[:, 3, 3] = i0 * np.cos(theta) ** 2
    M[:, 4, 4] = i0
    C = np.zeros((n, 5, 5))
    C[:, 3, 3] = -i0 * sc * theta_dot
    C[:, 3, 4] = -i0 * sc * psi_dot
    C[:, 4, 3] = i0 * sc * psi_dot
    g = np.zeros((n, 5))
    g[:, 2] = rod.mass * rod.gravity
    return M, C, g


def _scale_factors(rod: Rod) -> tuple:
    """(L (5,), L L^T (5, 5), m l^2, m l^2 omega, m g l) of ``scaled_matrices``, each as the rod's own floats give it."""
    L = np.array([rod.length] * 3 + [1.0, 1.0])
    ml2 = rod.mass * rod.length**2
    return L, L[:, None] * L[None, :], ml2, ml2 * rod.omega, rod.mass * rod.gravity * rod.length


def scaled_matrices(rod: Rod, M, C, g) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C and a generalised force (g or C v + g) in the paper's scaled units.

    With q = L q_s, L = diag(l, l, l, 1, 1), and t = t_s / omega:
    M_s = L M L / (m l^2), C_s = L C L / (m l^2 omega), g_s = L g / (m g l).
    """
    L, outer, ml2, ml2_omega, mgl = _scale_factors(rod)
    return M * outer / ml2, C * outer / ml2_omega, g * L / mgl


def _stat(quantity: str, got, want, tolerance, states: dict, *, scale=None) -> ErrorStat:
    """``error_stat`` with the allowance ``atol * scale + rtol * |want|`` (``scale`` per state or entry; None: 1).

    max_abs stays in the units of ``got`` (scaled units); max_rel is unchanged.
    """
    got = np.asarray(got, float)
    want = np.asarray(want, float)
    if scale is None:  # x / 1.0 is x: error_stat's own max_abs is already |got - want|
        return error_stat(quantity, got, want, tolerance, states)
    scale = np.asarray(scale, float)
    scale = scale.reshape(scale.shape + (1,) * (want.ndim - scale.ndim))
    stat = error_stat(quantity, got / scale, want / scale, tolerance, states)
    stat.max_abs = float(np.max(np.abs(got - want)))
    return stat


def _by_decade(cos: np.ndarray, errors: dict[str, np.ndarray]) -> list[dict]:
    """Largest of each error per decade of cos theta: shows the 1/cos and 1/cos^2 growth."""
    decade = np.minimum(np.floor(np.log10(cos)).astype(int), -1)  # cos theta = 1.0 rounds into [0.1, 1]
    rows = []
    for d in range(int(decade.min()), 0):
        sel = decade == d
        if sel.any():
            rows.append({"cos_theta": [10.0**d, 10.0 ** (d + 1)], "n": int(sel.sum()), **{k: float(e[sel].max()) for k, e in errors.items()}})
    return rows


def _mu_P_stat() -> ErrorStat:
    alphas = np.array(ALPHAS_MU_P)
    got = np.array([pinrod.mu_P(a) for a in alphas])
    want = mu_P_closed_form(alphas)
    return error_stat("mu_P from p", got, want, pinocchio_tol.PIN_MU_P, {"alpha": alphas})


def validate(n_states: int, rng: np.random.Generator, *, progress: bool = False) -> ValidationResult:
    """Compare Pinocchio with the analytic reference on ``n_states`` random states (see the module docstring)."""
    s = random_states(n_states, rng)
    n = n_states
    # Rod by rod, into preallocated arrays of all states: Pinocchio's raw terms go to scratch arrays of one
    # block (reused, small enough to stay in cache), everything else is written to its rows in scaled units.
    pin_acc = {name: np.empty((n, 3)) for name in ("delassus", "aba", "free")}
    pin_G = np.empty((n, 3, 3))
    pin_M, pin_C = np.empty((n, 5, 5)), np.empty((n, 5, 5))
    pin_g, pin_nle, pin_Cv = np.empty((n, 5)), np.empty((n, 5)), np.empty((n, 5))
    ref_M, ref_C, ref_g = np.empty((n, 5, 5)), np.empty((n, 5, 5)), np.empty((n, 5))
    ref_acc, ref_free, ref_G = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3, 3))
    pin_b, pin_p = np.empty(n), np.empty(n)
    v_scaled = np.empty((n, 5))
    starts = np.flatnonzero(np.diff(s["rod"], prepend=-1))
    blocks = [slice(a, b) for a, b in zip(starts, [*starts[1:], n])]
    most = max(b.stop - b.start for b in blocks)
    raw_M, raw_C, raw_J, raw_dJ = (np.empty((most, k, 5)) for k in (5, 5, 6, 6))
    raw_g, raw_nle, raw_aba = np.empty((most, 5)), np.empty((most, 5)), np.empty((most, 3))
    tips = np.stack((s["x"], s["y"], np.zeros(n)), axis=-1)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n, desc="validate pinocchio", unit="state")
    for idx in blocks:
        i, k = idx.start, idx.stop - idx.start
        rod = Rod(mass=s["m"][i], length=s["l"][i], inertia=s["I0"][i], gravity=s["g"][i])
        q, v = paper_to_qv(rod, s["theta"][idx], s["varphi"][idx], s["Theta"][idx], s["Psi"][idx], s["eta"][idx], s["psi"][idx], tip=tips[idx])
        F = s["F"][idx] * rod.force_scale
        rod_engine = pinrod.PinocchioRod(rod)
        rod_engine.fill_terms(q, v, raw_M[:k], raw_C[:k], raw_g[:k], raw_nle[:k], raw_J[:k], raw_dJ[:k])
        terms = pinrod.RodTerms(v=v, M=pinrod.symmetrised(raw_M[:k]), C=raw_C[:k], g=raw_g[:k], nle=raw_nle[:k],
                                J=np.ascontiguousarray(raw_J[:k, :3]), dJ=np.ascontiguousarray(raw_dJ[:k, :3]))
        rod_engine.fill_aba_tip_acceleration(q, v, np.einsum("nij,ni->nj", terms.J, F), raw_aba[:k])
        acc_scale = rod.gravity  # accelerations in units of g = l omega^2
        pin_acc["delassus"][idx] = terms.tip_acceleration(F) / acc_scale
        pin_acc["aba"][idx] = raw_aba[:k] / acc_scale
        pin_acc["free"][idx] = terms.free_acceleration() / acc_scale
        pin_G[idx] = terms.delassus() * rod.mass  # per unit scaled force m g, in units of g
        pin_b[idx], pin_p[idx] = pinrod.slip_coefficients(rod, terms, s["psi"][idx] + s["varphi"][idx], s["mu"][idx])
        L, outer, ml2, ml2_omega, mgl = _scale_factors(rod)  # scaled_matrices' factors, for the two forces below
        pin_M[idx], pin_C[idx], pin_g[idx] = scaled_matrices(rod, terms.M, terms.C, terms.g)
        pin_nle[idx] = terms.nle * L / mgl
        pin_Cv[idx] = (np.einsum("nij,nj->ni", terms.C, v) + terms.g) * L / mgl
        ref_M[idx], ref_C[idx], ref_g[idx] = scaled_matrices(rod, *reference_terms(rod, q, v))
        v_scaled[idx] = v * np.array([1.0, 1.0, 1.0, rod.length, rod.length]) / (rod.length * rod.omega)
        # eq. linode2 (the reference reads rates in rad/s) in one call at six (rates, force) pairs per state:
        # (rates, F), (rates, 0), and at rest with 0 and with the unit forces m g e_j, whose differences are
        # the columns of G (G does not depend on the rates; at rest the difference does not cancel large
        # velocity terms).
        zero, unit = np.zeros(k), np.zeros((3, k, 3))
        for j in range(3):
            unit[j, :, j] = rod.force_scale
        Psi_dot, Theta_dot = s["Psi"][idx] * rod.omega, s["Theta"][idx] * rod.omega
        ref = analytic.tip_acceleration(
            rod, np.tile(s["psi"][idx], 6), np.tile(s["theta"][idx], 6), np.concatenate((Psi_dot, Psi_dot, zero, zero, zero, zero)),
            np.concatenate((Theta_dot, Theta_dot, zero, zero, zero, zero)), np.concatenate((F, np.zeros((2 * k, 3)), unit.reshape(-1, 3))),
        ).reshape(6, k, 3) / acc_scale  # fmt: skip
        ref_acc[idx], ref_free[idx] = ref[0], ref[1]
        for j in range(3):
            ref_G[idx, :, j] = ref[3 + j] - ref[2]
        if bar is not None:
            bar.update(k)
    if bar is not None:
        bar.close()

    theta, Psi, Theta, alpha, mu = s["theta"], s["Psi"], s["Theta"], s["alpha"], s["mu"]
    ref_b = analytic.b(Psi, Theta, theta)
    ref_p = analytic.p(theta, s["varphi"], mu, alpha)
    # Term scales (scaled units).  Eq. linode2 sums force terms with coefficients <= 1 + alpha, velocity
    # terms and gravity 1; Pinocchio's spatial algebra also forms products of the linear velocities
    # with the rates that cancel only in exact arithmetic, so the velocity terms are measured by
    # V = (1 + |v_s|_1)^2 over all five scaled velocities, not by Psi^2 + Theta^2 alone.
    rates = 1 + np.abs(v_scaled).sum(axis=1)
    V = rates**2
    A = (1 + alpha) * np.abs(s["F"]).sum(axis=1) + V
    cos = np.cos(theta)
    kappa = 1.0 / cos**2  # condition number of M in its natural units diag(m, m, m, I0, I0)
    where = {k: s[k] for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi", "alpha", "mu", "m", "l", "I0", "g")}
    stats = [
        _stat("tip acc, aba", pin_acc["aba"], ref_acc, pinocchio_tol.PIN_TIP_ACCELERATION, where, scale=A / cos),
        _stat("tip acc, G F + free", pin_acc["delassus"], ref_acc, pinocchio_tol.PIN_THROUGH_MINV, where, scale=kappa * A),
        _stat("Delassus G", pin_G, ref_G, pinocchio_tol.PIN_THROUGH_MINV, where, scale=kappa * (1 + alpha)),
        _stat("free tip acc", pin_acc["free"], ref_free, pinocchio_tol.PIN_THROUGH_MINV, where, scale=kappa * V),
        _stat("M (crba)", pin_M, ref_M, pinocchio_tol.PIN_MATRICES, where),
        _stat("C (Coriolis matrix)", pin_C, ref_C, pinocchio_tol.PIN_MATRICES, where, scale=rates),
        _stat("g (gravity)", pin_g, ref_g, pinocchio_tol.PIN_MATRICES, where),
        _stat("C v + g = nle", pin_Cv, pin_nle, pinocchio_tol.PIN_MATRICES, where, scale=V),
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
    stats.append(error_stat("mode", np.where(boundary, ref_mode, pin_mode), ref_mode, pinocchio_tol.PIN_MODE, where))
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
        "tip_acc_error_over_A_by_cos_theta": _by_decade(cos, {
            "aba": np.abs(pin_acc["aba"] - ref_acc).max(axis=1) / A,
            "G F + free": np.abs(pin_acc["delassus"] - ref_acc).max(axis=1) / A,
        }),
        "tolerances": {k: v for k, v in tol.all_tolerances().items() if k.startswith("PIN_")},
    }
    return ValidationResult(engine="pinocchio", stats=stats, extra=extra)
