"""The GB manifold b = p = 0, the matrix K and the desingularised slipping flow (sections 4-5 of the paper).

``slip_until_event`` (the slipping rod run to its first event) lives in
``crosscheck.slipping`` and is re-exported here.
"""

from __future__ import annotations

from crosscheck.slipping import X_STATE, SlipResult, slip_outcomes, slip_rhs, slip_until_event

__all__ = ["X_STATE", "SlipResult", "slip_outcomes", "slip_rhs", "slip_until_event"]
