"""mujoco's own sections."""

__all__ = ["sections"]


def sections() -> tuple:
    """The engine's own report sections, in report order (its ``ReportPlan.sections``)."""
    from crosscheck.engines.mujoco.sections import friction_skew, liftoff, trajectories, validate

    return (liftoff.SECTION, trajectories.SECTION, validate.SECTION, friction_skew.SECTION)
