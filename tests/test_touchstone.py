"""``lcchain spectrum --touchstone``: the ladder as a two-port in a Touchstone file that scikit-rf reads
(issue 33, item 3), against the circuit's exact phasors (lcchain.circuit.phasor.source_currents), whose port
currents are the sources', not the coils' (a coil's self-capacitance carries the difference)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers.tolerances import ATOL_S_EXACT_PORTS, ATOL_TWO_PORT_S, ATOL_UNITARY, RTOL_PORT_CURRENT

from lcchain.cli.main import main
from lcchain.runs.request import AC, Request
from lcchain.runs.twoport import scattering, two_port_theory
from lcchain.theory.cases import chain_for_case


@pytest.mark.ngspice
def test_a_touchstone_file_reads_in_scikit_rf_as_the_exact_two_port(tmp_path: Path, capsys) -> None:
    skrf = pytest.importorskip("skrf")
    target = tmp_path / "ladder.s2p"
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--L0", "10e-6", "--C0", "10e-9", "--points", "100",
                 "--touchstone", str(target), "--z0", "75"]) == 0
    assert "two-port: 100 frequencies" in capsys.readouterr().out
    assert "# Hz S RI R 75" in target.read_text().splitlines()
    network = skrf.Network(str(target))
    assert network.s.shape == (100, 2, 2) and np.allclose(network.z0, 75.0)
    # the ports named as a reader names them (a "port 1:" comment was dropped), what the file is of in its comments
    assert network.port_names[0].startswith("a break in loop 1") and "effects: none" in network.comments
    request = Request(chain_for_case("two-mass", 8), AC(100), L0=10e-6, C0=10e-9)
    exact = two_port_theory(request, network.f, z0=75.0)
    np.testing.assert_allclose(network.s, exact.S, rtol=0, atol=ATOL_TWO_PORT_S)
    # lossless: unitary; reciprocal: S12 = S21; the ladder is mirror-symmetric only in its values, not asked here
    unit = np.einsum("fij,fkj->fik", network.s, network.s.conj())
    np.testing.assert_allclose(unit, np.broadcast_to(np.eye(2), unit.shape), rtol=0, atol=ATOL_UNITARY)
    np.testing.assert_allclose(network.s[:, 0, 1], network.s[:, 1, 0], rtol=0, atol=ATOL_TWO_PORT_S)


@pytest.mark.ngspice
def test_a_real_pole_does_not_place_the_two_ports_sweep(tmp_path: Path, capsys) -> None:
    """A coil's capacitor discharging through an ESR is a real pole far above the band: the sweep's top is the
    highest resonance, as spectrum's (it went to 35 GHz for a band ending near 1 MHz, where |S11| passed 1)."""
    target = tmp_path / "parts.s2p"
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--coil-capacitance", "0.01", "--capacitor-esr",
                 "0.01", "--touchstone", str(target)]) == 0
    rows = np.array([[float(x) for x in line.split()] for line in target.read_text().splitlines()
                     if line.strip() and not line.startswith(("!", "#"))])
    band_top = 2.0 / (2 * np.pi * np.sqrt(10e-6 * 10e-9))  # the ladder's, 1.01 MHz (the defaults' L0, C0)
    assert rows[-1, 0] < 1.2 * band_top
    s11, s21 = rows[:, 1] + 1j * rows[:, 2], rows[:, 3] + 1j * rows[:, 4]
    assert np.all(np.abs(s11) ** 2 + np.abs(s21) ** 2 <= 1.0 + ATOL_UNITARY)  # lossy: passive


def test_scattering_of_a_matched_and_an_open_port() -> None:
    """S = (1 - z0 Y)(1 + z0 Y)^-1: two unconnected ports each loaded by 1/z0 are matched (S = 0); open ports
    (Y = 0) reflect fully (S = 1)."""
    z0 = 50.0
    np.testing.assert_allclose(scattering(np.eye(2)[None] / z0, z0), np.zeros((1, 2, 2)), atol=ATOL_S_EXACT_PORTS)
    np.testing.assert_allclose(scattering(np.zeros((1, 2, 2)), z0), np.eye(2)[None], atol=ATOL_S_EXACT_PORTS)


def test_touchstone_options_are_refused_in_one_line(tmp_path: Path, capsys) -> None:
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--z0", "50"]) == 2
    assert "--z0" in capsys.readouterr().err
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--touchstone", str(tmp_path / "x.txt")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--touchstone" in err
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--touchstone", str(tmp_path / "x.s2p"),
                 "--z0", "-5"]) == 2
    assert "--z0" in capsys.readouterr().err and not (tmp_path / "x.s2p").exists()


@pytest.mark.ngspice
def test_a_coil_capacitance_is_in_the_port_currents_of_both_engines_and_of_theory(tmp_path: Path, capsys) -> None:
    """With a capacitor C_p across every coil a port's current is its coil's and C_p's: I_1 = I_L1 (1 + s^2 L_1 C_p)
    (nothing else in coil 1's branch), 8 % more than the coil's at the band top here; the file held the coil's."""
    from lcchain.circuit.effects import CoilCapacitance
    from lcchain.circuit.exact import CircuitTheory
    from lcchain.circuit.ladder import Ladder
    from lcchain.circuit.netlist import ac_circuit_elements

    chain = chain_for_case("two-mass", 8)
    request = Request(chain, AC(100), effects=(CoilCapacitance(0.01),), L0=10e-6, C0=10e-9)
    for engine in ("ngspice", "gnucap"):
        target = tmp_path / f"{engine}.s2p"
        assert main(["spectrum", "--case", "two-mass", "--N", "8", "--L0", "10e-6", "--C0", "10e-9", "--points",
                     "100", "--coil-capacitance", "0.01", "--engine", engine, "--touchstone", str(target)]) == 0
        capsys.readouterr()
        rows = np.array([[float(x) for x in line.split()] for line in target.read_text().splitlines()
                         if line.strip() and not line.startswith(("!", "#"))])
        measured = (rows[:, 1::2] + 1j * rows[:, 2::2]).reshape(-1, 2, 2).transpose(0, 2, 1)  # v1: S11 S21 S12 S22
        exact = two_port_theory(request, rows[:, 0])
        np.testing.assert_allclose(measured, exact.S, rtol=0, atol=ATOL_TWO_PORT_S)
    # the ports' theory against the coils' own (the modal sum of lcchain.circuit.exact), times what C_p adds
    frequency = rows[:, 0]
    ladder = Ladder(chain, 10e-6, 10e-9)
    poles, residues, direct = CircuitTheory(ac_circuit_elements(ladder, request.effects)).admittances(["L1"])
    s = 2j * np.pi * frequency
    coil = direct[0] + residues[0] @ (1.0 / (s[None, :] - poles[:, None]))
    L1, Cp = ladder.inductances()[0], 0.01 * 10e-9
    np.testing.assert_allclose(exact.Y[:, 0, 0], coil * (1.0 + s**2 * L1 * Cp), rtol=RTOL_PORT_CURRENT)
    top = 2.0 / (2 * np.pi * np.sqrt(10e-6 * 10e-9))  # the band top, Hz: C_p's share there is 4 L1/L0 %
    assert abs(np.interp(top, frequency, np.abs(exact.Y[:, 0, 0] / coil)) - 1.0) > 0.05


def test_the_phasor_solve_is_the_hand_formula_of_a_transformer_and_a_series_rlc() -> None:
    """lcchain.circuit.phasor against closed forms: a series RLC's current V / (R + sL + 1/(sC)), and a transformer's
    primary current V / (R1 + sL1 - (sM)^2 / (sL2 + R2)) with M = k sqrt(L1 L2); ngspice's sign (into + node)."""
    from lcchain.circuit.elements import Element
    from lcchain.circuit.phasor import source_currents

    frequency = np.geomspace(1e2, 1e8, 25)
    s = 2j * np.pi * frequency
    series = [Element("R1", "a", "b", 50.0), Element("L1", "b", "c", 1e-5), Element("C1", "c", "0", 1e-9)]
    current = source_currents(series, [("V1", "a", "0", 1.0)], frequency)[0]
    np.testing.assert_allclose(-current, 1.0 / (50.0 + s * 1e-5 + 1.0 / (s * 1e-9)), rtol=RTOL_PORT_CURRENT)
    L1, L2, k = 1e-5, 4e-5, 0.6
    transformer = [Element("R1", "a", "b", 10.0), Element("L1", "b", "0", L1), Element("L2", "c", "0", L2),
                   Element("K1", "L1", "L2", k), Element("R2", "c", "0", 200.0)]
    current = source_currents(transformer, [("V1", "a", "0", 2.0)], frequency)[0]
    M = k * np.sqrt(L1 * L2)
    np.testing.assert_allclose(-current, 2.0 / (10.0 + s * L1 - (s * M) ** 2 / (s * L2 + 200.0)),
                               rtol=RTOL_PORT_CURRENT)


def test_the_two_port_is_priced_before_anything_runs(tmp_path: Path, capsys) -> None:
    """--touchstone's two AC analyses and exact phasors ran after the spectrum, unpriced: their price (6.5 s at
    N = 2000) is now checked first, and --max-time refuses it naming --touchstone before ngspice starts."""
    target = tmp_path / "big.s2p"
    assert main(["spectrum", "--case", "two-mass", "--N", "2000", "--touchstone", str(target), "--max-time", "3s"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lcchain: --touchstone = ") and "a two-port: 2 x 401 frequencies" in err
    assert err.count("\n") == 1 and not target.exists()


def test_a_lossless_circuit_with_parts_is_priced_as_the_dense_problem_it_is() -> None:
    """Only the bare ladder's poles are a tridiagonal problem: a coil's capacitance, lossless too, makes the
    circuit theory that places the sweep dense (N = 400: 0.09 s, where the tridiagonal price said 0.04 s)."""
    from lcchain.circuit.effects import CoilCapacitance
    from lcchain.circuit.exact import circuit_cost
    from lcchain.circuit.ladder import Ladder
    from lcchain.circuit.netlist import ac_circuit_elements
    from lcchain.runs.twoport import sweep_cost

    ladder = Ladder(chain_for_case("two-mass", 400))
    parts = (CoilCapacitance(0.01),)
    assert sweep_cost(ladder, parts) == circuit_cost(ac_circuit_elements(ladder, parts), 1)
    assert sweep_cost(ladder, ())[0] < circuit_cost(ac_circuit_elements(ladder, ()), 1)[0]
