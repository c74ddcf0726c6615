"""The options every command shares (the rod's state and parameters), with help that states each range.

The ranges come from ``crosscheck.checks``, which also checks the values, so
the help and the error of an option always say the same thing.
"""

from __future__ import annotations

from crosscheck.checks import ALPHA, AZIMUTH, ETA, MU, RATE, THETA, VARPHI

#: (help, metavar) of each state option; metavars differ where only the case does (--theta / --Theta).
STATE_HELP = {
    "theta": (f"polar angle of the rod to the plane [rad], in {THETA}", "THETA"),
    "varphi": (f"relative slip angle beta - psi [rad], in {VARPHI}", "VARPHI"),
    "Theta": (f"scaled polar rate theta_dot / omega, in {RATE}", "THETA_DOT"),
    "Psi": (f"scaled azimuthal rate psi_dot / omega, in {RATE}", "PSI_DOT"),
    "eta": (f"scaled slip speed of the tip, in {ETA}", "ETA"),
    "mu": (f"friction coefficient, in {MU}", "MU"),
}


def add_state(parser, names=("theta", "varphi", "Theta", "Psi", "eta", "mu"), *, required: bool = True) -> None:
    """Add the state options ``names`` (text, parsed by ``crosscheck.checks.number`` so the CLI and the API agree)."""
    for name in names:
        text, metavar = STATE_HELP[name]
        parser.add_argument(f"--{name}", type=str, metavar=metavar, required=required, help=text)


def add_alpha(parser) -> None:
    parser.add_argument("--alpha", type=str, default="3", metavar="ALPHA", help=f"m l^2 / I0, in {ALPHA} (default 3: uniform rod)")


def add_psi(parser) -> None:
    parser.add_argument("--psi", type=str, default="0", metavar="PSI", help=f"azimuth [rad], in {AZIMUTH} (default 0)")
