"""Every number the paper prints (crosscheck.theory.paper.PRINTED), to its printed digits."""

import math

import pytest

from crosscheck.theory import critical as cr
from crosscheck.theory.paper import PRINTED
from crosscheck.tolerances import CLOSED_FORM

AGREE = [pv for pv in PRINTED if not pv.known_discrepancy]
MISPRINTED = [pv for pv in PRINTED if pv.known_discrepancy]


@pytest.mark.parametrize("pv", AGREE, ids=lambda pv: pv.name)
def test_printed_value_reproduced_to_printed_digits(pv):
    assert abs(pv.computed() - pv.value) <= pv.half_ulp, (pv.computed(), pv.printed)


@pytest.mark.parametrize("pv", MISPRINTED, ids=lambda pv: pv.name)
def test_misprints_are_off_by_one_in_the_last_digit_only(pv):
    # A misprint documented in the registry is a last-digit slip, never a different number.
    err = abs(pv.computed() - pv.value)
    assert pv.half_ulp < err <= 3 * pv.half_ulp


def test_varphi_1_misprint_is_inconsistent_with_the_printed_varphi_2():
    # eq. varphi12: varphi_1 + varphi_2 = -pi exactly, so the printed pair must sum to -pi
    # within one printed unit; -1.8807 + -1.2610 = -3.1417 misses -pi = -3.14159 by 1.1e-4.
    cv = cr.critical_values(1.4, 3.0)
    assert cv.varphi_1 + cv.varphi_2 == pytest.approx(-math.pi, abs=CLOSED_FORM.atol)
    assert abs(-1.8807 + -1.2610 + math.pi) > 1e-4
    assert round(-math.pi - -1.2610, 4) == round(cv.varphi_1, 4) == -1.8806


def test_closed_forms_for_the_uniform_rod():
    # The paper writes these as exact expressions for alpha = 3.
    assert cr.mu_P(3.0) == pytest.approx(4 / 3, rel=CLOSED_FORM.rtol)
    assert cr.mu_C(3.0) == pytest.approx(8 / (3 * math.sqrt(3)), rel=CLOSED_FORM.rtol)
    assert cr.mu_L(3.0) == pytest.approx(3 / math.sqrt(2), rel=CLOSED_FORM.rtol)
    assert math.sin(cr.theta_L) == pytest.approx(1 / math.sqrt(3), rel=CLOSED_FORM.rtol)
    assert cr.Psi_L**2 == pytest.approx(3 * math.sqrt(3) / 2, rel=CLOSED_FORM.rtol)
