"""Scenes: one experiment written down in TOML, parsed into typed objects (pure).

A scene names the chain, the components, the excitation, the real-world
effects to include, how long to watch and what to report.  This module only
reads the file and validates it: it does no physics, builds no chain, writes
no file and runs nothing.  Everything a scene holds is an immutable
``@dataclass(frozen=True)`` whose ``__post_init__`` checks its own fields, so
a scene built in Python is held to the same rules as one read from a file.

Every problem raises :class:`~lcchain.errors.ParameterError` naming the dotted
TOML key (``effects.tolerance.L``), the value and what is allowed, prefixed by
the file when the scene came from one::

    bench.toml: effects.tolerance.L = -0.05 is not allowed: expected a number, 0 <= L < 1

The file format (every key, its default and its range) is the contract of
issue 5; ``examples/scenes/`` holds complete scenes.
"""

from __future__ import annotations

import math
import numbers
import os
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import MISSING, dataclass, field, fields
from typing import Any, Literal, get_args

from .errors import ParameterError
from .netlist import check_user_text
from .types import (BACKENDS, CASES, EXCITATION_KINDS, METHODS, PROBES, PULSE_SHAPES, Backend, Case, ExcitationKind,
                    Method, Probes, PulseShape)

__all__ = [
    "ExcitationKind",
    "PulseShape",
    "ESeries",
    "Probes",
    "PlotKind",
    "EXCITATION_KINDS",
    "PULSE_SHAPES",
    "E_SERIES",
    "PLOT_KINDS",
    "DEFAULT_TITLE",
    "MAX_N",
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
    "load_scene",
    "parse_scene",
]

#: The IEC 60063 preferred-number series every L and C can be rounded to.
ESeries = Literal["E12", "E24", "E96"]
#: The pictures a scene can ask for.
PlotKind = Literal["overlay", "spacetime", "histogram"]

E_SERIES: tuple[str, ...] = get_args(ESeries)
PLOT_KINDS: tuple[str, ...] = get_args(PlotKind)

DEFAULT_TITLE = "lcchain scene"
#: Largest chain a scene may ask for (the netlist has ~2N elements).
MAX_N = 100_000
#: The perfectly transmitting chains exist for these N only (Sec. II.C of the paper).
PERFECT_N = (3, 4, 5)
MIN_N = 3
MAX_WIDTH = 1000.0
MAX_SAMPLES = 10_000
MAX_TRANSITS = 1000
DEFAULT_ACCURACY = 1e-3

# The keys each table accepts, in the order the contract lists them.
_TOP_KEYS = ("title", "chain", "units", "excitation", "effects", "analysis", "output")
_CHAIN_KEYS = ("case", "N", "masses", "springs")
_UNITS_KEYS = ("L0", "C0")
_EXCITATION_KEYS = ("kind", "I0", "shape", "width")
_EFFECT_KEYS = {
    "losses": ("Q",),
    "walls": ("K0",),
    "tolerance": ("L", "C", "samples", "seed"),
    "preferred_values": ("series",),
}
_ANALYSIS_KEYS = ("transits", "accuracy", "dt", "backend", "method")
_OUTPUT_KEYS = ("probes", "report", "plots")


# --------------------------------------------------------------- field checks
# Each raises ParameterError(field, value, allowed) without a file; parse_scene
# adds the file.  Booleans are not numbers (TOML `true` is not 1).


def _is_integer(value: object) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _is_real(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _real(name: str, value: object, allowed: str, ok) -> float:
    """A finite real number (int or float) for which ``ok(x)`` holds, as a float."""
    if not _is_real(value):
        raise ParameterError(name, value, allowed)
    try:
        number = float(value)  # type: ignore[arg-type]
    except OverflowError:
        raise ParameterError(name, value, allowed) from None
    if not math.isfinite(number) or not ok(number):
        raise ParameterError(name, value, allowed)
    return number


def _integer(name: str, value: object, low: int, high: int | None) -> int:
    """An integer (not a float, not a boolean) in [low, high]."""
    allowed = f"an integer from {low} to {high}" if high is not None else f"an integer >= {low}"
    if not _is_integer(value):
        raise ParameterError(name, value, allowed)
    number = int(value)  # type: ignore[arg-type]
    if number < low or (high is not None and number > high):
        raise ParameterError(name, value, allowed)
    return number


def _choice(name: str, value: object, options: Sequence[str], note: str = "") -> str:
    if not isinstance(value, str) or value not in options:
        raise ParameterError(name, value, " | ".join(options) + note)
    return value


def _numbers(name: str, values: object, allowed: str) -> tuple:
    """A list (or tuple) of real numbers, each still unchecked for range."""
    if hasattr(values, "tolist") and not isinstance(values, Sequence):
        values = values.tolist()  # a numpy array, from Python callers
    if isinstance(values, (str, bytes, Mapping)) or not isinstance(values, Sequence):
        raise ParameterError(name, values, allowed)
    for i, value in enumerate(values):
        if not _is_real(value):
            raise ParameterError(f"{name}[{i}]", value, "a number")
    return tuple(values)


def _instance(name: str, value: object, cls: type, optional: bool = False) -> None:
    if (value is None and optional) or isinstance(value, cls):
        return
    raise ParameterError(name, value, f"a {cls.__name__}" + (" or None" if optional else ""))


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
        Number of masses, 3 <= N <= :data:`MAX_N`; 3, 4 or 5 for ``perfect``;
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
        _choice("chain.case", self.case, CASES)
        if self.case != "custom":
            for name in ("masses", "springs"):
                if getattr(self, name) is not None:
                    raise ParameterError(f"chain.{name}", getattr(self, name), f'no {name} unless case = "custom"')
            N = _integer("chain.N", self.N, MIN_N, MAX_N)
            if self.case == "perfect" and N not in PERFECT_N:
                raise ParameterError("chain.N", self.N, "3, 4 or 5 (the perfect chains of the paper)")
            object.__setattr__(self, "N", N)
            return

        allowed = f'a list of {MIN_N} to {MAX_N} numbers > 0 (required for case = "custom")'
        if self.masses is None:
            raise ParameterError("chain.masses", None, allowed)
        masses = _numbers("chain.masses", self.masses, allowed)
        if not MIN_N <= len(masses) <= MAX_N:
            raise ParameterError("chain.masses", self.masses, allowed)
        masses = tuple(_real(f"chain.masses[{i}]", m, "a finite number > 0", lambda x: x > 0) for i, m in enumerate(masses))
        N = len(masses)
        if not _is_integer(self.N) or self.N != N:
            raise ParameterError("chain.N", self.N, f"len(chain.masses) = {N} (or leave N out)")

        allowed = f'a list of N+1 = {N + 1} numbers >= 0, walls first and last (required for case = "custom")'
        if self.springs is None:
            raise ParameterError("chain.springs", None, allowed)
        springs = _numbers("chain.springs", self.springs, allowed)
        if len(springs) != N + 1:
            raise ParameterError("chain.springs", self.springs, allowed)
        checked = []
        for i, k in enumerate(springs):
            if 0 < i < N:
                checked.append(_real(f"chain.springs[{i}]", k, "a finite number > 0 (an inner spring)", lambda x: x > 0))
            else:
                checked.append(_real(f"chain.springs[{i}]", k, "a finite number >= 0 (a wall; 0 = free end)", lambda x: x >= 0))
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

    L0: float = 10e-6
    C0: float = 10e-9

    def __post_init__(self) -> None:
        for name in ("L0", "C0"):
            value = _real(f"units.{name}", getattr(self, name), "a finite number > 0", lambda x: x > 0)
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
        Current in ampere (> 0): the kick, or the current the pulse's area
        gives L_1.
    shape : {"gaussian", "rect"}, optional
        Pulse only (required there): g(t) of unit area.
    width : float, optional
        Pulse only (required there): the gaussian's standard deviation or the
        rect's duration, in units of sqrt(L0*C0), 0 < width <= 1000.
    """

    kind: ExcitationKind = "kick"
    I0: float = 1e-3
    shape: PulseShape | None = None
    width: float | None = None

    def __post_init__(self) -> None:
        _choice("excitation.kind", self.kind, EXCITATION_KINDS)
        object.__setattr__(self, "I0", _real("excitation.I0", self.I0, "a finite number > 0 (ampere)", lambda x: x > 0))
        if self.kind != "pulse":
            for name in ("shape", "width"):
                if getattr(self, name) is not None:
                    raise ParameterError(f"excitation.{name}", getattr(self, name), f'no {name} unless kind = "pulse"')
            return
        _choice("excitation.shape", self.shape, PULSE_SHAPES, ' (required when kind = "pulse")')
        allowed = f'a number, 0 < width <= {MAX_WIDTH:g} (units of sqrt(L0*C0); required when kind = "pulse")'
        object.__setattr__(self, "width", _real("excitation.width", self.width, allowed, lambda x: 0 < x <= MAX_WIDTH))


@dataclass(frozen=True)
class Losses:
    """``[effects.losses]``: a series resistor R_i = L_i / (Q sqrt(L0*C0)) with every inductor.

    Parameters
    ----------
    Q : float
        Quality factor of every inductor at 1/sqrt(L0*C0) (dimensionless, > 0).
    """

    Q: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "Q", _real("effects.losses.Q", self.Q, "a finite number > 0", lambda x: x > 0))


@dataclass(frozen=True)
class Walls:
    """``[effects.walls]``: a wall spring K0 at each end, as in the paper's bounded chain.

    Parameters
    ----------
    K0 : float
        Wall spring constant in bulk units (> 0); its capacitor is C0 / K0.
    """

    K0: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "K0", _real("effects.walls.K0", self.K0, "a finite number > 0", lambda x: x > 0))


@dataclass(frozen=True)
class Tolerance:
    """``[effects.tolerance]``: component values drawn around their nominal ones.

    Parameters
    ----------
    L, C : float
        Relative tolerance of every inductor / capacitor, 0 <= tol < 1.
    samples : int
        Number of sampled circuits, 1..10000.
    seed : int
        Seed of ``numpy.random.default_rng`` (>= 0), so that a study repeats.
    """

    L: float = 0.0
    C: float = 0.0
    samples: int = 1
    seed: int = 0

    def __post_init__(self) -> None:
        for name in ("L", "C"):
            value = _real(f"effects.tolerance.{name}", getattr(self, name), f"a number, 0 <= {name} < 1", lambda x: 0 <= x < 1)
            object.__setattr__(self, name, value)
        object.__setattr__(self, "samples", _integer("effects.tolerance.samples", self.samples, 1, MAX_SAMPLES))
        object.__setattr__(self, "seed", _integer("effects.tolerance.seed", self.seed, 0, None))


@dataclass(frozen=True)
class PreferredValues:
    """``[effects.preferred_values]``: every L and C rounded to a preferred-number series.

    Parameters
    ----------
    series : {"E12", "E24", "E96"}
    """

    series: ESeries

    def __post_init__(self) -> None:
        _choice("effects.preferred_values.series", self.series, E_SERIES)


@dataclass(frozen=True)
class Effects:
    """The ``[effects.*]`` tables: each real-world effect the scene asks for, or None."""

    losses: Losses | None = None
    walls: Walls | None = None
    tolerance: Tolerance | None = None
    preferred_values: PreferredValues | None = None

    def __post_init__(self) -> None:
        _instance("effects.losses", self.losses, Losses, optional=True)
        _instance("effects.walls", self.walls, Walls, optional=True)
        _instance("effects.tolerance", self.tolerance, Tolerance, optional=True)
        _instance("effects.preferred_values", self.preferred_values, PreferredValues, optional=True)


@dataclass(frozen=True)
class Analysis:
    """The ``[analysis]`` table: how long to watch and how finely.

    Parameters
    ----------
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
    """

    transits: int = 1
    accuracy: float | None = None
    dt: float | None = None
    backend: Backend = "batch"
    method: Method = "trap"

    def __post_init__(self) -> None:
        object.__setattr__(self, "transits", _integer("analysis.transits", self.transits, 1, MAX_TRANSITS))
        if self.accuracy is not None and self.dt is not None:
            raise ParameterError(
                "analysis.dt", self.dt, "no dt when analysis.accuracy is given (they are mutually exclusive)"
            )
        if self.dt is not None:
            allowed = "a number, 0 < dt <= 1 (units of sqrt(L0*C0))"
            object.__setattr__(self, "dt", _real("analysis.dt", self.dt, allowed, lambda x: 0 < x <= 1))
        else:
            # Neither given: the default accuracy; dt given: no accuracy at all.
            accuracy = DEFAULT_ACCURACY if self.accuracy is None else self.accuracy
            allowed = "a number, 0 < accuracy < 1"
            object.__setattr__(self, "accuracy", _real("analysis.accuracy", accuracy, allowed, lambda x: 0 < x < 1))
        _choice("analysis.backend", self.backend, BACKENDS)
        _choice("analysis.method", self.method, METHODS)


@dataclass(frozen=True)
class Output:
    """The ``[output]`` table: what to save and what to draw.

    Parameters
    ----------
    probes : {"ends", "all"}
        Save the two end loop currents, or every loop current.
    report : str, optional
        Path of the JSON report, relative to the current directory (not
        resolved here).
    plots : tuple of {"overlay", "spacetime", "histogram"}
        Pictures to draw, each at most once.
    """

    probes: Probes = "ends"
    report: str | None = None
    plots: tuple[PlotKind, ...] = ("overlay",)

    def __post_init__(self) -> None:
        _choice("output.probes", self.probes, PROBES)
        if self.report is not None:
            if (
                not isinstance(self.report, str)
                or not self.report.strip()
                or any(ord(ch) < 32 or ord(ch) == 127 for ch in self.report)
            ):
                raise ParameterError("output.report", self.report, "a file path (one line of text)")
        allowed = "a list of distinct names from " + ", ".join(PLOT_KINDS)
        if isinstance(self.plots, (str, bytes, Mapping)) or not isinstance(self.plots, Sequence):
            raise ParameterError("output.plots", self.plots, allowed)
        for i, kind in enumerate(self.plots):
            _choice(f"output.plots[{i}]", kind, PLOT_KINDS)
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
        check_user_text("title", self.title)
        for name, cls in (
            ("chain", ChainSpec),
            ("units", Units),
            ("excitation", ExcitationSpec),
            ("effects", Effects),
            ("analysis", Analysis),
            ("output", Output),
        ):
            _instance(name, getattr(self, name), cls)
        plots = list(self.output.plots)
        if "spacetime" in plots and self.output.probes != "all":
            raise ParameterError("output.plots", plots, 'no "spacetime" unless output.probes = "all"')
        tolerance = self.effects.tolerance
        if "histogram" in plots and (tolerance is None or tolerance.samples < 2):
            raise ParameterError("output.plots", plots, 'no "histogram" unless effects.tolerance.samples > 1')

    def to_dict(self) -> dict[str, Any]:
        """The scene as plain data with the file's keys (JSON- and TOML-writable).

        Keys left at None are omitted, ``effects`` holds only the effects
        present, and ``parse_scene(scene.to_dict()) == scene``.
        """

        def table(obj: object, keys: Sequence[str]) -> dict[str, Any]:
            out = {}
            for key in keys:
                value = getattr(obj, key)
                if value is not None:
                    out[key] = list(value) if isinstance(value, tuple) else value
            return out

        effects = {
            name: table(getattr(self.effects, name), keys)
            for name, keys in _EFFECT_KEYS.items()
            if getattr(self.effects, name) is not None
        }
        return {
            "title": self.title,
            "chain": table(self.chain, _CHAIN_KEYS),
            "units": table(self.units, _UNITS_KEYS),
            "excitation": table(self.excitation, _EXCITATION_KEYS),
            "effects": effects,
            "analysis": table(self.analysis, _ANALYSIS_KEYS),
            "output": table(self.output, _OUTPUT_KEYS),
        }


# -------------------------------------------------------------------- parsing


def load_scene(path: str | os.PathLike) -> Scene:
    """Read and validate a scene file.

    Parameters
    ----------
    path : str or os.PathLike
        The TOML file.  Errors name it as given.

    Raises
    ------
    ParameterError
        The file cannot be read, is not valid TOML (the message has the line
        number and text), or breaks a rule of the scene format.
    """
    where = os.fspath(path)
    try:
        with open(path, "rb") as handle:
            raw = handle.read()
    except OSError as error:
        raise ParameterError("scene", where, f"a readable TOML file ({error.strerror or error})", where) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as error:
        raise ParameterError("scene", where, f"UTF-8 text ({error.reason} at byte {error.start})", where) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        match = re.search(r"at line (\d+)", str(error))
        if match:
            line = int(match.group(1))
            lines = text.splitlines()
            shown = lines[line - 1] if 0 < line <= len(lines) else ""
            raise ParameterError(f"line {line}", shown, f"valid TOML ({error})", where) from None
        raise ParameterError("scene", where, f"valid TOML ({error})", where) from None
    return parse_scene(data, source=where)


def parse_scene(data: Mapping, source: str | None = None) -> Scene:
    """Validate a scene given as nested mappings (a parsed TOML or JSON document).

    Parameters
    ----------
    data : Mapping
        The tables of the scene file; absent optional tables and keys take
        their defaults.
    source : str, optional
        Where the data came from; prefixed to every error message and kept
        as ``Scene.source``.

    Raises
    ------
    ParameterError
        Unknown key, wrong type, value out of range or inconsistent tables.
    """
    try:
        return _parse(data, source)
    except ParameterError as error:
        if error.where is not None or source is None:
            raise
        raise ParameterError(error.field, error.value, error.allowed, source) from None


def _table(data: Mapping, name: str, keys: Sequence[str], required: bool = False) -> dict[str, Any]:
    """The sub-table ``name`` of ``data`` (dotted path), with only known keys."""
    last = name.rsplit(".", 1)[-1]
    if last not in data:
        if required:
            raise ParameterError(name, None, f"a table [{name}] (required)")
        return {}
    table = data[last]
    if not isinstance(table, Mapping):
        raise ParameterError(name, table, f"a table [{name}]")
    _known_keys(table, keys, name)
    return dict(table)


def _known_keys(table: Mapping, keys: Sequence[str], path: str) -> None:
    for key in table:
        if key not in keys:
            where = f"in [{path}]" if path else "at the top level"
            dotted = f"{path}.{key}" if path else str(key)
            raise ParameterError(dotted, table[key], f"one of the keys {', '.join(keys)} {where} (unknown key)")


def _parse(data: Mapping, source: str | None) -> Scene:
    if not isinstance(data, Mapping):
        raise ParameterError("scene", data, "a table of tables")
    _known_keys(data, _TOP_KEYS, "")

    chain = _table(data, "chain", _CHAIN_KEYS, required=True)
    _choice("chain.case", chain.get("case"), CASES)
    if "N" not in chain:
        if chain["case"] != "custom":
            raise ParameterError("chain.N", None, f"an integer from {MIN_N} to {MAX_N} (required)")
        masses = chain.get("masses")
        if isinstance(masses, Sequence) and not isinstance(masses, (str, bytes)):
            chain["N"] = len(masses)
    chain_spec = ChainSpec(
        case=chain["case"],
        N=chain.get("N"),
        masses=chain.get("masses"),
        springs=chain.get("springs"),
    )

    units = Units(**_table(data, "units", _UNITS_KEYS))
    excitation = ExcitationSpec(**_table(data, "excitation", _EXCITATION_KEYS))

    effects_table = _table(data, "effects", tuple(_EFFECT_KEYS))
    effects: dict[str, Any] = {}
    for name, cls in (("losses", Losses), ("walls", Walls), ("tolerance", Tolerance), ("preferred_values", PreferredValues)):
        if name not in effects_table:
            continue
        values = _table(effects_table, f"effects.{name}", _EFFECT_KEYS[name])
        for required in fields(cls):
            if required.default is MISSING:
                # Let the class name what it expects of the missing value.
                values.setdefault(required.name, None)
        effects[name] = cls(**values)

    analysis = Analysis(**_table(data, "analysis", _ANALYSIS_KEYS))
    output = Output(**_table(data, "output", _OUTPUT_KEYS))

    return Scene(
        title=data.get("title", DEFAULT_TITLE),
        chain=chain_spec,
        units=units,
        excitation=excitation,
        effects=Effects(**effects),
        analysis=analysis,
        output=output,
        source=source,
    )
