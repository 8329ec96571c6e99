"""What an AC analysis returns, whichever engine ran it: :class:`AcResult`, checked by :func:`ac_result`.

Every engine's :meth:`~lcchain.spice.engine.Engine.run_ac` reads its own output into columns (``"frequency"`` in
Hz and complex vectors by canonical name) and hands them to :func:`ac_result`, so that every engine's result
passes the same checks: as many frequencies as asked, each once, every vector present, all finite.  Several
``.ac`` cards (a sweep in segments) give every card's frequencies, which come out in ascending order.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import SimulationError
from ..core.frozen import FrozenArrays, FrozenMap
from .log import trim_log, useful_output
from .measure import Measurements, measure_names, read_measurements
from .simulator import Simulator

__all__ = ["AcResult", "ac_result"]


@dataclass(frozen=True, eq=False)
class AcResult(FrozenArrays):
    """One AC analysis.

    Attributes
    ----------
    frequency : numpy.ndarray
        Hz, ascending (read-only).
    vectors : Mapping[str, numpy.ndarray]
        Complex phasors (A for a branch current) by canonical name, for a source of 1 V.
    engine_version : str
    netlist_sha256 : str
        Of lcchain's netlist text (ngspice's dialect), whichever engine ran it.
    wall_s : float
        The engine's process's wall time.
    log : str
    engine : str
        The engine's name (:data:`lcchain.spice.engines.ENGINES`).
    measurements : Mapping[str, tuple[float | None, str]]
        The netlist's ``.meas ac`` results by name: (value, "") or (None, ngspice's reason).
    """

    frequency: np.ndarray
    vectors: Mapping[str, np.ndarray]
    engine_version: str
    netlist_sha256: str
    wall_s: float
    log: str = field(repr=False)
    engine: str = "ngspice"
    measurements: Measurements = field(default_factory=FrozenMap)

    @property
    def points(self) -> int:
        return int(self.frequency.size)


def ac_result(netlist: str, columns: Mapping[str, np.ndarray], log: str, names: Sequence[str], points: int,
              simulator: Simulator, wall_s: float) -> AcResult:
    """An engine's AC columns as an :class:`AcResult`, checked.

    Parameters
    ----------
    netlist : str
        lcchain's netlist text (hashed into the result).
    columns : Mapping[str, numpy.ndarray]
        ``"frequency"`` (Hz, real) and complex vectors by canonical name, as the engine read them (in any order:
        they are sorted by frequency).
    log : str
        The engine's output worth keeping and quoting.
    names : sequence of str
        The canonical names asked for (none: every vector the engine saved).
    points : int
        The frequencies the netlist's ``.ac`` line asks for.
    simulator : Simulator
        The one that ran (its engine and version go into the result).
    wall_s : float
        Seconds.

    Raises
    ------
    SimulationError
        A frequency or a vector missing, too few or too many frequencies, one twice (overlapping cards), or a value
        that is not finite.
    """
    engine = simulator.engine

    def fail(reason: str) -> SimulationError:
        return SimulationError(reason, useful_output(log), "failed", engine)

    if "frequency" not in columns:
        raise fail(f"{engine} returned no frequency vector")
    frequency = np.array(columns["frequency"], dtype=np.float64)
    if frequency.size != points:
        raise fail(f"{engine} returned {frequency.size} frequencies, not the {points} asked for")
    order = np.argsort(frequency, kind="stable")  # several .ac cards: in the engine's own order
    frequency = frequency[order]
    if not np.all(np.isfinite(frequency)):
        raise fail(f"{engine} returned a frequency that is not finite")
    if np.any(np.diff(frequency) <= 0):
        raise fail(f"{engine} returned a frequency twice (overlapping .ac cards)")
    found = {}
    for name in names or sorted(key for key in columns if key != "frequency"):  # none named: every one saved
        if name not in columns:
            raise fail(f"{engine} saved no vector {name!r}")
        values = np.array(columns[name], dtype=np.complex128)
        if values.shape != frequency.shape:
            raise fail(f"the vector {name!r} has {values.size} points, frequency has {frequency.size}")
        values = values[order]
        if not np.all(np.isfinite(values)):
            raise fail(f"the vector {name!r} holds a value that is not finite (a frequency at a pole?)")
        found[name] = values
    frequency.flags.writeable = False
    return AcResult(frequency, FrozenMap(found), simulator.version,
                    hashlib.sha256(netlist.encode("utf-8")).hexdigest(), wall_s, trim_log(log), engine,
                    FrozenMap(read_measurements(log, measure_names(netlist))))
