"""Unilateral normal contact laws of the compliant rod: the force as a function of penetration and its rate.

Scaled units (section 2.1 of the paper): the penetration delta = -gap of the
contact point in units of l, its rate delta' in l omega, the force in m g.  A
law has a small parameter eps (the contact's time scale: the force builds up
over a time O(eps), and the penetration of a resting rod is O(eps^2)) and a
dimensionless damping xi.  Every law pushes only (F_n >= 0) and only while the
contact point penetrates (delta > 0); ``push`` is the unclipped expression
whose sign decides whether the contact holds, so the integrator can put an
event on its zero crossing.

Laws are looked up by name (``get``); ``register`` adds one.
"""

from __future__ import annotations

from dataclasses import dataclass

from crosscheck.checks import Interval

__all__ = ["NormalLaw", "KelvinVoigt", "HuntCrossley", "LAWS", "get", "register", "names", "EPS", "XI"]

#: The contact's time scale eps (scaled by 1/omega).  Below 1e-7 the resting penetration eps^2 F_n
#: (~1e-14 l) comes within ~100 ulp of the O(1) position it is a difference of, and the stiffness
#: 1/eps^2 > 1e14 leaves the gap's rounding error as the force; above 1 the contact is slower than
#: the rod's own time 1/omega and no longer a regularisation of the rigid contact the paper studies.
EPS = Interval(1e-7, 1.0, lo_open=False, hi_open=False)

#: The dimensionless damping xi (damping xi / eps).  Critical damping of the normal row is
#: xi = 2 / sqrt(p) = O(1); 1000 is three orders past it, where the contact is all dashpot.
XI = Interval(0.0, 1e3, lo_open=False, hi_open=False)


@dataclass(frozen=True)
class NormalLaw:
    """A unilateral normal law F_n = max(0, push(delta, delta')) for delta > 0, else 0.

    Subclasses give ``push`` and its partial derivatives (the stiff part of the
    integrator's Jacobian).
    """

    name = "abstract"

    def push(self, delta: float, delta_rate: float, eps: float, xi: float) -> float:
        raise NotImplementedError

    def dpush(self, delta: float, delta_rate: float, eps: float, xi: float) -> tuple[float, float]:
        """(d push / d delta, d push / d delta')."""
        raise NotImplementedError

    def energy(self, delta: float, eps: float) -> float:
        """The conservative (elastic) part's stored energy at penetration delta > 0 [m g l]."""
        raise NotImplementedError

    def force(self, delta: float, delta_rate: float, eps: float, xi: float) -> float:
        """F_n [m g]: max(0, push) while delta > 0, 0 otherwise."""
        if delta <= 0.0:
            return 0.0
        return max(0.0, self.push(delta, delta_rate, eps, xi))


@dataclass(frozen=True)
class KelvinVoigt(NormalLaw):
    """Linear spring and dashpot: push = delta / eps^2 + (xi / eps) delta'.

    Stiffness 1/eps^2 and damping xi/eps in scaled units: the undamped contact
    oscillates at angular frequency ~ sqrt(G_nn)/eps (G_nn the normal Delassus
    entry, eq. p's p at mu = 0), and xi = 2/sqrt(G_nn) is critical damping.  A
    rod resting with force F_z penetrates delta = eps^2 F_z (the slow manifold).
    """

    name = "kelvin-voigt"

    def push(self, delta, delta_rate, eps, xi):
        return delta / (eps * eps) + (xi / eps) * delta_rate

    def dpush(self, delta, delta_rate, eps, xi):
        return 1.0 / (eps * eps), xi / eps

    def energy(self, delta, eps):
        return 0.5 * delta * delta / (eps * eps)


@dataclass(frozen=True)
class HuntCrossley(NormalLaw):
    """Hunt-Crossley: push = (delta / eps^2) (1 + (xi / eps) delta'), damping proportional to penetration.

    With this form the damping vanishes at first touch (no force jump when
    the contact closes with a normal velocity) and the coefficient of
    restitution depends on the impact speed; the slow manifold is the same
    delta = eps^2 F_z as Kelvin-Voigt's.
    """

    name = "hunt-crossley"

    def push(self, delta, delta_rate, eps, xi):
        return delta / (eps * eps) * (1.0 + (xi / eps) * delta_rate)

    def dpush(self, delta, delta_rate, eps, xi):
        return (1.0 + (xi / eps) * delta_rate) / (eps * eps), delta * xi / (eps**3)

    def energy(self, delta, eps):
        return 0.5 * delta * delta / (eps * eps)


#: The known laws by name.
LAWS: dict[str, NormalLaw] = {}


def register(law: NormalLaw) -> NormalLaw:
    """Make ``law`` available as ``get(law.name)``; a taken name is refused."""
    if law.name in LAWS:
        raise ValueError(f"a normal law named {law.name!r} is already registered")
    LAWS[law.name] = law
    return law


register(KelvinVoigt())
register(HuntCrossley())


def names() -> list[str]:
    """Names of the known laws, sorted."""
    return sorted(LAWS)


def get(name) -> NormalLaw:
    """The law called ``name``; ValueError listing the known names otherwise."""
    if isinstance(name, NormalLaw):
        return name
    if not isinstance(name, str) or name not in LAWS:
        raise ValueError(f"law must be one of {', '.join(names())}; got {name!r}")
    return LAWS[name]
