"""The interventions' summary (``crosscheck.studies.interventions.summarise``): every tally adds up over the starts.

Over seeded random sets of laddered disagreements (causes named or not, interventions that remove them at some step
or none, joint rows, the ladder's overdetermined pairs, p minima and boundary distances), each count of the summary is
the number of starts with a property read off the start alone, and the counts split the same starts in several ways
that must agree.  The cases of each tally one by one are in ``test_interventions.py``.  And the theory each
intervention is judged against is the comparison's, cut at the study's horizon (the last test).
"""

from __future__ import annotations

import numpy as np
import pytest

from crosscheck import SlipState
from crosscheck.engines.classifier import Thresholds
from crosscheck.engines.spec import LADDER_CAUSES
from crosscheck.studies.interventions import intervene, summarise

#: Causes the random starts draw from: three of the ladder's and one it does not attribute.
CAUSES = ("geometry", "compliance", "friction law", "unexplained")
DISTANCES = (0.01, 0.03, 0.3, "inf", None)


def _random_start(rng: np.random.Generator) -> dict:
    cause = str(rng.choice(CAUSES))
    causes = {}
    for c in CAUSES[:3]:
        if rng.random() < 0.75:  # a cause the engine declares interventions for
            causes[c] = [
                {"text": f"{c} step {i}", "removes": bool(rng.random() < 0.3)} for i in range(int(rng.integers(1, 4)))
            ]
    iv = {"theory": "SLIP", "causes": causes, "theory_p_min": float(rng.uniform(0.0, 0.5))}
    if rng.random() < 0.4:
        iv["joint"] = [{"with": c, "removes": bool(rng.random() < 0.5)} for c in CAUSES[1:3]]
    if cause == "geometry" and rng.random() < 0.5:
        iv["without_offset"] = {"also": str(rng.choice(CAUSES[1:3]))}
    return {"cause": cause, "interventions": iv, "boundary_distance": DISTANCES[int(rng.integers(len(DISTANCES)))]}


def _fixing(r: dict) -> set[str]:
    return {c for c, rows in r["interventions"]["causes"].items() if any(x["removes"] for x in rows)}


def _joint(r: dict) -> list[str]:
    return [x["with"] for x in r["interventions"].get("joint") or [] if x["removes"]]


def _both(r: dict) -> bool:
    """The ladder's overdetermined pair, removed by the two interventions together and by neither alone."""
    also = (r["interventions"].get("without_offset") or {}).get("also")
    return bool(also) and not _fixing(r) and also in _joint(r)


@pytest.mark.parametrize("seed", range(4))
def test_every_tally_is_a_count_of_starts_and_the_splits_agree(seed):
    rng = np.random.default_rng(seed)
    results = [_random_start(rng) for _ in range(120)]
    s = summarise(results)
    per = s["per_cause"]
    named = [r for r in results if r["cause"] in LADDER_CAUSES]
    assert (s["n"], sum(row["n"] for row in per.values())) == (len(results), len(results))
    assert s["attributed"] == len(named) and {c: row["n"] for c, row in per.items()} == {
        c: sum(r["cause"] == c for r in results) for c in per
    }
    assert s["removed_by_any"] == sum(bool(_fixing(r) or _joint(r)) for r in results)
    # confirmed: per cause, and split by p and by distance alike
    assert s["confirmed"] == sum(per[c]["confirmed"] for c in per if c in LADDER_CAUSES)
    assert s["confirmed_share"] == s["confirmed"] / s["attributed"]
    own = [r for r in named if r["cause"] in r["interventions"]["causes"]]
    assert s["confirmed"] == sum(r["cause"] in _fixing(r) or _both(r) for r in own)
    assert sum(sum(row["overdetermined"].values()) for row in per.values()) == sum(map(_both, own))
    assert sum(row["no_intervention"] for row in per.values()) == len(named) - len(own)
    band = Thresholds().jam_p_eff
    assert s["by_p"]["in_band"]["attributed"] == sum(r["interventions"]["theory_p_min"] <= band for r in named)
    for key in ("attributed", "confirmed"):
        assert s["by_p"]["in_band"][key] + s["by_p"]["above"][key] == s[key]
    probed = [r for r in named if r["boundary_distance"] is not None]
    assert s["unprobed"] == len(named) - len(probed)
    assert [d["distance"] for d in s["by_distance"]] == sorted({float(r["boundary_distance"]) for r in probed})
    assert sum(d["attributed"] for d in s["by_distance"]) == len(probed)
    assert sum(d["confirmed"] for d in s["by_distance"]) <= s["confirmed"]
    # removed by another cause instead: per cause that removes it, and once per start
    other = [r for r in results if _fixing(r) and r["cause"] not in _fixing(r)]
    for c, row in per.items():
        mine = [r for r in other if r["cause"] == c]
        assert row["by_other_starts"] == len(mine)
        assert row["by_other"] == {x: n for x in CAUSES if (n := sum(x in _fixing(r) for r in mine))}, c
    assert s["misattributed"] == sum(r["cause"] in LADDER_CAUSES for r in other)
    # jointly and none: starts no single intervention removes
    assert s["jointly"] == sum(sum(row["jointly"].values()) for row in per.values())
    assert s["jointly"] == sum(not _fixing(r) and bool(_joint(r)) and not _both(r) for r in results)
    assert sum(row["none"] for row in per.values()) == sum(not _fixing(r) and not _joint(r) for r in results)
    # what each of a cause's own interventions removes, out of the starts that tried it
    for c, row in per.items():
        rows = [x for r in results if r["cause"] == c for x in r["interventions"]["causes"].get(c) or []]
        assert row["tried"] == {t: sum(x["text"] == t for x in rows) for t in {x["text"] for x in rows}}
        assert row["by_intervention"] == {t: sum(x["removes"] for x in rows if x["text"] == t) for t in row["tried"]}
    pairs = s["pairs"]
    assert (
        pairs["predicted"]
        == sum(bool(r["interventions"].get("without_offset", {}).get("also")) for r in named)
        == sum(v for k, v in pairs.items() if k != "predicted")
    )


def test_the_theory_an_intervention_is_judged_against_is_cut_at_the_horizon():
    """The theory's run is the comparison's: cut at the study's horizon, as the engine runs are, not run on to its own
    event.  The start slips to its exit from the paper's chart at t = 0.788 (``tests/test_interventions.py``)."""
    state, mu = SlipState(theta=1.0, varphi=-1.9, Theta=0.0, Psi=0.875, eta=1.0), 0.875
    whole = intervene("bullet", state, mu, causes=[])
    cut = intervene("bullet", state, mu, horizon=0.5, causes=[])
    assert whole["theory"] == cut["theory"] == "SLIP" and 0.78 < whole["theory_time"] < 0.8
    assert cut["theory_time"] == 0.5 and cut["theory_eta_min"] > whole["theory_eta_min"]


def test_a_start_whose_least_p_is_exactly_the_band_edge_is_in_the_band():
    """``by_p``'s band is eq. p <= p_band, its edge included (and a start without a p minimum is above it)."""
    band = Thresholds().jam_p_eff
    starts = [
        {
            "cause": "geometry",
            "interventions": {"theory": "SLIP", "causes": {"geometry": [{"text": "g", "removes": r}]}},
        }
        for r in (True, False, True)
    ]
    starts[0]["interventions"]["theory_p_min"] = band
    starts[1]["interventions"]["theory_p_min"] = float(np.nextafter(band, 1.0))
    by_p = summarise(starts)["by_p"]
    assert by_p["in_band"] == {"attributed": 1, "confirmed": 1} and by_p["above"] == {"attributed": 2, "confirmed": 1}
