"""The report's sections, in report order: the analytic figures of the paper, the printed numbers and the GB
manifold (sections 3.5 to 5), then every registered engine's sections, generated from its ``EngineSpec``.

An engine's sections are its outcome maps (``engine_maps``), at the maps' options its contact-force quality
(``engine_contact``), lift-off onset (``engine_onset``) and the paper's IC1 and IC2 (``engine_ic``), its
convergence (``engine_convergence``) and its ladder (``engine_ladder``) where its ``ReportPlan`` asks for them,
then the sections it declares as its own (MuJoCo's friction skew, the compliant limit, ...).  ``all_sections()`` reads the registry when called, so an engine registered at run
time (``crosscheck.engines.register``) has its sections in the next report; ``SECTIONS`` is ``all_sections()``
read at attribute access.
"""

from __future__ import annotations

from crosscheck.engines.spec import resolve
from crosscheck.report.section import Section
from crosscheck.report.sections import (
    bifurcations,
    critical_angles,
    engine_contact,
    engine_convergence,
    engine_ic,
    engine_impact,
    engine_interventions,
    engine_ladder,
    engine_maps,
    engine_onset,
    engine_psi,
    engine_rounding,
    gb_det_zeros,
    gb_eigenvectors,
    gb_local,
    gb_manifold,
    gb_quartic,
    gb_separatrix,
    impact_engines,
    kinematic_cases,
    kinematic_surfaces,
    mechanisms,
    mode_maps,
    p_region,
    printed_numbers,
    psi_engines,
)

__all__ = ["SECTIONS", "THEORY_SECTIONS", "all_sections", "cross_engine_sections", "engine_sections", "section_by_slug"]

#: The sections of the theory alone (no engine), in report order.
THEORY_SECTIONS: tuple[Section, ...] = (
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
)


def engine_sections(spec) -> tuple[Section, ...]:
    """The sections of one engine (``crosscheck.engines.EngineSpec``): maps, convergence, then its own."""
    plan = spec.report
    if plan is None:
        return ()
    out = []
    if plan.maps is not None:
        out.append(engine_maps.section(spec, plan.maps, beside=plan.beside, n=plan.maps_n))
        out.append(engine_contact.section(spec, plan.maps))
        if plan.onset:
            out.append(engine_onset.section(spec, plan.maps))
        out.append(engine_ic.section(spec, plan.maps))
        out.append(engine_impact.section(spec, plan.maps))
        out.append(engine_psi.section(spec, plan.maps))
        out.append(engine_rounding.section(spec, plan.maps, plan.maps_n))
    if plan.convergence is not None:
        out.append(engine_convergence.section(spec, plan.convergence, plan.convergence_n))
    if plan.ladder and plan.maps is not None:  # after its maps: it ladders their disagreements
        out.append(engine_ladder.section(spec, plan.maps, f"{spec.slug}_maps", plan.ladder_states))
    if plan.sections is not None:
        out.extend(resolve(plan.sections)())
    ladder = next((s for s in out if s.slug == f"{spec.slug}_ladder"), None)
    if spec.interventions and ladder is not None:  # after its ladder: it reruns the ladder's starts
        out.append(engine_interventions.section(spec, ladder))
    return tuple(out)


def all_sections(names=None) -> tuple[Section, ...]:
    """Every section in report order: the theory's, then each engine's (``crosscheck.engines.specs()`` order).

    names: the engines whose sections are included (None: every engine); an engine that cannot run here (its library
    is not installed: ``EngineSpec.unavailable``) has none (``skipped_engines`` says why, one line each).
    """
    from crosscheck import engines

    chosen = [s for s in engines.specs() if (names is None or s.name in names) and not s.unavailable()]
    return THEORY_SECTIONS + tuple(s for spec in chosen for s in engine_sections(spec)) + cross_engine_sections(chosen)


def cross_engine_sections(specs) -> tuple[Section, ...]:
    """The sections that gather every engine's results of one study into one figure (after the engines' own)."""
    return (impact_engines.section(specs), psi_engines.section(specs))


def skipped_engines(names=None) -> list[str]:
    """One line per engine (of ``names``, None: all) whose sections ``all_sections`` leaves out, saying why."""
    from crosscheck import engines

    return [
        f"skipped {s.label}'s sections: {s.unavailable()}"
        for s in engines.specs()
        if (names is None or s.name in names) and s.unavailable()
    ]


def __getattr__(name: str):
    if name == "SECTIONS":
        return all_sections()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def section_by_slug(slug: str, sections=None) -> Section:
    """The section named ``slug`` among ``sections`` (all by default); ValueError listing the valid names otherwise."""
    sections = all_sections() if sections is None else sections
    for s in sections:
        if s.slug == slug:
            return s
    raise ValueError(f"--only must be one of: {', '.join(s.slug for s in sections)}; got {slug!r}")
