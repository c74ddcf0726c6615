"""Every tolerance of the project, in one place, with where its number comes from.

A value ``got`` passes against ``want`` when
``|got - want| <= atol + rtol * |want|`` (numpy's ``isclose`` rule; scipy's
``_ivp`` error measure).  ``Tolerance.ratio`` gives the error in multiples of
the allowance, so reports can say "0.3 of tolerance" rather than "passed".

Sections: analytic reference, Pinocchio, MuJoCo, GB manifold.  Each engine's
section is edited only by that engine's module.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["Tolerance", "all_tolerances"]


@dataclass(frozen=True)
class Tolerance:
    """An allowance atol + rtol |want| and where its numbers come from.

    ``guard`` marks a regression guard: a threshold set from a measured
    spread (so that a change which moves the measurement is noticed), not a
    bound derived from the paper, the integrator or the timestep.  Reports
    label the two kinds differently.
    """

    atol: float
    rtol: float
    why: str
    guard: bool = False

    def allowance(self, want) -> np.ndarray:
        """atol + rtol |want|: the largest |got - want| that passes."""
        return self.atol + self.rtol * np.abs(np.asarray(want, float))

    def ratio(self, got, want) -> np.ndarray:
        """|got - want| / allowance(want): <= 1 passes."""
        got, want = np.asarray(got, float), np.asarray(want, float)
        return np.abs(got - want) / self.allowance(want)

    def ok(self, got, want) -> bool:
        r = self.ratio(got, want)
        return bool(np.all(np.isfinite(r) & (r <= 1.0)))

    def as_dict(self) -> dict:
        return asdict(self)


# ---------------------------------------------------------------- analytic ---
#: Closed forms evaluated two ways in double precision (a handful of
#: trig/sqrt operations each, condition numbers O(10) away from theta -> 0,
#: pi/2): 1e-12 relative is ~4500 ulp, ample for the rounding of ~20 flops
#: and tight enough to catch any wrong coefficient.
CLOSED_FORM = Tolerance(atol=1e-12, rtol=1e-12, why="double-precision rounding of closed forms (~20 flops)")

#: Identities that evaluate a function at a root computed by another closed
#: form, e.g. p(theta_+(varphi), varphi) = 0: p has terms of size 1 + alpha,
#: so the residual is rounding of O(alpha) numbers.
ROOT_RESIDUAL = Tolerance(atol=1e-12, rtol=0.0, why="rounding of O(1 + alpha) terms at a closed-form root")

#: Symbolic (sympy Lagrangian) vs numeric eq. linode2 at random states: the
#: required 1e-12 relative bound, relative to the norm of the acceleration
#: vector (componentwise for eq. rotode).
DERIVATION = Tolerance(atol=0.0, rtol=1e-12, why="required: independent derivation to 1e-12 relative (measured 1.2e-15)")

#: Central finite differences with step h of a smooth function: truncation
#: O(h^2 f''') + rounding O(eps f / h); h = 1e-6 gives ~1e-8 relative.
FINITE_DIFFERENCE = Tolerance(atol=1e-7, rtol=1e-6, why="central differences, h = 1e-6: truncation + eps/h rounding")


# --------------------------------------------------------------- pinocchio ---
# Pinocchio (crosscheck.engines.pinocchio.model) against the analytic reference, compared in the paper's scaled
# units.  Each allowance is atol * scale, where scale is the size of the terms the quantity is summed
# from (its term scale; crosscheck.engines.pinocchio.studies.dynamics_terms): A = (1 + alpha)|F|_1 + V for tip accelerations,
# V = (1 + |v_s|_1)^2 for velocity terms (v_s the five scaled velocities), 1 for M and g, 1 + |v_s|_1
# for C, (1 + alpha)(1 + mu) for p.  Rounding of a sum is bounded by a small multiple of eps times its
# term scale; atol = 1e-14 is ~45 eps.  Measured maxima over 1e5 random states (validate, seeds 1, 2)
# are quoted with each.
#
# Why a condition number.  Pinocchio forms M_psipsi = I0 cos^2 theta with an absolute rounding of
# ~eps I0 (crba and computeMinverse alike; the rotated inertia of the body), not eps I0 cos^2 theta.
# Everything that goes through M^-1 in the psi direction (G = J M^-1 J^T, the free acceleration, the
# route G F + free) therefore carries the relative error eps * kappa, kappa = 1/cos^2 theta, the
# condition number of M in its natural units diag(m, m, m, I0, I0).  Measured: error/A = 1.1 eps/cos^2
# theta on every decade of cos theta from 1e-6 to 1e-1.  So the required 1e-12 relative (to A) holds for
# G F + free only where cos theta >~ 1.6e-2 (1.5e-12 at cos theta in [1e-2, 1e-1), 1.6e-10 in [1e-3,
# 1e-2)).  aba never forms M, but its bias forces carry the same absolute eps I0 |v|^2 and are divided
# by the articulated inertia I0 cos^2 theta, then mapped by J_psi = l cos theta: error/A = 1.5 eps/cos
# theta, i.e. within 1e-12 for cos theta >~ 3e-4.  Neither is a modelling error: both scale exactly
# as the rounding analysis says, and the vertical components (b, p) do not see it (the tip's height
# does not depend on psi).

#: Tip acceleration by aba + classical frame acceleration vs eq. linode2, scale A / cos theta.
#: Measured max 3.3e-16 (1.5 eps).
PIN_TIP_ACCELERATION = Tolerance(atol=1e-14, rtol=0.0, why="aba route: ~45 eps of A / cos theta (articulated inertia I0 cos^2 theta)")

#: G F + free acceleration, G and the free acceleration vs eq. linode2, scale kappa * term scale,
#: kappa = 1 / cos^2 theta.  Measured max 2.4e-15 (11 eps); 2e-14 covers the ~25 operations of
#: a 5 x 5 solve and the products with J.
PIN_THROUGH_MINV = Tolerance(atol=2e-14, rtol=0.0, why="through M^-1: ~90 eps of the term scale times cond(M) = 1/cos^2 theta")

#: M, C, g and C v + g = nonLinearEffects entry by entry in scaled units (M_s = L M L / (m l^2) etc.).
#: Measured max 1.0e-15 (C), 5.6e-16 (M, g), 3.3e-16 (nle).
PIN_MATRICES = Tolerance(atol=1e-14, rtol=0.0, why="M, C, g entries: ~45 eps of the entry scale (1 for M, g; 1 + |v_s| for C)")

#: b and p from Pinocchio's free acceleration and Delassus row e_z^T G vs eqs. b and p.
#: Measured max 2.1e-15 (b, scale V), 1.0e-15 (p, scale (1 + alpha)(1 + mu)).
PIN_SLIP = Tolerance(atol=1e-14, rtol=0.0, why="b, p: ~45 eps of their term scale; z row of G avoids the psi direction")

#: LCP modes must be identical (codes differ by >= 1) except on a boundary band |b| or |p| <= PIN_SLIP.
PIN_MODE = Tolerance(atol=0.5, rtol=0.0, why="mode codes equal off the boundary band of PIN_SLIP")

#: mu_P found from Pinocchio's p alone (min over theta by bounded Brent, root in mu by brentq to
#: xtol 1e-14) vs 2 sqrt(1 + alpha) / alpha: the required 1e-9.  Measured 2.2e-16.
PIN_MU_P = Tolerance(atol=1e-9, rtol=0.0, why="required: mu_P from p to 1e-9")

#: Finite differences (J vs tip positions, dJ vs J along v, M' vs M along v): the allowance is this
#: multiple (atol) of the a-priori error bound eps f / h + h^2 |f'''| / 6 of a central difference with
#: step h, f and f''' bounded from the rod's size and rates (tests/test_pinocchio_model.py).
PIN_FINITE_DIFFERENCE = Tolerance(atol=4.0, rtol=0.0, why="multiple of the central-difference bound eps f/h + h^2 f'''/6")


# ------------------------------------------------------------------ mujoco ---
#: MuJoCo's free tip acceleration (contacts off) vs eq. linode2 with F = 0 and
#: eq. b, in units of g.  The only modelling difference is the axial inertia
#: eps = 1e-12 I0 (``engines.mujoco_model.AXIAL_INERTIA``; MuJoCo needs > 0), which
#: changes the psi inertia by a relative 1e-12 tan^2 theta (<= 1e-9 for theta
#: <= 1.54); measured max 9e-10 over 300 random states (1e-9 at eps = 1e-9 I0
#: was 9e-7: the error is proportional to eps).
MUJOCO_FREE_ACCELERATION = Tolerance(atol=1e-8, rtol=1e-8, why="axial inertia 1e-12 I0 in the psi inertia, x tan^2 theta")

#: MuJoCo's tip acceleration with contact vs eq. linode2 with MuJoCo's own
#: contact force moved to the capsule's contact point
#: (``studies.mujoco_contact.capsule_tip_acceleration``), as a fraction of the term scale
#: g (1 + alpha |F|_1 / (m g)).  Exact up to the solver's stopping rule: with
#: solver_tolerance 1e-10 (the default) force and acceleration agree to ~6e-7;
#: run to its iteration limit (solver_tolerance 0) the measured max is 1.4e-11
#: over 200 random states x 5 radii.  Without the correction the error is
#: 0.41 r/l (max; 0.27 r/l median): linear convergence as r -> 0.
MUJOCO_CONTACT_ACCELERATION = Tolerance(atol=1e-9, rtol=0.0, why="converged contact solve (solver_tolerance 0): rounding of forces up to ~50 m g")

#: Smallest Psi at which MuJoCo lifts off at t = 0 (theta_L, Theta = 0,
#: varphi = -pi/2) vs Psi_L (eq. psil), default timestep 3e-4.  LIFTOFF needs
#: lift_steps = 3 force-free rows with upward acceleration; along the free
#: flight b(t) = b0 - Psi^4 cos^2 sin^3 t^2 + ..., so a rod that just lifts
#: off must keep b > 0 for 2 more rows: Psi* - Psi_L <= (Psi_L^3 / 6)(3 dt)^2
#: = 5.5e-7 at dt = 3e-4, 6e-5 at 3.1e-3 (1 ms for a 1 m rod).  Measured:
#: 6e-11 (the bisection's resolution) for 1e-4 and 1e-5 s, 3.9e-9 for 1e-3 s,
#: for mu = 0.3, 1, 2: semi-implicit Euler lags Psi by one step, which keeps
#: b(row 2) = b0 + O(dt^3).
MUJOCO_LIFTOFF_ONSET = Tolerance(atol=5.5e-7, rtol=0.0, why="3 rows of b > 0 needed: (Psi_L^3/6)(3 dt)^2 at dt = 3e-4")
MUJOCO_LIFTOFF_ONSET_COARSE = Tolerance(atol=6.1e-5, rtol=0.0, why="(Psi_L^3/6)(3 dt)^2 at dt = 3.13e-3 (1 ms for a 1 m rod)")

#: Ratio kappa in MuJoCo's lift-off decision b - kappa Theta^2 sin(theta) = 0
#: (b of eq. b; Theta^2 sin(theta) l omega^2 is the dJ v part of the tip's
#: vertical acceleration).  Started with the contact inactive, the first
#: semi-implicit Euler step sets z_1 = dt^2 (J qacc + dJv / 2) = dt^2 (b -
#: Theta^2 sin / 2): kappa = 1/2, measured 0.4993..0.5007 for |Theta| = 0.5, 1.
#: With the contact active and mu = 0 MuJoCo's constraint sees J qacc = b -
#: Theta^2 sin: kappa = 1, measured to 1e-4.  0.01 covers the bisection and
#: the O(dt) terms of the first step.
MUJOCO_DJV_KAPPA = Tolerance(atol=0.01, rtol=0.0, why="bisection on Psi + O(dt) terms of the first Euler step")

# Event agreement and jams (crosscheck.studies.agreement and .jams, crosscheck validate mujoco), at the default
# timestep 3e-4, timeconst 0.06, radius 0.01, horizon 2, random slipping states with mu in [0.3, 6].
# These are not rounding bounds: MuJoCo's soft elliptic contact is a different model (its force builds
# up over tau; off the planar section its friction is rotated from -slip by up to ~30 deg, see
# crosscheck.engines.mujoco.studies.contact.friction_skew), so the allowances are measured values with a margin.

#: Fraction of random slipping states whose MuJoCo first event (crosscheck.engines.classifier, compared up to the
#: analytic event + 2 tau) differs from slip_until_event's, an analytic JAM met by a MuJoCo STICK
#: counting as agreement.  Measured 0.12 +- 0.026 (range 0.08-0.17) over 7 seeds of 300 states (the
#: default of validate), so 0.2 is ~3 sd above the mean (sd ~0.06 at 30 states); the disagreement
#: sits next to the analytic event boundaries, in the first few tau and off the planar section.
MUJOCO_EVENT_DISAGREEMENT = Tolerance(atol=0.2, rtol=0.0, why="regression guard: measured 0.12 +- 0.026 (n = 300): soft contact + friction skew", guard=True)

#: Median |t_MuJoCo - t_analytic| over states where both report the same event: the soft contact's
#: response time tau = 0.06 (its force builds up over tau; STICK is read at eta = tau).  Measured
#: 0.022-0.032.
MUJOCO_EVENT_TIME = Tolerance(atol=0.06, rtol=0.0, why="contact time constant tau = 0.06 (measured 0.022-0.032)")

#: Number of MuJoCo JAMs (crosscheck.engines.classifier) among random slipping states with mu < mu_P: none
#: allowed (atol 0.5 on an integer count).  Below mu_P eq. p > 0 for every slip direction, so no
#: friction direction (MuJoCo's skewed one included) can make the slipping force unbounded.
#: Asserted only for mu with p_min(mu) > Thresholds.jam_p_eff (crosscheck.studies.validate.MUS_BELOW): near
#: mu_P the JAM rule's p_eff <= 0.2 admits hard slips and landings of a hopping tip (mu = 1.3,
#: p_min = 0.04: 1 of 60 at seed 0, reported in validate's extra, not asserted).
MUJOCO_NO_JAM_BELOW_MU_P = Tolerance(atol=0.5, rtol=0.0, why="integer count must be 0: p > 0 for all varphi below mu_P")

#: Fraction of Corollary 4.2 states (crosscheck.corollary.corollary_states: analytic JAM at t in
#: [0.2, 1.5], b <= -0.1 and |varphi + pi/2| >= 0.1 at the jam) whose MuJoCo slip does NOT end (no
#: JAM, STICK or LIFTOFF of crosscheck.engines.classifier) within 0.15 = 2.5 tau of the analytic jam, pooled over
#: mu = 1.4, 1.7, 6.  Measured 0.37 +- 0.06 over 8 seeds of 45 states (max 0.51); validate pools 90
#: states (binomial sd 0.05), so 0.55 is ~3.5 sd above the mean.  MuJoCo delivers the impulse itself
#: (JAM) in 7-40 % of them; otherwise its soft contact ends the slip by sticking or lifting off.
MUJOCO_COROLLARY_STOP = Tolerance(atol=0.55, rtol=0.0, why="regression guard: measured 0.37 +- 0.06 (sd 0.05 at n = 90): soft contact ends the slip by stick/lift-off", guard=True)

# The rigid engine (crosscheck.engines.pinocchio.stepper): a time-stepper on Pinocchio's NCP solvers.

#: One step of a slipping tip: normal impulse / dt against eq. FZ, -b/p, with p evaluated for the
#: friction direction of the step (the end-of-step slip, which the NCP's Coulomb law sees).  The
#: step enforces a_A = J a + dJ v = 0 along the normal, so the two are equal up to the solver's
#: stopping rule: complementarity and feasibility below 1e-13 m g x dt (Options.tolerance), i.e.
#: 1e-13 relative to an O(1) m g force.  Measured <= 1.4e-11 over 1600 seeded states with F_z >= 1e-2 m g
#: whose step has the slip as its only solution (crosscheck.engines.pinocchio.studies.rigid.sticking_admissible: above mu_P,
#: near p = 0, the step also admits the stuck tip, and PGS may return that one instead).
RIGID_STEP_FORCE = Tolerance(atol=0.0, rtol=1e-9, why="required; NCP solved to 1e-13 m g x dt (measured <= 1.4e-11)")

#: Lift-off onset of the rigid engine at theta_L, Theta = 0, varphi = -pi/2: the first step's impulse
#: is 0 iff b >= 0 (eq. b enters the step exactly through dt dJ v), and a rigid LIFTOFF needs one
#: force-free upward row, so the onset is Psi_L whatever the timestep: no soft-contact delay.  The
#: bound is the required 1e-9; measured: the bisection's resolution (1.9e-12) at dt = 3e-3 ... 1e-4.
RIGID_LIFTOFF_ONSET = Tolerance(atol=1e-9, rtol=0.0, why="required: exact one-step lift-off decision (measured at the 1.9e-12 resolution)")

#: Order of convergence of the rigid engine's slipping trajectories to slip_until_event: semi-implicit
#: Euler is first order.  Measured 1.00001 over dt = 4e-3 ... 2.5e-4 (errors 4.7e-4 ... 2.9e-5 at t = 0.3).
RIGID_SLIP_ORDER = Tolerance(atol=0.05, rtol=0.0, why="semi-implicit Euler: first order (measured 1.00001)")

#: Order of convergence of the rigid engine's state one row after its jam to crosscheck.iwc.impact
#: (the impact without collision), as dt -> 0, from planar impasses (p < 0, b < 0 on varphi = -pi/2,
#: Psi = 0 at t = 0).  The step solves the same impulse problem at the same configuration plus the
#: O(dt) gravity, Coriolis and dJ v terms: first order.  Measured 0.9992-1.0000 (mu = 1.4, 2; Theta
#: = 0.5, -0.3) over dt = 1e-3, 3e-4, 1e-4.
RIGID_IWC_ORDER = Tolerance(atol=0.05, rtol=0.0, why="one step = the IWC + O(dt) terms: first order (measured 0.9992-1.0000)")

# The rigid engine's contact events (crosscheck.studies.validate), timestep 1e-3, the same random
# states and horizon as MuJoCo's.  The engine is the theory's own rigid Coulomb contact, so what
# differs is discretisation: events within O(dt) of a boundary of the analytic outcome, and the
# square-root approach to p = 0 (p ~ (t_jam - t)^(1/2), measured exponents 0.49-0.57: the force
# -b/p grows like (t_jam - t)^(-1/2)), which a first-order step meets early by up to O(sqrt(dt)).

#: Fraction of random slipping states whose rigid-engine first event differs from slip_until_event's
#: (compared up to the analytic event + 3 dt; an analytic JAM met by a STICK counts as agreement, as for
#: MuJoCo).  Measured 0.033 at seed 0 (n = 300; 0.077 before the engine's sticking-impulse rescue and
#: 0.133 at seed 1 with n = 30).  Without the JAM-as-STICK allowance the agreement is 0.85: 35 of 64
#: analytic JAMs end in a STICK one row before the jam, because the slip, decelerated by the force
#: -b/p ~ (t_jam - t)^(-1/2), runs out within the last step when the analytic slip speed at the jam is
#: below ~ mu |b| sqrt(dt); those 35 become JAMs as dt shrinks: 0, 16, 30 of 35 at dt = 1e-3, 3e-4,
#: 1e-4.  A regression guard from measured values, not a derived bound.
RIGID_EVENT_DISAGREEMENT = Tolerance(atol=0.15, rtol=0.0, why="regression guard: measured 0.033 (n = 300, seed 0), on event boundaries", guard=True)

#: Median |t_engine - t_analytic| over states with the same event: a first-order stepper shifts an
#: event by O(dt) = 1e-3 (measured 0.00155 at seed 0, n = 300: lift-offs and jams, O(dt)-O(sqrt(dt))).
RIGID_EVENT_TIME = Tolerance(atol=0.01, rtol=0.0, why="regression guard: O(dt)-O(sqrt dt) event shift (measured 0.0016)", guard=True)

#: Rigid JAMs among random slipping states below mu_P: none (p > 0 for every slip direction).
RIGID_NO_JAM_BELOW_MU_P = Tolerance(atol=0.5, rtol=0.0, why="integer count must be 0: p > 0 for all varphi below mu_P")

#: Fraction of Corollary 4.2 states (mu = 1.4, 1.7, 6) whose rigid-engine slip does not end (JAM,
#: STICK or LIFTOFF) within RIGID_JAM_WINDOW = 0.05 of the analytic jam.  Measured 0.056 at seed 0
#: (n = 90) and 0.067 at seed 1; the JAMs alone are 0.83 and 0.74 of the states (mu = 6: 0.73 and
#: 0.57; the rest stick at the jam row, as in RIGID_EVENT_DISAGREEMENT).
RIGID_COROLLARY_STOP = Tolerance(atol=0.2, rtol=0.0, why="regression guard: measured 0.056-0.067 (n = 90, seeds 0, 1)", guard=True)

#: The keys of an engine's event-tolerance profile (``EngineSpec.tolerances``, declared by each engine
#: with its own derivations or measurements): the checks of ``crosscheck.studies.validate``.
EVENT_TOLERANCE_KEYS = ("liftoff_onset", "event_disagreement", "event_time", "no_jam_below_mu_P", "corollary_stop")


# ---------------------------------------------------------------------- gb ---
#: solve_ivp (DOP853) tolerances of the desingularised slipping flow, eq. f.
#: The state is O(1) (angles, scaled rates, eta ~ 0.1-10); rtol 1e-10 keeps the
#: global error of t and of the event times near 1e-9 over the O(10) scaled
#: times of a run while one run still takes a few ms.
SLIP_INTEGRATION = Tolerance(atol=1e-12, rtol=1e-10, why="solve_ivp DOP853 on eq. f: O(1) states, event times ~1e-9")

#: A slipping trajectory has "reached the GB manifold" when hypot(p, b) falls
#: below this.  GB points are equilibria of eq. f, approached only as s -> inf
#: (real time t converges), so reaching them needs a threshold; 1e-7 is 1000x
#: above the integration error of p and b (atol 1e-12, rtol 1e-10 of O(1+alpha)
#: terms) and the real time still left is ~ eta p / |lambda| ~ 1e-7.
GB_REACHED = Tolerance(atol=1e-7, rtol=0.0, why="radius of the (p, b) ball counted as reaching the GB manifold")

#: p below -1e-8 counts as having crossed p = 0 (JAM).  p is computed from
#: theta and varphi integrated at rtol 1e-10 with |grad p| ~ alpha mu ~ 5, so
#: its error is ~5e-10; on the planar section p = 0 is invariant (eq. pdotarg
#: vanishes at varphi = -pi/2) and that noise alone would fake a crossing.
P_RESOLVED = Tolerance(atol=1e-8, rtol=0.0, why="depth below p = 0 that counts as a crossing (20x the error of p)")

#: The tip has stuck when eta falls below this (scaled speed, units l omega).
#: eta = 0 is a set of equilibria of eq. f (approached as s -> inf); the real
#: time left, eta / |d eta/dt|, is added linearly, so the time error is O(1e-18).
STICK_SPEED = Tolerance(atol=1e-9, rtol=0.0, why="scaled slip speed counted as stuck (eta = 0 is an equilibrium of eq. f)")

#: Runs stop (outcome SLIP) when theta comes this close to 0 or pi/2: the
#: coefficients d1 = -alpha mu cos(varphi)/cos(theta) and c1 = 2 Psi Theta tan(theta)
#: of Appendix A blow up at theta = pi/2, and SlipState needs theta in (0, pi/2).
THETA_MARGIN = Tolerance(atol=1e-6, rtol=0.0, why="distance from theta = 0, pi/2 where a run stops (domain of SlipState)")

#: Identities that hold only on b = p = 0 (K = B A, eq. K; J = A B, eq.
#: jacobian; eig J = eig K + 4 zeros), evaluated at GB points from closed forms
#: (varphi_pm, a square root): b and p are ~1e-15 there and multiply
#: coefficients up to ~1e4 near theta -> pi/2 (d1 ~ 1/cos theta).  Measured
#: worst: 5e-14 (K), 2e-11 (J) relative over mu in [1.34, 6], |Psi| <= 10.
GB_IDENTITY = Tolerance(atol=1e-9, rtol=1e-9, why="identities on b = p = 0 at closed-form GB points (residual 1e-15 x coefficients <= 1e4)")

#: Event times of the desingularised flow against a real-time solve_ivp of
#: eq. polareqs_varphi where that is regular (p bounded away from 0): both runs
#: at rtol 1e-10, so their difference is a few 1e-9 over O(1) times.
EVENT_TIME = Tolerance(atol=1e-7, rtol=1e-7, why="event time: eq. f (s-time) vs real-time eq. polareqs_varphi, both rtol 1e-10")

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
SLIP_FLOOR = Tolerance(atol=0.5 * SLIP_STOP.atol, rtol=0.0,
                       why="compliant rod: restart-direction floor of the slip speed, strictly below the slip-stop event")

#: Order of convergence of the compliant rod to the rigid flow (slow
#: variables at t = 1, eps = 0.04, 0.02, 0.01, started on the slow manifold;
#: slip-stop time against the rigid STICK time).  The error is
#: C eps^2 (1 + kappa eps + ...): the fitted slope differs from 2 by
#: ~kappa eps_max / (2 ln 2).  Measured slopes: 2.005 and 1.970 (two slipping
#: states, eps 0.005-0.04), 2.0 for the stop time; 0.1 is 3x the largest
#: measured deviation: a regression guard on the order, not a bound.
COMPLIANT_ORDER = Tolerance(atol=0.1, rtol=0.0, why="compliant -> rigid: fitted order 2 (3x the measured deviation 0.03)", guard=True)

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
COMPLIANT_RESTART = Tolerance(atol=5.0, rtol=0.0, why="slip direction after a stick break: turn rate (measured <= 0.9)", guard=True)

#: One step of the compliant rod may raise the computed energy by its local
#: error: <= atol + rtol |y_i| ~ 3e-8 per component (COMPLIANT_INTEGRATION,
#: |y_i| <= 3) times |dE/dy_i| (velocities <= 3, gravity 1, the elastic
#: force <= 3), summed over ~10 components: 3e-7.
COMPLIANT_ENERGY = Tolerance(atol=3e-7, rtol=0.0, why="energy rise within one solver step's local error allowance")



def all_tolerances() -> dict[str, dict]:
    """Every named tolerance of this module, for reports' provenance blocks."""
    return {k: v.as_dict() for k, v in globals().items() if isinstance(v, Tolerance)}

# ----------------------------------------------------------------- capsule ---
# The rigid rod with its contact at the capsule point C = A - r K (crosscheck.capsule), scaled units.

#: p_C and b of crosscheck.capsule against Pinocchio with the tip Jacobian moved to C (J_C = J + r [K]x J_omega):
#: the allowance is atol * (1 + alpha)(1 + mu)(1 + r)(1 + |v_s|_1 / eta_C).  (1 + alpha)(1 + mu)(1 + r) bounds
#: the terms of p_C (1, alpha cos^2 theta, alpha mu cos theta (sin theta + r)); as for PIN_SLIP, ~45 eps of it.
#: Pinocchio's friction direction comes from J_C v, whose rounding eps |v_s|_1 turns the slip angle by
#: eps |v_s|_1 / eta_C, hence the last factor.  Measured 7e-16 of the scale (800 states, r = 0 ... 0.3).
CAPSULE_PIN_SLIP = Tolerance(atol=1e-14, rtol=0.0, why="p_C, b at C vs Pinocchio: ~45 eps of the term scale x (1 + |v_s|/eta_C)")

#: C's slip velocity (eta_C, and varphi_C x eta_C) of crosscheck.capsule.contact_slip against Pinocchio's J_C v:
#: rounding of sums of the five scaled velocities, atol * (1 + |v_s|_1).  Measured 3e-15 absolute.
CAPSULE_PIN_VELOCITY = Tolerance(atol=1e-14, rtol=0.0, why="C's slip velocity vs Pinocchio J_C v: ~45 eps of 1 + |v_s|_1")

#: The real-time slipping field at C (eta_C', varphi_C', Psi', Theta' = f / (eta_C p_C)) against Pinocchio's aba
#: with tau = J_C^T F, F = F_z (-mu u_C/|u_C|, 1), F_z from Pinocchio's own Delassus row at C: quantities through
#: M^-1, so PIN_THROUGH_MINV's 2e-14 of the term scale (1 + alpha)(1 + f)(1 + |v_s|_1)^2 / cos^2 theta,
#: times (1 + 1 / eta_C) for varphi_C' (an angular rate of the slip).  f = |F_z| (1 + (1 + alpha)(1 + mu) / |p_C|):
#: F_z = -b / p_C carries the rounding of p_C's terms relative to |p_C| (measured without that factor: 1.2e-14
#: at p_C = 0.0014).  Measured 2e-17 of that scale (2000 states, r = 0 ... 0.3).
CAPSULE_PIN_DYNAMICS = Tolerance(atol=2e-14, rtol=0.0, why="slip dynamics at C vs Pinocchio aba: through M^-1, as PIN_THROUGH_MINV")

#: crosscheck.capsule.slip_until_event at r = 0 against crosscheck.slipping.slip_until_event: the same vector
#: field (eq. f) written with other roundings (~1e-16 relative), both at SLIP_INTEGRATION, so event times agree
#: to the integrators' error, ~1e-9 over O(1) times (SLIP_INTEGRATION's level).  Measured 2e-14 (200 states).
CAPSULE_REDUCTION_TIME = Tolerance(atol=1e-9, rtol=1e-9, why="r = 0 vs crosscheck.slipping: same field, SLIP_INTEGRATION error")

#: A JAM approached at C (F_z ~ (t_jam - t)^(-1/2)) in the desingularised time: the event time at integrator
#: tolerance rtol (atol = rtol / 100) lies within atol + rtol * (this factor) * t of the rtol = 1e-13 time.  A
#: tolerance-proportional integrator's global error is ~ rtol times the number of steps' error growth; over the
#: O(1) times of a run 10 covers it (measured error 2e-4 ... 0.12 rtol t at rtol 1e-5 ... 1e-11 on the test's jam).
CAPSULE_JAM_CONVERGENCE = Tolerance(atol=0.0, rtol=10.0, why="JAM time at C converges with the integrator's tolerance (error <= 10 rtol t)")

#: F_z = -b / p_C near a JAM at C: with k = -(dp_C/ds) / eta_C at the jam (finite: the desingularised field is
#: smooth there), p_C^2 = 2 k (t_jam - t) and F_z sqrt(t_jam - t) -> -b / sqrt(2 k), with a relative correction
#: c sqrt(t_jam - t) from the next order.  On the steps within 5e-3 of t_jam the coefficient c varies by
#: O(sqrt(5e-3)) = 0.07 times an O(1) ratio of higher-order terms: rtol 0.5 of its value at the last step allows
#: that ratio up to 7, and a wrong limit (a constant relative offset) makes c grow as 1/sqrt(t_jam - t), 8x over
#: those steps.  Measured 0.09 (tests/test_capsule.py's jam).
CAPSULE_JAM_FORCE_LAW = Tolerance(atol=0.0, rtol=0.5, why="F_z sqrt(t_jam - t) -> -b/sqrt(2k) with an O(sqrt(t_jam - t)) correction")


# ------------------------------------------------------------------ ladder ---
# The ladder (crosscheck.engines.mujoco.studies.ladder): a named cause for each MuJoCo-theory disagreement.

#: The IC2 lift-off time of the paper's rod (Fig. 20, alpha = 3, mu = 1.4) is quoted as 0.01654: half a
#: unit of its last digit.  Rung 1 computes it to ~1e-9 (EVENT_TIME), so this is the quote's rounding.
LADDER_QUOTED_TIME = Tolerance(atol=5e-6, rtol=0.0, why="half a unit of the last digit of the quoted IC2 lift-off time 0.01654")

#: The ladder's goal: at least 90 % of the disagreements of the MuJoCo maps attributed to a named cause
#: (geometry, compliance, friction law, discretisation).  A target set for the study, not a bound derived
#: from the physics or the numerics: the report labels its check a regression guard.
LADDER_ATTRIBUTED = Tolerance(atol=0.1, rtol=0.0, why="goal, not a derived bound: at least 90% of the disagreements get a named cause", guard=True)

# ------------------------------------------- compliant rod: the eps -> 0 limit ---
#: The eps-free fast problem (crosscheck.engines.compliant.studies.limit.fast_limit,
#: DOP853 at rtol 1e-11) against independent computations of the same
#: numbers: the planar closed form of e (a 2x2 linear oscillator's release
#: time by brentq at 1e-14) and the rigid impulse's P_c and w
#: (crosscheck.iwc, DOP853 at rtol 1e-12).  The fast problem starts at
#: P0 = 1e-9 on the exact linear growth direction, an O(P0) = 1e-9 relative
#: error; measured differences <= 4e-12.
COMPLIANT_LIMIT_FAST = Tolerance(atol=1e-9, rtol=1e-9, why="fast problem vs closed form / iwc: start at P0 = 1e-9 on the linear direction")

#: t_stop/eps of the compliant rod minus its leading law (1/lambda) ln(1/eps)
#: + C, against the first corrections C1 eps T + C2 eps T^2
#: (compliant_limit.time_corrections: the drift of the slip speed and of
#: lambda along the formal slipping flow during the growth).  The remainder
#: is O(eps) without the factor T = t_stop/eps, i.e. O(1/T) relative to the
#: corrections; with T >= 2 in the tests and a remainder coefficient of the
#: same size as C1 (the same drifts, over the O(eps) start-up transient),
#: rtol 0.5.  Measured worst 0.22 (xi = 5, eps = 1e-2, T = 1.6); 0.04 at xi = 1.
COMPLIANT_LIMIT_SLIP_TIME = Tolerance(atol=0.0, rtol=0.5, why="O(eps) remainder ~ 1/T of the O(eps T) corrections, T >= 2")

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
COMPLIANT_LIMIT_POST_ORDER = Tolerance(atol=0.15, rtol=0.0, why="error ~ t_end = O(eps ln(1/eps)); O(eps) remainder shifts the slope by ~1/ln(1/eps)")

#: Observed order of the slip-stop lag t_stop - t_jam at a Corollary 4.2
#: jam, against 4/5: near the jam p ~ -k (P - P_jam), and delta'' = -b - p F_n
#: balances at t - t_jam ~ eps^(4/5), P - P_jam ~ eps^(2/5) (module docstring
#: of crosscheck.engines.compliant.studies.limit), with corrections of relative order
#: eps^(1/5) (the impulse P_stop - P_jam = O(1) beyond the inner region),
#: which shift a fitted slope over eps in [1e-5, 1e-3] by (1/5) c eps^(1/5)
#: <= 0.05 c, c = O(1): 0.1.  Measured 0.76-0.80.
COMPLIANT_LIMIT_JAM_LAG_ORDER = Tolerance(atol=0.1, rtol=0.0, why="t_stop - t_jam ~ eps^(4/5) (1 + O(eps^(1/5)))")


# -------------------------------------------------------------- mujoco_law ---
# MuJoCo's contact law in continuous time (crosscheck.engines.mujoco.law, the engine "mujoco_law").

#: The law's force against MuJoCo's efc_force at the same state, solver run to its iteration limit
#: (solver_tolerance 0): both are the exact minimiser of the same 3 x 3 cone problem, so they differ by
#: rounding amplified by the condition number of A + R (measured <= 7 on the test's states) and by the
#: slip angle's root polish (1e-15 rad): ~1e-14 to 1e-13 of |f|.  1e-11 leaves a factor 100.  Measured
#: 8e-14 (16 random states).
MUJOCO_LAW_FORCE = Tolerance(atol=0.0, rtol=1e-11, why="same convex problem solved exactly twice: rounding x cond(A + R) <= 7 (measured 8e-14)")

#: R and aref against efc_R and efc_aref: closed forms of the same ~20 flops (impedance sigmoid,
#: (1 - d)/d diagApprox, -B J v - K d dist) with J v through a 3 x 5 product: CLOSED_FORM's 1e-12,
#: relative to the size of the terms (aref's normal row is a difference of two terms ~1e3 m/s^2 that
#: nearly cancel).  Measured 0.5 of the allowance at worst.
MUJOCO_LAW_PIECES = Tolerance(atol=1e-12, rtol=1e-12, why="closed forms of the same ~20 flops (as CLOSED_FORM)")

#: The cone solver's optimality (KKT) residuals on random problems, relative to |g| + |H| |f|: f in K,
#: y = H f + g in the dual cone, f . y = 0.  A 3 x 3 solve and a Brent root to 1e-15 rad: 1e-12.
MUJOCO_LAW_KKT = Tolerance(atol=1e-12, rtol=0.0, why="3 x 3 solve + slip-angle root to 1e-15 rad: KKT residuals ~1e-14")

#: Order p of MuJoCo's approach to the continuous-time law as its timestep shrinks: the slope of
#: log(RMS over rows of |tip (x, y) error|) against log(timestep) over three timesteps (2e-4, 1e-4, 5e-5),
#: horizon 0.4.  Semi-implicit Euler is first order, but the slipping capsule rides on dist = 0 in a
#: sliding mode that MuJoCo realises as a chatter of contact and free steps, whose phase makes the error
#: irregular.  Measured slopes 0.79-1.54 over 8 states and 3 timestep triples (the test's state: 1.08).
MUJOCO_LAW_ORDER = Tolerance(atol=0.6, rtol=0.0, why="regression guard: first order, measured slopes 0.79-1.54 (chatter of the sliding mode)", guard=True)

#: The friction skew predicted by the law's run against MuJoCo's measured skew on the same state, first
#: 0.1 of the run, timestep 3e-4, over states whose law run has a contact and keeps theta in (0, pi/2):
#: the runs differ by MuJoCo's O(dt) discretisation of the sliding mode's chatter, and MuJoCo's value
#: converges to the law's as dt -> 0 (worst state: 5.79, 3.44, 3.63, 3.49 degrees at dt = 3e-4, 1e-4,
#: 3e-5, 1e-5 against the law's 3.50).  Measured at 3e-4: median 0.04, p99 1.8, max 2.3 degrees
#: (n = 234, seeds 1, 2); 3 degrees = 0.052 rad.
MUJOCO_LAW_SKEW = Tolerance(atol=0.052, rtol=0.0, why="regression guard: law run vs MuJoCo at dt = 3e-4, measured max 2.3 deg (n = 234)", guard=True)

#: The closed form angle(u, u + a_t / B) against the angle of the solved force: an identity of the cone's
#: optimality conditions (f_t anti-parallel to a_t + B u + R_t f_t), so rounding of the solve only.
MUJOCO_LAW_SKEW_IDENTITY = Tolerance(atol=1e-9, rtol=0.0, why="identity of the KKT conditions: rounding of the solve (~1e-13 rad)")
