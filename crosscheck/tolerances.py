"""Every tolerance of the project, in one place, with where its number comes from.

A value ``got`` passes against ``want`` when
``|got - want| <= atol + rtol * |want|`` (numpy's ``isclose`` rule; scipy's
``_ivp`` error measure).  ``Tolerance.ratio`` gives the error in multiples of
the allowance, so reports can say "0.3 of tolerance" rather than "passed".

Sections: analytic reference, GB manifold and slipping flow, the capsule
point, and the keys of an engine's event profile.  Each engine keeps its own
tolerances (its checks, its event profile, its solver's settings) in its
subpackage's ``tolerances`` module; ``all_tolerances`` collects them all from the modules it is given
(``crosscheck.report.provenance.all_tolerances`` gives every registered engine's).
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
DERIVATION = Tolerance(
    atol=0.0, rtol=1e-12, why="required: independent derivation to 1e-12 relative (measured 1.2e-15)"
)

#: Central finite differences with step h of a smooth function: truncation
#: O(h^2 f''') + rounding O(eps f / h); h = 1e-6 gives ~1e-8 relative.
FINITE_DIFFERENCE = Tolerance(atol=1e-7, rtol=1e-6, why="central differences, h = 1e-6: truncation + eps/h rounding")


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
STICK_SPEED = Tolerance(
    atol=1e-9, rtol=0.0, why="scaled slip speed counted as stuck (eta = 0 is an equilibrium of eq. f)"
)

#: Runs stop (outcome SLIP) when theta comes this close to 0 or pi/2: the
#: coefficients d1 = -alpha mu cos(varphi)/cos(theta) and c1 = 2 Psi Theta tan(theta)
#: of Appendix A blow up at theta = pi/2, and SlipState needs theta in (0, pi/2).
THETA_MARGIN = Tolerance(
    atol=1e-6, rtol=0.0, why="distance from theta = 0, pi/2 where a run stops (domain of SlipState)"
)

#: Identities that hold only on b = p = 0 (K = B A, eq. K; J = A B, eq.
#: jacobian; eig J = eig K + 4 zeros), evaluated at GB points from closed forms
#: (varphi_pm, a square root): b and p are ~1e-15 there and multiply
#: coefficients up to ~1e4 near theta -> pi/2 (d1 ~ 1/cos theta).  Measured
#: worst: 5e-14 (K), 2e-11 (J) relative over mu in [1.34, 6], |Psi| <= 10.
GB_IDENTITY = Tolerance(
    atol=1e-9, rtol=1e-9, why="identities on b = p = 0 at closed-form GB points (residual 1e-15 x coefficients <= 1e4)"
)

#: Event times of the desingularised flow against a real-time solve_ivp of
#: eq. polareqs_varphi where that is regular (p bounded away from 0): both runs
#: at rtol 1e-10, so their difference is a few 1e-9 over O(1) times.
EVENT_TIME = Tolerance(
    atol=1e-7, rtol=1e-7, why="event time: eq. f (s-time) vs real-time eq. polareqs_varphi, both rtol 1e-10"
)

# ----------------------------------------------------------------- capsule ---
# The rigid rod with its contact at the capsule point C = A - r K (crosscheck.theory.capsule), scaled units.

#: p_C and b of crosscheck.theory.capsule against Pinocchio with the tip Jacobian moved to C (J_C = J + r [K]x J_omega):
#: the allowance is atol * (1 + alpha)(1 + mu)(1 + r)(1 + |v_s|_1 / eta_C).  (1 + alpha)(1 + mu)(1 + r) bounds
#: the terms of p_C (1, alpha cos^2 theta, alpha mu cos theta (sin theta + r)); as for PIN_SLIP, ~45 eps of it.
#: Pinocchio's friction direction comes from J_C v, whose rounding eps |v_s|_1 turns the slip angle by
#: eps |v_s|_1 / eta_C, hence the last factor.  Measured 7e-16 of the scale (800 states, r = 0 ... 0.3).
CAPSULE_PIN_SLIP = Tolerance(
    atol=1e-14, rtol=0.0, why="p_C, b at C vs Pinocchio: ~45 eps of the term scale x (1 + |v_s|/eta_C)"
)

#: C's slip velocity (eta_C, and varphi_C x eta_C) of crosscheck.theory.capsule.contact_slip against Pinocchio's J_C v:
#: rounding of sums of the five scaled velocities, atol * (1 + |v_s|_1).  Measured 3e-15 absolute.
CAPSULE_PIN_VELOCITY = Tolerance(
    atol=1e-14, rtol=0.0, why="C's slip velocity vs Pinocchio J_C v: ~45 eps of 1 + |v_s|_1"
)

#: The real-time slipping field at C (eta_C', varphi_C', Psi', Theta' = f / (eta_C p_C)) against Pinocchio's aba
#: with tau = J_C^T F, F = F_z (-mu u_C/|u_C|, 1), F_z from Pinocchio's own Delassus row at C: quantities through
#: M^-1, so PIN_THROUGH_MINV's 2e-14 of the term scale (1 + alpha)(1 + f)(1 + |v_s|_1)^2 / cos^2 theta,
#: times (1 + 1 / eta_C) for varphi_C' (an angular rate of the slip).  f = |F_z| (1 + (1 + alpha)(1 + mu) / |p_C|):
#: F_z = -b / p_C carries the rounding of p_C's terms relative to |p_C| (measured without that factor: 1.2e-14
#: at p_C = 0.0014).  Measured 2e-17 of that scale (2000 states, r = 0 ... 0.3).
CAPSULE_PIN_DYNAMICS = Tolerance(
    atol=2e-14, rtol=0.0, why="slip dynamics at C vs Pinocchio aba: through M^-1, as PIN_THROUGH_MINV"
)

#: crosscheck.theory.capsule.slip_until_event at r = 0 against crosscheck.theory.slipping.slip_until_event: the same vector
#: field (eq. f) written with other roundings (~1e-16 relative), both at SLIP_INTEGRATION, so event times agree
#: to the integrators' error, ~1e-9 over O(1) times (SLIP_INTEGRATION's level).  Measured 2e-14 (200 states).
CAPSULE_REDUCTION_TIME = Tolerance(
    atol=1e-9, rtol=1e-9, why="r = 0 vs crosscheck.theory.slipping: same field, SLIP_INTEGRATION error"
)

#: A JAM approached at C (F_z ~ (t_jam - t)^(-1/2)) in the desingularised time: the event time at integrator
#: tolerance rtol (atol = rtol / 100) lies within atol + rtol * (this factor) * t of the rtol = 1e-13 time.  A
#: tolerance-proportional integrator's global error is ~ rtol times the number of steps' error growth; over the
#: O(1) times of a run 10 covers it (measured error 2e-4 ... 0.12 rtol t at rtol 1e-5 ... 1e-11 on the test's jam).
CAPSULE_JAM_CONVERGENCE = Tolerance(
    atol=0.0, rtol=10.0, why="JAM time at C converges with the integrator's tolerance (error <= 10 rtol t)"
)

#: F_z = -b / p_C near a JAM at C: with k = -(dp_C/ds) / eta_C at the jam (finite: the desingularised field is
#: smooth there), p_C^2 = 2 k (t_jam - t) and F_z sqrt(t_jam - t) -> -b / sqrt(2 k), with a relative correction
#: c sqrt(t_jam - t) from the next order.  On the steps within 5e-3 of t_jam the coefficient c varies by
#: O(sqrt(5e-3)) = 0.07 times an O(1) ratio of higher-order terms: rtol 0.5 of its value at the last step allows
#: that ratio up to 7, and a wrong limit (a constant relative offset) makes c grow as 1/sqrt(t_jam - t), 8x over
#: those steps.  Measured 0.09 (tests/test_capsule.py's jam).
CAPSULE_JAM_FORCE_LAW = Tolerance(
    atol=0.0, rtol=0.5, why="F_z sqrt(t_jam - t) -> -b/sqrt(2k) with an O(sqrt(t_jam - t)) correction"
)


#: The ladder (``crosscheck.studies.ladder``): the IC2 lift-off time of the paper's rod (Fig. 20, alpha = 3, mu = 1.4)
#: is quoted as 0.01654: half a unit of its last digit.  Rung 1 computes it to ~1e-9 (EVENT_TIME), so this is the
#: quote's rounding.
LADDER_QUOTED_TIME = Tolerance(
    atol=5e-6, rtol=0.0, why="half a unit of the last digit of the quoted IC2 lift-off time 0.01654"
)

#: The ladder's goal: at least 90 % of an engine's laddered disagreements attributed to a named cause (a rung's).  A
#: target set for the study, not a bound derived from the physics or the numerics: the report labels its check a
#: regression guard, and the findings call an engine's disagreements "explained" from it.
LADDER_ATTRIBUTED = Tolerance(
    atol=0.1, rtol=0.0, why="goal, not a derived bound: at least 90% of the disagreements get a named cause", guard=True
)


def named(module=None) -> dict[str, dict]:
    """Every ``Tolerance`` defined at the top of ``module`` (this one by default), by name, as ``as_dict``."""
    scope = globals() if module is None else vars(module)
    return {k: v.as_dict() for k, v in scope.items() if isinstance(v, Tolerance)}


def all_tolerances(modules=()) -> dict[str, dict]:
    """Every named tolerance, for reports' provenance blocks: this module's comparison allowances and those of each
    of ``modules`` (an engine's ``tolerances`` module)."""
    out = named()
    for module in modules:
        out.update(named(module))
    return out
