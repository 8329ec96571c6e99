"""Scenes: one experiment written down in TOML, parsed into typed objects (pure).

A scene names the chain, the components, the excitation, the real-world
effects to include, how long to watch and what to report.  This module holds
its schema: it does no physics, builds no chain, writes no file and runs
nothing; :mod:`lcchain.scenes.load` reads files into it.  Everything a scene holds is an immutable
``@dataclass(frozen=True)`` whose ``__post_init__`` checks its own fields, so
a scene built in Python is held to the same rules as one read from a file.

Every problem raises :class:`~lcchain.errors.ParameterError` naming the dotted
TOML key (``effects.tolerance.L``), the value and what is allowed, prefixed by
the file when the scene came from one::

    bench.toml: effects.tolerance.L = -0.05 is not allowed: expected a number, 0 <= L < 1

The file format (every key, its default and its range) is the contract of
issue 5; ``lcchain/scenes/examples/`` (``lcchain examples``; ``examples/scenes/`` links there) holds complete scenes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import PurePosixPath
from typing import TypeVar

from ..circuit.effects import EFFECTS, Effect, Losses, PreferredValues, Tolerance, Walls, effect_fields
from ..core.analyses import analysis_kind
from ..core.checks import choice, instance, integer, is_integer, numbers_list, real, text_line
from ..core.errors import ParameterError
from ..core.frozen import FrozenMap, Reduced
from ..core.json import LooseJSONObject
from ..core.limits import (
    MAX_AC_POINTS,
    MAX_CIRCUIT_N,
    MAX_DT,
    MAX_I0,
    MAX_PULSE_WIDTH,
    MAX_TITLE_LENGTH,
    MAX_TRANSITS,
    MIN_AC_POINTS,
    MIN_I0,
    MIN_N,
    MIN_PULSE_WIDTH,
)
from ..core.types import (
    ANALYSIS_KINDS,
    DEFAULT_C0,
    DEFAULT_I0,
    DEFAULT_L0,
    EXCITATION_KINDS,
    METHODS,
    PLOT_KINDS,
    PROBES,
    PULSE_SHAPES,
    AnalysisKind,
    Backend,
    Case,
    ExcitationKind,
    Method,
    PlotKind,
    Probes,
    PulseShape,
)
from ..spice.engine import Engine
from ..spice.engines import DEFAULT_ENGINE, engine_named
from ..theory.cases import named_case, scene_cases

__all__ = [
    "ChainSpec",
    "Units",
    "ExcitationSpec",
    "Losses",
    "Walls",
    "Tolerance",
    "PreferredValues",
    "Effects",
    "Analysis",
    "Output",
    "Scene",
    "DEFAULT_TITLE",
    "DEFAULT_ACCURACY",
    "TRANSIENT_KEYS",
    "ANALYSIS_PLOTS",
    "check_ac_keys",
    "effect_keys",
]

DEFAULT_TITLE = "lcchain scene"
#: analysis.accuracy when neither it nor analysis.dt is given.
DEFAULT_ACCURACY = 1e-3


def _real(name: str, value: object, allowed: str, *, above: float | None = None, at_least: float | None = None,
          below: float | None = None, at_most: float | None = None) -> float:
    return real(name, value, allowed=allowed, above=above, at_least=at_least, below=below, at_most=at_most)


# ---------------------------------------------------------------- scene parts


@dataclass(frozen=True)
class ChainSpec:
    """The ``[chain]`` table: which chain, by name or by its masses and springs.

    Parameters
    ----------
    case : {"one-mass", "two-mass", "uniform-free", "uniform-bounded", "perfect", "custom"}
        A named family (built later by :func:`lcchain.cases.chain_for_case`)
        or ``custom``.
    N : int
        Number of masses, 3 <= N <= :data:`MAX_CIRCUIT_N` (:data:`MAX_PERFECT_N` for ``perfect``);
        ``len(masses)`` for ``custom``.
    masses : tuple of float, optional
        ``custom`` only: the N masses in bulk units, each finite and > 0.
    springs : tuple of float, optional
        ``custom`` only: the N+1 spring constants in bulk units, walls first
        and last (0 = free end), inner ones > 0.
    """

    case: Case
    N: int
    masses: tuple[float, ...] | None = None
    springs: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        choice("chain.case", self.case, scene_cases())
        named = named_case(self.case)
        if named is not None:
            for name in ("masses", "springs"):
                if getattr(self, name) is not None:
                    raise ParameterError(f"chain.{name}", getattr(self, name), f'no {name} unless case = "custom"')
            N = integer("chain.N", self.N, at_least=MIN_N, at_most=MAX_CIRCUIT_N)
            if N > named.max_N:
                raise ParameterError("chain.N", self.N, f"an integer from {MIN_N} to {named.max_N} for case "
                                     f"{self.case}")
            object.__setattr__(self, "N", N)
            return

        allowed = f'a list of {MIN_N} to {MAX_CIRCUIT_N} numbers > 0 (required for case = "custom")'
        if self.masses is None:
            raise ParameterError("chain.masses", None, allowed)
        masses = numbers_list("chain.masses", self.masses, allowed)
        if not MIN_N <= len(masses) <= MAX_CIRCUIT_N:
            raise ParameterError("chain.masses", self.masses, allowed)
        masses = tuple(_real(f"chain.masses[{i}]", m, "a finite number > 0", above=0.0) for i, m in enumerate(masses))
        N = len(masses)
        if not is_integer(self.N) or self.N != N:
            raise ParameterError("chain.N", self.N, f"len(chain.masses) = {N} (or leave N out)")

        allowed = f'a list of N+1 = {N + 1} numbers >= 0, walls first and last (required for case = "custom")'
        if self.springs is None:
            raise ParameterError("chain.springs", None, allowed)
        springs = numbers_list("chain.springs", self.springs, allowed)
        if len(springs) != N + 1:
            raise ParameterError("chain.springs", self.springs, allowed)
        checked = []
        for i, k in enumerate(springs):
            if 0 < i < N:
                checked.append(_real(f"chain.springs[{i}]", k, "a finite number > 0 (an inner spring)", above=0.0))
            else:
                checked.append(_real(f"chain.springs[{i}]", k, "a finite number >= 0 (a wall; 0 = free end)",
                                     at_least=0.0))
        object.__setattr__(self, "N", N)
        object.__setattr__(self, "masses", masses)
        object.__setattr__(self, "springs", tuple(checked))


@dataclass(frozen=True)
class Units:
    """The ``[units]`` table: the scale of the ladder.

    Parameters
    ----------
    L0 : float
        Inductance of a unit mass, in henry (> 0).
    C0 : float
        Capacitance of a unit spring, in farad (> 0).  Time is in units of
        sqrt(L0*C0) seconds.
    """

    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0

    def __post_init__(self) -> None:
        for name in ("L0", "C0"):
            value = _real(f"units.{name}", getattr(self, name), "a finite number > 0", above=0.0)
            object.__setattr__(self, name, value)


@dataclass(frozen=True)
class ExcitationSpec:
    """The ``[excitation]`` table: how loop 1 (mass 1) is set in motion.

    Parameters
    ----------
    kind : {"kick", "displacement", "pulse"}
        An initial current I0 in L_1, the initial charge it implies, or a
        voltage source v(t) = L_1 * I0 * g(t) in loop 1.
    I0 : float
        Current in ampere (1e-100 to 1e100): the kick, or the current the pulse's area
        gives L_1.
    shape : {"gaussian", "rect"}, optional
        Pulse only (required there): g(t) of unit area.
    width : float, optional
        Pulse only (required there): the gaussian's standard deviation or the
        rect's duration, in units of sqrt(L0*C0), 1e-3 <= width <= 1000.
    """

    kind: ExcitationKind = "kick"
    I0: float = DEFAULT_I0
    shape: PulseShape | None = None
    width: float | None = None

    def __post_init__(self) -> None:
        choice("excitation.kind", self.kind, EXCITATION_KINDS)
        current = _real("excitation.I0", self.I0, f"a number, {MIN_I0:g} <= I0 <= {MAX_I0:g} (ampere)",
                        at_least=MIN_I0, at_most=MAX_I0)
        object.__setattr__(self, "I0", current)
        if self.kind != "pulse":
            for name in ("shape", "width"):
                if getattr(self, name) is not None:
                    raise ParameterError(f"excitation.{name}", getattr(self, name), f'no {name} unless kind = "pulse"')
            return
        choice("excitation.shape", self.shape, PULSE_SHAPES, ' (required when kind = "pulse")')
        allowed = (f'a number, {MIN_PULSE_WIDTH:g} <= width <= {MAX_PULSE_WIDTH:g} (units of sqrt(L0*C0); '
                   'required when kind = "pulse"; a narrower pulse is a kick)')
        width = _real("excitation.width", self.width, allowed, at_least=MIN_PULSE_WIDTH, at_most=MAX_PULSE_WIDTH)
        object.__setattr__(self, "width", width)


E = TypeVar("E", bound=Effect)


class Effects:
    """The ``[effects.*]`` tables: the effects the scene asks for, by key.

    Any effect of the registry :data:`lcchain.circuit.effects.EFFECTS` (lcchain's own and those installed
    packages add) is a table: nothing is listed here, so an effect cannot be in the registry and missing from
    scenes, nor the other way round.  Immutable; equal when the same effects are asked for.

    Parameters
    ----------
    parts : Mapping of str to Effect, optional
        Scene key -> effect (None: absent).
    **by_key : Effect or None
        The same, as keywords: ``Effects(losses=Losses(100.0))``.
    """

    __slots__ = ("_parts",)
    _parts: FrozenMap[str, Effect]

    def __init__(self, parts: Mapping[str, Effect | None] | None = None, /, **by_key: Effect | None) -> None:
        given = {**(dict(parts) if parts is not None else {}), **by_key}
        for key, part in given.items():
            if key not in EFFECTS:
                raise ParameterError(f"effects.{key}", part, f"an effect of {', '.join(EFFECTS)}")
            instance(f"effects.{key}", part, EFFECTS[key], optional=True)
        ordered = {key: part for key in EFFECTS if (part := given.get(key)) is not None}
        object.__setattr__(self, "_parts", FrozenMap(ordered))

    def __getattr__(self, key: str) -> Effect | None:
        """``effects.losses``: the effect of that scene key, or None (a key no effect has: AttributeError)."""
        if key.startswith("_") or key not in EFFECTS:
            raise AttributeError(f"no effect {key!r} (the effects: {', '.join(EFFECTS)})")
        return self._parts.get(key)

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("Effects is immutable")

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Effects) and dict(self._parts) == dict(other._parts)

    def __hash__(self) -> int:
        return hash(frozenset(self._parts.items()))

    def __repr__(self) -> str:
        return f"Effects({', '.join(f'{key}={part!r}' for key, part in self._parts.items())})"

    def __reduce__(self) -> Reduced:
        return (type(self), (dict(self._parts),))

    def get(self, kind: type[E]) -> E | None:
        """The scene's effect of this type, or None."""
        part = self._parts.get(kind.key)
        return part if isinstance(part, kind) else None

    def items(self) -> tuple[tuple[str, Effect], ...]:
        """(key, effect) of the effects asked for, in the registry's order."""
        return tuple(self._parts.items())

    def present(self) -> tuple[Effect, ...]:
        """The effects the scene asks for, in the registry's order."""
        return tuple(self._parts.values())


#: The ``[analysis]`` keys of a transient only, refused with ``kind = "ac"``.
TRANSIENT_KEYS = ("transits", "accuracy", "dt", "method", "extrapolate")
def check_ac_keys(table: Mapping[str, object]) -> None:
    """Refuse a transient's key in the ``[analysis]`` table of an AC sweep, naming it."""
    for key in TRANSIENT_KEYS:
        if key in table:
            raise ParameterError(f"analysis.{key}", table[key], 'no such key with analysis.kind = "ac" (an AC sweep '
                                 "has points, backend and engine)")


#: The plots each analysis can draw (``[output] plots``); the first is its default.
ANALYSIS_PLOTS: dict[str, tuple[PlotKind, ...]] = {"transient": ("overlay", "spacetime", "histogram"),
                                                   "ac": ("spectrum", "spacing")}


@dataclass(frozen=True)
class Analysis:
    """The ``[analysis]`` table: how long to watch and how finely, or which frequencies to sweep.

    Parameters
    ----------
    kind : {"transient", "ac"}
        A transient (the default), or an AC sweep of the ladder's spectrum
        (:class:`lcchain.runs.request.AC`): its normal frequencies and end
        weights against theory.  With ``"ac"`` only ``points``, ``backend``
        and ``engine`` apply; a transient's keys are refused.
    points : int, optional
        ``kind = "ac"`` only: frequencies of the sweep (default: twice the
        fewest that separate every pole).
    transits : int
        Number of end-to-end transits to watch, 1..1000.
    accuracy : float, optional
        Target relative accuracy, 0 < accuracy < 1 (the step follows from
        it).  Exclusive with ``dt``; when neither is given, 1e-3.
    dt : float, optional
        Fixed maximum step in units of sqrt(L0*C0), 0 < dt <= 1.
    backend : {"batch", "shared"}
        ``ngspice -b`` subprocess or the shared library.
    method : {"trap", "gear"}
        Integration method.
    extrapolate : {1, 2, 3}, optional
        Combine this many runs at dt, dt/2, dt/4 per sample
        (:mod:`lcchain.compare.extrapolate`); with ``accuracy`` and not
        given, the cheapest of 1, 2 and 3 predicted to meet it; with ``dt``
        and not given, 1.  Gear and rect pulses fall back to one run, with
        the reason in the report.
    engine : str
        The circuit simulator, a name in :data:`lcchain.spice.engines.ENGINES`
        (``"ngspice"``, ``"gnucap"``); gnucap makes one run per sample (no
        extrapolation) and runs no pulse.
    """

    transits: int = 1
    accuracy: float | None = None
    dt: float | None = None
    backend: Backend = "batch"
    method: Method = "trap"
    extrapolate: int | None = None
    engine: str = DEFAULT_ENGINE
    kind: AnalysisKind = "transient"
    points: int | None = None

    def __post_init__(self) -> None:
        choice("analysis.kind", self.kind, ANALYSIS_KINDS)
        if analysis_kind(self.kind).swept:
            self._check_ac()
            return
        if self.points is not None:
            raise ParameterError("analysis.points", self.points, 'no points unless analysis.kind = "ac" (a '
                                 "transient's steps follow from dt or accuracy)")
        transits = integer("analysis.transits", self.transits, at_least=1, at_most=MAX_TRANSITS)
        object.__setattr__(self, "transits", transits)
        if self.accuracy is not None and self.dt is not None:
            raise ParameterError(
                "analysis.dt", self.dt, "no dt when analysis.accuracy is given (they are mutually exclusive)"
            )
        if self.dt is not None:
            allowed = f"a number, 0 < dt <= {MAX_DT:g} (units of sqrt(L0*C0))"
            object.__setattr__(self, "dt", _real("analysis.dt", self.dt, allowed, above=0.0, at_most=MAX_DT))
        else:
            # Neither given: the default accuracy; dt given: no accuracy at all.
            accuracy = DEFAULT_ACCURACY if self.accuracy is None else self.accuracy
            allowed = "a number, 0 < accuracy < 1"
            object.__setattr__(self, "accuracy", _real("analysis.accuracy", accuracy, allowed, above=0.0, below=1.0))
        choice("analysis.method", self.method, METHODS)
        if self.extrapolate is not None:
            object.__setattr__(self, "extrapolate", integer("analysis.extrapolate", self.extrapolate, at_least=1,
                                                            at_most=3))
        engine = self._check_engine()
        if not engine.extrapolates and self.extrapolate is not None and self.extrapolate > 1:
            raise ParameterError("analysis.extrapolate", self.extrapolate,
                                 f"1 with engine {engine.name} (no extrapolation): {engine.no_extrapolation}")

    def _check_engine(self) -> Engine:
        engine = engine_named(self.engine, "analysis.engine")
        engine.check_transport("analysis.backend", self.backend)
        return engine

    def _check_ac(self) -> None:
        defaults = {f.name: f.default for f in fields(self)}
        check_ac_keys({key: getattr(self, key) for key in TRANSIENT_KEYS if getattr(self, key) != defaults[key]})
        if self.points is not None:
            object.__setattr__(self, "points", integer("analysis.points", self.points, at_least=MIN_AC_POINTS,
                                                       at_most=MAX_AC_POINTS))
        self._check_engine()

    def keys(self) -> tuple[str, ...]:
        """The keys of the table this analysis has (an AC sweep: none of a transient's)."""
        if analysis_kind(self.kind).swept:
            return tuple(key for key in ANALYSIS_KEYS if key not in TRANSIENT_KEYS)
        return tuple(key for key in ANALYSIS_KEYS if key not in ("kind", "points"))


@dataclass(frozen=True)
class Output:
    """The ``[output]`` table: what to save and what to draw.

    Parameters
    ----------
    probes : {"ends", "all"}
        Save the two end loop currents, or every loop current.
    report : str, optional
        Path of the JSON report, relative to the current directory and
        inside it (no leading ``/``, no ``..``), ending in ``.json``; the
        plots are named after it (``out/r.json`` -> ``out/r-overlay.png``).
    plots : tuple of {"overlay", "spacetime", "histogram"}
        Pictures to draw, each at most once.
    """

    probes: Probes = "ends"
    report: str | None = None
    plots: tuple[PlotKind, ...] = ("overlay",)

    def __post_init__(self) -> None:
        choice("output.probes", self.probes, PROBES)
        if self.report is not None:
            if not isinstance(self.report, str) or not self.report.strip() \
                    or any(ord(ch) < 32 or ord(ch) == 127 for ch in self.report):
                raise ParameterError("output.report", self.report, "a file path (one line of text)")
            path = PurePosixPath(self.report.replace("\\", "/"))
            if path.is_absolute() or ".." in path.parts or path.suffix.lower() != ".json":
                raise ParameterError("output.report", self.report, "a relative path ending in .json that stays in "
                                     "the current folder (no leading /, no ..); the plots are named after it")
        allowed = "a list of distinct names from " + ", ".join(PLOT_KINDS)
        if isinstance(self.plots, (str, bytes, Mapping)) or not isinstance(self.plots, Sequence):
            raise ParameterError("output.plots", self.plots, allowed)
        for i, kind in enumerate(self.plots):
            choice(f"output.plots[{i}]", kind, PLOT_KINDS)
        if len(set(self.plots)) != len(self.plots):
            raise ParameterError("output.plots", list(self.plots), allowed)
        object.__setattr__(self, "plots", tuple(self.plots))


@dataclass(frozen=True)
class Scene:
    """One experiment: every table of a scene file, validated.

    ``source`` (the file it came from) is metadata: it is not part of the
    scene's equality nor of :meth:`to_dict`.
    """

    title: str
    chain: ChainSpec
    units: Units
    excitation: ExcitationSpec
    effects: Effects
    analysis: Analysis
    output: Output
    source: str | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        text_line("title", self.title, MAX_TITLE_LENGTH, title=True)
        for name, cls in (
            ("chain", ChainSpec),
            ("units", Units),
            ("excitation", ExcitationSpec),
            ("effects", Effects),
            ("analysis", Analysis),
            ("output", Output),
        ):
            instance(name, getattr(self, name), cls)
        plots = list(self.output.plots)
        kind = self.analysis.kind
        drawn = ANALYSIS_PLOTS[kind]
        if any(plot not in drawn for plot in plots):
            raise ParameterError("output.plots", plots, f"plots of an analysis of kind {kind!r}: "
                                 f"{', '.join(drawn)}")
        if analysis_kind(kind).swept and self.excitation != ExcitationSpec():
            raise ParameterError("excitation", self.excitation.kind, 'no [excitation] with analysis.kind = "ac" (the '
                                 "sweep drives loop 1 with a unit AC voltage)")
        if analysis_kind(kind).swept and self.output.probes != "ends":
            raise ParameterError("output.probes", self.output.probes, 'ends with analysis.kind = "ac" (the sweep '
                                 "saves I_1 and I_N)")
        if "spacetime" in plots and self.output.probes != "all":
            raise ParameterError("output.plots", plots, 'no "spacetime" unless output.probes = "all"')
        tolerance = self.effects.get(Tolerance)
        for spread in ("histogram", "spacing"):
            if spread in plots and (tolerance is None or tolerance.samples < 2):
                raise ParameterError("output.plots", plots, f'no "{spread}" unless effects.tolerance.samples > 1')

    def to_dict(self) -> LooseJSONObject:
        """The scene as plain data with the file's keys (JSON- and TOML-writable).

        Keys left at None are omitted, ``effects`` holds only the effects
        present, and ``parse_scene(scene.to_dict()) == scene``.  A TOML document: the studies read and edit it by
        key (a varied part), hence :data:`~lcchain.core.json.LooseJSONObject`.
        """

        def table(obj: object, keys: Sequence[str]) -> dict[str, object]:
            out: dict[str, object] = {}
            for key in keys:
                value = getattr(obj, key)
                if value is not None:
                    out[key] = list(value) if isinstance(value, tuple) else value
            return out

        effects = {name: table(part, effect_keys(type(part))) for name, part in self.effects.items()}
        return {
            "title": self.title,
            "chain": table(self.chain, CHAIN_KEYS),
            "units": table(self.units, UNITS_KEYS),
            "excitation": table(self.excitation, EXCITATION_KEYS),
            "effects": effects,
            # The default engine is left out: the scenes (and the studies' stores) made before engines had none.
            "analysis": {key: value for key, value in table(self.analysis, self.analysis.keys()).items()
                         if (key, value) != ("engine", DEFAULT_ENGINE)},
            "output": table(self.output, OUTPUT_KEYS),
        }


# ------------------------------------------------------------ the file's keys
# Derived from the dataclasses: a field is a key, nothing is listed twice.


def _keys(cls: type) -> tuple[str, ...]:
    return tuple(f.name for f in fields(cls) if f.name != "source")


def effect_keys(cls: type[Effect]) -> tuple[str, ...]:
    """The keys of an effect's table: its fields (read when a scene is, so that plugins are registered)."""
    return tuple(f.name for f in effect_fields(cls))


TOP_KEYS = _keys(Scene)
CHAIN_KEYS = _keys(ChainSpec)
UNITS_KEYS = _keys(Units)
EXCITATION_KEYS = _keys(ExcitationSpec)
ANALYSIS_KEYS = _keys(Analysis)
OUTPUT_KEYS = _keys(Output)
