"""Figures share their mathtext parses within a process, draw exactly as with matplotlib's own per-renderer caches,
and never carry a parse (and the fonts it holds) across a fork into the render's workers."""

from __future__ import annotations

import functools
import multiprocessing

import numpy as np
from matplotlib.mathtext import MathTextParser

from crosscheck.report.plotting import MATHTEXT_PARSES, plt, save_figure


def _figure_bytes(tmp_path, name: str) -> tuple[bytes, bytes]:
    """A figure with the report's kinds of mathtext (a symbol, a subscript in a title, a log axis's ticks), saved
    as the report saves every figure; its PNG and SVG bytes."""
    fig, ax = plt.subplots(figsize=(4, 3))
    x = np.logspace(-4, 0, 20)
    ax.loglog(x, x**2)
    ax.set_xlabel(r"$\theta$")
    ax.set_title(r"$\Psi_L$ = 1.6119, $\varphi\in(-\pi,0]$")
    save_figure(fig, tmp_path / name)
    return (tmp_path / f"{name}.png").read_bytes(), (tmp_path / f"{name}.svg").read_bytes()


def test_a_shared_parse_draws_every_figure_byte_for_byte_as_matplotlibs_own_caches(tmp_path, monkeypatch):
    assert MATHTEXT_PARSES is not None, (
        "matplotlib no longer has MathTextParser._parse_cached: the report's figures parse per renderer"
    )
    with monkeypatch.context() as m:  # matplotlib's own: one cache per renderer (each savefig makes a new one)
        m.setattr(MathTextParser, "_parse_cached", functools.lru_cache(50)(MATHTEXT_PARSES.matplotlib_parse))
        own = _figure_bytes(tmp_path, "own")
    MATHTEXT_PARSES.cache_clear()
    first = _figure_bytes(tmp_path, "first")
    hits = MATHTEXT_PARSES.cache_info().hits
    again = _figure_bytes(tmp_path, "again")
    assert MATHTEXT_PARSES.cache_info().hits > hits  # the second figure's labels came from the first's parses
    assert first == own and again == own


def _shared_parses_in_child(_):
    return MATHTEXT_PARSES.cache_info().currsize


def test_a_forked_process_starts_without_the_parses_of_its_parent(tmp_path):
    # a vector parse holds FreeType fonts whose file offset a fork shares: the parent drawing while its forked
    # render workers read those fonts' tables garbled glyphs ("failed to load glyph")
    _figure_bytes(tmp_path, "parent")
    assert MATHTEXT_PARSES.cache_info().currsize > 0
    with multiprocessing.get_context("fork").Pool(1) as pool:
        assert pool.map(_shared_parses_in_child, [0]) == [0]
    assert MATHTEXT_PARSES.cache_info().currsize > 0  # the parent keeps its own
