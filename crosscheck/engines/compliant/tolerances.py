"""The compliant rod's tolerances: its integration settings, slip-stop event, checks, and its eps -> 0 limit's.

Each allowance with where its number comes from (``crosscheck.tolerances.Tolerance``: atol + rtol |want|;
``guard=True`` marks a regression guard set from a measured spread).
"""

from __future__ import annotations

from crosscheck.tolerances import Tolerance

# -------------------------------------------------------- compliant rod ---
#: solve_ivp (Radau) on the compliant rod (crosscheck.engines.compliant): rtol 1e-8
#: and atol 1e-10 on O(1) states; on the gap g of the contact point atol is
#: scaled by eps, so a gap error moves the force F_n = -g / eps^2 + ... by at
#: most 1e-10 / eps (1e-7 m g at eps = 1e-3).  Scaling by eps^2 instead (the
#: penetration's own size) made the solver resolve each decaying fast
#: transient of the contact to 1e-10 of its size: 2-3x the steps for no gain.
#: Measured against rtol 1e-11 / atol 1e-13 runs over t in [0, 1] (slipping,
#: slip stop, stick, stick break; eps = 1e-2, 1e-3): slow variables within
#: 5e-9, slip-stop times within 5e-11; 1000x below the O(eps^2) model error
#: at the smallest eps = 1e-2 the tests take.
COMPLIANT_INTEGRATION = Tolerance(atol=1e-10, rtol=1e-8, why="Radau on the compliant rod: O(1) states, gap atol x eps")

#: The compliant rod's slip-stop event fires when C's slip speed falls to this
#: (scaled, l omega); the friction direction s/|s| is singular at s = 0, so
#: the stop is an event at a tiny speed, as the rigid flow's STICK_SPEED; the
#: residual slip is removed by a tangential impulse (kinetic energy change
#: ~1e-18) and the time still needed, 1e-9 / |ds/dt|, is added linearly.
SLIP_STOP = Tolerance(atol=1e-9, rtol=0.0, why="compliant rod: slip speed of C at which the slip-stop event fires")

#: Below this slip speed of C the compliant rod's slipping friction takes the
#: state's restart direction d instead of s/|s| (``Dynamics.slip_floor``).
#: d depends on the state, not on s: for a stopping slip it is the approach's
#: friction direction, so inside the floor a solver step can carry s through
#: 0 to the far side smoothly; with |s| above the slip-stop speed at both of
#: its ends the event (a sign change of |s| - SLIP_STOP.atol between step
#: ends) is not seen.  On the far side the friction s/|s| has turned round
#: while d has not: outside the floor |s| falls, inside it rises (measured at
#: a Corollary 4.2 stop, mu = 6, eps = 1e-3: d|s|/dt = -475 and +393), so a
#: floor at the event's speed is a surface attracting from both sides, which
#: an implicit solver approaches geometrically and never crosses (|s| ->
#: 1.0002e-9, steps 1e-11 -> 7e-16, step-size underflow).  The floor must lie
#: strictly below the slip-stop event, so the far side's slip falls through
#: the event's speed where s/|s| is smooth.  Half of it leaves a window of
#: 5e-10 in |s| (>= 5e-13 in time at the measured |ds/dt| <= 1e3, ~1e4 ulp of
#: t ~ 1) and keeps the switch 5x above the solver's absolute velocity
#: tolerance (COMPLIANT_INTEGRATION.atol = 1e-10), so a restarting slip's
#: direction at the switch is not the solver's error.  A stop seen on the far
#: side is late by ~2 SLIP_STOP.atol / |ds/dt| (5e-12 there): the far side's return.
SLIP_FLOOR = Tolerance(
    atol=0.5 * SLIP_STOP.atol,
    rtol=0.0,
    why="compliant rod: restart-direction floor of the slip speed, strictly below the slip-stop event",
)

#: Order of convergence of the compliant rod to the rigid flow (slow
#: variables at t = 1, eps = 0.04, 0.02, 0.01, started on the slow manifold;
#: slip-stop time against the rigid STICK time).  The error is
#: C eps^2 (1 + kappa eps + ...): the fitted slope differs from 2 by
#: ~kappa eps_max / (2 ln 2).  Measured slopes: 2.005 and 1.970 (two slipping
#: states, eps 0.005-0.04), 2.0 for the stop time; 0.1 is 3x the largest
#: measured deviation: a regression guard on the order, not a bound.
COMPLIANT_ORDER = Tolerance(
    atol=0.1, rtol=0.0, why="compliant -> rigid: fitted order 2 (3x the measured deviation 0.03)", guard=True
)

#: Central differences of a body point's position (step h = 1e-5, O(1)
#: positions and rates |v| <= ~5): truncation h^2 |third derivative| / 6
#: <= 1e-10 x 125 / 6 ~ 2e-9, rounding 1e-16 / h = 1e-11.
COMPLIANT_KINEMATICS = Tolerance(atol=5e-9, rtol=0.0, why="C's velocity by central differences, h = 1e-5, |v| <= 5")

#: After a stick break the slip grows from rest along the restart direction,
#: which turns with the state: the angle between C's slip and the direction
#: opposite the friction at the break, per unit time tau after it, is
#: (2/3)|d'| with d' the restart direction's rate (O(1): the rod's rates are
#: O(1)).  Measured 0.87 at tau = 1e-4 and 0.36 at 1e-3; 5 is a guard.  A
#: wrong restart direction gives an O(1) angle, i.e. 1e3-1e4 per unit time.
COMPLIANT_RESTART = Tolerance(
    atol=5.0, rtol=0.0, why="slip direction after a stick break: turn rate (measured <= 0.9)", guard=True
)

#: One step of the compliant rod may raise the computed energy by its local
#: error: <= atol + rtol |y_i| ~ 3e-8 per component (COMPLIANT_INTEGRATION,
#: |y_i| <= 3) times |dE/dy_i| (velocities <= 3, gravity 1, the elastic
#: force <= 3), summed over ~10 components: 3e-7.
COMPLIANT_ENERGY = Tolerance(atol=3e-7, rtol=0.0, why="energy rise within one solver step's local error allowance")


# ------------------------------------------- compliant rod: the eps -> 0 limit ---
#: The eps-free fast problem (crosscheck.engines.compliant.studies.limit.fast_limit,
#: DOP853 at rtol 1e-11) against independent computations of the same
#: numbers: the planar closed form of e (a 2x2 linear oscillator's release
#: time by brentq at 1e-14) and the rigid impulse's P_c and w
#: (crosscheck.theory.impact.darboux_keller, DOP853 at rtol 1e-12).  The fast problem starts at
#: P0 = 1e-9 on the exact linear growth direction, an O(P0) = 1e-9 relative
#: error; measured differences <= 4e-12.
COMPLIANT_LIMIT_FAST = Tolerance(
    atol=1e-9, rtol=1e-9, why="fast problem vs closed form / iwc: start at P0 = 1e-9 on the linear direction"
)

#: t_stop/eps of the compliant rod minus its leading law (1/lambda) ln(1/eps)
#: + C, against the first corrections C1 eps T + C2 eps T^2
#: (compliant_limit.time_corrections: the drift of the slip speed and of
#: lambda along the formal slipping flow during the growth).  The remainder
#: is O(eps) without the factor T = t_stop/eps, i.e. O(1/T) relative to the
#: corrections; with T >= 2 in the tests and a remainder coefficient of the
#: same size as C1 (the same drifts, over the O(eps) start-up transient),
#: rtol 0.5.  Measured worst 0.22 (xi = 5, eps = 1e-2, T = 1.6); 0.04 at xi = 1.
COMPLIANT_LIMIT_SLIP_TIME = Tolerance(
    atol=0.0, rtol=0.5, why="O(eps) remainder ~ 1/T of the O(eps T) corrections, T >= 2"
)

#: e S xi^2 -> 1 as xi -> inf (compliant_limit.planar_restitution): the
#: overdamped stick phase releases on its slow mode with w_f = (1 + |p|/S)
#: d_s/xi; the corrections are relative O(1/(|p| xi^2)) (lambda = |p| xi +
#: 1/xi - ...) and O(ln(xi)/xi^2) (the fast mode's tail at the release); at
#: xi = 30 and |p| >= 0.08 both are below 0.03; 0.07 = 2/xi allows twice
#: that.  Measured 0.022 (p = -0.08), 0.011 (p = -0.85).
COMPLIANT_LIMIT_LARGE_XI = Tolerance(atol=0.07, rtol=0.0, why="e S xi^2 = 1 + O(1/(|p| xi^2)) at xi = 30")

#: Observed order of the post-event error (compliant at the contact end
#: against the limit impact) at inconsistent starts, against the observed
#: order of the contact-end time t_end = O(eps ln(1/eps)) over the same eps:
#: the compliant impulse ends t_end after the rigid (instantaneous) one, and
#: the O(1) dynamics drift by O(t_end) meanwhile.  The error's O(eps)
#: remainder (the impulse's own O(eps) span, without the log) changes the
#: local slope by ~1/ln(1/eps) <= 0.15 between eps = 1e-2 and 1e-6.
#: Measured differences 0.01-0.03 (p <= -0.56); 0.10 at p = -0.08, where
#: t_end is ~10x longer.
COMPLIANT_LIMIT_POST_ORDER = Tolerance(
    atol=0.15, rtol=0.0, why="error ~ t_end = O(eps ln(1/eps)); O(eps) remainder shifts the slope by ~1/ln(1/eps)"
)

#: Observed order of the slip-stop lag t_stop - t_jam at a Corollary 4.2
#: jam, against 4/5: near the jam p ~ -k (P - P_jam), and delta'' = -b - p F_n
#: balances at t - t_jam ~ eps^(4/5), P - P_jam ~ eps^(2/5) (module docstring
#: of crosscheck.engines.compliant.studies.limit), with corrections of relative order
#: eps^(1/5) (the impulse P_stop - P_jam = O(1) beyond the inner region),
#: which shift a fitted slope over eps in [1e-5, 1e-3] by (1/5) c eps^(1/5)
#: <= 0.05 c, c = O(1): 0.1.  Measured 0.76-0.80.
COMPLIANT_LIMIT_JAM_LAG_ORDER = Tolerance(atol=0.1, rtol=0.0, why="t_stop - t_jam ~ eps^(4/5) (1 + O(eps^(1/5)))")
