"""MuJoCo's instantaneous contact law for the capsule rod: the force its solver computes at one state.

MuJoCo (Computation chapter, "Constraint model" and "Solver") finds the
contact force f of one elliptic condim-3 contact by the convex problem

    f = argmin_{f in K}  1/2 f^T (A + R) f + f^T (a0 - aref),
    K = {f : f_n >= 0, |f_t| <= mu f_n}                        (elliptic cone)

in the contact frame (rows: normal n = +z, tangents t1, t2), where

* A = J M^-1 J^T is the Delassus operator at MuJoCo's contact point
  P = A_tip - (r + dist/2) K (midway into the penetration ``dist`` < 0 below
  the cap centre A), J the 3 x 5 Jacobian of the rod's material point at P
  (rows n, t1, t2), M the rod's mass matrix in q = (X, Y, Z, psi, theta);
* a0 = J qacc_smooth, the unconstrained contact-point acceleration *without*
  the dJ/dt v term (MuJoCo's constraint acceleration is J qacc);
* aref = -B J v - K imp (dist, 0, 0): the reference acceleration of solref
  (timeconst tau, dampratio zeta) with B = 2 / (dmax tau),
  K = 1 / (dmax^2 tau^2 zeta^2) on the normal row; the friction rows have
  K = 0 and take their tau from solreffriction when it is set;
* imp = d(|dist|) the impedance of solimp (d0, dmax, width, midpoint, power):
  d0 + y(x) (dmax - d0), x = |dist| / width clipped to [0, 1], y the power
  sigmoid a x^p below the midpoint and 1 - b (1 - x)^p above it;
* R = (1 - imp) / imp * diagApprox, diagApprox = the *translational*
  ``body_invweight0`` of the rod (the floor's is 0): a constant of the model,
  the mean diagonal of the body-centre-of-mass Delassus operator at qpos0,
  1/m for this rod (its slides act at the centre of mass), not A's diagonal;
  the friction rows have R_t = R_n / impratio.

The primal form that MuJoCo's Newton solver minimises (over qacc: the Gauss
cost plus the soft cone penalty of ``mj_constraintUpdate``) has this f as
its dual solution; tests/test_mujoco_law.py compares f, R and aref with
MuJoCo's efc_force, efc_R and efc_aref.

Why the friction is not opposite the slip.  On the cone's surface the
optimality condition is f_t = -lambda ((A + R) f + a0 - aref)_t, lambda >= 0,
and ((A + R) f + a0 - aref)_t = a_t + B v_t + R_t f_t with a_t = J_t qacc the
contact point's tangential acceleration.  R_t f_t is parallel to f_t, so
f_t is anti-parallel to v_t + a_t / B: MuJoCo's friction opposes the slip
velocity extrapolated over the friction damping time 1/B = dmax tau_f / 2,
not the slip velocity itself (``skew_angle``).  While slipping, aref_t =
-B v_t dominates g and f grows like B, so a_t / B does not shrink with
tau_f: the direction is that of the cone-constrained minimiser of
1/2 f^T (A + R) f + B v_t . f_t, which is -v_t only when the tangential block
of A + R is isotropic and decoupled from the normal row.  At the rod's
contact point it is neither: across the rod (along i) A_tt = (1 + alpha)/m,
along its horizontal projection (1 + alpha (sin theta + r/l)^2)/m, smaller
(1.28 against 4 at theta = 0.3, alpha = 3), and a push along the rod also
moves the point vertically (A_nt != 0); hence the skew; R_t = R_n / impratio is isotropic, so a
small impratio (R_t >> A_tt) dilutes it, at the price of a softer friction.
``crosscheck.engines.mujoco.studies.friction_skew`` measures all of this in MuJoCo.

Units.  ``contact_problem`` and the solver work in the rod's physical units
(MuJoCo's SI); ``contact_force`` returns the world force in m g.  q, v are
the generalised coordinates and velocities of ``crosscheck.coordinates``
(physical units, as MuJoCo's qpos, qvel); options are the MuJoCo engine's
scaled ``Options``, converted here exactly as ``build_model`` converts them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from crosscheck.checks import FINITE, MU, POSITIVE, check
from crosscheck.engines.mujoco.model import axial_inertia
from crosscheck.engines.mujoco.options import Options
from crosscheck.rod import Rod

__all__ = [
    "Parameters",
    "ContactProblem",
    "impedance",
    "inverse_weight",
    "mass_matrix",
    "smooth_force",
    "smooth_accelerations",
    "contact_problem",
    "solve_cone",
    "contact_frame",
    "contact_force",
    "accelerations",
    "skew_angle",
    "MINIMP",
    "MAXIMP",
    "MINVAL",
    "MINMU",
    "NO_FEED_FORWARD_IMPEDANCE",
]

#: MuJoCo's clamps (mjMINIMP, mjMAXIMP: impedance parameters; mjMINVAL: smallest R; mjMINMU: smallest friction,
#: so that mu = 0 is a cone of opening 1e-5, not a frictionless contact).
MINIMP, MAXIMP, MINVAL, MINMU = 1e-4, 0.9999, 1e-15, 1e-5

#: The normal row's impedance of the law without its feed-forward (``contact_problem``): the fraction of the
#: rigid normal force fed forward at once, 0.95 by default and this much without; the rest of the law's force
#: is its solref spring-damper, to within this fraction.
NO_FEED_FORWARD_IMPEDANCE = 1e-3

#: Sample count of the slip direction on the cone's surface before the stationarity root is polished:
#: 5 degrees apart, so the two sign changes of the stationarity function around the optimum are bracketed.
CONE_SAMPLES = 72


@dataclass(frozen=True)
class Parameters:
    """A run's MuJoCo contact parameters in the rod's physical units (as the compiled model holds them).

    Attributes: radius r [m]; timeconst, friction_timeconst [s] (after MuJoCo's
    "refsafe" max(tau, 2 timestep)); dampratio; solimp with width in m;
    impratio; dmax (clamped solimp[1]); feed_forward: False for the law
    without its feed-forward (``contact_problem``).
    """

    radius: float
    timeconst: float
    friction_timeconst: float
    dampratio: float
    solimp: tuple
    impratio: float
    feed_forward: bool = True

    @classmethod
    def of(cls, rod: Rod, options: Options, *, impratio: float | None = None, feed_forward: bool = True) -> Parameters:
        """Convert scaled ``Options`` as ``crosscheck.engines.mujoco.model.build_model`` does (impratio: the options' unless given;
        ``feed_forward``: as the attribute)."""
        if not isinstance(options, Options):
            raise ValueError(f"options must be crosscheck.engines.mujoco.options.Options; got {type(options).__name__}")
        impratio = float(check("impratio", options.impratio if impratio is None else impratio, POSITIVE))
        w, l = rod.omega, rod.length
        dt = options.timestep / w
        tau = max(options.timeconst / w, 2 * dt)
        tau_f = tau if options.friction_timeconst is None else max(options.friction_timeconst / w, 2 * dt)
        d0, dmax, width, mid, power = options.solimp
        # getsolparam's clamps
        solimp = (
            min(MAXIMP, max(MINIMP, d0)),
            min(MAXIMP, max(MINIMP, dmax)),
            max(0.0, width * l),
            min(MAXIMP, max(MINIMP, mid)),
            max(1.0, power),
        )
        return cls(options.radius * l, tau, tau_f, options.dampratio, solimp, impratio, bool(feed_forward))

    @property
    def damping(self) -> tuple[float, float]:
        """(B normal, B friction) [1/s]: 2 / (dmax tau)."""
        dmax = self.solimp[1]
        return 2.0 / (dmax * self.timeconst), 2.0 / (dmax * self.friction_timeconst)

    @property
    def stiffness(self) -> float:
        """K of the normal row [1/s^2]: 1 / (dmax^2 tau^2 zeta^2) (the friction rows have K = 0)."""
        dmax = self.solimp[1]
        return 1.0 / (dmax * dmax * self.timeconst**2 * self.dampratio**2)


def impedance(solimp, dist) -> np.ndarray:
    """MuJoCo's impedance d(dist) of solimp (d0, dmax, width [m], midpoint, power); vectorised in dist [m]."""
    d0, dmax, width, mid, power = solimp
    if isinstance(
        dist, float
    ):  # one distance (the contact law's hot loop): the same operations on numpy's float64 scalars
        return _impedance_scalar(d0, dmax, width, mid, power, dist)
    dist = np.asarray(dist, dtype=float)
    if d0 == dmax or width <= 1e-15:
        return np.full(dist.shape, 0.5 * (d0 + dmax))
    x = np.clip(np.abs(dist) / width, 0.0, 1.0)
    if power == 1:
        y = x
    else:
        lo = x**power / mid ** (power - 1)
        hi = 1 - (1 - x) ** power / (1 - mid) ** (power - 1)
        y = np.where(x <= mid, lo, hi)
    return d0 + y * (dmax - d0)


def _impedance_scalar(d0, dmax, width, mid, power, dist: float) -> np.ndarray:
    """``impedance`` of one distance, operation for operation (np.float64 scalars: numpy's scalar power, as the
    array path's 0-d results take), without the array machinery that cost 15 us a call; a 0-d array as before."""
    if d0 == dmax or width <= 1e-15:
        return np.asarray(0.5 * (d0 + dmax))
    x = min(max(np.float64(abs(dist)) / width, 0.0), 1.0)  # np.clip's value: clipping is exact
    x = np.float64(x)
    if power == 1:
        y = x
    else:
        y = x**power / mid ** (power - 1) if x <= mid else 1 - (1 - x) ** power / (1 - mid) ** (power - 1)
    return np.asarray(d0 + y * (dmax - d0))


def inverse_weight(rod: Rod) -> float:
    """The rod's translational ``body_invweight0`` [1/kg]: MuJoCo's diagApprox of every contact row.

    MuJoCo's setConst takes the Jacobian of the body's centre of mass at
    qpos0, forms J M^-1 J^T and averages its translational diagonal.  The
    rod's centre of mass S is moved by the slides X, Y, Z only (the hinges act
    about S), so that block is I / m and the weight is 1/m, whatever the pose.
    """
    return 1.0 / rod.mass


def mass_matrix(rod: Rod, q) -> np.ndarray:
    """Diagonal of M(q) for q = (X, Y, Z, psi, theta): (m, m, m, I0 cos^2 + eps sin^2, I0) with eps the axial inertia."""
    st, ct = math.sin(q[4]), math.cos(q[4])
    I0 = rod.inertia
    return np.array([rod.mass, rod.mass, rod.mass, I0 * ct * ct + axial_inertia(I0) * st * st, I0])


def smooth_accelerations(rod: Rod, q, v) -> np.ndarray:
    """qacc without contact, M^-1 qfrc_smooth [physical]: ``contact_problem``'s ``qacc_smooth``, computed alone."""
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    return 1.0 / mass_matrix(rod, q) * smooth_force(rod, q, v)


def smooth_force(rod: Rod, q, v) -> np.ndarray:
    """Gravity minus the velocity-product terms of the rod's equations of motion (MuJoCo's qfrc_smooth) [N, N m]."""
    st, ct = math.sin(q[4]), math.cos(q[4])
    dI = (rod.inertia - axial_inertia(rod.inertia)) * st * ct  # -1/2 d(I_psi psi)/d theta
    return np.array([0.0, 0.0, -rod.mass * rod.gravity, 2.0 * dI * v[3] * v[4], -dI * v[3] * v[3]])


def _point_jacobian(rod: Rod, q, offset: float) -> np.ndarray:
    """World 3 x 5 Jacobian of the rod's material point P = A - offset K (v_P = J v)."""
    psi, theta = q[3], q[4]
    l = rod.length
    sp, cp, st, ct = math.sin(psi), math.cos(psi), math.sin(theta), math.cos(theta)
    rx, ry, rz = l * ct * sp, -l * ct * cp, -l * st - offset  # P - S
    J = np.zeros((3, 5))
    J[0, 0] = J[1, 1] = J[2, 2] = 1.0
    J[:, 3] = (-ry, rx, 0.0)  # K x (P - S)
    J[:, 4] = (sp * rz, -cp * rz, cp * ry - sp * rx)  # i x (P - S), i = (cos psi, sin psi, 0)
    return J


def contact_frame(psi: float) -> np.ndarray:
    """MuJoCo's plane-capsule contact frame (rows: normal +z, tangent 1, tangent 2 = normal x tangent 1).

    Tangent 1 is the capsule's axis from B towards A projected on the plane,
    (sin psi, -cos psi, 0) (as MuJoCo's contact.frame reports it).  The world force does not depend on the
    tangent's choice (R and B are the same on both friction rows).
    """
    sp, cp = math.sin(psi), math.cos(psi)
    return np.array([[0.0, 0.0, 1.0], [sp, -cp, 0.0], [cp, sp, 0.0]])


@dataclass(frozen=True, eq=False)
class ContactProblem:
    """MuJoCo's contact problem at one state, physical units, contact frame rows (n, t1, t2).

    Attributes:
      dist: signed distance of the capsule to the plane [m] (< 0: penetrating).
      imp: impedance d(dist).
      frame: (3, 3) contact frame, rows (n, t1, t2) in world coordinates.
      J: (3, 5) contact-frame Jacobian at MuJoCo's contact point.
      A: (3, 3) Delassus operator J M^-1 J^T [1/kg].
      R: (3,) regulariser [1/kg]; aref: (3,) reference acceleration [m/s^2].
      a0: (3,) unconstrained contact-point acceleration J qacc_smooth [m/s^2].
      vel: (3,) contact-point velocity J v [m/s]; mu: friction, at least MINMU as MuJoCo clamps it;
      B: (3,) damping [1/s].
      minv: (5,) inverse mass matrix diagonal; qacc_smooth: (5,).
    """

    dist: float
    imp: float
    frame: np.ndarray
    J: np.ndarray
    A: np.ndarray
    R: np.ndarray
    aref: np.ndarray
    a0: np.ndarray
    vel: np.ndarray
    mu: float
    B: np.ndarray
    minv: np.ndarray
    qacc_smooth: np.ndarray

    def force(self) -> np.ndarray:
        """The solution f of MuJoCo's convex problem, contact frame [N]."""
        return solve_cone(self.A + np.diag(self.R), self.a0 - self.aref, self.mu)


def contact_problem(
    rod: Rod, q, v, mu: float, options: Options, *, impratio: float | None = None, parameters: Parameters | None = None
) -> ContactProblem:
    """Build MuJoCo's contact problem at generalised (q, v) (physical) for friction mu and scaled ``options``.

    The contact is the A end cap's lowest point; the problem is built whatever
    the sign of dist (MuJoCo has the contact only while dist < 0: see
    ``contact_force``).  ``parameters``: ``Parameters.of(rod, options, impratio=impratio)`` when the caller
    already has it (an integration calls this at every evaluation with the same options).

    Without the feed-forward (``parameters.feed_forward`` False) the normal row
    has the constant impedance d_n = ``NO_FEED_FORWARD_IMPEDANCE``: its
    K, B and R at d_n, the friction rows as MuJoCo's (their R_t from the
    normal row's R at the solimp impedance, B_f at dmax).  Why this is the
    law without the feed-forward: the normal row's force is
    f_n = (aref_n - a0_n) / (A_nn + R_n) with R_n = (1 - d) / d w (w the
    inverse weight), so as d -> 0, f_n -> -((2 / tau) v_n + dist / (tau^2 zeta^2)) / w
    - d a0_n / w: solref's spring-damper alone, with a fraction d of the
    rigid force -a0_n / A_nn fed forward where MuJoCo's default feeds 0.9-0.95.
    What is left of MuJoCo's law then is its friction (the cone problem with
    its skewed direction and soft stick) on a spring-damper normal force, as
    the matched Kelvin-Voigt rod has.
    """
    par = Parameters.of(rod, options, impratio=impratio) if parameters is None else parameters
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    l = rod.length
    dist = q[2] - l * math.sin(q[4]) - par.radius  # z_A - r
    Jw = _point_jacobian(rod, q, par.radius + 0.5 * dist)
    frame = contact_frame(q[3])
    J = frame @ Jw
    minv = 1.0 / mass_matrix(rod, q)
    A = (J * minv) @ J.T
    qacc_smooth = minv * smooth_force(rod, q, v)
    a0 = J @ qacc_smooth
    vel = J @ v
    imp = float(impedance(par.solimp, dist))
    Bn, Bf = par.damping
    B = np.array([Bn, Bf, Bf])
    aref = -B * vel
    aref[0] -= par.stiffness * imp * dist
    w = inverse_weight(rod)
    Rn = max(MINVAL, (1.0 - imp) * w / imp)
    Rt = Rn / max(MINVAL, par.impratio)
    R = np.array([Rn, Rt, Rt])
    if not par.feed_forward:  # the normal row at the constant impedance d_n (docstring); the friction rows unchanged
        d = NO_FEED_FORWARD_IMPEDANCE
        B[0] = 2.0 / (d * par.timeconst)
        aref[0] = -B[0] * vel[0] - dist / (d * par.timeconst**2 * par.dampratio**2)  # K(d_n) d_n dist
        R[0] = (1.0 - d) * w / d
    mu = max(MINMU, float(mu))  # mj_assignFriction's clamp
    return ContactProblem(dist, imp, frame, J, A, R, aref, a0, vel, mu, B, minv, qacc_smooth)


def _cone_direction(a, mu):
    if isinstance(
        a, float
    ):  # one angle (Brent's iterations): the same numpy cosine and sine, without broadcasting's cost
        return np.array((1.0, mu * np.cos(a), mu * np.sin(a)))
    return np.stack(np.broadcast_arrays(1.0, mu * np.cos(a), mu * np.sin(a)), -1)


#: The sampled slip directions' angles of ``solve_cone`` (the same for every call).
_CONE_ANGLES = np.linspace(0.0, 2 * math.pi, CONE_SAMPLES, endpoint=False)
_CONE_ANGLES.flags.writeable = False

#: The sampled directions on the cone of each friction coefficient met (a run has one): mu -> (CONE_SAMPLES, 3).
_cone_samples: dict = {}


def _sampled_directions(mu: float) -> np.ndarray:
    d = _cone_samples.get(mu)
    if d is None:
        if len(_cone_samples) >= 256:  # a sweep over many mu: keep the memory bounded
            _cone_samples.clear()
        d = _cone_samples[mu] = _cone_direction(_CONE_ANGLES, mu)
        d.flags.writeable = False
    return d


def solve_cone(H: np.ndarray, g: np.ndarray, mu: float) -> np.ndarray:
    """argmin 1/2 f^T H f + g^T f over the cone |f_t| <= mu f_n (f_n = f[0]); H symmetric positive definite.

    Three cases: g in the dual cone (g_n >= mu |g_t|) gives f = 0; an
    unconstrained minimiser inside the cone is the answer; otherwise f lies on
    the surface, f = f_n (1, mu cos a, mu sin a) with f_n = -g.d / d^T H d, and
    a maximises (g.d)^2 / d^T H d (g.d < 0): sampled, then the root of its
    derivative is polished to machine precision by Brent's method.
    """
    g = np.asarray(g, dtype=float)
    if mu <= 0.0:
        return np.array([max(0.0, -g[0] / H[0, 0]), 0.0, 0.0])
    if g[0] >= mu * math.hypot(g[1], g[2]):
        return np.zeros(3)
    f = -np.linalg.solve(H, g)
    if f[0] >= 0.0 and math.hypot(f[1], f[2]) <= mu * f[0]:
        return f
    a = _CONE_ANGLES
    d = _sampled_directions(mu)
    N = d @ g
    D = np.einsum("ki,ij,kj->k", d, H, d)
    h = np.where(N < 0, N * N / D, -np.inf)
    k = int(np.argmax(h))

    # On Python floats: Brent's method calls it ~5 times a solve, and 3-vectors through numpy cost 6 us a call.
    g0, g1, g2 = g.tolist()
    (h00, h01, h02), (_, h11, h12), (_, _, h22) = H.tolist()

    def stationarity(x):  # (g.d') (d H d) - (g.d) (d' H d): zero where d/da (g.d)^2 / dHd = 0
        d1, d2 = mu * math.cos(x), mu * math.sin(x)  # d = (1, d1, d2), d' = (0, -d2, d1)
        Hd1, Hd2 = h01 + h11 * d1 + h12 * d2, h02 + h12 * d1 + h22 * d2
        dHd = h00 + h01 * d1 + h02 * d2 + d1 * Hd1 + d2 * Hd2
        return (g2 * d1 - g1 * d2) * dHd - (g0 + g1 * d1 + g2 * d2) * (d1 * Hd2 - d2 * Hd1)

    step = 2 * math.pi / CONE_SAMPLES
    lo, hi = a[k] - step, a[k] + step
    slo, shi = stationarity(lo), stationarity(hi)
    x = brentq(stationarity, lo, hi, xtol=1e-15, rtol=1e-15) if slo * shi < 0 else a[k]
    dd = _cone_direction(x, mu)
    fn = max(0.0, -(g @ dd) / (dd @ H @ dd))
    return fn * dd


def contact_force(rod: Rod, q, v, mu: float, options: Options, *, impratio: float | None = None) -> np.ndarray:
    """MuJoCo's contact force on the rod at generalised (q, v) [physical], world frame, in m g.

    Zero while the capsule does not penetrate (dist >= 0: MuJoCo keeps a
    contact only while dist < margin = 0).  mu is clamped to MINMU as MuJoCo
    does.  On the sliding mode at dist = 0 (``crosscheck.engines.mujoco.ode``)
    the motion applies a fraction lambda of this force, not all of it.  ``options``: the MuJoCo engine's
    scaled ``Options``; impratio the options' unless given.
    """
    mu = float(check("mu", mu, MU))
    q = check("q", q, FINITE)
    v = check("v", v, FINITE)
    if q.shape != (5,) or v.shape != (5,):
        raise ValueError(f"q and v must each have 5 numbers (X, Y, Z, psi, theta); got shapes {q.shape} and {v.shape}")
    pb = contact_problem(rod, q, v, mu, options, impratio=impratio)
    if pb.dist >= 0.0:
        return np.zeros(3)
    return pb.frame.T @ pb.force() / rod.force_scale


def accelerations(
    rod: Rod,
    q,
    v,
    mu: float,
    options: Options,
    *,
    contact: bool,
    impratio: float | None = None,
    parameters: Parameters | None = None,
):
    """qacc [physical] and the contact force (contact frame [N]) under MuJoCo's law; ``contact`` says whether the contact exists
    (``parameters``: as ``contact_problem``)."""
    pb = contact_problem(rod, q, v, mu, options, impratio=impratio, parameters=parameters)
    if not contact:
        return pb.qacc_smooth, np.zeros(3), pb
    f = pb.force()
    return pb.qacc_smooth + pb.minv * (pb.J.T @ f), f, pb


def skew_angle(slip, accel, damping) -> np.ndarray:
    """Angle [rad] from -slip to MuJoCo's friction on the cone's surface: the angle from u to u + a/B (an identity).

    slip: (..., 2) tangential contact-point velocity u; accel: (..., 2) its
    tangential acceleration a = J_t qacc; damping: B of the friction rows
    (1/time in the same units).  Counter-clockwise positive, as
    ``crosscheck.engines.mujoco.studies.contact.friction_skew`` measures it.
    """
    u = np.asarray(slip, dtype=float)
    w = u + np.asarray(accel, dtype=float) / np.asarray(damping, dtype=float)[..., None]
    ang = np.arctan2(w[..., 1], w[..., 0]) - np.arctan2(u[..., 1], u[..., 0])
    return np.angle(np.exp(1j * ang))
