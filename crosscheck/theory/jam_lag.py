"""How late a spring contact's slip stop follows the rigid rod's Corollary 4.2 jam: the inner time and the pole of Painleve I.

The rigid rod meets p = 0 with b < 0 at t_jam (Corollary 4.2).  A contact
whose normal force is a spring, F_n = delta / eps^2 (plus damping; the
compliant rod, Drake's point contact), cannot jam there: its force has to
grow through an inner region first (``crosscheck.theory.compliant_limit``).
Near the jam p is linear in the normal impulse P, p = -k (P - P_jam), with

    k = -dp/dP = mu alpha^2 s c^2 cos^2 varphi (s - mu c sin varphi) / eta

(s, c = sin, cos theta: the turning of the slip direction during an impulse,
``crosscheck.theory.impact.darboux_keller``), and the penetration obeys
delta'' = -b - p F_n = |b| + k Q F_n with Q = P - P_jam, F_n = Q' = delta / eps^2
(damping dropped: it is smaller by a positive power of eps there).  So
eps^2 Q''' = |b| + k Q Q', and with Q = a q, t - t_jam = T s,

    T = (eps^4 / (k |b|))^(1/5),   a = (|b| T / k)^(1/2),   q''' = 1 + q q'.

Before the jam the rigid force is -b/p, i.e. Q = -(2 |b| (t_jam - t) / k)^(1/2),
q = -(-2 s)^(1/2); integrating once with that matching gives

    q'' = s + q^2 / 2,

the first Painleve equation (q = 12^(3/5) y, s = 12^(1/5) x gives y'' = 6 y^2 + x),
on the solution with q ~ -(-2 s)^(1/2) and no oscillation as s -> -inf (damping
removes the oscillating ones: Boutroux's tritronquee solution).  It has a pole,
q ~ 12 / (s* - s)^2, at s* = ``inner_pole()`` = 3.919 (12^(1/5) times the
tritronquee's first real pole, x ~ 2.3842): the impulse leaves the inner
region there, and the rest of the impact without collision is delivered on a
shorter time.  So the slip stop lags the rigid jam by

    t_stop - t_jam = s* (eps^4 / (k |b|))^(1/5) (1 + o(1)),

the eps^(4/5) law the compliant rod shows; measured on it (``tests/test_compliant_limit.py``),
the lag over s* T rises to 1 as 0.62-0.68, 0.75-0.77, 0.83-0.84 at eps = 1e-3, 1e-4,
1e-5.  A start close to the jam (the inner region not yet entered from the
rigid approach) stops sooner: Drake's point contact, x 10 to x 1000 stiffer,
at starts that jam at t ~ 3e-4, lags 0.18-0.32 s* T.

Where the rod slips at a small p > 0 without reaching 0 (a slip that passes close
to p = 0 and lifts off or slips on), the same penetration equation,
delta'' = -b - p delta / eps^2 linearised about the slipping force, is an
oscillator of frequency p^(1/2) / eps: the contact follows the rod's normal
motion in a time eps / p^(1/2), longer than its own eps by 1 / p^(1/2) where the
rod's effective normal mass m / p is large (``contact_time_at``).

Scaled units (section 2.1): eps, T and t in 1/omega, b in g/l.
"""

from __future__ import annotations

import functools
import math

from scipy.integrate import solve_ivp

__all__ = ["inner_pole", "jam_stiffness", "inner_scale", "spring_jam_lag", "P_FLOOR", "contact_time_at"]


@functools.lru_cache(maxsize=1)
def inner_pole() -> float:
    """s*, the pole of q'' = s + q^2/2 on the solution q ~ -(-2s)^(1/2) - (-2s)^(-2) (s -> -inf; module docstring).

    Integrated (DOP853, rtol 1e-12) from s0 = -200, where the two terms of the expansion leave an error
    O((-2 s0)^(-9/2)) that the equation's oscillating modes carry on undamped (amplitude ~1e-12), to q = 1e8;
    the pole is then s + (12 / q)^(1/2) from q ~ 12 / (s* - s)^2.
    """
    s0 = -200.0
    r = math.sqrt(-2.0 * s0)
    q0, dq0 = -r - r**-4, 1.0 / r - 4.0 * r**-6  # d/ds of -r - r^-4 with dr/ds = -1/r

    def blown(_s, y):
        return y[0] - 1e8

    blown.terminal = True
    sol = solve_ivp(
        lambda s, y: (y[1], s + 0.5 * y[0] ** 2),
        (s0, 10.0),
        (q0, dq0),
        method="DOP853",
        rtol=1e-12,
        atol=1e-12,
        events=blown,
    )
    s_end, q_end = float(sol.t_events[0][0]), float(sol.y_events[0][0][0])
    return s_end + math.sqrt(12.0 / q_end)


def jam_stiffness(theta: float, varphi: float, eta: float, mu: float, alpha: float) -> float:
    """k = -dp/dP: how fast eq. p falls with the normal impulse of an impact without collision (module docstring)."""
    s, c = math.sin(theta), math.cos(theta)
    return mu * alpha**2 * s * c * c * math.cos(varphi) ** 2 * (s - mu * c * math.sin(varphi)) / eta


def inner_scale(b: float, k: float) -> float:
    """(k |b|)^(-1/5): the inner time T over eps^(4/5), at a jam with b < 0 and k > 0; NaN elsewhere (no Corollary 4.2 jam,
    or the planar section k = 0, where p does not move with the impulse and the inner region is another)."""
    return (k * -b) ** -0.2 if b < 0.0 and k > 0.0 and math.isfinite(b * k) else math.nan


def spring_jam_lag(eps: float, scale: float) -> float:
    """s* scale eps^(4/5): the slip stop's lag behind the rigid jam for a spring contact of time ``eps`` (module docstring);
    0 where ``scale`` is NaN (no such jam) or ``eps`` is 0."""
    return inner_pole() * scale * eps**0.8 if eps > 0.0 and math.isfinite(scale) else 0.0


#: The least p at which ``contact_time_at`` is taken: a slip that passes closer to p = 0 without reaching it is given
#: the time at this p, a contact 1000 times stiffer than at p = 1, rather than an unbounded one.
P_FLOOR = 1e-3


def contact_time_at(p_min: float) -> float:
    """eps_p / eps = 1 / max(p_min, P_FLOOR)^(1/2): a spring contact's time where the rod's slip keeps eq. p >= p_min > 0,
    over its time at p = 1 (module docstring).  1 where p_min >= 1 (the contact is no slower there than at p = 1), where
    p_min <= 0 (the slip reaches p = 0: a jam, whose inner time ``spring_jam_lag`` gives, or a start at p <= 0) or where
    it is not a number."""
    if not 0.0 < p_min < 1.0:  # (NaN: no such p)
        return 1.0
    return max(float(p_min), P_FLOOR) ** -0.5
