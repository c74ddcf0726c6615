"""The rigid engine's steps over a batch of states in numpy: closed-form terms and NCP, Pinocchio's PGS where the NCP has several solutions.

One step is the stepper's (``crosscheck.engines.pinocchio.stepper``, the
same v_free, u with dt dJ v and gap / dt, the same contact band, the same
semi-implicit Euler), with Pinocchio's terms replaced by their closed forms
(``closed_form``) and the NCP solved by ``ncp.solve``.  Where a row's NCP has
one solution that is the solution PGS converges to (to its tolerance,
1e-13 m g dt); where it has several, which one the engine takes is PGS's
choice from its cold start, not the problem's, so that row's step is made
by Pinocchio's own stepper (``Stepper.step``, with its retries and sticking
guess): the batch then follows the PGS engine through every jam.  Where PGS
misses its tolerance on a problem with one solution (it cycles at large mu),
the batch has the exact solution instead: those steps are the only ones
where the two engines differ by more than the solver's tolerance
(``solver="pgs"`` keeps Pinocchio's stepper for every step).

Solver health per row, as the stepper's: a closed-form step counts 0
iterations, complementarity 0 and converged; a step handed to PGS counts
PGS's.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from crosscheck.engines.pinocchio import ncp
from crosscheck.engines.pinocchio.closed_form import angles, free_velocity, jacobian_times, tip_terms, velocity_change
from crosscheck.engines.pinocchio.options import Options
from crosscheck.engines.pinocchio.step import Stepper
from crosscheck.rod import Rod

__all__ = ["BatchStepper", "run_batch"]


class BatchStepper:
    """B states of one rod, each with its own mu, stepped together (physical units)."""

    def __init__(self, rod: Rod, mu: np.ndarray, options: Options):
        self.rod, self.options = rod, options
        self.mu = np.asarray(mu, float)
        self.dt = options.timestep / rod.omega
        self.band = options.gap * rod.length
        self._pgs: dict[float, object] = {}
        self.handed = 0  # steps made by Pinocchio's PGS stepper
        self._health = np.tile(
            [0.0, 0.0, 1.0], (len(self.mu), 1)
        )  # a closed-form step: 0 iterations, complementarity 0, converged

    def _stepper(self, mu: float):
        if mu not in self._pgs:
            self._pgs[mu] = Stepper(self.rod, mu, dataclasses.replace(self.options, solver="pgs"))
        return self._pgs[mu]

    def step(self, q: np.ndarray, v: np.ndarray, row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One step of every state from (q, v), each (B, 5) [physical]; returns (q_next, v_next).

        ``row`` (B, 20) receives what the record needs at the step's start (physical, world axes): tip position,
        velocity, classical acceleration (with qdd = (v_next - v) / dt), impulse, psi, theta, their rates, then
        active, iterations, complementarity, converged.
        """
        dt, rod = self.dt, self.rod
        A = angles(q)
        T = tip_terms(rod, q, v, A)
        vf = free_velocity(rod, q, v, dt, A)
        B = len(q)
        vel, Jvf = jacobian_times(rod, A, np.stack((v, vf)))  # the tip's velocity at v and at v_free, one call
        gap = T.pos[:, 2]
        active = gap <= self.band
        u = Jvf + dt * T.dJv
        u[:, 2] += gap / dt
        lam = np.zeros_like(u)
        solved = np.ones(B, bool)
        press = active & (u[:, 2] < 0.0)
        if press.all():
            lam, solved, _ = ncp.solve(T.G, u, self.mu)
        elif press.any():
            lam[press], solved[press], _ = ncp.solve(T.G[press], u[press], self.mu[press])
        if not solved.all():
            lam[~solved] = 0.0
        v1 = vf + velocity_change(rod, q, lam, A)
        q1 = q + dt * v1
        # the classical acceleration dJ v + J (v1 - v) / dt with J v1 = J v_free + G lambda (no third J product);
        # one write of the whole row (a dozen slice writes cost more than the copy at these sizes)
        acc = T.dJv + (Jvf - vel + np.einsum("bij,bj->bi", T.G, lam)) / dt
        row[:] = np.concatenate((T.pos, vel, acc, lam, q[:, 3:5], v[:, 3:5], active[:, None], self._health), axis=1)
        for i in np.flatnonzero(~solved):
            # several solutions: the step PGS makes (Pinocchio's terms, its retries and sticking guess)
            self.handed += 1
            q1[i], v1[i], info = self._stepper(float(self.mu[i])).step(q[i], v[i])
            row[i, 0:3], row[i, 3:6], row[i, 6:9], row[i, 9:12] = info.tip_pos, info.tip_vel, info.tip_acc, info.impulse
            row[i, 16:20] = info.active, info.iterations, info.complementarity, info.converged
        return q1, v1


def run_batch(
    rod: Rod, q0: np.ndarray, v0: np.ndarray, mu: np.ndarray, options: Options, n: int
) -> tuple[np.ndarray, int]:
    """``n`` steps of B states from (q0, v0) (B, 5) [physical], friction ``mu`` (B,).

    Returns (rows (B, n, 20), the number of steps handed to PGS); row k is the state at t_k and its step's
    impulse, as ``BatchStepper.step`` fills it.
    """
    stepper = BatchStepper(rod, mu, options)
    q, v = np.array(q0, float), np.array(v0, float)
    rows = np.empty((q.shape[0], n, 20))
    with np.errstate(
        all="ignore"
    ):  # a run that leaves 0 < theta < pi/2 diverges as with Pinocchio; the classifier says DIVERGED
        for k in range(n):
            q, v = stepper.step(q, v, rows[:, k])
    return rows, stepper.handed
