"""The slender rod as a Pinocchio model (M, C, g, J, Delassus), answering the questions of ``crosscheck.theory.analytic``.

This is the model of the Pinocchio engine: its dynamics terms are checked
against the paper's equations (``crosscheck.engines.pinocchio.studies.dynamics_terms``), and a
time-stepping engine on Pinocchio's constraint solvers shares it.

The model: a chain of single-axis joints PX, PY, PZ, RZ (psi), RX
(theta), so that q = (X, Y, Z, psi, theta) is ``crosscheck.coordinates.GENERALIZED``
and the body rotation is Rz(psi) Rx(theta) (eq. rotmatrix).  The body's spatial
inertia is mass m at the centre S (the origin of the RX joint frame) with the
rotational inertia diag(I0, 0, I0) about S (eq. inertia).  Pinocchio 4.1
accepts this singular inertia as it is: ``crba`` gives M = diag(m, m, m,
I0 cos^2 theta, I0), positive definite on 0 < theta < pi/2, and ``aba`` runs
without regularisation (tested).  None is applied; had one been needed, an
axial inertia eps_r I0 would have added eps_r I0 sin^2 theta to M_psipsi, a
relative error eps_r tan^2 theta in the psi direction (1e4 eps_r at
cos theta = 1e-2).  The operational frame ``tip`` sits at A, at
(0, -l, 0) in the body frame.  We do not use a composite joint: in pin 4.1 its
Coriolis matrix and Jacobian time variation are wrong.

What Pinocchio computes (``RodTerms``): M (``crba``), C (``computeCoriolisMatrix``),
g (``computeGeneralizedGravity``), the nonlinear effects C v + g
(``nonLinearEffects``), the tip Jacobian J and its time variation dJ in
LOCAL_WORLD_ALIGNED (translation rows only, world axes), and from them the
Delassus matrix G = J M^-1 J^T and the free tip acceleration
dJ v - J M^-1 (C v + g).  The tip acceleration under a tip force F is then
G F + free acceleration (eq. linode2), or, by an independent route, the
frame's classical acceleration after ``aba`` with tau = J^T F.

Accuracy.  The two routes differ near the vertical rod: Pinocchio forms
M_psipsi = I0 cos^2 theta with an absolute rounding error of about eps I0, so
every quantity that goes through M^-1 in the psi direction (G, the free
acceleration, G F + free) carries a relative error ~ eps / cos^2 theta, the
condition number of M in its natural units diag(m, m, m, I0, I0).  ``aba``
never forms M; its bias forces carry an absolute eps I0 |v|^2 that the
articulated inertia I0 cos^2 theta and J_psi = l cos theta turn into
~ eps / cos theta.  The vertical components (b, p) see neither: the tip's
height does not depend on psi.  Measured numbers and the tolerances are in
the Pinocchio section of ``crosscheck.tolerances``.

The module-level functions have the names, signatures and meaning of their
counterparts in ``crosscheck.theory.analytic``; every conversion between the paper's
variables and (q, v) goes through ``crosscheck.coordinates``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
import pinocchio as pin
from scipy.optimize import minimize_scalar

from crosscheck.checks import ALPHA, MU, check
from crosscheck.coordinates import GENERALIZED, paper_to_qv
from crosscheck.engines.pinocchio import spd
from crosscheck.rod import Rod
from crosscheck.theory import analytic
from crosscheck.theory.analytic import _force_components  # same check and message as the reference

__all__ = [
    "TIP_FRAME",
    "JOINT_TYPES",
    "ROUTES",
    "build_model",
    "PinocchioRod",
    "RodTerms",
    "engine",
    "slip_coefficients",
    "slip_coefficients_of",
    "symmetrised",
    "tip_acceleration",
    "b",
    "p",
    "normal_force",
    "mode",
    "mu_P",
]

#: Name of the operational frame at the tip A.
TIP_FRAME = "tip"

#: One single-axis joint per generalised coordinate, in the order of ``GENERALIZED``.
JOINT_TYPES = dict(
    zip(GENERALIZED, (pin.JointModelPX, pin.JointModelPY, pin.JointModelPZ, pin.JointModelRZ, pin.JointModelRX))
)

#: Routes of ``tip_acceleration``: "delassus" = G F + free acceleration; "aba" = aba with tau = J^T F,
#: then the tip frame's classical acceleration.
ROUTES = ("delassus", "aba")

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def build_model(rod: Rod) -> pin.Model:
    """The rod as a ``pinocchio.Model`` with joints named as ``GENERALIZED`` and the frame ``TIP_FRAME``.

    Gravity is (0, 0, -g) [m/s^2]; all placements are the identity, so the
    RX joint's frame has its origin at S and its axes are the body axes (i, j, k).
    """
    model = pin.Model()
    model.name = "painleve_rod"
    model.gravity.linear[:] = (0.0, 0.0, -rod.gravity)
    parent = 0
    for name, joint in JOINT_TYPES.items():
        parent = model.addJoint(parent, joint(), pin.SE3.Identity(), name)
    model.appendBodyToJoint(parent, _body(rod), pin.SE3.Identity())
    model.addFrame(pin.Frame(TIP_FRAME, parent, _tip_placement(rod), pin.FrameType.OP_FRAME))
    return model


def _body(rod: Rod) -> pin.Inertia:
    # Slender rod along the body j axis: no inertia about it (eq. inertia).
    return pin.Inertia(rod.mass, np.zeros(3), np.diag([rod.inertia, 0.0, rod.inertia]))


def _tip_placement(rod: Rod) -> pin.SE3:
    return pin.SE3(np.eye(3), np.array([0.0, -rod.length, 0.0]))


@dataclass(frozen=True)
class RodTerms:
    """Pinocchio's dynamics terms of the rod at N states (physical units, world axes).

    Attributes:
      v: (N, 5) generalised velocities [m/s, rad/s].
      M: (N, 5, 5) joint-space inertia matrix (crba, symmetrised).
      C: (N, 5, 5) Coriolis matrix, C v = Coriolis and centrifugal forces.
      g: (N, 5) generalised gravity.
      nle: (N, 5) nonLinearEffects = C v + g computed by RNEA.
      J: (N, 3, 5) tip Jacobian, translation rows, LOCAL_WORLD_ALIGNED.
      dJ: (N, 3, 5) its time variation, same frame: tip acceleration = J a + dJ v.
    """

    v: np.ndarray
    M: np.ndarray
    C: np.ndarray
    g: np.ndarray
    nle: np.ndarray
    J: np.ndarray
    dJ: np.ndarray

    @cached_property
    def bias(self) -> np.ndarray:
        """C v + g, (N, 5) [N, N m]: the generalised bias forces from C and g (compare ``nle``; read-only, computed once)."""
        return _read_only(np.einsum("nij,nj->ni", self.C, self.v) + self.g)

    @cached_property
    def _solved(self) -> tuple[np.ndarray, np.ndarray]:
        # With M = L L^T (Cholesky; M is symmetric positive definite): W = L^-1 J^T (5, 3, N) and z = L^-1 (C v + g)
        # (5, N), one forward substitution for both, so that G = W^T W and J M^-1 (C v + g) = W^T z (no backward one).
        rhs = np.empty((5, 4, self.M.shape[0]))
        rhs[:, :3] = self.J.transpose(2, 1, 0)
        rhs[:, 3] = self.bias.T
        w = spd.forward_solve(spd.cholesky_columns(self.M), rhs)
        return w[:, :3], w[:, 3]

    @cached_property
    def _delassus(self) -> np.ndarray:
        w, _ = self._solved
        return _read_only(np.einsum("kin,kjn->nij", w, w))

    @cached_property
    def _free(self) -> np.ndarray:
        w, z = self._solved
        return _read_only(np.einsum("nij,nj->ni", self.dJ, self.v) - np.einsum("kin,kn->ni", w, z))

    def delassus(self) -> np.ndarray:
        """G = J M^-1 J^T, (N, 3, 3) [m/s^2 per N]: tip acceleration per unit tip force (read-only, computed once)."""
        return self._delassus

    def free_acceleration(self) -> np.ndarray:
        """dJ v - J M^-1 (C v + g), (N, 3) [m/s^2]: tip acceleration without contact force (read-only, computed once)."""
        return self._free

    def tip_acceleration(self, force) -> np.ndarray:
        """G F + free acceleration, (N, 3) [m/s^2], for tip forces F of shape (N, 3) [N]."""
        return np.einsum("nij,nj->ni", self.delassus(), np.asarray(force, float)) + self.free_acceleration()


def _read_only(x: np.ndarray) -> np.ndarray:
    # shared by every caller of a RodTerms method: an in-place change would corrupt the others' results
    x.flags.writeable = False
    return x


_LOWER = np.tril_indices(5, -1)


def symmetrised(M: np.ndarray) -> np.ndarray:
    """M (N, 5, 5) from its upper triangle (``crba`` fills the upper triangle only).

    Each entry is its upper-triangle value plus 0.0, as triu(M) + triu(M, 1)^T forms it (a -0.0 becomes
    0.0), in a third of the time.
    """
    out = np.add(M, 0.0)
    out[:, _LOWER[0], _LOWER[1]] = out[:, _LOWER[1], _LOWER[0]]
    return out


def _rows(x, n: int) -> np.ndarray:
    x = np.ascontiguousarray(np.broadcast_to(np.asarray(x, dtype=float), (n, 5)))
    return x


class PinocchioRod:
    """A ``Rod`` built in Pinocchio with its own ``pinocchio.Data``; evaluates batches of states.

    Not thread-safe (one Data).  ``engine(rod)`` returns a cached instance.
    """

    def __init__(self, rod: Rod):
        self.rod = rod
        self.model = build_model(rod)
        self.data = self.model.createData()
        self.tip = self.model.getFrameId(TIP_FRAME)

    def set_rod(self, rod: Rod) -> None:
        """Make this the engine of ``rod`` in place: gravity, the body's inertia and the tip's placement as ``build_model``
        sets them; the joints and the data are kept (the data carries no parameter of the rod from one call to the next).

        A fraction of the cost of a new ``PinocchioRod`` where rods follow one another (``dynamics_terms.validate``);
        not for the shared instances of ``engine``.
        """
        model = self.model
        model.gravity.linear[:] = (0.0, 0.0, -rod.gravity)
        model.inertias[model.njoints - 1] = _body(
            rod
        )  # the body alone on the last joint, as appendBodyToJoint leaves it
        model.frames[self.tip].placement = _tip_placement(rod)
        self.rod = rod

    def terms(self, q, v) -> RodTerms:
        """Pinocchio's M, C, g, C v + g, J, dJ at the states (q, v), each (N, 5) (see ``RodTerms``)."""
        q = np.atleast_2d(np.asarray(q, float))
        n = q.shape[0]
        q, v = _rows(q, n), _rows(v, n)
        M, C, J6, dJ6 = (np.empty((n, k, 5)) for k in (5, 5, 6, 6))
        g, nle = np.empty((n, 5)), np.empty((n, 5))
        self.fill_terms(q, v, M, C, g, nle, J6, dJ6)
        return RodTerms(
            v=v,
            M=symmetrised(M),
            C=C,
            g=g,
            nle=nle,
            J=np.ascontiguousarray(J6[:, :3]),
            dJ=np.ascontiguousarray(dJ6[:, :3]),
        )

    def fill_terms(self, q, v, M, C, g, nle, J6, dJ6) -> None:
        """Pinocchio's terms at (q, v) ((N, 5) C-contiguous arrays) written into preallocated arrays (views of larger ones allowed).

        M (N, 5, 5) upper triangle only, as ``crba`` fills it (``symmetrised`` completes it); C (N, 5, 5); g,
        nle (N, 5); J6, dJ6 (N, 6, 5): the whole frame Jacobian and its time variation, LOCAL_WORLD_ALIGNED
        (rows 0-2 translation).  The loop holds only the Pinocchio calls and one append of each result's bytes
        to a buffer, copied into the outputs once after the loop: at ~0.6 us per call, a slice, an attribute
        lookup, an item assignment or a temporary per state costs a large part of a call
        (``benchmarks/bench_pinocchio.py``).
        """
        model, data, tip, lwa = self.model, self.data, self.tip, _LWA
        crba, coriolis, gravity, nonlinear = (
            pin.crba,
            pin.computeCoriolisMatrix,
            pin.computeGeneralizedGravity,
            pin.nonLinearEffects,
        )
        jacobians_dt, frame_jacobian, frame_jacobian_dt = (
            pin.computeJointJacobiansTimeVariation,
            pin.getFrameJacobian,
            pin.getFrameJacobianTimeVariation,
        )
        buffers = [bytearray() for _ in range(6)]
        put_M, put_C, put_g, put_nle, put_J, put_dJ = (b.extend for b in buffers)
        # extend() copies a C-contiguous float64 result through the buffer protocol (a non-contiguous one raises
        # BufferError): cheaper than M[i] = ..., and the result is freed at once, so numpy's small-array cache
        # serves the next call (keeping the results in lists until the end is slower).
        for qi, vi in zip(q, v):
            put_M(crba(model, data, qi))
            put_C(coriolis(model, data, qi, vi))
            put_g(gravity(model, data, qi))
            put_nle(nonlinear(model, data, qi, vi))
            jacobians_dt(model, data, qi, vi)
            put_J(frame_jacobian(model, data, tip, lwa))
            put_dJ(frame_jacobian_dt(model, data, tip, lwa))
        for out, buffer in zip((M, C, g, nle, J6, dJ6), buffers):
            out[...] = np.frombuffer(buffer).reshape(out.shape)

    def aba_tip_acceleration(self, q, v, force, *, J=None) -> np.ndarray:
        """Tip acceleration (N, 3) [m/s^2] by ``aba`` with tau = J^T F, then the frame's classical acceleration.

        ``J`` (N, 3, 5) may be passed when already known (e.g. ``terms(q, v).J``);
        otherwise Pinocchio computes it here.
        """
        q = np.atleast_2d(np.asarray(q, float))
        n = q.shape[0]
        q, v = _rows(q, n), _rows(v, n)
        force = np.ascontiguousarray(np.broadcast_to(np.asarray(force, float), (n, 3)))
        if J is None:
            J = self.jacobian(q)
        out = np.empty((n, 3))
        self.fill_aba_tip_acceleration(q, v, np.einsum("nij,ni->nj", J, force), out)
        return out

    def fill_aba_tip_acceleration(self, q, v, tau, out) -> None:
        """``aba`` with the generalised forces tau (N, 5), then the tip's classical acceleration written into ``out`` (N, 3)."""
        model, data, tip, lwa = self.model, self.data, self.tip, _LWA
        aba, kinematics, classical = pin.aba, pin.forwardKinematics, pin.getFrameClassicalAcceleration
        buffer = bytearray()
        put = buffer.extend  # as in fill_terms
        for qi, vi, ti in zip(q, v, tau):
            kinematics(model, data, qi, vi, aba(model, data, qi, vi, ti))
            put(classical(model, data, tip, lwa).linear)
        out[...] = np.frombuffer(buffer).reshape(out.shape)

    def jacobian(self, q) -> np.ndarray:
        """Tip Jacobian (N, 3, 5), translation rows, LOCAL_WORLD_ALIGNED."""
        q = np.atleast_2d(np.asarray(q, float))
        n = q.shape[0]
        q = _rows(q, n)
        out = np.empty((n, 3, 5))
        for i in range(n):
            out[i] = pin.computeFrameJacobian(self.model, self.data, q[i], self.tip, _LWA)[:3]
        return out

    def tip_position(self, q) -> np.ndarray:
        """Tip A in the world frame (N, 3) [m], from Pinocchio's frame placement."""
        q = np.atleast_2d(np.asarray(q, float))
        n = q.shape[0]
        q = _rows(q, n)
        out = np.empty((n, 3))
        for i in range(n):
            pin.framesForwardKinematics(self.model, self.data, q[i])
            out[i] = self.data.oMf[self.tip].translation
        return out

    def mass_matrix(self, q) -> np.ndarray:
        """M(q) (N, 5, 5) by crba, symmetrised (for finite differences of M along a path)."""
        q = np.atleast_2d(np.asarray(q, float))
        return self.terms(q, np.zeros_like(q)).M


@lru_cache(maxsize=512)
def engine(rod: Rod) -> PinocchioRod:
    """The cached ``PinocchioRod`` of ``rod`` (Rod is frozen, hence hashable)."""
    return PinocchioRod(rod)


# --------------------------------------------------------------------------
# The questions of crosscheck.theory.analytic
# --------------------------------------------------------------------------


def slip_coefficients(rod: Rod, terms: RodTerms, beta, mu) -> tuple[np.ndarray, np.ndarray]:
    """Scaled (b, p) of eqs. b and p from Pinocchio's free acceleration and Delassus matrix.

    In physical units the vertical tip acceleration under Coulomb sliding
    friction F = F_z (-mu cos beta, -mu sin beta, 1) is
    e_z^T (free + G F) = e_z^T free + (e_z^T G (e_z - mu t_hat)) F_z,
    t_hat = (cos beta, sin beta, 0).  Scaling accelerations by g and forces by
    m g gives b = e_z^T free / g and p = m e_z^T G (e_z - mu t_hat).

    Args:
      rod: the rod of ``terms`` (physical units).
      terms: ``RodTerms`` of N states.
      beta: slip angle psi + varphi [rad], (N,) or scalar.
      mu: friction coefficient, (N,) or scalar.

    Returns:
      (b, p), each (N,).
    """
    return slip_coefficients_of(terms, beta, mu, mass=rod.mass, gravity=rod.gravity)


def slip_coefficients_of(terms: RodTerms, beta, mu, *, mass, gravity) -> tuple[np.ndarray, np.ndarray]:
    """``slip_coefficients`` with the rod's mass m [kg] and gravity g [m/s^2] given per state ((N,) arrays) or as scalars.

    For terms of many rods at once (``crosscheck.engines.pinocchio.studies.dynamics_terms``): the
    arithmetic per state is the same as with one rod's scalars.
    """
    n = terms.M.shape[0]
    beta = np.broadcast_to(np.asarray(beta, float), (n,))
    mu = np.broadcast_to(np.asarray(mu, float), (n,))
    G = terms.delassus()
    free = terms.free_acceleration()
    direction = np.stack((-mu * np.cos(beta), -mu * np.sin(beta), np.ones(n)), axis=-1)  # e_z - mu t_hat
    return free[:, 2] / gravity, mass * np.einsum("nj,nj->n", G[:, 2, :], direction)


def tip_acceleration(rod: Rod, psi, theta, psi_dot, theta_dot, force, *, route: str = "delassus") -> np.ndarray:
    """Acceleration (x'', y'', z'') of the tip A computed by Pinocchio (compare eq. linode2).

    Args:
      rod: the rod, in physical units (m, l, I0, g).
      psi: azimuthal angle [rad].
      theta: polar angle [rad], in (0, pi/2).
      psi_dot, theta_dot: angular rates [rad/s].
      force: contact force (Fx, Fy, Fz) [N] applied at A, world frame, shape (..., 3).
      route: "delassus" (G F + free acceleration) or "aba" (aba with tau = J^T F,
        then the tip frame's classical acceleration); see ``ROUTES``.

    Returns:
      (..., 3) array of tip accelerations [m/s^2], world frame, gravity included.
      Arguments broadcast as in ``crosscheck.theory.analytic.tip_acceleration``.
    """
    if route not in ROUTES:
        raise ValueError(f"route must be one of {', '.join(ROUTES)}; got {route!r}")
    fx, fy, fz = _force_components(force)
    force = np.stack((fx, fy, fz), axis=-1)
    psi, psi_dot, theta_dot = (check(n, x) for n, x in (("psi", psi), ("psi_dot", psi_dot), ("theta_dot", theta_dot)))
    # The tip acceleration does not depend on where S is nor on how fast it translates: place the
    # tip at rest at the origin (eta = 0) and convert the rates to the paper's scaled ones.
    q, v = paper_to_qv(rod, theta, 0.0, theta_dot / rod.omega, psi_dot / rod.omega, 0.0, psi)
    shape = np.broadcast_shapes(q.shape[:-1], force.shape[:-1])
    q = np.broadcast_to(q, shape + (5,)).reshape(-1, 5)
    v = np.broadcast_to(v, shape + (5,)).reshape(-1, 5)
    force = np.broadcast_to(force, shape + (3,)).reshape(-1, 3)
    rod_engine = engine(rod)
    if route == "aba":
        out = rod_engine.aba_tip_acceleration(q, v, force)
    else:
        out = rod_engine.terms(q, v).tip_acceleration(force)
    return out.reshape(shape + (3,))


def _scaled_slip(theta, varphi, Theta, Psi, mu, alpha) -> tuple[np.ndarray, np.ndarray]:
    """(b, p) at broadcast scaled states, one Pinocchio model per distinct alpha (``Rod.scaled``)."""
    mu = check("mu", mu, MU)
    alpha = check("alpha", alpha, ALPHA)
    varphi = check("varphi", varphi)
    theta, varphi, Theta, Psi, mu, alpha = np.broadcast_arrays(
        *(np.asarray(x, float) for x in (theta, varphi, Theta, Psi, mu, alpha))
    )
    shape = theta.shape
    flat = [x.reshape(-1) for x in (theta, varphi, Theta, Psi, mu, alpha)]
    theta, varphi, Theta, Psi, mu, alpha = flat
    b_out = np.empty(theta.shape)
    p_out = np.empty(theta.shape)
    values, inverse = np.unique(alpha, return_inverse=True)
    for k, a in enumerate(values):
        rod = Rod.scaled(float(a))
        idx = np.flatnonzero(inverse == k)
        # eta = 1: a slipping tip with heading beta = psi + varphi (psi = 0).
        q, v = paper_to_qv(rod, theta[idx], varphi[idx], Theta[idx], Psi[idx], 1.0, 0.0)
        b_out[idx], p_out[idx] = slip_coefficients(rod, engine(rod).terms(q, v), varphi[idx], mu[idx])
    return b_out.reshape(shape), p_out.reshape(shape)


def b(Psi, Theta, theta):
    """Scaled vertical free acceleration of the tip from Pinocchio (compare eq. b).

    e_z^T (dJ v - J M^-1 (C v + g)) / g at psi = 0 on the scaled rod (alpha = 3;
    b does not depend on alpha, m, I0 or psi).  Arrays broadcast.
    """
    out, _ = _scaled_slip(theta, 0.0, Theta, Psi, 0.0, 3.0)
    return out


def p(theta, varphi, mu, alpha):
    """Scaled vertical tip acceleration per unit normal force while slipping, from Pinocchio (compare eq. p).

    p = e_z^T G (e_z - mu t_hat) on ``Rod.scaled(alpha)``, t_hat = (cos beta,
    sin beta, 0) the unit slip direction, beta = psi + varphi (psi = 0; p does
    not depend on psi).  Arrays broadcast.
    """
    _, out = _scaled_slip(theta, varphi, 0.0, 0.0, mu, alpha)
    return out


def normal_force(Psi, Theta, theta, varphi, mu, alpha):
    """Scaled normal force F_z = -b / p from Pinocchio's b and p (compare eq. FZ); inf where p = 0."""
    bb, pp = _scaled_slip(theta, varphi, Theta, Psi, mu, alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        return -bb / pp


#: The LCP mode of (b, p) (section 3.1) is engine-independent: feed it this module's b and p.
mode = analytic.mode


def mu_P(alpha, *, xatol: float = 1e-10) -> float:
    """Painleve's critical friction found numerically from this module's ``p`` alone.

    The smallest mu at which min over theta in (0, pi/2) of p(theta, -pi/2, mu,
    alpha) touches 0 (compare eq. mup2D, 2 sqrt(1 + alpha) / alpha).  p is
    affine in mu (eq. p: p = p0 - mu p1, p1 = p(mu = 0) - p(mu = 1) > 0 on
    (0, pi/2) at varphi = -pi/2), so p(theta, mu) <= 0 exactly where
    mu >= p0 / p1, and mu_P = min over theta of p0 / p1: one bounded Brent
    search in theta (to ``xatol``), whose minimum value is accurate to rounding
    because the ratio is flat there.
    """
    alpha = float(check("alpha", alpha, ALPHA))
    # p(theta, -pi/2, mu, alpha) as ``p`` computes it (the same (q, v), terms and slip_coefficients, hence the same
    # value to the last bit), without its per-call checks and grouping by alpha: Brent calls it ~30 times.
    rod = Rod.scaled(alpha)
    varphi = np.array([-math.pi / 2])
    mus = np.array([0.0, 1.0])

    def ratio(theta: float) -> float:
        q, v = paper_to_qv(rod, np.full(2, float(theta)), np.repeat(varphi, 2), np.zeros(2), np.zeros(2), 1.0, 0.0)
        p0, p_one = slip_coefficients(rod, engine(rod).terms(q, v), np.repeat(varphi, 2), mus)[1]
        slope = p0 - p_one
        return float(p0 / slope) if slope > 0.0 else math.inf

    res = minimize_scalar(ratio, bounds=(0.0, math.pi / 2), method="bounded", options={"xatol": xatol})
    return float(res.fun)
