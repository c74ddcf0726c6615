"""The one place where the paper's variables meet generalised coordinates.

Generalised coordinates q = (X, Y, Z, psi, theta) [m, m, m, rad, rad] and
velocities v = (X', Y', Z', psi', theta') [m/s, rad/s], with (X, Y, Z) the
centre of mass S in the world frame and the body rotation Rz(psi) Rx(theta)
(eq. rotmatrix).  Every engine (Pinocchio, MuJoCo) orders its joints this way.

The paper's variables are scaled (section 2.1): Theta = theta'/omega,
Psi = psi'/omega, eta = |tip velocity| / (l omega), varphi = beta - psi with
beta the heading of the tip velocity; tip position in units of l and tip normal
velocity w in units of l omega.
"""

from __future__ import annotations

import numpy as np

from crosscheck.checks import FINITE, NONNEGATIVE, THETA, real, same_shape
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__all__ = [
    "GENERALIZED",
    "tip_position",
    "tip_velocity",
    "paper_to_qv",
    "qv_of",
    "qv_to_paper",
    "to_generalized",
    "from_generalized",
]

#: Names of the generalised coordinates, in order.
GENERALIZED = ("X", "Y", "Z", "psi", "theta")


def _rod(rod) -> Rod:
    if not isinstance(rod, Rod):
        raise ValueError(f"rod must be a Rod (crosscheck.Rod); got {type(rod).__name__}")
    return rod


def _qv(q, v) -> tuple[np.ndarray, np.ndarray]:
    """q and v as real (..., 5) arrays of one shape (ValueError naming them otherwise)."""
    q, v = real("q", q, FINITE), real("v", v, FINITE)
    if q.shape[-1:] != (5,) or q.shape != v.shape:
        raise ValueError(
            f"q and v must have one shape (..., 5) ({', '.join(GENERALIZED)}); got {q.shape} and {v.shape}"
        )
    return q, v


def tip_position(rod: Rod, q) -> np.ndarray:
    """Tip A in the world frame [m], eq. tipfromcentre.  q: (..., 5) -> (..., 3)."""
    q = np.asarray(q, dtype=float)
    X, Y, Z, psi, theta = np.moveaxis(q, -1, 0)
    l = rod.length
    return np.stack(
        (X + l * np.cos(theta) * np.sin(psi), Y - l * np.cos(theta) * np.cos(psi), Z - l * np.sin(theta)), -1
    )


def tip_velocity(rod: Rod, q, v) -> np.ndarray:
    """Velocity of the tip A in the world frame [m/s], the derivative of eq. tipfromcentre."""
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    _, _, _, psi, theta = np.moveaxis(q, -1, 0)
    dX, dY, dZ, dpsi, dtheta = np.moveaxis(v, -1, 0)
    l = rod.length
    s, c, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    return np.stack(
        (
            dX + l * (-s * sp * dtheta + c * cp * dpsi),
            dY + l * (s * cp * dtheta + c * sp * dpsi),
            dZ - l * c * dtheta,
        ),
        -1,
    )


def paper_to_qv(rod: Rod, theta, varphi, Theta, Psi, eta, psi=0.0, *, tip=(0.0, 0.0, 0.0), w=0.0):
    """Generalised (q, v) [physical units] from the paper's scaled variables.

    Args:
      theta, varphi, Theta, Psi, eta, psi: as in ``SlipState`` (scaled); arrays broadcast.
      tip: tip position (x, y, z) in units of l (default: at the origin, on the plane).
      w: scaled normal velocity of the tip (0 while slipping).

    Returns:
      (q, v), each an (..., 5) array ordered as ``GENERALIZED``.
    """
    _rod(rod)
    theta = real("theta", theta, THETA)
    eta = real("eta", eta, NONNEGATIVE)
    varphi, Theta, Psi, psi, w = (
        real(n, x, FINITE) for n, x in (("varphi", varphi), ("Theta", Theta), ("Psi", Psi), ("psi", psi), ("w", w))
    )
    theta, varphi, Theta, Psi, eta, psi, w = same_shape(
        theta=theta, varphi=varphi, Theta=Theta, Psi=Psi, eta=eta, psi=psi, w=w
    )
    tip = real("tip", tip, FINITE)
    if tip.shape[-1:] != (3,):
        raise ValueError(f"tip must have shape (..., 3) (x, y, z in units of l); got {tip.shape}")
    return qv_of(rod.length, rod.omega, theta, varphi, Theta, Psi, eta, psi, tip, w)


def qv_of(l, om, theta, varphi, Theta, Psi, eta, psi, tip, w):
    """``paper_to_qv`` from the rod's length l [m] and omega [1/s] (floats, or one rod's per state, for many rods in one
    call: the same arithmetic state by state), arguments unchecked arrays (tip (..., 3) in units of l)."""
    tip = tip * (l[..., None] if np.ndim(l) else l)
    s, c, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    q = np.stack(
        np.broadcast_arrays(tip[..., 0] - l * c * sp, tip[..., 1] + l * c * cp, tip[..., 2] + l * s, psi, theta), -1
    )
    dtheta, dpsi = Theta * om, Psi * om
    beta = psi + varphi
    u, vv, ww = eta * l * om * np.cos(beta), eta * l * om * np.sin(beta), w * l * om
    v = np.stack(
        (
            u - l * (-s * sp * dtheta + c * cp * dpsi),
            vv - l * (s * cp * dtheta + c * sp * dpsi),
            ww + l * c * dtheta,
            dpsi,
            dtheta,
        ),
        -1,
    )
    return q, v


def qv_to_paper(rod: Rod, q, v) -> dict[str, np.ndarray]:
    """The paper's scaled variables from (q, v) [physical units].

    Returns a dict with theta, varphi, Theta, Psi, eta, psi, and the tip's
    scaled position x, y, z and normal velocity w.  varphi is wrapped to
    (-pi, pi]; it lies in the paper's (-pi, 0] only for states of that range.
    """
    _rod(rod)
    q, v = _qv(q, v)
    l, om = rod.length, rod.omega
    tip = tip_position(rod, q) / l
    tv = tip_velocity(rod, q, v) / (l * om)
    psi, theta = q[..., 3], q[..., 4]
    beta = np.arctan2(tv[..., 1], tv[..., 0])
    varphi = np.angle(np.exp(1j * (beta - psi)))
    return {
        "theta": theta,
        "varphi": varphi,
        "Theta": v[..., 4] / om,
        "Psi": v[..., 3] / om,
        "eta": np.hypot(tv[..., 0], tv[..., 1]),
        "psi": psi,
        "x": tip[..., 0],
        "y": tip[..., 1],
        "z": tip[..., 2],
        "w": tv[..., 2],
    }


def to_generalized(rod: Rod, state: SlipState, *, tip=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) of a ``SlipState`` with the tip at ``tip`` (units of l) on the plane."""
    if not isinstance(state, SlipState):
        raise ValueError(f"state must be a SlipState; got {type(state).__name__}")
    return paper_to_qv(rod, state.theta, state.varphi, state.Theta, state.Psi, state.eta, state.psi, tip=tip)


def from_generalized(rod: Rod, q, v) -> SlipState:
    """The ``SlipState`` of a single (q, v); raises if it is outside the paper's ranges."""
    q, v = _qv(q, v)
    if q.shape != (5,) or v.shape != (5,):
        raise ValueError(f"q and v must each have shape (5,) ({', '.join(GENERALIZED)}); got {q.shape} and {v.shape}")
    d = qv_to_paper(rod, q, v)
    return SlipState(**{k: float(d[k]) for k in ("theta", "varphi", "Theta", "Psi", "eta", "psi")})
