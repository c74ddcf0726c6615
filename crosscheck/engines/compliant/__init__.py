"""The compliant rod in 3D: the paper's rod on an elastic plane (contact regularisation) with exact Coulomb friction.

The paper's closing remark: contact regularisation, a rigid rod on an elastic
surface, resolves the Painleve paradox in 2D, and its 3D extension is left to
further work.  This package is that model: the rod of section 2 (eq.
inertia, alpha = m l^2 / I0) with a unilateral normal law of small parameter
eps (Kelvin-Voigt by default: stiffness 1/eps^2, damping xi/eps in scaled
units) at the tip A or at a capsule's lowest point C = A - r K, exact Coulomb
friction with a stick phase, integrated event by event with a stiff method.

Energy.  With xi >= 0 and mu >= 0 the total mechanical energy (kinetic,
gravity, and the law's elastic energy while penetrating) never increases:
the dashpot dissipates xi/eps delta'^2, slipping friction mu F_n |s|, stuck
friction does no work, and where the clipped force is zero inside the plane
(the law would pull) the stored elastic energy only drains.

Modules: ``laws`` (the normal laws), ``model`` (the dynamics), ``trajectory``
(the event-driven solution, ``integrate``), ``switches`` (its mode switches), ``manifold`` (the slow
manifold's start, ``slow_manifold``), ``run`` (``simulate``: the engine's
``Run``).
"""

from crosscheck.engines.compliant.laws import LAWS, NormalLaw
from crosscheck.engines.compliant.manifold import rigid_normal_force, slow_manifold
from crosscheck.engines.compliant.model import Dynamics
from crosscheck.engines.compliant.run import Options, simulate, sweep
from crosscheck.engines.compliant.switches import EVENT_KINDS, Event
from crosscheck.engines.compliant.trajectory import Trajectory, integrate
from crosscheck.engines.spec import EngineSpec, Execution, ReportPlan

__all__ = [
    "ENGINES",
    "integrate",
    "simulate",
    "sweep",
    "slow_manifold",
    "rigid_normal_force",
    "Options",
    "Trajectory",
    "Event",
    "EVENT_KINDS",
    "Dynamics",
    "NormalLaw",
    "LAWS",
]


ENGINES = (
    EngineSpec(
        name="compliant",
        engine="crosscheck.engines.compliant.run",
        tags={"compliant", "continuous"},
        execution=Execution(one_core={"workers": 1}),
        report=ReportPlan(sections="crosscheck.engines.compliant.sections:sections", order=30),
    ),
)
