"""The rigid engine's tolerances: Pinocchio's terms against the analytic ones, its one-step checks and its event profile.

Each allowance with where its number comes from (``crosscheck.tolerances.Tolerance``: atol + rtol |want|;
``guard=True`` marks a regression guard set from a measured spread).
"""

from __future__ import annotations

from crosscheck.tolerances import Tolerance

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
PIN_TIP_ACCELERATION = Tolerance(
    atol=1e-14, rtol=0.0, why="aba route: ~45 eps of A / cos theta (articulated inertia I0 cos^2 theta)"
)

#: G F + free acceleration, G and the free acceleration vs eq. linode2, scale kappa * term scale,
#: kappa = 1 / cos^2 theta.  Measured max 2.4e-15 (11 eps); 2e-14 covers the ~25 operations of
#: a 5 x 5 solve and the products with J.
PIN_THROUGH_MINV = Tolerance(
    atol=2e-14, rtol=0.0, why="through M^-1: ~90 eps of the term scale times cond(M) = 1/cos^2 theta"
)

#: M, C, g and C v + g = nonLinearEffects entry by entry in scaled units (M_s = L M L / (m l^2) etc.).
#: Measured max 1.0e-15 (C), 5.6e-16 (M, g), 3.3e-16 (nle).
PIN_MATRICES = Tolerance(
    atol=1e-14, rtol=0.0, why="M, C, g entries: ~45 eps of the entry scale (1 for M, g; 1 + |v_s| for C)"
)

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
PIN_FINITE_DIFFERENCE = Tolerance(
    atol=4.0, rtol=0.0, why="multiple of the central-difference bound eps f/h + h^2 f'''/6"
)


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
RIGID_LIFTOFF_ONSET = Tolerance(
    atol=1e-9, rtol=0.0, why="required: exact one-step lift-off decision (measured at the 1.9e-12 resolution)"
)

#: Order of convergence of the rigid engine's slipping trajectories to slip_until_event: semi-implicit
#: Euler is first order.  Measured 1.00001 over dt = 4e-3 ... 2.5e-4 (errors 4.7e-4 ... 2.9e-5 at t = 0.3).
RIGID_SLIP_ORDER = Tolerance(atol=0.05, rtol=0.0, why="semi-implicit Euler: first order (measured 1.00001)")

#: Order of convergence of the rigid engine's state one row after its jam to crosscheck.theory.impact.darboux_keller.impact
#: (the impact without collision), as dt -> 0, from planar impasses (p < 0, b < 0 on varphi = -pi/2,
#: Psi = 0 at t = 0).  The step solves the same impulse problem at the same configuration plus the
#: O(dt) gravity, Coriolis and dJ v terms: first order.  Measured 0.9992-1.0000 (mu = 1.4, 2; Theta
#: = 0.5, -0.3) over dt = 1e-3, 3e-4, 1e-4.
RIGID_IWC_ORDER = Tolerance(
    atol=0.05, rtol=0.0, why="one step = the IWC + O(dt) terms: first order (measured 0.9992-1.0000)"
)

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
RIGID_EVENT_DISAGREEMENT = Tolerance(
    atol=0.15, rtol=0.0, why="regression guard: measured 0.033 (n = 300, seed 0), on event boundaries", guard=True
)

#: Median |t_engine - t_analytic| over states with the same event: a first-order stepper shifts an
#: event by O(dt) = 1e-3 (measured 0.00155 at seed 0, n = 300: lift-offs and jams, O(dt)-O(sqrt(dt))).
RIGID_EVENT_TIME = Tolerance(
    atol=0.01, rtol=0.0, why="regression guard: O(dt)-O(sqrt dt) event shift (measured 0.0016)", guard=True
)

#: Rigid JAMs among random slipping states below mu_P: none (p > 0 for every slip direction).
RIGID_NO_JAM_BELOW_MU_P = Tolerance(atol=0.5, rtol=0.0, why="integer count must be 0: p > 0 for all varphi below mu_P")

#: Fraction of Corollary 4.2 states (mu = 1.4, 1.7, 6) whose rigid-engine slip does not end (JAM,
#: STICK or LIFTOFF) within RIGID_JAM_WINDOW = 0.05 of the analytic jam.  Measured 0.056 at seed 0
#: (n = 90) and 0.067 at seed 1; the JAMs alone are 0.83 and 0.74 of the states (mu = 6: 0.73 and
#: 0.57; the rest stick at the jam row, as in RIGID_EVENT_DISAGREEMENT).
RIGID_COROLLARY_STOP = Tolerance(
    atol=0.2, rtol=0.0, why="regression guard: measured 0.056-0.067 (n = 90, seeds 0, 1)", guard=True
)

#: The batched closed-form stepper (crosscheck.engines.pinocchio.batch) against Pinocchio's PGS stepper, one step from
#: the same state: impulse relative to max(m g dt, |lambda|) and velocity relative to its size.  PGS stops at
#: complementarity and feasibility 1e-13 m g dt (Options.tolerance), the closed form is exact to rounding, and the two
#: terms (closed form, Pinocchio's) differ by ~eps / cos^2 theta (PIN_THROUGH_MINV): so the two steps differ by the solver's
#: stopping rule, ~1e-13 relative to a slipping step's impulse, at most the 1e-11 measured for RIGID_STEP_FORCE.  Only
#: steps where PGS met its tolerance are compared.  Measured max over the slip, lift-off, stick and two jam starts of
#: tests/test_engine_pinocchio_batch.py: 1.7e-12 (impulse), 6.2e-15 (velocity).
RIGID_BATCH_STEP = Tolerance(
    atol=0.0, rtol=1e-9, why="PGS's stopping rule 1e-13 m g dt against an exact solution (measured <= 1.7e-12)"
)
