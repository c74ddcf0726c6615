"""Runs/s of a MuJoCo sweep through ``crosscheck.sweeps`` against the engine's own ``sweep`` on the same states, measured in the same run.

Baseline: ``engines.get("mujoco").sweep`` on every run of the spec in this
process with one rollout thread (``nthread=1``), which is what one chunk does
(the layer's parallelism is over chunks).  Measured, best of ``--repeat``:

* layer / baseline on 1 worker (target >= 0.9): the store's Parquet writes,
  checksums and manifest, the spec's expansion;
* parallel efficiency on 2 workers (forked processes; target >= 0.8 of 2x);
* the Dask path (a ``LocalCluster`` of 2 single-threaded workers): its time
  against the process pool's, per chunk (the per-chunk overhead; the
  cluster's start-up is timed apart);
* what a 1e6-run map would take at the measured rates on this machine, and
  on 64 cores assuming the measured 2-worker efficiency holds.

    python benchmarks/bench_sweeps.py [--states 256] [--chunk 32] [--horizon 0.5] [--repeat 2]
"""

from __future__ import annotations

import argparse
import tempfile
import time
import tomllib
from pathlib import Path

from timing import best_of  # benchmarks/timing.py (the script's directory is on sys.path)

from crosscheck import Rod, SlipState, sweeps
from crosscheck.engines import get

SPEC = """
[sweep]
engine = "mujoco"
horizon = {horizon}
seed = 0
chunk = {chunk}
[states]
random = {states}
theta = {{low = 0.2, high = 1.3}}
varphi = {{low = -3.0, high = -0.1}}
Theta = {{low = -1.0, high = 1.0}}
Psi = {{low = -1.5, high = 1.5}}
eta = {{low = 0.2, high = 3.0}}
[parameters]
mu = 0.8
alpha = 3.0
[options]
timestep = 1e-3
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--states", type=int, default=256)
    ap.add_argument("--chunk", type=int, default=32)
    ap.add_argument("--horizon", type=float, default=0.5)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    spec = sweeps.parse_spec(tomllib.loads(SPEC.format(**vars(args))))
    cols = spec.runs()
    states = [
        SlipState(
            theta=cols["theta"][i],
            varphi=cols["varphi"][i],
            Theta=cols["Theta"][i],
            Psi=cols["Psi"][i],
            eta=cols["eta"][i],
        )
        for i in range(spec.n_runs)
    ]
    n = spec.n_runs
    tmp = Path(tempfile.mkdtemp(prefix="bench_sweeps_"))

    def layer(workers, scheduler=None):
        k = len(list(tmp.iterdir()))
        return lambda: sweeps.run(
            spec, tmp / f"s{k}-{time.perf_counter_ns()}", workers=workers, scheduler=scheduler, progress=False
        )

    # warm up (imports of pyarrow and the engine, MuJoCo's first compile): a one-time cost, not per sweep
    warm = sweeps.parse_spec(tomllib.loads(SPEC.format(states=2, chunk=2, horizon=0.01)))
    sweeps.run(warm, tmp / "warm", workers=1, progress=False)

    def base():
        return get("mujoco").sweep(
            Rod.scaled(3.0), states, cols["mu"], horizon=spec.horizon, timestep=1e-3, nthread=1, progress=False
        )

    # interleaved repetitions (baseline, 1 worker, 2 workers, ...): the machine's speed drifts by 20 % and more
    # between minutes (measured: the same rollout took 1.4 s and 2.0 s), which best-of blocks would attribute to the layer
    times = {"base": [], "1": [], "2": []}
    for _ in range(args.repeat):
        for key, f in (("base", base), ("1", layer(1)), ("2", layer(2))):
            t0 = time.perf_counter()
            f()
            times[key].append(time.perf_counter() - t0)
    t_base, t_1, t_2 = (min(times[k]) for k in ("base", "1", "2"))
    from distributed import LocalCluster

    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    t_start = time.perf_counter() - t0
    try:
        t_dask = best_of(args.repeat, layer(2, cluster.scheduler_address))
    finally:
        cluster.close()
    print(
        f"{n} MuJoCo runs (horizon {spec.horizon:g}, timestep 1e-3) in {spec.n_chunks} chunks of {spec.chunk}, best of {args.repeat}"
    )
    print(f"engine sweep, one process:     {n / t_base:8.1f} runs/s")
    print(f"sweeps layer, 1 worker:        {n / t_1:8.1f} runs/s   ratio {t_base / t_1:.2f} (target >= 0.9)")
    print(
        f"sweeps layer, 2 workers:       {n / t_2:8.1f} runs/s   parallel efficiency {t_1 / (2 * t_2):.2f} (target >= 0.8)"
    )
    print(
        f"sweeps layer, Dask 2 workers:  {n / t_dask:8.1f} runs/s   overhead vs the pool {1e3 * (t_dask - t_2) / spec.n_chunks:+.1f} ms per chunk"
        f" (cluster start-up {t_start:.1f} s, not included)"
    )
    rate1, eff = n / t_1, t_1 / (2 * t_2)
    for cores in (2, 64):
        secs = 1e6 / (rate1 * (1 if cores == 1 else cores * eff))
        print(
            f"1e6 runs of horizon {spec.horizon:g}: {secs / 3600:.2f} h on {cores} cores (measured 1-worker rate x cores x 2-worker efficiency)"
        )


if __name__ == "__main__":
    main()
