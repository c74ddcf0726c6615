"""crosscheck: the 3D Painleve rod, analytic reference vs Pinocchio vs MuJoCo.

Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painleve paradox*.
"""

from crosscheck import analytic
from crosscheck.analytic import Mode, critical_values, mode
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__version__ = "0.1.0"

__all__ = ["Rod", "SlipState", "Mode", "Outcome", "analytic", "critical_values", "mode", "__version__"]
