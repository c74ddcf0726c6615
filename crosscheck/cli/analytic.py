"""``crosscheck critical`` and ``crosscheck classify``: the analytic reference."""

from __future__ import annotations

import json
import math

from crosscheck.checks import ALPHA, MU, RATE, THETA, VARPHI
from crosscheck.checks import number as _num
from crosscheck.cli.options import add_alpha, add_state
from crosscheck.theory import analytic

# Number arguments are parsed by ``crosscheck.checks.number`` (type=str here) so
# that the CLI and the Python API give the same message for the same mistake.


def _critical(args) -> int:
    cv = analytic.critical_values(_num("mu", args.mu, MU), _num("alpha", args.alpha, ALPHA))
    d = cv.as_dict()
    if args.json:
        print(json.dumps({k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in d.items()}, indent=2))
        return 0
    notes = {
        "mu_P": "Painleve critical friction, eq. mup2D",
        "mu_C": "Genot-Brogliato critical friction, eq. muC",
        "mu_L": "theta_1 = theta_L, eq. mul",
        "theta_P": "eq. thetap",
        "theta_L": "eq. thetal",
        "Psi_L": "lift-off at Theta = 0, eq. psil",
        "Psi_P": "Psi_1 = Psi_2 at mu_P, eq. psip",
        "theta_1": "eq. theta12",
        "theta_2": "eq. theta12",
        "Psi_1": "eq. psi1",
        "Psi_2": "eq. psi2",
        "varphi_1": "eq. varphi12",
        "varphi_2": "eq. varphi12",
    }
    print(
        f"critical values for mu = {cv.mu:g}, alpha = {cv.alpha:g}  "
        f"(mechanism {analytic.mechanism(cv.mu, cv.alpha).name})"
    )
    for k, note in notes.items():
        v = d[k]
        text = "n/a (mu < mu_P)" if math.isnan(v) else f"{v:.6f}"
        print(f"  {k:<9} {text:>16}   {note}")
    return 0


def _classify(args) -> int:
    theta = _num("theta", args.theta, THETA)
    varphi = _num("varphi", args.varphi, VARPHI)
    Theta = _num("Theta", args.Theta, RATE)
    Psi = _num("Psi", args.Psi, RATE)
    mu = _num("mu", args.mu, MU)
    alpha = _num("alpha", args.alpha, ALPHA)
    bb = float(analytic.b(Psi, Theta, theta))
    pp = float(analytic.p(theta, varphi, mu, alpha))
    b_tol, p_tol = float(analytic.b_rounding(Psi, Theta, theta)), float(analytic.p_rounding(theta, varphi, mu, alpha))
    on = analytic.boundary(bb, pp, b_tol, p_tol)
    # On a boundary the computed sign is rounding noise: name the modes on either side instead of picking one.
    b_sides = (-1.0, 1.0) if "b" in on else (bb,)
    p_sides = (-1.0, 1.0) if "p" in on else (pp,)
    sides = sorted({analytic.mode(x, y).name for x in b_sides for y in p_sides})
    fz = -bb / pp if not on and pp != 0.0 else math.nan
    out = {
        "theta": theta,
        "varphi": varphi,
        "Theta": Theta,
        "Psi": Psi,
        "mu": mu,
        "alpha": alpha,
        "b": bb,
        "p": pp,
        "b_rounding": b_tol,
        "p_rounding": p_tol,
        "F_z": fz if math.isfinite(fz) else None,
        "mode": "BOUNDARY" if on else sides[0],
        "boundary": on or None,
        "modes_either_side": sides if on else None,
        "kinematic_case": analytic.kinematic_case(mu, Psi, alpha),
    }
    if args.json:
        print(json.dumps(out, indent=2))
    elif on:
        print(
            f"b = {bb:.6g}  p = {pp:.6g}  mode: on the boundary {on} (|b|, |p| within rounding {b_tol:.2g}, {p_tol:.2g}) "
            f"between {' and '.join(sides)}; F_z = -b/p undefined  (kinematic case {out['kinematic_case']})"
        )
    else:
        print(
            f"b = {bb:.6g}  p = {pp:.6g}  F_z = -b/p = {fz:.6g}  mode = {out['mode']}  (kinematic case {out['kinematic_case']})"
        )
    return 0


def register(sub) -> None:
    c = sub.add_parser("critical", help="print every critical value of the paper for (mu, alpha)")
    add_state(c, ("mu",))
    add_alpha(c)
    c.add_argument("--json", action="store_true", help="print the result as JSON")
    c.set_defaults(func=_critical)

    k = sub.add_parser("classify", help="b, p, F_z and the contact mode of one state")
    add_state(k, ("theta", "varphi", "Theta", "Psi", "mu"))
    add_alpha(k)
    k.add_argument("--json", action="store_true", help="print the result as JSON")
    k.set_defaults(func=_classify)
