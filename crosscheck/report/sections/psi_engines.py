"""Every engine across the paper's three critical values of Psi: outcome shares against |Psi| with Psi_L, Psi_1, Psi_2
marked, jams above Psi_2 and choices at indeterminate starts.

Gathers the saved results of each engine's ``<slug>_psi`` section (``engine_psi``) and, where it ran, its lift-off
onset (``<slug>_liftoff``) once they have finished, keeps a copy of their numbers (so ``--from-results`` redraws it),
and draws one panel per engine.  Reads the registry when the report is built.  Scaled units (section 2.1).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from crosscheck.report.section import RenderContext, RunContext, Section, Table

SLUG = "psi_engines"

#: The |Psi| bins of the figure's shares.
BIN_EDGES = (1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0)


def params(quick: bool, slugs: list) -> dict:
    return {"engines": list(slugs), "bin_edges": list(BIN_EDGES)}


def run(ctx: RunContext) -> None:
    cols = {k: [] for k in ("engine", "abs_Psi", "theory_outcome", "engine_outcome")}
    summaries = []
    for slug in ctx.params["engines"]:
        done = ctx.finished(f"{slug}_psi")
        if done is None:
            continue
        s = done[1].read_json("summary")
        t = done[1].read_table("slipping")
        onset = ctx.finished(f"{slug}_liftoff")
        if onset is not None and (onset[1].root / "onset.csv").is_file():
            rows = list(csv.DictReader((onset[1].root / "onset.csv").open()))
            errs = [abs(float(r["onset_minus_Psi_L"])) for r in rows if r.get("onset_minus_Psi_L") not in ("", "nan")]
            s["onset_error"] = max(errs) if errs else None
        summaries.append(s)
        n = len(t["Psi"])
        cols["engine"] += [s["engine"]] * n
        cols["abs_Psi"] += np.abs(t["Psi"]).tolist()
        cols["theory_outcome"] += t["theory_outcome"].astype(int).tolist()
        cols["engine_outcome"] += t["engine_outcome"].astype(int).tolist()
    ctx.store.write_table("outcomes", cols)
    ctx.store.write_json("summaries", summaries)


def _shares(outcome: np.ndarray, abs_Psi: np.ndarray, edges: np.ndarray, code: int) -> np.ndarray:
    k = np.digitize(abs_Psi, edges) - 1
    return np.array([np.mean(outcome[k == i] == code) if (k == i).any() else np.nan for i in range(len(edges) - 1)])


def render(ctx: RenderContext) -> list:
    from crosscheck.outcome import Outcome
    from crosscheck.report.format import engine_label
    from crosscheck.report.plotting import OUTCOME_COLORS, plt

    t = ctx.store.read_table("outcomes", text=("engine",))
    summaries = ctx.store.read_json("summaries")
    edges = np.array(ctx.params["bin_edges"])
    mid = 0.5 * (edges[1:] + edges[:-1])
    names = list(dict.fromkeys(t["engine"].tolist()))
    ncol = min(4, max(1, len(names)))
    nrow = max(1, -(-len(names) // ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.2 * ncol, 2.8 * nrow), sharex=True, sharey=True, squeeze=False)
    codes = (Outcome.SLIP, Outcome.LIFTOFF, Outcome.STICK, Outcome.JAM, Outcome.LAUNCH)
    for ax, name in zip(axes.flat, names):
        m = t["engine"] == name
        for o in codes:
            c = OUTCOME_COLORS.get(int(o), "0.5")
            e = _shares(t["engine_outcome"][m].astype(int), t["abs_Psi"][m], edges, int(o))
            a = _shares(t["theory_outcome"][m].astype(int), t["abs_Psi"][m], edges, int(o))
            ax.plot(mid, e, "-o", ms=3, color=c, label=o.name.lower())
            ax.plot(mid, a, "--", color=c, lw=0.9)
        s = next(x for x in summaries if x["engine"] == name)
        for v, lab in ((s["Psi_L"], "Psi_L"), (s["Psi_1"], "Psi_1"), (s["Psi_2"], "Psi_2")):
            ax.axvline(v, color="k", lw=0.7, ls=":")
            ax.text(v, 1.02, lab, fontsize=6, ha="center", transform=ax.get_xaxis_transform())
        ax.set_title(engine_label(name), fontsize=8, pad=10)
    for ax in axes.flat[len(names) :]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("|Psi| at the start")
    for ax in axes[:, 0]:
        ax.set_ylabel("share of starts")
    axes.flat[0].legend(fontsize=6)
    cap = (
        "Outcome shares of the slipping starts (b < 0 < p, mu = 1.4) by |Psi| at the start, each engine (solid) "
        "against the "
        "theory's slipping flow (dashed), with Psi_L, Psi_1 and Psi_2 marked (section 3.3)."
    )
    return [ctx.figure("outcome_shares", fig, cap, ["outcomes.csv", "summaries.json"]), _table(ctx, summaries)]


def _table(ctx: RenderContext, summaries: list) -> Table:
    from crosscheck.report.format import engine_label

    rows = []
    if summaries:
        b = summaries[0]["bands"]
        rows.append(["theory (slipping flow)", "0", *[f"{x['theory_jams']} of {x['n']}" for x in b], "0", "-", "-"])
    for s in summaries:
        base = s["settings"][0]["choices"] if s["settings"] else {}
        same = s["same_choice_two_finest"]
        onset = s.get("onset_error")
        rows.append(
            [
                engine_label(s["engine"]),
                "-" if onset is None else f"{onset:.2g}",
                *[f"{x['engine_jams']} of {x['n']}" for x in s["bands"]],
                str(s["ruled_out_jams"]),
                ", ".join(f"{k} {v}" for k, v in base.items()) or "-",
                "-" if same is None else f"{100 * same:.0f} %",
            ]
        )
    b = summaries[0]["bands"] if summaries else [{"lo": lo, "hi": hi} for lo, hi in ((1.95, 3.0), (3.1, 5.0))]
    return Table(
        caption=(
            "The critical values of Psi on every engine: its worst lift-off onset error |onset - Psi_L| (its onset "
            "section), "
            "its jams at the slipping starts of each band of |Psi|, its jams with |Psi| > Psi_2 at the jam (ruled out "
            "by the "
            "paper's theorem: no inconsistent state exists there; an engine that makes one is wrong), what it chooses "
            "at the "
            "indeterminate starts above Psi_1 at its maps' options, and the share of them where its two finest "
            "settings "
            "choose the same."
        ),
        header=[
            "engine",
            "onset |Psi - Psi_L|",
            *[f"jams, |Psi| in ({x['lo']:g}, {x['hi']:g})" for x in b],
            "jams with |Psi| > Psi_2",
            "indeterminate: choices",
            "same choice, two finest settings",
        ],
        rows=rows,
        data=ctx.data("summaries.json", "outcomes.csv"),
    )


def finding(data: Path) -> list:
    """Two findings lines: each engine's jams above Psi_2 (ruled out by the theorem), and its choices at indeterminate
    starts."""
    from crosscheck.report.finding import Finding, read_json
    from crosscheck.report.format import engine_label

    summaries = read_json(data / "summaries.json") or []
    if not summaries:
        return []
    wrong = [s for s in summaries if s["ruled_out_jams"]]
    psi2 = summaries[0]["Psi_2"]
    jams = "; ".join(f"{engine_label(s['engine'])} {s['ruled_out_jams']} of {s['n_slipping']}" for s in summaries)
    choices = "; ".join(
        f"{engine_label(s['engine'])} " + ", ".join(f"{k.lower()} {v}" for k, v in s["settings"][0]["choices"].items())
        for s in summaries
        if s["settings"]
    )
    lift = all(set(s["settings"][0]["choices"]) == {"LIFTOFF"} for s in summaries if s["settings"])
    return [
        Finding(
            "jams above Psi_2",
            f"slipping starts whose jam comes with |Psi| > Psi_2 = {psi2:.4f}: {jams}",
            "none"
            if not wrong
            else f"{len(wrong)} engine{'s' if len(wrong) > 1 else ''} jam where the theorem rules it out",
            data.name,
            why="section 3.3: for |Psi| >= Psi_2 no state has p < 0 with b < 0, so a slipping rod cannot jam; any such "
            "jam is wrong",
        ),
        Finding(
            "indeterminate starts above Psi_1",
            "at Theta = 0, p < 0 < b (the theory allows lift-off or an impulsive stop), each engine chooses: "
            f"{choices}",
            "all lift off" if lift else "engines choose differently",
            data.name,
            why="the compliant theory's choice for a contact that starts untouched is lift-off "
            "(crosscheck.theory.compliant_limit.indeterminate_boundary)",
        ),
    ]


def section(specs) -> Section:
    """The cross-engine section over the engines ``specs`` with a Psi section (``engine_psi``)."""
    slugs = [s.slug for s in specs if s.report is not None and s.report.maps is not None]
    after = [f"{s}_psi" for s in slugs] + [
        f"{s.slug}_liftoff" for s in specs if s.report is not None and s.report.maps is not None and s.report.onset
    ]
    return Section(
        slug=SLUG,
        title="The critical values Psi_L, Psi_1 and Psi_2, every engine",
        paper="section 3.3, eqs. psil, psi1, psi2",
        params=lambda quick: params(quick, slugs),
        run=run,
        render=render,
        finding=finding,
        after=tuple(after),
    )
