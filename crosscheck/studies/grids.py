"""Starting states for the studies: product grids, random slipping states, and their b and p (eqs. b, p).

Every study of ``crosscheck.studies`` takes its states as a dict of (N,)
arrays with the keys ``AXES`` ("points"), built from an ``EventGrid`` or
drawn at random with a seeded ``numpy.random.Generator``.  All in the
paper's scaled units (section 2.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crosscheck.checks import ETA, MU, RATE, THETA, VARPHI, check
from crosscheck.state import SlipState
from crosscheck.theory.critical import theta_L

__all__ = [
    "AXES",
    "EventGrid",
    "DEFAULT_GRID",
    "SMALL_GRID",
    "floats",
    "initial_b_p",
    "states_at",
    "random_event_points",
    "random_slipping_states",
]

#: Axes of an ``EventGrid``, in the order of its shape.
AXES = ("theta", "varphi", "Theta", "Psi", "mu", "eta")


def floats(name: str, values, interval) -> tuple[float, ...]:
    """``values`` as a non-empty tuple of floats in ``interval`` (ValueError naming ``name`` otherwise)."""
    arr = np.atleast_1d(check(name, values, interval)).astype(float)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D sequence of numbers in {interval}; got {values!r}")
    return tuple(float(x) for x in arr)


@dataclass(frozen=True)
class EventGrid:
    """A product grid of initial slipping states and friction coefficients (scaled units).

    Every combination of the axes is one state; ``points()`` lists them in C
    order of ``AXES`` (theta slowest, eta fastest).  psi = 0 (cyclic).

    Attributes: one non-empty tuple per axis of ``AXES``: theta in (0, pi/2),
    varphi in (-pi, 0], Theta and Psi finite, mu >= 0, eta >= 0.
    """

    theta: tuple
    varphi: tuple
    Theta: tuple
    Psi: tuple
    mu: tuple
    eta: tuple = (1.0,)

    def __post_init__(self) -> None:
        intervals = {"theta": THETA, "varphi": VARPHI, "Theta": RATE, "Psi": RATE, "mu": MU, "eta": ETA}
        for name in AXES:
            object.__setattr__(self, name, floats(name, getattr(self, name), intervals[name]))

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(getattr(self, a)) for a in AXES)

    def __len__(self) -> int:
        return int(np.prod(self.shape))

    def points(self) -> dict[str, np.ndarray]:
        """(N,) arrays, one per axis, N = len(grid), C order of ``AXES``."""
        mesh = np.meshgrid(*(np.array(getattr(self, a)) for a in AXES), indexing="ij")
        return {a: m.ravel() for a, m in zip(AXES, mesh)}

    def as_dict(self) -> dict[str, list[float]]:
        return {a: list(getattr(self, a)) for a in AXES}


#: The report's grid: 5616 states, of which ~2400 start slipping (b < 0 < p).
#: Psi over both signs with varphi on one side of -pi/2 covers all
#: directions: (varphi, Psi) -> (-pi - varphi, -Psi) maps analytic runs onto
#: each other (mirror in the rod's vertical plane; checked to 1e-11 in time).
#: mu from well below mu_P(3) = 4/3 to 6 (the paper's 1.4, 1.7, 6 included).
DEFAULT_GRID = EventGrid(
    theta=(0.3, float(theta_L), 0.9, 1.2),
    varphi=(-math.pi / 2, -3 * math.pi / 8, -math.pi / 4, -math.pi / 8),
    Theta=(-0.5, 0.0, 0.5),
    Psi=tuple(np.linspace(-3.0, 3.0, 13)),
    mu=(0.3, 0.6, 1.0, 1.3, 1.4, 1.7, 2.5, 4.0, 6.0),
)

#: A grid for tests: 2 x 2 x 1 x 4 x 3 = 48 states.
SMALL_GRID = EventGrid(
    theta=(0.3, 0.9), varphi=(-math.pi / 2, -math.pi / 4), Theta=(0.0,), Psi=(-1.5, -0.5, 0.5, 1.5), mu=(0.6, 1.4, 4.0)
)


def initial_b_p(points: dict, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """Eqs. b and p at every point (each (N,))."""
    th, vp, Th, Ps, mu = (points[k] for k in ("theta", "varphi", "Theta", "Psi", "mu"))
    s, c = np.sin(th), np.cos(th)
    b = (Ps**2 * c**2 + Th**2) * s - 1.0  # eq. b
    p = 1.0 + alpha + alpha * s * (mu * c * np.sin(vp) - s)  # eq. p
    return b, p


def states_at(points: dict, idx) -> list[SlipState]:
    """The ``SlipState``s of the points ``idx``."""
    return [
        SlipState(
            theta=points["theta"][i],
            varphi=points["varphi"][i],
            Theta=points["Theta"][i],
            Psi=points["Psi"][i],
            eta=points["eta"][i],
        )
        for i in idx
    ]


def random_event_points(n: int, rng: np.random.Generator, *, alpha: float = 3.0) -> dict[str, np.ndarray]:
    """n random slipping starts (b < 0 < p) with random mu, each key of ``AXES`` an (n,) array.

    theta ~ U(0.1, 1.45), varphi ~ -U(0, pi) (clipped into (-pi, 0]), Theta ~
    U(-1, 1), Psi ~ U(-3, 3), eta ~ U(0.3, 2), mu ~ U(0.3, 6).
    """
    out = {k: [] for k in ("theta", "varphi", "Theta", "Psi", "mu", "eta")}
    while len(out["theta"]) < n:
        m = 4 * (n - len(out["theta"])) + 8
        th, vp = rng.uniform(0.1, 1.45, m), -rng.uniform(0.0, math.pi * (1 - 1e-9), m)
        Th, Ps, eta, mu = (
            rng.uniform(-1, 1, m),
            rng.uniform(-3, 3, m),
            rng.uniform(0.3, 2.0, m),
            rng.uniform(0.3, 6.0, m),
        )
        s, c = np.sin(th), np.cos(th)
        ok = ((Ps**2 * c**2 + Th**2) * s - 1 < 0) & (1 + alpha + alpha * s * (mu * c * np.sin(vp) - s) > 0)
        for k, v in zip(out, (th, vp, Th, Ps, mu, eta)):
            out[k].extend(v[ok].tolist())
    return {k: np.array(v[:n]) for k, v in out.items()}


def random_slipping_states(mu: float, n: int, rng: np.random.Generator, alpha: float) -> list[SlipState]:
    """n random slipping states (b < 0 < p) at one mu.

    theta ~ U(0.05, 1.5), varphi ~ -U(0, pi), Theta ~ U(-1.5, 1.5), Psi ~ U(-2.5, 2.5), eta ~ U(0.2, 3).
    """
    out = []
    while len(out) < n:
        s = SlipState(
            theta=rng.uniform(0.05, 1.5),
            varphi=-rng.uniform(0.0, math.pi * (1 - 1e-9)),
            Theta=rng.uniform(-1.5, 1.5),
            Psi=rng.uniform(-2.5, 2.5),
            eta=rng.uniform(0.2, 3),
        )
        st, ct = math.sin(s.theta), math.cos(s.theta)
        if (s.Psi**2 * ct**2 + s.Theta**2) * st - 1 < 0 and 1 + alpha + alpha * st * (
            mu * ct * math.sin(s.varphi) - st
        ) > 0:
            out.append(s)
    return out
