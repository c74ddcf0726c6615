"""The critical values of Psi as the theory and an engine see them (``crosscheck.studies.psi_critical``)."""

from __future__ import annotations

import numpy as np
import pytest

from crosscheck import engines
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.studies import psi_critical as pc
from crosscheck.theory import analytic, critical

MU, ALPHA = 1.4, 3.0
CV = critical.critical_values(mu=MU, alpha=ALPHA)


def test_the_critical_values_are_the_papers_at_mu_1_4():
    assert (round(CV.Psi_L, 4), round(CV.Psi_1, 4), round(CV.Psi_2, 4)) == (1.6119, 1.9480, 3.0097)


def test_the_slipping_flow_never_jams_above_Psi_2_and_does_below_it():
    """Section 3.3: for |Psi| >= Psi_2 no state has p < 0 with b < 0, so no slip jams there; below it some do."""
    rng = np.random.default_rng(7)
    S = pc.slipping_starts(160, rng, MU, ALPHA)
    ev = pc.theory_events(S, MU, ALPHA, horizon=0.5)
    jam = ev["outcome"] == Outcome.JAM
    assert not pc.ruled_out_jams(ev["outcome"], ev["Psi_event"], MU, ALPHA).any()
    assert (np.abs(ev["Psi_event"][jam]) < CV.Psi_2).all() and jam.any()


def test_no_inconsistent_state_exists_above_Psi_2_and_no_indeterminate_one_at_Theta_0_below_Psi_1():
    """The two kinematic statements behind the study, over seeded random (theta, varphi, Theta) at mu = 1.4."""
    rng = np.random.default_rng(3)
    n = 200_000
    theta, varphi = rng.uniform(0.01, 1.56, n), -rng.uniform(0.0, np.pi, n)
    p = analytic.p(theta, varphi, MU, ALPHA)
    above = CV.Psi_2 * (1 + 1e-9) + rng.uniform(0, 3, n)
    assert not ((p < 0) & (analytic.b(above, rng.uniform(-2, 2, n), theta) < 0)).any()
    below = CV.Psi_1 * (1 - 1e-9) * rng.uniform(0, 1, n)
    assert not ((p < 0) & (analytic.b(below, 0.0, theta) > 0)).any()
    assert ((p < 0) & (analytic.b(CV.Psi_1 + 0.3, 0.0, theta) > 0)).any()  # and just above Psi_1 there are some


def test_indeterminate_starts_are_indeterminate_and_the_compliant_theory_lifts_an_untouched_contact_off():
    rng = np.random.default_rng(1)
    for s in pc.indeterminate_starts(6, rng, MU, ALPHA):
        assert s.Theta == 0.0 and abs(s.Psi) > CV.Psi_1
        assert analytic.p(s.theta, s.varphi, MU, ALPHA) < 0 < analytic.b(s.Psi, 0.0, s.theta)
        assert pc.compliant_prediction(s, MU, ALPHA) == "LIFTOFF"
    with pytest.raises(ValueError, match="mu must be > mu_P"):
        pc.indeterminate_starts(1, rng, 1.0, ALPHA)


def test_the_rigid_stepper_never_jams_above_Psi_2():
    """Pinocchio's exact-cone stepper at slipping starts with |Psi| in (3.1, 5): no jam where the theorem rules one
    out."""
    rng = np.random.default_rng(11)
    S = pc.slipping_starts(12, rng, MU, ALPHA, abs_Psi=(3.1, 5.0))
    e = pc.engine_events(engines.get("pinocchio"), Rod.scaled(ALPHA), S, MU, horizon=0.5, options={"timestep": 3e-3})
    assert not pc.ruled_out_jams(e["outcome"], e["Psi_event"], MU, ALPHA).any()
    assert set(e["outcome"].tolist()) <= {int(o) for o in Outcome}
