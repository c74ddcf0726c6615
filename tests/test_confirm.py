"""A ladder's cause confirmed on the engine for one start (``crosscheck.studies.confirm``): MuJoCo at the paper's
IC2."""

from __future__ import annotations

import pytest

from crosscheck.state import SlipState
from crosscheck.studies.confirm import VERDICTS, confirm, strongest

#: The paper's IC2 (Fig. 20): the theory lifts off at t = 0.01654; MuJoCo at its defaults jams at once.
IC2 = SlipState(theta=1.1031, varphi=-1.9233, Theta=0.9, Psi=0.0, eta=2.0)


def test_mujoco_at_ic2_confirms_feed_forward_only_as_a_pair_with_geometry():
    """Neither a capsule of radius r/16 nor solimp d = 0.01 on every row removes MuJoCo's jam at IC2 alone; together
    they give the theory's lift-off: the disagreement is overdetermined, and explain must say so."""
    c = confirm("mujoco", IC2, 1.4, cause="feed-forward", reference="JAM")
    assert c["theory"] == "LIFTOFF"
    assert c["verdict"] == "confirmed as a pair" and c["pair_with"] == ["geometry"]
    assert "confirmed as a pair with geometry" in c["text"]
    assert not any(r["removes"] for r in c["singles"]["feed-forward"] + c["singles"]["geometry"])
    pair = next(p for p in c["pairs"] if p["with"] == "geometry" and p["removes"])
    assert pair["options"]["radius"] == pytest.approx(0.01 / 16) and pair["label"] == "LIFTOFF"


def test_a_start_without_a_disagreement_has_nothing_to_confirm_and_strongest_keeps_each_familys_last():
    c = confirm("mujoco", IC2, 1.4, cause="agree")
    assert c["verdict"] == "no disagreement" and c["verdict"] in VERDICTS and not c["singles"]
    rows = [{"text": "a1", "family": "a"}, {"text": "b1", "family": "b"}, {"text": "a2", "family": "a"}]
    assert [r["text"] for r in strongest(rows)] == ["a2", "b1"]
