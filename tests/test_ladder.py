"""MuJoCo's ladder (its rungs ``crosscheck.engines.mujoco.studies.ladder``, climbed by ``crosscheck.studies.ladder``):
MuJoCo-equivalent (eps, xi), causes, the study's relabelling, IC2, and ``crosscheck explain``."""

import json
import math

import mujoco
import numpy as np
import pytest

from crosscheck import engines
from crosscheck.cli import main
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.mujoco.law import impedance
from crosscheck.engines.mujoco.model import START_GAP, build_model, initial_state
from crosscheck.engines.mujoco.options import Options
from crosscheck.engines.mujoco.studies import kelvin_voigt as KV
from crosscheck.engines.mujoco.studies import ladder as rungs_of_mujoco
from crosscheck.engines.spec import LADDER_CAUSES
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.studies import ladder as L
from crosscheck.studies.agreement import comparison_labels
from crosscheck.theory.paper import FIG20_INITIAL_CONDITIONS
from crosscheck.theory.slipping import slip_until_event
from crosscheck.tolerances import CLOSED_FORM, EVENT_TIME, LADDER_QUOTED_TIME

IC2 = SlipState(**FIG20_INITIAL_CONDITIONS[1])
#: A start of the quick report's (theta, Theta) map at which the rigid rod jams at A and at C, MuJoCo sticks.
STICKS = SlipState(theta=1.175, varphi=-1.9, Theta=0.25, Psi=0.0, eta=1.0)

#: MuJoCo's rungs in order (rung k is RUNGS[k - 1]): the theory, its declared models, MuJoCo itself.
RUNGS = ("tip", "capsule", "compliant", "spring_law", "mujoco_law", "engine")


def ladder(state, mu, **kw):
    """MuJoCo's declared ladder from ``state``, with its rungs by name."""
    ld = L.run_ladder("mujoco", state, mu, **kw)
    assert [r.name for r in ld.rungs] == list(RUNGS) and [r.cause for r in ld.rungs[1:]] == list(LADDER_CAUSES[:5])
    return ld, {r.name: r for r in ld.rungs}


@pytest.fixture(scope="module")
def ic2():
    return ladder(IC2, 1.4)


def test_mujoco_equivalent_matches_mujocos_own_normal_row():
    """(eps, xi) give the Kelvin-Voigt gap MuJoCo's stiffness and damping: checked against MuJoCo's efc_KBIP, efc_aref and J M^-1 J^T."""
    alpha, opts = 3.0, Options()
    m = KV.mujoco_equivalent(IC2, alpha, timeconst=opts.timeconst, dampratio=opts.dampratio, solimp=opts.solimp)
    rod = Rod.scaled(alpha)
    model = build_model(rod, 0.0, opts)
    data = mujoco.MjData(model)
    mujoco.mj_setState(
        model, data, initial_state(model, rod, IC2, opts.radius, data=data), mujoco.mjtState.mjSTATE_FULLPHYSICS
    )
    vel = -0.3  # the gap closing: a damping term of either sign would show
    data.qpos[2] -= m.penetration + START_GAP * rod.length  # C sinks from its start to the operating penetration
    data.qvel[:] = 0.0
    data.qvel[2] = vel
    mujoco.mj_forward(model, data)
    pos, v = data.efc_pos[0], data.efc_vel[0]
    assert CLOSED_FORM.ok(pos, -m.penetration) and CLOSED_FORM.ok(v, vel)
    K, B, d, _ = data.efc_KBIP[0]
    assert CLOSED_FORM.ok(K, m.K) and CLOSED_FORM.ok(B, m.B) and CLOSED_FORM.ok(d, m.d)
    # the normal Delassus entry is the frictionless eq. p, 1 + alpha cos^2 theta, at C as at A
    J = data.efc_J.reshape(data.nefc, model.nv)[0].copy()
    x = np.zeros((1, model.nv))
    mujoco.mj_solveM(model, data, x, J[None, :])
    assert CLOSED_FORM.ok(J @ x[0], m.A_nn) and CLOSED_FORM.ok(m.A_nn, 1 + alpha * math.cos(IC2.theta) ** 2)
    # the impedance-weighted reference acceleration d aref = -d B v - d^2 K r is what the spring-damper's force does to the gap
    kv = -pos / m.eps**2 - (m.xi / m.eps) * v
    assert CLOSED_FORM.ok(m.A_nn * kv, d * data.efc_aref[0])
    # the operating penetration is MuJoCo's static balance of the normal row: (1 - d) |b| = d^2 K |r|
    assert CLOSED_FORM.ok((1 - d) * -m.b, d * d * K * m.penetration)
    # and both gaps ring at d / (dmax tau zeta) with damping ratio zeta
    assert CLOSED_FORM.ok(math.sqrt(m.A_nn) / m.eps, m.frequency) and CLOSED_FORM.ok(
        m.xi * math.sqrt(m.A_nn) / 2, opts.dampratio
    )


def test_impedance_is_mujocos_sigmoid_at_its_ends_and_midpoint():
    solimp = (0.9, 0.95, 0.001, 0.5, 2.0)
    d = impedance(solimp, [0.0, 0.0005, -0.0005, 0.001, 0.01])
    assert np.allclose(d, [0.9, 0.925, 0.925, 0.95, 0.95], rtol=0, atol=1e-15)


def test_ic2_rungs(ic2):
    """IC2: the paper's rod lifts off at t = 0.01654 with p = 0.0125; the rigid rod at C jams, the Kelvin-Voigt rod at C does not, nor does
    MuJoCo's law without its feed-forward (MuJoCo's friction on its spring-damper); MuJoCo's law and MuJoCo jam at once: cause feed-forward
    (the final stretch of matches starts at rung 5), after a detour through SLIP from rung 3 that the feed-forward ends.  (On MuJoCo
    itself a sixteen times thinner capsule still jams, impratio 0.01 lifts off: ``tests/test_interventions.py``.)"""
    ld, by = ic2
    one, two, six = by["tip"], by["capsule"], by["engine"]
    first = slip_until_event(IC2, 1.4, 3.0, t_max=2.0)
    assert one.outcome == Outcome.LIFTOFF and LADDER_QUOTED_TIME.ok(one.time, 0.01654) and abs(first.p - 0.0125) <= 5e-5
    assert EVENT_TIME.ok(one.time, first.time)
    # geometry by construction: the same rigid rod at r = 0 lifts off like rung 1, at MuJoCo's r = 0.01 it jams
    from crosscheck.theory import capsule

    assert capsule.slip_until_event(IC2, 1.4, 3.0, radius=0.0, t_max=2.0).outcome == Outcome.LIFTOFF
    assert two.outcome == Outcome.JAM and two.time < one.time
    # rung 6 is MuJoCo's own label as the agreement study compares it: rerun over the study's whole horizon (2 + two windows)
    opts = Options()
    full = engines.get("mujoco").simulate(
        Rod.scaled(3.0), IC2, 1.4, horizon=2.0 + 2 * Thresholds().window_rows(opts.timestep) * opts.timestep
    )
    study_label = comparison_labels(
        np.array([int(full.outcome)]), np.array([full.event_time]), np.array([ld.until + ld.lag])
    )[0]
    assert six.label == Outcome(int(study_label)) == Outcome.JAM and six.time == full.event_time == 0.0
    three, spring, law = by["compliant"], by["spring_law"], by["mujoco_law"]
    assert three.label == spring.label == Outcome.SLIP and law.label == Outcome.JAM
    assert ld.disagree and ld.cause == "feed-forward" and ld.first_change == 2 and not ld.missing
    assert ld.detour == (3, 5) and ld.detour_ended_by == "feed-forward"


def test_every_rung_starts_at_the_slip_speed_of_the_capsule_point():
    """The models in between start where MuJoCo starts: the slip speed of C (A's for rung 1), whatever their contact law."""
    rod, opts, th = Rod.scaled(3.0), Options(), Thresholds()
    runs = [
        getattr(rungs_of_mujoco, name)(rod, IC2, 1.4, horizon=0.01, thresholds=th, options=opts)
        for name in ("compliant", "spring_law", "mujoco_law")
    ]
    eta_C = engines.get("mujoco").simulate(rod, IC2, 1.4, horizon=0.01).record.eta[0]
    assert abs(eta_C - IC2.eta) > 1e-3  # C's slip differs from A's: the comparison is not empty
    assert all(abs(r.record.eta[0] - eta_C) < 1e-9 for r in runs)


def test_every_rung_is_relabelled_by_the_studys_comparison_time():
    """At STICKS the rigid rod jams at t ~ 0.002: the comparison ends at that time + 2 tau; the compliant rod's later stick counts as SLIP."""
    ld, by = ladder(STICKS, 1.4)
    end = ld.until + ld.lag
    assert by["tip"].outcome == Outcome.JAM and ld.lag == pytest.approx(2 * Options().timeconst)
    for r in ld.rungs:
        assert r.ok
        assert r.label == (r.outcome if r.outcome == Outcome.SLIP or r.time <= end else Outcome.SLIP)
    # the Kelvin-Voigt rod and MuJoCo's law without its feed-forward both stick after the comparison (their springs build the
    # force over the time constant); MuJoCo sticks within it, and so does its law in continuous time: "feed-forward"
    for name in ("compliant", "spring_law"):
        r = by[name]
        assert r.outcome == Outcome.STICK and r.time > end and r.label == Outcome.SLIP
    assert by["engine"].label == by["mujoco_law"].label == Outcome.STICK
    assert ld.cause == "feed-forward" and ld.first_change == 3 and ld.detour == (3, 5)


def test_discretisation_by_construction():
    """A start MuJoCo gets right at its default timestep (it slips on, as every other rung) but sticks at dt = 0.02: "discretisation"."""
    s, mu = (
        SlipState(
            theta=0.8630037871702823,
            varphi=-0.4238407591851616,
            Theta=-0.7116807745607325,
            Psi=1.3459483414117317,
            eta=0.7612966136188739,
        ),
        1.2313181877396664,
    )
    fine, by = ladder(s, mu)
    assert by["tip"].label == by["engine"].label == Outcome.SLIP and fine.cause == "agree" and not fine.disagree
    coarse, _ = ladder(s, mu, timestep=0.02)
    assert [r.label for r in coarse.rungs] == [Outcome.SLIP] * 5 + [Outcome.STICK]
    assert coarse.cause == "discretisation" and coarse.first_change == 6 and coarse.detour is None


def _rung(k, label, status="ok"):
    cause = None if k == 1 else LADDER_CAUSES[k - 2]
    return L.Rung(k, RUNGS[k - 1], cause, status, label, 0.0, label if status == "ok" else None)


J, S, T, L_ = Outcome.JAM, Outcome.SLIP, Outcome.STICK, Outcome.LIFTOFF


@pytest.mark.parametrize(
    "labels, reference, cause",
    [
        ((L_, J, J, J, J, J), J, "geometry"),
        ((L_, J, S, J, J, J), J, "friction law"),  # rung 3 undoes rung 2's match
        ((L_, J, S, S, J, J), J, "feed-forward"),  # and rung 4 keeps rung 3's detour
        ((S, S, T, T, T, T), T, "compliance"),
        ((S, S, T, S, S, T), T, "discretisation"),
        ((J, J, J, T, T, T), T, "friction law"),
        ((J, J, J, J, T, T), T, "feed-forward"),
        ((J, J, J, J, J, T), T, "discretisation"),
        ((J, J, J, J, J, J), T, "unexplained"),
        ((J, J, None, T, T, T), T, "undetermined"),
        ((J, T, None, J, J, J), T, "unexplained"),  # a given reference rung 6 misses
        ((J, J, J, None, T, T), T, "undetermined"),
        ((T, J, J, J, J, T), T, "agree"),
        ((Outcome.GB, J, J, J, J, T), T, "not rated"),
    ],
)
def test_cause_is_the_first_rung_of_the_final_stretch_matching_mujoco(labels, reference, cause):
    rungs = [_rung(k, lab, "ok" if lab is not None else "failed") for k, lab in enumerate(labels, start=1)]
    got = L._cause(rungs, reference)
    ld = L.EngineLadder("mujoco", STICKS, 1.4, 0.0, 0.0, tuple(rungs), reference, got)
    assert got == cause and ld.disagree == (cause not in ("agree", "not rated"))


def test_a_failing_rung_is_reported_and_blocks_the_cause_after_it(monkeypatch):
    """At STICKS the final stretch starts at rung 5 (feed-forward): with rung 4 unable to run, it might have extended
    the stretch, so the cause is undetermined."""

    def broken(*args, **kwargs):
        raise ImportError("the spring-damper law is not built")

    monkeypatch.setattr(rungs_of_mujoco, "spring_law", broken)
    ld, by = ladder(STICKS, 1.4)
    assert by["spring_law"].status == "failed" and "the spring-damper law is not built" in by["spring_law"].detail
    assert ld.missing == ["spring_law"] and ld.cause == "undetermined"


def test_disagreements_are_the_rated_starts_where_mujoco_differs():
    from crosscheck.report.sections.engine_ladder import _chosen

    a = np.array([Outcome.SLIP, Outcome.JAM, Outcome.GB, Outcome.LIFTOFF, Outcome.STICK], int)
    m = np.array([Outcome.SLIP, Outcome.STICK, Outcome.JAM, -2, Outcome.DIVERGED], int)
    chosen, n_all = _chosen({"map": {"analytic_outcome": a, "mujoco": m}}, "mujoco", None)
    assert [i for _, _, i in chosen] == [1, 4] and n_all == 2
    # an even spread when fewer are laddered: the first and the last
    many = {"map": {"analytic_outcome": np.full(7, int(Outcome.SLIP)), "mujoco": np.full(7, int(Outcome.JAM))}}
    assert [i for _, _, i in _chosen(many, "mujoco", 3)[0]] == [0, 3, 6]


def test_explain_prints_each_rung_and_the_cause(ic2, capsys):
    ld, by = ic2
    argv = [
        "explain",
        "--theta",
        "1.1031",
        "--varphi",
        "-1.9233",
        "--Theta",
        "0.9",
        "--Psi",
        "0",
        "--eta",
        "2",
        "--mu",
        "1.4",
    ]
    assert main(argv) == 0
    out = capsys.readouterr().out.splitlines()
    rungs = [line for line in out if line[:2] in ("1 ", "2 ", "3 ", "4 ", "5 ", "6 ")]
    assert [line.split()[1] for line in rungs] == list(RUNGS)
    assert rungs[0].endswith(f"LIFTOFF at t = {by['tip'].time:.6g}") and rungs[1].endswith(
        f"JAM at t = {by['capsule'].time:.6g}"
    )
    assert "cause: feed-forward (MuJoCo JAM, theory LIFTOFF)" in out
    # the cause checked on MuJoCo itself: neither the r/16 capsule nor solimp d = 0.01 alone, the two together
    assert out[-1].startswith("confirmation: feed-forward: confirmed as a pair with geometry")
    assert any(line.startswith("pair with    geometry") and line.endswith("LIFTOFF (removes it)") for line in out)
    assert main(argv + ["--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["confirmation"]["verdict"] == "confirmed as a pair" and got["confirmation"]["pair_with"] == ["geometry"]
    assert (
        got["cause"] == "feed-forward"
        and got["detour"] == [3, 5]
        and [r["label"] for r in got["rungs"]] == [r.label.name for r in ld.rungs]
    )


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--radius", "0.7"], "radius must be in [0, 0.5); got 0.7"),
        (
            ["--timestep", "0.1"],
            "timestep must be at most timeconst / 2 = 0.03 (MuJoCo's refsafe, with its default contact time constant "
            "timeconst = 0.06); got 0.1",
        ),
        (["--mu", "-1"], "mu must be in [0, 1000]; got -1.0"),
    ],
)
def test_explain_bad_input_is_one_line(extra, message, capsys):
    argv = [
        "explain",
        "--theta",
        "1.1031",
        "--varphi",
        "-1.9233",
        "--Theta",
        "0.9",
        "--Psi",
        "0",
        "--eta",
        "2",
        "--mu",
        "1.4",
    ] + extra
    assert main(argv) == 2
    assert capsys.readouterr().err == f"crosscheck: error: {message}\n"


def test_a_start_once_decided_by_rounding_now_has_one_outcome_at_every_last_bit():
    """A start of the maps whose MuJoCo outcome was decided by rounding (a JAM at t = 0.0027 or a LIFTOFF at 0.0186 as
    theta moved by one ulp, while the capsule started exactly on the plane): with the start START_GAP above the plane
    MuJoCo jams from it and from every start 1 or 2 ulp of theta away, so the probe finds no other outcome there."""
    s = SlipState(theta=0.9515625, varphi=-1.9, Theta=0.890625, Psi=0.0, eta=1.0)
    ld, by = ladder(s, 1.4, reference=Outcome.JAM)
    assert by["engine"].label == Outcome.JAM
    assert L.decided_by_rounding("mujoco", ld, Outcome.JAM)
    assert not any(L.decided_by_rounding("mujoco", ld, o) for o in Outcome if o != Outcome.JAM)


def test_the_cause_is_the_first_rung_of_the_final_stretch_of_matches():
    """A match the next rung undoes is not the cause; a failed rung just before the stretch leaves it undetermined."""
    from types import SimpleNamespace as R

    from crosscheck.studies.ladder import final_stretch_cause

    J, L, S = Outcome.JAM, Outcome.LIFTOFF, Outcome.SLIP
    ok = lambda lab, c: R(ok=True, label=lab, cause=c)  # noqa: E731
    cause = lambda rungs: final_stretch_cause(rungs, J, lambda r: r.cause)  # noqa: E731
    assert (
        cause([ok(J, "g"), ok(S, "c"), ok(J, "f"), ok(J, "d")]) == "f"
    )  # IC2's pattern: rung 2's jam is undone by rung 3
    assert cause([ok(J, "g"), ok(J, "c"), ok(J, "f"), ok(J, "d")]) == "g"  # monotone: the first match
    assert (
        cause([ok(S, "g"), ok(J, "c"), ok(L, "f"), ok(J, "d")]) == "d"
    )  # the law in continuous time does not jam, the steps do
    assert (
        cause([ok(J, "g"), ok(J, "c"), ok(J, "f"), ok(L, "d")]) == "unexplained"
    )  # the last rung differs (a given reference)
    assert cause([ok(S, "g"), R(ok=False, label=None, cause="c"), ok(J, "f"), ok(J, "d")]) == "undetermined"
    assert (
        cause([R(ok=False, label=None, cause="g"), ok(S, "c"), ok(J, "f"), ok(J, "d")]) == "f"
    )  # the failure is before a rung that differs


@pytest.mark.parametrize(
    "labels, reference, want",
    [
        ((J, J, S, S, T, T), T, (2, 4)),  # the spring's slip, ended by the feed-forward's stick
        ((L_, J, S, J, J, J), J, (2, 3)),
        ((J, J, J, T, T, T), T, None),  # monotone
        ((J, T, J, T), T, None),  # back and forth between the theory's and the engine's: no third outcome
        ((J, S, S, S), T, (1, None)),  # never back
        ((J, None, S, None, T), T, (2, 4)),  # rungs that did not run are passed over
    ],
)
def test_a_detour_is_a_stretch_of_rungs_on_neither_the_theorys_nor_the_engines_outcome(labels, reference, want):
    from crosscheck.studies.ladder import detour

    assert detour(labels, reference) == want
