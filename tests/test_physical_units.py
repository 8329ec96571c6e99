"""Every output also in seconds, hertz and ohms for the given L0 and C0 (issue 33, item 1), beside the bulk units."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from helpers.tolerances import RTOL_ARITHMETIC

from lcchain.cli.main import main
from lcchain.core.physical import physical_scales


def test_the_scales_of_the_bulk_units() -> None:
    """tau = sqrt(L0 C0), Z = sqrt(L0 / C0); omega = 1 is 1 / (2 pi tau) Hz, the band top omega = 2 twice that."""
    scales = physical_scales(10e-6, 10e-9)
    tau = math.sqrt(1e-13)
    expected = {"time_unit_s": tau, "impedance_ohm": math.sqrt(1e3), "frequency_unit_Hz": 1 / (2 * math.pi * tau),
                "band_top_Hz": 1 / (math.pi * tau)}
    for key, value in expected.items():
        assert scales[key] == pytest.approx(value, rel=RTOL_ARITHMETIC)


@pytest.mark.ngspice
def test_simulate_and_spectrum_json_add_seconds_and_hertz(capsys, tmp_path) -> None:
    assert main(["simulate", "--case", "two-mass", "--N", "10", "--L0", "10u", "--C0", "10n", "--json",
                 "--plot", str(tmp_path / "s.png")]) == 0
    data = json.loads(capsys.readouterr().out)
    tau = data["physical"]["time_unit_s"]
    assert (data["L0"], data["C0"]) == (1e-5, 1e-8) and data["dt_s"] == pytest.approx(data["dt"] * tau)
    for arrival in data["arrivals"]:  # the bulk keys as they were, seconds beside them
        assert arrival["t_sim_s"] == pytest.approx(arrival["t_sim"] * tau, rel=RTOL_ARITHMETIC)
    assert main(["spectrum", "--case", "two-mass", "--N", "6", "--L0", "10u", "--C0", "10n", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    hz = data["physical"]["frequency_unit_Hz"]
    for mode in data["modes"]:
        assert mode["omega_theory_Hz"] == pytest.approx(mode["omega_theory"] * hz, rel=RTOL_ARITHMETIC)
    assert main(["spectrum", "--case", "two-mass", "--N", "6", "--L0", "10u", "--C0", "10n"]) == 0
    out = capsys.readouterr().out
    assert "time unit sqrt(L0 C0) = 316.228 ns" in out and "f (circuit), Hz" in out


def test_plots_carry_a_second_axis_in_si() -> None:
    pytest.importorskip("matplotlib")
    from lcchain.report.plots import OverlayCurves, overlay, spectrum

    t = np.linspace(0.0, 10.0, 50)
    figure = overlay(OverlayCurves(t, np.sin(t), t, np.sin(t), time_unit=3e-7))
    labels = [child.get_xlabel() for ax in figure.axes for child in ax.child_axes]
    assert "time [s]" in labels
    omega = np.array([0.5, 1.0, 1.5])
    figure = spectrum(omega, [0.3, 0.3, 0.4], omega, [0.3, 0.3, 0.4], frequency_unit=5e5)
    assert "frequency [Hz]" in [child.get_xlabel() for ax in figure.axes for child in ax.child_axes]


@pytest.mark.ngspice
def test_the_band_top_of_a_chain_with_coupled_coils_is_above_its_modes(capsys: pytest.CaptureFixture[str]) -> None:
    """With neighbouring coils coupled by k the pass band reaches 2 / sqrt(1 - 2k) (largest at q = pi), not 2:
    the modes printed above "the band top" at k = 0.2 (1.29 against 1.01 MHz)."""
    assert main(["spectrum", "--case", "uniform-free", "--N", "20", "--coupling", "0.2", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    top = data["physical"]["band_top_Hz"]
    assert top == pytest.approx(2.0 / math.sqrt(1.0 - 0.4) * data["physical"]["frequency_unit_Hz"], rel=RTOL_ARITHMETIC)
    highest = max(mode["omega_Hz"] for mode in data["modes"] if mode.get("omega_Hz") is not None)
    assert 0.95 * top < highest < top
