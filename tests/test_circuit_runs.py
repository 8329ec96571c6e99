"""Runs of circuits whose elements are no chain's (issue 30, item 3): compared with the circuit's own exact theory.

Every run reports two separate things: the simulator against the exact theory of the circuit it ran (the
integration error, which the accuracy model predicts from the circuit's own modes), and the circuit's exact
response against the ideal chain's alpha_N(t) (what the effects cost the pulse).  A coil's self-capacitance
reported "ok" against the ideal chain's theory with an error of 0.105 where 1.3e-4 was predicted: here the error
is the simulator's own, and the effect's cost is reported beside it.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_CIRCUIT_KICK_AT_ZERO,
    ATOL_CIRCUIT_PEAK_IS_THEORY,
    ATOL_IDEAL_PEAK_ON_GRID,
    ATOL_RESPONSE_IN_I0,
    MAX_DISPLACED_COIL_ERROR,
    MAX_PULSE_RUN_ERROR,
    PREDICTION_FACTOR,
)

import lcchain
from lcchain.circuit.effects import (
    CapacitorESL,
    CapacitorESR,
    CoilCapacitance,
    CoilResistance,
    Coupling,
    Effect,
    Losses,
    Tolerance,
    Walls,
)
from lcchain.circuit.ladder import Ladder
from lcchain.runs.execute import CircuitResponse
from lcchain.runs.request import AC, Drive, Request, Transient, plan_request
from lcchain.theory.cases import chain_for_case
from lcchain.theory.response import linear_response

REAL: dict[str, tuple[Effect, ...]] = {
    "coil capacitance": (CoilCapacitance(0.05),),
    "coil resistance": (CoilResistance(0.02),),
    "capacitor ESR": (CapacitorESR(0.03),),
    "capacitor ESL": (CapacitorESL(0.02),),
    "losses and coil capacitance": (Losses(60.0), CoilCapacitance(0.05)),
    "coupling with losses": (Coupling(0.1), Losses(40.0)),
    # a coil's capacitor and a capacitor's ESL ring at 1/sqrt(r L) (7 here): slow enough for the step to resolve;
    # with walls the rail nodes' self-capacitances float (their capacitors to ground sit behind the ESR)
    "all four, coupled, walls": (Coupling(0.05), Walls(0.3), CoilCapacitance(0.2), CoilResistance(0.01),
                                 CapacitorESR(0.02), CapacitorESL(0.1)),
}


def _run(effects: tuple[Effect, ...], *, engine: str = "ngspice", drive: Drive | None = None, N: int = 10,
         **analysis: object) -> lcchain.SimulationReport:
    chosen = Transient(**({"dt": 0.02} | analysis))  # type: ignore[arg-type]
    return lcchain.simulate(Request(chain_for_case("two-mass", N), chosen, drive=drive or Drive(), effects=effects,
                                    engine=engine))


@pytest.mark.ngspice
@pytest.mark.parametrize("engine", ["ngspice", pytest.param("gnucap", marks=pytest.mark.gnucap)])
@pytest.mark.parametrize("name", REAL)
def test_a_real_part_run_meets_the_error_predicted_from_its_own_circuit(engine: str, name: str) -> None:
    report = _run(REAL[name], engine=engine)
    metrics = report.record.metrics
    assert report.record.ok and metrics is not None and metrics.predicted_error is not None
    assert metrics.max_abs_error <= PREDICTION_FACTOR * metrics.predicted_error
    assert metrics.max_abs_error >= metrics.predicted_error / PREDICTION_FACTOR  # the prediction is sharp, too
    cost = metrics.effects
    assert cost is not None
    # the circuit's first arrival is what the simulator saw, to the integration error
    first = next(a for a in metrics.arrivals if a.end == "last")
    assert abs(cost.peak_circuit - first.peak_theory) <= ATOL_CIRCUIT_PEAK_IS_THEORY
    assert abs(cost.peak_circuit - first.peak_sim) <= 2 * PREDICTION_FACTOR * metrics.predicted_error
    # the ideal is the chain's own alpha_N(t), no simulator involved
    spec = plan_request(Request(report.chain, Transient(dt=0.02))).specs[0]
    t = np.linspace(0.8 * cost.t_ideal, 1.2 * cost.t_ideal, 4001)
    assert abs(cost.peak_ideal - float(np.max(linear_response(spec.theory.chain, t)[1]))) <= ATOL_IDEAL_PEAK_ON_GRID
    assert "effects" in metrics.to_dict() and report.record.summary()["effects"]["energy_loss"] == cost.energy_loss


@pytest.mark.ngspice
def test_a_coil_capacitance_is_no_longer_an_ok_against_the_wrong_theory() -> None:
    # The case the issue found: a capacitor across each coil, compared with the ideal chain, was an "ok" with an
    # error 800 times the prediction.  Against its own circuit the error is the simulator's; the ideal chain's
    # difference is the effect's cost, reported apart.
    report = _run((CoilCapacitance(0.1),), N=12, dt=0.05)
    metrics = report.record.metrics
    assert metrics is not None and metrics.predicted_error is not None and metrics.effects is not None
    assert metrics.max_abs_error <= PREDICTION_FACTOR * metrics.predicted_error
    ideal = linear_response(report.chain, report.waveforms.t)
    wrong = float(np.max(np.abs(ideal[1] - report.waveforms.last)))
    assert wrong > 10 * metrics.max_abs_error
    assert abs(metrics.effects.peak_circuit - metrics.effects.peak_ideal) > 10 * metrics.max_abs_error


@pytest.mark.ngspice
@pytest.mark.parametrize("drive", [Drive("displacement"), Drive("pulse", pulse=("gaussian", 0.5)),
                                   Drive("pulse", pulse=("rect", 0.5))], ids=["displacement", "gaussian", "rect"])
def test_every_drive_is_followed_with_real_parts(drive: Drive) -> None:
    report = _run((CoilCapacitance(0.05), CapacitorESR(0.02)), drive=drive)
    metrics = report.record.metrics
    assert report.record.ok and metrics is not None and metrics.effects is not None
    if drive.kind == "displacement":
        assert metrics.predicted_error is not None
        assert metrics.max_abs_error <= PREDICTION_FACTOR * metrics.predicted_error
        assert metrics.effects.energy_loss is None
    else:  # a pulse: the step resolves it (dt = width / 8), no model predicts the error
        assert metrics.max_abs_error < MAX_PULSE_RUN_ERROR


@pytest.mark.ngspice
def test_an_extrapolation_and_an_accuracy_follow_the_circuit() -> None:
    effects = (CoilResistance(0.01), CapacitorESL(0.01))
    report = _run(effects, dt=0.04, extrapolate=3)
    assert report.extrapolation.runs == 3 and report.predicted_error is not None
    assert report.comparison.max_abs_error <= PREDICTION_FACTOR * report.predicted_error
    accuracy = 1e-4  # asked for, and met
    accurate = _run(effects, dt=None, accuracy=accuracy)
    assert accurate.comparison.max_abs_error <= accuracy


@pytest.mark.ngspice
@pytest.mark.parametrize("effects", [
    (CoilCapacitance(0.05), CoilResistance(0.02), CapacitorESR(0.05), CapacitorESL(0.05)),
    (CapacitorESR(100.0),),
], ids=["every part", "a large ESR"])
def test_an_accuracy_is_met_with_the_circuits_own_modes(effects: tuple[Effect, ...]) -> None:
    """The step an accuracy asks for is the circuit's, not the ideal chain's: with every part at N = 6 the chain's
    step (0.0156) was predicted and measured at 2.8e-3 against 1e-4, and the run failed its accuracy."""
    accuracy = 1e-4  # asked for, and to be met
    report = _run(effects, N=6, dt=None, accuracy=accuracy)
    metrics = report.record.metrics
    assert report.record.ok and metrics is not None and metrics.predicted_error is not None
    assert metrics.max_abs_error <= accuracy and metrics.predicted_error <= accuracy


@pytest.mark.ngspice
@pytest.mark.parametrize("case", ["two-mass", "uniform-bounded"])
def test_a_displaced_mass_with_its_coils_self_capacitance_is_the_circuit_ngspice_runs(case: str) -> None:
    """The spring's capacitor holds the displacement's charge and the coil's self-capacitor beside it starts at 0 V
    (it has no IC): the charge is shared at once, in ngspice as in the theory.  The theory charged both, and was
    4.8e-2 (two-mass) and 0.19 (uniform-bounded, a wall) off ngspice at coil capacitance 0.05."""
    report = lcchain.simulate(Request(chain_for_case(case, 6), Transient(dt=0.01), drive=Drive("displacement"),
                                      effects=(CoilCapacitance(0.05),)))
    assert report.record.ok and report.record.metrics is not None
    assert report.record.metrics.max_abs_error < MAX_DISPLACED_COIL_ERROR


@pytest.mark.ngspice
def test_tolerance_samples_are_each_compared_with_their_own_circuit(tmp_path) -> None:
    from lcchain.studies.plan import request_plan
    from lcchain.studies.run import run_plan

    request = Request(chain_for_case("two-mass", 10), Transient(dt=0.02),
                      effects=(Tolerance(L=0.05, C=0.05, samples=3, seed=4), CoilCapacitance(0.05)))
    plan = plan_request(request)
    circuits = [spec.theory.circuit for spec in plan.specs]
    assert all(circuits) and len({c for c in circuits}) == 3  # each sample's own elements
    for spec, chain in zip(plan.specs, plan.chains, strict=True):
        coil = next(e for e in spec.theory.circuit if e.name == "L1")
        assert coil.value == Ladder(chain).inductances()[0]
    summary = run_plan(request_plan([({"case": "tolerance"}, request)]), tmp_path / "t.sqlite")
    assert summary.ok == 3 and summary.failed == 0
    from lcchain.studies.exports import table_rows
    from lcchain.studies.store import Store

    with Store(tmp_path / "t.sqlite") as store:  # the two numbers, stored apart and read back
        runs = store.runs()
        rows = table_rows(runs)
    for run, row in zip(runs, rows, strict=True):
        cost = run.to_dict()["effects"]
        assert row["effects_energy_loss"] == cost["energy_loss"] and cost["peak_circuit"] != cost["peak_ideal"]
        assert run.to_dict()["max_abs_error"] <= PREDICTION_FACTOR * run.to_dict()["predicted_error"]


def test_the_chain_stays_the_fast_path_where_it_applies() -> None:
    chain = chain_for_case("two-mass", 10)
    for effects in ((), (Losses(50.0),), (Walls(0.2), Losses(50.0)), (Coupling(0.1),)):
        spec = plan_request(Request(chain, Transient(dt=0.02), effects=effects)).specs[0]
        assert spec.theory.circuit is None
    for effects in REAL.values():
        spec = plan_request(Request(chain, Transient(dt=0.02), effects=effects)).specs[0]
        assert spec.theory.circuit is not None and spec.theory.Q is None
        cards = [e.card() for e in spec.theory.circuit]
        body = [line for line in spec.netlist.splitlines() if line[:1] in "LCRKBV" and not line.startswith(".")]
        assert body == cards  # the netlist is written from the very elements the theory solves


def test_the_circuit_theory_is_priced() -> None:
    from lcchain.core.budget import Budget, BudgetError
    from lcchain.studies.plan import request_plan

    chain = chain_for_case("two-mass", 400)
    lossy = (CoilResistance(0.01), CoilCapacitance(0.01))
    plain, real = (Request(chain, Transient(dt=0.05), effects=effects) for effects in ((), lossy))
    priced, ideal = (request_plan([({"n": 1}, r)]).price(1) for r in (real, plain))
    assert priced.seconds > ideal.seconds + 1.0 and priced.memory > ideal.memory  # a dense eigen-solution of ~1600
    with pytest.raises(BudgetError, match="exact theory"):
        plan_request(real, Budget(max_memory=ideal.total_memory * 1.05, max_seconds=3600))


def test_an_ac_analysis_of_a_circuit_no_chain_can_say_runs_against_the_circuit() -> None:
    # issue 30, item 5: compared with the circuit's own poles and residues (tests/test_circuit_spectrum.py)
    spec = plan_request(Request(chain_for_case("two-mass", 10), AC(), effects=(CoilCapacitance(0.05),))).specs[0]
    assert spec.theory is not None and getattr(spec.theory, "circuit", None) is not None


def test_the_circuit_response_is_the_elements_response() -> None:
    # CircuitResponse is the circuit theory in the comparison's units: I/I0 against t/sqrt(L0 C0)
    spec = plan_request(Request(chain_for_case("two-mass", 8), Transient(dt=0.02),
                                effects=(CoilCapacitance(0.05),))).specs[0]
    theory = spec.theory
    response = CircuitResponse(theory, "ends")
    t = np.array([0.0, 1.0, 5.0])
    amperes = response.exact.currents(t * theory.time_unit, ["i(l1)", "i(l8)"])
    assert np.allclose(response(t), amperes / theory.I0, rtol=0, atol=ATOL_RESPONSE_IN_I0)
    assert abs(response(np.array([0.0]))[0, 0] - 1.0) < ATOL_CIRCUIT_KICK_AT_ZERO  # the kick: I0 in L1 at t = 0
