"""The report's sections, in report order: the analytic figures of the paper, the printed numbers,
the GB manifold (sections 3.5 to 5), then the Pinocchio and MuJoCo cross-validations."""

from __future__ import annotations

from crosscheck.report.section import Section
from crosscheck.report.sections import critical_angles, gb_det_zeros, gb_eigenvectors, gb_manifold, gb_quartic, gb_separatrix, kinematic_cases, mechanisms, mode_maps, mujoco_convergence, mujoco_liftoff, mujoco_maps, mujoco_trajectories, mujoco_validate, p_region, pinocchio, printed_numbers

__all__ = ["SECTIONS", "section_by_slug"]

SECTIONS: tuple[Section, ...] = (
    p_region.SECTION,
    mode_maps.SECTION,
    kinematic_cases.SECTION,
    mechanisms.SECTION,
    critical_angles.SECTION,
    printed_numbers.SECTION,
    gb_manifold.SECTION,
    gb_eigenvectors.SECTION,
    gb_quartic.SECTION,
    gb_det_zeros.SECTION,
    gb_separatrix.SECTION,
    pinocchio.SECTION,
    mujoco_liftoff.SECTION,
    mujoco_maps.SECTION,
    mujoco_convergence.SECTION,
    mujoco_trajectories.SECTION,
    mujoco_validate.SECTION,
)


def section_by_slug(slug: str) -> Section:
    """The section named ``slug``; ValueError listing the valid names otherwise."""
    for s in SECTIONS:
        if s.slug == slug:
            return s
    raise ValueError(f"unknown report section {slug!r}; sections are: {', '.join(s.slug for s in SECTIONS)}")
