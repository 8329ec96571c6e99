"""The circuit's exact admittances (issue 30, item 5): I_Lk(s) / V(s) from a unit source in series with loop 1.

:meth:`lcchain.circuit.exact.CircuitTheory.admittances` gives them as poles and residues.  Checked against an
independent solution written here: the element cards parsed into modified nodal equations
(G + s C, coils' branch rows s L, a ``K`` card's s M, the source's row) solved at complex frequencies, for every
real part alone and together, lossless and lossy, coupled, at small N.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers.tolerances import RTOL_CIRCUIT_ADMITTANCE

import lcchain
from lcchain.circuit.effects import (
    CapacitorESL,
    CapacitorESR,
    CoilCapacitance,
    CoilResistance,
    Effect,
    Losses,
    with_walls,
)
from lcchain.circuit.exact import CircuitTheory
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import ac_circuit_elements
from lcchain.core.errors import ParameterError
from lcchain.theory.chain import Chain

L0, C0 = 1e-5, 1e-8


def nodal_admittances(cards: list[str], s: complex, probes: list[str]) -> np.ndarray:
    """I(probe) / V of the cards' voltage source at complex frequency s (rad/s): modified nodal analysis of the
    cards' text (R, L, C, K, one V source), independent of lcchain's circuit code."""
    rows = [card.split() for card in cards]
    nodes: list[str] = []
    for r in rows:
        if r[0][0] in "RLCVrlcv":
            nodes += [n for n in r[1:3] if n != "0" and n not in nodes]
    branches = [r for r in rows if r[0][0] in "LlVv"]
    n, m = len(nodes), len(branches)
    index = {node: k for k, node in enumerate(nodes)}
    branch = {r[0].lower(): n + k for k, r in enumerate(branches)}
    Y = np.zeros((n + m, n + m), dtype=complex)
    rhs = np.zeros(n + m, dtype=complex)
    inductance = {r[0].lower(): float(r[3]) for r in rows if r[0][0] in "Ll"}
    for r in rows:
        kind, ends = r[0][0].upper(), ((index.get(r[1]), 1.0), (index.get(r[2]), -1.0))
        if kind in "RC":
            y = 1.0 / float(r[3]) if kind == "R" else s * float(r[3])
            for p, sp in ends:
                for q, sq in ends:
                    if p is not None and q is not None:
                        Y[p, q] += sp * sq * y
        elif kind in "LV":
            b = branch[r[0].lower()]
            for p, sp in ends:
                if p is not None:
                    Y[p, b] += sp
                    Y[b, p] += sp
            if kind == "L":
                Y[b, b] -= s * float(r[3])
            else:
                rhs[b] = 1.0
        elif kind == "K":
            p, q = branch[r[1].lower()], branch[r[2].lower()]
            mutual = float(r[3]) * np.sqrt(inductance[r[1].lower()] * inductance[r[2].lower()])
            Y[p, q] -= s * mutual
            Y[q, p] -= s * mutual
    x = np.linalg.solve(Y, rhs)
    return np.array([x[branch[p.lower()]] for p in probes])


def _chain(case: str, N: int, *, walls: float | None = None, coupling: float = 0.0) -> Chain:
    chain = lcchain.chain_for_case(case, N)
    chain = with_walls(chain, walls) if walls is not None else chain
    return chain.with_coupling(coupling) if coupling else chain


PARTS: dict[str, tuple[Chain, tuple[Effect, ...]]] = {
    "coil capacitance": (_chain("two-mass", 5), (CoilCapacitance(0.05),)),
    "coil resistance": (_chain("two-mass", 5), (CoilResistance(0.05),)),
    "capacitor ESR": (_chain("one-mass", 5, walls=0.8), (CapacitorESR(0.05),)),
    "capacitor ESL": (_chain("two-mass", 5), (CapacitorESL(0.05),)),
    "self-capacitance and ESL": (_chain("uniform-free", 4), (CoilCapacitance(0.1), CapacitorESL(0.1))),
    "coupled, every part, losses": (_chain("one-mass", 4, coupling=0.2),
                                    (CoilCapacitance(0.05), CoilResistance(0.03), CapacitorESR(0.02),
                                     CapacitorESL(0.04), Losses(30.0))),
    "coupled with losses": (_chain("two-mass", 4, coupling=0.25), (Losses(8.0),)),
}


@pytest.mark.parametrize("name", PARTS)
def test_the_admittances_are_the_nodal_equations(name: str) -> None:
    chain, effects = PARTS[name]
    ladder = Ladder(chain, L0, C0)
    elements = ac_circuit_elements(ladder, effects)
    theory = CircuitTheory(elements)
    probes = ["L1", f"L{chain.N}"]
    poles, residues, direct = theory.admittances(probes)
    cards = [e.card() for e in elements[:-1]] + [f"V1 s1 {ladder.node(0)} DC 0 AC 1"]
    tau = ladder.time_unit
    for s in np.array([0.3 + 1.1j, 0.05 + 0.7j, 0.2 + 2.0j, 0.01 + 1.9j, 3.0 + 0.5j, 0.1 + 7.0j]) / tau:
        expected = nodal_admittances(cards, s, probes)
        got = direct + (residues / (s - poles)).sum(axis=1)
        # relative to the larger of the two: far above the band I_N / V is I_1 / V's cancelling remainder
        assert np.max(np.abs(got - expected)) < RTOL_CIRCUIT_ADMITTANCE * np.max(np.abs(expected)), s * tau
    # a real circuit: conjugate poles carry conjugate residues, and a coil carries nothing at infinite frequency
    upper = poles.imag > 0
    for p, r in zip(poles[upper], residues[:, upper].T, strict=True):
        partner = np.argmin(np.abs(poles - np.conj(p)))
        assert np.allclose(residues[:, partner], np.conj(r), rtol=RTOL_CIRCUIT_ADMITTANCE,
                           atol=RTOL_CIRCUIT_ADMITTANCE * np.max(np.abs(residues)))
    assert np.all(np.abs(direct) * ladder.impedance < RTOL_CIRCUIT_ADMITTANCE)
    assert theory.lossless == (not any(isinstance(e, (CoilResistance, CapacitorESR, Losses)) for e in effects))


def test_a_circuit_without_a_source_has_no_admittances() -> None:
    from lcchain.circuit.elements import ladder_elements

    ladder = Ladder(_chain("two-mass", 3), L0, C0)
    with pytest.raises(ParameterError, match="source"):
        CircuitTheory(ladder_elements(ladder, (CoilCapacitance(0.1),), kick=1e-3)).admittances(["L1"])
