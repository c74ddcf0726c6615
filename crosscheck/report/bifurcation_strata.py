"""Fig. 21's strata of (mu, Psi): the curves and points where the kinematic case changes, and the paper's 19 cells.

Each codimension-1 curve is the zero set of one function of (mu, Psi) (``defining_function``: F_L, F_1, F_2 or
F_P, eqs. psil, psi1, psi2, mup2D), sampled along its varied coordinate (``curve_samples``); the codimension-2
points are where they meet; each cell of the paper's grid gets one (mu, Psi) inside its stratum (``cell_point``).
The section that computes and draws them: ``crosscheck.report.sections.bifurcations``.
"""

from __future__ import annotations

import numpy as np

from crosscheck.theory import analytic, critical

__all__ = [
    "CURVES",
    "POINTS",
    "CELLS",
    "MU_STRATA",
    "PSI_STRATA",
    "defining_function",
    "defining_scale",
    "constants",
    "curve_samples",
    "cell_point",
    "across",
]

#: Codimension-1 curves: id -> (critical value it is, the function that vanishes on it, varied coordinate,
#: its range as names of the constants, (case below or left, case above or right)).
CURVES = {
    "L_I": ("Psi = Psi_L", "L", "mu", ("0", "mu_P"), (1, 2)),
    "L_II": ("Psi = Psi_L", "L", "mu", ("mu_P", "mu_L"), (3, 4)),
    "L_III": ("Psi = Psi_L", "L", "mu", ("mu_L", "mu_max"), (3, 5)),
    "1_II": ("Psi = Psi_1(mu)", "1", "mu", ("mu_P", "mu_L"), (4, 6)),
    "1_III": ("Psi = Psi_1(mu)", "1", "mu", ("mu_L", "mu_max"), (5, 6)),
    "2": ("Psi = Psi_2(mu)", "2", "mu", ("mu_P", "mu_max"), (6, 7)),
    "P_a": ("mu = mu_P", "P", "Psi", ("0", "Psi_L"), (1, 3)),
    "P_b": ("mu = mu_P", "P", "Psi", ("Psi_L", "Psi_P"), (2, 4)),
    "P_c": ("mu = mu_P", "P", "Psi", ("Psi_P", "Psi_max"), (2, 7)),
}

#: Codimension-2 points: name -> (mu, Psi as names of constants, the curves through it).
POINTS = {
    "(mu_P, Psi_L)": ("mu_P", "Psi_L", ("L_I", "L_II", "P_a", "P_b")),
    "(mu_P, Psi_P)": ("mu_P", "Psi_P", ("1_II", "2", "P_b", "P_c")),
    "(mu_L, Psi_L)": ("mu_L", "Psi_L", ("L_II", "L_III", "1_II", "1_III")),
}

#: The paper's 19 cells (column: mu stratum 0-4, row: |Psi| stratum 0-6) and what each shows:
#: ("case", k) a generic case, ("curve", id) a codimension-1 curve, ("point", name) a codimension-2 point.
#: Cells spanning several strata in the paper (cases 2, 3, 6, 7 and Psi = Psi_2) sit in their middle column or row.
CELLS = (
    (0, 0, ("case", 1)),
    (0, 1, ("curve", "L_I")),
    (0, 4, ("case", 2)),
    (1, 0, ("curve", "P_a")),
    (1, 1, ("point", "(mu_P, Psi_L)")),
    (1, 3, ("curve", "P_b")),
    (1, 5, ("point", "(mu_P, Psi_P)")),
    (1, 6, ("curve", "P_c")),
    (2, 1, ("curve", "L_II")),
    (2, 2, ("case", 4)),
    (2, 3, ("curve", "1_II")),
    (3, 0, ("case", 3)),
    (3, 2, ("point", "(mu_L, Psi_L)")),
    (3, 4, ("case", 6)),
    (3, 5, ("curve", "2")),
    (3, 6, ("case", 7)),
    (4, 1, ("curve", "L_III")),
    (4, 2, ("case", 5)),
    (4, 3, ("curve", "1_III")),
)
MU_STRATA = ("$\\mu\\in[0,\\mu_P)$", "$\\mu=\\mu_P$", "$\\mu\\in(\\mu_P,\\mu_L)$", "$\\mu=\\mu_L$", "$\\mu>\\mu_L$")
PSI_STRATA = (
    "$|\\Psi|\\in[0,\\Psi_L)$",
    "$|\\Psi|=\\Psi_L$",
    "$|\\Psi|\\in(\\Psi_L,\\Psi_1)$",
    "$|\\Psi|=\\Psi_1$",
    "$|\\Psi|\\in(\\Psi_1,\\Psi_2)$",
    "$|\\Psi|=\\Psi_2$",
    "$|\\Psi|>\\Psi_2$",
)


def defining_function(kind: str, mu, Psi, alpha: float):
    """The function of (mu, Psi) whose zeros are the codimension-1 curve of ``kind`` ("L", "1", "2" or "P"); see the module docstring."""
    if kind == "L":
        return analytic.b(Psi, 0.0, critical.theta_L) + 0.0 * np.asarray(mu, float)
    if kind == "P":
        return critical.p_min(mu, alpha) + 0.0 * np.asarray(Psi, float)
    theta = critical.theta_12(mu, alpha)[0 if kind == "1" else 1]
    return analytic.b(Psi, 0.0, theta)


def defining_scale(kind: str, mu, Psi, alpha: float):
    # size of the terms each function sums, for the closed-form allowance
    if kind == "P":
        return 1.0 + alpha * (1.0 + np.sqrt(1.0 + np.asarray(mu, float) ** 2))
    return 1.0 + np.asarray(Psi, float) ** 2


def constants(alpha: float, mu_max: float, Psi_max: float) -> dict:
    return {
        "0": 0.0,
        "alpha": alpha,
        "mu_P": float(critical.mu_P(alpha)),
        "mu_L": float(critical.mu_L(alpha)),
        "Psi_L": critical.Psi_L,
        "Psi_P": float(critical.Psi_P(alpha)),
        "theta_L": critical.theta_L,
        "theta_P": float(critical.theta_P(alpha)),
        "mu_max": mu_max,
        "Psi_max": Psi_max,
    }


def curve_samples(cid: str, c: dict, n: int) -> tuple[np.ndarray, np.ndarray]:
    _, kind, along, (lo, hi), _ = CURVES[cid]
    t = np.linspace(c[lo], c[hi], n)
    if along == "Psi":
        return np.full(n, c["mu_P"]), t
    if kind == "L":
        return t, np.full(n, c["Psi_L"])
    th = critical.theta_12(t, c["alpha"])[0 if kind == "1" else 1]
    return t, critical.Psi_on_b0(th)


def cell_point(col: int, row: int, what: tuple, c: dict, mu_ex: list[float]) -> tuple[float, float]:
    """A (mu, Psi) inside the stratum of one cell of the paper's grid."""
    mu = {0: mu_ex[0], 1: c["mu_P"], 2: mu_ex[1], 3: c["mu_L"], 4: mu_ex[2]}[col]
    if what[0] == "point":
        pm, pP, _ = POINTS[what[1]]
        return c[pm], c[pP]
    if col == 1:  # mu = mu_P: Psi_1 = Psi_2 = Psi_P
        return mu, {0: 0.0, 3: (c["Psi_L"] + c["Psi_P"]) / 2, 6: c["Psi_P"] + 1.0}[row]
    if col == 0:
        return mu, {0: 0.0, 1: c["Psi_L"], 4: 2.0 * c["Psi_L"]}[row]
    cv = critical.critical_values(mu, c["alpha"])
    return mu, {
        0: 0.0,
        1: cv.Psi_L,
        2: (cv.Psi_L + cv.Psi_1) / 2,
        3: cv.Psi_1,
        4: (cv.Psi_1 + cv.Psi_2) / 2,
        5: cv.Psi_2,
        6: cv.Psi_2 + 1.0,
    }[row]


def across(cid: str, mu, Psi, d: float, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """kinematic_case just below/left and above/right of points of a curve (a relative step ``d``)."""
    if CURVES[cid][2] == "Psi":  # a line mu = const: step in mu
        return critical.kinematic_case(mu - d, Psi, alpha), critical.kinematic_case(mu + d, Psi, alpha)
    return critical.kinematic_case(mu, Psi - d * np.maximum(1, Psi), alpha), critical.kinematic_case(
        mu, Psi + d * np.maximum(1, Psi), alpha
    )
