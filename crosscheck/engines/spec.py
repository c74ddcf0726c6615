"""What an engine declares about itself: one ``EngineSpec``, a short required part and optional parts.

An engine subpackage (``crosscheck/engines/<name>/``) or an installed plugin (entry-point group
``crosscheck.engines``, ``docs/adding-an-engine.md``) exposes ``ENGINES``, a tuple of ``EngineSpec``.  What every
engine writes is short::

    EngineSpec(name="numpy_rod", engine="numpy_rod.engine:ENGINE", label="numpy penalty rod",
               libraries=("numpy",), tags={"compliant", "time_stepping"})

and what it may add is grouped in optional parts: ``Ladder`` (the models between it and the theory, and the
interventions that test each cause), ``ReportPlan`` (its report sections), ``Validation`` (its event-tolerance
profile and own checks) and ``Execution`` (how sweeps run it).  The registry (``crosscheck.engines``) collects
them; studies, sweeps, tolerances, findings and provenance read the registry and never name an engine.

Lazy references.  Everything imported only when used is a string in entry-point syntax: ``"package.module"`` (the
module) or ``"package.module:attribute"`` (an attribute of it, dots for nested ones), so declaring and listing
engines imports no engine library.  Where a reference is expected, the object itself is accepted too (it is then
simply not lazy).  ``resolve`` turns either into the object.

Everything an engine's ``simulate`` and ``sweep`` take and return is in the paper's scaled units (section 2.1): time
in 1/omega, lengths in l, velocities in l omega, accelerations in g, forces in m g; so are its ``Options``.  An
engine written in SI units goes through ``crosscheck.engines.adapter`` instead.
"""

from __future__ import annotations

import functools
import importlib
import inspect
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

__all__ = [
    "EngineSpec",
    "Ladder",
    "ReportPlan",
    "Validation",
    "Execution",
    "Intervention",
    "EngineUnavailable",
    "TAGS",
    "LADDER_CAUSES",
    "resolve",
]

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
#: step, the convex relaxation of the step's contact problem (a relaxed engine against a non-relaxed step of the
#: same law and timestep: the mechanism behind SAP's "gliding", its launch of a slipping tip), a pyramid of
#: friction instead of the cone (two friction rows bounded apart: DART's box), a friction bound fixed before the
#: friction enters (DART's Dantzig step bounds the friction rows by mu times the frictionless normal impulse), a
#: contact projected on positions within the step (XPBD: no force, a position correction relaxed over a few
#: iterations), and float32 arithmetic (MuJoCo Warp against the same model in MuJoCo in C's float64).
LADDER_CAUSES = (
    "geometry",
    "compliance",
    "friction law",
    "feed-forward",
    "discretisation",
    "relaxation",
    "pyramid cone",
    "friction bound",
    "position projection",
    "float32",
)

#: Rungs that are not references: the theory on the engine's capsule, and the engine itself.
_NAMED_RUNGS = ("capsule", "engine")


class EngineUnavailable(ValueError):
    """An engine that cannot run here (its library is not installed, or its plugin failed to load): one line."""


def resolve(ref):
    """The object a lazy reference names: ``"pkg.mod"`` -> the module, ``"pkg.mod:attr.sub"`` -> that attribute;
    anything that is not a string is returned as it is."""
    if not isinstance(ref, str):
        return ref
    module, _, attr = ref.partition(":")
    obj = importlib.import_module(module)
    for part in filter(None, attr.split(".")):
        obj = getattr(obj, part)
    return obj


def _check_ref(owner: str, what: str, ref, *, optional: bool = True) -> None:
    if ref is None and optional:
        return
    if isinstance(ref, str):
        module, colon, attr = ref.partition(":")
        ok = all(p.isidentifier() for p in module.split(".")) and (
            not colon or all(p.isidentifier() for p in attr.split("."))
        )
        if not ok:
            raise ValueError(
                f"{owner} {what} must be a reference 'package.module' or 'package.module:attr'; got {ref!r}"
            )


def _frozen_map(m) -> dict | None:
    """A copy of a declared mapping (a dict: the spec pickles into worker processes; a mappingproxy does not)."""
    return None if m is None else dict(m)


@dataclass(frozen=True)
class Intervention:
    """One change of the engine itself in the way a cause names (``Ladder.interventions``).

    Attributes:
      text: what it does, for tables ("capsule radius 0.01 -> 0.000625").
      options: the engine's options to set over the run's (scaled units), e.g. ``{"radius": 6.25e-4}``.
      family: which way of the cause it takes, where a cause has two ("impratio", "friction time constant"): each
        family runs weakest first, and its last is its strongest; "" for a cause with one way.
    """

    text: str
    options: Mapping[str, Any]
    family: str = ""


@dataclass(frozen=True, kw_only=True, eq=False)
class Ladder(Mapping):
    """The models in between an engine and the theory (``crosscheck.studies.ladder``), and what tests each cause.

    A mapping cause -> rung, causes among ``LADDER_CAUSES`` in their order:
      rungs: cause -> "capsule" (the theory on the engine's capsule: the contact point C = A - r K), "engine" (the
        engine itself) or a reference to ``rung(rod, state, mu, *, horizon, thresholds, options) -> Run``, a model
        that differs from the rung before it by that cause alone.
      interventions: cause -> reference to ``function(options) -> tuple[Intervention, ...]`` (optionally with a
        keyword ``p_min``): changes of the engine itself, weakest first, that remove a disagreement of that cause if
        the cause is right (``crosscheck.studies.interventions``); causes among the rungs'.
    """

    rungs: Mapping[str, Any]
    interventions: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        bad = [c for c in self.rungs if c not in LADDER_CAUSES]
        if bad:
            raise ValueError(f"ladder causes must be among {', '.join(LADDER_CAUSES)}; got {bad[0]!r}")
        bad = [c for c in self.interventions if c not in self.rungs]
        if bad:
            raise ValueError(
                f"intervention causes must be among the ladder's ({', '.join(self.rungs)}); got {bad[0]!r}"
            )
        for c, rung in self.rungs.items():
            if rung not in _NAMED_RUNGS:
                _check_ref("ladder", f"rung {c!r}", rung, optional=False)
        for c, ref in self.interventions.items():
            _check_ref("ladder", f"intervention {c!r}", ref, optional=False)
        object.__setattr__(self, "rungs", _frozen_map({c: self.rungs[c] for c in LADDER_CAUSES if c in self.rungs}))
        object.__setattr__(self, "interventions", _frozen_map(self.interventions))

    def __getitem__(self, cause: str):
        return self.rungs[cause]

    def __iter__(self) -> Iterator[str]:
        return iter(self.rungs)

    def __len__(self) -> int:
        return len(self.rungs)


@dataclass(frozen=True, kw_only=True)
class ReportPlan:
    """The report sections generated for an engine, with its settings in each report.

    Attributes:
      slug: the prefix of its sections (``<slug>_maps``); the engine's name if empty.
      maps: {"quick": options, "full": options} of its outcome-map section (None: no map section).
      convergence: {"quick": [options, ...], "full": [...]} of its convergence section (None: none).
      convergence_n: {"quick": n, "full": n}, the (theta, Theta) grid size of that section (None: the section's default).
      maps_n: {"quick": n, "full": n}, the size of each n x n outcome map (None: the section's default, 10 and 32);
        smaller for an engine whose runs cost more (the report says so in the section's parameters).
      beside: slug of another map section drawn beside this engine's (None: drawn alone).
      sections: reference to a function returning the engine's own sections (``crosscheck.report.section.Section``),
        placed after its generic ones (None: none).
      ladder: whether the generic ladder section (``<slug>_ladder``: the disagreements of its maps through
        ``crosscheck.studies.ladder``) is generated.
      onset: whether the generic lift-off onset section (``<slug>_liftoff``) is generated (False for an engine
        that declares its own, as MuJoCo's over its timestep).
      ladder_states: {"quick": n, "full": n or None}, how many of its maps' disagreements the ladder section runs (an
        even spread; None: every one); None: the section's default, 3 and 30.
      order: where the engine's sections stand among the engines' (lower first).
    """

    slug: str = ""
    maps: Mapping[str, Mapping] | None = None
    convergence: Mapping[str, Any] | None = None
    convergence_n: Mapping[str, int] | None = None
    maps_n: Mapping[str, int] | None = None
    beside: str | None = None
    sections: Any = None
    onset: bool = True
    ladder: bool = False
    ladder_states: Mapping[str, int | None] | None = None
    order: int = 100

    def __post_init__(self) -> None:
        if self.slug and not self.slug.isidentifier():
            raise ValueError(f"report slug must be an identifier; got {self.slug!r}")
        _check_ref("report", "sections", self.sections)


@dataclass(frozen=True, kw_only=True)
class Validation:
    """What ``crosscheck validate`` judges of an engine beyond the contract test.

    Attributes:
      tolerances: its event-tolerance profile, keys ``EVENT_TOLERANCE_KEYS`` of ``crosscheck.tolerances`` (each a
        ``Tolerance``); None: ``validate`` does not judge its events.
      checks: reference to ``f(rod, n_states, rng) -> list[ErrorStat]``, checks only this engine has, run first.
      dynamics: reference to a module with ``DEFAULT_STATES`` and ``validate(n, rng, *, progress)`` checking its
        dynamics terms against the analytic ones.
    """

    tolerances: Mapping[str, Any] | None = None
    checks: Any = None
    dynamics: str | None = None

    def __post_init__(self) -> None:
        if self.tolerances is not None:
            from crosscheck.tolerances import EVENT_TOLERANCE_KEYS

            missing = [k for k in EVENT_TOLERANCE_KEYS if k not in self.tolerances]
            if missing:
                raise ValueError(f"tolerance profile lacks {missing[0]!r} (needs {', '.join(EVENT_TOLERANCE_KEYS)})")
            object.__setattr__(self, "tolerances", _frozen_map(self.tolerances))
        _check_ref("validation", "checks", self.checks)
        _check_ref("validation", "dynamics", self.dynamics)


@dataclass(frozen=True, kw_only=True)
class Execution:
    """How sweeps and studies run an engine.

    Attributes:
      one_core: keyword arguments of ``sweep`` that keep it on one core (a sweep's parallel unit is then the chunk).
      solver_columns: fields of its ``Run.solver`` statistics kept per run in sweep tables (``solver_<field>``).
      sweep_chunk: runs per chunk when a study sends its sweeps through a sweep store (None: the study's default).
      stops_at_event: its ``simulate`` takes ``until_event=True`` and then stops a run once its first event is
        judged (``crosscheck.engines.classifier.first_event_final``); ``EngineSpec.first_event`` uses it.
      preload: reference to a function of the engine's ``Options`` class that does the library's one-time work of a
        process (imports, kernel loads), called once by the report before it forks its sections, so that each
        inherits it instead of repeating it (None: nothing to do).
      provenance: reference to a function of the engine's ``Options`` class returning a JSON-able dict about this
        process's runs of the engine that belongs in the report's provenance (a kernel compile time; {} when none).
    """

    one_core: Mapping[str, Any] = field(default_factory=dict)
    solver_columns: tuple[str, ...] = ()
    sweep_chunk: int | None = None
    stops_at_event: bool = False
    preload: Any = None
    provenance: Any = None

    def __post_init__(self) -> None:
        _check_ref("Execution", "preload", self.preload)
        _check_ref("Execution", "provenance", self.provenance)
        c = self.sweep_chunk
        if c is not None and not (isinstance(c, int) and not isinstance(c, bool) and 1 <= c <= 1_000_000):
            raise ValueError(f"sweep_chunk must be an integer in [1, 1000000] or None; got {c!r}")
        if not isinstance(self.stops_at_event, bool):
            raise ValueError(f"stops_at_event must be True or False; got {self.stops_at_event!r}")
        object.__setattr__(self, "one_core", _frozen_map(self.one_core))
        object.__setattr__(self, "solver_columns", tuple(self.solver_columns))


def _per_state(name: str, value, n: int) -> list:
    """``value`` as n values: one value repeated, or a sequence of n (ValueError naming ``name`` otherwise)."""
    if isinstance(value, str) or not hasattr(value, "__len__"):
        return [value] * n
    values = list(value)
    if len(values) != n:
        raise ValueError(f"{name} must be one number or one per state ({n}); got {len(values)} values")
    return values


def _check_rod_and_thresholds(rod, thresholds) -> None:
    """One ValueError line for a ``rod`` that is not a ``Rod`` or ``thresholds`` that are not ``Thresholds`` (or None)."""
    from crosscheck.engines.classifier import Thresholds
    from crosscheck.rod import Rod

    if not isinstance(rod, Rod):
        raise ValueError(f"rod must be a crosscheck.Rod; got {type(rod).__name__}")
    if thresholds is not None and not isinstance(thresholds, Thresholds):
        raise ValueError(f"thresholds must be a crosscheck.engines.Thresholds or None; got {thresholds!r}")


def _with_rod(result, rod):
    """``result`` (a ``Run`` or ``SweepResult``) naming the rod it simulated, when the engine did not set it itself."""
    import dataclasses

    if dataclasses.is_dataclass(result) and getattr(result, "rod", False) is None:
        return dataclasses.replace(result, rod=rod)
    return result


@dataclass(frozen=True, kw_only=True, eq=False)
class EngineSpec:
    """One engine: how to run it, what it is, and the optional parts a study or the report reads.

    Required part:
      name: the registry name (``crosscheck.engines.get(name)``), an identifier.
      engine: reference to what runs it: a module or object with ``Options`` (a frozen dataclass of scaled options
        with the properties ``timestep``, ``contact_time``, ``friction_time``), ``simulate`` and ``sweep`` (the
        signatures of ``crosscheck.engines.base.Engine``); an SI engine wrapped by ``crosscheck.engines.adapter``.
      label: how tables and messages name it ("MuJoCo", "Drake SAP"); the name if empty.
      libraries: PyPI distributions it imports; their versions go into provenance and a result store's key, and
        ``crosscheck engines`` says "not installed" for a missing one.
      tags: a subset of ``TAGS``.
    May add:
      install: the pip argument that brings its libraries ("crosscheck[drake]"; "" : its libraries themselves).
      defaults: options that differ from ``Options()``'s in every run the harness makes (Drake's approximation).
      ladder, report, validation: ``Ladder``, ``ReportPlan``, ``Validation`` (None: none).
      execution: ``Execution`` (how sweeps run it).
      origin: where it comes from: "built in", or the plugin's "distribution version" (set by the registry).

    Flat read-only views of the parts keep the readers short: ``slug``, ``interventions``, ``tolerances``,
    ``checks``, ``dynamics``, ``one_core``, ``solver_columns``, ``sweep_chunk``, ``stops_at_event``, ``module``.
    """

    name: str
    engine: Any
    label: str = ""
    libraries: tuple[str, ...] = ()
    tags: frozenset = frozenset()
    install: str = ""
    defaults: Mapping[str, Any] = field(default_factory=dict)
    ladder: Ladder | None = None
    report: ReportPlan | None = None
    validation: Validation | None = None
    execution: Execution = field(default_factory=Execution)
    origin: str = "built in"

    def __post_init__(self) -> None:
        name = self.name
        if not (isinstance(name, str) and name.isidentifier()):
            raise ValueError(f"engine name must be an identifier; got {name!r}")
        if self.engine is None:
            raise ValueError(f"engine {name!r} needs engine= (a reference 'package.module[:attr]' to what runs it)")
        _check_ref(f"engine {name!r}", "engine", self.engine, optional=False)
        tags = frozenset(self.tags)
        unknown = sorted(tags - TAGS)
        if unknown:
            raise ValueError(f"engine {name!r} tags must be among {', '.join(sorted(TAGS))}; got {unknown[0]!r}")
        for part, kind in (("ladder", Ladder), ("report", ReportPlan), ("validation", Validation)):
            value = getattr(self, part)
            if value is not None and not isinstance(value, kind):
                raise ValueError(
                    f"engine {name!r} {part} must be a {kind.__name__} or None; got {type(value).__name__}"
                )
        if not isinstance(self.execution, Execution):
            raise ValueError(f"engine {name!r} execution must be an Execution; got {type(self.execution).__name__}")
        object.__setattr__(self, "tags", tags)
        object.__setattr__(self, "label", self.label or name)
        object.__setattr__(self, "libraries", tuple(self.libraries))
        object.__setattr__(self, "defaults", _frozen_map(self.defaults))

    def __repr__(self) -> str:
        return f"EngineSpec(name={self.name!r}, label={self.label!r}, tags={sorted(self.tags)})"

    # --- flat views of the optional parts -------------------------------------------------------------------------
    @property
    def slug(self) -> str:
        return (self.report.slug if self.report else "") or self.name

    @property
    def interventions(self) -> Mapping[str, Any] | None:
        return (self.ladder.interventions or None) if self.ladder else None

    @property
    def tolerances(self) -> Mapping[str, Any] | None:
        return self.validation.tolerances if self.validation else None

    @property
    def checks(self):
        return resolve(self.validation.checks) if self.validation and self.validation.checks else None

    @property
    def dynamics(self) -> str | None:
        return self.validation.dynamics if self.validation else None

    @property
    def one_core(self) -> Mapping[str, Any]:
        return self.execution.one_core

    @property
    def solver_columns(self) -> tuple[str, ...]:
        return self.execution.solver_columns

    @property
    def sweep_chunk(self) -> int | None:
        return self.execution.sweep_chunk

    @property
    def stops_at_event(self) -> bool:
        return self.execution.stops_at_event

    @property
    def module(self) -> str | None:
        """The module of ``engine`` (what a report section's code digest covers)."""
        if isinstance(self.engine, str):
            return self.engine.partition(":")[0]
        return getattr(self.engine, "__module__", None) or getattr(self.engine, "__name__", None)

    # --- running --------------------------------------------------------------------------------------------------
    def pip_line(self) -> str:
        """The command that installs this engine's libraries."""
        what = self.install or " ".join(self.libraries)
        return f'python3 -m pip install "{what}"' if "[" in what else f"python3 -m pip install {what}"

    def missing(self) -> tuple[str, ...]:
        """Its libraries that are not installed (by their distribution metadata: nothing is imported)."""
        return tuple(lib for lib in self.libraries if not _installed(lib))

    def unavailable(self) -> str:
        """One line saying why this engine cannot run here ("" when it can)."""
        missing = self.missing()
        if missing:
            return f"engine {self.name!r} needs {', '.join(missing)}, which is not installed: {self.pip_line()}"
        return ""

    def _runner(self):
        why = self.unavailable()
        if why:
            raise EngineUnavailable(why)
        try:
            return resolve(self.engine)
        except ImportError as e:
            first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            raise EngineUnavailable(
                f"engine {self.name!r} failed to import ({type(e).__name__}: {first}): {self.pip_line()}"
            ) from e

    @property
    def Options(self) -> type:
        return self._runner().Options

    def options(self, **options):
        """``Options`` of a run with ``options`` over the engine's ``defaults`` (ValueError naming an unknown or bad one)."""
        from crosscheck.engines.base import options_from_kwargs

        return options_from_kwargs(self.Options, {**self.defaults, **options}, self.label)

    def simulate(self, rod, state, mu, *, horizon, thresholds=None, **options):
        """The engine's ``simulate`` with its ``defaults`` (see ``crosscheck.engines.base.Engine``)."""
        _check_rod_and_thresholds(rod, thresholds)
        return _with_rod(
            self._runner().simulate(
                rod, state, mu, horizon=horizon, thresholds=thresholds, **{**self.defaults, **options}
            ),
            rod,
        )

    def simulate_each(self, rod, states, mu, *, horizon, thresholds=None, **options) -> list:
        """``simulate`` of every state of ``states``; ``mu`` and ``horizon`` one number or one per state.

        An engine whose module has ``simulate_batch`` (the batched path of the tag "batched": one call of the library
        for all the states) runs them that way and must return the same ``Run`` of each, record for record; the
        others run one ``simulate`` per state.  A ``simulate`` option that only one run at a time takes
        (``until_event``) takes the one-per-state path.
        """
        states = list(states)
        mus, horizons = _per_state("mu", mu, len(states)), _per_state("horizon", horizon, len(states))
        batch = getattr(self._runner(), "simulate_batch", None)
        if batch is not None and states and "until_event" not in options:
            _check_rod_and_thresholds(rod, thresholds)
            return batch(rod, states, mus, horizon=horizons, thresholds=thresholds, **{**self.defaults, **options})
        return [
            self.simulate(rod, s, m, horizon=h, thresholds=thresholds, **options)
            for s, m, h in zip(states, mus, horizons)
        ]

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
        return _with_rod(
            self._runner().sweep(
                rod, states, mu, horizon=horizon, thresholds=thresholds, **{**self.defaults, **options}
            ),
            rod,
        )

    def preload(self) -> None:
        """The library's one-time work of this process (``Execution.preload``, given the engine's ``Options`` class):
        nothing when the engine declares none or cannot run here."""
        if self.execution.preload is not None and not self.unavailable():
            resolve(self.execution.preload)(self.Options)

    def provenance(self) -> dict:
        """What this process's runs of the engine add to the report's provenance (``Execution.provenance``, given the
        engine's ``Options`` class); {} when the engine declares nothing or cannot run here."""
        if self.execution.provenance is None or self.unavailable():
            return {}
        return dict(resolve(self.execution.provenance)(self.Options))

    def interventions_for(self, cause: str, options, *, p_min: float | None = None) -> tuple[Intervention, ...]:
        """The engine's interventions for ``cause`` from the run's ``options`` (weakest first); () if it declares none.

        ``p_min``: the least eq. p along the theory's slip from the start at hand, passed on to a function that takes it
        (a keyword ``p_min``): a compliant contact follows the rod's normal motion more slowly where p is small
        (``crosscheck.engines.drake.interventions.compliance``).  None: the start is not known.
        """
        ref = (self.interventions or {}).get(cause)
        if ref is None:
            return ()
        fn = resolve(ref)
        if p_min is not None and "p_min" in inspect.signature(fn).parameters:
            return tuple(fn(options, p_min=p_min))
        return tuple(fn(options))

    def has(self, tag: str) -> bool:
        """Whether the engine carries ``tag`` (one of ``TAGS``)."""
        if tag not in TAGS:
            raise ValueError(f"tag must be one of {', '.join(sorted(TAGS))}; got {tag!r}")
        return tag in self.tags


@functools.cache
def _installed(distribution: str) -> bool:
    """Whether ``distribution`` is installed, read once per process from its metadata (~3 ms a read: every command
    line builds its parser over every engine's sections)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        version(distribution)
    except PackageNotFoundError:
        return False
    return True
