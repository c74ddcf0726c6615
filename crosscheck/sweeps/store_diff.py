"""Two sweep stores compared run by run: confusion matrix, agreement with its confidence interval, event-time errors, the disagreeing states.

Runs are matched on their inputs (theta, varphi, Theta, Psi, eta, psi, mu,
alpha), so the two stores may differ in engine or options (MuJoCo against
the analytic reference, or MuJoCo at two timesteps); each store must hold
one run per input (one option combination).  Outcomes are compared as they
are (no comparison window): use equal horizons.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crosscheck.files import out_error, write_atomic
from crosscheck.outcome import Outcome

__all__ = ["Comparison", "compare_frames", "compare_stores", "wilson_interval", "KEYS"]

#: The input columns that identify a run across stores.
KEYS = ("theta", "varphi", "Theta", "Psi", "eta", "psi", "mu", "alpha")
#: Inputs equal to this many decimals are one run's (the inputs are O(1) to O(1e3): 1e-12 is ~1e4 ulps, far below any
#: step of a grid, far above the last-bit differences of numpy.linspace against a list).
KEY_DECIMALS = 12

_NAMES = [o.name for o in Outcome]


def wilson_interval(k: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion k/n (95 % by default); (nan, nan) for n = 0."""
    if n == 0:
        return math.nan, math.nan
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return max(0.0, c - h), min(1.0, c + h)


@dataclass
class Comparison:
    """The comparison of B against A (see the module docstring); ``as_dict()`` is JSON-able."""

    a: str
    b: str
    n: int
    confusion: np.ndarray  # rows: A's outcome, columns: B's, indexed by Outcome values
    agreement: float
    interval: tuple
    time_difference: dict  # per event name: n, median, median |d|, 95th percentile |d| of t_B - t_A
    disagreeing: object  # pandas.DataFrame of the runs whose outcomes differ
    caveats: tuple = ()  # what the agreement does not say: runs without a match, unequal or short horizons

    def as_dict(self) -> dict:
        fin = lambda x: None if isinstance(x, float) and not math.isfinite(x) else x  # noqa: E731
        return {
            "a": self.a,
            "b": self.b,
            "n": self.n,
            "labels": _NAMES,
            "confusion": self.confusion.tolist(),
            "agreement": fin(self.agreement),
            "agreement_95": [fin(x) for x in self.interval],
            "time_difference": self.time_difference,
            "n_disagreeing": len(self.disagreeing),
            "caveats": list(self.caveats),
        }

    def table(self) -> str:
        used = [i for i in range(len(_NAMES)) if self.confusion[i].sum() or self.confusion[:, i].sum()]
        w = max(8, *(len(_NAMES[i]) for i in used))
        corner = "A \\ B"
        lines = [
            f"{self.b} against {self.a}: {self.n} runs, agreement {self.agreement:.3f} (95 % CI {self.interval[0]:.3f}-{self.interval[1]:.3f})",
            f"{corner:>{w}} " + " ".join(f"{_NAMES[j]:>{w}}" for j in used),
        ]
        for i in used:
            lines.append(f"{_NAMES[i]:>{w}} " + " ".join(f"{int(self.confusion[i, j]):>{w}d}" for j in used))
        for ev, d in self.time_difference.items():
            if d["n"]:
                lines.append(
                    f"{ev}: {d['n']} shared, t_B - t_A median {d['median']:+.3g}, median |.| {d['median_abs']:.3g}, 95th pct |.| {d['p95_abs']:.3g}"
                )
        lines.append(f"{len(self.disagreeing)} runs disagree")
        lines += [f"caveat: {c}" for c in self.caveats]
        return "\n".join(lines)


def compare_frames(a, b, *, name_a: str = "A", name_b: str = "B") -> Comparison:
    """Compare two sweep tables (``crosscheck.sweeps.load``) matched on ``KEYS``."""
    for df, name in ((a, name_a), (b, name_b)):
        if df.duplicated(list(KEYS)).any():
            raise ValueError(
                f"{name} has several runs per input (an option swept); compare needs one: filter its table and use compare_frames"
            )
    # matched on the inputs to KEY_DECIMALS decimals: a range and a list of one grid differ in the last bit
    # (numpy.linspace's 0.6000000000000001 against 0.6), and exact keys once matched 9 of 12 runs without a word
    ka, kb = (df.assign(**{f"_key_{k}": df[k].round(KEY_DECIMALS) for k in KEYS}) for df in (a, b))
    on = [f"_key_{k}" for k in KEYS]
    j = ka.merge(kb.drop(columns=list(KEYS)), on=on, suffixes=("_a", "_b")).drop(columns=on)
    caveats = []
    if len(j) < max(len(a), len(b)):
        caveats.append(
            f"{len(a) - len(j)} runs of {name_a} and {len(b) - len(j)} of {name_b} have no run with the same inputs "
            f"(to {KEY_DECIMALS} decimals) in the other store and are not compared"
        )
    if not len(j):
        raise ValueError(
            f"{name_a} and {name_b} share no runs (no equal theta, varphi, Theta, Psi, eta, psi, mu, alpha)"
        )
    oa = np.array([Outcome[o] for o in j["outcome_a"]], int)
    ob = np.array([Outcome[o] for o in j["outcome_b"]], int)
    conf = np.zeros((len(_NAMES), len(_NAMES)), int)
    np.add.at(conf, (oa, ob), 1)
    agree = oa == ob
    k, n = int(agree.sum()), len(j)
    td = {}
    for ev in (Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM):
        s = agree & (oa == ev)
        d = (j["event_time_b"] - j["event_time_a"]).to_numpy()[s]
        td[ev.name] = {
            "n": int(s.sum()),
            "median": float(np.median(d)) if s.any() else None,
            "median_abs": float(np.median(np.abs(d))) if s.any() else None,
            "p95_abs": float(np.percentile(np.abs(d), 95)) if s.any() else None,
        }
    cols = [*KEYS, "outcome_a", "event_time_a", "outcome_b", "event_time_b"]
    return Comparison(
        a=name_a,
        b=name_b,
        n=n,
        confusion=conf,
        agreement=k / n,
        interval=wilson_interval(k, n),
        time_difference=td,
        disagreeing=j.loc[~agree, cols].reset_index(drop=True),
        caveats=tuple(caveats),
    )


def _horizon_caveats(dir_a: Path, dir_b: Path) -> tuple:
    """The caveats of two stores' horizons: unequal (outcomes of runs of unequal length), or shorter than the
    classifier's window (``Thresholds.window``: an event in the window at the end of a run is not judged)."""
    from crosscheck.engines.thresholds import Thresholds
    from crosscheck.sweeps.store import Store

    horizons = []
    for d in (dir_a, dir_b):
        spec = (Store(d).read_manifest() or {}).get("spec") or {}
        h = (spec.get("sweep") or {}).get("horizon")
        horizons.append(float(h) if isinstance(h, (int, float)) and not isinstance(h, bool) else math.nan)
    out = []
    if horizons[0] != horizons[1] and all(map(math.isfinite, horizons)):
        out.append(
            f"the horizons differ ({horizons[0]:g} against {horizons[1]:g}): outcomes of runs of unequal length are "
            "compared as they are"
        )
    window = Thresholds().window
    if any(h < window for h in horizons):
        out.append(
            f"a horizon ({min(horizons):g}) is shorter than the classifier's window ({window:g}): an engine's event "
            "in it can be missed, so agreement there says little"
        )
    return tuple(out)


def compare_stores(
    dir_a: str | Path, dir_b: str | Path, *, out: str | Path | None = None
) -> tuple[Comparison, list[Path]]:
    """Compare the sweeps in two stores; write ``<out>.json`` (summary) and ``<out>-disagreeing.csv``.

    ``out`` defaults to ``<dir_b>/compare-<name of dir_a>``.  Returns the comparison and the files written.
    """
    from crosscheck.sweeps import load

    dir_a, dir_b = Path(dir_a), Path(dir_b)
    for name, d in (("DIR_A", dir_a), ("DIR_B", dir_b)):
        try:
            store = (d / "manifest.json").is_file()
        except OSError as e:  # a name the file system refuses (too long)
            store, d = False, f"{str(d)[:60]}... ({e.strerror})"
        if not store:
            raise ValueError(
                f"{name} must be a sweep store (a directory with the manifest.json of crosscheck sweep); got {str(d)!r}"
            )
    c = compare_frames(load(dir_a), load(dir_b), name_a=str(dir_a), name_b=str(dir_b))
    c.caveats = c.caveats + _horizon_caveats(dir_a, dir_b)
    if out is not None and (not str(out).strip() or str(out).endswith("/")):
        raise ValueError(
            f"out must be a file name prefix (the JSON and CSV are <out>.json and <out>-disagreeing.csv); got {str(out)!r}"
        )
    out = Path(out) if out is not None else dir_b / f"compare-{dir_a.resolve().name}"
    js, csv = out.with_name(out.name + ".json"), out.with_name(out.name + "-disagreeing.csv")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise ValueError(
            f"out must be in a writable directory; cannot create {str(out.parent)[:200]!r}: {e.strerror or e}"
        ) from None
    # through a temporary file each: a full disk or a refused path is one line, and no half-written file stays
    write_atomic(js, (json.dumps(c.as_dict(), indent=1) + "\n").encode(), error=out_error)
    write_atomic(csv, c.disagreeing.to_csv(index=False).encode(), error=out_error)
    return c, [js, csv]
