"""compare matches one grid written two ways and says what its agreement does not cover (unmatched runs, horizons)."""

from __future__ import annotations

import pytest

from crosscheck.cli import main
from crosscheck.sweeps.store_diff import compare_stores

HEAD = '[sweep]\nengine = "analytic"\nhorizon = {h}\nchunk = 5\n'
TAIL = "varphi = -1.3\nTheta = [0.0, 0.45]\nPsi = 0.2\neta = 0.8\n[parameters]\nmu = 0.7\n"


def _store(tmp_path, name: str, theta: str, horizon: float):
    spec = tmp_path / f"{name}.toml"
    spec.write_text(HEAD.format(h=horizon) + f"[states]\ntheta = {theta}\n" + TAIL)
    assert main(["sweep", str(spec), "--out", str(tmp_path / name), "--workers", "1", "--no-progress"]) == 0
    return tmp_path / name


def test_a_range_and_a_list_of_one_grid_match_every_run(tmp_path):
    # numpy.linspace(0.3, 1.2, 7) holds 0.44999999999999996 and 0.6000000000000001, the list 0.45 and 0.6
    a = _store(tmp_path, "range", "{start = 0.3, stop = 1.2, num = 7}", 0.3)
    b = _store(tmp_path, "list", "[0.3, 0.45, 0.6, 0.75, 0.9, 1.05, 1.2]", 0.3)
    c, _ = compare_stores(a, b)
    assert (c.n, c.agreement, c.caveats) == (14, 1.0, ())


def test_unmatched_runs_and_unequal_or_short_horizons_are_caveats(tmp_path, capsys):
    a = _store(tmp_path, "long", "[0.5, 0.8, 1.1]", 0.3)
    b = _store(tmp_path, "short", "[0.5, 0.8, 1.15]", 0.03)
    c, _ = compare_stores(a, b)
    assert c.n == 4
    assert c.caveats[0].startswith("2 runs of") and "have no run with the same inputs" in c.caveats[0]
    assert c.caveats[1].startswith("the horizons differ (0.3 against 0.03)")
    assert c.caveats[2].startswith("a horizon (0.03) is shorter than the classifier's window (0.05)")
    assert main(["compare", str(a), str(b)]) == 0
    printed = capsys.readouterr().out
    assert [line for line in printed.splitlines() if line.startswith("caveat: ")] == [f"caveat: {x}" for x in c.caveats]
    assert c.as_dict()["caveats"] == list(c.caveats)


@pytest.mark.parametrize("horizon", [0.3])
def test_equal_long_horizons_have_no_caveat(tmp_path, horizon):
    a = _store(tmp_path, "a", "[0.5, 0.8]", horizon)
    b = _store(tmp_path, "b", "[0.5, 0.8]", horizon)
    assert compare_stores(a, b)[0].caveats == ()
