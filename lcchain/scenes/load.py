"""Reading a scene: TOML (or nested mappings) into the typed, validated :class:`~lcchain.scenes.schema.Scene`.

Unknown keys are errors that name the key and the file; every other problem
raises :class:`~lcchain.core.errors.ParameterError` naming the dotted key, the
value and what is allowed, prefixed by the file.  The loader does no physics.
"""

from __future__ import annotations

import copy
import os
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import MISSING

from ..circuit.effects import E_SERIES, EFFECTS, Effect, effect_fields
from ..core.analyses import analysis_kind
from ..core.checks import choice, integer, real
from ..core.errors import ParameterError
from ..core.json import LooseJSON, LooseJSONObject
from ..core.limits import MAX_CIRCUIT_N, MAX_SAMPLES, MAX_SCENE_BYTES, MIN_N
from ..core.types import ANALYSIS_KINDS
from ..spice.inputs import read_input
from ..theory.cases import named_case, scene_cases
from .schema import (
    ANALYSIS_KEYS,
    ANALYSIS_PLOTS,
    CHAIN_KEYS,
    DEFAULT_TITLE,
    EXCITATION_KEYS,
    OUTPUT_KEYS,
    TOP_KEYS,
    UNITS_KEYS,
    Analysis,
    ChainSpec,
    Effects,
    ExcitationSpec,
    Output,
    Scene,
    Units,
    check_ac_keys,
    effect_keys,
)

__all__ = ["load_scene", "parse_scene", "override_parts"]


def load_scene(path: str | os.PathLike[str]) -> Scene:
    """Read and validate a scene file.

    Parameters
    ----------
    path : str or os.PathLike
        The TOML file.  Errors name it as given.

    Raises
    ------
    ParameterError
        ``path`` is not a file name; the file is not a regular file (a FIFO, a
        device, a folder), is larger than :data:`~lcchain.core.limits.MAX_SCENE_BYTES`,
        cannot be read, is not valid TOML (the message has the line
        number and text), or breaks a rule of the scene format.
    """
    given: object = path
    where = os.fspath(given) if isinstance(given, (str, os.PathLike)) else None
    if not isinstance(where, str):
        raise ParameterError("path", type(path).__name__, "a file name (str or os.PathLike)")
    try:
        text = read_input(where, "scene", MAX_SCENE_BYTES)
    except ParameterError as error:
        raise error.located(where) from None
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
    except RecursionError:
        raise ParameterError("scene", where, "TOML nested a few levels deep (tables of values); this one nests "
                             "too deeply to read", where) from None
    return parse_scene(data, source=where)


def parse_scene(data: Mapping[str, LooseJSON], source: str | None = None) -> Scene:
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


def _table(data: Mapping[str, LooseJSON], name: str, keys: Sequence[str], required: bool = False) -> LooseJSONObject:
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


def _known_keys(table: Mapping[str, object], keys: Sequence[str], path: str) -> None:
    for key in table:
        if key not in keys:
            where = f"in [{path}]" if path else "at the top level"
            dotted = f"{path}.{key}" if path else str(key)
            raise ParameterError(dotted, table[key], f"one of the keys {', '.join(keys)} {where} (unknown key)")


def _parse(data: Mapping[str, LooseJSON], source: str | None) -> Scene:
    if not isinstance(data, Mapping):
        raise ParameterError("scene", data, "a table of tables")
    _known_keys(data, TOP_KEYS, "")

    chain = _table(data, "chain", CHAIN_KEYS, required=True)
    choice("chain.case", chain.get("case"), scene_cases())
    if "N" not in chain:
        if named_case(chain["case"]) is not None:  # a named case's size; a custom chain's is its masses
            raise ParameterError("chain.N", None, f"an integer from {MIN_N} to {MAX_CIRCUIT_N} (required)")
        masses = chain.get("masses")
        if isinstance(masses, Sequence) and not isinstance(masses, (str, bytes)):
            chain["N"] = len(masses)
    chain_spec = ChainSpec(
        case=chain["case"],
        N=chain.get("N"),  # type: ignore[arg-type]  # ChainSpec checks it and names it
        masses=chain.get("masses"),
        springs=chain.get("springs"),
    )

    units = Units(**_table(data, "units", UNITS_KEYS))
    excitation = ExcitationSpec(**_table(data, "excitation", EXCITATION_KEYS))

    effects_table = _table(data, "effects", tuple(EFFECTS))
    effects: dict[str, Effect] = {}
    for name, cls in EFFECTS.items():
        if name not in effects_table:
            continue
        values = _table(effects_table, f"effects.{name}", effect_keys(cls))
        for required in effect_fields(cls):
            if required.default is MISSING:
                # Let the class name what it expects of the missing value.
                values.setdefault(required.name, None)
        effects[name] = cls(**values)

    analysis_table = _table(data, "analysis", ANALYSIS_KEYS)
    output_table = _table(data, "output", OUTPUT_KEYS)
    kind = analysis_table.get("kind", ANALYSIS_KINDS[0])
    if kind in ANALYSIS_KINDS and analysis_kind(kind).swept:  # a transient's key is refused even at its default
        check_ac_keys(analysis_table)
    if kind in ANALYSIS_PLOTS:
        output_table.setdefault("plots", ANALYSIS_PLOTS[kind][:1])
    analysis = Analysis(**analysis_table)
    output = Output(**output_table)

    return Scene(
        title=data.get("title", DEFAULT_TITLE),
        chain=chain_spec,
        units=units,
        excitation=excitation,
        effects=Effects(effects),
        analysis=analysis,
        output=output,
        source=source,
    )


def check_samples_spread(samples: int | None, datas: Sequence[Mapping[str, LooseJSON]]) -> None:
    """Refuse ``--samples`` N > 1 where no scene it makes draws from a tolerance (``[effects.tolerance]`` L and C
    both 0 or absent in every one): its samples would all be the nominal circuit.  A sweep through a tolerance of 0
    beside others is no such case."""
    if samples is None or samples <= 1:
        return
    for data in datas:
        effects = data.get("effects")
        table = effects.get("tolerance") if isinstance(effects, Mapping) else None
        if isinstance(table, Mapping) and any(isinstance(table.get(name), (int, float)) and table.get(name)
                                              for name in ("L", "C")):
            return
    raise ParameterError("--samples", samples, "1 without a tolerance to draw from (every sample would be the "
                         "nominal circuit): give --tolerance, or L or C in the scene's [effects.tolerance]")


def override_parts(data: Mapping[str, LooseJSON], *, tolerance: Mapping[str, float] | None = None,
                   series: str | None = None, samples: int | None = None, seed: int | None = None) -> LooseJSONObject:
    """A scene's tables with its real parts set from the command line, for a Monte Carlo without editing the file.

    Each value is checked under the option that gave it (``--tolerance L = 1.5 is not allowed: ...``) before
    the scene is; the scene's other keys stay.

    Parameters
    ----------
    data : Mapping
        The scene's tables (:meth:`Scene.to_dict`).
    tolerance : mapping, optional
        ``{"L": tol_L, "C": tol_C}`` (either or both), relative, 0 <= tol < 1: ``effects.tolerance.L``/``.C``.
    series : str, optional
        An IEC 60063 series (``"E12"``, ``"E24"``, ``"E96"``): ``effects.preferred_values.series``.
    samples : int, optional
        Tolerance samples, 1 .. :data:`~lcchain.core.limits.MAX_SAMPLES`: ``effects.tolerance.samples``.
    seed : int, optional
        The tolerance draw's seed, >= 0: ``effects.tolerance.seed``.
    """
    out = copy.deepcopy(dict(data))
    effects = out.setdefault("effects", {})
    drawn: dict[str, float] = {}
    for name, value in (tolerance or {}).items():
        if name not in ("L", "C"):
            raise ParameterError("--tolerance", f"{name}={value}", "L=TOL, C=TOL or one TOL for both")
        drawn[name] = real(f"--tolerance {name}", value, at_least=0.0, below=1.0,
                           allowed=f"a relative tolerance, 0 <= {name} < 1")
    if samples is not None:
        drawn["samples"] = integer("--samples", samples, at_least=1, at_most=MAX_SAMPLES)
    if seed is not None:
        drawn["seed"] = integer("--seed", seed, at_least=0)
    if drawn:
        effects.setdefault("tolerance", {}).update(drawn)
    if series is not None:
        effects.setdefault("preferred_values", {})["series"] = choice("--series", series, tuple(E_SERIES))
    return out
