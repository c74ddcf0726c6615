"""MuJoCo's rungs: the models between the rigid theory and MuJoCo that its ``Ladder`` declares (``crosscheck.studies.ladder``).

MuJoCo's capsule differs from the paper's rod in five ways at once: its
contact point C lies a radius r below the tip A, its contact is compliant,
its soft elliptic friction is not exactly opposite the slip, its normal force
feeds most of the rigid force forward at once (the impedance), and its time
is discretised.  Its ladder adds them one at a time:

====  ==============  ==============  ===================================================================
rung  name            cause           model
====  ==============  ==============  ===================================================================
1     ``tip``         (the theory)    rigid rod, contact at A: ``crosscheck.theory.slipping.slip_until_event``
2     ``capsule``     geometry        rigid rod, contact at C: ``crosscheck.theory.capsule``
3     ``compliant``   compliance      Kelvin-Voigt rod at C, exact Coulomb friction, MuJoCo-equivalent
                                      (eps, xi) (``mujoco_equivalent``)
4     ``spring_law``  friction law    MuJoCo's contact law at C in continuous time without its normal
                                      force's feed-forward: MuJoCo's friction on its solref spring-damper
5     ``mujoco_law``  feed-forward    MuJoCo's contact law at C in continuous time (``mujoco_law``)
6     ``engine``      discretisation  MuJoCo at the run's timestep
====  ==============  ==============  ===================================================================

Why the cause is the first rung of the final stretch of matches rather than
the first match: two of MuJoCo's differences can each change the outcome, and
a match that the next rung undoes is not the difference MuJoCo keeps.  Near
p = 0 the rigid rod at C jams where the rod at A lifts off (the offset r moves
p across 0), while the Kelvin-Voigt rod at C lifts off again and only MuJoCo's
law jams (the paper's IC2): the first match is geometry, yet a sixteen times
thinner MuJoCo capsule still jams and a smaller impedance removes the jam
(``crosscheck.studies.interventions``).  "friction law" is MuJoCo's friction
where rung 3 has Coulomb's: not opposite the slip, regularised and coupled to
the normal row by one convex problem.  "feed-forward" is the rest of MuJoCo's
law: its impedance applies a fraction d (0.9-0.95 by default) of the rigid
normal force at once, where the matched spring, and rung 4's solref
spring-damper, build the force over the time constant
(``crosscheck.engines.mujoco.law.contact_problem``).  Without rung 4 the two
were one cause, and a ladder often went from the theory's outcome to a third
one at rung 3 (the spring's slower force: a slip where the theory jams) and to
MuJoCo's only at the law: rung 4 shows the feed-forward as the step that ends
such a detour (``crosscheck.studies.ladder.detour``).

Rung 3's Kelvin-Voigt contact (F_n = -gap/eps^2 - (xi/eps) gap') is matched to
MuJoCo's normal row in ``crosscheck.engines.mujoco.studies.kelvin_voigt``:
equal stiffness and damping, eps = (dmax/d) timeconst dampratio sqrt(A_nn),
xi = 2 dampratio / sqrt(A_nn), A_nn = 1 + alpha cos^2 theta, d the impedance
at MuJoCo's static penetration of the start.

Each rung here is ``rung(rod, state, mu, *, horizon, thresholds, options)
-> Run`` with ``options`` MuJoCo's ``Options``.  Scaled units (section 2.1).
"""

from __future__ import annotations

from crosscheck import engines
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.mujoco.studies.kelvin_voigt import mujoco_equivalent
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = ["compliant", "spring_law", "mujoco_law"]


def compliant(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds, options):
    """Rung 3: the Kelvin-Voigt rod at C with MuJoCo-equivalent (eps, xi), recorded at MuJoCo's timestep (the
    classifier's windows then span the same rows)."""
    match = mujoco_equivalent(
        state, rod.alpha, timeconst=options.timeconst, dampratio=options.dampratio, solimp=options.solimp
    )
    return engines.get("compliant").simulate(
        rod,
        state,
        mu,
        horizon=horizon,
        thresholds=thresholds,
        eps=match.eps,
        xi=match.xi,
        radius=options.radius,
        timestep=options.timestep,
    )


def spring_law(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds, options):
    """Rung 4: MuJoCo's contact law at C in continuous time without its normal force's feed-forward."""
    return engines.get("mujoco_law").simulate(
        rod, state, mu, horizon=horizon, thresholds=thresholds, feed_forward=False, **options.as_dict()
    )


def mujoco_law(rod: Rod, state: SlipState, mu: float, *, horizon: float, thresholds: Thresholds, options):
    """Rung 5: MuJoCo's contact law at C in continuous time, at the run's options."""
    return engines.get("mujoco_law").simulate(
        rod, state, mu, horizon=horizon, thresholds=thresholds, **options.as_dict()
    )
