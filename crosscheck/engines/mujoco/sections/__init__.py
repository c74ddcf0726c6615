"""mujoco's own sections."""

__all__ = ["sections"]


def sections() -> tuple:
    """The engine's own report sections, in report order (its ``ReportPlan.sections``)."""
    from crosscheck.engines.mujoco.sections import friction_skew, ladder, liftoff, trajectories, validate

    # the ladder last: it reads the saved results of MuJoCo's map section
    return (liftoff.SECTION, trajectories.SECTION, validate.SECTION, friction_skew.SECTION, ladder.SECTION)
