"""The circuit's exact theory on hard cases (issue 30, item 6): accurate where it accepts, refused where float64 is not.

Hard cases: a coil self-resonance 1.001x the band top (omega = 2), a capacitor ESL resonating at it, Q from 1 to
1e6, coupling 0.999 of its limit, damping within rounding of critical, N = 2000 near the coupling limit.  The
references are not lcchain's circuit code: ``expm`` of the state matrix parsed from the netlist cards
(helpers/state_space.py) and the uniform ladder between walls in closed form (helpers/uniform.py), which stays exact
through critical damping.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from helpers.state_space import expm_currents
from helpers.tolerances import ATOL_HARD_ACCEPTED, ATOL_HARD_WELL_CONDITIONED
from helpers.uniform import uniform_currents

import lcchain
from lcchain.circuit.effects import CapacitorESL, CapacitorESR, CoilCapacitance, CoilResistance, Effect, Losses
from lcchain.circuit.elements import Element, ladder_elements
from lcchain.circuit.exact import CircuitTheory
from lcchain.circuit.ladder import Ladder
from lcchain.core.errors import ParameterError
from lcchain.core.limits import MAX_PARASITIC
from lcchain.runs.request import AC, Request, Transient
from lcchain.runs.request.plan import plan_request
from lcchain.theory.chain import MAX_COUPLING
from lcchain.theory.spectrum import normal_modes

L0, C0, I0 = 1e-5, 1e-8, 1e-3
#: A coil capacitance r C0 whose self-resonance 1/sqrt(r) is 1.001x the band top 2.
R_NEAR_TOP = 1.0 / (4.0 * 1.001 ** 2)
#: An ESL L L0 whose capacitor (C0) resonates at the band top: 1/sqrt(L) = 2.
ESL_AT_TOP = 0.25
K_NEAR_LIMIT = 0.999 * MAX_COUPLING


def _ladder(case: str, N: int, coupling: float = 0.0) -> Ladder:
    chain = lcchain.chain_for_case(case, N)
    return Ladder(chain.with_coupling(coupling) if coupling else chain, L0, C0)


def _theory_and_expm(ladder: Ladder, effects: tuple[Effect, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Every loop's current over I0 at 13 times over 4 N: the circuit theory's and expm's."""
    N = ladder.chain.N
    elements = ladder_elements(ladder, effects, kick=I0)
    times = np.linspace(0.0, 4.0 * N, 13) * ladder.time_unit
    probes = [f"L{j}" for j in range(1, N + 1)]
    reference = expm_currents([e.card() for e in elements], times, probes)
    return CircuitTheory(elements).currents(times, probes) / I0, reference / I0


EXPM_CASES = {
    "Q=1": ((Losses(1.0),), 0.0),
    "Q=1e3": ((Losses(1e3),), 0.0),
    "Q=1e6": ((Losses(1e6),), 0.0),
    "coupling 0.999 max": ((), K_NEAR_LIMIT),
    "coupling 0.999 max, Q=1": ((Losses(1.0),), K_NEAR_LIMIT),
    "self-resonance 1.001x band top": ((CoilCapacitance(R_NEAR_TOP),), 0.0),
    "self-resonance 1.001x band top, winding R": ((CoilCapacitance(R_NEAR_TOP), CoilResistance(1e-3)), 0.0),
    "self-resonance far above (r = 1e-5), Q=1e6": ((CoilCapacitance(1e-5), Losses(1e6)), 0.0),
}


#: The rest run in the slow suite (each expm reference takes about 0.5 s on a loaded machine).
FAST = ("Q=1", "Q=1e6", "coupling 0.999 max, Q=1", "self-resonance 1.001x band top, winding R")


@pytest.mark.parametrize("name", [n if n in FAST else pytest.param(n, marks=pytest.mark.slow) for n in EXPM_CASES])
def test_a_hard_case_is_the_matrix_exponential(name: str) -> None:
    effects, coupling = EXPM_CASES[name]
    got, reference = _theory_and_expm(_ladder("two-mass", 8, coupling), effects)
    assert np.max(np.abs(got - reference)) < ATOL_HARD_WELL_CONDITIONED


CLOSED_FORM_CASES = {
    "ESL at the band top": ((CapacitorESL(ESL_AT_TOP),), 0.0, {"esl": ESL_AT_TOP}),
    "ESL at the band top, ESR": ((CapacitorESL(ESL_AT_TOP), CapacitorESR(1e-6)), 0.0,
                                 {"esl": ESL_AT_TOP, "esr": 1e-6}),
    "ESL at the band top, every loss, coupling 0.999 max": (
        (CapacitorESL(ESL_AT_TOP), CapacitorESR(0.01), CoilResistance(0.02), Losses(1.0)), K_NEAR_LIMIT,
        {"esl": ESL_AT_TOP, "esr": 0.01, "coil_resistance": 0.02, "Q": 1.0}),
    "self-resonance 1.001x band top": ((CoilCapacitance(R_NEAR_TOP),), 0.0, {"coil_capacitance": R_NEAR_TOP}),
}


def _theory_and_closed_form(N: int, effects: tuple[Effect, ...], coupling: float, keywords: dict[str, float],
                            times: int) -> tuple[np.ndarray, np.ndarray]:
    ladder = _ladder("uniform-bounded", N, coupling)
    t = np.linspace(0.0, 3.0 * N, times)
    got = CircuitTheory(ladder_elements(ladder, effects, kick=I0)).currents(t * ladder.time_unit, ["L1", f"L{N}"])
    return got / I0, uniform_currents(N, t, [1, N], coupling=coupling, **keywords)


@pytest.mark.parametrize("name", CLOSED_FORM_CASES)
def test_a_hard_case_is_the_uniform_ladders_closed_form(name: str) -> None:
    # A capacitor's ESL leaves nodes with coils alone, which the expm reference cannot parse: the closed form can.
    effects, coupling, keywords = CLOSED_FORM_CASES[name]
    got, reference = _theory_and_closed_form(9, effects, coupling, keywords, 301)
    assert np.max(np.abs(got - reference)) < ATOL_HARD_WELL_CONDITIONED


def _critical_Q(chain: lcchain.Chain) -> float:
    """The Q that damps the chain's lowest moving mode critically: omega_1 = 1/(2 Q) (Losses: gamma = 1/(2Q))."""
    omega = normal_modes(chain).omega
    return float(1.0 / (2.0 * omega[omega > 0][0]))


@pytest.mark.parametrize("off", [pytest.param(1e-8, marks=pytest.mark.slow), 1e-11,
                                 pytest.param(-1e-11, marks=pytest.mark.slow)])
def test_damping_near_critical_is_accepted_and_accurate(off: float) -> None:
    # A pair of poles 1e-11 from coalescing: nearly parallel eigenvectors (cond(V) ~ 1e6), still within 1e-9.
    ladder = _ladder("two-mass", 8)
    got, reference = _theory_and_expm(ladder, (Losses(_critical_Q(ladder.chain) * (1 + off)),))
    assert np.max(np.abs(got - reference)) < ATOL_HARD_ACCEPTED


@pytest.mark.parametrize("case, N", [("two-mass", 8), ("uniform-free", 8), ("one-mass", 7)])
def test_damping_at_critical_is_refused_naming_the_resistors(case: str, N: int) -> None:
    # At critical damping the eigenvector matrix is (numerically) defective: the modal expansion would lose ~1e-9 .. 1e-8.
    ladder = _ladder(case, N)
    with pytest.raises(ParameterError) as caught:
        CircuitTheory(ladder_elements(ladder, (Losses(_critical_Q(ladder.chain)),), kick=I0))
    message = str(caught.value)
    assert caught.value.field == "R" and "critical" in message and "\n" not in message


def test_a_mode_lost_in_the_rounding_of_the_highest_is_refused() -> None:
    # Two separate tanks with omega^2 in the ratio 3e-14: float64 cannot tell the slow one from a zero mode.
    elements = [Element("L1", "a", "0", 1e-5, 1e-3), Element("C1", "a", "0", 1e-8),
                Element("L2", "b", "0", 1e-5), Element("C2", "b", "0", 1e-8 / 3e-14)]
    with pytest.raises(ParameterError) as caught:
        CircuitTheory(elements)
    assert caught.value.field == "circuit" and "zero mode" in str(caught.value) and "\n" not in str(caught.value)


@pytest.mark.slow
def test_the_longest_ladder_at_the_coupling_limit_keeps_its_lowest_modes() -> None:
    # N = 2000, k = (1 - 1e-9)/2: omega_1^2 / omega_max^2 = 3.8e-13.  A zero-mode threshold of 1e-12 of the highest
    # froze the lowest modes (5e-9 off); measured now 1.3e-10 .. 2e-10 (2 eps cond(L), cond(L) = 1.6e6).
    k = 0.5 * (1 - 1e-9)
    got, reference = _theory_and_closed_form(2000, (), k, {}, 1001)
    assert np.max(np.abs(got - reference)) < ATOL_HARD_ACCEPTED


@pytest.mark.slow
@pytest.mark.parametrize("name, effects, coupling, keywords", [
    ("Q=1", (Losses(1.0),), 0.0, {"Q": 1.0}),
    ("Q=1e6", (Losses(1e6),), 0.0, {"Q": 1e6}),
    ("ESL at the band top, ESR, coupling", (CapacitorESL(ESL_AT_TOP), CapacitorESR(0.01)), K_NEAR_LIMIT,
     {"esl": ESL_AT_TOP, "esr": 0.01}),
    ("lowest mode within 1e-10 of critical", (Losses(1 / (4 * np.sin(np.pi / 1002)) * (1 + 1e-10)),), 0.0,
     {"Q": 1 / (4 * np.sin(np.pi / 1002)) * (1 + 1e-10)}),
])
def test_a_lossy_500_loop_ladder_is_the_closed_form(name: str, effects: tuple[Effect, ...], coupling: float,
                                                    keywords: dict[str, float]) -> None:
    got, reference = _theory_and_closed_form(500, effects, coupling, keywords, 1001)
    assert np.max(np.abs(got - reference)) < ATOL_HARD_ACCEPTED


def test_a_response_float64_cannot_give_is_refused_in_words_not_nan() -> None:
    # An ESR 1e18 times the bulk impedance (past MAX_PARASITIC, as an Element list may still say): rounding leaves
    # a pole growing at about 2e8/s, whose response overflowed to NaN and numpy's warnings before it was refused.
    stiff = [dataclasses.replace(e, value=e.value * 1e18) if e.name.startswith("RS") else e
             for e in ladder_elements(_ladder("two-mass", 10), (CapacitorESR(1.0),), kick=I0)]
    theory = CircuitTheory(stiff)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's overflow warnings would fail the test before the refusal
        with pytest.raises(ParameterError) as caught:
            theory.currents(np.linspace(0.0, 40.0, 50) * np.sqrt(L0 * C0), ["L1", "L10"])
    message = str(caught.value)
    assert caught.value.field == "circuit" and "overflowed" in message and "\n" not in message


@pytest.mark.parametrize("part", [CoilCapacitance, CoilResistance, CapacitorESR, CapacitorESL])
def test_a_parasitic_past_a_million_bulk_parts_is_refused_naming_its_range(part: type[Effect]) -> None:
    field = next(f.name for f in dataclasses.fields(part))
    part(MAX_PARASITIC)  # the bound itself is allowed
    for value in (MAX_PARASITIC * 1.1, 1e300):
        with pytest.raises(ParameterError) as caught:
            part(value)
        assert caught.value.field == f"effects.{part.key}.{field}" and f"<= {MAX_PARASITIC:g}" in str(caught.value)


def test_a_circuit_damped_at_critical_is_refused_before_a_run_naming_the_effects_parameter() -> None:
    # Losses at the Q that damps the circuit's lowest mode critically (its own omega, a coil capacitance beside):
    # the refusal names effects.losses.Q and its value, not the whole effect (its ClassVars are no parameters).
    chain = lcchain.chain_for_case("two-mass", 8)
    ladder = Ladder(chain)
    poles = CircuitTheory(ladder_elements(ladder, (CoilCapacitance(1e-9),), kick=I0)).poles
    omega = np.sort(np.abs(poles.imag)) * ladder.time_unit
    critical = 1.0 / (2.0 * omega[omega > 0][0])
    with pytest.raises(ParameterError) as caught:
        plan_request(Request(chain, Transient(dt=0.05), effects=(Losses(critical), CoilCapacitance(1e-9))))
    assert (caught.value.field, caught.value.value) == ("effects.losses.Q", critical)
    assert "critical" in str(caught.value) and "\n" not in str(caught.value)


@pytest.mark.parametrize("part", [CapacitorESR, CoilResistance])
def test_an_ac_sweep_of_a_circuit_with_every_mode_overdamped_is_refused_naming_the_resistor(part: type[Effect]
                                                                                           ) -> None:
    # R = 10 sqrt(L0/C0): every pole real; the sweep placed by the resonances divided by zero (a traceback)
    chain = lcchain.chain_for_case("two-mass", 10)
    with pytest.raises(ParameterError) as caught:
        plan_request(Request(chain, AC(), effects=(part(10.0),)))
    assert (caught.value.field, caught.value.value) == (f"effects.{part.key}.R", 10.0)
    assert "overdamped" in str(caught.value) and "\n" not in str(caught.value)


@pytest.mark.parametrize("part, field", [(CapacitorESL, "L"), (CoilCapacitance, "ratio")])
def test_an_ac_sweep_whose_parts_resonate_too_far_apart_is_refused_naming_the_part(part: type[Effect], field: str
                                                                                  ) -> None:
    # a part a million times its bulk element: its resonance lies so far from the ladder's that no sweep of
    # MAX_AC_POINTS frequencies separates the poles; the refusal named --N (the chain), which the user did not vary
    chain = lcchain.chain_for_case("two-mass", 10)
    with pytest.raises(ParameterError) as caught:
        plan_request(Request(chain, AC(), effects=(part(MAX_PARASITIC),)))
    assert (caught.value.field, caught.value.value) == (f"effects.{part.key}.{field}", MAX_PARASITIC)
    assert "a circuit whose poles a sweep" in str(caught.value) and "\n" not in str(caught.value)
