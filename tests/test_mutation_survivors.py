"""Promises of the newer code that a plausible bug broke without any test noticing: each test here names one.

The interventions' tallies of starts another cause removes; the end of a stick (its heading, and the tip's slip
direction in the world after it); a ladder rung that sticks after the theory's slip fell below the engine's STICK
floor; a chunk record written for another sweep copied into a store whose manifest is intact; the spring jam's inner
time exactly at k |b| != 1.  The convergence verdict's edges are in ``test_verdict_edges.py`` and every engine's
physical-rod record in ``test_physical_rod_records.py``.
"""

from __future__ import annotations

import json
import math
import shutil
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from crosscheck import Rod, SlipState, engines, sweeps
from crosscheck.engines.classifier import Thresholds, classify
from crosscheck.engines.record import FIELDS, Record
from crosscheck.engines.spec import EngineSpec, Ladder
from crosscheck.outcome import Outcome
from crosscheck.studies.interventions import summarise
from crosscheck.studies.ladder import run_ladder
from crosscheck.sweeps.store import StoreError
from crosscheck.theory.impact.continuation import run as hybrid_run
from crosscheck.theory.jam_lag import inner_pole, inner_scale, spring_jam_lag
from crosscheck.theory.sticking import at_rest, stick_until_event

ALPHA = 3.0

# ------------------------------------------------------------------------------------- interventions ---


def _removed_by(cause: str, fixing: set[str], causes=("geometry", "compliance", "friction law")) -> dict:
    """A laddered start named ``cause`` whose interventions remove the disagreement for the causes ``fixing`` alone."""
    return {
        "cause": cause,
        "interventions": {
            "theory": "SLIP",
            "causes": {c: [{"text": f"{c} step", "removes": c in fixing}] for c in causes},
        },
    }


def test_a_start_other_causes_remove_counts_once_and_only_an_attributed_one_is_misattributed():
    """``by_other`` counts each other cause that removes a start; ``by_other_starts`` counts the start once however
    many do; ``misattributed`` counts such starts only where the ladder named one of its causes ("unexplained" is
    not an attribution, so it cannot be a wrong one)."""
    results = [
        _removed_by("geometry", {"compliance", "friction law"}),  # two other causes remove it: one misattributed start
        _removed_by("geometry", {"geometry", "compliance"}),  # its own cause removes it: confirmed, not misattributed
        _removed_by("unexplained", {"geometry"}),  # removed, but the ladder named no cause
        _removed_by("compliance", set()),  # nothing removes it
    ]
    s = summarise(results)
    geometry, unexplained = s["per_cause"]["geometry"], s["per_cause"]["unexplained"]
    assert geometry["by_other"] == {"compliance": 1, "friction law": 1} and geometry["by_other_starts"] == 1
    assert unexplained["by_other"] == {"geometry": 1} and unexplained["by_other_starts"] == 1
    assert s["per_cause"]["compliance"]["by_other_starts"] == 0 and s["per_cause"]["compliance"]["none"] == 1
    assert (s["attributed"], s["confirmed"], s["misattributed"]) == (3, 1, 1)
    # every attributed start is confirmed, misattributed, jointly removed, unremoved or without an intervention
    per = [s["per_cause"][c] for c in ("geometry", "compliance")]
    assert s["attributed"] == sum(
        r["confirmed"] + r["by_other_starts"] + sum(r["jointly"].values()) + r["none"] + r["no_intervention"]
        for r in per
    )


# ----------------------------------------------------------------------------------------- sticking ---

#: A resting rod that pivots about its stuck tip, then slips outwards (varphi = -pi/2) when its friction ratio reaches
#: mu = 0.3 at t = 0.1744 (``tests/test_theory_sticking.py``), its heading turned from 0.4 to 0.476 meanwhile.
STICK_THEN_SLIP = (SlipState(theta=1.2, varphi=-math.pi / 2, Theta=-0.3, Psi=0.5, eta=0.0, psi=0.4), 0.3)
#: The rigid engine's timestep: it follows the hybrid model at first order in dt (``test_theory_sticking.py``).
DT = 3e-4


def test_a_stick_turns_the_heading_as_its_vertical_momentum_says_and_the_engine_follows():
    """While stuck, psi' = Psi and Psi cos^2 theta is conserved, so the heading at the stick's end is the start's plus
    the integral of Psi: the end state carries it (the slip after the stick starts from it), the rigid engine's psi
    at the cone exit agrees with it to first order in dt (measured 0.15 dt at dt = 3e-4; allowance 0.5 dt, as the
    other states in ``test_stick_then_slip_against_the_rigid_engine``), and its tip stays put meanwhile, moving
    slower than the classifier's STICK floor."""
    state, mu = STICK_THEN_SLIP
    assert at_rest(state, mu, ALPHA).mode == "stick"
    k = stick_until_event(state, mu, ALPHA, t_max=1.0)
    assert k.reason == "cone" and k.time == pytest.approx(0.1744, abs=1e-4)
    assert k.state.psi == k.y[-1, 0]  # the end state is the integration's last row
    turned = k.state.psi - state.psi
    assert turned == pytest.approx(_heading_turn(state, k.time), rel=1e-8) and turned > 0.05
    R = engines.get("pinocchio").simulate(Rod.scaled(ALPHA), state, mu, horizon=k.time + 0.15, timestep=DT).record
    i = round(k.time / DT)
    assert abs(R.psi[i] - k.state.psi) <= 0.5 * DT
    floor = Thresholds().stick_floor(timestep=DT, friction_timeconst=0.0, rigid=True)
    assert np.abs(R.tip_pos[:i, :2] - R.tip_pos[0, :2]).max() <= floor * k.time
    # the slip after the stick starts from the turned heading: the tip's slip direction in the world, psi + varphi,
    # 0.1 after the cone exit is the engine's (first order in dt: measured 0.62-0.68 dt; allowance 2 dt)
    j = round((k.time + 0.1) / DT)
    h = hybrid_run(state, mu, ALPHA, horizon=float(R.t[j]))
    assert [type(x).__name__ for x in h.segments] == ["Segment", "StickSegment", "Segment"]
    assert h.segments[2].start.psi == k.state.psi
    last = h.segments[2].slip.state
    beta = math.atan2(R.slip_vel[j, 1], R.slip_vel[j, 0])
    assert abs(beta - (last.psi + last.varphi)) <= 2 * DT and abs(R.psi[j] - last.psi) <= 0.5 * DT


def _heading_turn(state: SlipState, t_end: float) -> float:
    """psi(t_end) - psi(0) of the pivoting rod, integrated as psi' = Psi alongside eq. rotode with the sticking force
    (``stick_rates``) at tight tolerances: an independent integration of the same model."""
    from scipy.integrate import solve_ivp

    from crosscheck.theory.sticking import stick_rates

    def rhs(_t, y):
        Psi_dot, Theta_dot = stick_rates(y[1], y[2], y[3], ALPHA)
        return [y[2], y[3], Psi_dot, Theta_dot]

    y0 = [0.0, state.theta, state.Psi, state.Theta]
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="Radau", rtol=1e-12, atol=1e-14)
    return float(sol.y[0, -1])


# ------------------------------------------------------------------------------------------- ladder ---

#: A start of the full report's Psi_mu map whose theory slips to its exit from the paper's chart (t = 0.788), its
#: slip speed falling to 2.6e-3 on the way, below a rigid engine's STICK floor (10 timesteps: 0.01)
#: (``tests/test_interventions.py``).
SLIP_BELOW_FLOOR = (SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.875, eta=1.0), 0.875)


def test_a_rung_that_sticks_once_the_theorys_slip_is_below_its_stick_floor_is_labelled_the_theorys_slip():
    """The rigid engine as the one rung of a ladder: it STICKs within two steps of the time the theory's slip speed
    crosses its STICK floor, which the classifier cannot tell from the theory's slip; the rung is labelled SLIP, as
    the agreement study labels it (``comparison.stick_from``), and the ladder finds no disagreement."""
    state, mu = SLIP_BELOW_FLOOR
    pinocchio = engines.get("pinocchio")
    toy = EngineSpec(
        name="toy_rigid_ladder",
        engine=pinocchio.engine,
        tags=pinocchio.tags,
        ladder=Ladder(rungs={"discretisation": "engine"}),
    )
    engines.register(toy)
    try:
        ladder = run_ladder("toy_rigid_ladder", state, mu)
    finally:
        engines.unregister("toy_rigid_ladder")
    theory, rung = ladder.rungs
    assert (theory.outcome, theory.label) == (Outcome.SLIP, Outcome.SLIP)
    assert rung.outcome == Outcome.STICK and rung.time < ladder.until
    assert rung.label == Outcome.SLIP and ladder.cause == "agree"


# -------------------------------------------------------------------------------------------- store ---

SPEC = """
[sweep]
engine = "analytic"
horizon = 0.2
seed = 0
chunk = 2
[states]
theta = {start = 0.5, stop = 1.1, num = 3}
varphi = -1.5707963267948966
Theta = [0.0, 0.6]
Psi = 0.0
eta = 1.0
[parameters]
mu = 0.5
alpha = 3.0
"""  # 6 runs in 3 chunks


def test_a_chunk_and_its_record_from_another_sweep_are_refused_by_an_intact_manifest(tmp_path):
    """Another spec with the same layout (runs, chunks) at another mu: its chunk 1 and record, copied into this store,
    name the right file, rows and checksum, and its table holds runs 2 to 3; only the record's spec sha256 tells it
    apart.  ``load`` refuses it, naming the record, and a re-run recomputes that chunk alone."""
    here, there = tmp_path / "here.toml", tmp_path / "there.toml"
    here.write_text(SPEC)
    there.write_text(SPEC.replace("mu = 0.5", "mu = 0.6"))
    out, foreign = tmp_path / "out", tmp_path / "foreign"
    sweeps.run(here, out, workers=1, progress=False)
    sweeps.run(there, foreign, workers=1, progress=False)
    ref = sweeps.load(out).drop(columns=["wall_time"])
    manifest = (out / "manifest.json").read_bytes()
    for ext in ("parquet", "json"):
        shutil.copy(foreign / "chunks" / f"chunk-000001.{ext}", out / "chunks" / f"chunk-000001.{ext}")
    assert (out / "manifest.json").read_bytes() == manifest  # the manifest is untouched
    assert json.loads((out / "chunks" / "chunk-000001.json").read_text())["file"] == "chunk-000001.parquet"
    with pytest.raises(
        StoreError,
        match=r"chunk 1 of .* has a damaged record chunk-000001.json \(written for another sweep \(its spec sha256 "
        r"differs\)\)",
    ):
        sweeps.load(out)
    with pytest.warns(UserWarning, match="written for another sweep"):
        s = sweeps.run(here, out, workers=1, progress=False)
    assert (s.reused, s.computed) == ([0, 2], [1])
    pd.testing.assert_frame_equal(sweeps.load(out).drop(columns=["wall_time"]), ref)


# ------------------------------------------------------------------------------------------ jam lag ---


def test_the_inner_time_is_the_fifth_root_exactly_away_from_k_b_one():
    """T / eps^(4/5) = (k |b|)^(-1/5): at k |b| = 32 it is 1/2 and at 1/32 it is 2, both exact in binary, where any
    other exponent is off by a factor (2^(1/4) for -1/4); and the lag s* T at eps = 2^-5 is
    s* (eps^4 / (k |b|))^(1/5)."""
    assert inner_scale(-2.0, 16.0) == 0.5 and inner_scale(-0.25, 0.125) == 2.0
    assert inner_scale(-1.0, 32.0) == inner_scale(-32.0, 1.0) == 0.5  # only the product k |b| enters
    eps = 2.0**-5
    for b, k in ((-2.0, 16.0), (-0.3, 7.0)):
        want = inner_pole() * (eps**4 / (k * -b)) ** 0.2
        assert spring_jam_lag(eps, inner_scale(b, k)) == pytest.approx(want, rel=1e-14)


# --------------------------------------------------------------------------------------- classifier ---

#: A slip of the rigid engine for 0.3 (scaled), without event: the classifier's DIVERGED guards on a clean record.
CLEAN_SLIP = (SlipState(theta=0.5, varphi=-math.pi / 2, Theta=0.0, Psi=0.5, eta=1.0), 0.5)
#: The guard on the tip's vertical acceleration: |a_z + 1| < 1e9 (in g, from free fall, eq. b: a free tip has
#: a_z = b >= -1); a row at or beyond it either way is a divergence, a row just inside is not.
AZ_GUARD = 1e9


def _fault(R, k, name, value, column=None):
    x = np.array(getattr(R, name), dtype=float)
    if column is None:
        x[k] = value
    else:
        x[k, column] = value
    return replace(R, **{name: x})


@pytest.mark.parametrize(
    "name, column, value, diverged",
    [
        ("theta", None, math.inf, True),
        ("theta", None, math.nan, True),
        ("normal_force", None, math.inf, True),
        ("tip_acc", 2, math.nan, True),
        ("tip_acc", 2, -1.0 + AZ_GUARD, True),
        ("tip_acc", 2, -1.0 - AZ_GUARD, True),
        ("tip_acc", 2, -1.0 + AZ_GUARD - 1.0, False),
        ("tip_acc", 2, -1.0 - AZ_GUARD + 1.0, False),
    ],
    ids=[
        "theta_inf",
        "theta_nan",
        "force_inf",
        "az_nan",
        "az_at_guard_up",
        "az_at_guard_down",
        "az_inside_up",
        "az_inside_down",
    ],
)
def test_a_non_finite_or_runaway_row_of_any_field_is_diverged_at_that_row(name, column, value, diverged):
    """Each field the classifier guards (theta, the normal force, the tip's vertical acceleration) diverges the run
    at its faulty row, and the acceleration's guard is exactly |a_z + 1| < 1e9 g on both sides of free fall."""
    state, mu = CLEAN_SLIP
    dt = 1e-3
    run = engines.get("pinocchio").simulate(Rod.scaled(ALPHA), state, mu, horizon=0.3, timestep=dt)
    assert run.outcome == Outcome.SLIP
    k = 120
    c = classify(_fault(run.record, k, name, value, column), mu=mu, alpha=ALPHA, timestep=dt, rigid=True)
    if diverged:
        assert (c.outcome, c.event_row) == (Outcome.DIVERGED, k)
    else:
        assert c.outcome != Outcome.DIVERGED


#: A slow slip of the rigid engine at mu = 0.6 whose slip stops at t = 0.038 and sticks (``test_theory_sticking.py``).
SLIP_THEN_STICK = (SlipState(theta=1.2, varphi=-math.pi / 2, Theta=-0.3, Psi=0.5, eta=0.05, psi=0.4), 0.6)


def test_a_batch_of_records_is_classified_as_each_of_its_runs():
    """The classifier reads a batch (a leading axis of runs, as a batched sweep gives it) run by run: a STICK, a SLIP
    and a fault in the same batch each get exactly what they get alone, every field of the classification."""
    dt = 1e-3
    pin = engines.get("pinocchio")
    stick = pin.simulate(Rod.scaled(ALPHA), SLIP_THEN_STICK[0], 0.6, horizon=0.3, timestep=dt).record
    slip = pin.simulate(Rod.scaled(ALPHA), CLEAN_SLIP[0], 0.6, horizon=0.3, timestep=dt).record
    runs = [stick, slip, _fault(slip, 150, "theta", math.nan), stick]
    batch = Record(**{f: np.stack([getattr(r, f) for r in runs]) for f in FIELDS})
    together = classify(batch, mu=0.6, alpha=ALPHA, timestep=dt, rigid=True)
    alone = [classify(r, mu=0.6, alpha=ALPHA, timestep=dt, rigid=True) for r in runs]
    assert [Outcome(int(c.outcome)) for c in alone] == [Outcome.STICK, Outcome.SLIP, Outcome.DIVERGED, Outcome.STICK]
    for i, c in enumerate(alone):
        for f in c._fields:
            np.testing.assert_array_equal(getattr(together, f)[i], getattr(c, f), err_msg=f"run {i}: {f}")
