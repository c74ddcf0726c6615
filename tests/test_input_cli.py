"""Command-line inputs that need more than a table row: compare's --out (two real stores, a real read-only mount),
a valid IPv6 scheduler address, and the rule for how a number is written (crosscheck.cli.options)."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest
from conftest import tmpfs

from crosscheck import sweeps
from crosscheck.cli import main

SPEC = """
[sweep]
engine = "analytic"
horizon = 0.2
chunk = 4
[states]
theta = [0.5, 1.0]
varphi = -1.5707963267948966
Theta = 0.0
Psi = 0.0
eta = 1.0
[parameters]
mu = 0.5
"""


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    root = tmp_path_factory.mktemp("compare")
    (root / "spec.toml").write_text(SPEC)
    for name in ("a", "b"):
        sweeps.run(root / "spec.toml", root / name, workers=1, progress=False)
    return root


@pytest.fixture(scope="module")
def read_only(tmp_path_factory):
    """A real read-only tmpfs (skipped where this process cannot mount one)."""
    with tmpfs(tmp_path_factory.mktemp("ro"), "ro,size=64k") as mnt:
        yield mnt


def _one_line(capsys) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("crosscheck: error: out must be "), err
    return err


@pytest.mark.parametrize(
    "out",
    ["", "/proc/x/y", "FILE/sub", "n" * 300, "DIR/"],
    ids=["empty", "proc", "under-a-file", "too-long", "a-directory"],
)
def test_compare_out_is_checked_as_every_out(stores, out, capsys):
    out = out.replace("FILE", str(stores / "spec.toml")).replace("DIR", str(stores))
    if out.startswith("n"):
        out = str(stores / out)
    assert main(["compare", str(stores / "a"), str(stores / "b"), "--out", out]) == 2
    _one_line(capsys)


def test_compare_stores_whose_names_are_too_long(stores, capsys):
    assert main(["compare", str(stores / ("n" * 300)), str(stores / "b")]) == 2
    err = capsys.readouterr().err
    assert (
        err.count("\n") == 1
        and err.startswith("crosscheck: error: DIR_A must be a sweep store")
        and "File name too long" in err
    )


def test_compare_out_on_a_read_only_mount(stores, read_only, capsys):
    assert main(["compare", str(stores / "a"), str(stores / "b"), "--out", str(read_only / "c")]) == 2
    err = _one_line(capsys)
    assert str(read_only) in err and "Read-only file system" in err


def test_compare_writes_where_it_is_told(stores, capsys):
    assert main(["compare", str(stores / "a"), str(stores / "b"), "--out", str(stores / "sub" / "c")]) == 0
    assert (stores / "sub" / "c.json").is_file() and (stores / "sub" / "c-disagreeing.csv").is_file()
    assert not list((stores / "sub").glob(".*"))  # no temporary file left


def test_a_too_long_out_in_python_is_one_store_error(tmp_path):
    with pytest.raises(sweeps.StoreError, match="File name too long"):
        sweeps.run(
            sweeps.parse_spec(__import__("tomllib").loads(SPEC)), tmp_path / ("n" * 300), workers=1, progress=False
        )


@pytest.mark.parametrize(
    "address",
    ["tcp://[::1]:8786", "[::1]:8786", "tcp://127.0.0.1:8786", "localhost:8786", "tcp://scheduler.example.org:1"],
)
def test_scheduler_addresses_dask_takes_are_taken(address):
    from crosscheck.sweeps.runner import check_scheduler

    assert check_scheduler(address) == address


def test_an_ipv6_scheduler_is_reached():
    from crosscheck.sweeps.runner import check_reachable

    try:
        server = socket.create_server(("::1", 0), family=socket.AF_INET6)
    except OSError:
        pytest.skip("no IPv6 loopback here")
    with server:
        port = server.getsockname()[1]
        assert check_reachable(f"tcp://[::1]:{port}", timeout=2) == f"tcp://[::1]:{port}"
    with pytest.raises(
        ValueError,
        match=r"scheduler must be a reachable Dask scheduler; nothing accepts connections at 'tcp://\[::1\]:\d+'",
    ):
        check_reachable(f"tcp://[::1]:{port}", timeout=2)


@pytest.mark.parametrize("text", ["1.4", "+1.4", " 1.4", "14e-1", ".14e1", "1.40000000000000000000"])
def test_ascii_numbers_are_read_as_written(text, capsys):
    assert main(["critical", "--mu", text, "--alpha", "3"]) == 0
    assert "mu = 1.4" in capsys.readouterr().out.replace("mu=", "mu = ")


@pytest.mark.parametrize("text", ["\u0663", "\uff11.\uff14", "1_4", "\u00b2", "1" * 101])
def test_other_digits_underscores_and_long_text_are_refused_naming_the_option(text, capsys):
    assert main(["critical", "--mu", text, "--alpha", "3"]) == 2
    err = capsys.readouterr().err
    assert (
        err.startswith(
            "crosscheck: error: argument --mu: must be a number written with ASCII digits (sign, point, exponent; no underscores), "
            "at most 100 characters; got "
        )
        and err.count("\n") == 1
    )


def test_the_rule_is_documented_where_it_is_applied():
    from crosscheck.cli import options

    assert (
        "ASCII" in options.__doc__ and "underscores" in options.__doc__ and Path(options.__file__).name == "options.py"
    )
