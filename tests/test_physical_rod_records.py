"""Every engine's record is in the paper's scaled units whatever the rod: one test per registered engine.

The rod's dynamics in scaled units (section 2.1: time 1/omega, lengths l, accelerations g, forces m g) depend on
alpha alone, so rods of different mass, length and gravity with the same alpha give the same ``Record``, every field
of it, and the same outcome.  A conversion left in physical units (an acceleration not divided by g, a force not by
m g, a time not multiplied by omega) is off for some rod below by a factor of g (9.81, or 1.62 on the Moon), m g (up
to 490 N), l (down to 0.01 m) or omega (up to 31 / s): far outside either tolerance.  Parametrised over
``crosscheck.engines.names()`` as the contract test is, so an engine added to the registry is held to it.
"""

from __future__ import annotations

import numpy as np
import pytest

from crosscheck import engines
from crosscheck.engines.record import FIELDS
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.tolerances import Tolerance

ENGINES = engines.names()

#: Rods with alpha = 3 (a uniform rod's I0 = m l^2 / 3): a 1 m rod on Earth, a 1 cm pin (omega = 31 / s), a heavy
#: short bar (m g = 490 N) and a rod on the Moon (g = 1.62).
RODS = {
    "uniform_1m": Rod.uniform(1.0, 1.0),
    "pin_1cm": Rod.uniform(0.2, 0.01),
    "heavy_short": Rod(mass=50.0, length=0.3, inertia=1.5, gravity=9.81),
    "moon": Rod.uniform(2.0, 0.5, gravity=1.62),
}
#: Off the planar section with a rate and a heading, slipping at mu = 0.5: every field is nonzero in some row.
STATE = SlipState(theta=0.8, varphi=-1.2, Theta=0.3, Psi=0.5, eta=1.5, psi=0.4)
MU = 0.5
#: Scaled time: ten rows or more of every engine (its default timestep, at most a tenth of this).
HORIZON = 0.05

#: A time-stepping engine steps in scaled time (its timestep / omega), so two rods do the same arithmetic on numbers
#: scaled by m, l and g: the records differ by rounding, amplified by the contact solvers' own tolerances.  Measured
#: max |difference| / (1 + max |field|): 2e-16 to 2.6e-12 (MuJoCo, Drake's discrete approximations, Pinocchio),
#: 1.7e-9 (Bullet's tip acceleration, its solver stopped at 1e-13 in physical impulses).
STEPPED = Tolerance(
    atol=1e-8, rtol=0.0, why="time-stepped in scaled time: rounding and solver tolerances (measured <= 1.7e-9)"
)
#: An error-controlled integrator picks its steps from an error norm in the units it integrates in: an engine that
#: integrates in physical units (Drake's continuous plant, runge_kutta3 at accuracy 1e-6) takes other steps for
#: another rod, and its records agree to its accuracy, not to rounding: measured 4.1e-5 (its tip acceleration and
#: contact force), 1.5e-7 in the states.  The crosscheck compliant rod, which integrates in scaled units, agrees
#: exactly.  1e-3: 25 times the measured, and a unit error (a factor >= 1.6 for every rod here) is 600 times it.
CONTINUOUS = Tolerance(
    atol=1e-3,
    rtol=0.0,
    why="error-controlled steps chosen in physical units: agreement to the integrator's accuracy (measured 4.1e-5)",
)


def _options(spec) -> dict:
    """The engine's default options with a timestep fine enough for HORIZON to hold ten rows or more."""
    opts = spec.options()
    return {"timestep": min(opts.timestep, HORIZON / 10)}


@pytest.mark.parametrize("name", ENGINES)
def test_every_field_of_the_record_is_the_same_in_scaled_units_for_every_rod(name):
    spec = engines.get(name)
    tol = CONTINUOUS if spec.has("continuous") else STEPPED
    opts = _options(spec)
    base = spec.simulate(Rod.scaled(3.0), STATE, MU, horizon=HORIZON, **opts)
    R = base.record
    # the conversions are exercised: a contact force in some row (a relaxed engine launches this tip at once, MuJoCo's
    # capsule chatters on the plane: not every row has one) and a tip acceleration in every row
    assert len(R) >= 10 and np.any(R.active) and np.any(R.normal_force > 0) and np.any(R.force[:, :2] != 0)
    assert np.all(np.linalg.norm(R.tip_acc, axis=-1) > 0) and np.all(R.eta > 0)
    for rod_name, rod in RODS.items():
        run = spec.simulate(rod, STATE, MU, horizon=HORIZON, **opts)
        assert (run.outcome, run.nstep) == (base.outcome, base.nstep), rod_name
        assert np.isnan(run.event_time) == np.isnan(base.event_time), rod_name
        if not np.isnan(base.event_time):
            assert abs(run.event_time - base.event_time) <= tol.atol * (1.0 + HORIZON), rod_name
        np.testing.assert_array_equal(run.record.active, R.active, err_msg=rod_name)
        for f in FIELDS:
            if f == "active":
                continue
            got, want = np.asarray(getattr(run.record, f), float), np.asarray(getattr(R, f), float)
            assert got.shape == want.shape, (rod_name, f)
            err = np.abs(got - want).max() / (1.0 + np.abs(want).max())
            assert err <= tol.atol, f"{name}, {rod_name}: {f} differs by {err:.3g} (of 1 + max |{f}|) > {tol.atol:g}"
