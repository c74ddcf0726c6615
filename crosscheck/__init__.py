"""crosscheck: the 3D Painleve rod, analytic reference vs Pinocchio vs MuJoCo.

Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painleve paradox*.
"""

from crosscheck import analytic
from crosscheck.analytic import Mode, critical_values, mode
from crosscheck.coordinates import from_generalized, to_generalized
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState

__version__ = "0.1.0"

# Layout: the theory at the top of the package (analytic, critical, gb, slipping,
# corollary, coordinates, paper), the contact engines in crosscheck.engines (looked
# up by name: crosscheck.engines.get("mujoco")), the studies that compare any engine
# with the theory in crosscheck.studies, the report in crosscheck.report and the
# command line in crosscheck.cli.  Engines and studies are imported by name:
# importing crosscheck alone does not load Pinocchio or MuJoCo.
__all__ = [
    "Rod",
    "SlipState",
    "Mode",
    "Outcome",
    "analytic",
    "critical_values",
    "mode",
    "to_generalized",
    "from_generalized",
    "__version__",
]
