"""The report's figures are laid out once, at the PNG's dpi, and both files keep that layout (``plotting.save_figure``)."""

from __future__ import annotations

import re

import numpy as np

from crosscheck.report.plotting import plt, save_figure


def _figure():
    """Two axes with what moves a constrained layout: tick labels of a log axis, mathtext labels, a title, a legend."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(6, 3))
    x = np.linspace(0.01, 1, 50)
    a.plot(x, np.sin(5 * x), label="sin")
    a.legend()
    a.set_xlabel(r"$\theta$")
    b.semilogy(x, np.exp(8 * x))
    b.set_ylabel(r"$\Psi_L$ (scaled)")
    b.set_title("a title")
    return fig, a


def test_the_png_is_byte_for_byte_matplotlibs_own_constrained_layout_at_save_time(tmp_path):
    own, _ = _figure()
    own.savefig(tmp_path / "own.png", metadata={"Software": None})  # matplotlib lays it out inside savefig
    plt.close(own)
    fig, _ = _figure()
    save_figure(fig, tmp_path / "ours")
    assert (tmp_path / "ours.png").read_bytes() == (tmp_path / "own.png").read_bytes()


def test_the_svg_keeps_the_pngs_layout_instead_of_laying_out_again_at_its_own_dpi(tmp_path):
    own, own_axes = _figure()
    own.savefig(tmp_path / "own.png")  # the layout at the PNG's dpi, which the axes keep after savefig
    want = own_axes.get_position()
    width, height = (72 * x for x in own.get_size_inches())  # SVG user units are points
    plt.close(own)
    fig, _ = _figure()
    save_figure(fig, tmp_path / "ours")
    svg = (tmp_path / "ours.svg").read_text()
    # the first axes' background patch: M x0 y_bottom L x1 y_bottom L x1 y_top L x0 y_top, y down from the top
    frame = re.search(
        r'<g id="axes_1">\s*<g id="patch_2">\s*<path d="M ([-\d.]+) ([-\d.]+)\s*L ([-\d.]+) [-\d.]+\s*L [-\d.]+ ([-\d.]+)',
        svg,
    )
    x0, y_bottom, x1, y_top = (float(v) for v in frame.groups())
    # the SVG writes 6 decimals: 1e-6 pt; a layout at 72 dpi moves the frame by tenths of a point
    assert np.allclose(
        [x0, x1, y_top, y_bottom],
        [want.x0 * width, want.x1 * width, (1 - want.y1) * height, (1 - want.y0) * height],
        rtol=0,
        atol=1e-5,
    )
