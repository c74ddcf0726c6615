"""What an engine declares about itself: one ``EngineSpec`` record, the only place the harness learns an engine.

Each engine subpackage (``crosscheck/engines/<name>/``) exposes ``ENGINES``, a
tuple of ``EngineSpec``: its registered names (one subpackage may register
several, as Drake's contact approximations do), a label for tables, the
libraries whose versions go into provenance and into a result store's key,
its options and thread/process knob, the columns of its solver statistics,
its event-tolerance profile, the tags studies and report sections select on,
the models in between it and the theory (for the ladder) and the report
sections it owns.  ``crosscheck.engines`` (the registry) collects them;
studies, sweeps, tolerances, findings and provenance read the registry and
never name an engine.

Everything an engine takes and returns is in the paper's scaled units
(section 2.1): time in 1/omega, lengths in l, velocities in l omega,
accelerations in g, forces in m g; so are its ``Options``.
"""

from __future__ import annotations

import importlib
import inspect
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["EngineSpec", "ReportPlan", "Intervention", "TAGS", "LADDER_CAUSES"]

#: Tags an engine may carry, and what each promises:
#:   rigid: the contact is the theory's rigid Coulomb contact (no penetration, no compliance);
#:   compliant: the normal force comes from a penetration law (a spring-damper of some stiffness);
#:   relaxed: the contact problem is a convex or regularised relaxation of Coulomb's law (MuJoCo, Drake SAP);
#:   time_stepping: a fixed timestep, one impulse per step (``Options.timestep`` is the step);
#:   continuous: an error-controlled integrator; ``Options.timestep`` is only the spacing of record rows;
#:   batched: ``sweep`` runs a batch in one call of the library (faster than one ``simulate`` per state).
TAGS = frozenset({"rigid", "compliant", "relaxed", "time_stepping", "continuous", "batched"})

#: The causes a ladder can name, in the order of its rungs (each rung one model closer to the engine): the contact
#: point's place, the contact's compliance, the engine's friction law (its own law in continuous time), a
#: normal force that feeds the rigid force forward at once where a spring builds it (MuJoCo's impedance), the time
#: step, and the convex relaxation of the step's contact problem (a relaxed engine against a non-relaxed step of the
#: same law and timestep: the mechanism behind SAP's "gliding", its launch of a slipping tip).
LADDER_CAUSES = ("geometry", "compliance", "friction law", "feed-forward", "discretisation", "relaxation")


@dataclass(frozen=True)
class Intervention:
    """One change of the engine itself in the way a cause names (``EngineSpec.interventions``).

    Attributes:
      text: what it does, for tables ("capsule radius 0.01 -> 0.000625").
      options: the engine's options to set over the run's (scaled units), e.g. ``{"radius": 6.25e-4}``.
      family: which way of the cause it takes, where a cause has two ("impratio", "friction time constant"): each
        family runs weakest first, and its last is its strongest; "" for a cause with one way.
    """

    text: str
    options: Mapping[str, Any]
    family: str = ""


@dataclass(frozen=True)
class ReportPlan:
    """The report sections generated for an engine, with its settings in each report.

    Attributes:
      maps: {"quick": options, "full": options} of its outcome-map section (None: no map section).
      convergence: {"quick": [options, ...], "full": [...]} of its convergence section (None: none).
      convergence_n: {"quick": n, "full": n}, the (theta, Theta) grid size of that section (None: the section's default).
      maps_n: {"quick": n, "full": n}, the size of each n x n outcome map (None: the section's default, 10 and 32);
        smaller for an engine whose runs cost more (the report says so in the section's parameters).
      beside: slug of another map section drawn beside this engine's (None: drawn alone).
      sections: a callable returning the engine's own sections (``crosscheck.report.section.Section``),
        placed after its generic ones; called when the report is built, so the engine's report code is
        imported only then.
      ladder: whether the generic ladder section (``<slug>_ladder``: the disagreements of its maps through
        ``crosscheck.studies.ladder``) is generated (False for an engine without a ladder or with its own, as MuJoCo's).
      onset: whether the generic lift-off onset section (``<slug>_liftoff``) is generated (False for an engine
        that declares its own, as MuJoCo's over its timestep).
      order: where the engine's sections stand among the engines' (lower first).
      ladder_section: slug of the section whose saved ladders the engine's interventions section reads
        (None: ``<slug>_ladder`` when ``ladder``; MuJoCo's own ladder section is "ladder").
    """

    maps: Mapping[str, Mapping] | None = None
    convergence: Mapping[str, Any] | None = None
    convergence_n: Mapping[str, int] | None = None
    maps_n: Mapping[str, int] | None = None
    beside: str | None = None
    sections: Callable[[], tuple] | None = None
    onset: bool = True
    ladder: bool = False
    order: int = 100
    ladder_section: str | None = None


def _check_rod_and_thresholds(rod, thresholds) -> None:
    """One ValueError line for a ``rod`` that is not a ``Rod`` or ``thresholds`` that are not ``Thresholds`` (or None)."""
    from crosscheck.engines.classifier import Thresholds
    from crosscheck.rod import Rod

    if not isinstance(rod, Rod):
        raise ValueError(f"rod must be a crosscheck.Rod; got {type(rod).__name__}")
    if thresholds is not None and not isinstance(thresholds, Thresholds):
        raise ValueError(f"thresholds must be a crosscheck.engines.Thresholds or None; got {thresholds!r}")


class EngineSpec:
    """One registered engine: how to run it and everything the harness needs to know about it.

    Construct with keyword arguments (all but ``name`` optional):
      name: the registry name (``crosscheck.engines.get(name)``), an identifier.
      module: the module that defines ``Options``, ``simulate`` and ``sweep``
        (imported on first use, so that listing the engines does not import
        their libraries); or give them directly:
      Options: a frozen dataclass of the engine's parameters in scaled units, with
        the properties ``timestep``, ``contact_time`` and ``friction_time`` (see
        ``crosscheck.engines.base.Engine``).
      simulate, sweep: functions with the signatures of ``Engine``
        (module-level, so that the record pickles into worker processes).
      label: how tables and messages name it ("MuJoCo", "Drake SAP"); the name if empty.
      slug: the prefix of its report sections (``<slug>_maps``); the name if empty.
      libraries: PyPI distributions whose versions go into provenance and into a result
        store's record of what computed it (a store is not resumed under other versions:
        ``crosscheck.sweeps.store``).
      defaults: options that differ from ``Options()``'s in every run the harness makes
        of it (e.g. the approximation of one of Drake's registered names).
      one_core: keyword arguments of ``sweep`` that keep it on one core (a sweep's
        parallel unit is then the chunk): its thread or process knob.
      solver_columns: fields of its ``Run.solver`` statistics kept per run in sweep
        tables (as ``solver_<field>``), integers.
      tolerances: its event-tolerance profile, keys ``EVENT_TOLERANCE_KEYS`` of
        ``crosscheck.tolerances`` (each a ``Tolerance``); None: ``validate`` does not
        judge its events.
      tags: a subset of ``TAGS``.
      ladder: the models in between it and the theory, cause -> rung (see
        ``crosscheck.engines.mujoco.studies.ladder``); None: no ladder.
      interventions: cause -> "module:function", ``function(options) -> tuple[Intervention, ...]``: changes of
        the engine itself, weakest first, that remove a disagreement of that cause if the cause is right
        (``crosscheck.studies.interventions``); causes among those of ``ladder``.  None: none.
      checks: ``f(rod, n_states, rng) -> list[ErrorStat]``, checks only this engine has,
        run first by ``validate``; None: none.
      dynamics: module with ``DEFAULT_STATES`` and ``validate(n, rng, *, progress)``
        checking its dynamics terms against the analytic ones; None: none.
      report: the report sections generated for it (``ReportPlan``); None: none.
      sweep_chunk: runs per chunk when a study sends its sweeps through a sweep store
        (``crosscheck.studies.agreement_store``); None: the study's default.  Larger for an engine whose
        ``sweep`` steps a chunk as one batch and gets cheaper per step the larger the batch (a killed
        run loses at most one chunk of finished work).
      stops_at_event: its ``simulate`` takes ``until_event=True`` and then stops a run once its first event is
        judged (``crosscheck.engines.classifier.first_event_final``), with the whole run's outcome and event
        time; ``first_event`` uses it.
    """

    def __init__(
        self,
        *,
        name: str,
        module: str | None = None,
        Options: type | None = None,
        simulate: Callable | None = None,
        sweep: Callable | None = None,
        label: str = "",
        slug: str = "",
        libraries: Sequence[str] = (),
        defaults: Mapping[str, Any] | None = None,
        one_core: Mapping[str, Any] | None = None,
        solver_columns: Sequence[str] = (),
        tolerances: Mapping[str, Any] | None = None,
        tags: Iterable[str] = (),
        ladder: Mapping[str, Any] | None = None,
        checks: Callable | None = None,
        dynamics: str | None = None,
        report: ReportPlan | None = None,
        interventions: Mapping[str, str] | None = None,
        sweep_chunk: int | None = None,
        stops_at_event: bool = False,
    ) -> None:
        if not (isinstance(name, str) and name.isidentifier()):
            raise ValueError(f"engine name must be an identifier; got {name!r}")
        given = {k: v for k, v in (("Options", Options), ("simulate", simulate), ("sweep", sweep)) if v is not None}
        if module is None and len(given) < 3:
            raise ValueError(f"engine {name!r} needs a module or all of Options, simulate and sweep")
        tags = frozenset(tags)
        unknown = sorted(tags - TAGS)
        if unknown:
            raise ValueError(f"engine {name!r} tags must be among {', '.join(sorted(TAGS))}; got {unknown[0]!r}")
        if ladder is not None and set(ladder) - set(LADDER_CAUSES):
            bad = sorted(set(ladder) - set(LADDER_CAUSES))[0]
            raise ValueError(f"engine {name!r} ladder causes must be among {', '.join(LADDER_CAUSES)}; got {bad!r}")
        if interventions is not None and set(interventions) - set(ladder or ()):
            bad = sorted(set(interventions) - set(ladder or ()))[0]
            raise ValueError(
                f"engine {name!r} intervention causes must be among its ladder's ({', '.join(ladder or ())}); got {bad!r}"
            )
        if tolerances is not None:
            from crosscheck.tolerances import EVENT_TOLERANCE_KEYS

            missing = [k for k in EVENT_TOLERANCE_KEYS if k not in tolerances]
            if missing:
                raise ValueError(
                    f"engine {name!r} tolerance profile lacks {missing[0]!r} (needs {', '.join(EVENT_TOLERANCE_KEYS)})"
                )
        if sweep_chunk is not None and not (
            isinstance(sweep_chunk, int) and not isinstance(sweep_chunk, bool) and 1 <= sweep_chunk <= 1_000_000
        ):
            raise ValueError(
                f"engine {name!r} sweep_chunk must be an integer in [1, 1000000] or None; got {sweep_chunk!r}"
            )
        if not isinstance(stops_at_event, bool):
            raise ValueError(f"engine {name!r} stops_at_event must be True or False; got {stops_at_event!r}")
        d = self.__dict__
        d.update(
            name=name,
            module=module,
            label=label or name,
            slug=slug or name,
            libraries=tuple(libraries),
            defaults=dict(defaults or {}),
            one_core=dict(one_core or {}),
            solver_columns=tuple(solver_columns),
            tolerances=None if tolerances is None else dict(tolerances),
            tags=tags,
            ladder=None if ladder is None else dict(ladder),
            checks=checks,
            dynamics=dynamics,
            report=report,
            interventions=None if interventions is None else dict(interventions),
            sweep_chunk=sweep_chunk,
            stops_at_event=stops_at_event,
            _given=given,
        )

    def __setattr__(self, key, value):
        raise AttributeError(f"EngineSpec is read-only; cannot set {key!r}")

    def __repr__(self) -> str:
        return f"EngineSpec(name={self.name!r}, label={self.label!r}, tags={sorted(self.tags)})"

    def _part(self, what: str):
        if what in self._given:
            return self._given[what]
        return getattr(importlib.import_module(self.module), what)

    @property
    def Options(self) -> type:
        return self._part("Options")

    def options(self, **options):
        """``Options`` of a run with ``options`` over the engine's ``defaults`` (ValueError naming an unknown or bad one)."""
        from crosscheck.engines.base import options_from_kwargs

        return options_from_kwargs(self.Options, {**self.defaults, **options}, self.label)

    def simulate(self, rod, state, mu, *, horizon, thresholds=None, **options):
        """The engine's ``simulate`` with its ``defaults`` (see ``crosscheck.engines.base.Engine``)."""
        _check_rod_and_thresholds(rod, thresholds)
        return self._part("simulate")(
            rod, state, mu, horizon=horizon, thresholds=thresholds, **{**self.defaults, **options}
        )

    def first_event(self, rod, state, mu, *, horizon, thresholds=None, **options):
        """(outcome, event time) of ``simulate``'s run, stopped once its first event is judged where the engine can
        (``stops_at_event``): nothing the run does after that changes them (the ladders and interventions read no more)."""
        from crosscheck.outcome import Outcome

        stop = {"until_event": True} if self.stops_at_event else {}
        run = self.simulate(rod, state, mu, horizon=horizon, thresholds=thresholds, **options, **stop)
        return Outcome(int(run.outcome)), float(run.event_time)

    def sweep(self, rod, states, mu, *, horizon, thresholds=None, **options):
        """The engine's ``sweep`` with its ``defaults`` (see ``crosscheck.engines.base.Engine``)."""
        _check_rod_and_thresholds(rod, thresholds)
        return self._part("sweep")(
            rod, states, mu, horizon=horizon, thresholds=thresholds, **{**self.defaults, **options}
        )

    def interventions_for(self, cause: str, options, *, p_min: float | None = None) -> tuple[Intervention, ...]:
        """The engine's interventions for ``cause`` from the run's ``options`` (weakest first); () if it declares none.

        ``p_min``: the least eq. p along the theory's slip from the start at hand, passed on to a function that takes it
        (a keyword ``p_min``): a compliant contact follows the rod's normal motion more slowly where p is small
        (``crosscheck.engines.drake.interventions.compliance``).  None: the start is not known.
        """
        rung = (self.interventions or {}).get(cause)
        if rung is None:
            return ()
        module, _, attr = rung.partition(":")
        fn = getattr(importlib.import_module(module), attr)
        if p_min is not None and "p_min" in inspect.signature(fn).parameters:
            return tuple(fn(options, p_min=p_min))
        return tuple(fn(options))

    def has(self, tag: str) -> bool:
        """Whether the engine carries ``tag`` (one of ``TAGS``)."""
        if tag not in TAGS:
            raise ValueError(f"tag must be one of {', '.join(sorted(TAGS))}; got {tag!r}")
        return tag in self.tags
