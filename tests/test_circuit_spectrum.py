"""The spectrum of a circuit with real parts against the circuit's own exact poles and residues (issue 30, item 5).

An AC analysis of a ladder whose effects write elements no chain has (a coil's self-capacitance or winding
resistance, a capacitor's ESR or ESL, coupled coils with losses) is compared with the circuit's exact admittances
(:meth:`lcchain.circuit.exact.CircuitTheory.admittances`, checked against nodal equations in
tests/test_circuit_admittances.py): its omega_n = |p_n|, the end weights P_n = m_1 b_n of its sections, and with
resistors each mode's own Q_n = omega_n / gamma_n.  The engines run for real.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_CIRCUIT_SPECTRUM_P,
    CHAIN_MISSES_CIRCUIT,
    RTOL_CIRCUIT_SPECTRUM_OMEGA,
    RTOL_CIRCUIT_SPECTRUM_Q,
    RTOL_ENVELOPE_Y11,
)

from lcchain.circuit.effects import (
    CapacitorESL,
    CapacitorESR,
    CoilCapacitance,
    CoilResistance,
    Coupling,
    Effect,
    Losses,
)
from lcchain.circuit.elements import Element
from lcchain.circuit.netlist import ac_circuit_elements
from lcchain.compare.poles import CircuitModes, merged_poles
from lcchain.compare.spectral import SpectrumMetrics
from lcchain.runs.execute import ac_metrics, execute
from lcchain.runs.request import AC, Request, plan_request
from lcchain.runs.spec import SpectrumTheory
from lcchain.runs.spectrum import SpectrumOptions, measure_spectrum
from lcchain.theory.cases import chain_for_case
from lcchain.theory.exact import driven_modes

PARTS: dict[str, tuple[str, int, tuple[Effect, ...]]] = {
    "coil capacitance": ("two-mass", 8, (CoilCapacitance(0.05),)),
    "coil resistance": ("two-mass", 8, (CoilResistance(0.01),)),
    "capacitor ESR": ("two-mass", 8, (CapacitorESR(0.01),)),
    "capacitor ESL": ("two-mass", 8, (CapacitorESL(0.05),)),
    "coupled with losses": ("two-mass", 6, (Coupling(0.2), Losses(50.0))),
    "every part, coupled, losses": ("one-mass", 6, (Coupling(0.2), CoilCapacitance(0.05), CoilResistance(0.01),
                                                    CapacitorESR(0.01), CapacitorESL(0.04), Losses(100.0))),
    # a coil's capacitor and a capacitor's ESR: real poles (RC) far beyond the sweep, which no sweep can place,
    # and a free chain's zero mode, which no resistor damps
    "coil capacitance and ESR": ("two-mass", 8, (CoilCapacitance(0.05), CapacitorESR(0.01))),
}
LOSSY = {"coil resistance", "capacitor ESR", "coupled with losses", "every part, coupled, losses",
         "coil capacitance and ESR"}


def _check(name: str, engine: str) -> None:
    case, N, effects = PARTS[name]
    report = measure_spectrum(chain_for_case(case, N), options=SpectrumOptions(effects=effects, engine=engine))
    assert report.theory.method == "circuit"
    assert report.seen.all()  # every mode of the circuit, resolved or not, is seen
    assert report.max_rel_error_omega < RTOL_CIRCUIT_SPECTRUM_OMEGA
    assert report.max_abs_error_P < ATOL_CIRCUIT_SPECTRUM_P
    if name in LOSSY:
        assert report.gamma_theory is not None and np.all(np.isfinite(report.gamma))
        assert report.max_rel_error_Q < RTOL_CIRCUIT_SPECTRUM_Q
        assert report.to_dict()["max_rel_error_Q"] == report.max_rel_error_Q
    else:
        assert report.gamma_theory is None and np.isnan(report.max_rel_error_Q)


@pytest.mark.ngspice
@pytest.mark.parametrize("name", PARTS)
def test_ngspice_spectrum_is_the_circuits_poles_and_residues(name: str) -> None:
    _check(name, "ngspice")


@pytest.mark.gnucap
@pytest.mark.parametrize("name", ["coil capacitance", "capacitor ESR", "every part, coupled, losses"])
def test_gnucap_spectrum_is_the_circuits_poles_and_residues(name: str) -> None:
    _check(name, "gnucap")


@pytest.mark.ngspice
def test_the_chains_driven_modes_are_clearly_not_such_a_circuits() -> None:
    # the same samples judged against the chain (the old comparison) miss by far more than the circuit's targets:
    # the comparison above is really against the circuit's poles
    chain = chain_for_case("two-mass", 8)
    spec = plan_request(Request(chain, AC(), effects=(CoilCapacitance(0.05),))).specs[0]
    record = execute(spec)
    assert record.ok and record.run is not None and record.spectrum is not None
    assert record.spectrum.max_rel_error_omega < RTOL_CIRCUIT_SPECTRUM_OMEGA
    assert isinstance(spec.theory, SpectrumTheory)
    as_chain = ac_metrics(replace(spec.theory, circuit=None), record.run)
    assert as_chain.max_rel_error_omega > CHAIN_MISSES_CIRCUIT
    # and the circuit's frequencies are not the chain's
    assert np.max(np.abs(record.spectrum.omega_theory - driven_modes(chain).omega)
                  / np.maximum(driven_modes(chain).omega, 1.0)) > CHAIN_MISSES_CIRCUIT


def test_the_plan_compares_with_the_very_elements_the_netlist_is_written_with() -> None:
    effects: tuple[Effect, ...] = (CoilCapacitance(0.05), CapacitorESL(0.04), CoilResistance(0.01))
    chain = chain_for_case("one-mass", 5)
    plan = plan_request(Request(chain, AC(), effects=effects))
    spec = plan.specs[0]
    assert isinstance(spec.theory, SpectrumTheory) and spec.theory.circuit is not None and spec.theory.Q is None
    circuit = spec.theory.circuit
    assert circuit == ac_circuit_elements(plan.ladder, effects)
    cards = [line for line in spec.netlist.splitlines() if line[:1] in "RLCK"]
    assert cards == [e.card() for e in circuit if isinstance(e, Element)]
    # the sweep covers every mode of the circuit: its coils' self-resonances far above the chain's band too
    from lcchain.runs.execute import circuit_modes

    modes = circuit_modes(circuit, chain.N, plan.ladder.time_unit, plan.ladder.impedance)
    assert modes.N > chain.N and np.max(modes.omega) > 5.0
    assert plan.omega_max is not None and plan.omega_max > np.max(modes.omega)
    # a key of its own, while a chain's AC run keeps the fingerprint it had (no "circuit" in it)
    assert "circuit" in spec.theory.fingerprint()
    plain = plan_request(Request(chain, AC())).specs[0]
    assert isinstance(plain.theory, SpectrumTheory) and plain.theory.circuit is None
    assert "circuit" not in plain.theory.fingerprint() and plain.key("v") != spec.key("v")


def test_the_metrics_keep_the_circuits_own_decay_rates() -> None:
    metrics = SpectrumMetrics(np.array([0.0, 1.0]), np.array([0.0, 1.0 + 1e-12]), np.array([0.5, 0.2]),
                              np.array([0.5, 0.2]), np.array([True, True]), gamma=np.array([0.1, 0.02]),
                              gamma_theory=np.array([0.1, 0.02]))
    back = SpectrumMetrics.from_dict(metrics.to_dict())
    assert back.gamma_theory is not None and np.array_equal(back.gamma_theory, [0.1, 0.02])
    assert back.Q_theory[1] == 1.0 / 0.02 and back.max_rel_error_Q == metrics.max_rel_error_Q
    assert metrics.to_dict()["Q"] is None


@pytest.mark.ngspice
@pytest.mark.slow
def test_a_larger_circuit_with_every_part_and_overlapping_resonances() -> None:
    # N = 20: 39 modes (the ESL and the coils' self-capacitance resonate far above the band), resistors that make
    # neighbouring resonances overlap near the band's top
    effects = (CoilCapacitance(0.05), CoilResistance(0.01), CapacitorESR(0.01), CapacitorESL(0.04))
    report = measure_spectrum(chain_for_case("two-mass", 20), options=SpectrumOptions(effects=effects))
    assert report.theory.N > 20 and report.seen.all()
    assert report.max_rel_error_omega < RTOL_CIRCUIT_SPECTRUM_OMEGA
    assert report.max_abs_error_P < ATOL_CIRCUIT_SPECTRUM_P
    assert report.max_rel_error_Q < RTOL_CIRCUIT_SPECTRUM_Q


@pytest.mark.ngspice
def test_a_scene_and_the_command_line_take_real_parts(tmp_path, monkeypatch, capsys) -> None:
    # The scene's AC report and lcchain spectrum, with a winding resistance: each mode decays at its own rate (no
    # [effects.losses] Q), compared with the circuit's own poles.
    import json

    from lcchain.cli.main import main

    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "parts.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 8\n[effects.coil_resistance]\nR = 0.01\n'
                     '[analysis]\nkind = "ac"\n[output]\nreport = "r.json"\n')
    assert main(["run", str(scene), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert "Q" not in report and report["max_rel_error_Q"] < RTOL_CIRCUIT_SPECTRUM_Q
    assert report["max_rel_error_omega"] < RTOL_CIRCUIT_SPECTRUM_OMEGA
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--coil-capacitance", "0.05", "--capacitor-esr",
                 "0.01", "--json"]) == 0
    spectrum = json.loads(capsys.readouterr().out)
    assert spectrum["max_rel_error_omega"] < RTOL_CIRCUIT_SPECTRUM_OMEGA
    assert spectrum["max_rel_error_pole"] < RTOL_CIRCUIT_SPECTRUM_Q
    # the report's modes are the compared ones, each with its weight (its density was every pole's, the ESR's
    # real poles far beyond the sweep included: 15 weights for 8 modes); its count, the circuit's, not N's
    assert len(spectrum["modes"]) == 8 and spectrum["seen"] <= 8
    assert main(["spectrum", "--case", "two-mass", "--N", "10", "--capacitor-esl", "0.01", "--coil-capacitance",
                 "0.01"]) == 0
    assert "(19 of 19 modes seen at the ends)" in capsys.readouterr().out


def test_a_fit_the_samples_cannot_resolve_stops_at_its_bound() -> None:
    # A circuit damped past what its samples resolve (ESR 10 sqrt(L0/C0) beside a coil capacitance), sampled from its
    # exact admittances: the fit took 850 evaluations (44 s against a price of 6.8 s) and left modes unseen anyway.
    from lcchain.circuit.exact import CircuitTheory
    from lcchain.circuit.ladder import Ladder
    from lcchain.compare.poles import FIT_MAX_EVALUATIONS, fit_poles

    ladder = Ladder(chain_for_case("two-mass", 12))
    elements = ac_circuit_elements(ladder, (CoilCapacitance(0.01), CapacitorESR(10.0)))
    poles, residues, direct = CircuitTheory(elements).admittances(["L1", "L12"])
    omega = np.linspace(0.01, 10.6, 4000)  # units of 1/sqrt(L0 C0), as the plan's sweep
    s = 1j * omega / ladder.time_unit
    y11, yN1 = (ladder.impedance * (direct[k] + residues[k] @ (1.0 / (s[None, :] - poles[:, None])))
                for k in (0, 1))
    fit = fit_poles(omega, y11, -yN1, lossy=True)
    assert fit.sweeps <= FIT_MAX_EVALUATIONS


def _modes(omega: list[float], gamma: list[float]) -> CircuitModes:
    size = len(omega)
    return CircuitModes(np.array(omega), np.array(gamma), np.ones(size), np.ones(size), True)


def test_a_circuits_modes_merge_where_their_bands_overlap_and_they_barely_ring() -> None:
    # two resonances 0.3 widths apart (|p - q| = 0.3 (h_p + h_q)): merged when they ring a few times, measured when
    # they ring hundreds of times (the fit separates those); closer than the chain's fit separates: merged whatever
    gap = 0.3 * 0.1
    assert merged_poles(_modes([1.0, 1.0 + gap], [0.1, 0.1])).all()
    gap = 0.3 * 0.01
    assert not merged_poles(_modes([1.0, 1.0 + gap], [0.01, 0.01])).any()
    gap = 0.1 * 0.01
    assert merged_poles(_modes([1.0, 1.0 + gap], [0.01, 0.01])).all()
    # bands that do not overlap, however damped: measured; a band that reaches zero frequency: merged
    assert not merged_poles(_modes([1.0, 3.0], [0.9, 0.9])).any()
    assert merged_poles(_modes([0.5, 3.0], [0.6, 0.6])).tolist() == [True, False]
    # real poles: one alone is measured (a free chain's translation that a winding resistance damps), two merge
    assert not merged_poles(_modes([0.0, 1.0], [0.05, 0.01])).any()
    assert merged_poles(_modes([0.0, 0.0, 2.0], [0.05, 0.2, 0.01])).tolist() == [True, True, False]
    # a free chain's translation merges with a real pole, or a ring whose band reaches zero, and they with it
    assert merged_poles(_modes([0.0, 0.0, 2.0], [0.0, 0.05, 0.01])).tolist() == [True, True, False]
    assert merged_poles(_modes([0.0, 0.5, 2.0], [0.0, 0.6, 0.01])).tolist() == [True, True, False]
    assert not merged_poles(_modes([0.0, 0.5, 2.0], [0.0, 0.1, 0.01])).any()
    # lossless: nothing merges, not even modes closer than any sweep resolves
    assert not merged_poles(_modes([0.0, 1.0, 1.0 + 1e-9], [0.0, 0.0, 0.0])).any()


# circuits damped past what a sweep resolves: real poles, resonances that ring once or twice
DAMPED = {"capacitor ESR of 2": ("two-mass", 12, (CapacitorESR(2.0),)),
          "winding resistance of 0.3": ("two-mass", 12, (CoilResistance(0.3),)),
          "coil capacitance, capacitor ESR of 2": ("one-mass", 10, (CoilCapacitance(0.05), CapacitorESR(2.0)))}


@pytest.mark.ngspice
@pytest.mark.parametrize("name", DAMPED)
def test_a_heavily_damped_circuits_merged_modes_are_said_and_its_admittance_compared(name: str) -> None:
    case, N, effects = DAMPED[name]
    report = measure_spectrum(chain_for_case(case, N), options=SpectrumOptions(effects=effects))
    assert report.failure == ""
    plan = plan_request(Request(chain_for_case(case, N), AC(), effects=effects))
    assert isinstance(plan.specs[0].theory, SpectrumTheory) and plan.specs[0].theory.circuit is not None
    from lcchain.compare.poles import measurable
    from lcchain.runs.execute import circuit_modes

    exact = measurable(circuit_modes(plan.specs[0].theory.circuit, N, plan.ladder.time_unit, plan.ladder.impedance),
                       report.omega_max)
    merged = merged_poles(exact)
    assert merged.any() and np.array_equal(report.merged_modes, merged)
    assert np.isnan(report.omega[merged]).all()  # said, with no value
    resolved = report.resolved
    assert report.seen[resolved].all()
    if resolved.any():
        assert report.max_rel_error_omega < RTOL_CIRCUIT_SPECTRUM_OMEGA
        assert report.max_abs_error_P < ATOL_CIRCUIT_SPECTRUM_P
    # what the merged modes make together is compared with the circuit's exact admittance over the whole sweep
    assert report.envelope_error is not None and report.envelope_error < RTOL_ENVELOPE_Y11
    assert report.to_dict()["merged"] == [int(n) + 1 for n in np.flatnonzero(merged)]


@pytest.mark.ngspice
def test_the_command_line_passes_a_heavily_damped_circuit_and_names_its_merged_modes(capsys) -> None:
    from lcchain.cli.main import main

    assert main(["spectrum", "--case", "two-mass", "--N", "12", "--capacitor-esr", "2"]) == 0
    out = capsys.readouterr().out
    assert "merged by the losses" in out and "Y_11 against the exact lossy admittance" in out


@pytest.mark.ngspice
def test_a_scene_whose_every_mode_merges_reports_no_error_and_valid_json(tmp_path, monkeypatch, capsys) -> None:
    # nothing compared is no error of 0: the scene says n/a, and its report is JSON any reader takes (null, not NaN)
    import json

    from lcchain.cli.main import main

    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "damped.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 12\n[effects.capacitor_esr]\nR = 2.0\n'
                     '[analysis]\nkind = "ac"\n[output]\nreport = "r.json"\n')
    assert main(["run", str(scene)]) == 0
    row = [line for line in capsys.readouterr().out.splitlines() if line.split()[:1] == ["1"]]
    assert row and row[0].split()[1:4] == ["0", "n/a", "n/a"]

    def refuse(constant: str) -> float:
        raise ValueError(f"{constant} is no JSON")

    report = json.loads((tmp_path / "r.json").read_text(), parse_constant=refuse)
    sample = report["samples"][0]
    assert sample["max_rel_error_omega"] is None and sample["max_abs_error_P"] is None
    assert report["max_rel_error_omega"] is None and sample["modes_seen"] == 0


@pytest.mark.ngspice
def test_a_store_of_runs_whose_every_mode_merges_holds_no_error_of_zero(tmp_path, capsys) -> None:
    # a Monte Carlo of a heavily damped circuit: its store says n/a, never an error of 0 (nothing was compared), and
    # keeps what was measured, Y_11 against the exact admittance
    import json

    from lcchain.cli.main import main

    scene = tmp_path / "damped.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 12\n[effects.capacitor_esr]\nR = 2.0\n[effects.tolerance]\n'
                     'L = 0.05\nC = 0.05\nsamples = 2\n[analysis]\nkind = "ac"\n[output]\nplots = []\n')
    store = tmp_path / "s.sqlite"
    assert main(["sweep", str(scene), "--samples", "2", "--store", str(store), "--executor", "serial"]) == 0
    capsys.readouterr()
    assert main(["results", str(store)]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines() if line.split()[:2] in (["0", "ok"],
                                                                                                  ["1", "ok"])]
    assert len(rows) == 2 and all(row[4:7] == ["0", "n/a", "n/a"] for row in rows)
    assert main(["results", str(store), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for run in data["runs"] if isinstance(data, dict) else data:
        assert run["max_rel_error_omega"] is None and run["max_abs_error_P"] is None and run["modes_seen"] == 0
        assert run["max_rel_error_Y11"] < RTOL_ENVELOPE_Y11
    assert main(["results", str(store), "--summary", "--metric", "omega"]) == 2
    assert "compared no mode" in capsys.readouterr().err


def test_side_by_side_is_refused_for_an_ac_scene_before_it_runs(tmp_path, capsys) -> None:
    # its overlays are a transient's waveforms: an AC scene has none (it ended in an AssertionError after the run)
    from lcchain.cli.main import main

    scene = tmp_path / "ac.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 8\n[analysis]\nkind = "ac"\n[output]\nplots = []\n')
    assert main(["run", str(scene), "--side-by-side", str(tmp_path / "sbs.png")]) == 2
    said = capsys.readouterr().err
    assert "--side-by-side" in said and "transient scenes only" in said and "Traceback" not in said
    assert not (tmp_path / "sbs.png").exists()
