"""The LC ladder as a PySpice ``Circuit``, for PySpice users to embed.

PySpice is imported when :func:`ladder_circuit` is called, never by
``import lcchain``.  The elements, node names and values are those of
:func:`lcchain.netlist.netlist_text` (same mapping, same full-precision
floats); the analysis is left to the caller, e.g.::

    circuit = ladder_circuit(Ladder(chain, 10e-6, 10e-9))
    simulator = circuit.simulator()           # PySpice's own path
    analysis = simulator.transient(step_time=..., end_time=..., use_initial_condition=True)

(lcchain itself runs ngspice through :mod:`lcchain.ngspice`, which avoids
PySpice's high-level simulator: it leaks memory per run with ngspice 39.)
"""

from __future__ import annotations

from .errors import ParameterError
from .netlist import Ladder, check_user_text
from .types import EXCITATIONS, Excitation

__all__ = ["ladder_circuit"]


def ladder_circuit(ladder: Ladder, *, excitation: Excitation = "kick", I0: float = 1e-3,
                   title: str = "lcchain LC ladder"):
    """Build the ladder as a ``PySpice.Spice.Netlist.Circuit``.

    Parameters
    ----------
    ladder : Ladder
        Chain and bulk values L0 (H), C0 (F).
    excitation : {"kick", "displacement"}
        Initial condition: current I0 in L_1, or charge I0 sqrt(L0 C0) in loop 1.
    I0 : float
        Ampere.
    title : str
        One line (validated as for netlists).

    Returns
    -------
    PySpice.Spice.Netlist.Circuit
    """
    from PySpice.Spice.Netlist import Circuit

    if excitation not in EXCITATIONS:
        raise ParameterError("excitation", excitation, " | ".join(EXCITATIONS))
    circuit = Circuit(check_user_text("title", title))
    chain = ladder.chain
    N = chain.N
    L = ladder.inductances()
    C = ladder.capacitances()
    Q0 = I0 * ladder.time_unit
    for i in range(1, N + 1):
        extra = {"initial_condition": float(I0)} if (excitation == "kick" and i == 1) else {}
        circuit.L(str(i), ladder.node(i - 1), ladder.node(i), float(L[i - 1]), **extra)
        if i < N:
            extra = {"initial_condition": float(Q0 / C[i])} if (excitation == "displacement" and i == 1) else {}
            circuit.C(f"{i}_{i + 1}", f"n{i}", circuit.gnd, float(C[i]), **extra)
    for wall in (0, N):
        if C[wall] is not None:
            extra = {"initial_condition": float(-Q0 / C[0])} if (excitation == "displacement" and wall == 0) else {}
            circuit.C(f"{wall}_{wall + 1}", ladder.node(wall), circuit.gnd, float(C[wall]), **extra)
    return circuit
