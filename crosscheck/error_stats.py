"""Error summaries shared by the ``crosscheck validate <engine>`` commands.

An engine's validation returns a ``ValidationResult``: one ``ErrorStat`` per
quantity (largest absolute and relative error and the state where the error,
measured in multiples of its tolerance, is largest) plus free-form JSON-able
extras (tables, confusion matrices).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field

import numpy as np

from crosscheck.tolerances import Tolerance

__all__ = ["ErrorStat", "ValidationResult", "error_stat", "as_json"]


@dataclass
class ErrorStat:
    quantity: str
    n: int
    max_abs: float
    max_rel: float
    max_ratio: float  # max |err| / (atol + rtol |want|); <= 1 passes
    worst_state: dict
    tolerance: dict
    passed: bool


def error_stat(quantity: str, got, want, tol: Tolerance, states: dict[str, np.ndarray]) -> ErrorStat:
    """Compare ``got`` with ``want`` (shape (N, ...)) state by state.

    ``states`` maps variable names to (N,) arrays describing each state; the
    entry of the worst state (largest tolerance ratio) is reported.
    """
    got = np.asarray(got, float)
    want = np.asarray(want, float)
    n = got.shape[0]
    err = np.abs(got - want).reshape(n, -1)
    scale = np.abs(want).reshape(n, -1)
    ratio = tol.ratio(got, want).reshape(n, -1)
    ratio = np.where(np.isfinite(ratio), ratio, np.inf)
    # relative error only where the reference is non-zero; exact zeros of the
    # reference (structural zeros of C, g, ...) are judged by max_abs alone
    nz = scale > 0
    max_rel = float((err[nz] / scale[nz]).max()) if nz.any() else math.nan
    per_state = ratio.max(axis=1)
    i = int(np.argmax(per_state))
    worst = {k: float(np.asarray(v)[i]) for k, v in states.items()}
    worst["index"] = i
    return ErrorStat(
        quantity=quantity,
        n=n,
        max_abs=float(err.max()),
        max_rel=max_rel,
        max_ratio=float(per_state.max()),
        worst_state=worst,
        tolerance=tol.as_dict(),
        passed=bool(per_state.max() <= 1.0),
    )


def as_json(x):
    """Standard JSON values: numpy -> python, non-finite floats -> None (JSON has no NaN or inf)."""
    if isinstance(x, dict):
        return {str(k): as_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [as_json(v) for v in x]
    if isinstance(x, np.ndarray):
        return as_json(x.tolist())
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, (np.integer, np.bool_)):
        return x.item()
    return x


@dataclass
class ValidationResult:
    engine: str
    stats: list[ErrorStat]
    extra: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return all(s.passed for s in self.stats)

    def to_json(self) -> str:
        """Standard JSON: non-finite floats (NaN, inf) become null."""
        doc = {
            "engine": self.engine,
            "passed": self.passed,
            "stats": [asdict(s) for s in self.stats],
            "extra": self.extra,
        }
        return json.dumps(as_json(doc), indent=2, allow_nan=False)

    def to_table(self) -> str:
        """The stats as aligned text columns: the quantity column as wide as its longest name, "-" where a number does not
        apply (no relative error for a count, whose reference is 0)."""

        def num(x: float, fmt: str) -> str:
            return format(x, fmt) if math.isfinite(x) else "-"

        w = max([len("quantity"), *(len(s.quantity) for s in self.stats)])
        head = f"{'quantity':<{w}} {'n':>7} {'max abs':>10} {'max rel':>10} {'/tol':>8}  result  worst state"
        lines = [f"validate {self.engine}", head, "-" * len(head)]
        for s in self.stats:
            where = ", ".join(f"{k}={v:.4g}" for k, v in s.worst_state.items() if k != "index")
            lines.append(
                f"{s.quantity:<{w}} {s.n:>7} {num(s.max_abs, '.2e'):>10} {num(s.max_rel, '.2e'):>10} {num(s.max_ratio, '.3f'):>8}  "
                f"{'ok' if s.passed else 'FAIL':<6}  {where}"
            )
        lines.append("passed" if self.passed else "FAILED")
        return "\n".join(lines)
