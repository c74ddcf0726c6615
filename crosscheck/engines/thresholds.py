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

    Attributes:
      window: W, the averaging window (scaled time).  A slipping soft
        contact cycles spike -> flight -> landing; measured cycle lengths in
        MuJoCo are ~0.1 (timestep 3e-3, i.e. dt = 1e-3 s for a 1 m rod),
        ~0.04 (3e-4) and ~0.01 (3e-5).  W = 0.05 (16 ms for a 1 m rod) averages
        over whole cycles at the default timestep and finer, and is still
        short against the O(1) time on which the rigid slipping state
        changes.  W is never fewer than ``window_steps`` rows, which covers
        coarse timesteps (40 x 3e-3 = 0.12 > one cycle).  With W = 0.02 and 10
        rows, landings of the chatter at dt = 1e-3 s were classified as jams
        below mu_P.
      window_steps: lower bound of W in rows (see ``window``).
      jam_force: JAM needs a window-mean normal force >= this [m g].  One
        m g, the weight: a slipping rod's window-mean force is the rigid
        -b/p = O(1) (below 1 unless b < -1 or p < 1), so this floor only
        rules out small forces whose ratio to a near-zero rigid force is big.
      jam_ratio: ... and >= this multiple of the window's rigid slipping
        force mean(max(0, -b)) / p_eff_W (p_eff_W: the force-weighted window
        mean of p_eff; the force counts as 0 where p_eff_W <= 0, as no
        slipping solution with the engine's friction holds the tip there).
        -b is clipped per row: a window mean of b itself is pulled to 0 by the
        b > 0 rows of a lift-off later in the window, and then the rigid force
        of a slip at small p_eff passed for 3x the rigid force.
      jam_slip_loss: ... and the contact point's slip speed eta falls by at
        least this fraction of its value within the window: the abrupt loss
        of slip speed of an impact without collision.  A rigid slipping rod
        loses speed at |eta'| = |Q1 F_z + A1| = O(1), i.e. a fraction
        O(W / eta) = O(0.05 / eta) per window.
      jam_p_eff: ... and p_eff_W <= this: the engine's rod is at its own
        p = 0, where the theory's jam happens.  0.2 is 5 % of the range
        1 + alpha = 4 of eq. p for the uniform rod, i.e. the slipping force
        -b/p_eff is already >= 5 |b| m g.  Measured in MuJoCo: the jams of
        Corollary 4.2 states it reproduces have p_eff 0.088-0.093; landings of
        a hopping (chattering) tip at mu = 1.3 < mu_P that pass the force and
        slip-loss tests have p_eff 0.45.
      lift_steps: LIFTOFF needs this many consecutive rows with zero normal
        force and upward tip acceleration.  During a force-free row the tip
        acceleration is exactly the free acceleration b of eq. b, so an upward
        acceleration there is the paper's lift-off condition b > 0; chatter
        flights of a slipping tip have b < 0 and never qualify.  More than one
        row, because the first row after a start without contact force is free
        even when the next position step then closes the gap.
      stick_speed: STICK when the contact point's slip speed eta falls below
        max(stick_speed, stick_creep tau_f) while the rod is in contact (some
        normal force in the last window); tau_f is the friction time constant
        of the run (0 for a rigid contact).  A stuck soft contact creeps at
        v ~ a_t dmax tau_f / 2 (a_t the tangential acceleration friction has
        to cancel, O(1) g): measured in MuJoCo 0.024, 0.008 and 0.002 for
        tau_f = 0.06, 0.02, 0.006, i.e. 0.4 tau_f, so a fixed 1e-2 reads a
        stuck rod as slipping at the default tau_f = 0.06.  The event time is
        early by at most the threshold / |eta'|, |eta'| = O(mu F_z).
      stick_creep: the multiple of tau_f in the STICK threshold: 1, i.e.
        2.5 x the measured creep.
      rigid_stick_steps: the STICK threshold of a rigid contact (``classify``'s
        ``rigid``) in units of the timestep.  A rigid tip sticks exactly at the
        end of a step (its NCP makes J v + dt dJ v vanish), so the velocity a
        record holds at the start of the next step is -dt dJ v_t, with
        |dJ v| = O(Theta^2 + Psi^2) <= ~10 in the paper's ranges: 10 dt.  The
        soft floor 1e-2 would read a slow slip whose direction swings round as
        eta -> 0 (the analytic run leaves the domain through varphi = 0 or
        -pi there) as STICK.
      launch_ratio: LAUNCH when a row with a contact force and b < 0 (the
        theory's free acceleration pulls the tip down: a rigid contact keeps
        it on the plane) is followed by an upward normal speed of the contact
        point of at least launch_ratio times the row's slip speed eta, at
        least launch_speed, and at least |b| W / 2 (so that a ballistic flight
        under b outlasts the window), then by a whole window with no contact
        force while b stays negative.  The scale is the slip speed because a convex relaxation of
        Coulomb's law separates a sliding contact at v_n = mu |v_t|
        (Anitescu's relaxation; Drake's SAP "gliding", Castro et al. 2023):
        0.45 l omega at eta = 1, mu = 1.4 in a probe of SAP at Psi just below
        Psi_L.  0.1 is a quarter of that at mu = 0.4.  MuJoCo's soft contact
        hops too: on 40 random slipping starts (mu = 1, horizon 1), runs with
        such a flight before their first event were 8, 4, 1, 7 and 8 at
        (timestep, timeconst) = (3e-3, 0.06), (1e-3, 0.06), (3e-4, 0.06),
        (3e-4, 0.02) and (1e-4, 0.006), with speeds 0.01-0.26 l omega; with
        launch_ratio 0.2, 3, 1, 0, 4, 7.  A regression-guard choice from
        these measurements, not a derived bound.
      launch_speed: the floor of a LAUNCH's upward speed [l omega].  As a
        slip slows to a stop, eta -> 0 and a soft contact's last hop passes
        launch_ratio eta at speeds of 0.01 l omega (MuJoCo and its law in
        continuous time, rising 2e-4 l, at the ladder test's STICKS start);
        MuJoCo's hops at its default (timestep 3e-4, timeconst 0.06) were at
        most 0.045 on the 40 starts above.  0.05 lies just above them and
        well below the 0.45 of SAP's gliding: a regression-guard choice.
      jam_contact_times: the look-back of a compliant slip stop's JAM test
        (``classify``'s ``contact_time`` tau_c > 0), in contact times: the
        stop is judged on the rows of the last jam_contact_times tau_c before
        it (at least lift_steps rows, the rigid rule's look-ahead).  3: the
        compliant rod's impulse grows as e^(lambda t / tau_c) up to the stop
        (``crosscheck.theory.compliant_limit``), so 3 tau_c hold a fraction
        1 - e^(-3 lambda) of it, 95 % at lambda = 1 (|p| = 0.5, xi = 1), and
        its mean force ~ P_stop / (3 tau_c) is O(1/tau_c) >> -b/p; a longer
        look-back only dilutes the mean towards the slipping force of the
        rows before the jam.  Measured: from the inconsistent start mu = 2,
        theta = pi/4 the compliant rod's slip falls from 80 % to 0 in
        1.0-1.5 eps (eps = 0.03-0.001), and the look-back holds 93-97 % of
        the fast problem's P_stop; Drake's continuous Hunt-Crossley contact
        at stiffness 1e6 (tau_c = 1e-3) from a Corollary 4.2 start falls
        from 77 % to 0 in 2 tau_c.
      diverged_speed: DIVERGED when the scaled tip speed exceeds this (energy
        is bounded: a slipping rod of the paper's ranges never exceeds O(10)),
        when any value is not finite, or when the engine's clock stops
        advancing (``mujoco.rollout`` stops stepping after a MuJoCo warning
        and repeats the last row).  A divergence is the outcome also after
        theta has left (0, pi/2) (with ``exit_time`` before it): an engine
        that blows up is never hidden as a censored SLIP.
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
