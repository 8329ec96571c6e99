"""An AC analysis of lcchain's own ladder in ngspice: complex vectors against frequency.

:func:`run_ac` runs an AC netlist (:func:`lcchain.circuit.netlist.ac_netlist_text`) with the batch
transport's discipline (:mod:`lcchain.spice.runner`: the netlist on standard input, the raw file on an
unnamed descriptor, its own process group, a timeout, nothing left behind) and returns the frequencies and
the complex vectors, checked: every vector present, as many points as asked, all finite.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..core.checks import integer, real
from ..core.errors import ParameterError, SimulationError
from ..core.frozen import FrozenArrays, FrozenMap
from .log import failure_reason, fatal_lines, trim_log, useful_output
from .runner import _placement, _run_batch
from .simulator import Simulator, find_simulator
from .text import canonical_vector_name

__all__ = ["AcResult", "run_ac"]


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
    wall_s : float
        The ngspice process's wall time.
    log : str
    """

    frequency: np.ndarray
    vectors: Mapping[str, np.ndarray]
    engine_version: str
    netlist_sha256: str
    wall_s: float
    log: str = field(repr=False)

    @property
    def points(self) -> int:
        return int(self.frequency.size)


def run_ac(netlist: str, vectors: Sequence[str], points: int, *, simulator: Simulator | None = None,
           timeout: float = 600.0) -> AcResult:
    """Run lcchain's AC netlist in ngspice (batch) and return its complex vectors.

    A netlist of several ``.ac`` cards (a sweep in segments) gives every plot's frequencies, in ascending order;
    ``points`` counts them all.

    Raises
    ------
    SimulationError
        ngspice failed, timed out, or its output is not the analysis asked for.
    """
    if not isinstance(netlist, str) or ".ac " not in netlist:
        raise ParameterError("netlist", type(netlist).__name__, "an AC netlist written by lcchain")
    names = [canonical_vector_name(v) for v in vectors]
    points = integer("points", points, at_least=1)
    timeout = real("timeout", timeout, above=0.0, unit="seconds")
    simulator = simulator if simulator is not None else find_simulator("batch")
    if simulator.engine != "ngspice" or simulator.backend != "batch":
        raise ParameterError("simulator", f"{simulator.engine} {simulator.backend}", "ngspice's batch transport "
                             "(the AC analysis runs in ngspice only)")
    with _placement(simulator, False, None) as place:
        columns, log, wall = _run_batch(netlist, simulator, timeout, 0.0, None, place, None, plot="ac", joined=True)

    def fail(reason: str) -> SimulationError:
        return SimulationError(reason, useful_output(log))

    if fatal_lines(log):
        raise SimulationError(failure_reason(log, ""), useful_output(log))
    if "frequency" not in columns:
        raise fail("ngspice returned no frequency vector")
    frequency = columns["frequency"].real  # ngspice leaves the imaginary part undefined
    if frequency.size != points:
        raise fail(f"ngspice returned {frequency.size} frequencies, not the {points} asked for")
    order = np.argsort(frequency, kind="stable")  # several .ac cards: ngspice runs them in its own order
    frequency = np.ascontiguousarray(frequency[order])
    if np.any(np.diff(frequency) <= 0):
        raise fail("ngspice returned a frequency twice (overlapping .ac cards)")
    found = {}
    for name in names:
        if name not in columns:
            raise fail(f"ngspice saved no vector {name!r}")
        values = np.ascontiguousarray(columns[name][order])
        if not np.all(np.isfinite(values)):
            raise fail(f"the vector {name!r} holds a value that is not finite (a frequency at a pole?)")
        found[name] = values
    return AcResult(frequency, FrozenMap(found), simulator.version,
                    hashlib.sha256(netlist.encode("utf-8")).hexdigest(), wall, trim_log(log))
