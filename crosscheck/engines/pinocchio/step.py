"""One step of the rigid engine: Moreau / Stewart-Trinkle on Pinocchio's constraint solvers with the exact Coulomb cone.

The rod is the 5-joint model of ``crosscheck.engines.pinocchio.model`` (the
same one whose M, C, g, Jacobians and Delassus operator are checked against
the paper); the contact is Pinocchio's ``PointContactConstraintModel``
between the plane (the universe, world axes: two tangential rows, then the
normal) and the tip A, with ``setFriction(mu)``.  One step of length dt from
(q_k, v_k):

    v_free = v_k + dt M^-1 (-C v_k - g)                    (aba with tau = 0)
    u      = J v_free + dt dJ v_k + (gap_k / dt) n         (the contact velocity at the end of the step)
    lambda = the impulse of the nonlinear complementarity problem (NCP) on
             the exact Coulomb cone: u + G lambda = u+, lambda in K_mu,
             u+ + mu |u+_t| n in K_mu*, lambda . (u+ + mu |u+_t| n) = 0
    v_k+1  = v_free + M^-1 J^T lambda,   q_k+1 = q_k + dt v_k+1   (semi-implicit Euler)

with G = J M^-1 J^T the Delassus operator (Pinocchio's
``ConstraintCholeskyDecomposition``) and the NCP solved by Pinocchio's
``PGSConstraintSolver`` (default) or ``ADMMConstraintSolver`` with
``solve_ncp = True``.  Why each term:

* ``dt dJ v_k``: the contact velocity at the end of the step is
  J(q_k+1) v_k+1 ~ J v_k+1 + dt dJ v.  Without it the step enforces J a = 0
  instead of the tip acceleration a_A = J a + dJ v = 0, and misses the
  centripetal term of eq. b: the normal impulse / dt would not be -b/p and
  the lift-off decision would not be b > 0 (MuJoCo's active contact misses
  this term, as ``crosscheck.engines.mujoco.studies.contact`` measures).  With it the
  impulse of a slipping step is exactly eq. FZ with the friction direction
  of the end-of-step slip, and lift-off happens iff b > 0.
* ``gap_k / dt``: the next gap gap_k + dt u+_n stays non-negative (to first
  order); a tip above the plane may still fall freely onto it.
* ``solve_ncp = True``: the convex relaxation (``solve_ncp = False``, the
  cone complementarity problem of Anitescu and of Drake's SAP) replaces the
  normal velocity by u_n + mu |u_t| in the complementarity and launches a
  slipping tip off the plane at w = mu |u_t| in one step: wrong for this
  problem (tests/test_engine_pinocchio.py checks that it happens and that we
  do not do it).

Contact activation.  The contact enters the NCP when the tip's height is at
most ``Options.contact_gap`` (default 10 dt^2 in units of l).  Each position
step raises a slipping tip by about sin theta (dt Theta)^2 / 2 (the arc of
the rod's rotation), so a threshold near machine zero would drop the contact
every step and make the tip hop; 10 dt^2 covers |Theta| up to ~4.5.  A tip
inside the band but lifting off is not held: the gap term lets the NCP
return lambda = 0 when the free motion keeps the gap positive.

Solver health is data: each step records the solver's iterations and
complementarity; a step that misses ``Options.tolerance`` is solved again
with ten times the iterations, up to ``Options.max_iterations_limit``, then
once more warm-started from the sticking impulse -G^-1 u if that lies in
the cone, and the steps that still miss it are counted in ``Run.solver``.
Why the sticking guess, and why only last: ``docs/pinocchio_step.md``.

Everything this module takes and returns is in the paper's scaled units
(section 2.1); the Pinocchio model and the step itself are physical (``Rod``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from crosscheck.engines.pinocchio.model import TIP_FRAME, build_model
from crosscheck.engines.pinocchio.options import Options
from crosscheck.rod import Rod

__all__ = ["Stepper", "StepInfo"]

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@dataclass
class StepInfo:
    """What one step did: the impulse (world axes, physical), whether the contact was in the NCP, solver health,
    and the tip's position, velocity and classical acceleration at the step's start (world axes, physical; the
    acceleration with qdd = (v_next - v) / dt), which a record row needs."""

    impulse: np.ndarray
    active: bool
    iterations: int
    complementarity: float
    converged: bool
    tip_pos: np.ndarray
    tip_vel: np.ndarray
    tip_acc: np.ndarray


class Stepper:
    """The rod, its contact and a constraint solver, built once and stepped many times (physical units inside)."""

    def __init__(self, rod: Rod, mu: float, options: Options):
        self.rod, self.mu, self.options = rod, float(mu), options
        self.model = build_model(rod)
        self.data = self.model.createData()
        frame = self.model.frames[self.model.getFrameId(TIP_FRAME)]
        self.tip = self.model.getFrameId(TIP_FRAME)
        contact = pin.PointContactConstraintModel(self.model, 0, pin.SE3.Identity(), frame.parentJoint, frame.placement)
        contact.setFriction(self.mu)
        self.constraint = pin.ConstraintModel(contact)
        self.models = pin.StdVec_ConstraintModel()
        self.models.append(self.constraint)
        self.datas = pin.StdVec_ConstraintData()
        self.datas.append(self.constraint.createData())
        self.cholesky = pin.ConstraintCholeskyDecomposition(self.model, self.data, self.models, self.datas)
        if options.solver == "admm":
            self.solver, self.settings, self.result = (
                pin.ADMMConstraintSolver(3),
                pin.ADMMSolverSettings(),
                pin.ADMMSolverResult(),
            )
        else:  # "pgs", and the steps "auto" and "closed_form" hand to PGS
            self.solver, self.settings, self.result = (
                pin.PGSConstraintSolver(3),
                pin.PGSSolverSettings(),
                pin.PGSSolverResult(),
            )
        s = self.settings
        s.solve_ncp = bool(options.ncp)
        self.dt = options.timestep / rod.omega
        s.absolute_complementarity_tol = s.absolute_feasibility_tol = options.tolerance * rod.force_scale * self.dt
        s.relative_complementarity_tol = s.relative_feasibility_tol = 0.0
        self.zeros = np.zeros(self.model.nv)

    def step(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, StepInfo]:
        """One step from (q, v) [physical]; returns (q_next, v_next, StepInfo)."""
        model, data, dt = self.model, self.data, self.dt
        a_free = pin.aba(model, data, q, v, self.zeros)
        v_free = v + dt * a_free
        # tip kinematics at (q, v): height, Jacobian, dJ v (classical acceleration with qdd = 0)
        pin.forwardKinematics(model, data, q, v, self.zeros)
        pin.updateFramePlacement(model, data, self.tip)
        pos = data.oMf[self.tip].translation.copy()
        gap = pos[2]
        active = gap <= self.options.gap * self.rod.length
        if not active:
            pin.forwardKinematics(model, data, q, v, a_free)
            vel = pin.getFrameVelocity(model, data, self.tip, _LWA).linear
            acc = pin.getFrameClassicalAcceleration(model, data, self.tip, _LWA).linear
            return q + dt * v_free, v_free, StepInfo(np.zeros(3), False, 0, 0.0, True, pos, vel, acc)
        dJv = pin.getFrameClassicalAcceleration(model, data, self.tip, _LWA).linear
        pin.computeJointJacobians(model, data, q)
        pin.crba(model, data, q)
        self.constraint.calc(model, data, self.datas[0])
        J = pin.getConstraintsJacobian(model, data, self.models, self.datas)
        self.cholesky.compute(model, data, self.models, self.datas, 0.0)
        G = self.cholesky.getDelassusOperatorCholeskyExpression()
        u = J @ v_free + dt * dJv
        u[2] += gap / dt
        cap, iterations, stick_tried = self.options.max_iterations, 0, False
        while True:
            self.settings.max_iterations = cap
            self.solver.solve(G, u, self.models, self.datas, self.settings, self.result)
            iterations += self.result.iterations
            if self.result.converged:
                break
            if cap < self.options.max_iterations_limit:
                cap = min(10 * cap, self.options.max_iterations_limit)
                continue
            if stick_tried:
                break
            stick_tried = True
            lam = -np.linalg.solve(G.matrix(), u)  # the sticking impulse (module docstring)
            if not (lam[2] > 0.0 and math.hypot(lam[0], lam[1]) <= self.mu * lam[2]):
                break
            self.result.setConstraintImpulseGuess(lam)
        lam = np.array(self.result.retrieveConstraintImpulses())
        pin.cholesky.decompose(
            model, data
        )  # M = U D U^T of the crba above: M^-1 J^T lambda in O(nv) (a numpy solve costs 25x more)
        v_next = v_free + pin.cholesky.solve(model, data, J.T @ lam)
        # the row's tip kinematics from this step's J (the contact frame is the world's) and dJ v: no more Pinocchio calls
        info = StepInfo(
            lam,
            True,
            iterations,
            float(self.result.complementarity),
            bool(self.result.converged),
            pos,
            J @ v,
            dJv + J @ ((v_next - v) / dt),
        )
        return q + dt * v_next, v_next, info
