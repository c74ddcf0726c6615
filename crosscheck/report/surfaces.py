"""The surfaces b = 0 and p = 0 in (theta, varphi, Theta) at fixed Psi (Figs. 3-7): their meshes and their 3D drawing.

b = 0 (eq. b) is the graph Theta = sqrt(1/sin theta - Psi^2 cos^2 theta) over every varphi where the root is real;
p = 0 (eq. p) is the cylinder over the closed curve varphi = varphi_-+(theta), theta in [theta_1, theta_2] (eqs.
varphistar, theta12); they meet in the GB manifold.  ``surface_meshes`` samples the three as tables to save,
``draw_surfaces`` draws them as the paper does (the sections ``kinematic_surfaces`` and ``bifurcations``).
"""

from __future__ import annotations

import math

import numpy as np

from crosscheck.theory import critical
from crosscheck.tolerances import CLOSED_FORM

__all__ = ["Theta2_on_b0", "b0_pieces", "p0_cylinder", "surface_meshes", "draw_surfaces"]


def Theta2_on_b0(Psi, theta):
    """Theta^2 on b = 0 (eq. b): 1/sin theta - Psi^2 cos^2 theta; negative where b > 0 already at Theta = 0."""
    return 1.0 / np.sin(theta) - Psi**2 * np.cos(theta) ** 2


def b0_pieces(Psi: float, Theta_max: float, *, n: int = 20001) -> list[tuple[float, float]]:
    """theta intervals of (0, pi/2] where b = 0 has a root 0 <= Theta <= Theta_max, edges refined by brentq.

    Theta^2 on b = 0 tends to +inf as theta -> 0 (clipped at Theta_max) and to 1
    at theta = pi/2; it is negative in the theta gap (|Psi| > Psi_L).  A
    double root (|Psi| = Psi_L at theta_L) is not an edge: the surface touches
    Theta = 0 there and the interval goes on.
    """
    from scipy.optimize import brentq

    theta = np.linspace(0.0, np.pi / 2, n)[1:]
    g = Theta2_on_b0(Psi, theta)
    inside = (g >= 0) & (g <= Theta_max**2)
    pieces = []
    for lo_i, hi_i in _runs(inside):
        ends = []
        for i, side in ((lo_i, -1), (hi_i, +1)):
            j = i + side
            if j < 0 or j >= theta.size:  # the run reaches the end of the sampled range (theta = pi/2)
                ends.append(float(theta[i]))
                continue
            level = 0.0 if g[j] < 0 else Theta_max**2
            a, b = sorted((float(theta[i]), float(theta[j])))
            ends.append(brentq(lambda t: Theta2_on_b0(Psi, t) - level, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps))
        pieces.append((ends[0], ends[1]))
    return pieces


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    # (first, last) index of each run of True
    d = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


def _spaced(lo: float, hi: float, n: int) -> np.ndarray:
    # cosine spacing: Theta on b = 0 and varphi on p = 0 have square-root ends
    return lo + (hi - lo) * 0.5 * (1 - np.cos(np.pi * np.linspace(0.0, 1.0, n)))


def p0_cylinder(mu: float, alpha: float, *, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The closed curve p = 0 in (theta, varphi) (eqs. varphistar, theta12): theta_1 -> theta_2 on varphi_-, back on varphi_+.

    Returns (theta, varphi), 2n - 1 samples, the last equal to the first.
    """
    cv = critical.critical_values(mu, alpha)
    th = _spaced(cv.theta_1, cv.theta_2, n)
    vm, vp = critical.varphi_pm(th, mu, alpha)
    # varphi_-+ meet at -pi/2 where theta = theta_1,2; rounding of the arccos argument can leave NaN there
    vm, vp = np.where(np.isnan(vm), -np.pi / 2, vm), np.where(np.isnan(vp), -np.pi / 2, vp)
    return np.concatenate([th, th[::-1][1:]]), np.concatenate([vm, vp[::-1][1:]])


def surface_meshes(
    mu: float,
    Psi: float,
    alpha: float,
    Theta_max: float,
    *,
    n_surface: int,
    n_varphi: int,
    n_Theta: int,
    n_gb: int,
    n_fine: int = 20001,
) -> dict:
    """The 3D picture at one (mu, Psi) as tables (columns of equal length) ready to save and draw.

    Returns a dict with
      "b0": piece, i, j, theta, varphi, Theta: the mesh of b = 0 for Theta in [0, Theta_max] (i along theta, j along varphi);
      "p0": part, i, j, theta, varphi, Theta: the cylinder p = 0 in two parts, below b = 0 (part 0, inconsistent inside)
        and above it (part 1, indeterminate inside), so that a view from above draws b = 0 between them; empty for
        mu < mu_P, a segment at mu = mu_P;
      "gb": curve, theta, varphi, Theta: the GB manifold in Theta >= 0 (``crosscheck.theory.gb.gb_manifold``); where that is
        empty but b = 0 touches the cylinder at theta_1 or theta_2 with Theta = 0 (|Psi| = Psi_1, Psi_2), that point;
      "pieces": the theta intervals of b = 0 (``b0_pieces``); "gb_curves": the ``GBCurve`` list; "tangency": whether
        "gb" is such a touching point.
    """
    from crosscheck.theory import gb

    vp = np.linspace(-np.pi, 0.0, n_varphi)
    pieces = b0_pieces(Psi, Theta_max, n=n_fine)
    b0 = {k: [] for k in ("piece", "i", "j", "theta", "varphi", "Theta")}
    for k, (lo, hi) in enumerate(pieces):
        th = _spaced(lo, hi, n_surface)
        if (
            lo < critical.theta_L < hi
        ):  # where b = 0 comes closest to Theta = 0 at Psi_L (a tangency, eq. thetal): sample it
            th = np.sort(np.append(th, critical.theta_L))
        T = np.sqrt(np.maximum(Theta2_on_b0(Psi, th), 0.0))  # the edges are roots: clip their rounding
        for key, v in (
            ("piece", np.full(th.size * vp.size, k)),
            ("i", np.repeat(np.arange(th.size), vp.size)),
            ("j", np.tile(np.arange(vp.size), th.size)),
            ("theta", np.repeat(th, vp.size)),
            ("varphi", np.tile(vp, th.size)),
            ("Theta", np.repeat(T, vp.size)),
        ):
            b0[key] += list(v)
    p0 = {k: [] for k in ("part", "i", "j", "theta", "varphi", "Theta")}
    g = {k: [] for k in ("curve", "theta", "varphi", "Theta")}
    th1, th2 = (float(t) for t in critical.theta_12(mu, alpha))
    curves, tangency = [], False
    if not math.isnan(th1):  # p < 0 somewhere: mu >= mu_P
        cth, cvp = p0_cylinder(mu, alpha, n=n_surface)
        u = np.linspace(0.0, 1.0, n_Theta)
        cut = np.minimum(
            np.sqrt(np.maximum(Theta2_on_b0(Psi, cth), 0.0)), Theta_max
        )  # b = 0 on the cylinder (0 in the theta gap)
        for part, (lo, hi) in enumerate(((np.zeros_like(cut), cut), (cut, np.full_like(cut, Theta_max)))):
            Th = lo[:, None] + (hi - lo)[:, None] * u[None, :]
            for key, v in (
                ("part", np.full(Th.size, part)),
                ("i", np.repeat(np.arange(cth.size), u.size)),
                ("j", np.tile(np.arange(u.size), cth.size)),
                ("theta", np.repeat(cth, u.size)),
                ("varphi", np.repeat(cvp, u.size)),
                ("Theta", Th.ravel()),
            ):
                p0[key] += list(v)
        curves = gb.gb_manifold(mu, Psi, alpha, n=n_gb)
        for k, c in enumerate(curves):
            keep = c.Theta >= 0
            for key, v in (
                ("curve", np.full(keep.sum(), k)),
                ("theta", c.theta[keep]),
                ("varphi", c.varphi[keep]),
                ("Theta", c.Theta[keep]),
            ):
                g[key] += list(v)
        if not curves:
            # at |Psi| = Psi_2 the manifold is the point where b = 0 touches the cylinder at Theta = 0; gb_manifold's theta
            # gap can miss it by rounding (its edge lands 1e-15 beyond theta_2)
            for t in (th1, th2):
                if abs(Theta2_on_b0(Psi, t)) <= CLOSED_FORM.allowance(1 / math.sin(t)):
                    g = {"curve": [0], "theta": [t], "varphi": [-math.pi / 2], "Theta": [0.0]}
                    tangency = True
                    break
    return {"b0": b0, "p0": p0, "gb": g, "pieces": pieces, "gb_curves": curves, "tangency": tangency}


def draw_surfaces(ax, b0: dict, p0: dict, g: dict, Theta_max: float, *, labels: bool = True) -> None:
    """Draw the tables of ``surface_meshes`` on a 3D axes made with ``computed_zorder=False``: b = 0 red, p = 0 blue, GB black."""
    from matplotlib.colors import LightSource

    from crosscheck.report.plotting import B_COLOR, P_COLOR

    def mesh(t, key, k):
        sel = t[key] == k
        ni, nj = int(t["i"][sel].max()) + 1, int(t["j"][sel].max()) + 1
        return (np.asarray(t[c])[sel].reshape(ni, nj) for c in ("theta", "varphi", "Theta"))

    light = LightSource(azdeg=300, altdeg=70)  # nearly overhead: b = 0 falling and rising in theta shade alike
    style = dict(
        alpha=0.55, linewidth=0, antialiased=True, shade=True, lightsource=light, rasterized=True
    )  # vector text, raster surfaces: small SVG
    p0 = {k: np.asarray(v) for k, v in p0.items()}
    b0 = {k: np.asarray(v) for k, v in b0.items()}
    # painter's order for a view from above: the cylinder below b = 0, then b = 0, then the cylinder above it
    degenerate = (
        p0["part"].size and np.ptp(p0["theta"]) == 0
    )  # mu = mu_P: p = 0 only on the segment theta_P, varphi = -pi/2
    if degenerate:
        ax.plot(p0["theta"][:2], p0["varphi"][:2], [0, Theta_max], color=P_COLOR, lw=2.0)
    elif p0["part"].size:
        ax.plot_surface(*mesh(p0, "part", 0), color=P_COLOR, **style)
    for k in np.unique(b0["piece"]):
        ax.plot_surface(*mesh(b0, "piece", k), color=B_COLOR, **style)
    if p0["part"].size and not degenerate:
        ax.plot_surface(*mesh(p0, "part", 1), color=P_COLOR, **style)
    g = {k: np.asarray(v, float) for k, v in g.items()}
    for k in np.unique(g["curve"]):
        sel = g["curve"] == k
        if sel.sum() == 1:
            ax.scatter(
                g["theta"][sel],
                g["varphi"][sel],
                g["Theta"][sel],
                color="k",
                s=14 if labels else 6,
                zorder=10,
                depthshade=False,
            )
        else:
            ax.plot(g["theta"][sel], g["varphi"][sel], g["Theta"][sel], color="k", lw=1.8 if labels else 1.0, zorder=10)
    ax.set_xlim(0, np.pi / 2)
    ax.set_ylim(-np.pi, 0)
    ax.set_zlim(0, Theta_max)
    ax.view_init(elev=24, azim=-122)
    if labels:
        ax.set_xticks([0, np.pi / 4, np.pi / 2], ["0", "$\\pi/4$", "$\\pi/2$"])
        ax.set_yticks([-np.pi, -np.pi / 2, 0], ["$-\\pi$", "$-\\pi/2$", "0"])
        ax.set_zticks([0, 1, 2])
        ax.set_xlabel("$\\theta$", labelpad=-6)
        ax.set_ylabel("$\\varphi$", labelpad=-6)
        ax.set_zlabel("$\\Theta$", labelpad=-8)
        ax.tick_params(pad=-2, labelsize=7)
        ax.set_box_aspect(None, zoom=1.05)
    else:
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_zticks([])
        ax.set_box_aspect(None, zoom=1.15)
