"""One engine run against the theory, drawn and tabulated: ``plot_run``, ``run_columns``, ``theory_trajectory``; and one
start's ladder on one figure: ``plot_ladder``.

``plot_run`` draws the run's theta, Theta, Psi, slip speed eta, contact height
and normal force (with -b/p, eq. FZ, on the engine's own states), with the
theory's slipping trajectory from the same start (``crosscheck.theory.slipping``,
eq. f) up to its first event and both event times marked.  Scaled units of the
paper throughout (time 1/omega, rates theta'/omega, forces m g, heights l).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["TheoryTrajectory", "theory_trajectory", "run_columns", "write_csv", "plot_run", "plot_ladder"]


@dataclass
class TheoryTrajectory:
    """The analytic slipping flow from one start to its first event: (n,) arrays in scaled units, and the event."""

    t: np.ndarray
    theta: np.ndarray
    Theta: np.ndarray
    Psi: np.ndarray
    eta: np.ndarray
    varphi: np.ndarray
    b: np.ndarray
    p: np.ndarray
    outcome: object  # Outcome
    time: float  # the event's scaled time (the horizon for SLIP)
    reason: str

    @property
    def normal_force(self) -> np.ndarray:
        """F_z = -b/p (eq. FZ) / (m g): the normal force while slipping."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return -self.b / self.p


def _b(theta, Theta, Psi):
    """Eq. b: the free vertical tip acceleration / g."""
    st, ct = np.sin(theta), np.cos(theta)
    return (Psi * Psi * ct * ct + Theta * Theta) * st - 1.0


def _p(theta, varphi, mu, alpha):
    """Eq. p at the tip."""
    st, ct = np.sin(theta), np.cos(theta)
    return 1.0 + alpha + alpha * st * (mu * ct * np.sin(varphi) - st)


def theory_trajectory(state, mu: float, alpha: float, horizon: float, *, n: int = 400) -> TheoryTrajectory:
    """The theory's slipping trajectory from ``state`` (a ``SlipState``) to its first event within ``horizon``, at ``n``
    points evenly spaced in the desingularised time s (eta p ds = dt, eq. f): the integrator's own steps are too few to draw."""
    from scipy.integrate import solve_ivp

    from crosscheck.theory.slipping import slip_rhs, slip_until_event
    from crosscheck.tolerances import SLIP_INTEGRATION

    first = slip_until_event(state, mu, alpha, t_max=horizon)
    s_end = float(first.s[-1])
    if s_end > 0:

        def rhs(s, y):
            return [*slip_rhs(y[:6], mu, alpha), y[0] * _p(y[4], y[1], mu, alpha)]  # dt/ds = eta p

        y0 = [state.eta, state.varphi, state.psi, state.Psi, state.theta, state.Theta, 0.0]
        sol = solve_ivp(
            rhs,
            (0.0, s_end),
            y0,
            method="DOP853",
            rtol=SLIP_INTEGRATION.rtol,
            atol=SLIP_INTEGRATION.atol,
            t_eval=np.linspace(0.0, s_end, n),
        )
        eta, varphi, _, Psi, theta, Theta, t = sol.y
    else:  # an event at the start: the start alone
        eta, varphi, Psi, theta, Theta, t = (
            np.array([v]) for v in (state.eta, state.varphi, state.Psi, state.theta, state.Theta, 0.0)
        )
    return TheoryTrajectory(
        t=t,
        theta=theta,
        Theta=Theta,
        Psi=Psi,
        eta=eta,
        varphi=varphi,
        b=_b(theta, Theta, Psi),
        p=_p(theta, varphi, mu, alpha),
        outcome=first.outcome,
        time=float(first.time),
        reason=first.reason,
    )


def run_columns(run) -> dict[str, np.ndarray]:
    """The run's record as columns (N rows, scaled units): t, theta, Theta, psi, Psi, eta (slip speed), varphi, gap (contact
    height / l), normal_force / (m g), active, b, p and -b/p (eqs. b, p, FZ on the engine's states)."""
    r = run.record
    b, p = r.b, r.p(run.mu, run.alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        fz = -b / p
    return {
        "t": r.t,
        "theta": r.theta,
        "Theta": r.Theta,
        "psi": r.psi,
        "Psi": r.Psi,
        "eta": r.eta,
        "varphi": r.varphi,
        "gap": r.gap,
        "normal_force": r.normal_force,
        "active": np.asarray(r.active, dtype=int),
        "b": b,
        "p": p,
        "minus_b_over_p": fz,
    }


def write_csv(path: Path | str, columns: dict[str, np.ndarray]) -> Path:
    """Write equal-length ``columns`` as a CSV file (12 significant digits), creating its directory."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(columns)
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names)
        for row in zip(*(np.asarray(columns[k]) for k in names)):
            w.writerow([f"{float(v):.12g}" for v in row])
    return path


def _event_line(ax, t: float, color, label: str | None) -> None:
    if math.isfinite(t):
        ax.axvline(t, color=color, lw=0.9, ls=":", label=label)


def plot_run(run, *, theory: bool = True, path: Path | str | None = None, title: str | None = None):
    """A figure of ``run`` (an engine's ``Run``): theta, Theta, Psi, slip speed, contact height, normal force against -b/p,
    the theory's trajectory from the same start overlaid (dashed) with its event time; saved to ``path`` if given
    (PNG, SVG or PDF by its suffix).  Returns the matplotlib figure."""
    from crosscheck.report.format import engine_label
    from crosscheck.report.plotting import LINE_COLORS, plt

    name = engine_label(run.engine)
    c = run_columns(run)
    th = theory_trajectory(run.state, run.mu, run.alpha, run.horizon) if theory else None
    fig, axes = plt.subplots(2, 3, figsize=(12, 6.4), sharex=True, constrained_layout=True)
    eng, ref = LINE_COLORS[0], "k"
    panels = [
        ("theta", "theta [rad]"),
        ("Theta", "Theta = theta' / omega"),
        ("Psi", "Psi = psi' / omega"),
        ("eta", "slip speed eta / (l omega)"),
        ("gap", "contact height / l"),
    ]
    for ax, (key, label) in zip(axes.flat, panels):
        ax.plot(c["t"], c[key], color=eng, lw=1.2, label=name)
        if th is not None:
            ax.plot(
                th.t,
                {"gap": np.zeros_like(th.t)}.get(key, getattr(th, key, None)),
                color=ref,
                lw=1.0,
                ls="--",
                label="theory (slipping flow)",
            )
        ax.set_ylabel(label)
    ax = axes.flat[5]
    ax.plot(c["t"], c["normal_force"], color=eng, lw=1.2, label=f"{name}: normal force")
    in_contact = np.where(
        c["active"] > 0, c["minus_b_over_p"], np.nan
    )  # -b/p is the slipping rod's force: drawn while in contact
    ax.plot(c["t"], in_contact, color=LINE_COLORS[1], lw=0.9, ls="-.", label=f"-b/p on {name}'s states (in contact)")
    shown = [c["normal_force"][np.isfinite(c["normal_force"])], in_contact[np.isfinite(in_contact)]]
    if th is not None:
        ax.plot(th.t, th.normal_force, color=ref, lw=1.0, ls="--", label="theory: -b/p (eq. FZ)")
        shown.append(th.normal_force[np.isfinite(th.normal_force)])
    vals = np.concatenate(shown) if shown else np.zeros(1)
    if vals.size:  # an impulsive step (a jam) is 1/dt high: keep the slipping force readable, say so in the legend
        lo, hi = np.percentile(vals, [1, 99])
        span = max(hi - lo, 0.5)
        ax.set_ylim(min(lo, 0.0) - 0.1 * span, hi + 0.25 * span)
    ax.set_ylabel("normal force / (m g)")
    for a in axes.flat:
        _event_line(
            a,
            run.event_time,
            eng,
            f"{name}: {run.outcome.name} at {run.event_time:.4g}" if math.isfinite(run.event_time) else None,
        )
        if th is not None:
            _event_line(
                a,
                th.time if th.outcome.name != "SLIP" else math.nan,
                ref,
                f"theory: {th.outcome.name} at {th.time:.4g}",
            )
        a.grid(alpha=0.3)
    for a in axes[1]:
        a.set_xlabel("t (scaled, 1/omega)")
    axes.flat[5].legend(fontsize=7, loc="best")
    axes.flat[0].legend(fontsize=7, loc="best")
    s = run.state
    fig.suptitle(
        title
        or (
            f"{name} from theta {s.theta:g}, varphi {s.varphi:g}, Theta {s.Theta:g}, Psi {s.Psi:g}, eta {s.eta:g}; mu {run.mu:g}, "
            f"alpha {run.alpha:g}: {name} {run.outcome.name}"
            + (f", theory {th.outcome.name}" if th is not None else "")
        ),
        fontsize=10,
    )
    if path is not None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path)
    return fig


def plot_ladder(ladder, *, path: Path | str | None = None, title: str = ""):
    """Every rung of one start's ladder on one figure: a bar from t = 0 to each rung's event, coloured by its outcome,
    labelled with the outcome (and its label as compared), the comparison window shaded, the cause in the title.

    ``ladder``: the result of ``crosscheck.studies.ladder.run_ladder``, or its saved JSON as attributes (``rungs`` with
    ``rung``, ``name``, ``status``, ``outcome``, ``time``, ``label``; ``until`` and ``lag``; ``cause``)."""
    from crosscheck.report.plotting import OUTCOME_COLORS, plt

    rungs = list(ladder.rungs)
    until = float(getattr(ladder, "until", math.nan))
    window = until + float(getattr(ladder, "lag", 0.0))
    times = [r.time for r in rungs if r.status == "ok" and math.isfinite(r.time)]
    t_max = max([window if math.isfinite(window) else 0.0, *times, 1e-3]) * 1.15
    fig, ax = plt.subplots(figsize=(9, 0.55 * len(rungs) + 1.6), constrained_layout=True)
    for k, r in enumerate(rungs):
        y = len(rungs) - 1 - k
        if r.status != "ok":
            ax.text(0.0, y, f"  {r.status}: {getattr(r, 'detail', '')}"[:90], va="center", fontsize=8, color="#a11")
            continue
        end = r.time if math.isfinite(r.time) else t_max
        color = OUTCOME_COLORS.get(int(r.outcome), (0.6, 0.6, 0.6))
        ax.barh(y, end, color=color, edgecolor="k", lw=0.5, height=0.6)
        relabel = "" if r.label is None or r.label == r.outcome else f" -> {r.label.name} as compared"
        when = f" at {r.time:.4g}" if math.isfinite(r.time) else " (no event)"
        ax.text(end, y, f" {r.outcome.name}{when}{relabel}", va="center", fontsize=8)
    if math.isfinite(window):
        ax.axvspan(window, t_max * 2, color="0.9", zorder=0)
        ax.axvline(window, color="0.4", lw=0.8, ls="--")
        ax.text(window, len(rungs) - 0.45, " compared up to here", fontsize=7, color="0.3", va="bottom")
    labels = []
    for r in rungs:
        what = getattr(r, "cause", None)
        labels.append(f"{r.rung} {r.name}" + (f" ({what})" if what else ""))
    ax.set_yticks(range(len(rungs)), labels[::-1], fontsize=8)
    ax.set_xlim(0, t_max * 1.35)
    ax.set_ylim(-0.7, len(rungs) - 0.2)
    ax.set_xlabel("t (scaled, 1/omega): each bar ends at the rung's first event")
    ax.set_title(title or f"cause: {getattr(ladder, 'cause', '?')}", fontsize=10)
    if path is not None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path)
    return fig
