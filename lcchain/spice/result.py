"""A transient run's result, as every engine returns it, and the checks every engine's run goes through.

An engine (:class:`lcchain.spice.engine.Engine`) checks a run's arguments with :func:`check_arguments`, reads its
program's output into columns, checks them with :func:`validate_columns` (points, last time point equal to
``tstop`` within :data:`TSTOP_RTOL`, every requested vector present, all finite) and returns a
:class:`RunResult`.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.checks import real
from ..core.errors import ParameterError, SimulationError
from ..core.frozen import FrozenArrays, FrozenMap
from ..core.limits import MAX_NETLIST_BYTES
from ..core.types import DEFAULT_ENGINE
from .inputs import read_input
from .log import useful_output
from .measure import Measurements
from .text import canonical_vector_name

__all__ = ["RunResult", "read_include", "check_arguments", "validate_columns", "TSTOP_RTOL"]

#: Relative tolerance on the last time point versus the requested ``tstop``.
TSTOP_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class RunResult(FrozenArrays):
    """Waveforms and metadata of one transient run (in ngspice or another engine).

    Attributes
    ----------
    time : numpy.ndarray
        Time points in seconds (read-only), ending at ``tstop``.
    vectors : Mapping[str, numpy.ndarray]
        Requested vectors (read-only arrays, amperes or volts) keyed by their
        normalised name (:func:`lcchain.spice.text.canonical_vector_name`).
    engine_version : str
        The engine's version, e.g. ``"39"`` for ngspice.
    netlist_sha256 : str
        SHA-256 (hex) of the netlist text encoded as UTF-8.
    options : Mapping[str, str]
        The ``.options`` the netlist sets (:func:`lcchain.spice.text.parse_options`).
    wall_s : float
        Wall time of the simulator in seconds: the ``ngspice -b`` process for
        ``"batch"``, loading and running the circuit inside the child for
        ``"shared"`` (child start-up excluded).
    backend : str
        ``"batch"`` or ``"shared"``.
    points : int
        Number of time points.
    log : str
        The simulator's output without blank lines and resource chatter, trimmed to
        :data:`LOG_MAX_CHARS` characters.
    engine : str
        The engine's name (:data:`lcchain.spice.engines.ENGINES`), ``"ngspice"`` by default.
    measurements : Mapping[str, tuple[float | None, str]]
        The netlist's ``.meas`` results by name (lower case): (value, "") or (None, ngspice's reason)
        (:func:`lcchain.spice.measure.read_measurements`).
    """

    time: np.ndarray
    vectors: Mapping[str, np.ndarray]
    engine_version: str
    netlist_sha256: str
    options: Mapping[str, str]
    wall_s: float
    backend: str
    points: int
    log: str = field(repr=False)
    engine: str = DEFAULT_ENGINE
    measurements: Measurements = field(default_factory=FrozenMap)

    @property
    def ngspice_version(self) -> str:
        """The default engine's (ngspice's) version when it ran this, else "" (records made before engines had
        only this field)."""
        return self.engine_version if self.engine == DEFAULT_ENGINE else ""

    def metadata(self) -> dict[str, object]:
        """Everything but the arrays, as a JSON-serialisable dict.

        Returns
        -------
        dict
            Keys ``engine``, ``engine_version``, ``ngspice_version`` (as the
            property), ``netlist_sha256``, ``options``,
            ``wall_s``, ``backend``, ``points``, ``vectors`` (the names),
            ``t_end`` (last time point, s) and ``log``.
        """
        return {
            "engine": self.engine,
            "engine_version": self.engine_version,
            "ngspice_version": self.ngspice_version,
            "netlist_sha256": self.netlist_sha256,
            "options": dict(self.options),
            "wall_s": float(self.wall_s),
            "backend": self.backend,
            "points": int(self.points),
            "vectors": list(self.vectors),
            "t_end": float(self.time[-1]),
            "log": self.log,
        }


def check_arguments(netlist: object, vectors: object, tstop: object, timeout: object,
                    max_output_bytes: object) -> tuple[str, list[str], float, float, float | None]:
    """A run's arguments, checked: the text, the canonical vector names (no ``time``), tstop, timeout, limit."""
    if not isinstance(netlist, str) or not netlist.strip():
        raise ParameterError("netlist", netlist, "non-empty netlist text")
    tstop = real("tstop", tstop, above=0.0, unit="seconds")
    timeout = real("timeout", timeout, above=0.0, unit="seconds")
    limit = None if max_output_bytes is None else real("max_output_bytes", max_output_bytes, above=0.0,
                                                        unit="bytes")
    if isinstance(vectors, str) or not isinstance(vectors, Sequence):
        raise ParameterError("vectors", vectors, "a sequence of vector names, not one string")
    names: list[str] = []
    for name in vectors:
        if not isinstance(name, str) or not name.strip() or re.search(r"\s", name.strip()):
            raise ParameterError("vectors", name, "an ngspice vector name such as 'i(l1)' or 'v(n3)'")
        key = canonical_vector_name(name)
        if key != "time" and key not in names:
            names.append(key)
    return netlist, names, tstop, timeout, limit


def read_include(path: Path, field: str) -> str:
    """A netlist's or an included file's text (the ``read`` of :func:`lcchain.spice.foreign.allowed_netlist`):
    a regular file of at most :data:`lcchain.core.limits.MAX_NETLIST_BYTES`."""
    return read_input(path, field, MAX_NETLIST_BYTES)



def validate_columns(columns: dict[str, np.ndarray], log: str, names: list[str], tstop: float,
                     engine: str = DEFAULT_ENGINE) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The time vector and the requested vectors of a run, checked: points, last time = tstop (within
    :data:`TSTOP_RTOL`), every name present, equal lengths, all finite; read-only float64 arrays.

    Raises
    ------
    SimulationError
        Naming what failed, with the useful end of the engine's output ``log``.
    """
    def fail(reason: str) -> SimulationError:
        return SimulationError(reason, useful_output(log), "failed", engine)

    if "time" not in columns:
        raise fail(f"{engine} returned no time vector (is there a .tran analysis?)")
    time_s = columns["time"]
    if time_s.size == 0:
        raise fail(f"{engine} returned zero time points")
    if not math.isclose(float(time_s[-1]), tstop, rel_tol=TSTOP_RTOL, abs_tol=0.0):
        raise fail(f"the last time point is {float(time_s[-1])!r} s, not tstop = {tstop!r} s")
    if not names:  # nothing named: every vector the engine saved
        names = sorted(key for key in columns if key != "time")
    missing = [name for name in names if name not in columns]
    if missing:
        available = ", ".join(sorted(k for k in columns if k != "time")) or "none"
        raise fail(f"requested vector(s) {', '.join(missing)} not in {engine}'s output (saved: {available}); "
                   "add them to the netlist's .save line")
    found: dict[str, np.ndarray] = {}
    for name in ["time", *names]:
        arr = np.ascontiguousarray(columns[name], dtype=np.float64)
        if arr.shape != time_s.shape:
            raise fail(f"vector {name} has {arr.size} points, time has {time_s.size}")
        if not np.all(np.isfinite(arr)):
            raise fail(f"vector {name} holds non-finite values")
        arr.flags.writeable = False
        found[name] = arr
    return found.pop("time"), found
