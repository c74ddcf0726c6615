"""MuJoCo changed in the way each cause of its ladder names: the interventions that should remove a disagreement of that cause.

Each function takes the run's ``Options`` and returns ``Intervention`` s,
weakest first (``crosscheck.studies.interventions`` runs them):

* geometry: a thinner capsule (MuJoCo needs r > 0: r / 4, r / 16);
* compliance: a stiffer contact toward the rigid limit, the time constant of
  solref down to a third and a tenth (never below MuJoCo's 2 dt), the last
  two with the impedance raised to d0 = dmax = 0.99 (the fraction of the
  rigid force MuJoCo feeds forward at once), and the strongest at a
  hundredth with the timestep divided by 16.  Why the smaller step: the
  rigid limit of a compliant contact is tau -> 0, and MuJoCo silently
  raises tau to 2 dt ("refsafe"), so at the run's step a tenth is as stiff
  as it gets; tau / dt = 32 at the strongest step still resolves the
  contact time (the run's own ratio is 200);
* friction law: two ways to make MuJoCo's friction oppose the slip as
  Coulomb's does (``crosscheck.engines.mujoco.studies.friction_skew``), each
  weakest first.  A shorter friction time constant (``friction_timeconst``):
  the friction is anti-parallel to u + a_t / B with B = 2 / (dmax tau_f),
  so tau_f -> 0 turns it toward -u.  A smaller ``impratio`` (0.1, 0.01):
  the friction rows' regulariser R_t = R_n / impratio is isotropic and
  outweighs the anisotropic, normal-coupled Delassus block that skews the
  friction (the skew section's medians fall from ~17 to ~6 degrees at 0.01),
  at the price of a softer friction (at 0.001 the friction no longer
  saturates the cone and the tip keeps slipping where it should stop);
* feed-forward: the impedance d0 = dmax lowered to 0.5, 0.1 and 0.01, so
  that MuJoCo applies a fraction d of the rigid normal force at once
  (0.9-0.95 by default) and builds the rest through its reference
  acceleration, as the matched spring does
  (``crosscheck.engines.mujoco.studies.kelvin_voigt``), with impratio raised
  by the normal regulariser's growth so that the friction rows keep their
  R_t = R_n / impratio: MuJoCo's own version of the ladder's rung without the
  feed-forward (``crosscheck.engines.mujoco.law.contact_problem``), which
  keeps the friction rows whole.  (MuJoCo has one impedance for all rows, so
  the friction rows' damping 2 / (dmax tau_f) still grows as dmax falls.)
  Neither is the feed-forward alone, so both run: first d lowered on every
  row as MuJoCo has it (0.1, 0.01; R_t then grows with R_n and the friction
  softens with the normal force), then with R_t kept (0.5, 0.1, 0.01; its
  strongest, the last of all, is the one joined to other causes').  Measured
  on the full report's 157 feed-forward starts: lowering d alone removes 87,
  119 and 125 at 0.5, 0.1, 0.01; with R_t kept 86, 118, 129; on a later full
  report's 94, d alone at 0.1 or 0.01 removes 2 that R_t kept does not, and
  none the other way round.  What the R_t-kept family cannot remove: near p = 0 (the theory's least p below ~0.05)
  MuJoCo jams in its first steps where the theory lifts off, the capsule's
  offset and the friction's skew each putting MuJoCo's own p_eff at or
  below 0 (the rigid rod at C jams at t = 0 too).  Lowering d then makes the
  normal row soft while the friction rows stay stiff, and MuJoCo's cone
  problem raises the normal force to carry the friction instead: from
  theta 1.114, varphi -1.9, Theta 0.984, Psi 0, mu 1.4 (the theory's -b/p
  ~9 m g, a lift-off at 0.0029), the first step's normal force is 9.3 m g
  at MuJoCo's defaults and 44 m g at d = 0.01 with R_t kept, and the slip
  still stops under it; keeping the friction rows' damping too (their time
  constant raised by dmax / d) gives 0.5 m g and a STICK.  MuJoCo has one
  impedance for a contact's rows, so its feed-forward cannot be removed
  without changing its friction; impratio 0.01 (the friction law's) removes
  14 of these by taking the skew away;
* discretisation: the timestep divided by 4 and 16 at the same contact.

Scaled units (section 2.1).
"""

from __future__ import annotations

from crosscheck.engines.spec import Intervention

__all__ = ["geometry", "compliance", "friction_law", "feed_forward", "discretisation"]


def geometry(o):
    return tuple(
        Intervention(f"capsule radius {o.radius:g} -> {o.radius / k:g}", {"radius": o.radius / k}) for k in (4, 16)
    )


def compliance(o):
    floor = 2 * o.timestep
    tc3, tc10 = max(floor, o.timeconst / 3), max(floor, o.timeconst / 10)
    d0, dmax, width, mid, power = o.solimp
    stiff = (max(d0, 0.99), max(dmax, 0.99), width, mid, power)
    dt16 = o.timestep / 16
    tc100 = max(2 * dt16, o.timeconst / 100)
    return (
        Intervention(f"time constant {o.timeconst:g} -> {tc3:g}", {"timeconst": tc3}),
        Intervention(
            f"time constant {o.timeconst:g} -> {tc10:g}, impedance {dmax:g} -> {stiff[1]:g}",
            {"timeconst": tc10, "solimp": stiff},
        ),
        Intervention(
            f"time constant {o.timeconst:g} -> {tc100:g}, impedance {dmax:g} -> {stiff[1]:g}, timestep {o.timestep:g} -> {dt16:g}",
            {"timeconst": tc100, "solimp": stiff, "timestep": dt16},
        ),
    )


def friction_law(o):
    now = o.timeconst if o.friction_timeconst is None else o.friction_timeconst
    steps = [max(2 * o.timestep, now / k) for k in (6, 30)]
    shorter = tuple(
        Intervention(f"friction time constant {now:g} -> {tf:g}", {"friction_timeconst": tf}, "friction time constant")
        for tf in steps
    )
    softer = tuple(
        Intervention(f"impratio {o.impratio:g} -> {r:g}", {"impratio": r}, "impratio")
        for r in (0.1 * o.impratio, 0.01 * o.impratio)
    )
    return shorter + softer


def feed_forward(o):
    d0, dmax, width, mid, power = o.solimp
    # lowered on every row as MuJoCo does it, the friction rows' R_t = R_n / impratio growing with R_n ...
    out = [
        Intervention(
            f"impedance {dmax:g} -> {d:g} on every row (impratio {o.impratio:g} kept)",
            {"solimp": (min(d0, d), min(dmax, d), width, mid, power)},
            "every row",
        )
        for d in (0.1, 0.01)
    ]
    for d in (0.5, 0.1, 0.01):  # ... then as the ladder's rung has it, the friction rows' R_t kept
        # R = (1 - d) / d w on every row: impratio scaled by the normal row's growth keeps the friction rows' R_t = R_n / impratio
        k = ((1.0 - d) / d) / ((1.0 - dmax) / dmax)
        out.append(
            Intervention(
                f"impedance {dmax:g} -> {d:g} (friction rows' regulariser kept: impratio {o.impratio:g} -> {o.impratio * k:.3g})",
                {"solimp": (min(d0, d), min(dmax, d), width, mid, power), "impratio": o.impratio * k},
                "friction rows kept",
            )
        )
    return tuple(out)


def discretisation(o):
    return tuple(
        Intervention(f"timestep {o.timestep:g} -> {o.timestep / k:g}", {"timestep": o.timestep / k}) for k in (4, 16)
    )
