"""The registered ``physx_pgs``: PhysX's engine with ``PgsOptions`` (PGS by default); imports SAPIEN."""

from crosscheck.engines.physx.engine import simulate, sweep
from crosscheck.engines.physx.options import PgsOptions as Options

__all__ = ["Options", "simulate", "sweep"]
