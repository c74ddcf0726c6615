"""The eps -> 0 asymptotics of the compliant rod (Kelvin-Voigt normal law, exact Coulomb friction) against the rigid impact without collision.

Conventions.  Scaled units (section 2.1).  delta = -gap >= 0 is the contact
point's penetration [l], w = gap' its normal velocity [l omega] (up > 0),
and the scaled Kelvin-Voigt law is F_n = max(0, delta/eps^2 + (xi/eps) delta')
[m g].  While the tip slips, its normal acceleration is affine in the
normal force with the friction -mu F_n along the slip (eqs. b, p, FZ):

    w' = b + p F_n,   i.e.   delta'' = -b - p (delta/eps^2 + xi delta'/eps).

Fast time tau = t/eps and the force-like penetration D = delta/eps^2 turn
this into D_tt = -b + |p| (D + xi D_t) for p < 0 (subscript t: d/dtau),
with the fixed point D* = b/|p| (the rigid slipping force -b/p, eq. FZ) and
x = D - D* obeying x_tt = |p| (x + xi x_t).  Its exponents solve

    lambda^2 - |p| xi lambda - |p| = 0:   lambda = (|p| xi + sqrt(p^2 xi^2 + 4 |p|))/2 > 0 > lambda_2

(``growth_rates``): the contact is an unstable spring-dashpot whose
"mass" 1/p is negative, the paper's Painleve mechanism.

Inconsistent start (p < 0, b < 0, the tip on the plane at rest: D = D_t = 0).
x(0) = |b|/|p|, x_t(0) = 0, so the unstable mode starts with amplitude
K = (|b|/|p|) |lambda_2| / (lambda + |lambda_2|) = O(1) in D, i.e.
delta = O(eps^2) and F_n = O(1).  The slip (speed eta = O(1)) stops once
the friction impulse mu P is O(1); P grows like (eps K/lambda) (1 + xi lambda)
e^(lambda tau), so the slip stops at

    t_stop = (eps/lambda) ln(1/eps) + eps C + O(eps^2 ln^2(1/eps)),

coefficient 1/lambda (k = 1 in t ~ (eps/lambda) ln(1/eps^k): the start is
O(eps^2) in delta but O(1) in force, and the impulse needed is O(1)).  The
O(1) offset C comes from the fast problem below (``FastLimit.offset``).

The fast problem (``fast_limit``).  With d = delta/eps and the normal
impulse P = int F_n dt, the eps -> 0 limit of the impulsive phase is
eps-free: the tip velocity u obeys the rigid impulse equations of
``crosscheck.theory.impact.darboux_keller`` in P (du/dP = G (f_t, 1), G the Delassus matrix, f_t
sliding or sticking friction), and the normal law adds

    dd/dtau = -u_n,   dP/dtau = f = d - xi u_n   (F_n = f/eps),

so along the IWC's impulse path d(P) solves dd/dP = -u_n(P)/f.  The
impulse ends where the push f returns to 0 (the law's tension cut-off),
at P_f: the post-event state is exactly ``crosscheck.theory.impact.darboux_keller.impact`` with
Poisson's coefficient e = P_f/P_c - 1 (same ODE in P, only the end
differs).  That e is not a function of xi alone: it depends on the state
through the slip-phase "mass" p and the stick-phase Schur complement S, and
in 3-D on the rotation of the slip during the impulse.  For large xi the
release comes as the overdamped slow mode decays, f ~ d - xi u_n -> 0 with
u_n ~ d/xi, so e -> 0: the compliant limit tends to the plastic IWC.

Corollary 4.2 jams (p -> 0 with b < 0) and indeterminate starts (p < 0, b > 0): ``docs/compliant_limit.md``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import ALPHA, MU, NONNEGATIVE, POSITIVE, THETA, Interval, check
from crosscheck.coordinates import tip_velocity, to_generalized
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic
from crosscheck.theory.impact.darboux_keller import Impact, delassus, impact
from crosscheck.theory.slipping import slip_until_event

__all__ = [
    "growth_rates",
    "FastLimit",
    "fast_limit",
    "planar_restitution",
    "indeterminate_boundary",
    "gb_reaching_rates",
    "time_corrections",
]

#: Relative accuracy of the fast problem's integration (DOP853) and the slip speed counted as stopped there.
_RTOL, _ATOL = 1e-11, 1e-14
_STOP = 1e-11
#: Normal impulse at which the fast problem leaves its asymptotic start (the linear growth or the self-similar jam solution).
_P0 = 1e-9


def growth_rates(p, xi):
    """(lambda, lambda_2): the roots of lambda^2 - |p| xi lambda - |p| = 0 for p < 0 (fast time tau = t/eps).

    lambda > 0 is the growth rate of the compliant contact's penetration
    while slipping with p < 0; lambda_2 < 0 the decay rate of the stable
    direction.  Arrays broadcast; p must be < 0 and xi >= 0.
    """
    p, xi = np.asarray(p, float), check("xi", xi, NONNEGATIVE)
    if np.any(~(p < 0.0)):
        raise ValueError(
            f"p must be in (-inf, 0) (the growth exists only where the tip's normal 'mass' 1/p is negative); got {p!r}"
        )
    a = -p
    root = np.sqrt(a * a * xi * xi + 4.0 * a)
    lam, lam2 = 0.5 * (a * xi + root), 0.5 * (a * xi - root)
    return (float(lam), float(lam2)) if lam.ndim == 0 else (lam, lam2)


@dataclass(frozen=True, eq=False)
class FastLimit:
    """The eps-free impulsive phase of the compliant rod (module docstring) from one state.

    Attributes:
      state, mu, alpha, xi: the inputs.  start: "inconsistent" (p < 0 at the
        state) or "jam" (p = 0 at the state: a Corollary 4.2 jam).
      p, b: eqs. p and b at the state.  lam, lam2: ``growth_rates`` (NaN for a jam).
      coefficient: 1/lambda, the slope of t_stop/eps against ln(1/eps) (NaN for a jam).
      offset: C in t_stop/eps = coefficient ln(1/eps) + C (NaN unless inconsistent with b < 0).
      P_stop: normal impulse at the first slip stop (NaN if the slip never stops).
      P_c: normal impulse at the end of compression (u_n = 0 rising); P_f: at the release (f = 0).
      restitution: the Poisson coefficient e = P_f/P_c - 1 the law implies at this state.
      w: the contact point's normal velocity after the release [l omega].
      phases: ((name, P_start, P_end), ...).
      impact: ``crosscheck.theory.impact.darboux_keller.impact`` at this state with ``restitution`` (clipped to [0, 1]): the limit post-event state.
    """

    state: SlipState
    mu: float
    alpha: float
    xi: float
    start: str
    p: float
    b: float
    lam: float
    lam2: float
    coefficient: float
    offset: float
    P_stop: float
    P_c: float
    P_f: float
    restitution: float
    w: float
    phases: tuple
    impact: Impact = field(repr=False)

    def as_dict(self) -> dict:
        i = self.impact
        return {
            "start": self.start,
            "xi": self.xi,
            "p": self.p,
            "b": self.b,
            "lambda": self.lam,
            "lambda_2": self.lam2,
            "coefficient": self.coefficient,
            "offset": self.offset,
            "P_stop": self.P_stop,
            "P_c": self.P_c,
            "P_f": self.P_f,
            "restitution": self.restitution,
            "w": self.w,
            "phases": [list(ph) for ph in self.phases],
            "iwc": {
                "Theta": i.Theta,
                "Psi": i.Psi,
                "eta": i.eta,
                "varphi": i.varphi,
                "w": i.w,
                "normal_impulse": i.normal_impulse,
                "compression_impulse": i.compression_impulse,
            },
        }


def _tip(state: SlipState, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """(G, u0): the Delassus matrix and the tip velocity (world x, y, z) at the state, scaled."""
    rod = Rod.scaled(alpha)
    q, v = to_generalized(rod, state)
    return delassus(state, alpha), tip_velocity(rod, q, v)


def fast_limit(state: SlipState, mu: float, alpha: float, *, xi: float) -> FastLimit:
    """The eps -> 0 limit of the compliant rod's impulsive phase from ``state`` (module docstring).

    Args:
      state: a ``SlipState`` with eq. p < 0 (an inconsistent or indeterminate
        start) or p = 0 up to ``crosscheck.theory.impact.darboux_keller.P_TOLERANCE``-like rounding
        (1e-9: a Corollary 4.2 jam state, from ``slip_until_event``).
      mu, alpha: friction coefficient and m l^2 / I0.
      xi: the Kelvin-Voigt damping (>= 0).

    Returns:
      ``FastLimit``.

    Raises:
      ValueError: bad arguments, p > 1e-9, or a jam state where p does not
        decrease along the impulse (no jam there).
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    xi = float(check("xi", xi, NONNEGATIVE))
    G, u0 = _tip(state, alpha)
    n0 = math.hypot(u0[0], u0[1])
    if not n0 > 0.0:
        raise ValueError(f"eta must be in (0, inf) for an impulse (a slipping tip); got {state.eta!r}")
    uh = u0[:2] / n0
    p = float(G[2, 2] - mu * G[2, :2] @ uh)
    b = float(analytic.b(state.Psi, state.Theta, state.theta))
    start, lam, lam2, coefficient, K, u, d0 = _asymptotic_start(G, u0, mu, xi, p, b)
    P, y, tau_stop, P_stop, P_c = _slip_in_P(G, u0, u, d0, mu, xi)
    phases: list[tuple[str, float, float]] = [("slip", 0.0, P)]
    z = np.array([y[0], y[1], y[2], y[3], y[4], y[5], P])
    z, P_c = _phases_in_tau(G, z, mu, xi, n0, slipping=math.isnan(P_stop), P_c=P_c, phases=phases)
    P_f = float(z[6])
    e = P_f / P_c - 1.0
    imp = impact(state, mu, alpha, restitution=min(max(e, 0.0), 1.0))
    offset = math.nan
    if start == "inconsistent" and b < 0:
        # the linear growth d = eps K e^(lambda tau) reaches d0 at tau_entry = ln(d0/(eps K))/lambda
        offset = math.log(d0 / K) / lam + tau_stop
    return FastLimit(
        state=state,
        mu=mu,
        alpha=alpha,
        xi=xi,
        start=start,
        p=p,
        b=b,
        lam=lam,
        lam2=lam2,
        coefficient=coefficient,
        offset=offset,
        P_stop=P_stop,
        P_c=P_c,
        P_f=P_f,
        restitution=e,
        w=float(z[2]),
        phases=tuple(phases),
        impact=imp,
    )


def _asymptotic_start(G, u0, mu: float, xi: float, p: float, b: float):
    """The fast problem's start at the small normal impulse ``_P0``: the linear growth along the unstable direction
    (p < 0) or the self-similar jam solution (p = 0).  Returns (start, lam, lam2, coefficient, K, u, d0): the kind of
    start, ``growth_rates``, 1/lambda, the unstable mode's amplitude K (NaN unless b < 0), the tip velocity u (3,)
    and the scaled penetration d0 at ``_P0``."""
    n0 = math.hypot(u0[0], u0[1])
    uh = u0[:2] / n0
    Gtt, Gtn = G[:2, :2], G[:2, 2]
    dut = Gtt @ (-mu * uh) + Gtn  # du_t/dP while slipping
    P0 = _P0
    u = u0 + G @ np.array([-mu * uh[0], -mu * uh[1], 1.0]) * P0
    if p < -1e-9:
        lam, lam2 = growth_rates(p, xi)
        c = lam / (1.0 + xi * lam)  # d = c P along the unstable direction
        u[2] = p * P0
        K = abs(b) / abs(p) * abs(lam2) / (lam + abs(lam2)) if b < 0 else math.nan
        return "inconsistent", lam, lam2, 1.0 / lam, K, u, c * P0
    if p <= 1e-9:
        # dp/dP = -mu G_nt . d(u_hat)/dP, d(u_hat)/dP = (I - u_hat u_hat^T) du_t/dP / |u_t|
        k = float(mu * Gtn @ ((np.eye(2) - np.outer(uh, uh)) @ dut) / n0)
        if not k > 0.0:
            raise ValueError(f"-dp/dP must be in (0, inf) at a jam (p decreasing along the impulse); got {k!r}")
        u[2] = -0.5 * k * P0 * P0
        return "jam", math.nan, math.nan, math.nan, math.nan, u, math.sqrt(k / 3.0) * P0**1.5
    raise ValueError(f"p must be <= 1e-9 (inconsistent or at a jam) for an impulse; got p = {p!r}")


def _slip_in_P(G, u0, u, d0: float, mu: float, xi: float):
    """The fast problem's first slip phase, integrated in the normal impulse P from ``_P0`` until the slip stops or
    the compression ends.  State y = (u_x, u_y, u_n, d, L_x, L_y, tau); f = d - xi u_n > 0 while compressing.
    u0 and u: the tip velocity at P = 0 and at ``_P0``.  Returns (P, y, tau_stop, P_stop, P_c) at the phase's end
    (NaN for the one of the two ends not reached)."""
    P0 = _P0
    n0 = math.hypot(u0[0], u0[1])
    uh = u0[:2] / n0

    def slip_P(_P, y):
        ut = y[:2]
        f_t = -mu * ut / math.hypot(ut[0], ut[1])
        f = y[3] - xi * y[2]
        du = G @ np.array([f_t[0], f_t[1], 1.0])
        return [du[0], du[1], du[2], -y[2] / f, f_t[0], f_t[1], 1.0 / f]

    def stopped(_P, y):
        return math.hypot(y[0], y[1]) - _STOP * (1.0 + n0)

    stopped.terminal, stopped.direction = True, -1

    def compressed(_P, y):
        return y[2]

    compressed.terminal, compressed.direction = True, +1
    y0 = np.array([u[0], u[1], u[2], d0, -mu * uh[0] * P0, -mu * uh[1] * P0, 0.0])
    sol = solve_ivp(
        slip_P, (P0, P0 + 1e3 * (1.0 + n0)), y0, method="DOP853", rtol=_RTOL, atol=_ATOL, events=[stopped, compressed]
    )
    if sol.status != 1:
        raise RuntimeError(f"fast problem: the slip phase did not end ({sol.message})")
    P, y = float(sol.t[-1]), sol.y[:, -1].copy()
    tau_stop = float(y[6]) if len(sol.t_events[0]) else math.nan
    P_stop = P if len(sol.t_events[0]) else math.nan
    P_c = math.nan if len(sol.t_events[0]) else P
    return P, y, tau_stop, P_stop, P_c


def _phases_in_tau(G, z, mu: float, xi: float, n0: float, *, slipping: bool, P_c: float, phases: list):
    """The fast problem after its first phase, in fast time tau: z = (u_x, u_y, u_n, d, L_x, L_y, P), slipping or
    stuck, until the push f = d - xi u_n falls to 0 (the release).  n0: the start's slip speed (the scale of the
    stopped slip); P_c: the end of compression if reached already (else NaN).  Appends each phase to ``phases``;
    returns (z, P_c) at the release."""
    Gtt, Gtn = G[:2, :2], G[:2, 2]
    S = float(G[2, 2] + Gtn @ -np.linalg.solve(Gtt, Gtn))
    f_s = -np.linalg.solve(Gtt, Gtn)
    mode = "slip" if slipping else None
    for _ in range(16):
        if mode is None:  # just stopped: the tip sticks (|f_s| < mu wherever p <= 0: darboux_keller's docstring)
            z[:2] = 0.0
            if not np.linalg.norm(f_s) < mu:
                raise RuntimeError(
                    f"fast problem: the sticking impulse |f_s| = {np.linalg.norm(f_s)!r} is outside the cone mu = {mu!r}"
                )
            mode = "stick"
        if mode == "stick":

            def rhs(_t, z):
                f = z[3] - xi * z[2]
                return [0.0, 0.0, S * f, -z[2], f_s[0] * f, f_s[1] * f, f]
        else:

            def rhs(_t, z):
                ut = z[:2]
                f_t = -mu * ut / math.hypot(ut[0], ut[1])
                f = z[3] - xi * z[2]
                du = G @ np.array([f_t[0], f_t[1], 1.0]) * f
                return [du[0], du[1], du[2], -z[2], f_t[0] * f, f_t[1] * f, f]

        def released(_t, z):
            return z[3] - xi * z[2]

        released.terminal, released.direction = True, -1

        def comp(_t, z):
            return z[2]

        comp.direction = +1

        def stop_t(_t, z):
            return math.hypot(z[0], z[1]) - _STOP * (1.0 + n0) if mode != "stick" else 1.0

        stop_t.terminal, stop_t.direction = True, -1
        P_start = float(z[6])
        sol = solve_ivp(rhs, (0.0, 1e4), z, method="DOP853", rtol=_RTOL, atol=_ATOL, events=[released, comp, stop_t])
        if sol.status != 1:
            raise RuntimeError(f"fast problem: the {mode} phase did not end ({sol.message})")
        z = sol.y[:, -1].copy()
        phases.append((mode, P_start, float(z[6])))
        if len(sol.t_events[1]) and math.isnan(P_c):
            P_c = float(sol.y_events[1][0][6])
        if len(sol.t_events[0]):
            break
        mode = None  # a slip stop: the tip sticks
    else:
        raise RuntimeError("fast problem: more than 16 phases")
    if math.isnan(P_c):
        raise RuntimeError("fast problem: released before the end of compression")
    return z, P_c


def planar_restitution(p, S, xi) -> float:
    """Poisson's e = P_f/P_c - 1 of the Kelvin-Voigt limit where the slip direction is fixed (the planar section) and the tip sticks.

    Slip phase (du_n/dP = p < 0): the penetration grows along the unstable
    direction, (d, d_t) = (1, lambda) d_s when the slip stops at P_s, with
    d = c P, c = lambda/(1 + xi lambda), so P_s = d_s/c.  Stick phase
    (du_n/dP = S > 0): d_tt + S xi d_t + S d = 0 from (1, lambda) d_s until
    the push f = d + xi d_t returns to 0 at tau_f with d_t(tau_f) = -w_f.
    Since u_n = |p| P_s at the slip stop and rises at S per unit impulse,
    P_c = P_s (1 + |p|/S) and P_f - P_c = w_f/S, so

        e = (w_f/d_s) c / (S + |p|),

    independent of P_s: a function of (p, S, xi) only.  w_f/d_s comes from
    the damped oscillator in closed form (its release time is the first root
    of f, found by bracketing).  For xi -> inf, e ~ 1/(S xi^2).
    """
    p, S, xi = float(p), float(check("S", S, POSITIVE)), float(check("xi", xi, NONNEGATIVE))
    lam, _ = growth_rates(p, xi)
    c = lam / (1.0 + xi * lam)
    # d_tt = -S (d + xi d_t) as a linear system: z = (d, d_t), z' = A z
    A = np.array([[0.0, 1.0], [-S, -S * xi]])
    w, V = np.linalg.eig(A)
    coef = np.linalg.solve(V, np.array([1.0, lam], dtype=complex))

    def z(t):
        return np.real(V @ (coef * np.exp(w * t)))

    def f(t):
        d, dd = z(t)
        return d + xi * dd

    # bracket the first sign change of f on a grid fine against both time scales
    step = 0.01 * min(1.0 / math.sqrt(S), 1.0 / (S * xi) if xi > 0 else math.inf, xi if xi > 0 else math.inf)
    t0 = 0.0
    while True:
        t1 = t0 + step
        if f(t1) <= 0.0:
            break
        t0 = t1
        step *= 1.02
        if t0 > 1e6:
            raise RuntimeError("planar_restitution: no release found")
    from scipy.optimize import brentq

    tf = brentq(f, t0, t1, xtol=1e-15, rtol=1e-14)
    w_f = -z(tf)[1]
    return float(w_f * c / (S + abs(p)))


def indeterminate_boundary(
    state: SlipState, mu: float, alpha: float, *, xi: float, eps: float, D0: float
) -> tuple[float, float]:
    """The start (gap, gap_rate) on the boundary between lift-off and an impact without collision, for a given penetration.

    For an indeterminate state (eq. p < 0 < eq. b), in the fast variables
    D = delta/eps^2, D_t = delta'/eps the fixed point D* = b/|p| has the
    stable manifold D_t = lambda_2 (D - D*) (``growth_rates``).  With
    gap = -eps^2 D0 the boundary's gap rate (gap' = -delta' = -eps D_t) is

        gap_rate* = -eps lambda_2 (D0 - D*) = eps |lambda_2| (D0 - D*);

    a start with gap_rate < gap_rate* (more inward) has a positive unstable
    component and jams, one with gap_rate > gap_rate* lifts off.  The
    boundary is exact for the frozen (p, b); their drift over the
    decision time O(eps) moves it by a relative O(eps).

    Returns:
      (gap, gap_rate*) [l, l omega].
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    eps = float(check("eps", eps, Interval(0.0, 1.0, lo_open=True, hi_open=False)))
    D0 = float(check("D0", D0, NONNEGATIVE))
    p, b = (
        float(analytic.p(state.theta, state.varphi, mu, alpha)),
        float(analytic.b(state.Psi, state.Theta, state.theta)),
    )
    if not (p < 0.0 < b):
        raise ValueError(f"state must be indeterminate (p < 0 < b); got p = {p!r}, b = {b!r}")
    _, lam2 = growth_rates(p, xi)
    return -eps * eps * D0, -eps * lam2 * (D0 - b / abs(p))


def gb_reaching_rates(
    mu: float,
    alpha: float,
    theta0: float,
    *,
    eta: float = 1.0,
    Theta_range: tuple[float, float] = (0.0, 3.0),
    n: int = 61,
    t_max: float = 5.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Planar starts (varphi = -pi/2, Psi = 0) at theta0 that slip into the GB point P+ (b = p = 0).

    Scans Theta0 over ``Theta_range`` and runs ``slip_until_event``; where
    mu > mu_C the point P+ attracts an open set of planar trajectories (Or's
    Theorem 1, reached in finite time), so the reaching rates form intervals.

    Returns:
      (Theta0 (n,), outcome codes (n,)); Outcome.GB marks the starts that reach P+.
    """
    mu, alpha = float(check("mu", mu, MU)), float(check("alpha", alpha, ALPHA))
    theta0 = float(check("theta0", theta0, THETA))
    Theta0 = np.linspace(*Theta_range, n)
    out = np.array(
        [
            slip_until_event(
                SlipState(theta=theta0, varphi=-math.pi / 2, Theta=float(T), Psi=0.0, eta=eta), mu, alpha, t_max=t_max
            ).outcome
            for T in Theta0
        ],
        dtype=np.int8,
    )
    return Theta0, out


def time_corrections(fast: FastLimit) -> tuple[float, float]:
    """(C1, C2) in t_stop/eps - (coefficient ln(1/eps) + offset) = C1 eps T + C2 eps T^2 + O(eps), T = t_stop/eps (inconsistent starts).

    While the unstable mode grows (for a time t_stop = eps T) the rest of the
    rod follows the formal slipping solution, eq. polareqs_varphi with the
    force at the fixed point, F_z = D* = -b/p (negative here: the
    exponential mode is measured from it).  The fast problem freezes that
    state; letting it drift gives, to first order in eps T:

    * C1: the exponential impulse must also undo the drift of the slip
      speed, d eta/dt = a_s - kappa D* (a_s the contact-free tangential
      acceleration along the slip, eq. linode2 with F = 0; kappa =
      -d|u_t|/dP the friction's deceleration per unit impulse), which moves
      the stop by ln(1 + (d eta/dt) t_stop / (kappa P_stop))/lambda:
      C1 = (a_s/kappa + |b|/|p|) / (lambda P_stop);
    * C2: the growth rate drifts, lambda(t) = lambda + lambda' t, so the
      exponent int lambda dt/eps reaches its value earlier by
      lambda' eps T^2 / (2 lambda): C2 = -lambda'/(2 lambda), with
      lambda' = (1 + xi lambda)/(2 lambda - |p| xi) d|p|/dt and dp/dt along
      the formal slipping flow (eq. f divided by dt/ds = eta p).  C2 = 0
      where p is stationary along the flow (``planar_impasse``: theta midway
      between the roots of p, Theta-independent).

    The remainder O(eps) (no factor T) comes from the O(eps) start-up
    transient's share of the same drifts.
    """
    if fast.start != "inconsistent" or not fast.b < 0:
        raise ValueError(f"fast must be an inconsistent start (p < 0, b < 0); got start {fast.start!r}, b = {fast.b!r}")
    from crosscheck.theory.slipping import slip_rhs

    G, u0 = _tip(fast.state, fast.alpha)
    uh = u0[:2] / math.hypot(u0[0], u0[1])
    s, mu, alpha = fast.state, fast.mu, fast.alpha
    a = analytic.tip_acceleration(Rod.scaled(alpha), s.psi, s.theta, s.Psi, s.Theta, np.zeros(3))
    a_s = float(a[:2] @ uh)
    kappa = float(mu * uh @ G[:2, :2] @ uh - uh @ G[:2, 2])
    C1 = (abs(fast.b / fast.p) + a_s / kappa) / (fast.lam * fast.P_stop)
    x = np.array([s.eta, s.varphi, s.psi, s.Psi, s.theta, s.Theta])
    dxdt = slip_rhs(x, mu, alpha) / (s.eta * fast.p)
    h = 1e-6

    def p_of(y):
        return float(analytic.p(y[4], y[1], mu, alpha))

    pdot = (p_of(x + h * dxdt) - p_of(x - h * dxdt)) / (2 * h)
    lam, xi = fast.lam, fast.xi
    lam_dot = (1.0 + xi * lam) / (2.0 * lam - abs(fast.p) * xi) * (-pdot)
    return C1, -lam_dot / (2.0 * lam)
