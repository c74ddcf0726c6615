"""``crosscheck gb`` (the GB manifold with its classification) and ``crosscheck slip`` (a slipping run's first event)."""

from __future__ import annotations

import json
import math

import numpy as np

from crosscheck.checks import ALPHA, AZIMUTH, ETA, HORIZON, MU, RATE, THETA, UNIT, VARPHI, integer
from crosscheck.checks import number as _num
from crosscheck.cli.options import add_alpha, add_psi, add_state, ascii_number

# Numbers are parsed by crosscheck.checks.number (type=str) so that the CLI and the
# Python API give the same one-line message for the same mistake.


#: Samples per theta interval of the curves the command computes (the det K zeros are bracketed between them).
RESOLUTION = 201
#: The most samples printed per curve.
MAX_PRINTED = 1000


def _complex(z) -> dict:
    return {"re": float(np.real(z)), "im": float(np.imag(z))}


def _gb(args) -> int:
    from crosscheck.theory import gb
    from crosscheck.theory.critical import critical_values, kinematic_case

    mu = _num("mu", args.mu, MU)
    alpha = _num("alpha", args.alpha, ALPHA)
    Psi = _num("Psi", args.Psi, RATE)
    eta = _num("eta", args.eta, ETA)
    n = integer("samples", args.samples, 1, MAX_PRINTED)
    cv = critical_values(mu, alpha)
    # The curves (and the det K zeros bracketed along them) at a fixed resolution: what is found
    # must not depend on how many samples the user asks to see.
    curves = gb.gb_manifold(mu, Psi, alpha, n=max(RESOLUTION, n))
    out = {
        "mu": mu,
        "alpha": alpha,
        "Psi": Psi,
        "eta": eta,
        "kinematic_case": kinematic_case(mu, Psi, alpha),
        "Psi_L": cv.Psi_L,
        "Psi_1": None if math.isnan(cv.Psi_1) else cv.Psi_1,
        "Psi_2": None if math.isnan(cv.Psi_2) else cv.Psi_2,
        "curves": [],
    }
    for c in curves:
        m = len(c.theta)
        idx = np.unique(np.linspace(0, m - 1, min(n, m)).round().astype(int))
        Kc = c.K(eta)[idx]
        lam, _ = gb.eigen(Kc)
        types = np.atleast_1d(gb.gb_type(Kc))
        samples = [
            {
                "theta": float(c.theta[i]),
                "varphi": float(c.varphi[i]),
                "Theta": float(c.Theta[i]),
                "type": gb.GBType(int(t)).name,
                "lambda_plus": _complex(l_[0]),
                "lambda_minus": _complex(l_[1]),
            }
            for i, t, l_ in zip(idx, types, lam)
        ]
        zeros = gb.det_K_zeros(c, eta)
        out["curves"].append(
            {
                "Theta_sign": c.sign,
                "crosses_Theta_0": c.crosses_zero,
                "samples": samples,
                "det_K_zeros": [dict(zip(("theta", "varphi", "Theta"), map(float, z))) for z in zeros],
            }
        )
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(
        f"GB manifold b = p = 0 for mu = {mu:g}, alpha = {alpha:g}, Psi = {Psi:g}, eta = {eta:g}  "
        f"(kinematic case {out['kinematic_case']}): {len(curves)} closed curve(s)"
    )
    if not curves:
        print("  none: mu < mu_P (no paradox) or |Psi| > Psi_2 (eqs. mup2D, psi2)")
    for k, c in enumerate(out["curves"], 1):
        where = "crosses Theta = 0" if c["crosses_Theta_0"] else ("Theta > 0" if c["Theta_sign"] > 0 else "Theta < 0")
        print(f"curve {k}: {where}")
        print(f"  {'theta':>8} {'varphi':>9} {'Theta':>9}  {'type':<15} {'lambda+':>20} {'lambda-':>20}")
        for s in c["samples"]:
            lp, lm = (f"{s[k_]['re']:+.4f}{s[k_]['im']:+.4f}j" for k_ in ("lambda_plus", "lambda_minus"))
            print(f"  {s['theta']:8.4f} {s['varphi']:9.4f} {s['Theta']:9.4f}  {s['type']:<15} {lp:>20} {lm:>20}")
        for z in c["det_K_zeros"]:
            print(f"  det K = 0 at theta = {z['theta']:.4f}, varphi = {z['varphi']:.4f}, Theta = {z['Theta']:.4f}")
    return 0


#: What each domain exit of ``slip`` means (``crosscheck.theory.slipping.DOMAIN_EXITS``).
LEFT = {
    "varphi=0": "varphi reached 0, the tip slipping square to the rod's projection, then towards S",
    "varphi=-pi": "varphi reached -pi, the tip slipping square to the rod's projection, then towards S",
    "varphi=pi/2": "the tip at rest starts slipping towards S, varphi = +pi/2",
    "theta=0": "theta reached 0, the rod flat on the plane",
    "theta=pi/2": "theta reached pi/2, the rod through the vertical",
}


def _slip(args) -> int:
    from crosscheck.state import SlipState
    from crosscheck.theory.gb import slip_until_event

    state = SlipState(
        theta=_num("theta", args.theta, THETA),
        varphi=_num("varphi", args.varphi, VARPHI),
        Theta=_num("Theta", args.Theta, RATE),
        Psi=_num("Psi", args.Psi, RATE),
        eta=_num("eta", args.eta, ETA),
        psi=_num("psi", args.psi, AZIMUTH),
    )
    mu, alpha, t_max = _num("mu", args.mu, MU), _num("alpha", args.alpha, ALPHA), _num("t_max", args.t_max, HORIZON)
    if args.continue_:
        return _hybrid(state, mu, alpha, t_max, _num("restitution", args.restitution, UNIT), args.json)
    r = slip_until_event(state, mu, alpha, t_max=t_max)
    if args.json:
        print(json.dumps(r.as_dict(), indent=2))
        return 0
    s = r.state
    if r.left_domain:  # not the horizon's SLIP: the paper's coordinates end here
        print(
            f"{r.outcome.name} up to t = {r.time:.9g} only: the run left the paper's domain there "
            f"({LEFT[r.reason]}); no event before it, nothing said after it; b = {r.b:.3g}, p = {r.p:.3g}"
        )
    else:
        print(f"{r.outcome.name} at t = {r.time:.9g} ({r.reason}); b = {r.b:.3g}, p = {r.p:.3g}")
    print(
        f"  theta = {s.theta:.6f}  varphi = {s.varphi:.6f}  Theta = {s.Theta:.6f}  Psi = {s.Psi:.6f}  "
        f"eta = {s.eta:.6f}  psi = {s.psi:.6f}"
    )
    return 0


def _hybrid(state, mu, alpha, t_max, restitution, as_json) -> int:
    from crosscheck.theory.impact import continuation as hybrid

    h = hybrid.run(state, mu, alpha, horizon=t_max, restitution=restitution)
    if as_json:
        print(json.dumps(h.as_dict(), indent=2))
        return 0
    for seg in h.segments:
        if isinstance(seg, hybrid.StickSegment):
            k = seg.stick
            then = f"; slips at varphi = {k.varphi:.6f}" if k.varphi is not None else ""
            print(
                f"stick from t = {seg.t0:.9g} to {seg.t1:.9g}: {k.outcome.name} ({k.reason}); F_j = {k.force[1]:.3g}, F_n = {k.force[2]:.3g}{then}"
            )
            continue
        r = seg.slip
        print(
            f"slip from t = {seg.t0:.9g} to {seg.t1:.9g}: {r.outcome.name} ({r.reason}); b = {r.b:.3g}, p = {r.p:.3g}"
        )
        if seg.impact is not None:
            i = seg.impact
            phases = ", ".join(f"{p.name} to P = {p.P_end:.6g}" for p in i.phases)
            print(
                f"  impact without collision: P = {i.normal_impulse:.6g}, tangential ({i.tangential_impulse[0]:.6g}, {i.tangential_impulse[1]:.6g}); "
                f"{phases}; energy lost {i.energy_lost:.6g}"
            )
            print(f"  after: Theta = {i.Theta:.6f}  Psi = {i.Psi:.6f}  eta = {i.eta:.6g}  w = {i.w:.3g}")
    print(f"{h.outcome.name} at t = {h.time:.9g} ({h.reason})")
    return 0


def register(sub) -> None:
    g = sub.add_parser("gb", help="samples of the GB manifold b = p = 0 with their type (node, saddle, focus)")
    add_state(g, ("mu",))
    add_alpha(g)
    g.add_argument(
        "--Psi",
        type=str,
        default="0",
        metavar="PSI_DOT",
        help=f"scaled azimuthal rate, fixed along the manifold, in {RATE} (default 0)",
    )
    g.add_argument(
        "--eta", type=str, default="1", metavar="ETA", help=f"scaled slip speed (K depends on it), in {ETA} (default 1)"
    )
    g.add_argument(
        "--samples",
        type=ascii_number,
        default="9",
        help=f"samples printed per curve, an integer in [1, {MAX_PRINTED}] (default 9)",
    )
    g.add_argument("--json", action="store_true", help="print the result as JSON")
    g.set_defaults(func=_gb)

    s = sub.add_parser("slip", help="integrate a slipping state to its first event (lift-off, jam, stick, GB)")
    add_state(s)
    add_psi(s)
    add_alpha(s)
    s.add_argument(
        "--t-max",
        dest="t_max",
        type=ascii_number,
        default="10",
        help="horizon in scaled time, in (0, 1e4] (default 10)",
    )
    s.add_argument(
        "--continue",
        dest="continue_",
        action="store_true",
        help="go on through impacts without collision (at a jam or a GB point), sticking and slipping again (the hybrid rigid model)",
    )
    s.add_argument(
        "--restitution",
        type=ascii_number,
        default="0",
        help="Poisson restitution of the impact, in [0, 1] (with --continue)",
    )
    s.add_argument("--json", action="store_true", help="print the result as JSON")
    s.set_defaults(func=_slip)
