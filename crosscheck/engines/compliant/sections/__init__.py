"""compliant's own sections."""

__all__ = ["sections"]


def sections() -> tuple:
    """The engine's own report sections, in report order (its ``ReportPlan.sections``)."""
    from crosscheck.engines.compliant.sections import limit

    return (limit.SECTION,)
