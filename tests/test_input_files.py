"""A states file's numbers follow the command line's rule (crosscheck.cli.options): ASCII digits, no underscores."""

from __future__ import annotations

import pytest

from crosscheck.cli import main

SPEC = '[sweep]\nengine = "analytic"\nhorizon = 0.5\n[states]\nfile = "states.csv"\n[parameters]\nmu = 0.5\n'


@pytest.mark.parametrize(
    "cell", ["\u0661", "1_0", "\uff11", "\u00b2"], ids=["arabic-indic", "underscore", "full-width", "superscript"]
)
def test_a_states_cell_in_other_digits_is_named(tmp_path, capsys, cell):
    (tmp_path / "states.csv").write_text(f"theta,varphi,Theta,Psi,eta\n1.0,-1.5,0,0,{cell}\n", encoding="utf-8")
    (tmp_path / "spec.toml").write_text(SPEC)
    assert main(["sweep", str(tmp_path / "spec.toml"), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == f"crosscheck: error: states.file row 1 eta must be a number; got {cell!r}\n"
    assert not (tmp_path / "o").exists()
