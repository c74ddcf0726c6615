"""The table of bad inputs: every CLI command and public function, each with a value that must be refused.

``cli_cases(tmp)`` and ``api_cases()`` return ``(id, input, param)`` triples:
``input`` is an argv list (run by ``audit.judge_cli``) or a zero-argument
callable (``audit.judge_api``), ``param`` the parameter the refusal must name.
Each case is a valid call with one value replaced, so any answer other than a
clean refusal is the fault of that value.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np

# Values that are never a number of any of our parameters.
NOT_FINITE = ["nan", "inf", "-inf", "abc", "", "1e400", "-1e400", "1,5"]

# Valid starting points (the paper's Fig. 20 state IC2, alpha = 3, mu = 1.4) for each command.
STATE = {"theta": "1.1031", "varphi": "-1.9233", "Theta": "0.9", "Psi": "0", "eta": "2"}

# Values outside each parameter's range, beyond the non-numbers above (1e308: finite, but
# beyond where the computation means anything in double precision).
OUT_OF_RANGE = {
    "theta": ["0", "-0.1", "1.5708", "2", "1e308"],
    "varphi": ["0.1", "-3.1416", "-4", "1e308"],
    "Theta": ["1e308", "-1e308", "1e7"],
    "Psi": ["1e308", "-1e308", "1e7"],
    "eta": ["-1", "1e308", "1e7"],  # (1e-300 is a valid start: below the stick speed, a stuck tip)
    "mu": ["-0.1", "1e308", "1e7"],
    "alpha": ["0", "-1", "1e308", "1e-300"],
    "psi": ["1e308", "-1e308"],
}


def _argv(command: list[str], options: dict[str, str], replace: str, value: str) -> list[str]:
    argv = list(command)
    for k, v in options.items():
        argv += [f"--{k}", value if k == replace else v]
    return argv


def _number_cases(
    name: str, command: list[str], options: dict[str, str], extra: dict[str, list[str]], only=None
) -> list:
    cases = []
    for opt in only or options:
        param = opt.replace("-", "_")
        for v in NOT_FINITE + OUT_OF_RANGE.get(param, []) + extra.get(opt, []):
            cases.append((f"{name} --{opt}={v!r}", _argv(command, options, opt, v), param))
    return cases


def cli_cases(tmp: Path) -> list:
    """Every (id, argv, param) of the command line; ``tmp`` is a scratch directory for path cases."""
    tmp = Path(tmp)
    cases = []
    cases += _number_cases("critical", ["critical"], {"mu": "1.4", "alpha": "3"}, {})
    classify = {k: v for k, v in STATE.items() if k != "eta"}  # classify needs no slip speed
    cases += _number_cases("classify", ["classify"], {**classify, "mu": "1.4", "alpha": "3"}, {})
    cases += _number_cases(
        "gb",
        ["gb"],
        {"mu": "1.7", "alpha": "3", "Psi": "0", "eta": "2", "samples": "5"},
        {"samples": ["0", "-1", "2.5", "1e9", "1e3", "100001"]},
    )
    cases += _number_cases(
        "slip",
        ["slip"],
        {**STATE, "mu": "1.4", "alpha": "3", "psi": "0", "t-max": "1"},
        {"t-max": ["0", "-1", "1e308"]},
    )
    cases += _number_cases(
        "slip --continue",
        ["slip", "--continue"],
        {**STATE, "mu": "1.4", "t-max": "1", "restitution": "0"},
        {"restitution": ["-0.1", "1.5"]},
        only=["restitution"],
    )
    cases += _number_cases(
        "simulate",
        ["simulate", "--engine", "mujoco"],
        {**STATE, "mu": "1.4", "alpha": "3", "horizon": "0.05", "timestep": "3e-3"},
        {"horizon": ["0", "-1", "1e308", "1e5"], "timestep": ["0", "-1", "1e-300", "10", "5e-324"]},
    )
    # explain: every value is refused before any rung of the ladder runs
    cases += _number_cases(
        "explain",
        ["explain"],
        {**STATE, "mu": "1.4", "alpha": "3", "timestep": "3e-4", "radius": "0.01", "horizon": "2"},
        {
            "horizon": ["0", "-1", "1e308", "1e5"],
            "timestep": ["0", "-1", "1e-300", "0.1", "5e-324"],
            "radius": ["0", "-0.1", "0.5", "1"],
        },
    )
    cases.append(
        (
            "explain --timestep=0.03 past --horizon=0.01",
            _argv(["explain"], {**STATE, "mu": "1.4", "timestep": "0.03", "horizon": "0.01"}, "", ""),
            "timestep",
        )
    )
    # an engine's declared ladder (Drake's, Bullet's): a timestep past the horizon, as every engine's simulate refuses it
    for engine in ("drake_sap", "bullet"):
        cases += _number_cases(
            f"explain --engine {engine}",
            ["explain", "--engine", engine],
            {**STATE, "mu": "1.4", "timestep": "1e-3", "horizon": "2"},
            {"timestep": ["0", "-1", "2.5", "5"]},
            only=["timestep"],
        )
    cases.append(
        (
            "simulate --engine=nonexistent",
            _argv(["simulate", "--engine", "nonexistent"], {**STATE, "mu": "1.4"}, "", ""),
            "engine",
        )
    )
    for engine in ("mujoco", "pinocchio"):
        for v in ["0", "-1", "1e3", "2.5", "1e9", "abc", ""]:
            cases.append((f"validate {engine} --states={v!r}", ["validate", engine, "--states", v], "states"))
        for v in ["-1", "1.5", "abc", "1e30", ""]:
            cases.append(
                (f"validate {engine} --seed={v!r}", ["validate", engine, "--states", "1", "--seed", v], "seed")
            )
        cases.append((f"validate {engine} --checks=bogus", ["validate", engine, "--checks", "bogus"], "--checks"))
    cases.append(("validate bogus", ["validate", "bogus"], "engine"))
    cases.append(("engines mujoco (takes no argument)", ["engines", "mujoco"], "arguments"))
    cases.append(("engines --jsn", ["engines", "--jsn"], "arguments"))
    # report: a cheap section, so that a wrongly accepted input costs seconds
    quick = ["report", "--quick", "--only", "critical_angles", "--no-progress"]
    a_file = tmp / "a_file"
    a_file.write_text("x")
    unwritable = tmp / "unwritable"
    unwritable.mkdir(exist_ok=True)
    unwritable.chmod(0o500)
    # (root writes through permission bits: the unwritable directory is a case only for other users)
    for v in ["", str(a_file), "/proc/x", str(a_file / "sub")] + ([str(unwritable / "r")] if os.geteuid() != 0 else []):
        cases.append((f"report --out={v!r}", quick + ["--out", v], "out"))
    # a directory crosscheck did not write: refused, never emptied (tests/test_never_deletes.py checks every byte)
    users = tmp / "users_project"
    (users / "src").mkdir(parents=True, exist_ok=True)
    (users / "src" / "main.c").write_text("int main;")
    (users / "report.md").write_text("my notes")
    cases.append(("report --out=<a user's project>", quick + ["--out", str(users)], "out"))
    cases.append(("report --out=<a user's project> --fresh", quick + ["--out", str(users), "--fresh"], "out"))
    cases.append(
        ("report --beside-files --out=<holding report.md>", quick + ["--out", str(users), "--beside-files"], "out")
    )
    import crosscheck

    package = str(Path(crosscheck.__file__).parent / "report")
    cases.append(("report --out=<the package's report/ source>", quick + ["--out", package, "--fresh"], "out"))
    for v in ["-1", "1.5", "abc", "", "1e30", "99999999999999999999"]:
        cases.append((f"report --seed={v!r}", quick + ["--out", str(tmp / "r_seed"), "--seed", v], "seed"))
    for v in ["0", "-1", "2000", "abc", "1.5"]:
        cases.append((f"report --workers={v!r}", quick + ["--out", str(tmp / "r_workers"), "--workers", v], "workers"))
    cases.append(
        ("report --only=bogus", ["report", "--quick", "--only", "bogus", "--out", str(tmp / "r_only")], "--only")
    )
    cases.append(
        ("report --from-results (empty dir)", ["report", "--from-results", "--out", str(tmp / "empty_report")], "out")
    )
    cases.append(
        ("report --scheduler=bogus", quick + ["--out", str(tmp / "r_sched"), "--scheduler", "bogus"], "scheduler")
    )
    # sweep: the spec file and its contents
    good = {
        "sweep": 'engine = "analytic"\nhorizon = 0.5\nseed = 0\nchunk = 4',
        "states": "theta = 1.0\nvarphi = -1.5707963267948966\nTheta = 0.0\nPsi = 0.0\neta = 1.0",
        "parameters": "mu = 0.5\nalpha = 3.0",
    }

    def spec(name: str, **tables) -> str:
        path = tmp / f"{name}.toml"
        doc = {**good, **tables}
        path.write_text("\n".join(f"[{k}]\n{v}" for k, v in doc.items() if v is not None) + "\n")
        return str(path)

    sweep_out = str(tmp / "sweep_out")
    too_long = str(tmp / ("n" * 300))
    cases.append(("sweep missing spec", ["sweep", str(tmp / "missing.toml"), "--out", sweep_out], "spec"))
    cases.append(("sweep spec is a directory", ["sweep", str(tmp), "--out", sweep_out], "spec"))
    (tmp / "broken.toml").write_text("[sweep\nengine = ")
    cases.append(("sweep malformed TOML", ["sweep", str(tmp / "broken.toml"), "--out", sweep_out], "spec"))
    bad_specs = {
        "engine": ("sweep", 'engine = "bogus"\nhorizon = 0.5\nseed = 0\nchunk = 4'),
        "horizon": ("sweep", 'engine = "analytic"\nhorizon = -1\nseed = 0\nchunk = 4'),
        "chunk": ("sweep", 'engine = "analytic"\nhorizon = 0.5\nseed = 0\nchunk = 0'),
        "seed": ("sweep", 'engine = "analytic"\nhorizon = 0.5\nseed = -3\nchunk = 4'),
        "theta": ("states", "theta = 2.0\nvarphi = -1.5\nTheta = 0.0\nPsi = 0.0\neta = 1.0"),
        "varphi": ("states", "theta = 1.0\nvarphi = 0.5\nTheta = 0.0\nPsi = 0.0\neta = 1.0"),
        "eta": ("states", "theta = 1.0\nvarphi = -1.5\nTheta = 0.0\nPsi = 0.0\neta = -1.0"),
        "Theta": ("states", "theta = 1.0\nvarphi = -1.5\nTheta = nan\nPsi = 0.0\neta = 1.0"),
        "Psi": ("states", "theta = 1.0\nvarphi = -1.5\nTheta = 0.0\nPsi = inf\neta = 1.0"),
        "num": (
            "states",
            "theta = {start = 0.4, stop = 1.2, num = 0}\nvarphi = -1.5\nTheta = 0.0\nPsi = 0.0\neta = 1.0",
        ),
        "mu": ("parameters", "mu = -0.5\nalpha = 3.0"),
        "alpha": ("parameters", "mu = 0.5\nalpha = 0.0"),
    }
    for param, (table, text) in bad_specs.items():
        cases.append(
            (f"sweep spec {param}", ["sweep", spec(f"bad_{param}", **{table: text}), "--out", sweep_out], param)
        )
    cases.append(("sweep --workers=0", ["sweep", spec("ok"), "--out", sweep_out, "--workers", "0"], "workers"))
    cases.append(("sweep --out=''", ["sweep", spec("ok"), "--out", ""], "out"))
    cases.append(("sweep --out=a file", ["sweep", spec("ok"), "--out", str(a_file)], "out"))
    for extra in ([], ["--fresh"]):
        cases.append(
            (f"sweep --out=<a user's project> {extra}", ["sweep", spec("ok"), "--out", str(users), *extra], "out")
        )
    # simulate's output files: checked before the run, never one written over another
    sim = _argv(["simulate", "--engine", "pinocchio"], {**STATE, "mu": "0.7", "horizon": "0.04"}, "", "")
    for outputs, param in [
        (["--plot", str(tmp / "k.svg"), "--csv", str(tmp / "k.svg")], "csv"),
        (["--plot", str(tmp / "k.pdf"), "--csv", str(tmp / "k_theory.csv")], "csv"),
        (["--plot", str(tmp / "k.gif")], "plot"),
        (["--plot", str(tmp / "k.html")], "plot"),
        (["--plot", ""], "plot"),
        (["--csv", "  "], "csv"),
        (["--csv", str(tmp)], "csv"),
        (["--plot", str(tmp)], "plot"),
        (["--plot", "/proc/self/k.svg"], "plot"),
        (["--csv", "/sys/k.csv"], "csv"),
        (["--csv", str(a_file / "k.csv")], "csv"),
        (["--plot", str(a_file / "k.png")], "plot"),
        (["--csv", too_long], "csv"),
    ]:
        cases.append((f"simulate {' '.join(outputs)[-40:]}", sim + outputs, param))
    # explain's --plot, checked before the ladder runs: at a horizon of 3000 the ladder would take minutes, longer
    # than the judge waits, so a clean refusal is one that spent no simulation time
    expl = _argv(["explain"], {**STATE, "mu": "1.4", "horizon": "3000"}, "", "")
    for plot in ["", "  ", str(tmp), "/proc/self/k.png", str(a_file / "k.png"), str(tmp / "k.gif"), too_long]:
        cases.append((f"explain --plot={plot[-30:]!r}", expl + ["--plot", plot], "plot"))
    # round 3 of the audit, with values of its own: starts within THETA_MARGIN of the vertical or the plane, the
    # compliant rod's timestep floor, MuJoCo's timestep past the horizon or past timeconst / 2, digits of other scripts
    for engine in ("compliant", "mujoco_law", "pinocchio"):
        for v in ["1.5707958", "1.5707963267948961", "3e-7"]:
            argv = _argv(["simulate", "--engine", engine], {**STATE, "mu": "0.9", "horizon": "0.03"}, "theta", v)
            cases.append((f"simulate --engine {engine} --theta={v!r}", argv, "theta"))
    cases.append(
        ("explain --theta=1.57079631", _argv(["explain"], {**STATE, "mu": "0.9"}, "theta", "1.57079631"), "theta")
    )
    cases.append(("slip --theta=8e-7", _argv(["slip"], {**STATE, "mu": "0.9", "t-max": "1"}, "theta", "8e-7"), "theta"))
    for engine, horizon, timestep in [
        ("compliant", "4e-13", "4e-13"),
        ("compliant", "0.05", "1e-320"),
        ("mujoco", "0.3", "0.045"),
        ("mujoco_law", "0.4", "0.031"),
        ("mujoco", "0.003", "0.01"),
        ("mujoco_law", "0.001", "0.002"),
    ]:
        cases.append(
            (
                f"simulate --engine {engine} --horizon={horizon} --timestep={timestep}",
                _argv(
                    ["simulate", "--engine", engine],
                    {**STATE, "mu": "0.9", "horizon": horizon, "timestep": timestep},
                    "",
                    "",
                ),
                "timestep",
            )
        )
    cases.append(
        (
            "simulate --engine drake_continuous --alpha=650",
            _argv(["simulate", "--engine", "drake_continuous"], {**STATE, "mu": "0.9", "alpha": "650"}, "", ""),
            "alpha",
        )
    )
    for opt, v in [("Psi", "2_5"), ("eta", "\u0667"), ("Psi", "\uff12"), ("mu", "1\u06f7"), ("alpha", "3_0")]:
        v = v.encode().decode("unicode_escape")
        argv = ["gb", "--mu", "1.7", "--samples", "3"] + ([] if opt == "mu" else []) + [f"--{opt}", v]
        cases.append((f"gb --{opt}={v!r}", argv, opt))
    # spec files: integers beyond float range, and more runs than any sweep may list
    huge = "9" * 330
    for param, (table, text) in {
        "horizon": ("sweep", f'engine = "analytic"\nhorizon = {huge}\nchunk = 4'),
        "seed": ("sweep", f'engine = "analytic"\nhorizon = 0.5\nseed = -{huge}\nchunk = 4'),
        "chunk": ("sweep", f'engine = "analytic"\nhorizon = 0.5\nchunk = {huge}'),
        "theta": ("states", f"theta = [0.8, {huge}]\nvarphi = -1.5\nTheta = 0.0\nPsi = 0.0\neta = 1.0"),
        "num": (
            "states",
            f"theta = {{start = 0.4, stop = 1.2, num = {huge}}}\nvarphi = -1.5\nTheta = 0.0\nPsi = 0.0\neta = 1.0",
        ),
        "mu": ("parameters", f"mu = {{start = -{huge}, stop = 1.0, num = 3}}"),
        "runs": ("parameters", "mu = {start = 0.1, stop = 2.0, num = 4000000}\nalpha = [1.0, 2.0, 3.0]"),
    }.items():
        cases.append(
            (
                f"sweep spec {param} (round 3)",
                ["sweep", spec(f"huge_{param}", **{table: text}), "--out", sweep_out],
                param,
            )
        )
    cases.append(
        (
            "sweep spec mujoco horizon=7500 (a record no chunk holds)",
            ["sweep", spec("mujoco_long", sweep='engine = "mujoco"\nhorizon = 7500\nchunk = 2'), "--out", sweep_out],
            "horizon",
        )
    )
    cases.append(("compare missing stores", ["compare", str(tmp / "no_a"), str(tmp / "no_b")], "a"))
    cases.append(("compare non-store", ["compare", str(tmp), str(tmp)], "a"))
    # how a number is written: ASCII only (crosscheck.cli.options), and no longer than a number needs
    not_ascii = ["\u00b2", "\u0663", "\uff11.\uff14", "1_000", "9" * 5000]
    for v in not_ascii:
        cases.append(
            (f"sweep --workers={v[:8]!r}", ["sweep", spec("ok"), "--out", sweep_out, "--workers", v], "workers")
        )
        cases.append((f"report --seed={v[:8]!r}", quick + ["--out", str(tmp / "r_seed"), "--seed", v], "seed"))
        cases.append(
            (f"report --workers={v[:8]!r}", quick + ["--out", str(tmp / "r_workers"), "--workers", v], "workers")
        )
        cases.append((f"critical --mu={v[:8]!r}", ["critical", "--mu", v, "--alpha", "3"], "mu"))
        cases.append(
            (
                f"simulate --theta={v[:8]!r}",
                _argv(["simulate"], {**STATE, "mu": "1.4", "horizon": "0.05"}, "theta", v),
                "theta",
            )
        )
        cases.append(
            (
                f"simulate --horizon={v[:8]!r}",
                _argv(["simulate"], {**STATE, "mu": "1.4", "horizon": "0.05"}, "horizon", v),
                "horizon",
            )
        )
        cases.append((f"gb --samples={v[:8]!r}", ["gb", "--mu", "1.7", "--samples", v], "samples"))
        cases.append((f"validate mujoco --states={v[:8]!r}", ["validate", "mujoco", "--states", v], "states"))
        cases.append((f"validate mujoco --seed={v[:8]!r}", ["validate", "mujoco", "--seed", v], "seed"))
        cases.append(
            (f"slip --t-max={v[:8]!r}", _argv(["slip"], {**STATE, "mu": "1.4", "t-max": "1"}, "t-max", v), "t-max")
        )
        cases.append(
            (
                f"explain --timestep={v[:8]!r}",
                _argv(["explain"], {**STATE, "mu": "1.4", "timestep": "3e-4"}, "timestep", v),
                "timestep",
            )
        )
    # paths the file system refuses, and scheduler addresses crosscheck cannot use
    cases.append(("sweep --out=<300-character name>", ["sweep", spec("ok"), "--out", too_long], "out"))
    cases.append(("report --out=<300-character name>", quick + ["--out", too_long], "out"))
    cases.append(
        ("report --from-results --out=<300-character name>", ["report", "--from-results", "--out", too_long], "out")
    )
    for v in [
        "tls://127.0.0.1:1",
        "ucx://127.0.0.1:1",
        "ws://127.0.0.1:1",
        "tcp://127.0.0.1",
        "tcp://127.0.0.1:70000",
        "tcp://[::1]",
        "tcp://:8786",
    ]:
        cases.append(
            (f"sweep --scheduler={v!r}", ["sweep", spec("ok"), "--out", sweep_out, "--scheduler", v], "scheduler")
        )
        cases.append(
            (f"report --scheduler={v!r}", quick + ["--out", str(tmp / "r_sched"), "--scheduler", v], "scheduler")
        )
    cases.append(
        (
            "report --scheduler=nothing listening",
            quick + ["--out", str(tmp / "r_sched"), "--scheduler", "tcp://127.0.0.1:1"],
            "scheduler",
        )
    )
    # spec and states files: every value a chunk will use is checked before any chunk runs
    (tmp / "not_utf8.toml").write_bytes(b'[sweep]\nengine = "analytic" # \xe9\n')
    cases.append(("sweep spec not UTF-8", ["sweep", str(tmp / "not_utf8.toml"), "--out", sweep_out], "spec"))
    fifo = tmp / "fifo.toml"
    if not fifo.exists():
        os.mkfifo(fifo)
    cases.append(("sweep spec is a FIFO", ["sweep", str(fifo), "--out", sweep_out], "spec"))
    cases.append(
        (
            "sweep spec options.timestep=[[1e-3]]",
            [
                "sweep",
                spec(
                    "nested_option", sweep='engine = "mujoco"\nhorizon = 0.05\nchunk = 4', options="timestep = [[1e-3]]"
                ),
                "--out",
                sweep_out,
            ],
            "timestep",
        )
    )
    header = "theta,varphi,Theta,Psi,eta\n"
    state_files = {
        "header only": header.encode(),
        "empty": b"",
        "ragged": (header + "1.0,-1.5,0,0\n").encode(),
        "semicolons": b"theta;varphi;Theta;Psi;eta\n1.0;-1.5;0;0;1\n",
        "latin-1": (header + "1.0,-1.5,0,0,1\xe9\n").encode("latin-1"),
        "binary": (header + "1.0,-1.5,0,0,1\0\n").encode(),
        "duplicated theta": b"theta,varphi,Theta,Psi,eta,theta\n1.0,-1.5,0,0,1,7\n",
        "unknown column": b"theta,varphi,Theta,Psi,eta,mu\n1.0,-1.5,0,0,1,0.5\n",
        "not a number": (header + "1.0,-1.5,0,0,one\n").encode(),
    }
    for i, (what, data) in enumerate(state_files.items()):
        (tmp / f"states_{i}.csv").write_bytes(data)
        cases.append(
            (
                f"sweep states.file {what}",
                ["sweep", spec(f"states_{i}", states=f'file = "states_{i}.csv"'), "--out", sweep_out],
                "file",
            )
        )
    for what, value in [
        ("/etc/passwd", '"/etc/passwd"'),
        ("a number", "5"),
        ("a list", '["a.csv"]'),
        ("a directory", '"."'),
        ("a FIFO", f'"{fifo.name}"'),
    ]:
        cases.append(
            (
                f"sweep states.file = {what}",
                ["sweep", spec(f"states_{what.replace('/', '_')}", states=f"file = {value}"), "--out", sweep_out],
                "file",
            )
        )
    # ids without the scratch directory's random name: pytest-xdist's workers must collect the same ids
    token = re.escape(tmp.name[-8:])  # (mkdtemp's random part)
    return [(re.sub(r"[^\s=]*" + token, "<tmp>", i), argv, param) for i, argv, param in cases]


def _simulate(engine, rod, state, key: str, value):
    """``engine.simulate`` of a short valid run at mu = 1.4 with ``key`` (mu or an option) set to ``value``."""
    kw = {"mu": 1.4, "horizon": 0.05, key: value}
    mu = kw.pop("mu")
    return engine.simulate(rod, state, mu, **kw)


def api_cases() -> list:
    """Every (id, call, param) of the Python API."""
    from crosscheck.coordinates import paper_to_qv
    from crosscheck.engines import classifier
    from crosscheck.engines.mujoco import engine as mujoco
    from crosscheck.engines.pinocchio import stepper as pinocchio
    from crosscheck.rod import Rod
    from crosscheck.state import SlipState
    from crosscheck.theory import analytic, critical
    from crosscheck.theory.corollary import corollary_states
    from crosscheck.theory.gb import det_K_zeros, gb_manifold
    from crosscheck.theory.impact import continuation as hybrid
    from crosscheck.theory.impact import darboux_keller as iwc
    from crosscheck.theory.slipping import slip_until_event

    ok_state = dict(theta=1.1031, varphi=-1.9233, Theta=0.9, Psi=0.0, eta=2.0)
    out_of_range = {
        "theta": [0.0, -0.1, 2.0],
        "varphi": [0.1, -4.0],
        "eta": [-1.0, 1e7],
        "Theta": [1e7],
        "Psi": [1e7],
        "mu": [-0.1, 1e7],
        "alpha": [0.0, -1.0, 1e-300, 1e7],
    }
    cases = []

    def add(name, fn, param):
        cases.append((name, fn, param))

    for k in ok_state:
        for v in [math.nan, math.inf, -math.inf, "abc", None]:
            add(f"SlipState({k}={v!r})", lambda k=k, v=v: SlipState(**{**ok_state, k: v}), k)
        for v in [1e308, -1e308] + out_of_range.get(k, []):
            # a state may hold any finite rate (a flow can reach it); a run may not start from one out of range
            add(
                f"slip_until_event(SlipState({k}={v!r}))",
                lambda k=k, v=v: slip_until_event(SlipState(**{**ok_state, k: v}), 1.4, 3.0),
                k,
            )
    for k, v in [
        ("theta", 2.0),
        ("varphi", 1e308),
        ("mu", -1.0),
        ("alpha", 0.0),
        ("mu", 1e308),
        ("alpha", 1e308),
        ("mu", math.nan),
    ]:
        add(
            f"analytic.p({k}={v!r})",
            lambda k=k, v=v: analytic.p(**{**dict(theta=1.0, varphi=-1.5, mu=1.0, alpha=3.0), k: v}),
            k,
        )
    for k, v in [("theta", 0.0), ("Psi", math.inf), ("Theta", math.nan), ("Psi", 1e308), ("Theta", -1e308)]:
        add(f"analytic.b({k}={v!r})", lambda k=k, v=v: analytic.b(**{**dict(Psi=0.0, Theta=0.5, theta=1.0), k: v}), k)
    for k, v in [("mu", -1.0), ("mu", math.nan), ("mu", 1e308), ("alpha", 0.0), ("alpha", 1e308), ("alpha", math.inf)]:
        add(
            f"critical_values({k}={v!r})",
            lambda k=k, v=v: critical.critical_values(**{**dict(mu=1.4, alpha=3.0), k: v}),
            k,
        )
    for k, v in [("mu", -1.0), ("Psi", 1e308), ("alpha", 0.0), ("Psi", math.nan)]:
        add(
            f"kinematic_case({k}={v!r})",
            lambda k=k, v=v: critical.kinematic_case(**{**dict(mu=1.4, Psi=0.5, alpha=3.0), k: v}),
            k,
        )
    for v in [0, -1, 1, 2.5, 10**9, "abc"]:
        add(f"gb_manifold(n={v!r})", lambda v=v: gb_manifold(1.7, 0.0, 3.0, n=v), "n")
    for k, v in [("mu", 1e308), ("Psi", 1e308), ("alpha", 1e308), ("mu", math.nan)]:
        add(f"gb_manifold({k}={v!r})", lambda k=k, v=v: gb_manifold(**{**dict(mu=1.7, Psi=0.0, alpha=3.0), k: v}), k)
    for v in [-1.0, math.nan, 1e308]:
        add(f"det_K_zeros(eta={v!r})", lambda v=v: det_K_zeros(gb_manifold(1.7, 0.0, 3.0)[0], v), "eta")
    for v in [0, -1, 2.5]:
        add(
            f"det_K_zeros(iterations={v!r})",
            lambda v=v: det_K_zeros(gb_manifold(1.7, 0.0, 3.0)[0], 1.0, iterations=v),
            "iterations",
        )
    s = SlipState(**ok_state)
    for k, v in [
        ("mu", -1.0),
        ("mu", 1e308),
        ("alpha", 0.0),
        ("t_max", 0.0),
        ("t_max", -1.0),
        ("t_max", math.nan),
        ("t_max", 1e308),
        ("s_max", 0.0),
        ("s_max", math.inf),
    ]:
        add(
            f"slip_until_event({k}={v!r})",
            lambda k=k, v=v: slip_until_event(s, **{**dict(mu=1.4, alpha=3.0, t_max=1.0), k: v}),
            k,
        )
    add("slip_until_event(state=dict)", lambda: slip_until_event(ok_state, 1.4, 3.0), "state")
    for k, v in [("mu", -1.0), ("alpha", 0.0), ("restitution", -0.1), ("restitution", 1.5), ("restitution", math.nan)]:
        add(f"iwc.impact({k}={v!r})", lambda k=k, v=v: iwc.impact(s, **{**dict(mu=1.4, alpha=3.0), k: v}), k)
    for k, v in [
        ("horizon", 0.0),
        ("horizon", math.inf),
        ("restitution", 2.0),
        ("max_impacts", -1),
        ("max_impacts", 2.5),
    ]:
        add(
            f"hybrid.run({k}={v!r})",
            lambda k=k, v=v: hybrid.run(s, **{**dict(mu=1.4, alpha=3.0, horizon=1.0), k: v}),
            k,
        )
    for k, v in [
        ("mass", 1e-200),
        ("inertia", 1e200),
        ("mass", 1e200),
        ("length", 1e200),
        ("mass", 0.0),
        ("gravity", -9.81),
        ("length", math.nan),
        ("inertia", math.inf),
    ]:
        add(f"Rod({k}={v!r}).alpha", lambda k=k, v=v: Rod(**{k: v}).alpha, k)
    add("Rod(mass=1e-200, inertia=1e200).alpha", lambda: Rod(mass=1e-200, inertia=1e200).alpha, "mass")
    add("Rod(mass=1e200, length=1e200).alpha", lambda: Rod(mass=1e200, length=1e200).alpha, "mass")
    add("Rod(mass=1e-50, inertia=1e50).alpha", lambda: Rod(mass=1e-50, inertia=1e50).alpha, "alpha")
    add("Rod(mass=1e50, length=1e50).alpha", lambda: Rod(mass=1e50, length=1e50).alpha, "alpha")
    rod = Rod.scaled(3.0)
    for k, v in [
        ("horizon", 0.0),
        ("horizon", 1e5),
        ("horizon", 1e308),
        ("horizon", math.nan),
        ("timestep", 0.0),
        ("timestep", 1e-300),
        ("radius", 5.0),
        ("radius", 1e308),
        ("radius", 0.0),
        ("radius", -0.01),
        ("timeconst", 0.0),
        ("dampratio", -1.0),
        ("solimp", (0.9, 0.95, 0.001, 0.5, -2.0)),
        ("solimp", (0.9, 0.95, 0.001, 1.5, 2.0)),
        ("solimp", (0.9, 0.95)),
        ("solver_tolerance", -1.0),
        ("bogus_option", 1.0),
        ("mu", -1.0),
        ("mu", 1e308),
    ]:
        add(f"mujoco.simulate({k}={v!r})", lambda k=k, v=v: _simulate(mujoco, rod, s, k, v), k)
    for k, v in [
        ("horizon", 0.0),
        ("horizon", 1e5),
        ("timestep", -1.0),
        ("solver", "bogus"),
        ("tolerance", 0.0),
        ("max_iterations", 0),
        ("max_iterations", 2.5),
        ("contact_gap", -1.0),
        ("ncp", "yes"),
    ]:
        add(f"pinocchio.simulate({k}={v!r})", lambda k=k, v=v: _simulate(pinocchio, rod, s, k, v), k)
    for k, v in [
        ("window", math.nan),
        ("window", -0.05),
        ("window_steps", 0),
        ("window_steps", 2.5),
        ("jam_force", -1.0),
        ("jam_ratio", 0.0),
        ("jam_p_eff", math.inf),
        ("lift_steps", 0),
        ("stick_speed", math.nan),
        ("diverged_speed", math.nan),
        ("diverged_speed", 0.0),
        ("rigid_stick_steps", -1.0),
    ]:
        add(f"Thresholds({k}={v!r})", lambda k=k, v=v: classifier.Thresholds(**{k: v}), k)
    for k, v in [("n", 0), ("n", -1), ("n", 2.5), ("mu", 1.0), ("mu", math.nan), ("horizon", 0.0)]:

        def call(k=k, v=v):
            kw = dict(mu=1.7, n=2, rng=np.random.default_rng(0))
            kw[k] = v
            return corollary_states(**kw)

        add(f"corollary_states({k}={v!r})", call, k)
    add("corollary_states(rng=0)", lambda: corollary_states(1.7, 2, 0), "rng")
    for k, v in [("theta", 2.0), ("eta", -1.0), ("Theta", math.nan), ("w", math.inf)]:
        add(f"paper_to_qv({k}={v!r})", lambda k=k, v=v: paper_to_qv(rod, **{**ok_state, k: v}), k)
    from crosscheck.engines import compliant
    from crosscheck.engines.mujoco import ode as mujoco_ode
    from crosscheck.theory import capsule

    for k, v in [
        ("eps", 0.0),
        ("eps", -1.0),
        ("eps", 1e-300),
        ("eps", 1e300),
        ("eps", math.nan),
        ("xi", -0.1),
        ("xi", 1e300),
        ("radius", 0.5),
        ("radius", -0.01),
        ("law", "bogus"),
        ("timestep", 0.0),
        ("rtol", 1e-300),
        ("horizon", 0.0),
        ("horizon", 1e308),
        ("mu", -1.0),
    ]:
        add(f"compliant.simulate({k}={v!r})", lambda k=k, v=v: _simulate(compliant, rod, s, k, v), k)
    for k, v in [
        ("gap", 0.01),
        ("gap", -1e308),
        ("gap_rate", math.inf),
        ("gap_rate", 1e308),
        ("stop_at", "bogus"),
        ("eps", 0.0),
    ]:
        add(
            f"compliant.integrate({k}={v!r})",
            lambda k=k, v=v: compliant.integrate(rod, s, 1.4, **{**dict(horizon=0.05, eps=1e-2, xi=1.0), k: v}),
            k,
        )
    for k, v in [
        ("radius", -0.01),
        ("radius", 0.5),
        ("radius", math.nan),
        ("mu", -1.0),
        ("alpha", 0.0),
        ("t_max", 0.0),
    ]:
        add(
            f"capsule.slip_until_event({k}={v!r})",
            lambda k=k, v=v: capsule.slip_until_event(s, **{**dict(mu=1.4, alpha=3.0, radius=0.01), k: v}),
            k,
        )
    for k, v in [
        ("horizon", 0.0),
        ("horizon", 1e5),
        ("radius", 0.0),
        ("radius", 0.7),
        ("timeconst", 0.0),
        ("solimp", (0.9, 0.95)),
        ("bogus_option", 1.0),
        ("mu", -1.0),
    ]:
        add(f"mujoco_ode.simulate({k}={v!r})", lambda k=k, v=v: _simulate(mujoco_ode, rod, s, k, v), k)
    from crosscheck.engines.mujoco.studies import kelvin_voigt
    from crosscheck.studies import ladder as declared

    # MuJoCo's declared ladder: its options refused before any rung runs, as the ladder's own arguments
    for k, v in [
        ("mu", -1.0),
        ("alpha", 0.0),
        ("horizon", 0.0),
        ("horizon", 1e5),
        ("timestep", 1e-300),
        ("radius", 0.7),
        ("timeconst", 0.0),
        ("solimp", (0.9, 0.95)),
        ("reference", 9),
        ("bogus_option", 1.0),
    ]:

        def call(k=k, v=v):
            kw = {"mu": 1.4, k: v}
            return declared.run_ladder("mujoco", s, kw.pop("mu"), **kw)

        add(f"studies.ladder.run_ladder('mujoco', {k}={v!r})", call, k)
    add(
        "studies.ladder.run_ladder('mujoco', timestep=0.03 past horizon=0.01)",
        lambda: declared.run_ladder("mujoco", s, 1.4, horizon=0.01, timestep=0.03),
        "timestep",
    )

    for k, v in [
        ("mu", -1.0),
        ("alpha", 0.0),
        ("horizon", 0.0),
        ("timestep", 5.0),
        ("timestep", 0.0),
        ("radius", 0.7),
        ("bogus_option", 1.0),
    ]:
        add(
            f"studies.ladder.run_ladder('drake_sap', {k}={v!r})",
            lambda k=k, v=v: declared.run_ladder("drake_sap", s, **{"mu": 1.4, "horizon": 2.0, k: v}),
            k,
        )
    for k, v in [("alpha", 0.0), ("timeconst", -1.0), ("dampratio", math.nan)]:
        add(
            f"kelvin_voigt.mujoco_equivalent({k}={v!r})",
            lambda k=k, v=v: kelvin_voigt.mujoco_equivalent(
                s, **{"alpha": 3.0, "timeconst": 0.06, "dampratio": 1.0, "solimp": (0.9, 0.95, 0.001, 0.5, 2.0), k: v}
            ),
            k,
        )
    # the front door's other arguments: a name that is not a string, a rod that is not a Rod, thresholds that are not Thresholds
    from crosscheck import engines as registry

    add("engines.get(['mujoco'])", lambda: registry.get(["mujoco"]), "engine")
    add("engines.get(None)", lambda: registry.get(None), "engine")
    add("get('mujoco').simulate(rod=None)", lambda: registry.get("mujoco").simulate(None, s, 1.4, horizon=0.1), "rod")
    add(
        "get('pinocchio').sweep(rod='rod')",
        lambda: registry.get("pinocchio").sweep("rod", [s], 1.4, horizon=0.1),
        "rod",
    )
    add(
        "get('mujoco').simulate(thresholds='bogus')",
        lambda: registry.get("mujoco").simulate(rod, s, 1.4, horizon=0.1, thresholds="bogus"),
        "thresholds",
    )
    add("critical_values(mu=[1.4, 1.5])", lambda: critical.critical_values([1.4, 1.5], 3.0), "mu")
    add(
        "get('mujoco').simulate(horizon=True)",
        lambda: registry.get("mujoco").simulate(rod, s, 1.4, horizon=True),
        "horizon",
    )
    add(
        "get('mujoco').simulate(mu=1.4+5j)",
        lambda: registry.get("mujoco").simulate(rod, s, 1.4 + 5j, horizon=0.1),
        "mu",
    )
    add(
        "get('mujoco').sweep(mu=complex array)",
        lambda: registry.get("mujoco").sweep(rod, [s, s], np.array([1.4 + 5j] * 2), horizon=0.1),
        "mu",
    )
    add(
        "get('mujoco').sweep(mu of 3 for 2 states)",
        lambda: registry.get("mujoco").sweep(rod, [s, s], [1.4, 1.4, 1.4], horizon=0.1),
        "mu",
    )
    # not real numbers, or several where one belongs: a complex value would lose its imaginary part, a bool count as 1
    from crosscheck.coordinates import from_generalized, to_generalized

    not_real = [np.complex128(1 + 1e-3j), b"1.0", True, np.array([1.0, 1.0]), [1.0]]
    for k in ok_state:
        for v in not_real:
            add(f"SlipState({k}={v!r})", lambda k=k, v=v: SlipState(**{**ok_state, k: v}), k)
    for k in ("mass", "length", "inertia", "gravity"):
        for v in (True, [1.0, 2.0], np.complex128(1 + 1j)):
            add(f"Rod({k}={v!r})", lambda k=k, v=v: Rod(**{k: v}), k)
    add("Rod.scaled([3, 4])", lambda: Rod.scaled([3, 4]), "alpha")
    # round 3: the rod a uniform rod's mass and length give, text digits of other scripts, a rod MuJoCo cannot hold
    add("Rod.uniform(1e60, 1e30)", lambda: Rod.uniform(1e60, 1e30), "mass")
    add("Rod.uniform(1e-70, 1e-20)", lambda: Rod.uniform(1e-70, 1e-20), "length")
    for k, v in [("Theta", "2_0"), ("eta", "\u0665"), ("Psi", "\uff13"), ("theta", "0.\u0669")]:
        add(f"SlipState({k}={v!r})", lambda k=k, v=v: SlipState(**{**ok_state, k: v}), k)
    add(
        "get('mujoco').simulate(Rod.uniform(1e-16, 2.0))",
        lambda: registry.get("mujoco").simulate(Rod.uniform(1e-16, 2.0), s, 1.4, horizon=0.05),
        "rod",
    )
    add(
        "get('mujoco').simulate(timestep=0.02 past horizon=0.005)",
        lambda: registry.get("mujoco").simulate(rod, s, 1.4, horizon=0.005, timestep=0.02),
        "timestep",
    )
    add(
        "slip_until_event(theta=pi/2 - 1 ulp)",
        lambda: slip_until_event(SlipState(**{**ok_state, "theta": math.nextafter(math.pi / 2, 0)}), 1.4, 3.0),
        "theta",
    )
    add("Rod.uniform([1, 2], 1)", lambda: Rod.uniform([1, 2], 1), "mass")
    add("analytic.p(theta complex)", lambda: analytic.p(np.array([1 + 1j]), -1.0, 1.0, 3.0), "theta")
    add("analytic.p(mu=True)", lambda: analytic.p(1.0, -1.0, True, 3.0), "mu")
    add("analytic.p(theta (2,), varphi (3,))", lambda: analytic.p([1.0, 1.1], [-1.0, -1.0, -1.0], 1.0, 3.0), "theta")
    add("analytic.b(Psi (2,), Theta (3,))", lambda: analytic.b([1.0, 1.1], [0.0, 0.0, 0.0], 1.0), "Psi")
    add("to_generalized(tip=(nan, 0, 0))", lambda: to_generalized(rod, s, tip=(math.nan, 0, 0)), "tip")
    add("to_generalized(tip=(1, 2))", lambda: to_generalized(rod, s, tip=(1, 2)), "tip")
    add("to_generalized(state=dict)", lambda: to_generalized(rod, ok_state), "state")
    add("from_generalized(q of shape (4,))", lambda: from_generalized(rod, np.zeros(4), np.zeros(5)), "q")
    add("from_generalized(q complex)", lambda: from_generalized(rod, np.zeros(5) + 1j, np.zeros(5)), "q")
    add(
        "paper_to_qv(theta (2,), Psi (3,))",
        lambda: paper_to_qv(rod, [1.0, 1.1], -1.0, 0.0, [0.0, 0.0, 0.0], 1.0),
        "theta",
    )
    add("paper_to_qv(rod=None)", lambda: paper_to_qv(None, **ok_state), "rod")
    for k, v in [
        ("horizon", True),
        ("horizon", np.array([0.05, 0.05])),
        ("horizon", np.complex128(0.05 + 1j)),
        ("mu", np.array([1.4, 1.4])),
        ("mu", np.complex128(1.4 + 5j)),
        ("mu", True),
        ("timestep", True),
        ("timestep", [1e-3]),
        ("timestep", np.complex128(1e-3 + 1j)),
    ]:
        add(f"pinocchio.simulate({k}={v!r})", lambda k=k, v=v: _simulate(pinocchio, rod, s, k, v), k)
    for k, v in [("timestep", True), ("timestep", [1e-3]), ("timestep", np.complex128(1e-3 + 1j)), ("radius", True)]:
        add(f"mujoco.simulate({k}={v!r})", lambda k=k, v=v: _simulate(mujoco, rod, s, k, v), k)
    for v in [np.array([1.4 + 5j] * 2), np.array([1.4, 1.4, 1.4]), np.ones((2, 2)), np.array([True, True])]:
        add(
            f"pinocchio.sweep(mu={v!r})",
            lambda v=v: pinocchio.sweep(rod, [s, s], v, horizon=0.05, progress=False, workers=1),
            "mu",
        )
    add(
        "pinocchio.sweep(horizon=True)",
        lambda: pinocchio.sweep(rod, [s, s], 1.4, horizon=True, progress=False, workers=1),
        "horizon",
    )
    return cases
