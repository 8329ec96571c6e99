"""The circuit's exact phasor response to its voltage sources: a sparse modified nodal analysis at each frequency.

What :class:`lcchain.circuit.exact.CircuitTheory` does not give: the current through a voltage source (a two-port's
port current, which a coil's self-capacitance makes other than its coil's).  Unknowns: every node's voltage but
ground's, every coil's current (from its node ``a`` to ``b``) and every source's current (into its ``+`` node,
through it, out of its ``-`` node: ngspice's ``i(vname)``)::

    KCL at every node:    sum of the currents leaving it = 0   (R: G dv, C: s C dv, coils and sources: their own)
    every coil:           v(a) - v(b) - s L i - s sum_k M i_k = 0      (K elements: M = k sqrt(L_1 L_2))
    every source:         v(+) - v(-) = its AC volts

one sparse LU factor a frequency: the ladder's bands keep it O(n).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import scipy  # its submodules load on first use

from ..core.errors import ParameterError
from .elements import GROUND, Element, Source

__all__ = ["source_currents"]


def source_currents(elements: Sequence[Element], sources: Sequence[Source], frequency: np.ndarray) -> np.ndarray:
    """The phasor current through each source (A, ngspice's ``i(name)``) at ``frequency`` (Hz): shape
    (len(sources), len(frequency)).

    Raises
    ------
    ParameterError
        An element that is not R, L, C or K, a K naming no coil, or a frequency at which the circuit has no
        unique solution (a pole on the axis).
    """
    nodes = sorted(({node for e in elements if e.kind != "K" for node in (e.a, e.b)}
                    | {node for _, a, b, _ in sources for node in (a, b)}) - {GROUND})
    index = {node: k for k, node in enumerate(nodes)}
    coils = [e for e in elements if e.kind == "L"]
    coil_index = {e.name.lower(): len(nodes) + k for k, e in enumerate(coils)}
    first_source = len(nodes) + len(coils)
    size = first_source + len(sources)
    fixed: dict[tuple[int, int], float] = {}  # the frequency's coefficient 0: conductances, incidences
    slope: dict[tuple[int, int], float] = {}  # its coefficient s: capacitances, inductances

    def add(table: dict[tuple[int, int], float], row: int | None, column: int | None, value: float) -> None:
        if row is not None and column is not None:
            table[row, column] = table.get((row, column), 0.0) + value

    def stamp(table: dict[tuple[int, int], float], a: str, b: str, value: float) -> None:
        ia, ib = index.get(a), index.get(b)
        add(table, ia, ia, value)
        add(table, ib, ib, value)
        add(table, ia, ib, -value)
        add(table, ib, ia, -value)

    def branch(row: int, a: str, b: str) -> None:  # a branch current from a to b: KCL and its voltage
        ia, ib = index.get(a), index.get(b)
        add(fixed, ia, row, 1.0)
        add(fixed, ib, row, -1.0)
        add(fixed, row, ia, 1.0)
        add(fixed, row, ib, -1.0)

    for element in elements:
        if element.kind == "R":
            stamp(fixed, element.a, element.b, 1.0 / element.value)
        elif element.kind == "C":
            stamp(slope, element.a, element.b, element.value)
        elif element.kind == "L":
            row = coil_index[element.name.lower()]
            branch(row, element.a, element.b)
            add(slope, row, row, -element.value)
        elif element.kind == "K":
            first, second = (coil_index.get(name.lower()) for name in (element.a, element.b))
            if first is None or second is None:
                raise ParameterError("elements", element.name, "a K element coupling two coils of the circuit")
            mutual = element.value * math.sqrt(coils[first - len(nodes)].value * coils[second - len(nodes)].value)
            add(slope, first, second, -mutual)
            add(slope, second, first, -mutual)
        else:
            raise ParameterError("elements", element.name, "R, L, C and K elements (the sources given apart)")
    rhs = np.zeros(size, dtype=complex)
    for k, (_, a, b, volts) in enumerate(sources):
        branch(first_source + k, a, b)
        rhs[first_source + k] = volts

    def matrix(table: dict[tuple[int, int], float]) -> scipy.sparse.csc_array:
        rows, columns = zip(*table, strict=True) if table else ((), ())
        return scipy.sparse.csc_array((list(table.values()), (rows, columns)), shape=(size, size), dtype=complex)

    G, S = matrix(fixed), matrix(slope)
    out = np.empty((len(sources), np.size(frequency)), dtype=complex)
    for j, hertz in enumerate(np.asarray(frequency, dtype=float).ravel()):
        try:
            solved = scipy.sparse.linalg.splu(G + 2j * math.pi * hertz * S).solve(rhs)
        except RuntimeError:  # singular: a pole on the axis at this frequency
            raise ParameterError("frequency", hertz, "a frequency at which the circuit's phasors are unique (not one "
                                 "of its resonances)") from None
        out[:, j] = solved[first_source:]
    return out
