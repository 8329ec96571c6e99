"""A netlist lcchain wrote, as a PySpice ``Circuit``, for PySpice users to embed.

PySpice is imported when :func:`circuit_from_netlist` is called, never by
``import lcchain`` (and it is an optional extra: ``pip install
'lcchain[shared]'``).  PySpice's own parser cannot read an inductor's
``IC=``, so this reads the element lines of :func:`lcchain.circuit.netlist.netlist_text`
(L, C and R with full-precision values and ``IC=``, the ``K`` lines of coupled
coils, the gaussian B-source and the rect PWL source) and builds the same circuit element by element: same
names, nodes and values.  The analysis is left to the caller, e.g.::

    from lcchain.circuit.netlist import netlist_text, SimulationOptions
    from lcchain.circuit.ladder import Ladder
    circuit = circuit_from_netlist(netlist_text(Ladder(chain), SimulationOptions(dt=0.05, tstop=30)))
    simulator = circuit.simulator()
    analysis = simulator.transient(step_time=..., end_time=..., use_initial_condition=True)

(lcchain itself runs ngspice through :mod:`lcchain.spice.ngspice.runner`, which avoids
PySpice's high-level simulator: it leaks memory per run with ngspice 39.)
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from ..core.errors import ExtraMissingError, ParameterError
from .text import netlist_lines

if TYPE_CHECKING:  # PySpice is optional (the shared extra), and has no annotations of its own
    from PySpice.Spice.Netlist import Circuit

__all__ = ["circuit_from_netlist"]

_TWO_TERMINAL = re.compile(r"^([LCR])(\S+)\s+(\S+)\s+(\S+)\s+(\S+)(?:\s+IC=(\S+))?$", re.IGNORECASE)
_COUPLING = re.compile(r"^K(\S+)\s+(L\S+)\s+(L\S+)\s+(\S+)$", re.IGNORECASE)
_B_SOURCE = re.compile(r"^B(\S+)\s+(\S+)\s+(\S+)\s+V=(.+)$", re.IGNORECASE)
_PWL = re.compile(r"^V(\S+)\s+(\S+)\s+(\S+)\s+PWL\((.*)\)$", re.IGNORECASE)


def circuit_from_netlist(text: str) -> Circuit:
    """Build the netlist's elements as a ``PySpice.Spice.Netlist.Circuit``.

    Parameters
    ----------
    text : str
        A netlist written by :func:`lcchain.circuit.netlist.netlist_text`
        (its first line is the title; comments and dot-commands are skipped).

    Returns
    -------
    PySpice.Spice.Netlist.Circuit

    Raises
    ------
    ExtraMissingError
        PySpice is not installed.
    ParameterError
        A line that is none of lcchain's elements.
    """
    try:
        from PySpice.Spice.Netlist import Circuit
    except ImportError:
        raise ExtraMissingError("PySpice", "shared", "the shared backend") from None
    lines = netlist_lines(text)
    circuit = Circuit(lines[0] or "lcchain")

    def node(name: str) -> object:  # a node name, or the circuit's ground
        return circuit.gnd if name == "0" else name

    for number, line in enumerate(lines[1:], start=2):
        stripped = line.strip()
        if not stripped or stripped[0] in "*.":
            continue
        element = _TWO_TERMINAL.match(stripped)
        if element:
            kind, name, a, b, value, ic = element.groups()
            extra = {"initial_condition": float(ic)} if ic is not None else {}
            factory = {"L": circuit.L, "C": circuit.C, "R": circuit.R}[kind.upper()]
            factory(name, node(a), node(b), float(value), **extra)
            continue
        coupling = _COUPLING.match(stripped)
        if coupling:
            name, first, second, k = coupling.groups()
            circuit.K(name, first, second, float(k))
            continue
        source = _B_SOURCE.match(stripped)
        if source:
            name, a, b, expression = source.groups()
            circuit.BehavioralSource(name, node(a), node(b), voltage_expression=expression)
            continue
        pwl = _PWL.match(stripped)
        if pwl:
            name, a, b, body = pwl.groups()
            numbers = [float(v) for v in body.split()]
            circuit.PieceWiseLinearVoltageSource(name, node(a), node(b), values=list(zip(numbers[::2], numbers[1::2],
                                                                                          strict=True)))
            continue
        raise ParameterError(f"netlist line {number}", stripped,
                             "an element line lcchain writes (L, C, R, K, B, V PWL)")
    return circuit
