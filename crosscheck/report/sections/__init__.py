"""The report's sections, in report order: the analytic figures of the paper, the printed numbers,
the GB manifold (sections 3.5 to 5), then the Pinocchio and MuJoCo cross-validations and the rigid engine."""

from __future__ import annotations

from crosscheck.report.section import Section
from crosscheck.report.sections import compliant_limit
from crosscheck.report.sections import ladder
from crosscheck.report.sections import bifurcations, critical_angles, friction_skew, gb_det_zeros, gb_eigenvectors, gb_local, gb_manifold, gb_quartic, gb_separatrix, kinematic_cases, kinematic_surfaces, mechanisms, mode_maps, mujoco_convergence, mujoco_liftoff, mujoco_maps, mujoco_trajectories, mujoco_validate, p_region, pinocchio, printed_numbers, rigid_engine

__all__ = ["SECTIONS", "section_by_slug"]

SECTIONS: tuple[Section, ...] = (
    p_region.SECTION,
    mode_maps.SECTION,
    kinematic_surfaces.SECTION,
    kinematic_cases.SECTION,
    bifurcations.SECTION,
    mechanisms.SECTION,
    critical_angles.SECTION,
    printed_numbers.SECTION,
    gb_manifold.SECTION,
    gb_eigenvectors.SECTION,
    gb_local.SECTION,
    gb_quartic.SECTION,
    gb_det_zeros.SECTION,
    gb_separatrix.SECTION,
    pinocchio.SECTION,
    mujoco_liftoff.SECTION,
    mujoco_maps.SECTION,
    mujoco_convergence.SECTION,
    mujoco_trajectories.SECTION,
    mujoco_validate.SECTION,
    # MuJoCo's contact law written out: its friction-direction skew predicted and measured
    friction_skew.SECTION,
    # the rigid engine on the same starts as MuJoCo's maps; the quick report at a coarser timestep (its cost is the NCP's)
    mujoco_maps.section("rigid_maps", "Rigid engine (Pinocchio) vs analytic: outcome maps beside MuJoCo's", "pinocchio",
                        {"quick": {"timestep": 3e-3}, "full": {"timestep": 1e-3}}, beside="mujoco_maps"),
    mujoco_convergence.section("rigid_convergence", "Rigid engine (Pinocchio) vs analytic: convergence in timestep", "pinocchio",
                               {"quick": [{"timestep": dt} for dt in (1e-2, 3e-3, 1e-3)],
                                "full": [{"timestep": dt} for dt in (3e-3, 1e-3, 3e-4)]}, n={"quick": 5, "full": 14}),
    rigid_engine.SECTION,
    # the compliant rod as eps -> 0 against the impact without collision (after the rigid engine's jams)
    compliant_limit.SECTION,
    # a named cause for each MuJoCo-theory disagreement of mujoco_maps (reads that section's saved results in the full report)
    ladder.SECTION,
)


def section_by_slug(slug: str) -> Section:
    """The section named ``slug``; ValueError listing the valid names otherwise."""
    for s in SECTIONS:
        if s.slug == slug:
            return s
    raise ValueError(f"--only must be one of: {', '.join(s.slug for s in SECTIONS)}; got {slug!r}")
