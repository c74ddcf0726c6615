"""pinocchio's own sections."""

__all__ = ["sections"]


def sections() -> tuple:
    """The engine's own report sections, in report order (its ``ReportPlan.sections``)."""
    from crosscheck.engines.pinocchio.sections import dynamics_terms, rigid_engine

    return (dynamics_terms.SECTION, rigid_engine.SECTION)
