"""One run's record, whichever analysis and engine made it, and the checks every engine's run goes through.

A run of any analysis is one :class:`RunResult`: what every run shares (the engine and its version, the netlist's
digest, the wall time, the log, the ``.meas`` results, the ``.options``, the transport) and the analysis's own
data as a field, :attr:`RunResult.data`: a :class:`TransientData` (time and real vectors) or an :class:`AcData`
(frequency and complex phasors), as python-control's ``TimeResponseData`` and ``FrequencyResponseData`` share one
shape.  ``time``, ``frequency``, ``vectors`` and ``points`` read the data through the record.

An engine (:class:`lcchain.spice.engine.Engine`) receives a checked :class:`~lcchain.spice.job.RunJob`, reads its
program's output into columns, checks them with :func:`validate_columns` (points, last time point equal to
``tstop`` within :data:`TSTOP_RTOL`, every requested vector present, all finite) and returns a
:class:`RunResult` of a :class:`TransientData`; an AC analysis's columns go through
:func:`lcchain.spice.acdata.ac_result`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar, Literal

from ..core.errors import SimulationError
from ..core.frozen import FrozenArrays, FrozenMap
from ..core.limits import MAX_NETLIST_BYTES
from ..core.types import DEFAULT_ENGINE
from .inputs import read_input
from .log import useful_output
from .measure import Measurements

if TYPE_CHECKING:
    import numpy as np

__all__ = ["RunResult", "TransientData", "AcData", "read_include", "validate_columns", "TSTOP_RTOL"]

#: Relative tolerance on the last time point versus the requested ``tstop``.
TSTOP_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class TransientData(FrozenArrays):
    """A transient's waveforms.

    Attributes
    ----------
    time : numpy.ndarray
        Time points in seconds (read-only), ending at ``tstop``.
    vectors : Mapping[str, numpy.ndarray]
        Real vectors (read-only arrays, amperes or volts) by canonical name
        (:func:`lcchain.spice.text.canonical_vector_name`).
    """

    analysis: ClassVar[Literal["transient"]] = "transient"

    time: np.ndarray
    vectors: Mapping[str, np.ndarray]

    @property
    def axis(self) -> np.ndarray:
        """The analysis's scale: :attr:`time`."""
        return self.time


@dataclass(frozen=True, eq=False)
class AcData(FrozenArrays):
    """An AC analysis's phasors.

    Attributes
    ----------
    frequency : numpy.ndarray
        Hz, ascending (read-only).
    vectors : Mapping[str, numpy.ndarray]
        Complex phasors (A for a branch current) by canonical name, for a source of 1 V.
    """

    analysis: ClassVar[Literal["ac"]] = "ac"

    frequency: np.ndarray
    vectors: Mapping[str, np.ndarray]

    @property
    def axis(self) -> np.ndarray:
        """The analysis's scale: :attr:`frequency`."""
        return self.frequency


@dataclass(frozen=True, eq=False)
class RunResult:
    """One run in an engine: its analysis's data and what every run records.

    Attributes
    ----------
    data : TransientData or AcData
        The analysis's own data.
    engine_version : str
        The engine's version, e.g. ``"39"`` for ngspice.
    netlist_sha256 : str
        SHA-256 (hex) of the netlist text (lcchain's, in ngspice's dialect, whichever engine ran it) as UTF-8.
    wall_s : float
        Wall time of the simulator in seconds: the ``ngspice -b`` process for ``"batch"``, loading and running
        the circuit inside the child for ``"shared"`` (child start-up excluded).
    log : str
        The simulator's output without blank lines and resource chatter, trimmed to
        :data:`lcchain.spice.log.LOG_MAX_CHARS` characters.
    engine : str
        The engine's name (:data:`lcchain.spice.engines.ENGINES`), ``"ngspice"`` by default.
    measurements : Mapping[str, tuple[float | None, str]]
        The netlist's ``.meas`` results by name (lower case): (value, "") or (None, ngspice's reason)
        (:func:`lcchain.spice.measure.read_measurements`).
    options : Mapping[str, str]
        The ``.options`` the netlist sets (:func:`lcchain.spice.text.parse_options`); a transient's.
    backend : str
        The transport that ran it: ``"batch"``, ``"shared"``, ``"warm"``.
    """

    data: TransientData | AcData
    engine_version: str
    netlist_sha256: str
    wall_s: float
    log: str = field(repr=False)
    engine: str = DEFAULT_ENGINE
    measurements: Measurements = field(default_factory=FrozenMap)
    options: Mapping[str, str] = field(default_factory=FrozenMap)
    backend: str = "batch"

    @property
    def analysis(self) -> Literal["transient", "ac"]:
        """``"transient"`` or ``"ac"``: the kind of :attr:`data`."""
        return self.data.analysis

    @property
    def time(self) -> np.ndarray:
        """A transient's time points, seconds (an AttributeError for another analysis)."""
        if not isinstance(self.data, TransientData):
            raise AttributeError(f"an {self.analysis} run has no time points (its scale is data.axis)")
        return self.data.time

    @property
    def frequency(self) -> np.ndarray:
        """An AC analysis's frequencies, Hz (an AttributeError for another analysis)."""
        if not isinstance(self.data, AcData):
            raise AttributeError(f"a {self.analysis} run has no frequencies (its scale is data.axis)")
        return self.data.frequency

    @property
    def vectors(self) -> Mapping[str, np.ndarray]:
        """The analysis's vectors by canonical name."""
        return self.data.vectors

    @property
    def points(self) -> int:
        """Time points or frequencies."""
        return int(self.data.axis.size)

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
            ``t_end`` (a transient's last time point, s; an AC analysis's ``f_end``, its last frequency, Hz)
            and ``log``.
        """
        end = {"t_end": float(self.time[-1])} if isinstance(self.data, TransientData) else \
            {"f_end": float(self.frequency[-1])}
        return {
            "engine": self.engine,
            "engine_version": self.engine_version,
            "ngspice_version": self.ngspice_version,
            "netlist_sha256": self.netlist_sha256,
            "options": dict(self.options),
            "wall_s": float(self.wall_s),
            "backend": self.backend,
            "points": self.points,
            "vectors": list(self.vectors),
            **end,
            "log": self.log,
        }


def read_include(path: Path, field: str) -> str:
    """A netlist's or an included file's text (the ``read`` of :func:`lcchain.spice.foreign.allowed_netlist`):
    a regular file of at most :data:`lcchain.core.limits.MAX_NETLIST_BYTES`."""
    return read_input(path, field, MAX_NETLIST_BYTES)


def validate_columns(columns: dict[str, np.ndarray], log: str, names: Sequence[str], tstop: float,
                     engine: str = DEFAULT_ENGINE) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The time vector and the requested vectors of a run, checked: points, last time = tstop (within
    :data:`TSTOP_RTOL`), every name present, equal lengths, all finite; read-only float64 arrays.

    Raises
    ------
    SimulationError
        Naming what failed, with the useful end of the engine's output ``log``.
    """
    import numpy as np

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
        raise fail(f"requested vector(s) {', '.join(missing)} not in {engine}'s output (saved: {available}): "
                   "no node or device of the circuit by that name, or one the engine writes otherwise")
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
