"""The rigid engine's run parameters in the paper's scaled units (importing this does not import Pinocchio)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crosscheck.checks import POSITIVE, check_timestep, real_scalar
from crosscheck.engines.options import EngineOptions

__all__ = ["Options", "SOLVERS"]

#: Constraint solvers that ``Options.solver`` names: "auto" (the closed form for every sweep, PGS for one ``simulate``),
#: the closed-form NCP over a batch of states (Pinocchio's PGS where a step's NCP has several
#: solutions; ``crosscheck.engines.pinocchio.batch``), and Pinocchio's own solvers for every step.
SOLVERS = ("auto", "closed_form", "pgs", "admm")


@dataclass(frozen=True)
class Options(EngineOptions):
    """Parameters of the rigid engine, in the paper's scaled units.

    Attributes:
      timestep: omega dt (default 1e-3).
      solver: "closed_form" (the NCP in closed form, a batch of states
        stepped together in numpy, PGS only at steps whose NCP has several
        solutions: ``crosscheck.engines.pinocchio.batch``), "pgs"
        (Pinocchio's projected Gauss-Seidel at every step), "admm", or "auto"
        (default): "closed_form" for every ``sweep`` and "pgs" for
        ``simulate``.  Every sweep, whatever its size: a state's outcome in a
        sweep must not depend on the other states swept with it (where the
        step's NCP has several solutions, the choice is PGS's and depends on
        its warm start, so the two solvers can choose differently: theta 1.2,
        varphi -1.9, Theta 0, Psi 1.7, eta 1, mu 1.4 at timestep 1e-3 lifts
        off at t = 0.021 by PGS alone and jams at 0.017 in closed form, as
        both do at 3e-4).  A batched step costs ~0.3 ms of numpy calls
        almost whatever the batch (3.5e3 steps/s for one state, 2.7e5 for
        128), a PGS step ~30 us per state: small sweeps cost more, a
        handful of states at most.
      tolerance: absolute complementarity and feasibility tolerance of the NCP
        as a force (m g): the solver stops when they are below tolerance x dt
        in impulses (default 1e-13, ~1e-13 of a step's impulse while slipping,
        whose force is O(1) m g).
      max_iterations: the solver's first iteration cap (default 1000).
      max_iterations_limit: the cap is raised tenfold, up to this, on a step
        that misses the tolerance (default 1e4: past the paradox the NCP may
        have several solutions and PGS cycles; more iterations did not help).
      contact_gap: the contact enters the NCP when the tip's height is at
        most this (units of l); None means 10 timestep^2 (module docstring).
      ncp: True solves the NCP on the exact cone; False the convex relaxation
        (kept only to show what it does wrong; ADMM only: Pinocchio 4.1's PGS
        solves the NCP whatever ``solve_ncp`` says).
    """

    timestep: float = 1e-3
    solver: str = "auto"
    tolerance: float = 1e-13
    max_iterations: int = 1000
    max_iterations_limit: int = 10_000
    contact_gap: float | None = None
    ncp: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "timestep", check_timestep(self.timestep))
        object.__setattr__(self, "tolerance", real_scalar("tolerance", self.tolerance, POSITIVE))
        if self.solver not in SOLVERS:
            raise ValueError(f"solver must be one of {', '.join(SOLVERS)}; got {self.solver!r}")
        for name in ("max_iterations", "max_iterations_limit"):
            v = getattr(self, name)
            if not (isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 1):
                raise ValueError(f"{name} must be an integer >= 1; got {v!r}")
        if self.max_iterations_limit < self.max_iterations:
            raise ValueError(
                f"max_iterations_limit must be >= max_iterations = {self.max_iterations}; got {self.max_iterations_limit}"
            )
        if self.contact_gap is not None:
            object.__setattr__(self, "contact_gap", real_scalar("contact_gap", self.contact_gap, POSITIVE))
        if not isinstance(self.ncp, (bool, np.bool_)):
            raise ValueError(f"ncp must be True or False; got {self.ncp!r}")
        if not self.ncp and self.solver != "admm":
            # Pinocchio 4.1's PGS solves the NCP whatever solve_ncp says (measured); ADMM follows it.
            raise ValueError(f"ncp=False (the convex relaxation) needs solver='admm'; got solver={self.solver!r}")

    LABEL = "Pinocchio"

    @property
    def gap(self) -> float:
        """The activation height of the contact [l]."""
        return self.contact_gap if self.contact_gap is not None else 10.0 * self.timestep**2

    @property
    def contact_time(self) -> float:
        """A rigid contact has no force build-up time."""
        return 0.0

    @property
    def friction_time(self) -> float:
        """A rigid contact does not creep."""
        return 0.0
