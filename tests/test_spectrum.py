"""The ladder's spectrum from an AC analysis (issue 21): normal frequencies and mode weights in ngspice.

Checked against an independent dense eigen-solution of K u = omega^2 M u (tests/helpers/dense.py: scipy.linalg.eigh on
the full matrices), not lcchain's own modes.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers.dense import dense_modes
from helpers.tolerances import ATOL_SPECTRUM_P, RTOL_SPECTRUM_OMEGA
from scipy.linalg import eigh

from lcchain.cli.main import main
from lcchain.compare.grid import segment_frequencies
from lcchain.compare.spectral import sweep_grid
from lcchain.compare.spectrum import fit_spectrum, min_points
from lcchain.core.errors import ParameterError, SimulationError
from lcchain.runs.spectrum import OMEGA_WEIGHT_FLOOR, SpectrumOptions, measure_spectrum
from lcchain.spice.ngspice.raw import read_raw
from lcchain.theory.cases import chain_for_case
from lcchain.theory.exact import driven_modes


def test_the_fit_recovers_poles_and_residues_of_exact_samples():
    chain = chain_for_case("two-mass", 16)
    omega, P = dense_modes(chain)
    m, K = chain.masses, chain.springs
    S = np.diag(K[:-1] + K[1:]) - np.diag(K[1:-1], 1) - np.diag(K[1:-1], -1)
    squares, u = eigh(S, np.diag(m))
    a, b = u[0] ** 2, u[0] * u[-1]
    top = 1.05 * omega[-1]
    w = np.linspace(top / 600, top, 600)
    x = w * w
    y11 = 1j * w * (a[None, :] / (squares[None, :] - x[:, None])).sum(axis=1)
    yN1 = 1j * w * (b[None, :] / (squares[None, :] - x[:, None])).sum(axis=1)
    fit = fit_spectrum(w, y11, yN1)
    assert fit.omega.size == chain.N
    assert np.max(np.abs(fit.omega[1:] - omega[1:]) / omega[1:]) < RTOL_SPECTRUM_OMEGA
    assert np.max(np.abs(m[0] * fit.last - P)) < ATOL_SPECTRUM_P
    with pytest.raises(ParameterError, match="omega"):
        fit_spectrum(w[::-1], y11, yN1)


@pytest.mark.ngspice
@pytest.mark.parametrize("chain", [chain_for_case("two-mass", 20), chain_for_case("perfect", 30),
                                   chain_for_case("uniform-bounded", 24), chain_for_case("perfect", 20, 1),
                                   chain_for_case("two-mass", 20).with_coupling(0.03),
                                   chain_for_case("one-mass", 60)],
                         ids=["two-mass-20", "perfect-30", "walls-24", "perfect-walled-20", "coupled-20",
                              "one-mass-60"])
def test_ngspice_spectrum_matches_a_dense_eigen_solution(chain):
    report = measure_spectrum(chain)
    omega, P = dense_modes(chain)
    seen = np.isfinite(report.omega)
    strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
    assert np.all(seen[strong])  # every mode that weighs at the ends is found
    error = np.abs(report.omega[strong] - omega[strong]) / np.where(omega[strong] > 0, omega[strong], 1.0)
    assert np.max(error) < RTOL_SPECTRUM_OMEGA
    assert np.max(np.abs(np.nan_to_num(report.P) - P)) < ATOL_SPECTRUM_P  # an unseen mode counts with P = 0
    assert report.max_rel_error_omega < RTOL_SPECTRUM_OMEGA and report.max_abs_error_P < ATOL_SPECTRUM_P


@pytest.mark.ngspice
def test_a_perfect_cradles_spacing_is_constant_in_the_circuit():
    """The headline of a perfect cradle, measured in ngspice: its normal frequencies are equally spaced."""
    report = measure_spectrum(chain_for_case("perfect", 24))
    strong = report.resolved & np.isfinite(report.omega)
    spacing = np.diff(report.omega[strong])
    assert np.max(np.abs(spacing - spacing.mean())) / spacing.mean() < 10 * RTOL_SPECTRUM_OMEGA
    two_mass = np.diff(measure_spectrum(chain_for_case("two-mass", 24)).omega)
    assert np.max(np.abs(two_mass - two_mass.mean())) / two_mass.mean() > 0.1  # the optimum's is not


@pytest.mark.ngspice
def test_spectrum_command(tmp_path, capsys):
    plot = tmp_path / "pk.png"
    assert main(["spectrum", "--case", "two-mass", "--N", "20", "--json", "--plot", str(plot)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert len(data["modes"]) == 20 and plot.stat().st_size > 10_000
    first = data["modes"][0]
    assert {"omega", "P", "omega_theory", "P_theory"} <= set(first) and first["omega_theory"] == 0.0
    assert data["max_rel_error_omega"] < RTOL_SPECTRUM_OMEGA and data["max_abs_error_P"] < ATOL_SPECTRUM_P
    needed = min_points(driven_modes(chain_for_case("two-mass", 20)).omega, data["omega_max"])
    assert abs(needed - min_points(dense_modes(chain_for_case("two-mass", 20))[0], data["omega_max"])) <= 2
    assert main(["spectrum", "--case", "two-mass", "--N", "20", "--points", str(needed - 1)]) == 2
    error = capsys.readouterr().err
    assert f"at least {needed}" in error and "--points" in error
    assert main(["spectrum", "--case", "two-mass", "--N", "2500"]) == 2
    assert "--N" in capsys.readouterr().err
    # priced before anything runs: the default sweep names the chain, a sweep asked for names --points
    assert main(["spectrum", "--case", "two-mass", "--N", "400", "--max-time", "1"]) == 2
    assert "--N = 400" in capsys.readouterr().err
    assert main(["spectrum", "--case", "two-mass", "--N", "400", "--max-time", "1", "--points", "900000"]) == 2
    assert "--points = 900000" in capsys.readouterr().err


def test_read_raw_reads_an_ac_plots_complex_columns():
    header = (b"Title: t\nDate: d\nPlotname: AC Analysis\nFlags: complex\nNo. Variables: 2\nNo. Points: 2\n"
              b"Variables:\n\t0\tfrequency\tfrequency\n\t1\ti(l1)\tcurrent\nBinary:\n")
    values = np.array([1.0 + 9e38j, 0.5 - 2j, 2.0 + 9e38j, 0.25 - 1j])
    columns = read_raw(header + values.tobytes(), "ac")
    assert np.array_equal(columns["frequency"].real, [1.0, 2.0])
    assert np.array_equal(columns["i(l1)"], [0.5 - 2j, 0.25 - 1j])
    with pytest.raises(SimulationError, match="no transient analysis"):
        read_raw(header + values.tobytes())


@pytest.mark.ngspice
def test_the_spectrum_reports_its_progress_engine_then_fit():
    """Long spectra (N = 2000: 6 s of ngspice, then 23 s of fit) show progress: 0, the engine's share of the priced
    work once the engine is done, 1 after the fit."""
    heard: list[float] = []
    measure_spectrum(chain_for_case("two-mass", 20), progress=heard.append)
    assert heard[0] == 0.0 and heard[-1] == 1.0 and len(heard) == 3 and 0.0 < heard[1] < 1.0


@pytest.mark.parametrize(("case", "N"), [("two-mass", 3), ("perfect", 10), ("uniform-bounded", 5), ("two-mass", 60)])
def test_the_sweep_ends_at_the_omega_max_it_reports(case, N):
    """The segments together cover (0, omega_max], and no sample lies beyond it (for small N the last segment
    ended half a spacing past the top pole, beyond the omega_max reported and keyed)."""
    omega = dense_modes(chain_for_case(case, N))[0]
    segments, points, omega_max = sweep_grid(omega)
    assert segments[0][1] == 0.0 and segments[-1][2] == omega_max > omega[-1]
    assert all(a[2] == b[1] for a, b in zip(segments[:-1], segments[1:], strict=True))
    sampled = segment_frequencies(segments)
    assert sampled.size == points and sampled.max() <= omega_max and np.all(np.diff(sampled) > 0)


@pytest.mark.ngspice
def test_no_segment_is_one_ngspice_cannot_sweep() -> None:
    # ngspice 39's ".ac lin 2 f1 f2" gives one frequency: a segment of two made the two-mass N = 8 sweep of 80
    # points fail ("ngspice returned 79 frequencies"). Every segment has three or more, and the run gets them all.
    from lcchain.compare.grid import MIN_SEGMENT_POINTS
    from lcchain.compare.spectral import sweep_grid
    from lcchain.theory.exact import driven_modes

    for case, N in (("two-mass", 8), ("perfect", 12), ("one-mass", 30)):
        omega = driven_modes(chain_for_case(case, N)).omega
        for points in (None, 60, 80, 97):
            try:
                segments, total, _ = sweep_grid(omega, points)
            except ParameterError:  # fewer than the poles need: refused before any segment is made
                continue
            assert min(n for n, _, _ in segments) >= MIN_SEGMENT_POINTS
            assert total == sum(n for n, _, _ in segments)
    report = measure_spectrum(chain_for_case("two-mass", 8), options=SpectrumOptions(points=80))
    assert report.points == 80
