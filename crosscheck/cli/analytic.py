"""``crosscheck critical`` and ``crosscheck classify``: the analytic reference."""

from __future__ import annotations

import json
import math

from crosscheck import analytic
from crosscheck.checks import ALPHA, FINITE, MU, THETA, VARPHI, number as _num

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
    print(f"critical values for mu = {cv.mu:g}, alpha = {cv.alpha:g}  "
          f"(mechanism {analytic.mechanism(cv.mu, cv.alpha).name})")
    for k, note in notes.items():
        v = d[k]
        text = "n/a (mu < mu_P)" if math.isnan(v) else f"{v:.6f}"
        print(f"  {k:<9} {text:>16}   {note}")
    return 0


def _classify(args) -> int:
    theta = _num("theta", args.theta, THETA)
    varphi = _num("varphi", args.varphi, VARPHI)
    Theta = _num("Theta", args.Theta, FINITE)
    Psi = _num("Psi", args.Psi, FINITE)
    mu = _num("mu", args.mu, MU)
    alpha = _num("alpha", args.alpha, ALPHA)
    bb = float(analytic.b(Psi, Theta, theta))
    pp = float(analytic.p(theta, varphi, mu, alpha))
    fz = float(analytic.normal_force(Psi, Theta, theta, varphi, mu, alpha))
    m = analytic.mode(bb, pp)
    out = {"theta": theta, "varphi": varphi, "Theta": Theta, "Psi": Psi, "mu": mu, "alpha": alpha,
           "b": bb, "p": pp, "F_z": fz if math.isfinite(fz) else None, "mode": m.name,
           "kinematic_case": analytic.kinematic_case(mu, Psi, alpha)}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"b = {bb:.6g}  p = {pp:.6g}  F_z = -b/p = {fz:.6g}  mode = {m.name}  (kinematic case {out['kinematic_case']})")
    return 0


def register(sub) -> None:
    c = sub.add_parser("critical", help="print every critical value of the paper for (mu, alpha)")
    c.add_argument("--mu", type=str, help="friction coefficient, >= 0")
    c.add_argument("--alpha", type=str, default="3", help="m l^2 / I0, > 0 (3: uniform rod)")
    c.add_argument("--json", action="store_true")
    c.set_defaults(func=_critical)

    k = sub.add_parser("classify", help="b, p, F_z and the contact mode of one state")
    for name, text in (("theta", "polar angle, (0, pi/2)"), ("varphi", "relative slip angle, (-pi, 0]"),
                       ("Theta", "scaled polar rate"), ("Psi", "scaled azimuthal rate"),
                       ("mu", "friction coefficient, >= 0")):
        k.add_argument(f"--{name}", type=str, help=text)
    k.add_argument("--alpha", type=str, default="3", help="m l^2 / I0, > 0")
    k.add_argument("--json", action="store_true")
    k.set_defaults(func=_classify)
