"""Newton's run parameters in the paper's scaled units, one ``Options`` for every Newton solver (imports no warp
unless a run asks for device "cuda")."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from crosscheck.checks import NONNEGATIVE, POSITIVE, UNIT, Interval
from crosscheck.engines.options import EngineOptions
from crosscheck.state import check_timestep, real, real_scalar
from crosscheck.stderr_fd import silenced

#: How tables and messages name the engine of each solver.
LABELS = {
    "mujoco": "Newton MuJoCo Warp",
    "xpbd": "Newton XPBD",
    "featherstone": "Newton Featherstone",
    "semi_implicit": "Newton semi-implicit",
}

__all__ = [
    "Options",
    "MuJoCoWarpOptions",
    "XPBDOptions",
    "FeatherstoneOptions",
    "SemiImplicitOptions",
    "SOLVERS",
    "DEVICES",
    "RADIUS",
    "CREEP_MARGIN",
    "MAX_ITERATIONS",
]

#: The Newton solvers crosscheck runs, by ``Options.solver``: Newton's class of each.
SOLVERS = {
    "mujoco": "SolverMuJoCo",
    "xpbd": "SolverXPBD",
    "featherstone": "SolverFeatherstone",
    "semi_implicit": "SolverSemiImplicit",
}

#: Where Warp runs the kernels (``Options.device``): "cuda" only where Warp sees a CUDA device.
DEVICES = ("cpu", "cuda")

#: The capsule radius r / l (as MuJoCo's: at r >= l/2 the end cap reaches the centre of mass).
RADIUS = Interval(0.0, 0.5, lo_open=True, hi_open=True)

#: A stuck contact of the penalty solvers' regularised friction creeps at up to m g / kf at 1 g; the STICK threshold's
#: friction time is this margin over that creep (as Drake's regularised friction: crosscheck.engines.drake.options).
CREEP_MARGIN = 2.5

#: Largest solver iteration count accepted (MuJoCo Warp on CPU launches its kernels once per iteration: ~10 ms each).
MAX_ITERATIONS = 1000

_PENALTY = ("featherstone", "semi_implicit")


def init_warp():
    """Warp, configured and initialised: no line per module it loads, and not its line about a missing CUDA driver
    (its C code writes it to stderr at initialisation on a machine without a GPU: a refused ``device="cuda"`` is then
    one line, ours).  Returns the ``warp`` module."""
    import warp as wp

    wp.config.quiet = True
    wp.config.log_level = wp.LOG_WARNING
    with silenced():
        wp.init()  # once per process (a no-op afterwards)
    return wp


def _cuda_present() -> bool:
    """Whether Warp sees a CUDA device (imports warp: only asked when a run names "cuda")."""
    return init_warp().get_cuda_device_count() > 0


@dataclass(frozen=True)
class Options(EngineOptions):
    """Parameters of a Newton run, in the paper's scaled units (one class for every solver; each reads its own).

    Attributes:
      solver: which Newton solver steps the rod (a key of ``SOLVERS``), fixed by each registered engine's subclass
        (``crosscheck.engines.newton.solvers``): its default, so that ``Options()`` of an engine is that engine's.
      device: "cpu" (default) or "cuda"; "cuda" is refused in one line where Warp sees no CUDA device.
      timestep: omega dt (default 1e-3, ~3.2e-4 s for a 1 m rod): Warp on CPU costs ~10 ms per MuJoCo Warp step
        of a batch, so the maps run at 1e-3 (``benchmarks/bench_newton.py``).
      radius: capsule radius r / l (default 0.01, as ``models/rod.xml``).
      iterations: the solver's iterations per step; 0 (default) takes each solver's own default: 100 for MuJoCo
        Warp (as ``models/rod.xml``), Newton's 2 for XPBD; the penalty solvers have none.
      ls_iterations: MuJoCo Warp's line-search iterations (default 50, as ``models/rod.xml``).
      solver_tolerance: MuJoCo Warp's solver tolerance (default 1e-10, as ``models/rod.xml``; in float32 the
        Newton solver stops on its iteration cap or its line search well before 1e-10).
      timeconst, dampratio, solimp, impratio: MuJoCo Warp's contact, as the ``mujoco`` engine's options of the
        same names (defaults 0.06, 1, MuJoCo's solimp with width / l, 1).
      contact_relaxation: XPBD's ``rigid_contact_relaxation`` (default 0.8, Newton's).
      stiffness: the penalty solvers' normal stiffness k l / (m g) (default 1e4, Drake's convergence base).
      damping: their normal damping c l omega / (m g) (default 200 = 2 sqrt(stiffness), critical for the mass m).
      friction_gain: their friction regularisation kf l omega / (m g): friction = min(mu F_n, kf |u|) opposite the
        slip u (default 1e3: a stuck tip creeps at up to 1e-3 l omega under 1 g).
      axial_inertia: the rod's moment about its own axis / I0 (default 1e-12, rod.xml's: only positive definite).  No
        joint turns about the axis, but it adds axial_inertia I0 (Psi sin theta)^2 to the kinetic energy: a relative
        error of axial_inertia tan^2 theta in the inertia about the vertical.  XPBD projects the D6 joint's locked
        axis after the contact, and with 1e-12 the contact's friction correction turns the capsule about its axis
        instead of moving the tip (``crosscheck.engines.newton.model``).
      mujoco_cpu: MuJoCo Warp only: Newton's ``SolverMuJoCo(use_mujoco_cpu=True)``, the same converted model stepped
        by MuJoCo in C in float64 instead of MuJoCo Warp in float32 (default False): the float32 cause's intervention.
        MuJoCo's data then carries the run in float64 from step to step (Newton's float32 state is only read back),
        and Newton steps one world of it, so a sweep runs its starts one world at a time.
      joint_stiffness, joint_damping: the semi-implicit solver only: its joints are penalty springs in maximal
        coordinates (``SolverSemiImplicit``'s ``joint_attach_ke``, ``joint_attach_kd``), so the D6 joint's locked axis,
        the rod's own, is a torsion spring of stiffness joint_stiffness m g l / rad and damping joint_damping x 0.01
        m g l / (omega rad) (Newton scales the angular damping by 0.01).  Defaults 2 and 0.5 (``SemiImplicitOptions``).
    """

    solver: str = "mujoco"
    device: str = "cpu"
    timestep: float = 1e-3
    radius: float = 0.01
    iterations: int = 0
    ls_iterations: int = 50
    solver_tolerance: float = 1e-10
    timeconst: float = 0.06
    dampratio: float = 1.0
    solimp: tuple = (0.9, 0.95, 0.001, 0.5, 2.0)
    impratio: float = 1.0
    contact_relaxation: float = 0.8
    stiffness: float = 1e4
    damping: float = 200.0
    friction_gain: float = 1e3
    axial_inertia: float = 1e-12
    mujoco_cpu: bool = False
    joint_stiffness: float = 2.0
    joint_damping: float = 0.5

    def __post_init__(self) -> None:
        own = type(self).__dataclass_fields__["solver"].default
        if self.solver != own:  # each registered engine is one solver: its Options class fixes it
            raise ValueError(f"solver must be {own} for newton_{own} (one engine per solver); got {self.solver!r}")
        if self.device not in DEVICES:
            raise ValueError(f"device must be one of {', '.join(DEVICES)}; got {self.device!r}")
        if self.device == "cuda" and not _cuda_present():
            raise ValueError("device must be cpu on this machine (Warp finds no CUDA device); got 'cuda'")
        set_ = object.__setattr__
        set_(self, "timestep", check_timestep(self.timestep))
        set_(self, "radius", real_scalar("radius", self.radius, RADIUS))
        for name, lo in (("iterations", 0), ("ls_iterations", 1)):
            n = getattr(self, name)
            if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and lo <= n <= MAX_ITERATIONS):
                raise ValueError(f"{name} must be an integer in [{lo}, {MAX_ITERATIONS}]; got {n!r}")
            set_(self, name, int(n))
        if not isinstance(self.mujoco_cpu, (bool, np.bool_)):
            raise ValueError(f"mujoco_cpu must be True or False; got {self.mujoco_cpu!r}")
        set_(self, "mujoco_cpu", bool(self.mujoco_cpu))
        if self.mujoco_cpu and self.solver != "mujoco":
            raise ValueError(f"mujoco_cpu must be False for newton_{self.solver} (a SolverMuJoCo setting); got True")
        set_(self, "solver_tolerance", real_scalar("solver_tolerance", self.solver_tolerance, NONNEGATIVE))
        for name in (
            "timeconst",
            "dampratio",
            "impratio",
            "stiffness",
            "damping",
            "friction_gain",
            "axial_inertia",
            "joint_stiffness",
            "joint_damping",
        ):
            set_(self, name, real_scalar(name, getattr(self, name), POSITIVE))
        if self.timeconst < 2 * self.timestep:
            raise ValueError(
                f"timeconst must be >= 2 timestep = {2 * self.timestep:g} (MuJoCo's refsafe); got {self.timeconst!r}"
            )
        if self.axial_inertia > 1.0:
            raise ValueError(f"axial_inertia must be in (0, 1] (a fraction of I0); got {self.axial_inertia!r}")
        set_(self, "contact_relaxation", real_scalar("contact_relaxation", self.contact_relaxation, UNIT))
        s = real("solimp", self.solimp)
        if s.shape != (5,) or not (0 < s[0] < 1 and 0 < s[1] < 1 and s[2] > 0 and 0 < s[3] < 1 and s[4] >= 1):
            raise ValueError(
                "solimp must be 5 numbers (d0, dmax in (0, 1), width > 0, midpoint in (0, 1), power >= 1); "
                f"got {self.solimp!r}"
            )
        set_(self, "solimp", tuple(float(x) for x in s))

    @classmethod
    def label_of(cls, options: dict[str, Any]) -> str:
        """The label of the engine of this class's solver (each registered engine has its own ``Options`` class)."""
        solver = cls.__dataclass_fields__["solver"].default
        return LABELS.get(solver, f"newton_{solver}")

    @property
    def solver_iterations(self) -> int:
        """The iterations the solver runs: ``iterations``, or the solver's default where it is 0."""
        return self.iterations or {"mujoco": 100, "xpbd": 2}.get(self.solver, 0)

    @property
    def contact_time(self) -> float:
        """Time over which the normal force builds up (scaled).

        MuJoCo Warp: solref's time constant, as the ``mujoco`` engine's.  Penalty solvers: 1/omega_n of the contact
        spring with the rod's mass, 1 / sqrt(stiffness), as Drake's.  XPBD: 0, its contact is a position projection
        within the step (no force build-up; the rigid classifier's rules).
        """
        if self.solver == "mujoco":
            return self.timeconst
        if self.solver in _PENALTY:
            return 1.0 / math.sqrt(self.stiffness)
        return 0.0

    @property
    def compliant_twin(self) -> dict | None:
        """The penalty solvers' normal law as the compliant rod's options (``crosscheck.engines.compliant``): Kelvin-Voigt
        with eps = 1 / sqrt(stiffness) and xi = damping / sqrt(stiffness) (F_n = delta / eps^2 + xi delta' / eps), exact
        Coulomb friction, the same radius and timestep (record rows); None for MuJoCo Warp and XPBD.  Newton's damping
        acts only while the capsule sinks and its friction is regularised (``friction_gain``); the twin has neither.
        Read by the maps' check of no impact without collision: a compliant contact of finite eps stops a slip hard
        where p > 0 is small (its normal mode's time eps / sqrt(p) is not short against the slip), which the rigid
        theory forbids.  Measured at theta = 1, varphi = -1.9, Psi = 1.3125, mu = 1.3125 (p = 0.18; the capsule's
        p_C falls to 0.06 as varphi turns to -pi/2): Featherstone at stiffness 1e4 jams at t = 0.051 at timesteps 1e-3
        and 5e-4 (0.028 at 2e-3, its window's first row), the twin (eps 0.01, xi 2) at 0.050.  The twin slips as the
        theory at eps = 3.2e-3 and 1e-3, and Featherstone at stiffness 1e5 and 1e6 no longer jams (it lifts off at
        t = 0.19 and 0.22, where the theory's b is within 0.03 of 0)."""
        if self.solver not in _PENALTY:
            return None
        k = math.sqrt(self.stiffness)
        return {"eps": 1.0 / k, "xi": self.damping / k, "radius": self.radius, "timestep": self.timestep}

    @property
    def friction_time(self) -> float:
        """The STICK threshold's friction time (scaled): MuJoCo Warp's ``timeconst`` (its friction rows share
        solref); the penalty solvers' CREEP_MARGIN x their creep speed at 1 g, 1 / friction_gain; 0 for XPBD (its
        static friction holds the contact point by position)."""
        if self.solver == "mujoco":
            return self.timeconst
        if self.solver in _PENALTY:
            return CREEP_MARGIN / self.friction_gain
        return 0.0


@dataclass(frozen=True)
class MuJoCoWarpOptions(Options):
    """``Options`` of ``newton_mujoco``: MuJoCo Warp."""

    solver: str = "mujoco"


@dataclass(frozen=True)
class XPBDOptions(Options):
    """``Options`` of ``newton_xpbd``: XPBD, with an axial moment of 1e-4 I0: at rod.xml's 1e-12 its contact projection
    turns the capsule about its own axis (4.6e3 omega within a horizon of 1 from theta = 1, varphi = -1.9, mu = 0.5)
    and launches it; at 1e-6 the spin is 2.8 omega, at 1e-4 0.03 omega (iterations 2), while the inertia about the
    vertical errs by 1e-4 tan^2 theta (``Options.axial_inertia``)."""

    solver: str = "xpbd"
    axial_inertia: float = 1e-4


@dataclass(frozen=True)
class FeatherstoneOptions(Options):
    """``Options`` of ``newton_featherstone``: Featherstone with Newton's penalty contact."""

    solver: str = "featherstone"


@dataclass(frozen=True)
class SemiImplicitOptions(Options):
    """``Options`` of ``newton_semi_implicit``: maximal coordinates, Newton's penalty contact, the D6 joint a penalty
    spring.  Its locked axis, the rod's own, is a torsion spring of stiffness k = joint_stiffness m g l about an axial
    moment a I0, explicit in time: stable while sqrt(k / (a I0)) dt < 2.  Newton's default k (1e4 N m / rad on the
    scaled rod) diverged at a = 1e-12 and 1e-4 within 0.02 of time from theta = 1, varphi = -1.9, mu = 0.5 (axial spin
    1e5-1e7 omega) and at a = 1e-2 at timestep 3e-3; a = 1e-4 (XPBD's) with k = 2 keeps sqrt(k / (a I0)) dt = 1.5 at
    the quick convergence grid's coarsest step 6e-3 (alpha 3), and the friction torque mu F_n r twists the capsule by
    ~r mu F_n / k ~ 1e-2 rad at most about its own axis.  Measured at these defaults from that start over a horizon of
    1: a slip, as Featherstone's, theta within 3.9e-6, 5.1e-6, 6.7e-6 of Featherstone's and the axial spin at most
    0.25, 0.15, 0.14 omega at timestep 6e-3, 3e-3, 1e-3.  Newton's angular damping (0.05 by default, a drag on every
    rotation) is set to 0."""

    solver: str = "semi_implicit"
    axial_inertia: float = 1e-4
