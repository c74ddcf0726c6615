"""Bad input raises ValueError naming the parameter and its allowed range (same text as the CLI)."""

import math
from pathlib import Path

import numpy as np
import pytest

from crosscheck import Rod, SlipState, critical_values
from crosscheck.coordinates import from_generalized, paper_to_qv, qv_to_paper, to_generalized
from crosscheck.theory import analytic


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: analytic.p(1.6, -1.0, 1.0, 3.0), "theta must be in (0, pi/2); got 1.6"),
        (lambda: analytic.p(0.0, -1.0, 1.0, 3.0), "theta must be in (0, pi/2); got 0.0"),
        (lambda: analytic.p(1.0, -1.0, -0.1, 3.0), "mu must be in [0, 1000]; got -0.1"),
        (lambda: analytic.p(1.0, -1.0, 1.0, 0.0), "alpha must be in [0.001, 1000]; got 0.0"),
        (lambda: analytic.p([0.5, np.nan], -1.0, 1.0, 3.0), "theta must be in (0, pi/2); got nan"),
        (lambda: analytic.b(np.inf, 0.0, 1.0), "Psi must be in [-1e+100, 1e+100]; got inf"),
        (lambda: critical_values(-1, 3), "mu must be in [0, 1000]; got -1.0"),
        (lambda: critical_values(1, -3), "alpha must be in [0.001, 1000]; got -3.0"),
        (lambda: analytic.kinematic_case(1.4, np.nan, 3), "Psi must be in [-100, 100]; got nan"),
        (lambda: Rod(mass=0.0), "mass must be in [1e-100, 1e+100]; got 0.0"),
        (lambda: Rod(inertia=-1.0), "inertia must be in [1e-100, 1e+100]; got -1.0"),
        (lambda: Rod.scaled(alpha=0), "alpha must be in [0.001, 1000]; got 0.0"),
        (lambda: SlipState(theta=2.0, varphi=-1, Theta=0, Psi=0, eta=1), "theta must be in (0, pi/2); got 2.0"),
        (lambda: SlipState(theta=1.0, varphi=0.5, Theta=0, Psi=0, eta=1), "varphi must be in (-pi, 0]; got 0.5"),
        (
            lambda: SlipState(theta=1.0, varphi=-math.pi, Theta=0, Psi=0, eta=1),
            f"varphi must be in (-pi, 0]; got {-math.pi!r}",
        ),
        (lambda: SlipState(theta=1.0, varphi=-1, Theta=0, Psi=0, eta=-1), "eta must be in [0, inf); got -1.0"),
        (
            lambda: SlipState(theta=1.0, varphi=-1, Theta=math.nan, Psi=0, eta=1),
            "Theta must be in (-inf, inf); got nan",
        ),
        (
            lambda: analytic.tip_acceleration(Rod(), 0, 1, 0, 0, [1, 2]),
            "force must have shape (..., 3) (Fx, Fy, Fz in the world frame); got (2,)",
        ),
        (lambda: analytic.scaled_rhs(np.zeros(9), 0, 1, 3), "state must have shape (..., 10) ordered as"),
    ],
)
def test_bad_input_message(call, message):
    with pytest.raises(ValueError) as err:
        call()
    assert str(err.value).startswith(message)


@pytest.mark.parametrize("interval", ["THETA", "VARPHI", "MU", "ETA", "HORIZON", "FINITE"])
def test_a_plain_number_is_checked_as_the_same_number_in_an_array(interval):
    # check tests a float or int without numpy; both paths must accept and refuse exactly the same values
    from crosscheck import checks

    iv = getattr(checks, interval)
    edges = [
        iv.lo,
        iv.hi,
        math.nextafter(iv.lo, math.inf),
        math.nextafter(iv.hi, -math.inf),
        math.nextafter(iv.lo, -math.inf),
        math.nextafter(iv.hi, math.inf),
        0.0,
        -0.0,
        1.0,
        -1.0,
        0,
        1,
        -1,
        math.nan,
        math.inf,
        -math.inf,
    ]
    for v in edges + [np.float64(e) for e in edges]:
        try:
            got = ("ok", float(checks.check("x", v, iv)))
        except ValueError as e:
            got = ("refused", str(e))
        try:
            want = ("ok", float(checks.check("x", np.array([v], float), iv)[0]))
        except ValueError as e:
            want = ("refused", str(e))
        assert got == want, (interval, v)
        assert got[0] == "refused" or checks.check("x", v, iv).shape == ()


def test_an_integer_beyond_every_float_is_refused_naming_the_parameter():
    from crosscheck.checks import MU, check

    with pytest.raises(ValueError, match="^mu must be in "):
        check("mu", 10**400, MU)
    with pytest.raises(ValueError, match="^mu must be a number in "):
        check("mu", [10**400], MU)
    with pytest.raises(ValueError, match="^eta must be in "):
        SlipState(theta=1.0, varphi=-1, Theta=0, Psi=0, eta=10**400)


def test_rod_scaled_units():
    rod = Rod.scaled(4.0)
    assert (rod.mass, rod.length, rod.gravity, rod.alpha, rod.omega) == (1.0, 1.0, 1.0, 4.0, 1.0)
    assert Rod.uniform(2.0, 0.5).alpha == pytest.approx(3.0, rel=1e-15)


def test_coordinates_round_trip():
    rng = np.random.default_rng(3)
    rod = Rod(mass=2.0, length=0.7, inertia=0.2, gravity=9.81)
    for _ in range(100):
        s = SlipState(
            theta=rng.uniform(0.01, 1.56),
            varphi=rng.uniform(-3.14, 0),
            Theta=rng.normal(),
            Psi=rng.normal(),
            eta=rng.uniform(0.01, 3),
            psi=rng.uniform(-3, 3),
        )
        q, v = to_generalized(rod, s, tip=(0.5, -0.2, 0.0))
        d = qv_to_paper(rod, q, v)
        assert d["z"] == pytest.approx(0.0, abs=1e-15) and d["w"] == pytest.approx(0.0, abs=1e-14)
        assert (d["x"], d["y"]) == pytest.approx((0.5, -0.2), abs=1e-15)
        back = from_generalized(rod, q, v)
        for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi"):
            assert getattr(back, k) == pytest.approx(getattr(s, k), rel=1e-12, abs=1e-12), k


def test_coordinates_vectorise():
    rod = Rod()
    q, v = paper_to_qv(rod, np.full(5, 0.8), -1.0, 0.2, np.linspace(-1, 1, 5), 1.0)
    assert q.shape == v.shape == (5, 5)
    np.testing.assert_allclose(qv_to_paper(rod, q, v)["Psi"], np.linspace(-1, 1, 5), rtol=1e-15)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["validate", "pinocchio", "--states", "1e3"], "states must be an integer in [1, 1000000]; got '1e3'"),
        (["validate", "mujoco", "--states", "0"], "states must be an integer in [1, 1000000]; got '0'"),
        (["validate", "mujoco", "--seed", "-1"], "seed must be an integer in [0, 9223372036854775807]; got '-1'"),
        (
            ["report", "--seed", "1.5", "--out", "unused"],
            "seed must be an integer in [0, 9223372036854775807]; got '1.5'",
        ),
        (["report", "--workers", "0", "--out", "unused"], "workers must be an integer in [1, 1024]; got '0'"),
        (
            ["sweep", "examples/sweep.toml", "--out", "unused", "--workers", "abc"],
            "workers must be an integer in [1, 1024]; got 'abc'",
        ),
    ],
    ids=["states-float", "states-zero", "seed-negative", "report-seed", "report-workers", "sweep-workers"],
)
def test_integer_options_name_their_range(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(Path(__file__).parents[1])
    from crosscheck.cli import main

    assert main(argv) == 2
    assert capsys.readouterr().err.strip().splitlines() == [f"crosscheck: error: {message}"]
    assert not Path("unused").exists()
