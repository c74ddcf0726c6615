"""What tests the numpy rod's one cause, compliance: a stiffer spring, its timestep shortened to keep sqrt(k) dt."""

from crosscheck.engines.spec import Intervention


def compliance(options):
    """The spring 10 and 100 times stiffer (weakest first), the timestep over sqrt(10) each time (stable steps)."""
    k, dt = options.stiffness, options.timestep
    return tuple(
        Intervention(f"stiffness {k:g} -> {k * f:g}", {"stiffness": k * f, "timestep": dt / f**0.5}) for f in (10, 100)
    )
