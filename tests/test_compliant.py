"""The compliant rod (crosscheck.compliant): convergence to the rigid flow, stick, the capsule's contact point, energy, bad inputs."""

from __future__ import annotations

import numpy as np
import pytest

from crosscheck.analytic import normal_force
from crosscheck.compliant import integrate, simulate
from crosscheck.rod import Rod
from crosscheck.slipping import slip_until_event
from crosscheck.state import SlipState

ROD = Rod.scaled(3.0)
SLIPPING = SlipState(theta=0.6, varphi=-1.0, Theta=0.3, Psi=0.5, eta=1.0)


def _slow_error(eps: float, mu: float = 0.3, horizon: float = 1.0) -> float:
    """Largest error of (eta, varphi, Psi, theta, Theta) at t = horizon against the rigid flow, started on the slow manifold."""
    rigid = slip_until_event(SLIPPING, mu, ROD.alpha, t_max=horizon)
    x = rigid.x[-1]
    Fz = float(normal_force(SLIPPING.Psi, SLIPPING.Theta, SLIPPING.theta, SLIPPING.varphi, mu, ROD.alpha))
    d = integrate(ROD, SLIPPING, mu, horizon=horizon, eps=eps, xi=1.0, gap=-eps**2 * Fz).state_at(horizon)
    return max(abs(d["eta"] - x[0]), abs(d["varphi"] - x[1]), abs(d["Psi"] - x[3]), abs(d["theta"] - x[4]), abs(d["Theta"] - x[5]))


def test_slipping_converges_to_the_rigid_flow():
    errs = [_slow_error(e) for e in (1e-1, 3e-2, 1e-2)]
    assert errs[0] > errs[1] > errs[2]


BAD = {
    "eps": (dict(eps=0.0, xi=1.0), "eps must be in (0, inf); got 0.0"),
    "xi": (dict(eps=1e-2, xi=-1.0), "xi must be in [0, inf); got -1.0"),
    "radius": (dict(eps=1e-2, xi=1.0, radius=0.5), "radius must be in [0, 0.5); got 0.5"),
    "law": (dict(eps=1e-2, xi=1.0, law="hertz"), "law must be one of hunt-crossley, kelvin-voigt; got 'hertz'"),
    "gap": (dict(eps=1e-2, xi=1.0, gap=1e-3), "gap must be in (-inf, 0]; got 0.001"),
}


@pytest.mark.parametrize("case", BAD, ids=str)
def test_bad_inputs_are_named(case):
    kw, message = BAD[case]
    with pytest.raises(ValueError) as e:
        integrate(ROD, SLIPPING, 0.3, horizon=0.1, **kw)
    assert str(e.value) == message
    kw = {k: v for k, v in kw.items() if k != "gap"}
    if "gap" not in BAD[case][0]:
        with pytest.raises(ValueError) as e:
            simulate(ROD, SLIPPING, 0.3, horizon=0.1, **kw)
        assert str(e.value) == message
