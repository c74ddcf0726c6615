"""The classifier's criteria, each number with where it comes from (``crosscheck.engines.classifier`` applies them)."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from crosscheck.checks import NONNEGATIVE, POSITIVE, check

__all__ = ["Thresholds"]


@dataclass(frozen=True)
class Thresholds:
    """Quantitative criteria of ``classify``, in the paper's scaled units.

    Each number's derivation and the measurements behind it are in ``docs/thresholds.md``; in short:

    Attributes:
      window: W, the averaging window (scaled time): whole cycles of a soft contact's chatter (MuJoCo's last ~0.04
        at timestep 3e-4), short against the O(1) time of the rigid slip.
      window_steps: lower bound of W in rows (coarse timesteps: 40 x 3e-3 = 0.12 > one cycle).
      jam_force: JAM needs a window-mean normal force >= this [m g], the weight: rules out small forces whose ratio
        to a near-zero rigid force is big.
      jam_ratio: ... and >= this multiple of the window's rigid slipping force mean(max(0, -b)) / p_eff_W (0 where
        p_eff_W <= 0: no slipping solution with the engine's friction).
      jam_slip_loss: ... and the slip speed eta falls by at least this fraction within the window (a rigid slip
        loses O(W / eta) per window).
      jam_p_eff: ... and p_eff_W <= this: the engine's rod at its own p = 0 (5 % of 1 + alpha; MuJoCo's
        reproduced Corollary 4.2 jams read 0.09, its hopping landings below mu_P 0.45).
      lift_steps: LIFTOFF needs this many consecutive force-free rows with upward tip acceleration (then the free
        acceleration b > 0); more than one, as the first row after a force-free start is free anyway.
      stick_speed: STICK when eta < max(stick_speed, stick_creep tau_f) with some normal force in the last window
        (tau_f the run's friction time constant, 0 for a rigid contact).
      stick_creep: the multiple of tau_f in that threshold: 2.5 x the creep measured in MuJoCo (0.4 tau_f).
      rigid_stick_steps: a rigid contact's STICK threshold in timesteps: its record holds -dt dJ v_t after it
        sticks, |dJ v| <= ~10.
      launch_ratio: LAUNCH when a contact row with b < 0 is followed by an upward speed >= launch_ratio eta (and
        launch_speed, and |b| W / 2), then a window without contact force under b < 0: a convex relaxation's
        separation at v_n = mu |v_t| (SAP's "gliding").  A regression-guard choice from measurements.
      launch_speed: the floor of that upward speed [l omega], above a soft contact's last hops as a slip stops
        (MuJoCo's at most 0.045) and below SAP's 0.45.  A regression-guard choice.
      jam_contact_times: the look-back of a compliant slip stop's JAM test in contact times (at least lift_steps
        rows): 3 tau_c hold 95 % of the stop's impulse at lambda = 1 (``crosscheck.theory.compliant_limit``).
      diverged_speed: DIVERGED beyond this scaled tip speed (a slipping rod never exceeds O(10)), at a non-finite
        value, or when the engine's clock stops; reported also after theta left (0, pi/2).
    """

    window: float = 0.05
    window_steps: int = 40
    jam_force: float = 1.0
    jam_ratio: float = 3.0
    jam_slip_loss: float = 0.2
    jam_p_eff: float = 0.2
    lift_steps: int = 3
    stick_speed: float = 1e-2
    stick_creep: float = 1.0
    rigid_stick_steps: float = 10.0
    launch_ratio: float = 0.1
    launch_speed: float = 0.05
    jam_contact_times: float = 3.0
    diverged_speed: float = 1e3

    def __post_init__(self) -> None:
        for name in ("window", "jam_ratio", "diverged_speed"):
            object.__setattr__(self, name, float(check(name, getattr(self, name), POSITIVE)))
        for name in (
            "jam_force",
            "jam_slip_loss",
            "jam_p_eff",
            "stick_speed",
            "stick_creep",
            "rigid_stick_steps",
            "launch_ratio",
            "launch_speed",
            "jam_contact_times",
        ):
            object.__setattr__(self, name, float(check(name, getattr(self, name), NONNEGATIVE)))
        for name in ("window_steps", "lift_steps"):
            v = getattr(self, name)
            if not (isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 1):
                raise ValueError(f"{name} must be an integer >= 1; got {v!r}")
            object.__setattr__(self, name, int(v))

    def window_rows(self, timestep: float) -> int:
        """Window length in rows for scaled timestep ``timestep``."""
        return max(int(self.window_steps), int(math.ceil(self.window / timestep - 1e-9)))

    def stop_rows(self, contact_time: float, timestep: float) -> int:
        """Look-back of a compliant slip stop's JAM test in rows: jam_contact_times contact times, at least lift_steps rows."""
        return max(int(self.lift_steps), int(math.ceil(self.jam_contact_times * contact_time / timestep - 1e-9)))

    def stick_threshold(self, friction_timeconst: float) -> float:
        """Slip speed below which a run with friction time constant ``friction_timeconst`` is stuck."""
        return max(self.stick_speed, self.stick_creep * friction_timeconst)

    def stick_floor(self, *, timestep: float, friction_timeconst: float, rigid: bool) -> float:
        """The slip speed below which ``classify`` calls a contact stuck: rigid_stick_steps timesteps for a rigid
        contact, ``stick_threshold(friction_timeconst)`` otherwise."""
        return self.rigid_stick_steps * timestep if rigid else self.stick_threshold(friction_timeconst)

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}
