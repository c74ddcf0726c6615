"""MuJoCo's tolerances: its free and contact accelerations, its event profile, and its contact law's checks.

Each allowance with where its number comes from (``crosscheck.tolerances.Tolerance``: atol + rtol |want|;
``guard=True`` marks a regression guard set from a measured spread).
"""

from __future__ import annotations

from crosscheck.tolerances import Tolerance

# ------------------------------------------------------------------ mujoco ---
#: MuJoCo's free tip acceleration (contacts off) vs eq. linode2 with F = 0 and
#: eq. b, in units of g.  The only modelling difference is the axial inertia
#: eps = 1e-12 I0 (``crosscheck.engines.mujoco.model.AXIAL_INERTIA``; MuJoCo needs > 0), which
#: changes the psi inertia by a relative 1e-12 tan^2 theta (<= 1e-9 for theta
#: <= 1.54); measured max 9e-10 over 300 random states (1e-9 at eps = 1e-9 I0
#: was 9e-7: the error is proportional to eps).
MUJOCO_FREE_ACCELERATION = Tolerance(
    atol=1e-8, rtol=1e-8, why="axial inertia 1e-12 I0 in the psi inertia, x tan^2 theta"
)

#: MuJoCo's tip acceleration with contact vs eq. linode2 with MuJoCo's own
#: contact force moved to the capsule's contact point
#: (``crosscheck.engines.mujoco.studies.contact.capsule_tip_acceleration``), as a fraction of the term scale
#: g (1 + alpha |F|_1 / (m g)).  Exact up to the solver's stopping rule: with
#: solver_tolerance 1e-10 (the default) force and acceleration agree to ~6e-7;
#: run to its iteration limit (solver_tolerance 0) the measured max is 1.4e-11
#: over 200 random states x 5 radii.  Without the correction the error is
#: 0.41 r/l (max; 0.27 r/l median): linear convergence as r -> 0.
MUJOCO_CONTACT_ACCELERATION = Tolerance(
    atol=1e-9, rtol=0.0, why="converged contact solve (solver_tolerance 0): rounding of forces up to ~50 m g"
)

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
MUJOCO_LIFTOFF_ONSET_COARSE = Tolerance(
    atol=6.1e-5, rtol=0.0, why="(Psi_L^3/6)(3 dt)^2 at dt = 3.13e-3 (1 ms for a 1 m rod)"
)

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
MUJOCO_EVENT_DISAGREEMENT = Tolerance(
    atol=0.2,
    rtol=0.0,
    why="regression guard: measured 0.12 +- 0.026 (n = 300): soft contact + friction skew",
    guard=True,
)

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

#: Fraction of Corollary 4.2 states (crosscheck.theory.corollary.corollary_states: analytic JAM at t in
#: [0.2, 1.5], b <= -0.1 and |varphi + pi/2| >= 0.1 at the jam) whose MuJoCo slip does NOT end (no
#: JAM, STICK or LIFTOFF of crosscheck.engines.classifier) within 0.15 = 2.5 tau of the analytic jam, pooled over
#: mu = 1.4, 1.7, 6.  Measured 0.37 +- 0.06 over 8 seeds of 45 states (max 0.51); validate pools 90
#: states (binomial sd 0.05), so 0.55 is ~3.5 sd above the mean.  MuJoCo delivers the impulse itself
#: (JAM) in 7-40 % of them; otherwise its soft contact ends the slip by sticking or lifting off.
MUJOCO_COROLLARY_STOP = Tolerance(
    atol=0.55,
    rtol=0.0,
    why="regression guard: measured 0.37 +- 0.06 (sd 0.05 at n = 90): soft contact ends the slip by stick/lift-off",
    guard=True,
)


# -------------------------------------------------------------- mujoco_law ---
# MuJoCo's contact law in continuous time (crosscheck.engines.mujoco.law, the engine "mujoco_law").

#: The law's force against MuJoCo's efc_force at the same state, solver run to its iteration limit
#: (solver_tolerance 0): both are the exact minimiser of the same 3 x 3 cone problem, so they differ by
#: rounding amplified by the condition number of A + R (measured <= 7 on the test's states) and by the
#: slip angle's root polish (1e-15 rad): ~1e-14 to 1e-13 of |f|.  1e-11 leaves a factor 100.  Measured
#: 8e-14 (16 random states).
MUJOCO_LAW_FORCE = Tolerance(
    atol=0.0, rtol=1e-11, why="same convex problem solved exactly twice: rounding x cond(A + R) <= 7 (measured 8e-14)"
)

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
MUJOCO_LAW_ORDER = Tolerance(
    atol=0.6,
    rtol=0.0,
    why="regression guard: first order, measured slopes 0.79-1.54 (chatter of the sliding mode)",
    guard=True,
)

#: The friction skew predicted by the law's run against MuJoCo's measured skew on the same state, first
#: 0.1 of the run, timestep 3e-4, over states whose law run has a contact and keeps theta in (0, pi/2):
#: the runs differ by MuJoCo's O(dt) discretisation of the sliding mode's chatter, and MuJoCo's value
#: converges to the law's as dt -> 0 (worst state: 5.79, 3.44, 3.63, 3.49 degrees at dt = 3e-4, 1e-4,
#: 3e-5, 1e-5 against the law's 3.50).  Measured at 3e-4: median 0.04, p99 1.8, max 2.3 degrees
#: (n = 234, seeds 1, 2); 3 degrees = 0.052 rad.
MUJOCO_LAW_SKEW = Tolerance(
    atol=0.052,
    rtol=0.0,
    why="regression guard: law run vs MuJoCo at dt = 3e-4, measured max 2.3 deg (n = 234)",
    guard=True,
)

#: The closed form angle(u, u + a_t / B) against the angle of the solved force: an identity of the cone's
#: optimality conditions (f_t anti-parallel to a_t + B u + R_t f_t), so rounding of the solve only.
MUJOCO_LAW_SKEW_IDENTITY = Tolerance(
    atol=1e-9, rtol=0.0, why="identity of the KKT conditions: rounding of the solve (~1e-13 rad)"
)
