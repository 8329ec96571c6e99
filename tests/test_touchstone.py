"""``lcchain spectrum --touchstone``: the ladder as a two-port in a Touchstone file that scikit-rf reads
(issue 33, item 3), against the circuit's exact admittances (lcchain.circuit.exact.CircuitTheory.admittances)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers.tolerances import ATOL_S_EXACT_PORTS, ATOL_TWO_PORT_S, ATOL_UNITARY

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
