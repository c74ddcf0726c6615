"""Every number the paper prints, beside the model's value.

A registry used by the tests (each printed number must be reproduced to its
printed digits) and by the report's "paper vs crosscheck" table.  A printed
value agrees when |computed - printed| <= half a unit of its last printed
digit.  Where the paper's own digits are off (by rounding or a typo) the
entry carries ``known_discrepancy`` with the reason, and the report flags it:
the discrepancy is shown, never hidden.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from crosscheck.theory import critical as cr

__all__ = ["PrintedValue", "PRINTED", "FIG20_INITIAL_CONDITIONS", "GB_POINTS", "PaperFigure", "FIGURES"]


@dataclass(frozen=True)
class PrintedValue:
    name: str  # the quantity and its parameters
    printed: str  # exactly as printed
    where: str  # equation label or figure of the paper
    compute: Callable[[], float]
    known_discrepancy: str = ""

    @property
    def value(self) -> float:
        return float(self.printed)

    @property
    def half_ulp(self) -> float:
        """Half a unit of the last printed digit."""
        digits = len(self.printed.split(".")[1]) if "." in self.printed else 0
        return 0.5 * 10.0**-digits

    def computed(self) -> float:
        return float(self.compute())

    def agrees(self) -> bool:
        return abs(self.computed() - self.value) <= self.half_ulp


def _cv(mu, alpha=3.0):
    return cr.critical_values(mu, alpha)


_MU_1P01 = 1.01 * float(cr.mu_P(3.0))

PRINTED: tuple[PrintedValue, ...] = (
    PrintedValue("mu_P(alpha=3)", "1.3333", "eq. mup2D (4/3)", lambda: cr.mu_P(3.0)),
    PrintedValue("mu_C(alpha=3)", "1.5396", "eq. muC, sec. 4 (8/(3 sqrt 3))", lambda: cr.mu_C(3.0)),
    PrintedValue("mu_L(alpha=3)", "2.1213", "eq. mul (3/sqrt 2)", lambda: cr.mu_L(3.0)),
    PrintedValue("theta_L", "0.6155", "eq. thetalvalue", lambda: cr.theta_L),
    PrintedValue("theta_L [deg]", "35.3", "eq. thetalvalue", lambda: math.degrees(cr.theta_L)),
    PrintedValue("Psi_L", "1.6119", "eq. psil", lambda: cr.Psi_L),
    PrintedValue(
        "Psi_L (sec. 3.5 text)",
        "1.6118",
        "sec. 3.5, Fig. GBs_bif3 text",
        lambda: cr.Psi_L,
        known_discrepancy="truncated rather than rounded: Psi_L = 1.611855 rounds to 1.6119 (as eq. psil prints)",
    ),
    PrintedValue("theta_P(alpha=3)", "1.1071", "eq. thetap, Fig. badsection", lambda: cr.theta_P(3.0)),
    PrintedValue("Psi_P(alpha=3)", "2.3644", "eq. psip", lambda: cr.Psi_P(3.0)),
    PrintedValue("theta_1(mu=1.4)", "0.9702", "Fig. badsection", lambda: _cv(1.4).theta_1),
    PrintedValue("theta_2(mu=1.4)", "1.2209", "Fig. badsection", lambda: _cv(1.4).theta_2),
    PrintedValue(
        "varphi_1(mu=1.4)",
        "-1.8807",
        "Fig. badsection",
        lambda: _cv(1.4).varphi_1,
        known_discrepancy=(
            "computed -1.880641 rounds to -1.8806; varphi_1 + varphi_2 = -pi exactly (eq. varphi12), and the "
            "printed varphi_2 = -1.2610 gives -pi - varphi_2 = -1.8806, so the printed last digit is off by one"
        ),
    ),
    PrintedValue("varphi_2(mu=1.4)", "-1.2610", "Fig. badsection", lambda: _cv(1.4).varphi_2),
    PrintedValue("Psi_1(mu=1.4)", "1.9480", "eq. psi1", lambda: _cv(1.4).Psi_1),
    PrintedValue("Psi_2(mu=1.4)", "3.0097", "eq. psi2", lambda: _cv(1.4).Psi_2),
    PrintedValue("Psi_1(mu=6)", "2.1876", "sec. 3.5", lambda: _cv(6.0).Psi_1),
    PrintedValue("Psi_2(mu=6)", "17.8171", "sec. 3.5", lambda: _cv(6.0).Psi_2),
    PrintedValue("1.01 mu_P(alpha=3)", "1.3467", "sec. 4.3", lambda: _MU_1P01),
    PrintedValue("Psi_1(mu=1.01 mu_P)", "2.1526", "sec. 4.3", lambda: _cv(_MU_1P01).Psi_1),
    PrintedValue("Psi_2(mu=1.01 mu_P)", "2.6220", "sec. 4.3", lambda: _cv(_MU_1P01).Psi_2),
    PrintedValue(
        "eps varphi_hat at Psi=0 (eps^2 mu_hat=0.01)", "0.1414", "sec. 4.3 footnote", lambda: math.sqrt(2 * 0.01)
    ),
    PrintedValue("theta_1(mu=1.7)", "0.7692", "Fig. planesmu1p7_w_traj", lambda: _cv(1.7).theta_1),
    PrintedValue("theta_2(mu=1.7)", "1.3333", "Fig. planesmu1p7_w_traj", lambda: _cv(1.7).theta_2),
    PrintedValue("Psi_1(mu=1.7)", "1.6689", "Fig. determinant_bif", lambda: _cv(1.7).Psi_1),
    PrintedValue("Psi_2(mu=1.7)", "4.3121", "Fig. determinant_bif", lambda: _cv(1.7).Psi_2),
    # Fig. stabilty_on_GB: manifolds at Psi = (Psi_L + Psi_1)/2 and (Psi_1 + Psi_2)/2,
    # printed in sec. 3.5 as the mechanism examples.
    PrintedValue("(Psi_L+Psi_1)/2 (mu=1.4)", "1.7800", "sec. 3.5, case 4", lambda: (cr.Psi_L + _cv(1.4).Psi_1) / 2),
    PrintedValue(
        "(Psi_1+Psi_2)/2 (mu=1.4)", "2.4789", "sec. 3.5, case 6", lambda: (_cv(1.4).Psi_1 + _cv(1.4).Psi_2) / 2
    ),
    PrintedValue("(Psi_L+Psi_1)/2 (mu=6)", "1.8997", "sec. 3.5, case 5", lambda: (cr.Psi_L + _cv(6.0).Psi_1) / 2),
    PrintedValue(
        "(Psi_1+Psi_2)/2 (mu=6)", "10.0024", "sec. 3.5, case 6", lambda: (_cv(6.0).Psi_1 + _cv(6.0).Psi_2) / 2
    ),
)

#: Points (theta_GB, varphi_GB) printed in Figs. planesmu1p4_w_traj (mu=1.4) and
#: planesmu1p7_w_traj (mu=1.7), alpha = 3; they lie on p = 0.  Fig. 13(d) prints
#: varphi = +2.1107, outside (-pi, 0]; -2.1107 is the value on p = 0 (a sign typo).
GB_POINTS: tuple[tuple[float, str, str, str], ...] = (
    (1.4, "0.9702", "-1.5708", "Fig. 12(a), P+"),
    (1.4, "1.0094", "-1.7832", "Fig. 12(b)"),
    (1.4, "1.0953", "-1.8793", "Fig. 12(c)"),
    (1.4, "1.1872", "-1.7978", "Fig. 12(d)"),
    (1.4, "1.2209", "-1.5708", "Fig. 12(e), Q+"),
    (1.7, "0.7692", "-1.5708", "Fig. 13(a)"),
    (1.7, "0.8517", "-1.9969", "Fig. 13(b)"),
    (1.7, "1.0227", "-2.2143", "Fig. 13(c)"),
    (1.7, "1.2562", "2.1107", "Fig. 13(d), printed with + sign"),
    (1.7, "1.3333", "-1.5708", "Fig. 13(e)"),
)

#: Initial conditions of Fig. my_ugly_simulations (alpha = 3, mu = 1.4).
FIG20_INITIAL_CONDITIONS = (
    dict(theta=1.1067, eta=2.1307, varphi=-1.8913, Psi=-0.1027, Theta=0.9000),
    dict(theta=1.1031, eta=2.0, varphi=-1.9233, Psi=0.0, Theta=0.9000),
)


@dataclass(frozen=True)
class PaperFigure:
    """One figure of the paper as it prints it (the order of its LaTeX figure environments)."""

    number: int
    labels: tuple[str, ...]  # its \label{...}s, panels first
    shows: str
    sections: tuple[str, ...]  # the report sections that recompute it (slugs); () if none
    why_not: str = ""  # why the report does not draw it, when ``sections`` is empty or partial


#: Every figure of the paper, numbered as printed, with where the report recomputes it.
FIGURES = (
    PaperFigure(
        1,
        ("fig:me2",),
        "the rod AB on the rough plane, its frames and angles",
        (),
        "a schematic drawing, not computed from the model",
    ),
    PaperFigure(
        2,
        ("fig:rod_orientations", "fig:badregion", "fig:badsection"),
        "(a) rod orientations with p < 0 in physical space, (b) the region p < 0 in (theta, varphi)",
        ("p_region",),
    ),
    PaperFigure(
        3,
        ("fig:pandb", "fig:p3.2", "fig:p3s"),
        "(a) the four modes in the (theta, Theta) section varphi = -pi/2, (b) the surfaces b = 0 "
        "and p = 0 in (theta, varphi, Theta) at Psi = 0",
        ("kinematic_surfaces", "mode_maps"),
    ),
    PaperFigure(
        4,
        ("fig:p3.3", "fig:p3.4", "fig:p3.5", "fig:p3.6", "fig:p3ss"),
        "the surfaces b = 0 and p = 0 as Psi grows (1.56, 1.7, 2.2, 5)",
        ("kinematic_surfaces", "mode_maps"),
    ),
    PaperFigure(
        5,
        ("fig:psi1.61192D", "fig:psi1.61193D", "fig:psi1.6119"),
        "(a) section and (b) surfaces at Psi = Psi_L",
        ("kinematic_surfaces", "mode_maps"),
    ),
    PaperFigure(
        6,
        ("fig:psi1.9482D", "fig:psi1.9483D", "fig:psi1.9483"),
        "(a) section and (b) surfaces at Psi = Psi_1",
        ("kinematic_surfaces", "mode_maps"),
    ),
    PaperFigure(
        7,
        ("fig:psi3.00972D", "fig:psi3.00973D", "fig:psi3.0097"),
        "(a) section and (b) surfaces at Psi = Psi_2",
        ("kinematic_surfaces", "mode_maps"),
    ),
    PaperFigure(
        8,
        ("fig:mechanisms",),
        "mechanisms I-III as Psi grows",
        ("mechanisms",),
        "a schematic; the report draws the mechanisms' regions (Fig. 9b)",
    ),
    PaperFigure(
        9,
        ("fig:muPsicases", "fig:alphamumech", "fig:CaseIs"),
        "(a) kinematic cases 1-7 in (mu, Psi), (b) mechanisms in (alpha, mu)",
        ("kinematic_cases", "mechanisms"),
    ),
    PaperFigure(10, ("fig:Psistheta",), "critical angles theta_L, theta_1, theta_2 against mu", ("critical_angles",)),
    PaperFigure(
        11,
        ("fig:GBmanifoldmu1p4", "fig:GBmanifoldmu6", "fig:GBs_bif3"),
        "the GB manifold at mu = 1.4 and mu = 6",
        ("gb_manifold",),
    ),
    PaperFigure(
        12, ("fig:planesmu1p4_w_traj",), "eigenvectors of K in the (p, b) plane at mu = 1.4", ("gb_eigenvectors",)
    ),
    PaperFigure(
        13, ("fig:planesmu1p7_w_traj",), "eigenvectors of K in the (p, b) plane at mu = 1.7", ("gb_eigenvectors",)
    ),
    PaperFigure(
        14,
        ("fig:pp1", "fig:pp2", "fig:pp8", "fig:ppsThetapos"),
        "local (p, b) dynamics near the GB manifold, Theta > 0",
        ("gb_local",),
        "sketches in the paper; computed here as linearised orbits at one GB point of each type found",
    ),
    PaperFigure(
        15,
        ("fig:pp3", "fig:pp6", "fig:pp5", "fig:pp4", "fig:pp7", "fig:ppsThetaneg"),
        "local (p, b) dynamics near the GB manifold, Theta < 0",
        ("gb_local",),
        "as Fig. 14",
    ),
    PaperFigure(16, ("fig:expan",), "the quartic in Psi against its asymptotic form near mu_P", ("gb_quartic",)),
    PaperFigure(17, ("fig:stabilty_on_GB",), "stability of the points of the GB manifold", ("gb_manifold",)),
    PaperFigure(
        18,
        ("fig:determinant_bif",),
        "zeros of det K on the GB manifold (alpha = 3, mu = 1.7, eta = 10)",
        ("gb_det_zeros",),
    ),
    PaperFigure(
        19,
        ("fig:evsb", "fig:pandora"),
        "eigenvectors along the GB manifold at alpha = 3, mu = 1.7, eta = 10, Psi = 1.062",
        ("gb_det_zeros",),
        "at the four zeros of det K and between them: the paper does not print its panels' points",
    ),
    PaperFigure(
        20,
        ("fig:my_ugly_simulations",),
        "slipping trajectories near the separatrix (initial conditions IC1, IC2)",
        ("gb_separatrix",),
    ),
    PaperFigure(
        21,
        ("fig:mechbifs",),
        "codimension-1 and -2 bifurcations between the kinematic cases in (mu, Psi): the curves and points, and the "
        "surfaces b = 0, p = 0 in each of the 19 strata",
        ("bifurcations",),
    ),
)
