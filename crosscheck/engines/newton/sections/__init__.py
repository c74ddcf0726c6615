"""Report sections of the Newton engines."""

__all__ = ["sections"]


def sections() -> tuple:
    """Newton's own report section, in report order (its ``ReportPlan.sections``)."""
    from crosscheck.engines.newton.sections import mujoco_c

    return (mujoco_c.SECTION,)
