"""The spectrum with losses and at large N (issue 21, section 1).

Checked against an independent dense eigen-solution of K u = omega^2 M u written out here (scipy.linalg.eigh on
the full matrices), not lcchain's own modes: with the series resistors L_i / (Q tau) every mode keeps its shape
and P_n, and decays at gamma = 1/Q, so its poles are -gamma/2 +- j sqrt(omega_n^2 - gamma^2/4) and its quality
factor omega_n Q (the damped oscillator of lcchain.theory.response's module docstring).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_SPECTRUM_GAMMA,
    ATOL_SPECTRUM_P,
    ATOL_SPECTRUM_RESPONSE,
    RTOL_SPECTRUM_OMEGA,
    RTOL_SPECTRUM_POLE,
    RTOL_SPECTRUM_Q,
)
from scipy.linalg import eigh

from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import ac_netlist_text
from lcchain.cli.main import main
from lcchain.compare.grid import min_points, segment_frequencies, sweep_segments
from lcchain.compare.spectrum import fit_spectrum
from lcchain.core.errors import ParameterError
from lcchain.runs.spectrum import OMEGA_WEIGHT_FLOOR, SpectrumOptions, measure_spectrum
from lcchain.spice.ngspice.raw import read_raw
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain


def _dense(chain: Chain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """omega_n^2, a_n = u_1n^2 and b_n = u_1n u_Nn (M-orthonormal u) from the full matrices (no coupling)."""
    m, K = chain.masses, chain.springs
    S = np.diag(K[:-1] + K[1:]) - np.diag(K[1:-1], 1) - np.diag(K[1:-1], -1)
    squares, u = eigh(S, np.diag(m))
    squares = np.clip(squares, 0.0, None)
    if chain.is_free:
        squares[0] = 0.0
    return squares, u[0] ** 2, u[0] * u[-1]


def _samples(chain: Chain, Q: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact Y_11 Z0 and Y_N1 Z0 of the lossy ladder, sum_n (a_n, b_n) s / (s^2 + s/Q + omega_n^2), on lcchain's
    grid for the dense frequencies."""
    squares, a, b = _dense(chain)
    omega = np.sqrt(squares)
    segments = sweep_segments(omega, 1.05 * omega[-1], 8)
    w = segment_frequencies(segments)
    s = 1j * w[:, None]
    D = s * s + s / Q + squares[None, :]
    return w, (a[None, :] * s / D).sum(axis=1), (b[None, :] * s / D).sum(axis=1)


@pytest.mark.parametrize(("chain", "Q"), [(Chain(np.ones(4), np.array([0.0, 1.0, 0.002, 3.0, 0.0])), 5.0),
                                          (chain_for_case("two-mass", 16), 50.0),
                                          (chain_for_case("two-mass", 16), 1e4)], ids=["overdamped", "Q50", "Q1e4"])
def test_the_lossy_fit_recovers_every_section_of_exact_samples(chain, Q):
    """Two loosely tied pairs of masses at Q = 5: their slow mode (omega = 0.045) is overdamped (omega < 1/(2Q)),
    two real poles, and the zero mode one real pole at -1/Q: every kind of section is found."""
    squares, a, b = _dense(chain)
    assert Q > 10 or np.count_nonzero((squares > 0) & (squares < 0.25 / Q**2)) == 1
    w, y11, yN1 = _samples(chain, Q)
    fit = fit_spectrum(w, y11, yN1, lossy=True)
    omega = np.sqrt(squares)
    assert fit.omega.size == chain.N
    assert np.max(np.abs(fit.omega - omega) / np.where(omega > 0, omega, 1.0)) < RTOL_SPECTRUM_OMEGA
    weighty = a >= OMEGA_WEIGHT_FLOOR  # gamma_n comes from Y_11: a mode barely felt at loop 1 is placed less well
    assert np.max(np.abs(fit.gamma - 1.0 / Q)[weighty]) * Q < RTOL_SPECTRUM_Q
    assert np.max(np.abs(chain.masses[0] * (fit.last - b))) < ATOL_SPECTRUM_P
    t = np.linspace(0.0, 40.0, 400)
    exact = chain.masses[0] * np.array([(b * _oscillator(squares, 1.0 / Q, time)).sum() for time in t])
    assert np.max(np.abs(fit.impulse(t, chain.masses[0] * fit.last) - exact)) < ATOL_SPECTRUM_RESPONSE
    with pytest.raises(ParameterError, match="omega"):
        fit_spectrum(w[::-1], y11, yN1, lossy=True)


def _oscillator(squares: np.ndarray, gamma: float, t: float) -> np.ndarray:
    """s'(t) of x'' + gamma x' + omega^2 x = delta (s(0) = 0, s'(0) = 1), from its two roots."""
    root = np.sqrt(gamma * gamma / 4 - squares + 0j)
    fast, slow = -gamma / 2 - root, -gamma / 2 + root
    return np.real((slow * np.exp(slow * t) - fast * np.exp(fast * t)) / (slow - fast))


@pytest.mark.ngspice
@pytest.mark.parametrize(("chain", "Q"), [(chain_for_case("two-mass", 20), 100.0),
                                          (chain_for_case("two-mass", 20), 10.0),
                                          (chain_for_case("perfect", 20, 1), 1000.0),
                                          (chain_for_case("uniform-bounded", 24), 1e4)],
                         ids=["two-mass-20-Q100", "two-mass-20-Q10", "perfect-walled-20-Q1000", "walls-24-Q1e4"])
def test_lossy_spectrum_in_ngspice_matches_a_dense_eigen_solution(chain, Q):
    report = measure_spectrum(chain, options=SpectrumOptions(Q=Q))
    squares, _, b = _dense(chain)
    omega, P = np.sqrt(squares), chain.masses[0] * b
    strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
    assert np.all(np.isfinite(report.omega[strong]))
    assert np.max(np.abs(report.omega[strong] - omega[strong]) / np.where(omega > 0, omega, 1.0)[strong]) \
        < RTOL_SPECTRUM_OMEGA
    assert np.max(np.abs(np.nan_to_num(report.P) - P)) < ATOL_SPECTRUM_P  # P_n unchanged by the losses
    assert np.max(np.abs(report.gamma[strong] - 1.0 / Q)) < ATOL_SPECTRUM_GAMMA
    moving = strong & (omega > 0)
    if Q <= 1000:
        assert np.max(np.abs(report.Q[moving] - omega[moving] * Q) / (omega[moving] * Q)) < RTOL_SPECTRUM_Q
        assert report.max_rel_error_Q < RTOL_SPECTRUM_Q
    gamma = 1.0 / Q
    poles = -gamma / 2 + 1j * np.sqrt(squares - gamma * gamma / 4 + 0j)
    assert np.max(np.abs(report.poles[strong] - poles[strong]) / np.abs(poles[strong])) < RTOL_SPECTRUM_POLE
    assert report.response_error is not None and report.response_error < ATOL_SPECTRUM_RESPONSE
    assert report.losses == Q


@pytest.mark.ngspice
@pytest.mark.slow  # 4 s: the segmented sweep's fast kin stay in the README's test command
def test_a_large_chain_on_the_segmented_sweep():
    """Two-mass N = 400: an even sweep would need ~80,000 frequencies (its smallest spacing, at the top of the band,
    shrinks like 1/N^2); the segments hold about eight per spacing wherever the poles are."""
    chain = chain_for_case("two-mass", 400)
    report = measure_spectrum(chain)
    squares, _, b = _dense(chain)
    omega, P = np.sqrt(squares), chain.masses[0] * b
    even = 4 * report.omega_max / np.min(np.diff(omega[1:]))
    assert report.segments > 1 and report.points < even / 10
    strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
    assert np.all(np.isfinite(report.omega[strong]))
    assert np.max(np.abs(report.omega[strong][1:] - omega[strong][1:]) / omega[strong][1:]) < RTOL_SPECTRUM_OMEGA
    assert np.max(np.abs(np.nan_to_num(report.P) - P)) < ATOL_SPECTRUM_P


def test_the_sweep_segments_share_the_points_asked_for():
    omega = np.sqrt(_dense(chain_for_case("two-mass", 60))[0])
    top = 1.05 * omega[-1]
    needed = min_points(omega, top)
    for points in (needed, 3 * needed + 7):
        segments = sweep_segments(omega, top, 4, points)
        assert sum(n for n, _, _ in segments) == points and all(n >= 2 for n, _, _ in segments)
        edges = [edge for _, lo, hi in segments for edge in (lo, hi)]
        assert edges[0] == 0.0 and edges[-1] == top and all(np.diff(edges) >= 0)
        w = segment_frequencies(segments)
        gaps = np.abs(omega[1:, None] - w[None, :])  # no frequency on a pole: segments meet between two
        assert np.min(gaps) > 0
    text = ac_netlist_text(Ladder(chain_for_case("two-mass", 60), 1e-6, 1e-9), segments=segments)
    assert text.count("\n.ac lin ") == len(segments)
    with pytest.raises(ParameterError, match=r"segments\[1\]"):
        ac_netlist_text(Ladder(chain_for_case("two-mass", 60), 1e-6, 1e-9), segments=[(20, 0.0, 1.0), (20, 0.5, 2.0)])


def test_read_raw_joins_the_plots_of_several_ac_cards():
    header = (b"Title: t\nDate: d\nPlotname: AC Analysis\nFlags: complex\nNo. Variables: 2\nNo. Points: 2\n"
              b"Variables:\n\t0\tfrequency\tfrequency\n\t1\ti(l1)\tcurrent\nBinary:\n")
    first = np.array([3.0 + 0j, 1j, 4.0 + 0j, 2j])
    second = np.array([1.0 + 0j, 3j, 2.0 + 0j, 4j])
    data = header + first.tobytes() + header + second.tobytes()
    assert np.array_equal(read_raw(data, "ac")["frequency"].real, [1.0, 2.0])  # the last, as before
    joined = read_raw(data, "ac", joined=True)
    assert np.array_equal(joined["frequency"].real, [3.0, 4.0, 1.0, 2.0])
    assert np.array_equal(joined["i(l1)"], [1j, 2j, 3j, 4j])


@pytest.mark.ngspice
def test_spectrum_command_with_losses(tmp_path, capsys):
    assert main(["spectrum", "--case", "two-mass", "--N", "12", "--Q", "100", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["Q"] == 100.0 and data["max_rel_error_Q"] < RTOL_SPECTRUM_Q
    assert {"Q", "Q_theory", "gamma"} <= set(data["modes"][1])
    assert main(["spectrum", "--case", "two-mass", "--N", "12", "--Q", "100"]) == 0
    assert "Q_n (circuit)" in capsys.readouterr().out
    for bad in ("0", "-1", "inf", "nan", "ten"):
        assert main(["spectrum", "--case", "two-mass", "--N", "12", "--Q", bad]) == 2
        assert "--Q" in capsys.readouterr().err
    # coupled coils with losses are no chain: compared with the circuit's own poles, each mode's own Q_n
    assert main(["spectrum", "--case", "two-mass", "--N", "12", "--Q", "100", "--coupling", "0.03"]) == 0
    assert "Q_n (circuit)" in capsys.readouterr().out
    # priced as an AC analysis: frequencies and unknowns (3 N with the resistors), not time points
    assert main(["spectrum", "--case", "two-mass", "--N", "100", "--Q", "1000", "--max-time", "0.9"]) == 2
    error = capsys.readouterr().err
    assert "frequencies x 300 unknowns" in error and "time points" not in error
    # beyond the 100 masses the rational fits were measured on, the fit from theory's lossy poles takes losses: a
    # lossy N = 1000 is planned and priced (here refused by its price alone), not refused by its N
    assert main(["spectrum", "--case", "two-mass", "--N", "1000", "--Q", "100", "--max-time", "0.9"]) == 2
    error = capsys.readouterr().err
    assert "--max-time" in error and "frequencies x 3000 unknowns" in error and "> 100" not in error
