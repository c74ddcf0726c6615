"""Re-run the classes of the third reliability audit with values of its own, and count the verdicts per class.

    PYTHONPATH=<tree> python tools/audit_round3.py [--tests <tree>/tests]

Each case runs the installed-on-PYTHONPATH crosscheck in a real process (the CLI) or in this one (the API) and is
judged: ``ok`` (the honest answer, or one line naming the parameter), ``data loss`` (a file it did not write changed
or vanished), ``silent wrong`` (an answer that is wrong, or no word about what it does not cover), ``hang`` (no
answer in the time limit), ``traceback`` or ``unnamed`` (a refusal that names no parameter or takes several lines).
Run it on the tree before a change and after it to give the counts of a closing note.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

IC2 = ["--theta", "1.1031", "--varphi", "-1.9233", "--Theta", "0.9", "--Psi", "0", "--eta", "2", "--mu", "1.4"]
REST = ["--theta", "0.97", "--varphi", "-2.2", "--Theta", "0", "--Psi", "0", "--eta", "0", "--mu", "0.12"]


def cli(argv, *, timeout=60, env=None, stdout=None, cwd=None):
    """(exit code or None on timeout, stdout, stderr) of ``crosscheck argv`` in its own process."""
    try:
        r = subprocess.run(
            [sys.executable, "-m", "crosscheck", *argv],
            capture_output=stdout is None,
            text=True,
            timeout=timeout,
            env={**os.environ, **(env or {})},
            stdout=stdout,
            cwd=cwd,
            stderr=subprocess.PIPE if stdout is not None else None,
        )
    except subprocess.TimeoutExpired:
        return None, "", ""
    return r.returncode, r.stdout or "", r.stderr or ""


def refusal(code, err, param) -> str:
    """The verdict on an input that must be refused in one line naming ``param``."""
    if code is None:
        return "hang"
    if "Traceback" in err:
        return "traceback"
    if code == 0:
        return "silent wrong"
    lines = [x for x in err.strip().splitlines() if x.strip()]
    # the parameter is the subject of the refusal ("timestep must ..."), not a word in another's ("timeconst must be
    # >= 2 timestep" names the option the user did not give)
    named = len(lines) == 1 and re.search(rf"(?<![A-Za-z_]){re.escape(param)}(?![A-Za-z_])[^;]*?\bmust\b", lines[0])
    return "ok" if named else "unnamed"


def snapshot(root: Path) -> dict:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest() for p in root.rglob("*") if p.is_file()
    }


def users_dir(root: Path) -> Path:
    for name, text in {
        "index.html": "<p>site</p>",
        "notes.md": "n",
        "sweeps/mine/a.txt": "a",
        "chunks/app.js": "js",
        "manifest.json": '{"app": 1}',
        "chunks/chunk-000000.parquet": "mine",
    }.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


def data_loss(tmp: Path) -> list:
    out = []
    quick = ["report", "--quick", "--only", "critical_angles", "--no-progress"]
    spec = tmp / "s.toml"
    spec.write_text(
        '[sweep]\nengine = "analytic"\nhorizon = 0.2\nchunk = 2\n[states]\ntheta = [0.7, 1.2]\n'
        "varphi = -1.1\nTheta = 0.2\nPsi = 0.0\neta = 0.6\n[parameters]\nmu = 0.4\n"
    )
    for i, argv in enumerate(
        [
            quick + ["--out"],
            quick + ["--fresh", "--out"],
            ["sweep", str(spec), "--fresh", "--workers", "1", "--out"],
            ["sweep", str(spec), "--workers", "1", "--out"],
        ]
    ):
        d = users_dir(tmp / f"user{i}")
        before = snapshot(d)
        code, _, err = cli(argv + [str(d)], timeout=120)
        out.append(
            (
                f"{' '.join(argv[:2])} into a user's dir",
                "data loss" if snapshot(d) != before else ("ok" if code == 2 else refusal(code, err, "out")),
            )
        )
    for i, (plot, csv) in enumerate([("k.svg", "k.svg"), ("m.pdf", "m_theory.csv")]):
        d = tmp / f"sim{i}"
        d.mkdir()
        (d / csv).write_text("the user's")
        before = snapshot(d)
        code, _, err = cli(
            ["simulate", "--engine", "pinocchio", *IC2, "--horizon", "0.05", "--plot", plot, "--csv", csv], cwd=d
        )
        out.append(
            (f"simulate --plot {plot} --csv {csv}", "data loss" if snapshot(d) != before else refusal(code, err, "csv"))
        )
    from crosscheck.sweeps import Store
    from crosscheck.sweeps.spec import parse_spec

    sp = parse_spec(
        {
            "sweep": {"engine": "analytic", "horizon": 0.2, "chunk": 1},
            "states": {"theta": 0.9, "varphi": -1.0, "Theta": 0.0, "Psi": 0.0, "eta": 0.5},
            "parameters": {"mu": {"start": 0.0, "stop": 1.0, "num": 1_000_003}},
        }
    )
    st = Store(tmp / "big")
    m = st.open(sp)
    st.write_chunk(m, 1_000_002, {"run": [1_000_002], "chunk": [1_000_002], "x": [1.0]}, 0.1)
    out.append(("chunk 1000002 counted", "ok" if "1000002" in st.read_manifest()["chunks"] else "data loss"))
    return out


def stick(tmp: Path) -> list:
    out = []
    for engine in ("pinocchio", "mujoco", "bullet", "drake_sap", "compliant"):
        code, o, err = cli(["simulate", "--engine", engine, *REST, "--horizon", "0.2", "--json"], timeout=120)
        got = json.loads(o)["outcome"] if code == 0 else f"exit {code}"
        out.append((f"simulate --engine {engine} at rest, mu 0.12", "silent wrong" if got == "STICK" else "ok"))
    code, o, err = cli(["slip", *REST, "--t-max", "0.2"])
    out.append(("slip at rest, mu 0.12", "silent wrong" if o.startswith("STICK") else "ok"))
    return out


def hangs(tmp: Path) -> list:
    out = []
    code, _, err = cli(["simulate", "--engine", "compliant", *IC2[:1], "1.5707962", *IC2[2:]], timeout=30)
    out.append(("compliant at theta = pi/2 - 1e-7", refusal(code, err, "theta")))
    code, _, err = cli(
        ["simulate", "--engine", "drake_continuous", *IC2, "--alpha", "700", "--horizon", "0.5"], timeout=60
    )
    out.append(("drake_continuous at alpha 700", refusal(code, err, "alpha")))
    big = tmp / "big.toml"
    big.write_text(
        '[sweep]\nengine = "analytic"\nhorizon = 0.2\nchunk = 3\n[states]\ntheta = 1.0\nvarphi = -1.0\n'
        "Theta = 0.0\nPsi = 0.0\neta = 1.0\n[parameters]\nmu = {start = 0.1, stop = 2.0, num = 8000000}\n"
        "alpha = {start = 1.0, stop = 4.0, num = 5000000}\n"
    )
    code, _, err = cli(["sweep", str(big), "--out", str(tmp / "bigout")], timeout=60)
    out.append(("a spec of 4e13 runs", refusal(code, err, "runs")))
    spec = tmp / "int.toml"
    spec.write_text(
        '[sweep]\nengine = "pinocchio"\nhorizon = 0.4\nchunk = 1\n[states]\n'
        "theta = {start = 0.55, stop = 1.25, num = 12}\nvarphi = -1.7\nTheta = 0.2\nPsi = 0.0\neta = 1.5\n"
        "[parameters]\nmu = 0.45\n"
    )
    argv = [sys.executable, "-m", "crosscheck", "sweep", str(spec), "--out", str(tmp / "intout"), "--workers", "2"]
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    t0 = time.monotonic()
    while not list((tmp / "intout").glob("chunks/chunk-*.json")) and time.monotonic() - t0 < 120:
        time.sleep(0.05)
    os.killpg(p.pid, signal.SIGINT)
    t1 = time.monotonic()
    try:
        _, err = p.communicate(timeout=30)
        stopped = time.monotonic() - t1
    except subprocess.TimeoutExpired:
        p.kill()
        err, stopped = "", math.inf
    kept = len(list((tmp / "intout").glob("chunks/chunk-*.json")))
    verdict = (
        "hang"
        if stopped > 5
        else "traceback"
        if "Traceback" in err
        else "ok"
        if len(err.strip().splitlines()) == 1 and kept
        else "unnamed"
    )
    out.append((f"Ctrl-C of a sweep (stopped in {stopped:.1f} s, {kept} chunks kept)", verdict))
    return out


def tracebacks(tmp: Path) -> list:
    out = []
    huge = "7" * 340
    for key, line in [("horizon", f"horizon = {huge}"), ("seed", f"seed = {huge}"), ("chunk", f"chunk = {huge}")]:
        spec = tmp / f"ov_{key}.toml"
        rest = "".join(f"{k} = {v}\n" for k, v in {"horizon": "0.3", "seed": "1", "chunk": "2"}.items() if k != key)
        spec.write_text(
            f'[sweep]\nengine = "analytic"\n{line}\n{rest}[states]\ntheta = 0.9\nvarphi = -1.0\n'
            "Theta = 0.0\nPsi = 0.0\neta = 1.0\n[parameters]\nmu = 0.3\n"
        )
        code, _, err = cli(["sweep", str(spec), "--out", str(tmp / f"o_{key}")])
        out.append((f"TOML {key} of 340 digits", refusal(code, err, key)))
    code, _, err = cli(
        ["simulate", "--engine", "compliant", *IC2, "--horizon", "2e-13", "--timestep", "2e-13"], timeout=60
    )
    out.append(("compliant timestep 2e-13", refusal(code, err, "timestep")))
    for engine in ("mujoco", "mujoco_law"):
        code, _, err = cli(["simulate", "--engine", engine, *IC2, "--horizon", "0.4", "--timestep", "0.2"])
        out.append((f"{engine} --timestep 0.2 (refsafe)", refusal(code, err, "timestep")))
        code, _, err = cli(["simulate", "--engine", engine, *IC2, "--horizon", "0.004", "--timestep", "0.01"])
        out.append((f"{engine} timestep past horizon", refusal(code, err, "timestep")))
    code, _, err = cli(
        ["simulate", "--engine", "mujoco_law", "--theta", repr(math.nextafter(math.pi / 2, 0)), *IC2[2:]], timeout=60
    )
    out.append(("mujoco_law at pi/2 - 1 ulp", refusal(code, err, "theta")))
    with open("/dev/full", "w") as full:
        code, _, err = cli(["critical", "--mu", "0.77"], stdout=full)
    out.append(
        (
            "critical > /dev/full",
            "ok" if code and len(err.strip().splitlines()) == 1 and "Traceback" not in err else "traceback",
        )
    )
    code, o, err = cli(
        ["simulate", "--engine", "pinocchio", *IC2, "--horizon", "0.03", "--csv", str(tmp / "d\u00e9j\u00e0.csv")],
        env={"PYTHONIOENCODING": "ascii"},
    )
    out.append(("non-ASCII --csv under PYTHONIOENCODING=ascii", "ok" if code == 0 else "traceback"))
    from crosscheck import Rod, SlipState, engines

    for name, call, param in [
        ("Rod.uniform(1e70, 1e20)", lambda: Rod.uniform(1e70, 1e20), "mass"),
        (
            "mujoco with a 2 cm rod",
            lambda: engines.get("mujoco").simulate(
                Rod.uniform(0.3, 0.02),
                SlipState(theta=0.9, varphi=-1.0, Theta=0.1, Psi=0.0, eta=0.8),
                0.5,
                horizon=0.05,
            ),
            None,
        ),
    ]:
        try:
            call()
            out.append((name, "ok" if param is None else "silent wrong"))
        except ValueError as e:
            named = param and re.search(rf"\b{param}\b[^;]*?\bmust\b", str(e)) and "\n" not in str(e)
            out.append((name, "ok" if named else "unnamed"))
        except Exception:  # noqa: BLE001
            out.append((name, "traceback"))
    return out


def silent(tmp: Path) -> list:
    out = []
    for opt, v in [("Psi", "2_5"), ("eta", "\u0667"), ("Psi", "\uff12")]:
        code, _, err = cli(["gb", "--mu", "1.7", "--samples", "3", f"--{opt}", v])
        out.append((f"gb --{opt} {v!r}", refusal(code, err, opt)))
    from crosscheck import SlipState

    try:
        SlipState(theta=1.0, varphi=-1.0, Theta="2_0", Psi=0.0, eta=1.0)
        out.append(("SlipState(Theta='2_0')", "silent wrong"))
    except ValueError:
        out.append(("SlipState(Theta='2_0')", "ok"))
    head = (
        '[sweep]\nengine = "analytic"\nhorizon = {h}\nchunk = 5\n[states]\ntheta = {t}\nvarphi = -1.3\n'
        "Theta = [0.0, 0.45]\nPsi = 0.2\neta = 0.8\n[parameters]\nmu = 0.7\n"
    )
    stores = {}
    for name, t, h in [
        ("range", "{start = 0.3, stop = 1.2, num = 7}", 0.3),
        ("list", "[0.3, 0.45, 0.6, 0.75, 0.9, 1.05, 1.2]", 0.3),
        ("short", "[0.3, 0.45, 0.6, 0.75, 0.9, 1.05, 1.2]", 0.02),
    ]:
        (tmp / f"{name}.toml").write_text(head.format(h=h, t=t))
        cli(["sweep", str(tmp / f"{name}.toml"), "--out", str(tmp / name), "--workers", "1"])
        stores[name] = str(tmp / name)
    (tmp / "long.toml").write_text(
        '[sweep]\nengine = "mujoco"\nhorizon = 8000\nchunk = 2\n[states]\ntheta = 1.0\n'
        "varphi = -1.5\nTheta = 0.0\nPsi = 0.0\neta = 1.0\n[parameters]\nmu = 0.5\n"
    )
    code, _, err = cli(["sweep", str(tmp / "long.toml"), "--out", str(tmp / "longout"), "--workers", "1"], timeout=120)
    out.append(("mujoco spec of horizon 8000", refusal(code, err, "horizon")))
    code, o, _ = cli(["compare", stores["range"], stores["list"]])
    out.append(("compare a range and a list of one grid", "ok" if ": 14 runs" in o else "silent wrong"))
    code, o, _ = cli(["compare", stores["list"], stores["short"]])
    out.append(("compare horizons 0.3 and 0.02", "ok" if "horizon" in o.lower() else "silent wrong"))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.parse_args()
    classes = {"data loss": data_loss, "stick": stick, "hangs": hangs, "tracebacks": tracebacks, "silent": silent}
    with tempfile.TemporaryDirectory(prefix="audit-round3-") as t:
        for cls, fn in classes.items():
            d = Path(t) / cls.replace(" ", "_")
            d.mkdir()
            rows = fn(d)
            counts = Counter(v for _, v in rows)
            print(f"{cls}: {len(rows)} cases, " + ", ".join(f"{k} {n}" for k, n in sorted(counts.items())), flush=True)
            for name, v in rows:
                if v != "ok":
                    print(f"    {v}: {name}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
