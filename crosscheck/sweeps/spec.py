"""A sweep's spec: the TOML file that names the engine, the states, mu and alpha and the engine options, checked before anything runs.

    [sweep]
    engine = "mujoco"        # a registered engine, or "analytic": slip_until_event's first event, or with
                             # [options] hybrid = true (and restitution = e) the hybrid flow through impacts
    horizon = 0.5            # scaled time
    seed = 0                 # random states and each chunk's generator derive from it
    chunk = 16               # runs per chunk (the unit of work and of storage)

    [states]                 # a product grid: each axis a scalar, a list, or {start, stop, num}
    theta = {start = 0.4, stop = 1.2, num = 5}
    varphi = -1.5707963267948966
    Theta = [0.0, 0.5]
    Psi = {start = 0.0, stop = 2.0, num = 4}
    eta = 1.0

    # or random samples:  [states] random = 1000, with each axis {low, high} (uniform) or a scalar
    # or a file:          [states] file = "states.csv"  (UTF-8, comma-separated; a header naming the columns theta,
    #                     varphi, Theta, Psi, eta[, psi] once each; one number per cell, one row per state)
    # or listed states:   [states] zip = true, each axis (and mu, if not in [parameters]) a list of one length

    [parameters]             # each a scalar or a list (a list sweeps it)
    mu = [0.5, 1.4]
    alpha = 3.0

    [options]                # the engine's options (its ``Options`` fields); a list sweeps that option too
    timestep = 3e-4

Every value a chunk will use is checked when the spec is read, before any
chunk runs: each state, mu, alpha, each option value and each combination of
swept options (``SpecError`` names the key, the value and what is allowed).
The spec itself must be a regular UTF-8 file (a FIFO is refused, never read).

Every run is one (state, mu, alpha, option combination); runs are ordered
state-major, then mu, alpha and the options in the order written, and cut
into chunks of ``chunk`` runs.  The paper's scaled units throughout
(section 2.1); the state's domain is ``SlipState``'s (theta in (0, pi/2),
varphi in (-pi, 0], eta > 0).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import re
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from crosscheck.checks import ALPHA_MAX, ALPHA_MIN, HORIZON_MAX, MU_MAX, PSI_MAX, RATE_MAX
from crosscheck.engines.base import MAX_RECORD_BYTES

__all__ = ["Spec", "SpecError", "load_spec", "parse_spec", "AXES", "ANALYTIC"]

#: The state axes of a spec, in the paper's names (psi, the heading, is optional and 0 by default).
AXES = ("theta", "varphi", "Theta", "Psi", "eta")

#: The engine name of the analytic reference (the first event of ``slip_until_event``).
ANALYTIC = "analytic"

_TABLES = {
    "sweep": {"engine", "horizon", "seed", "chunk"},
    "states": None,
    "parameters": {"mu", "alpha"},
    "options": None,
}


class SpecError(ValueError):
    """An invalid spec: the message names the key, the value and what is allowed."""


def _number(
    key: str,
    value: Any,
    *,
    low: float = -math.inf,
    high: float = math.inf,
    low_open: bool = False,
    integer: bool = False,
) -> float:
    ok_type = isinstance(value, int) if integer else isinstance(value, (int, float))
    if isinstance(value, bool) or not ok_type:
        raise SpecError(f"{key} must be {'an integer' if integer else 'a number'}; got {value!r}")
    try:
        v = float(value)
    except OverflowError:  # a TOML integer beyond float range (10**400): refused as out of range, not a traceback
        v = math.inf if value > 0 else -math.inf
    if not math.isfinite(v) or not ((low < v) if low_open else (low <= v)) or not v <= high:
        rng = f"{'(' if low_open else '['}{low:g}, {high:g}]"
        shown = (
            repr(value)
            if math.isfinite(v) or not isinstance(value, int)
            else f"an integer of {len(str(abs(value)))} digits"
        )
        raise SpecError(f"{key} must be in {rng}; got {shown}")
    return int(value) if integer else v


def _count(value: Any) -> int:
    """How many values ``_values`` will list for ``value`` (1 for anything it will refuse)."""
    if isinstance(value, dict) and isinstance(value.get("num"), int) and not isinstance(value["num"], bool):
        return max(1, value["num"])
    return max(1, len(value)) if isinstance(value, list) else 1


def _check_runs(sizes: list[int]) -> None:
    """SpecError unless the product of ``sizes`` (states, mu, alpha, each option's values) is at most ``MAX_RUNS``:
    checked before any chunk id is listed (1e14 runs once took 4 GB in 53 s)."""
    if math.prod(sizes) > MAX_RUNS:
        raise SpecError(
            f"runs (states x mu x alpha x option values) must be at most {MAX_RUNS}; got "
            f"{' x '.join(map(str, sizes))} = {math.prod(sizes):.3g}"
        )


def _values(key: str, value: Any, **limits) -> list[float]:
    """A scalar, a list, or {start, stop, num} (numpy.linspace, stop included) as a list of checked floats."""
    if isinstance(value, dict):
        unknown = sorted(set(value) - {"start", "stop", "num"})
        if unknown or set(value) != {"start", "stop", "num"}:
            raise SpecError(f"{key} as a range needs exactly the keys start, stop, num; got {sorted(value)}")
        num = _number(f"{key}.num", value["num"], low=1, high=MAX_STATES, integer=True)
        start, stop = _number(f"{key}.start", value["start"]), _number(f"{key}.stop", value["stop"])
        out = np.linspace(start, stop, num).tolist()
    elif isinstance(value, list):
        if not value:
            raise SpecError(f"{key} must not be an empty list")
        out = [_number(f"{key}[{i}]", v) for i, v in enumerate(value)]
    else:
        out = [_number(key, value, **limits)]
    return [_number(key, v, **limits) for v in out]


# Where each state axis may lie (SlipState's domain), in scaled units.
# (the same ranges as crosscheck.checks, which says where each bound comes from)
_LIMITS = {
    "theta": dict(low=0.0, high=math.pi / 2, low_open=True),
    "varphi": dict(low=-math.pi, high=0.0, low_open=True),
    "Theta": dict(low=-RATE_MAX, high=RATE_MAX),
    "Psi": dict(low=-RATE_MAX, high=RATE_MAX),
    "eta": dict(low=0.0, high=RATE_MAX, low_open=True),
    "psi": dict(low=-PSI_MAX, high=PSI_MAX),
}
_MU = dict(low=0.0, high=MU_MAX)
_ALPHA = dict(low=ALPHA_MIN, high=ALPHA_MAX)

#: The most states one spec may list: a sweep's columns are held in memory (8 bytes per axis and state).
MAX_STATES = 10_000_000


@dataclass(frozen=True)
class Spec:
    """A checked sweep spec (see the module docstring); ``runs()`` lists every run, ``digest`` identifies it."""

    engine: str
    horizon: float
    seed: int
    chunk: int
    states: dict  # axis -> (n,) float array, one entry per state
    mu: tuple
    alpha: tuple
    options: dict  # option -> tuple of values (a swept option has several)
    source: dict  # the TOML as read (for the manifest)

    @property
    def option_combinations(self) -> list[dict]:
        keys = list(self.options)
        return [dict(zip(keys, combo)) for combo in itertools.product(*(self.options[k] for k in keys))]

    @property
    def n_states(self) -> int:
        return len(self.states["theta"])

    @property
    def n_runs(self) -> int:
        return (
            self.n_states * (1 if self.mu_per_state else len(self.mu)) * len(self.alpha) * len(self.option_combinations)
        )

    @property
    def n_chunks(self) -> int:
        return math.ceil(self.n_runs / self.chunk)

    @property
    def mu_per_state(self) -> bool:
        """mu listed with the states (``zip = true``) rather than swept in [parameters]."""
        return "mu" in self.states

    def runs(self, chunk_id: int | None = None) -> dict[str, np.ndarray]:
        """The runs (of one chunk, or all) as columns: the state axes and psi, mu, alpha, the options, and ``run`` (the run's index)."""
        combos = self.option_combinations
        n_mu = 1 if self.mu_per_state else len(self.mu)
        n_inner = n_mu * len(self.alpha) * len(combos)
        lo, hi = (
            (0, self.n_runs)
            if chunk_id is None
            else (chunk_id * self.chunk, min((chunk_id + 1) * self.chunk, self.n_runs))
        )
        idx = np.arange(lo, hi)
        i_state, rest = np.divmod(idx, n_inner)
        i_mu, rest = np.divmod(rest, len(self.alpha) * len(combos))
        i_alpha, i_combo = np.divmod(rest, len(combos))
        cols = {k: np.asarray(self.states[k], float)[i_state] for k in (*AXES, "psi")}
        cols["mu"] = (
            np.asarray(self.states["mu"], float)[i_state] if self.mu_per_state else np.asarray(self.mu, float)[i_mu]
        )
        cols["alpha"] = np.asarray(self.alpha, float)[i_alpha]
        for k in self.options:
            cols[k] = np.array([combos[c][k] for c in i_combo])
        cols["run"] = idx
        return cols

    @property
    def caveats(self) -> tuple[str, ...]:
        """What the sweep's outcomes do not say: ``crosscheck.engines.base.horizon_caveats`` of its horizon at each
        option combination's timestep (a horizon shorter than the classifier's window); () for the theory's sweep,
        whose integration judges every event."""
        if self.engine == "analytic":
            return ()
        from crosscheck import engines
        from crosscheck.engines.base import horizon_caveats
        from crosscheck.engines.thresholds import Thresholds

        E, out = engines.get(self.engine), []
        for combo in self.option_combinations:
            for c in horizon_caveats(self.horizon, E.options(**combo), Thresholds()):
                out += [c] if c not in out else []
        return tuple(out)

    @property
    def digest(self) -> str:
        """sha256 of the spec's content (its runs and settings), independent of the TOML's formatting."""
        body = {
            "engine": self.engine,
            "horizon": self.horizon,
            "seed": self.seed,
            "chunk": self.chunk,
            "mu": self.mu,
            "alpha": self.alpha,
            "options": {k: list(v) for k, v in self.options.items()},
            "states": {k: np.asarray(v, float).tobytes().hex() for k, v in self.states.items()},
        }
        return hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()


def _check_tables(doc: dict) -> None:
    for t, v in doc.items():
        if t not in _TABLES:
            raise SpecError(f"unknown table [{t}]; tables are {', '.join(f'[{k}]' for k in _TABLES)}")
        if not isinstance(v, dict):
            raise SpecError(f"[{t}] must be a table; got {v!r}")
        allowed = _TABLES[t]
        if allowed is not None:
            for k in v:
                if k not in allowed:
                    raise SpecError(f"unknown key {k!r} in [{t}]; keys are {', '.join(sorted(allowed))}")
    if "sweep" not in doc or "engine" not in doc["sweep"] or "horizon" not in doc["sweep"]:
        raise SpecError("[sweep] needs engine and horizon")
    if "states" not in doc:
        raise SpecError("the spec needs a [states] table")
    zipped_mu = doc["states"].get("zip") is True and "mu" in doc["states"]
    if zipped_mu == ("mu" in doc.get("parameters", {})):
        raise SpecError(
            "mu goes in [parameters] (or, with [states] zip = true, in [states]: one per state), not both or neither"
        )


def _states(table: dict, seed: int, base: Path | None) -> dict[str, np.ndarray]:
    if "file" in table:
        extra = sorted(set(table) - {"file"})
        if extra:
            raise SpecError(f"[states] with file takes no other keys; got {', '.join(extra)}")
        if not isinstance(table["file"], str) or not table["file"].strip():
            raise SpecError(f"states.file must be the path of a CSV file (a string); got {table['file']!r}")
        path = Path(table["file"]) if base is None else base / table["file"]
        cols = _read_states_file(path)
        for a, v in cols.items():
            for i, x in enumerate(v):
                _number(f"states.file row {i + 1} {a}", float(x), **_LIMITS[a])
        return cols
    allowed = {*AXES, "psi", "random", "zip", "mu"}
    for k in table:
        if k not in allowed:
            raise SpecError(f"unknown key {k!r} in [states]; keys are {', '.join(sorted(allowed))} (or file)")
    missing = [a for a in AXES if a not in table]
    if missing:
        raise SpecError(f"[states] needs every axis {', '.join(AXES)}; missing {', '.join(missing)}")
    if table.get("zip", False) is not False:
        if table["zip"] is not True or "random" in table:
            raise SpecError(
                f"states.zip must be true (lists of equal length, one state per position, mu among them if wanted) and excludes random; got {table['zip']!r}"
            )
        cols = {a: _values(f"states.{a}", table[a], **_LIMITS[a]) for a in AXES if a in table}
        for a, lim in (("psi", _LIMITS["psi"]), ("mu", _MU)):
            if a in table:
                cols[a] = _values(f"states.{a}", table[a], **lim)
        n = {len(v) for v in cols.values()}
        if len(n) != 1:
            raise SpecError(
                f"states with zip = true need lists of one length; got lengths {', '.join(f'{a} {len(v)}' for a, v in cols.items())}"
            )
        cols.setdefault("psi", [0.0] * n.pop())
        return {a: np.asarray(v, float) for a, v in cols.items()}
    if "mu" in table:
        raise SpecError(
            "states.mu is allowed only with zip = true (one mu per listed state); otherwise mu goes in [parameters]"
        )
    if "random" in table:
        n = _number("states.random", table["random"], low=1, high=MAX_STATES, integer=True)
        rng = np.random.default_rng([seed, 0])  # the states' own stream; chunks draw from (seed, 1 + chunk id)
        cols = {}
        for a in (*AXES, "psi"):
            v = table.get(a, 0.0)
            if isinstance(v, dict):
                if set(v) != {"low", "high"}:
                    raise SpecError(f"states.{a} of random states must be a scalar or {{low, high}}; got {v!r}")
                lo, hi = (
                    _number(f"states.{a}.low", v["low"], **_LIMITS[a]),
                    _number(f"states.{a}.high", v["high"], **_LIMITS[a]),
                )
                if not lo < hi:
                    raise SpecError(f"states.{a} must have low < high; got low = {lo!r}, high = {hi!r}")
                cols[a] = rng.uniform(lo, hi, n)
            else:
                cols[a] = np.full(n, _number(f"states.{a}", v, **_LIMITS[a]))
        return cols
    axes = {a: _values(f"states.{a}", table.get(a, 0.0), **_LIMITS[a]) for a in (*AXES, "psi")}
    n = math.prod(len(v) for v in axes.values())
    if n > MAX_STATES:
        raise SpecError(
            f"[states] grid must have at most {MAX_STATES} states; got {' x '.join(str(len(v)) for v in axes.values())} = {n}"
        )
    grid = np.array(list(itertools.product(*(axes[a] for a in (*AXES, "psi")))), float)
    return {a: grid[:, i].copy() for i, a in enumerate((*AXES, "psi"))}


#: The most runs of one sweep (as many as states): its chunk ids are listed in memory.
MAX_RUNS = MAX_STATES

#: The most bytes of a states file (a row of six 17-digit numbers is ~110 bytes).
MAX_STATES_FILE_BYTES = 128 * MAX_STATES


def _read_states_file(path: Path) -> dict[str, np.ndarray]:
    """The columns of a states CSV: UTF-8, comma-separated, a header naming each axis once, one number per cell."""
    import csv
    import io

    try:
        if not path.is_file():  # also refuses a FIFO or a device, which would block or never end
            raise SpecError(f"states.file must be a readable CSV file; got {str(path)!r}")
        if path.stat().st_size > MAX_STATES_FILE_BYTES:
            raise SpecError(
                f"states.file must be at most {MAX_STATES_FILE_BYTES} bytes; {str(path)!r} has {path.stat().st_size}"
            )
        raw = path.read_bytes()
    except OSError as e:
        raise SpecError(f"states.file must be a readable CSV file; got {str(path)!r} ({e.strerror or e})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise SpecError(
            f"states.file must be a readable UTF-8 CSV file; {str(path)!r} has the byte 0x{raw[e.start]:02x} at byte {e.start + 1}"
        ) from None
    if "\0" in text:
        raise SpecError(
            f"states.file must be a readable CSV text file; {str(path)!r} has the byte 0x00 at byte {text.index(chr(0)) + 1}"
        )
    rows = [r for r in csv.reader(io.StringIO(text, newline="")) if r and any(c.strip() for c in r)]
    if not rows:
        raise SpecError(
            f"states.file must be a CSV file with a header row ({', '.join(AXES)}[, psi]) and one row per state; {str(path)!r} is empty"
        )
    header = [c.strip() for c in rows[0]]
    allowed = (*AXES, "psi")
    for c in header:
        if c not in allowed:
            raise SpecError(
                f"states.file must have only the columns ({', '.join(allowed)}) separated by commas; {str(path)!r} has {c[:40]!r}"
            )
        if header.count(c) > 1:
            raise SpecError(
                f"states.file must have each column ({', '.join(allowed)}) once; {str(path)!r} has {c!r} {header.count(c)} times"
            )
    missing = [a for a in AXES if a not in header]
    if missing:
        raise SpecError(
            f"states.file must have the columns {', '.join(AXES)}; {str(path)!r} lacks {', '.join(missing)}"
        )
    body = rows[1:]
    if not body:
        raise SpecError(
            f"states.file must be a CSV file with a header row ({', '.join(AXES)}[, psi]) and one row per state; {str(path)!r} has no states"
        )
    if len(body) > MAX_STATES:
        raise SpecError(f"states.file must have at most {MAX_STATES} states; {str(path)!r} has {len(body)}")
    cols = {c: np.empty(len(body)) for c in header}
    for i, r in enumerate(body):
        if len(r) != len(header):
            raise SpecError(
                f"states.file must have one value per column in every row ({len(header)}: {', '.join(header)}); {str(path)!r} row {i + 1} has {len(r)}"
            )
        for c, cell in zip(header, r):
            cols[c][i] = _cell(f"states.file row {i + 1} {c}", cell)
    out = {a: cols[a] for a in AXES}
    out["psi"] = cols["psi"] if "psi" in cols else np.zeros(len(body))
    return out


#: A number as a states file may write it (the command line's rule, ``crosscheck.cli.options``): ASCII digits, an optional
#: sign, point and exponent, no underscores (and nan / inf, which the ranges refuse).
_NUMBER = re.compile(r"^[+-]?((\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|nan|inf|infinity)$", re.IGNORECASE | re.ASCII)


def _cell(key: str, text: str) -> float:
    t = text.strip()
    if len(t) > 64 or not _NUMBER.match(t):
        raise SpecError(f"{key} must be a number; got {text[:64]!r}")
    return float(t)


def _options(engine: str, table: dict, horizon: float | None = None) -> dict[str, tuple]:
    if engine == ANALYTIC:
        out = {}
        for k, v in table.items():
            vals = v if isinstance(v, list) else [v]
            if not vals:
                raise SpecError(f"options.{k} must not be an empty list")
            if k == "hybrid":
                for x in vals:
                    if not isinstance(x, bool):
                        raise SpecError(f"options.hybrid must be true or false; got {x!r}")
            elif k == "restitution":
                vals = [_number("options.restitution", x, low=0.0, high=1.0) for x in vals]
            else:
                raise SpecError(f"unknown analytic option {k!r} in [options]; known options: hybrid, restitution")
            out[k] = tuple(vals)
        return out
    from crosscheck import engines

    E = engines.get(engine)
    known = {f.name for f in fields(E.Options)}
    out = {}
    for k, v in table.items():
        if k not in known:
            raise SpecError(f"unknown {engine} option {k!r} in [options]; known options: {', '.join(sorted(known))}")
        vals = v if isinstance(v, list) else [v]
        if not vals:
            raise SpecError(f"options.{k} must not be an empty list")
        for x in vals:
            try:
                E.Options(**{k: x})
            except ValueError as e:
                raise SpecError(f"options.{k}: {e}") from None
            except TypeError:
                raise SpecError(
                    f"options.{k} must be a value of {engine}'s option {k} (or a list of them); got {x!r}"
                ) from None
        out[k] = tuple(vals)
    # each combination a chunk will run, checked now (options that bound each other: MuJoCo's timeconst >= 2 timestep)
    combos = itertools.product(*(out[k] for k in out))
    too_long = []  # the combinations whose record no chunk can hold
    checked = 0
    for combo in itertools.islice(combos, MAX_OPTION_COMBINATIONS):
        checked += 1
        shown = ", ".join(f"{k} = {v!r}" for k, v in zip(out, combo))
        try:
            opts = E.Options(**dict(zip(out, combo)))
        except (TypeError, ValueError) as e:
            raise SpecError(f"options {shown}: {e}") from None
        # every engine's run refuses a step longer than its horizon: refused here, before any chunk runs
        if horizon is not None and getattr(opts, "timestep", 0.0) > horizon:
            raise SpecError(
                f"options {shown}: timestep must be in (0, sweep.horizon = {horizon:g}]; got {opts.timestep!r}"
            )
        step = getattr(opts, "timestep", None)
        if horizon is not None and step and horizon / step * MIN_ROW_BYTES > MAX_RECORD_BYTES:
            # a record no chunk can hold: each engine refuses it (its own bytes per row are at least MIN_ROW_BYTES)
            too_long.append(
                f"sweep.horizon must be at most {MAX_RECORD_BYTES / MIN_ROW_BYTES * step:.4g} at timestep {step:g} "
                f"({shown or 'the default options'}: a record of more than {MAX_RECORD_BYTES / 2**30:g} GiB); "
                f"got {horizon:g}"
            )
    if too_long and len(too_long) == checked:  # no chunk could run (one that fails among others is recorded as such)
        raise SpecError(too_long[0])
    return out


#: The fewest bytes per record row of any engine (MuJoCo's law, ``crosscheck.engines.mujoco.ode.ROW_BYTES``): a
#: spec whose record needs more than ``MAX_RECORD_BYTES`` at this size is refused by every engine, so by the spec.
MIN_ROW_BYTES = 512


#: Option combinations checked when the spec is read (a sweep of more is checked as far as this).
MAX_OPTION_COMBINATIONS = 100_000


def parse_spec(doc: dict, *, base: Path | None = None) -> Spec:
    """A ``Spec`` from a parsed TOML document (``base``: where a states file is looked up); ``SpecError`` names what is wrong."""
    if not isinstance(doc, dict):
        raise SpecError(f"a spec must be a TOML table; got {type(doc).__name__}")
    _check_tables(doc)
    sw = doc["sweep"]
    from crosscheck import engines

    engine = sw["engine"]
    if not isinstance(engine, str) or (engine != ANALYTIC and engine not in engines.names()):
        raise SpecError(f"sweep.engine must be one of {', '.join([ANALYTIC, *engines.names()])}; got {engine!r}")
    horizon = _number("sweep.horizon", sw["horizon"], low=0.0, high=HORIZON_MAX, low_open=True)
    seed = _number("sweep.seed", sw.get("seed", 0), low=0, integer=True)
    chunk = _number("sweep.chunk", sw.get("chunk", 64), low=1, integer=True)
    states = _states(doc["states"], seed, base)
    par = doc.get("parameters", {})
    _check_runs(
        [len(states["theta"]), _count(par.get("mu", 1.0)), _count(par.get("alpha", 3.0))]
    )  # before listing them
    mu = tuple(_values("parameters.mu", par["mu"], **_MU)) if "mu" in par else ()
    alpha = tuple(_values("parameters.alpha", par.get("alpha", 3.0), **_ALPHA))
    options = _options(engine, doc.get("options", {}), horizon)
    _check_runs([len(states["theta"]), 1 if "mu" in states else len(mu), len(alpha), *map(len, options.values())])
    return Spec(
        engine=engine,
        horizon=horizon,
        seed=seed,
        chunk=chunk,
        states=states,
        mu=mu,
        alpha=alpha,
        options=options,
        source=doc,
    )


#: The largest spec file read (a spec lists its states in a CSV file, not inline).
MAX_SPEC_BYTES = 64 * 1024 * 1024


def load_spec(path: str | Path) -> Spec:
    """Read and check a spec file (``SpecError`` for an unreadable file, bad TOML or a bad value)."""
    path = Path(path)
    try:
        if path.exists() and not path.is_file():  # a directory, a FIFO (which would block), a device
            raise SpecError(f"spec must be a readable TOML file; got {str(path)!r} (not a regular file)")
        if path.stat().st_size > MAX_SPEC_BYTES:
            raise SpecError(
                f"spec must be a TOML file of at most {MAX_SPEC_BYTES} bytes; got {str(path)!r} ({path.stat().st_size} bytes)"
            )
        raw = path.read_bytes()
    except OSError as e:
        raise SpecError(f"spec must be a readable TOML file; got {str(path)!r} ({e.strerror or e})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise SpecError(
            f"spec must be a readable UTF-8 TOML file; {str(path)!r} has the byte 0x{raw[e.start]:02x} at byte {e.start + 1}"
        ) from None
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise SpecError(f"spec {str(path)!r} is not valid TOML: {e}") from None
    return parse_spec(doc, base=path.parent)
