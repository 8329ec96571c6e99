"""The circuit's own exact theory (issue 30, item 1): built from the elements the netlist is written from.

Checked two ways, neither of them lcchain's circuit code:
* against an independent solution written here: the netlist *text* parsed into nodal matrices, a series R
  folded into its coil's branch, and ``scipy.linalg.expm`` of the state matrix, at small N;
* against the chain theory (:func:`lcchain.linear_response`) wherever it applies: every case, walls,
  coupling, proportional losses, tolerance samples, kick and displacement, to 1e-12.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers.state_space import dop853_currents, expm_currents
from helpers.tolerances import (
    ATOL_CIRCUIT_AGAINST_CHAIN,
    MAX_FINE_CIRCUIT_RUN_ERROR,
    MAX_GROUNDED_GROUP_ERROR,
    RTOL_CIRCUIT_AGAINST_DOP853,
    RTOL_CIRCUIT_AGAINST_EXPM,
    RTOL_FLUX_SHARING,
    RTOL_SPLIT_COIL,
)

import lcchain
from lcchain.circuit.effects import (
    CapacitorESL,
    CapacitorESR,
    CoilCapacitance,
    CoilResistance,
    Effect,
    Losses,
    Tolerance,
    with_walls,
)
from lcchain.circuit.elements import RECT_FALL, Element, ladder_elements, ladder_pulse
from lcchain.circuit.exact import CircuitTheory
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import Drive, SimulationOptions, netlist_text
from lcchain.core.errors import ParameterError
from lcchain.spice.engines import find_engine, run_engine
from lcchain.spice.job import RunJob
from lcchain.theory.response import linear_response

L0, C0, I0 = 1e-5, 1e-8, 1e-3


def _chain(case: str, N: int, walls: float | None = None, coupling: float = 0.0) -> lcchain.Chain:
    chain = lcchain.chain_for_case(case, N)
    if walls is not None:
        chain = with_walls(chain, walls)
    return chain.with_coupling(coupling) if coupling else chain


def _scale(ladder: Ladder) -> float:
    return ladder.time_unit


def _coil_capacitance(elements: tuple[Element, ...], ratio: float) -> tuple[Element, ...]:
    """A capacitor ratio C0 across every coil: no chain any more."""
    across = [Element(f"CP{e.name[1:]}", e.a, e.b, ratio * C0) for e in elements if e.kind == "L"]
    return elements + tuple(across)


SMALL = {
    "two-mass kick": (_chain("two-mass", 6), (), "kick"),
    "perfect displacement": (_chain("perfect", 5), (), "displacement"),
    "losses Q=20": (_chain("two-mass", 6), (Losses(20.0),), "kick"),
    "coupling 0.2": (_chain("one-mass", 5, coupling=0.2), (), "kick"),
    "coupling and losses": (_chain("two-mass", 5, coupling=0.25), (Losses(8.0),), "kick"),
    "walls and losses": (_chain("uniform-free", 5, walls=0.7), (Losses(5.0),), "displacement"),
}


@pytest.mark.parametrize("name", SMALL)
def test_the_circuit_theory_matches_the_matrix_exponential(name: str) -> None:
    chain, effects, drive = SMALL[name]
    ladder = Ladder(chain, L0, C0)
    elements = ladder_elements(ladder, effects, kick=I0 if drive == "kick" else None,
                               charge=I0 * ladder.time_unit if drive == "displacement" else None)
    times = np.linspace(0.0, 4.0 * chain.N, 9) * ladder.time_unit
    probes = ["L1", f"L{chain.N}"]
    reference = expm_currents([e.card() for e in elements], times, probes)
    got = CircuitTheory(elements).currents(times, probes)
    assert np.max(np.abs(got - reference)) < RTOL_CIRCUIT_AGAINST_EXPM * I0


@pytest.mark.parametrize("ratio", [0.05, 0.5])
@pytest.mark.parametrize("losses", [None, 30.0])
def test_a_coil_capacitance_is_followed_exactly(ratio: float, losses: float | None) -> None:
    # Capacitors across the coils make the nodal capacitance matrix non-diagonal: no chain can say it.
    ladder = Ladder(_chain("two-mass", 5), L0, C0)
    effects = (Losses(losses),) if losses else ()
    elements = _coil_capacitance(ladder_elements(ladder, effects, kick=I0), ratio)
    times = np.linspace(0.0, 20.0, 7) * ladder.time_unit
    reference = expm_currents([e.card() for e in elements], times, ["L1", "L5"])
    theory = CircuitTheory(elements)
    assert theory.lossless is (losses is None)
    assert np.max(np.abs(theory.currents(times, ["L1", "L5"]) - reference)) < RTOL_CIRCUIT_AGAINST_EXPM * I0


CHAINS = {
    "two-mass": lambda: _chain("two-mass", 24),
    "one-mass": lambda: _chain("one-mass", 17),
    "perfect": lambda: _chain("perfect", 16),
    "uniform-free": lambda: _chain("uniform-free", 12),
    "walls": lambda: _chain("two-mass", 20, walls=1.3),
    "coupling": lambda: _chain("two-mass", 15, coupling=0.3),
    "tolerance sample": lambda: Tolerance(L=0.05, C=0.05, samples=3, seed=4).realise(
        _chain("perfect", 20), L0, C0),
}


@pytest.mark.parametrize("Q", [None, 40.0], ids=["lossless", "Q=40"])
@pytest.mark.parametrize("drive", ["kick", "displacement"])
@pytest.mark.parametrize("name", CHAINS)
def test_the_circuit_theory_is_the_chain_theory_where_both_apply(name: str, drive: str, Q: float | None) -> None:
    chain = CHAINS[name]()
    if Q is not None and chain.coupled:
        pytest.skip("the chain theory has no losses with coupled coils (the circuit theory has: tested above)")
    ladder = Ladder(chain, L0, C0)
    unit = ladder.time_unit
    elements = ladder_elements(ladder, (Losses(Q),) if Q else (), kick=I0 if drive == "kick" else None,
                               charge=I0 * unit if drive == "displacement" else None)
    t = np.linspace(0.0, 3.0 * chain.N, 1501)
    reference = linear_response(chain, t, excitation="kick" if drive == "kick" else "displacement", Q=Q)
    theory = CircuitTheory(elements)
    probes = ["L1", f"L{chain.N}"]
    if drive == "kick":
        got = theory.currents(t * unit, probes) / I0
    else:
        got = theory.charges(t * unit, probes, [I0 * unit, 0.0]) / (I0 * unit)
    assert np.max(np.abs(got - reference)) < ATOL_CIRCUIT_AGAINST_CHAIN


def test_coils_in_series_are_one_coil() -> None:
    # A node joined by two coils alone carries no state: Kirchhoff's law ties their currents.
    ladder = Ladder(_chain("two-mass", 8), L0, C0)
    elements = list(ladder_elements(ladder, kick=I0))
    first = elements[0]
    split = [Element("L1", first.a, "x", 0.3 * first.value, first.ic),
             Element("L1b", "x", first.b, 0.7 * first.value, first.ic)]
    times = np.linspace(0.0, 30.0, 50) * ladder.time_unit
    whole = CircuitTheory(elements).currents(times, ["L1", "L8"])
    halves = CircuitTheory(split + elements[1:])
    assert halves.states == CircuitTheory(elements).states
    assert np.max(np.abs(halves.currents(times, ["L1", "L8"]) - whole)) < RTOL_SPLIT_COIL * I0
    assert np.max(np.abs(halves.currents(times, ["L1b"]) - whole[:1])) < RTOL_SPLIT_COIL * I0


@pytest.mark.parametrize("elements, said", [
    ([Element("L1", "a", "0", 1e-5, 1.0), Element("L2", "a", "0", 1e-5), Element("K1", "L1", "L2", 1.0)],
     "K1"),
    ([Element("L1", "a", "0", 1e-5), Element("R1", "a", "0", 0.0)], "R1"),
    ([Element("L1", "a", "0", 1e-5), Element("C1", "a", "b", 1e-8, 1.0)], "a coil can carry current"),
    ([Element("L1", "a", "0", 1e-5), Element("V1", "a", "0", 1.0)], "V1"),
    ([Element("L1", "a", "0", 1e-5), Element("K1", "L1", "L9", 0.1)], "K1"),
])
def test_what_the_theory_cannot_follow_is_refused_naming_the_element(elements: list[Element], said: str) -> None:
    with pytest.raises(ParameterError) as caught:
        CircuitTheory(elements)
    assert said in str(caught.value) and "\n" not in str(caught.value)


@pytest.mark.parametrize("charged", ["C1", "C2"])
def test_capacitors_at_a_node_share_its_charge_at_once_as_under_uic(charged: str) -> None:
    """A capacitor's IC is its own voltage, and one without IC starts at 0 V, as SPICE's UIC starts them: at a node
    where both meet, the charge C_charged * 1 V is shared at once, v(0+) = C_charged / (C1 + C2), and the node then
    rings with the coil at omega = 1 / sqrt(L (C1 + C2)).  (The theory took the IC as the node's voltage, charging
    the other capacitor too: a displaced mass with its coil's self-capacitance was 4.8e-2 off ngspice.)"""
    L, C1, C2 = 1e-5, 1e-8, 3e-8
    elements = [Element("L1", "a", "0", L), Element("C1", "a", "0", C1, 1.0 if charged == "C1" else None),
                Element("C2", "0", "a", C2, -1.0 if charged == "C2" else None)]
    v0 = (C1 if charged == "C1" else C2) / (C1 + C2)
    omega = 1.0 / np.sqrt(L * (C1 + C2))
    t = np.linspace(0.0, 4 * np.pi / omega, 9)
    current = CircuitTheory(elements).currents(t, ["L1"])[0]
    expected = v0 * np.sqrt((C1 + C2) / L) * np.sin(omega * t)
    assert np.allclose(current, expected, rtol=0.0, atol=RTOL_FLUX_SHARING * np.max(np.abs(expected)))


def test_initial_currents_that_break_kirchhoffs_law_redistribute_conserving_flux() -> None:
    # Two coils in series, only the first carrying a current: at once both carry L1 I0 / (L1 + L2).
    elements = [Element("L1", "0", "x", 1e-5, 1e-3), Element("L2", "x", "n", 3e-5), Element("C1", "n", "0", 1e-8)]
    currents = CircuitTheory(elements).currents(np.array([0.0]), ["L1", "L2"])
    assert np.allclose(currents[:, 0], 0.25e-3, rtol=RTOL_FLUX_SHARING)


@pytest.mark.parametrize("shape, width", [("gaussian", 0.3), ("gaussian", 2.0), ("rect", 0.5)])
@pytest.mark.parametrize("name", ["two-mass", "walls"])
@pytest.mark.parametrize("Q", [None, 25.0], ids=["lossless", "Q=25"])
def test_a_pulse_drive_is_the_chain_theory_where_both_apply(name: str, shape: str, width: float,
                                                             Q: float | None) -> None:
    chain = CHAINS[name]()
    ladder = Ladder(chain, L0, C0)
    pulse = ladder_pulse(ladder, "gaussian" if shape == "gaussian" else "rect", width, I0)
    theory = CircuitTheory(ladder_elements(ladder, (Losses(Q),) if Q else (), source=True) + (pulse,))
    t = np.concatenate((np.linspace(0.0, 20.0 * width, 301), np.linspace(0.0, 3.0 * chain.N, 1201)))
    got = theory.currents(t * ladder.time_unit, ["L1", f"L{chain.N}"]) / I0
    reference = linear_response(chain, t, excitation="pulse", pulse=("gaussian" if shape == "gaussian" else "rect",
                                                                      width), Q=Q)
    # the netlist's rect falls in RECT_FALL of its width, which the circuit theory follows and the chain's ignores
    allowed = 1e-12 + (RECT_FALL if shape == "rect" else 0.0)
    assert np.max(np.abs(got - reference)) < allowed


@pytest.mark.parametrize("losses", [None, 15.0])
def test_a_pulse_through_coil_capacitance_matches_dop853(losses: float | None) -> None:
    ladder = Ladder(_chain("two-mass", 4), L0, C0)
    pulse = ladder_pulse(ladder, "gaussian", 0.4, I0)
    elements = _coil_capacitance(ladder_elements(ladder, (Losses(losses),) if losses else (), source=True), 0.1)
    times = np.linspace(0.0, 15.0, 31) * ladder.time_unit
    reference = dop853_currents([e.card() for e in elements] + [pulse.card()], pulse, times, ["L1", "L4"])
    got = CircuitTheory((*elements, pulse)).currents(times, ["L1", "L4"])
    assert np.max(np.abs(got - reference)) < RTOL_CIRCUIT_AGAINST_DOP853 * I0


@pytest.mark.parametrize("effects", [(CoilCapacitance(0.05), CapacitorESR(0.02)),
                                     (CoilCapacitance(0.2), CoilResistance(0.01), CapacitorESR(0.02),
                                      CapacitorESL(0.1))], ids=["ESR", "all four"])
def test_a_floating_group_of_capacitors_is_the_limit_of_grounded_ones(effects: tuple[Effect, ...]) -> None:
    # With walls, every coil's self-capacitance joins the rail nodes n0 ... nN in a group with no capacitor to
    # ground (the walls' capacitors sit behind their ESR): its common voltage is no state.  The independent
    # reference cannot take a singular capacitance matrix, so it grounds each rail node through eps C0: its
    # answer moves as eps (a fast RC mode and a small shift) and converges to the circuit theory's.
    ladder = Ladder(_chain("two-mass", 5, walls=0.3), L0, C0)
    elements = ladder_elements(ladder, effects, kick=I0)
    times = np.linspace(0.0, 20.0, 9) * ladder.time_unit
    got = CircuitTheory(elements).currents(times, ["L1", "L5"])
    rails = sorted({node for e in elements for node in (e.a, e.b) if node.startswith("n")})
    errors = []
    for eps in (1e-5, 1e-6):
        grounded = [f"CE{k} {node} 0 {eps * C0!r}" for k, node in enumerate(rails)]
        reference = expm_currents([e.card() for e in elements] + grounded, times, ["L1", "L5"])
        errors.append(float(np.max(np.abs(got - reference))) / I0)
    assert errors[1] < MAX_GROUNDED_GROUP_ERROR
    assert 7.0 < errors[0] / errors[1] < 13.0  # first order in eps: towards the circuit theory, not elsewhere


# --------------------------------------------------------------------------- real parts, in ngspice and gnucap

REAL = {
    "coil capacitance": (CoilCapacitance(0.05),),
    "coil resistance": (CoilResistance(0.02),),
    "capacitor ESR": (CapacitorESR(0.03),),
    "capacitor ESL": (CapacitorESL(0.02),),
    # a coil's capacitor and a capacitor's ESL make a loop that rings at 1/sqrt(ratio L): 7 here, slow enough
    # for the trapezoidal rule's phase error to stay small over the run at these steps
    "all four, coupled": (CoilCapacitance(0.2), CoilResistance(0.01), CapacitorESR(0.02), CapacitorESL(0.1)),
}


def _simulated_error(engine: str, effects: tuple[Effect, ...], dt: float, coupling: float) -> float:
    ladder = Ladder(_chain("two-mass", 8, coupling=coupling), L0, C0)
    options = SimulationOptions(dt=dt, tstop=16.0)
    netlist = netlist_text(ladder, options, Drive(I0=I0), effects=effects)
    result = run_engine(RunJob(netlist, ["i(l1)", "i(l8)"], 16.0 * ladder.time_unit, foreign=False), find_engine(engine))
    theory = CircuitTheory(ladder_elements(ladder, effects, kick=I0)).currents(result.time, ["L1", "L8"])
    return max(float(np.max(np.abs(result.vectors[k] - theory[j]))) for j, k in enumerate(("i(l1)", "i(l8)"))) / I0


@pytest.mark.ngspice
@pytest.mark.parametrize("engine", ["ngspice", pytest.param("gnucap", marks=pytest.mark.gnucap)])
@pytest.mark.parametrize("name", REAL)
def test_the_simulators_converge_to_the_circuit_theory_of_real_parts(engine: str, name: str) -> None:
    # The trapezoidal rule's error falls as dt^2 towards the circuit's own exact response: halving the step
    # divides it by about four, and the finer run agrees to well under a percent of I0.
    effects = REAL[name]
    coupling = 0.2 if "coupled" in name else 0.0
    coarse, fine = (_simulated_error(engine, effects, dt, coupling) for dt in (0.02, 0.01))
    assert fine < MAX_FINE_CIRCUIT_RUN_ERROR
    assert 2.8 < coarse / fine < 5.5, (coarse, fine)


def test_every_place_an_effect_adds_elements_is_known_to_the_planner() -> None:
    # The planner skips its element-by-element check when no effect overrides an ELEMENT_HOOKS method: a new place
    # ladder_elements asks effects for elements must be listed there, or an effect using it would be compared with
    # the chain's theory instead of the circuit's.
    import inspect
    import re

    from lcchain.circuit import elements

    asked = set(re.findall(r"\bpart\.(\w+)\(", inspect.getsource(elements)))
    assert asked == set(elements.ELEMENT_HOOKS)
