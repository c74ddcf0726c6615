"""The slipping rod integrated to its first event, in the desingularised time of eq. f.

While the tip slips, F_z = -b/p (eq. FZ) and the real-time equations
(eq. polareqs_varphi) are singular where p = 0.  Section 4 of the paper
removes the singularity with the new time s, ``eta p ds = dt``, which gives
the vector field f(x) of eq. f on x = (eta, varphi, psi, Psi, theta, Theta)
(eq. x).  ``slip_until_event`` integrates f together with dt/ds = eta p, so
the crossing of p = 0 is a regular event and the real time t is recovered as
an extra state.

Events (the first one ends the run):

=========  ======================================================================
LIFTOFF    b reaches 0 (from below) while p > 0.
JAM        p reaches 0 (from above) while b < 0: the inconsistent region.  The
           run stops once p < -``P_RESOLVED.atol`` (1e-8) and reports the state
           and time at the last crossing of p = 0.  The margin matters only
           where p = 0 is invariant (the planar section varphi = -pi/2, Psi = 0,
           where eq. pdotarg vanishes): there trajectories slide along p = 0+
           towards P+ and integration noise of ~1e-10 in p must not count as a
           crossing.  Elsewhere p crosses transversally and the margin only
           delays the stop by ds ~ 1e-8 / |p'|.
GB         (p, b) enters the disc hypot(p, b) < ``GB_REACHED.atol`` (1e-7).  GB
           points are equilibria of f, reached only as s -> infinity while t
           converges (Or's Theorem 1: P+ in finite time), so a radius is needed.
STICK      eta falls below ``STICK_SPEED.atol`` (1e-9).  eta = 0 is also a set of
           equilibria of f; the real time still needed, eta / |d eta/dt|, is
           added linearly and the returned state has eta = 0.
SLIP       none of the above before ``t_max``; also (with ``reason`` saying
           which) when the run leaves the paper's domain: varphi reaches 0 or
           -pi (outside (-pi, 0] p > 0 and the paper's SlipState does not apply;
           the state is returned on the boundary, -pi as the next float above),
           theta comes within ``THETA_MARGIN.atol`` (1e-6) of 0 or pi/2, or
           the desingularised time exceeds ``s_max`` without an event (the flow
           creeps towards an equilibrium too slowly to decide).  The domain
           exits (``DOMAIN_EXITS``) say only that no event came before them:
           ``SlipResult.left_domain``.
DIVERGED   the integrator failed (step size underflow, non-finite values).
=========  ======================================================================

Near the vertical every start leaves the domain within a short time: the slender rod's azimuthal spin Psi' grows
like 1 / cos theta (docs/theory.md, "Near the vertical").

A start at rest (eta below ``STICK_SPEED``) is judged by the forces that would
hold it (``crosscheck.theory.sticking.at_rest``): STICK only when the stuck
rod's friction fits in the cone, |F_t| <= mu F_n; otherwise it lifts off, or
the slip starts in the direction the forces give (varphi = -pi/2, from eta =
``SLIP_ONSET_SPEED``; towards S, varphi = +pi/2, is SLIP at t = 0 with reason
"varphi=pi/2", outside the domain).  ``continue_slip`` (a state the model
reached) keeps the speed rule: its caller decides the mode at rest.
A start that is not slipping returns at once with t = 0 and an empty-ish
trajectory (the start alone), decided in this order: eta = 0 -> STICK;
hypot(p, b) < GB_REACHED.atol -> GB; b > 0 -> LIFTOFF (with p <= 0 this is the
indeterminate mode, whose lift-off solution we pick); p <= 0 (b <= 0) -> JAM
(inconsistent, or on p = 0).  A start with b = 0 < p is integrated (it lifts
off at t = 0 if b increases).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from crosscheck.checks import ALPHA, CONTACT_RADIUS, HORIZON, MU, Interval, check
from crosscheck.outcome import Outcome
from crosscheck.state import SlipState
from crosscheck.tolerances import GB_REACHED, P_RESOLVED, SLIP_INTEGRATION, STICK_SPEED, THETA_MARGIN

__all__ = [
    "X_STATE",
    "DOMAIN_EXITS",
    "RADIUS",
    "SlipResult",
    "slip_rhs",
    "slip_until_event",
    "slip_outcomes",
    "integrate",
]

#: The contact point's distance r below the tip A, in units of l: a thicker capsule is no longer the paper's slender rod.
RADIUS = CONTACT_RADIUS

#: Order of the desingularised state, eq. x.
X_STATE = ("eta", "varphi", "psi", "Psi", "theta", "Theta")

#: The reasons of a SLIP that is an exit from the paper's domain (-pi < varphi <= 0, 0 < theta < pi/2): the run
#: stopped there, before ``t_max``, with no event before it; what follows is outside the paper's coordinates.
DOMAIN_EXITS = ("varphi=0", "varphi=-pi", "varphi=pi/2", "theta=0", "theta=pi/2")

_HALF_PI = 0.5 * math.pi
_VARPHI_LOW = math.nextafter(-math.pi, 0.0)  # the closest float to -pi inside (-pi, 0]


def _coefficients(varphi, Psi, theta, Theta, mu, alpha, r, varphi_f=None):
    """b, p and the per-unit-F_z (...1) and force-free (...0) parts of the contact point's horizontal acceleration
    (a_i, a_j in the rod's (i, j) frame) and of Psi', Theta', with the contact at C = A - r K (scalars: hot loop).

    At r = 0 these are the paper's (C = A): p is eq. p, and a_i, a_j, Psi', Theta' give eq. polareqs_varphi with
    the coefficients of Appendix A (``crosscheck.theory.capsule`` derives the r terms).  ``varphi_f``: the friction's
    angle, -(cos varphi_f i + sin varphi_f j), where it is not opposite the slip (``crosscheck.engines.bullet.law``);
    None: Coulomb's, varphi (varphi enters only through the friction).
    """
    st, ct = math.sin(theta), math.cos(theta)
    sp, cp = (math.sin(varphi), math.cos(varphi)) if varphi_f is None else (math.sin(varphi_f), math.cos(varphi_f))
    sr = st + r
    W = Psi * Psi * ct * ct + Theta * Theta
    b = W * st - 1.0
    p = 1.0 + alpha * ct * ct + alpha * mu * ct * sr * sp
    ai1 = -(1.0 + alpha) * mu * cp
    ai0 = -r * Theta * Psi
    aj1 = -mu * sp * (1.0 + alpha * sr * sr) - alpha * ct * sr
    aj0 = ct * W - r * st * ct * Psi * Psi
    Psi1 = -alpha * mu * cp / ct
    Psi0 = 2.0 * Psi * Theta * st / ct
    Theta1 = -alpha * mu * sr * sp - alpha * ct
    Theta0 = -st * ct * Psi * Psi
    return b, p, ai1, ai0, aj1, aj0, Psi1, Psi0, Theta1, Theta0


def _rhs7(y, mu, alpha, r, varphi_f=None):
    """f(x) of eq. f at the contact point C plus dt/ds = eta p, for y = (eta, varphi, psi, Psi, theta, Theta, t)
    (``varphi_f``: the friction's angle as in ``_coefficients``; p is then the p of that friction)."""
    eta, varphi, Psi, theta, Theta = y[0], y[1], y[3], y[4], y[5]
    b, p, ai1, ai0, aj1, aj0, Psi1, Psi0, Theta1, Theta0 = _coefficients(
        varphi, Psi, theta, Theta, mu, alpha, r, varphi_f
    )
    # p times each acceleration: F_z p = -b removes the 1/p of eq. FZ
    Ai = -b * ai1 + p * ai0
    Aj = -b * aj1 + p * aj0
    sp, cp = math.sin(varphi), math.cos(varphi)
    ep = eta * p
    return [
        eta * (cp * Ai + sp * Aj),
        (cp * Aj - sp * Ai) - eta * Psi * p,
        ep * Psi,
        eta * (-b * Psi1 + p * Psi0),
        ep * Theta,
        eta * (-b * Theta1 + p * Theta0),
        ep,
    ]


def slip_rhs(x, mu, alpha, *, radius: float = 0.0) -> np.ndarray:
    """The desingularised slipping vector field f(x), eq. f (scalar state), with the contact at C = A - r K.

    Args:
      x: (6,) state ordered as ``X_STATE`` = (eta, varphi, psi, Psi, theta, Theta), scaled units; eta and varphi
        are the contact point's slip (the tip's at r = 0).
      mu, alpha: friction coefficient and m l^2 / I0.
      radius: r, the contact point's distance below the tip A [l] (0: the paper's rod; a capsule's radius).

    Returns:
      (6,) derivative with respect to s, where eta p ds = dt.  For an array
      version with the Jacobian at r = 0 see ``crosscheck.theory.gb.f``.
    """
    x = np.asarray(x, dtype=float)
    return np.array(_rhs7(x, float(mu), float(alpha), float(check("radius", radius, RADIUS)))[:6])


@dataclass(frozen=True, eq=False)
class SlipResult:
    """First event of a slipping run (``slip_until_event``).

    Attributes:
      outcome: what ended the run (see the module docstring for the rules).
      time: real scaled time t of the event (units 1/omega).
      state: ``SlipState`` at the event.
      reason: which rule fired: "start", "b=0", "p=0", "gb", "eta=0", "t_max",
        "varphi=0", "varphi=-pi", "theta=0", "theta=pi/2", "s_max" or "solver".
      b, p: eqs. b and p at the returned state.
      s: (n,) desingularised times of the integrator's steps.
      t: (n,) real scaled times at those steps (t[0] = 0).
      x: (n, 6) states at those steps, columns ordered as ``X_STATE``.
      left_domain (property): a SLIP that is a domain exit (``DOMAIN_EXITS``) at ``time``, not the end of ``t_max``.
    """

    outcome: Outcome
    time: float
    state: SlipState
    reason: str
    b: float
    p: float
    s: np.ndarray = field(repr=False)
    t: np.ndarray = field(repr=False)
    x: np.ndarray = field(repr=False)

    def as_dict(self) -> dict:
        """JSON-able summary (no trajectory)."""
        return {
            "outcome": self.outcome.name,
            "time": self.time,
            "reason": self.reason,
            "b": self.b,
            "p": self.p,
            "state": self.state.as_dict(),
            "left_domain": self.left_domain,
        }

    @property
    def left_domain(self) -> bool:
        """Whether the run stopped where it left the paper's domain (``DOMAIN_EXITS``): a SLIP up to ``time`` only."""
        return self.outcome is Outcome.SLIP and self.reason in DOMAIN_EXITS


def _start_outcome(eta: float, b: float, p: float) -> Outcome | None:
    """The outcome decided at the start, by the same resolutions as the events of the run.

    A start slower than the stick speed is stuck (the run's own STICK event
    would fire at once); a start within ``P_RESOLVED`` of p = 0 is on the
    boundary of the paradox region, not inside it: the run decides, and it
    jams only if p then falls below -P_RESOLVED (at mu = mu_P, where p >= 0
    everywhere, p = 0 at theta_P, varphi = -pi/2 computes as -8.9e-16 and
    was once called a JAM at t = 0 although no paradox exists there).
    """
    if eta < STICK_SPEED.atol:
        return Outcome.STICK
    if math.hypot(p, b) < GB_REACHED.atol:
        return Outcome.GB
    if b > 0.0:
        return Outcome.LIFTOFF
    if p <= -P_RESOLVED.atol:
        return Outcome.JAM
    return None


def _events(mu: float, alpha: float, r: float, t_max: float, friction=None):
    """Terminal event functions g(s, y) of the run and the (outcome, reason) each one means (``friction``: ``integrate``'s)."""

    def bp(y):
        b, p, *_ = _coefficients(y[1], y[3], y[4], y[5], mu, alpha, r, None if friction is None else friction(y))
        return b, p

    return event_table(bp, t_max)


def event_table(bp, t_max: float):
    """The run's event functions g(s, y) on the state y = (eta, varphi, psi, Psi, theta, Theta, t) of eq. f and
    the (outcome, reason) each one means, for any ``bp(y) -> (b, p)`` (the paper's at A, or at another contact point)."""
    gb_r, eta_stick, margin, p_resolved = GB_REACHED.atol, STICK_SPEED.atol, THETA_MARGIN.atol, P_RESOLVED.atol
    table = [
        (lambda s, y: bp(y)[0], +1, Outcome.LIFTOFF, "b=0"),
        (lambda s, y: bp(y)[1] + p_resolved, -1, Outcome.JAM, "p=0"),
        (lambda s, y: math.hypot(*bp(y)) - gb_r, -1, Outcome.GB, "gb"),
        (lambda s, y: y[0] - eta_stick, -1, Outcome.STICK, "eta=0"),
        (lambda s, y: y[6] - t_max, +1, Outcome.SLIP, "t_max"),
        (lambda s, y: y[1], +1, Outcome.SLIP, "varphi=0"),
        (lambda s, y: y[1] + math.pi, -1, Outcome.SLIP, "varphi=-pi"),
        (lambda s, y: y[4] - margin, -1, Outcome.SLIP, "theta=0"),
        (lambda s, y: _HALF_PI - margin - y[4], -1, Outcome.SLIP, "theta=pi/2"),
    ]
    funcs = []
    for g, direction, _, _ in table:
        g.terminal = True
        g.direction = direction
        funcs.append(g)
    # p = 0 itself, not terminal: a JAM is reported at the last crossing of p = 0
    p_zero = lambda s, y: bp(y)[1]  # noqa: E731
    p_zero.terminal, p_zero.direction = False, -1
    funcs.append(p_zero)
    return funcs, [(o, r) for _, _, o, r in table]


def first_event(sol, meaning, y0) -> tuple[Outcome, str, np.ndarray, np.ndarray]:
    """(outcome, reason, s, Y) of a finished ``solve_ivp`` run with the events of ``event_table``.

    The earliest terminal event (solve_ivp stops there; on a tie the table's
    order), or SLIP "s_max" when none fired.  A JAM fires at p = -P_RESOLVED;
    the crossing itself is the last root of p = 0 before it (none when the run
    started on the boundary, -P_RESOLVED < p <= 0: then the start ``y0``).  The
    trajectory (s, Y) is cut at the event and ends on its state.
    """
    s_arr, Y = sol.t, sol.y.T
    if sol.status != 1:
        return Outcome.SLIP, "s_max", s_arr, Y
    fired = [i for i, te in enumerate(sol.t_events[: len(meaning)]) if len(te)]
    i = min(fired, key=lambda k: (sol.t_events[k][0], k))
    outcome, reason = meaning[i]
    s_end, y_end = sol.t_events[i][0], sol.y_events[i][0]
    if outcome is Outcome.JAM:
        if len(sol.t_events[-1]):
            s_end, y_end = sol.t_events[-1][-1], sol.y_events[-1][-1]
        else:
            s_end, y_end = 0.0, y0
    keep = s_arr < s_end
    return outcome, reason, np.append(s_arr[keep], s_end), np.vstack([Y[keep], y_end])


def _state_from(y, *, eta=None) -> SlipState:
    varphi = min(max(float(y[1]), _VARPHI_LOW), 0.0)
    theta = min(max(float(y[4]), THETA_MARGIN.atol), _HALF_PI - THETA_MARGIN.atol)
    return SlipState(
        theta=theta,
        varphi=varphi,
        Theta=float(y[5]),
        Psi=float(y[3]),
        eta=float(y[0]) if eta is None else eta,
        psi=float(y[2]),
    )


def slip_until_event(state: SlipState, mu, alpha, *, t_max: float = 10.0, s_max: float = 1e4) -> SlipResult:
    """Integrate the slipping rod from ``state`` to its first event.

    Integrates f of eq. f (with F_z = -b/p, eq. FZ) in the desingularised time
    s, eta p ds = dt, with t as a seventh state, using ``solve_ivp`` (DOP853,
    tolerances ``SLIP_INTEGRATION``) and terminal events on b, p, hypot(p, b),
    eta, t and the domain boundaries.  See the module docstring for the event
    rules and for starts that are not slipping.

    Args:
      state: the initial ``SlipState`` (scaled units; the tip on the plane).
      mu: friction coefficient, >= 0.
      alpha: m l^2 / I0, > 0 (3 for a uniform rod).
      t_max: horizon in real scaled time (units 1/omega), > 0.
      s_max: horizon in desingularised time, > 0; reaching it without an
        event gives SLIP with reason "s_max".

    Returns:
      A ``SlipResult``: outcome, real time, state at the event, trajectory.
    """
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    state = state.check_start()
    if state.eta < STICK_SPEED.atol:
        onset = _from_rest(state, mu, alpha)
        if isinstance(onset, SlipResult):
            return onset
        state = onset or state
    return continue_slip(state, mu, alpha, t_max=t_max, s_max=s_max)


def _from_rest(state: SlipState, mu, alpha) -> SlipResult | SlipState | None:
    """A start at rest judged by the stuck rod's forces (``crosscheck.theory.sticking.at_rest``), not by its speed.

    None when the friction holds it (|F_t| <= mu F_n, F_n >= 0: the STICK at the start stands); a ``SlipResult`` at
    t = 0 when it lifts off (b > 0), has no rigid mode (JAM), or starts slipping towards S (varphi = +pi/2, outside
    the paper's domain (-pi, 0]: SLIP, reason "varphi=pi/2"); otherwise the slip onset, the start with varphi =
    -pi/2 (outwards) and eta = ``SLIP_ONSET_SPEED``, from which the flow runs.  The given varphi of a tip at rest
    means nothing: the forces choose the direction.
    """
    from crosscheck.theory.sticking import SLIP_ONSET_SPEED, at_rest

    rest = at_rest(state, mu, alpha)
    if rest.mode == "stick":
        return None
    b0, p0, *_ = _coefficients(state.varphi, state.Psi, state.theta, state.Theta, float(mu), float(alpha), 0.0)
    x0 = np.array([[state.eta, state.varphi, state.psi, state.Psi, state.theta, state.Theta]])
    if rest.mode != "slip" or rest.varphi > 0.0:
        outcome, reason = {
            "liftoff": (Outcome.LIFTOFF, "start"),
            "inconsistent": (Outcome.JAM, "start: at rest with no consistent mode"),
        }.get(rest.mode, (Outcome.SLIP, "varphi=pi/2"))
        return SlipResult(outcome, 0.0, state, reason, b0, p0, np.zeros(1), np.zeros(1), x0)
    return SlipState(
        theta=state.theta, varphi=rest.varphi, Theta=state.Theta, Psi=state.Psi, eta=SLIP_ONSET_SPEED, psi=state.psi
    )


def continue_slip(state: SlipState, mu, alpha, *, t_max: float = 10.0, s_max: float = 1e4) -> SlipResult:
    """``slip_until_event`` from a state the model itself reached (after an impact: its rates are not held
    to the ranges of a user's start)."""
    mu = float(check("mu", mu, MU))
    alpha = float(check("alpha", alpha, ALPHA))
    t_max = float(check("t_max", t_max, HORIZON))
    s_max = float(check("s_max", s_max, Interval(0.0, 1e8, lo_open=True, hi_open=False)))
    y0 = np.array([state.eta, state.varphi, state.psi, state.Psi, state.theta, state.Theta, 0.0])
    b0, p0, *_ = _coefficients(state.varphi, state.Psi, state.theta, state.Theta, mu, alpha, 0.0)
    early = _start_outcome(state.eta, b0, p0)
    if early is not None:
        return SlipResult(early, 0.0, state, "start", b0, p0, np.zeros(1), np.zeros(1), y0[None, :6].copy())
    outcome, t_end, y, reason, s_arr, Y, eta_out = integrate(y0, mu, alpha, 0.0, t_max=t_max, s_max=s_max)
    b, p, *_ = _coefficients(y[1], y[3], y[4], y[5], mu, alpha, 0.0)
    return SlipResult(outcome, t_end, _state_from(y, eta=eta_out), reason, b, p, s_arr, Y[:, 6].copy(), Y[:, :6].copy())


def integrate(
    y0: np.ndarray,
    mu: float,
    alpha: float,
    r: float,
    *,
    t_max: float,
    s_max: float,
    rtol: float | None = None,
    atol: float | None = None,
    friction=None,
) -> tuple:
    """The slipping flow with its contact at C = A - r K from the slipping start ``y0`` = (eta, varphi, psi, Psi, theta,
    Theta, 0) to its first event (checked arguments; the start rules are the caller's).

    ``friction(y)``: the friction's angle varphi_f at the 7-state y (``_coefficients``), for a friction law other than
    Coulomb's (``crosscheck.engines.bullet.law``); None: Coulomb's.

    Returns (outcome, t_end, y, reason, s, Y, eta_out): the event, its real time, the 7-state there, which rule fired,
    the trajectory cut at the event (s and the (n, 7) states), and 0 for a STICK's returned slip speed (None otherwise).
    """
    rtol = SLIP_INTEGRATION.rtol if rtol is None else rtol
    atol = SLIP_INTEGRATION.atol if atol is None else atol
    events, meaning = _events(mu, alpha, r, t_max, friction)
    fun = (
        (lambda s, y: _rhs7(y, mu, alpha, r))
        if friction is None
        else (lambda s, y: _rhs7(y, mu, alpha, r, friction(y)))
    )
    sol = solve_ivp(fun, (0.0, s_max), y0, method="DOP853", rtol=rtol, atol=atol, events=events)
    s_arr, Y = sol.t, sol.y.T
    if sol.status == -1 or not np.all(np.isfinite(Y)):
        good = np.all(np.isfinite(Y), axis=1)
        Y, s_arr = Y[good], s_arr[good]
        return Outcome.DIVERGED, float(Y[-1, 6]), Y[-1], "solver", s_arr, Y, None

    outcome, reason, s_arr, Y = first_event(sol, meaning, y0)
    y = Y[-1].copy()
    t_end = max(float(y[6]), 0.0)  # dt/ds = eta p < 0 only within P_RESOLVED of p = 0: rounding, not time
    eta_out = None
    if outcome is Outcome.STICK:
        # eta = 0 is reached as s -> inf but at finite real time: add the time
        # still needed at the current real-time deceleration d eta/dt = f_eta / (eta p).
        f7 = fun(0.0, y)
        deta_dt = f7[0] / f7[6]
        if deta_dt < 0:
            t_end += -y[0] / deta_dt
        eta_out = 0.0
    if outcome is Outcome.SLIP and reason == "t_max":
        t_end = t_max
    return outcome, t_end, y, reason, s_arr, Y, eta_out


def slip_outcomes(states, mu, alpha, *, t_max: float = 10.0) -> tuple[np.ndarray, np.ndarray]:
    """``slip_until_event`` over many states (a loop; each run takes a few ms).

    Args:
      states: iterable of ``SlipState``.
      mu, alpha, t_max: as ``slip_until_event``.

    Returns:
      (outcomes, times): (N,) int8 array of ``Outcome`` values and (N,) real scaled times.
    """
    results = [slip_until_event(s, mu, alpha, t_max=t_max) for s in states]
    return (np.array([r.outcome for r in results], dtype=np.int8), np.array([r.time for r in results], dtype=float))
