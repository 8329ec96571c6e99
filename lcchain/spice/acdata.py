"""What an AC analysis returns, whichever engine ran it: a :class:`~lcchain.spice.result.RunResult` of an
:class:`~lcchain.spice.result.AcData` (:data:`AcResult` names the same record), checked by :func:`ac_result`.

Every engine's :meth:`~lcchain.spice.engine.Engine.run_ac` reads its own output into columns (``"frequency"`` in
Hz and complex vectors by canonical name) and hands them to :func:`ac_result`, so that every engine's result
passes the same checks: as many frequencies as asked, each once, every vector present, all finite.  Several
``.ac`` cards (a sweep in segments) give every card's frequencies, which come out in ascending order.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from typing import TYPE_CHECKING

from ..core.errors import SimulationError
from ..core.frozen import FrozenMap
from .job import AcJob
from .log import trim_log, useful_output
from .measure import measure_names, read_measurements
from .result import AcData, RunResult
from .simulator import Simulator
from .text import parse_options

if TYPE_CHECKING:
    import numpy as np

__all__ = ["AcResult", "ac_result"]


#: An AC analysis's record: the same record as a transient's (:class:`lcchain.spice.result.RunResult`), whose
#: ``data`` is an :class:`~lcchain.spice.result.AcData` (``frequency`` in Hz, complex ``vectors``); the name is kept
#: for the code that says which analysis it holds.
AcResult = RunResult


def ac_result(job: AcJob, columns: Mapping[str, np.ndarray], log: str, simulator: Simulator,
              wall_s: float) -> RunResult:
    """An engine's AC columns as a run's record (an :class:`~lcchain.spice.result.AcData`), checked.

    Parameters
    ----------
    job : AcJob
        The run asked for: its netlist (lcchain's text, hashed into the result), the canonical names of its
        vectors (none: every vector the engine saved) and the frequencies its ``.ac`` cards ask for.
    columns : Mapping[str, numpy.ndarray]
        ``"frequency"`` (Hz, real) and complex vectors by canonical name, as the engine read them (in any order:
        they are sorted by frequency).
    log : str
        The engine's output worth keeping and quoting.
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
    import numpy as np

    engine, netlist, names, points = simulator.engine, job.netlist, job.vectors, job.points

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
    return RunResult(AcData(frequency, FrozenMap(found)), simulator.version,
                     hashlib.sha256(netlist.encode("utf-8")).hexdigest(), wall_s, trim_log(log), engine,
                     FrozenMap(read_measurements(log, measure_names(netlist))), FrozenMap(parse_options(netlist)),
                     simulator.backend)
