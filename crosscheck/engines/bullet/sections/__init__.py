"""Bullet's own report sections (beside the generic ones every engine gets)."""

__all__ = ["sections"]


def sections() -> tuple:
    """The engine's own report sections, in report order (its ``ReportPlan.sections``)."""
    from crosscheck.engines.bullet.sections import azimuth

    return (azimuth.SECTION,)
