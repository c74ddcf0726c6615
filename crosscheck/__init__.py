"""crosscheck: the 3D Painleve rod, analytic reference vs Pinocchio vs MuJoCo.

Reference: Cheesman, Hogan & Kristiansen, *The geometry of the Painleve paradox*.
"""

from crosscheck.coordinates import from_generalized, to_generalized
from crosscheck.outcome import Outcome
from crosscheck.rod import Rod
from crosscheck.state import SlipState
from crosscheck.theory import analytic
from crosscheck.theory.analytic import Mode, critical_values, mode

__version__ = "0.1.0"

# Layout: the core every layer uses at the top of the package (rod, state, outcome,
# coordinates, checks, files, tolerances); the paper's theory in crosscheck.theory;
# the contact engines in crosscheck.engines, one subpackage each, found through its
# registry; the studies that compare any engine with the theory in crosscheck.studies;
# resumable sweeps in crosscheck.sweeps; the report in crosscheck.report and the command
# line in crosscheck.cli.  Engines are imported when they run: importing crosscheck
# alone loads no engine library.
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
