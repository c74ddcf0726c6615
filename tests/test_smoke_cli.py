"""The CLI's error messages are part of the interface: one line, naming the parameter and range."""

import json

import pytest

from crosscheck.cli import main


@pytest.mark.parametrize(
    "argv, message",
    [
        (["critical", "--mu", "-1"], "mu must be in [0, 1000]; got -1.0"),
        (["critical", "--mu", "nan"], "mu must be in [0, 1000]; got nan"),
        (["critical", "--mu", "1", "--alpha", "0"], "alpha must be in [0.001, 1000]; got 0.0"),
        (["critical"], "the following arguments are required: --mu (--mu: friction coefficient, in [0, 1000])"),
        (["critical", "--mu", "abc"], "mu must be a number in [0, 1000]; got 'abc'"),
        (
            ["classify", "--theta", "2", "--varphi", "-1", "--Theta", "0", "--Psi", "0", "--mu", "1"],
            "theta must be in (0, pi/2); got 2.0",
        ),
        (
            ["classify", "--theta", "1", "--varphi", "0.5", "--Theta", "0", "--Psi", "0", "--mu", "1"],
            "varphi must be in (-pi, 0]; got 0.5",
        ),
        (
            ["classify", "--theta", "1", "--varphi", "-1", "--Psi", "0", "--mu", "1"],
            "the following arguments are required: --Theta (--Theta: scaled polar rate theta_dot / omega, in [-100, 100])",
        ),
    ],
)
def test_bad_arguments_exit_nonzero_with_one_line(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == f"crosscheck: error: {message}\n"


def test_critical_json_matches_api(capsys):
    from crosscheck import critical_values

    assert main(["critical", "--mu", "1.4", "--alpha", "3", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    want = critical_values(1.4, 3).as_dict()
    assert got == pytest.approx(want, rel=0, abs=0)


def test_critical_json_below_mu_P_reports_null(capsys):
    assert main(["critical", "--mu", "1.0", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["theta_1"] is None and got["Psi_2"] is None and got["mu_P"] == pytest.approx(4 / 3, abs=1e-15)


def test_classify_json(capsys):
    assert (
        main(
            [
                "classify",
                "--theta",
                "1.0",
                "--varphi",
                "-1.5707963267948966",
                "--Theta",
                "0",
                "--Psi",
                "0",
                "--mu",
                "1.4",
                "--json",
            ]
        )
        == 0
    )
    got = json.loads(capsys.readouterr().out)
    # theta = 1 lies in (theta_1, theta_2) = (0.9702, 1.2209) at varphi = -pi/2, so p < 0; b = -1 (rod at rest)
    assert got["b"] == -1.0 and got["p"] < 0 and got["mode"] == "INCONSISTENT"


def test_ci_runs_the_readme_test_command():
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    readme_lines = (root / "README.md").read_text().splitlines()
    test_command = readme_lines[1]
    assert "pytest" in test_command and "pytest" not in readme_lines[0]
    ci = (root / ".ci" / "run").read_text().splitlines()
    assert test_command in ci


def test_version_and_required_options_in_usage(capsys):
    from crosscheck import __version__

    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"crosscheck {__version__}\n"
    assert main(["slip", "--help"]) == 0
    usage = capsys.readouterr().out
    # required options are shown without brackets, optional ones with; --theta and --Theta have distinct metavars
    assert "--theta THETA --varphi VARPHI --Theta THETA_DOT" in " ".join(usage.split()) and "[--alpha ALPHA]" in usage


def test_only_section_into_a_new_directory_renders_that_section_alone(tmp_path, capsys):
    out = tmp_path / "new"
    assert main(["report", "--quick", "--only", "critical_angles", "--out", str(out), "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "FAILED" not in printed and "not run" not in printed
    md = (out / "report.md").read_text()
    assert "## Critical angles" in md and "## Region p < 0" not in md


def _readme_examples() -> list[str]:
    """The `crosscheck ...` lines of the README's ```sh blocks (the sweep block's run into a store aside: its own test)."""
    import re
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    lines = [ln for block in re.findall(r"```sh\n(.*?)```", readme, re.S) for ln in block.splitlines()]
    return [ln for ln in lines if ln.startswith("crosscheck ") and " sweep " not in f" {ln} "]


@pytest.mark.parametrize("line", _readme_examples(), ids=lambda s: " ".join(s.split()[:3]))
def test_every_readme_example_runs_as_written_and_prints_what_its_comment_says(line, tmp_path, monkeypatch, capsys):
    """Each example line of the README runs as it is (exit 0) and prints the event its comment promises."""
    import shlex

    command, _, comment = line.partition("#")
    monkeypatch.chdir(tmp_path)  # --plot files land here
    assert main(shlex.split(command)[1:]) == 0
    printed = capsys.readouterr().out
    words = comment.replace(",", " ").split()
    for outcome in ("SLIP", "JAM", "LIFTOFF"):
        if outcome in words:
            assert outcome in printed, (line, printed)
    import re

    shown = [float(x) for x in re.findall(r"-?\d+\.\d+(?:e[-+]?\d+)?", printed)]
    for number in (w for w in words if w.replace(".", "", 1).isdigit() and "." in w):
        half = 0.5 * 10.0 ** -len(number.split(".")[1])  # the comment's number is the printed one rounded
        assert any(abs(x - float(number)) <= half for x in shown), (line, number, printed)
