"""What many test files share: the paper's uniform rod and seeded random slipping states."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crosscheck.rod import Rod
from crosscheck.state import SlipState

#: alpha of a uniform rod (I0 = m l^2 / 3), the paper's running example.
ALPHA = 3.0


def random_slip_states(rng: np.random.Generator, n: int) -> list[SlipState]:
    """``n`` slipping states drawn from ``rng``: theta in (0.05, 1.5), varphi in (-3.1, 0], Theta ~ N(0, 1), Psi ~ N(0, 4),
    eta in (0, 2), psi in (-pi, pi): every quadrant of the slip direction, both signs of the rates."""
    return [
        SlipState(theta=rng.uniform(0.05, 1.5), varphi=-rng.uniform(0.0, 3.1), Theta=rng.normal(), Psi=2 * rng.normal(), eta=rng.uniform(0, 2),
                  psi=rng.uniform(-math.pi, math.pi))
        for _ in range(n)
    ]


@pytest.fixture
def rod() -> Rod:
    """The scaled uniform rod (m = l = g = 1, alpha = 3)."""
    return Rod.scaled(ALPHA)
