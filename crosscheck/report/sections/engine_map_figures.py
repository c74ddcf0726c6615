"""The figures, tables and interactive page of an engine's outcome maps (the section ``engine_maps`` runs them).

Per map the analytic first event, the engine's outcome, the outcome of the engine drawn beside it, and where the
engine and the analytic model disagree (orange on an analytic boundary, red inside); then the confusion matrix of
all maps, the disagreements by distance to the analytic boundary and the event-time errors.
"""

from __future__ import annotations

import numpy as np

from crosscheck.report.outcomes import NOT_SLIPPING, OUTCOME_NAMES, boundary_cells
from crosscheck.report.section import RenderContext, Table, Text

__all__ = ["render"]


def _floors(maps: list) -> str:
    floors = sorted({r["stick_floor"] for mp in maps for r in mp["runs"] if r.get("stick_floor") is not None})
    return ", ".join(f"{f:g}" for f in floors) or "-"


def _stick_as_slip(maps: list) -> str:
    n = sum(int(r.get("stick_as_slip") or 0) for mp in maps for r in mp["runs"])
    return f"{n} start{'' if n == 1 else 's'}"


def _label(name: str) -> str:
    return f"$\\{name}$"  # the axes are Greek letters of the paper


def _beside(ctx: RenderContext, slug: str | None):
    """The saved results of the section drawn beside this one (its store and its engine's name), or (None, "") if absent."""
    from crosscheck.report.store import SectionStore

    if not slug:
        return None, ""
    store = SectionStore(ctx.store.root.parent / slug)
    if not store.exists("maps.json") or not store.exists("status.json"):
        return None, ""
    return store, store.read_json("status")["params"]["engine"]


def render(ctx: RenderContext) -> list:
    from crosscheck.report.format import engine_label
    from crosscheck.report.interactive import outcome_maps_page, write_page
    from crosscheck.report.plotting import OUTCOME_COLORS

    P = ctx.params
    engine, name = P["engine"], engine_label(P["engine"])
    maps = ctx.store.read_json("maps")
    colors = {**OUTCOME_COLORS, NOT_SLIPPING: (0.8, 0.8, 0.8)}
    opts = ", ".join(f"{k} {v:g}" for k, v in P["options"].items())
    other, other_engine = _beside(ctx, P.get("beside"))
    blocks = [_intro(ctx, maps, name, opts, None if other is None else engine_label(other_engine))]
    blocks += _warnings(maps, name)
    blocks += _compliant_jams(ctx, name)
    page_rel = f"figures/{ctx.slug}/outcome_maps.html"
    pages, boundary_rows = [], []
    conf = 0
    diffs = {"difference": [], "outcome": []}
    for mp in maps:
        block, page, row = _map(ctx, mp, engine, name, other, other_engine, colors)
        block.data.append(page_rel)
        blocks.append(block)
        pages.append(page)
        boundary_rows.append(row)
        (run,) = mp["runs"]
        conf = conf + np.asarray(run["confusion"])
        for k in ("difference", "outcome"):
            diffs[k] += mp["time_difference"][k]
    names_ = {
        **{k: OUTCOME_NAMES[k].lower() for k in sorted(OUTCOME_COLORS)},
        NOT_SLIPPING: "not slipping at t = 0 (not compared)",
    }
    write_page(
        ctx.out / page_rel,
        outcome_maps_page(
            f"Analytic vs {name}: outcome maps (hover a cell)",
            pages,
            colors=colors,
            names=names_,
            intro=f"Each cell is one start (alpha = {P['alpha']:g}, scaled units); its tooltip gives the state, b and p "
            f"(eqs. b, p), the analytic first event and time, and each engine's outcome and time ({name}: {opts}).",
        ),
    )
    blocks.append(_confusion(ctx, maps, conf, name))
    blocks.append(
        Table(
            caption=f"Where {name} disagrees: compared starts on an analytic boundary of the map against the interior.",
            header=["map", "compared", "on a boundary", "disagree", "of which on a boundary", "interior"],
            rows=boundary_rows,
            data=ctx.data("maps.json"),
        )
    )
    blocks += _by_distance(ctx, maps)
    if diffs["difference"]:
        blocks += _event_time_errors(ctx, diffs, name)
    return blocks


def _intro(ctx: RenderContext, maps: list, name: str, opts: str, other_name: str | None) -> Text:
    """What a cell and each panel of the maps are."""
    P = ctx.params
    return Text(
        f"Each cell is one start (alpha = {P['alpha']:g}), compared over the scaled horizon {P['horizon']:g} by "
        f"`crosscheck.studies.agreement.agreement_study` ({name}: {opts}). Grey: not "
        f"slipping at t = 0 (b >= 0 or p <= 0), not compared. Panels: the analytic first event, {name}'s outcome (counted only up to the "
        "analytic comparison time; a JAM is judged against the engine's own friction direction), "
        + (f"{other_name}'s outcome on the same starts (its own section), " if other_name is not None else "")
        + "and where "
        f"{name} and the analytic model disagree. A {name} STICK where the theory slips on but slower than {name}'s STICK "
        f"floor (slip speed {_floors(maps)}, below which the classifier calls a contact stuck) is compared as that slip, "
        f"which it cannot be told from (`crosscheck.studies.comparison.stick_from`; {_stick_as_slip(maps)} here). Hover the cells of the interactive maps (`figures/{ctx.slug}/outcome_maps.html`, "
        "linked under each map) for each start's state and its analytic and engine outcomes and times."
    )


def _warnings(maps: list, name: str) -> list:
    """The engine's own console warnings during the runs, captured (MuJoCo's: crosscheck.engines.mujoco.warning_counts;
    DART's: crosscheck.engines.dart.console)."""
    warned: dict[str, int] = {}
    for mp in maps:
        for r in mp["runs"]:
            for kind, count in (r.get("engine_warnings") or {}).items():
                warned[kind] = warned.get(kind, 0) + int(count)
    if not warned:
        return []
    return [
        Text(
            f"{name} warned during these runs: "
            + "; ".join(f'{n} x "{k}"' for k, n in sorted(warned.items()))
            + ". "
            + (
                "Each is MuJoCo resetting a run after an instability. "
                if name == "MuJoCo"
                else "Each is one warning line the engine printed, counted instead of shown. "
            )
            + "The classifier records a run's divergence (DIVERGED unless an event came first)."
        )
    ]


def _compliant_jams(ctx: RenderContext, name: str) -> list:
    """The JAMs below mu_P that the engine's compliant law gives (``engine_maps._check_no_iwc``): an engine finding, named."""
    if not ctx.store.exists("jams_below_mu_P.json"):
        return []
    doc = ctx.store.read_json("jams_below_mu_P")
    jams, twin = [j for j in doc["jams"] if j["kind"] == "compliant"], doc["compliant_twin"]
    stiffer = doc["stiffer"]
    if not jams:
        return []
    starts = "; ".join(
        f"theta {j['theta']:g}, varphi {j['varphi']:g}, Psi {j['Psi']:g}, Theta {j['Theta']:g}, mu {j['mu']:g} "
        f"(JAM at t = {j['event_time']:g})"
        for j in jams
    )
    return [
        Text(
            f"Engine finding: below mu_P, where the rigid theory forbids it (p > 0), {name} jams from {len(jams)} "
            f"start{'' if len(jams) == 1 else 's'}: {starts}. The compliant rod with its contact law (eps "
            f"{twin['eps']:g}, xi {twin['xi']:g}, r {twin['radius']:g}) jams there too and slips at eps / {stiffer:g}: "
            "a compliant contact of finite eps stops the slip hard where p > 0 is small (its normal mode's time "
            "eps / sqrt(p) is not short against the slip), which only the rigid limit eps -> 0 rules out."
        )
    ]


def _map(ctx: RenderContext, mp: dict, engine: str, name: str, other, other_engine, colors: dict):
    """One map: its figure (analytic, engine, the engine beside, where they differ), its interactive page and its row
    of the boundary table."""
    from matplotlib.patches import Patch

    from crosscheck.report.format import engine_label
    from crosscheck.report.interactive import GridMap, Panel, engine_line, start_tooltip
    from crosscheck.report.plotting import categorical_image, outcome_legend, plt

    other_name = engine_label(other_engine)
    t = ctx.store.read_table(f"events_{mp['name']}", text=("analytic_reason",))
    x, y = np.asarray(mp["x"]["values"]), np.asarray(mp["y"]["values"])
    # EventGrid points are in C order of (theta, varphi, Theta, Psi, mu, eta): put them on the (y, x) image grid
    xi = np.abs(t[mp["x"]["name"]][:, None] - x[None, :]).argmin(axis=1)  # nearest: the CSV keeps 12 digits
    yi = np.abs(t[mp["y"]["name"]][:, None] - y[None, :]).argmin(axis=1)

    def image(values):
        img = np.full((y.size, x.size), np.nan)
        img[yi, xi] = values
        return img

    slipping = t["slipping"] == 1
    a = np.where(slipping, t["analytic_outcome"], NOT_SLIPPING)
    o = (
        other.read_table(f"events_{mp['name']}", text=("analytic_reason",))
        if other is not None and other.exists(f"events_{mp['name']}.csv")
        else None
    )
    panels = 3 if o is None else 4
    fig, axes = plt.subplots(1, panels, figsize=(3.85 * panels, 3.6), sharey=True)
    categorical_image(axes[0], x, y, image(a), colors)
    axes[0].set_title("analytic first event")
    categorical_image(axes[1], x, y, image(t[engine]), colors)
    axes[1].set_title(name)
    # below the panels, not over the data, with every colour used: grey is "not compared"
    used = [a[slipping], t[engine][slipping]] + ([o[other_engine][o["slipping"] == 1]] if o is not None else [])
    handles = outcome_legend(axes[1], np.concatenate(used)).legend_handles
    axes[1].get_legend().remove()
    handles.append(Patch(color=colors[NOT_SLIPPING], label="not slipping at t = 0 (not compared)"))
    fig.legend(
        handles=handles, loc="outside lower center", ncol=len(handles), fontsize=7, frameon=False
    )  # constrained layout makes room
    if o is not None:
        img, oi, oj = _on_grid(o, mp, x, y, o[other_engine])
        categorical_image(axes[2], x, y, img, colors)
        axes[2].set_title(f"{other_name} (beside)")
    a_img = image(a)
    edge = boundary_cells(np.nan_to_num(a_img, nan=-9))
    m_img = image(t[engine])
    # the same panels as SVG cells whose tooltips give each start (crosscheck.report.interactive)
    tips = [[""] * x.size for _ in y]
    for k in range(a.size):
        tips[yi[k]][xi[k]] = start_tooltip(t, k) + "\n" + engine_line(t, k, engine, name)
    svg_panels = [Panel("analytic first event", a_img), Panel(name, m_img)]
    if o is not None:
        for k in range(len(o[other_engine])):
            tips[oj[k]][oi[k]] += "\n" + engine_line(o, k, other_engine, other_name)
        svg_panels.append(Panel(f"{other_name} (beside)", img))
    agree = np.where(a_img == NOT_SLIPPING, NOT_SLIPPING, np.where(a_img == m_img, 0, np.where(edge, 1, 2)))
    categorical_image(
        axes[-1],
        x,
        y,
        agree,
        {NOT_SLIPPING: (0.8, 0.8, 0.8), 0: (0.95, 0.95, 0.95), 1: (0.95, 0.6, 0.2), 2: (0.8, 0.0, 0.0)},
    )
    axes[-1].set_title(f"{name} differs (orange: boundary, red: interior)", fontsize=9)
    for ax in axes:
        ax.set_xlabel(_label(mp["x"]["name"]))
    axes[0].set_ylabel(_label(mp["y"]["name"]))
    fixed = ", ".join(f"{k} = {v:g}" for k, v in mp["fixed"].items())
    (run,) = mp["runs"]
    block = ctx.figure(
        f"map_{mp['name']}",
        fig,
        f"Analytic vs {name} over ({mp['x']['name']}, {mp['y']['name']}) at {fixed}: {int(slipping.sum())} of {a.size} starts slip at t = 0; "
        f"{name} agrees on {100 * run['agreement']:.0f}% of the rated ones.",
        [f"events_{mp['name']}.csv", f"study_{mp['name']}.json", "maps.json"],
    )
    page = GridMap(
        f"({mp['x']['name']}, {mp['y']['name']}) at {fixed}",
        mp["x"]["name"],
        mp["y"]["name"],
        x,
        y,
        svg_panels,
        tips,
    )
    return block, page, _boundary_row(mp["name"], slipping, edge, agree)


def _on_grid(t: dict, mp: dict, x, y, values):
    """(image, column, row): ``values`` of the rows of the events table t on the map's (y, x) image grid (NaN where no
    start), and each start's column and row.  The CSV keeps 12 digits: each start goes to the nearest grid value."""
    xi = np.abs(t[mp["x"]["name"]][:, None] - x[None, :]).argmin(axis=1)
    yi = np.abs(t[mp["y"]["name"]][:, None] - y[None, :]).argmin(axis=1)
    img = np.full((y.size, x.size), np.nan)
    img[yi, xi] = values
    return img, xi, yi


def _boundary_row(name: str, slipping, edge, agree) -> list[str]:
    """The map's row of the boundary table: compared starts, those on an analytic boundary, the disagreements, of
    them on a boundary (``agree`` 1) and inside (2)."""
    return [
        name,
        str(int(slipping.sum())),
        str(int((edge & (agree != NOT_SLIPPING)).sum())),
        str(int(((agree == 1) | (agree == 2)).sum())),
        str(int((agree == 1).sum())),
        str(int((agree == 2).sum())),
    ]


def _confusion(ctx: RenderContext, maps: list, conf, name: str):
    """The confusion matrix of all maps as a figure (the counts in its cells)."""
    from crosscheck.report.plotting import plt

    used = [
        i for i in range(len(conf)) if conf[i].sum() or conf[:, i].sum()
    ]  # results saved before an outcome was added have fewer
    sub = conf[np.ix_(used, used)]
    names = [OUTCOME_NAMES[i].lower() for i in used]
    fig, ax = plt.subplots(figsize=(4.6, 3.8))
    ax.imshow(np.log1p(sub), cmap="Blues")
    for i in range(len(used)):
        for j in range(len(used)):
            ax.text(
                j,
                i,
                str(sub[i, j]),
                ha="center",
                va="center",
                fontsize=9,
                color="k" if sub[i, j] < sub.max() / 2 else "w",
            )
    ax.set_xticks(range(len(used)), names, rotation=30)
    ax.set_yticks(range(len(used)), names)
    ax.set_xlabel(name)
    ax.set_ylabel("analytic first event")
    total, diag = int(sub.sum()), int(np.trace(sub))
    # the counts are printed in the cells and saved in maps.json: no second copy as a table
    return ctx.figure(
        "confusion",
        fig,
        f"Confusion matrix, all maps (rows: analytic first event; columns: {name} as compared; the count "
        f"in each cell): {diag} of {total} compared starts on the diagonal ({100 * diag / max(total, 1):.0f}%).",
        ["maps.json"] + [f"study_{mp['name']}.json" for mp in maps],
    )


def _by_distance(ctx: RenderContext, maps: list) -> list:
    """Agreement by the probed distance of a start to the analytic boundary (a table, when the maps probed it)."""
    dist_rows = []
    for mp in maps:
        (run,) = mp["runs"]
        for b in run.get("by_distance", []):
            if b["n"] and b["agreement"] is not None:
                dist_rows.append(
                    [
                        mp["name"],
                        f"[{b['distance'][0]:g}, {b['distance'][1]:g})",
                        str(b["n"]),
                        f"{100 * b['agreement']:.0f}%",
                    ]
                )
    if not dist_rows:  # the quick report does not probe the distance (boundary_directions = 0)
        return []
    return [
        Table(
            caption="Agreement by the probed distance of the start to the analytic event boundary (scaled units).",
            header=["map", "distance", "n", "agreement"],
            rows=dist_rows,
            data=ctx.data(*[f"study_{mp['name']}.json" for mp in maps]),
        )
    ]


def _event_time_errors(ctx: RenderContext, diffs: dict, name: str) -> list:
    """Where the engine and the analytic model report the same event: a histogram of their time differences and a
    table of them."""
    from crosscheck.report.plotting import OUTCOME_COLORS, plt

    dd, oo = np.asarray(diffs["difference"]), np.asarray(diffs["outcome"])
    fig, ax = plt.subplots(figsize=(6, 3.6))
    rows = []
    bins = np.histogram_bin_edges(dd, bins=30)  # one set of bins for every event, stacked: each stays visible
    stack, colors_, labels = [], [], []
    for event, code in (("LIFTOFF", 1), ("STICK", 2), ("JAM", 3)):
        s = oo == event
        if s.any():
            stack.append(dd[s])
            colors_.append(OUTCOME_COLORS[code])
            labels.append(f"{event.lower()} ({int(s.sum())})")
            rows.append(
                [
                    event.lower(),
                    str(int(s.sum())),
                    f"{np.median(dd[s]):+.3g}",
                    f"{np.median(np.abs(dd[s])):.3g}",
                    f"{np.max(np.abs(dd[s])):.3g}",
                ]
            )
    ax.hist(stack, bins=bins, color=colors_, label=labels, stacked=True, edgecolor="k", lw=0.3)
    ax.set_xlabel(f"t_{name} - t_analytic (scaled)")
    ax.set_ylabel("starts (stacked by event)")
    ax.legend(fontsize=7)
    return [
        ctx.figure(
            "event_time_errors",
            fig,
            f"Event-time errors where {name} and the analytic model report the same event, all maps.",
            ["maps.json"],
        ),
        Table(
            caption=f"Event-time differences ({name} - analytic, scaled time).",
            header=["event", "n", "median", "median |diff|", "max |diff|"],
            rows=rows,
            data=ctx.data("maps.json"),
        ),
    ]
