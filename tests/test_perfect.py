"""Perfect cradles for any N, designed from their spectrum (issue 13).

Every designed chain is checked by means that share nothing with the design:
its frequencies by numpy's dense SVD of the chain's scaled incidence matrix
(the design uses scipy's tridiagonal eigen-solvers on a zero-diagonal Jacobi
matrix), its transmission by lcchain's exact diagonalisation of B, and the
small chains against the paper's fractions.
"""

from __future__ import annotations

import json
import math
import pickle
import subprocess
import sys
from fractions import Fraction as F

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_DESIGNED_LOSS,
    ATOL_PERFECT_TRANSFER,
    RTOL_ARRIVAL_TIMES_OMEGA,
    RTOL_DESIGNED_ARRIVAL_TIME,
    RTOL_PERFECT_FRACTIONS,
    RTOL_PERFECT_SPECTRUM,
    RTOL_SPECTRUM_OF_AGAINST_SVD,
    RTOL_STIELTJES_NEWTON,
)

import lcchain
from lcchain.core.errors import ParameterError
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.design import optimal_two_mass
from lcchain.theory.perfect import chain_from_spectrum, perfect_design, spectrum_of
from lcchain.theory.spectrum import transmission_amplitude

#: Table II's N = 4 optimum as Nelder-Mead finds it (xatol 1e-7 on log r, log w; observed 2e-8).
RTOL_OPTIMUM = 1e-6


def svd_frequencies(chain: Chain) -> np.ndarray:
    """The chain's frequencies as the singular values of A (N x (N+1)), B = A A^T: column e is spring e.

    A[i, e] = +-sqrt(K_e / m_i) for the two masses spring e joins (one at a wall).  Dense LAPACK SVD
    (numpy's gesdd): nothing in common with the design's tridiagonal solvers.
    """
    m, K = chain.masses, chain.springs
    N = chain.N
    A = np.zeros((N, N + 1))
    for e in range(N + 1):
        if e >= 1:
            A[e - 1, e] = math.sqrt(K[e] / m[e - 1])
        if e < N:
            A[e, e] = -math.sqrt(K[e] / m[e])
    return np.sort(np.linalg.svd(A, compute_uv=False))[-N:]


def assert_spectrum(design, rtol=RTOL_PERFECT_SPECTRUM):
    """Frequencies right to rtol relative (the free chain's zero mode: relative to the spacing)."""
    measured = svd_frequencies(design.chain)
    wanted = design.frequencies
    spacing = wanted[1] - wanted[0]
    scale = np.where(wanted > 0, wanted, spacing)
    worst = np.max(np.abs(measured - wanted) / scale)
    assert worst < rtol, f"frequencies off by {worst:.3g} relative"
    # and they are the prescribed equally spaced comb: omega_n = (n - 1 + 2 j) pi / T
    comb = (np.arange(design.N) + 2 * design.walls) * math.pi / design.t_arrival
    np.testing.assert_allclose(wanted, comb, rtol=rtol)


def assert_shape(design):
    """Mirror symmetric (exactly), positive, bulk units (central mass and central spring 1)."""
    m, K = design.chain.masses, design.chain.springs
    np.testing.assert_array_equal(m, m[::-1])
    np.testing.assert_array_equal(K, K[::-1])
    assert np.all(m > 0) and np.all(K[1:-1] > 0)
    assert (K[0] == 0) == (design.walls == 0)
    assert m[design.N // 2] == 1.0 and K[(design.N + 1) // 2] == 1.0


# ------------------------------------------------------------------ the paper's perfect chains
def test_three_masses_from_the_spectrum():
    """Sec. II.C: frequencies 0, dw, 2 dw give masses (3/2, 1, 3/2), springs (1, 1), T = sqrt(3/2) pi."""
    chain, scale = chain_from_spectrum([0.0, 1.0, 2.0])
    np.testing.assert_allclose(chain.masses, [1.5, 1.0, 1.5], rtol=RTOL_PERFECT_FRACTIONS)
    np.testing.assert_allclose(chain.springs, [0.0, 1.0, 1.0, 0.0], rtol=RTOL_PERFECT_FRACTIONS)
    assert math.pi / scale == pytest.approx(math.sqrt(1.5) * math.pi, rel=RTOL_PERFECT_FRACTIONS)


def test_four_masses_from_the_spectrum_are_fig_cradle4():
    """Fig. cradle4: end masses 5/3 of the inner ones, end springs 5/6; T = sqrt(3) pi in these units."""
    chain, scale = chain_from_spectrum([0.0, 1.0, 2.0, 3.0])
    np.testing.assert_allclose(chain.masses, [5 / 3, 1, 1, 5 / 3], rtol=RTOL_PERFECT_FRACTIONS)
    np.testing.assert_allclose(chain.springs, [0, 5 / 6, 1, 5 / 6, 0], rtol=RTOL_PERFECT_FRACTIONS)
    assert math.pi / scale == pytest.approx(math.sqrt(3) * math.pi, rel=RTOL_PERFECT_FRACTIONS)


def test_four_masses_scaled_by_eleven_twelfths_are_table_two_and_sec_ii_c():
    """Sec. II.C prints m1 = 55/36, m2 = 11/12: every mass of Fig. cradle4's chain times 11/12; Table II's
    N = 4 optimum (r*, w*) is that chain too."""
    bulk, paper = Chain.perfect(4, bulk=True), Chain.perfect(4)
    ratio = F(11, 12)
    for m_bulk, m_paper in zip(bulk.masses, paper.masses, strict=True):
        assert F(m_paper) == pytest.approx(F(m_bulk) * ratio, rel=RTOL_PERFECT_FRACTIONS)
    np.testing.assert_array_equal(bulk.springs, paper.springs)
    table = optimal_two_mass(4).chain
    np.testing.assert_allclose(table.masses, bulk.masses * 11 / 12, rtol=RTOL_OPTIMUM)
    np.testing.assert_allclose(table.springs, bulk.springs, rtol=RTOL_OPTIMUM)


def test_five_masses_from_the_spectrum_are_the_appendix_chain():
    """Appendix A: w = 2/5, t = 8/5, x^2 = 7/25, y^2 = 9/10, i.e. (35/18, 10/9, 1, 10/9, 35/18), K12 = 7/9."""
    chain, scale = chain_from_spectrum([0.0, 1.0, 2.0, 3.0, 4.0])
    m, K = chain.masses, chain.springs
    w, t = K[1] / m[0], (1 + K[1]) / m[1]
    x2, y2 = K[1] ** 2 / (m[0] * m[1]), 1 / m[1]
    assert (w, t, x2, y2) == pytest.approx((2 / 5, 8 / 5, 7 / 25, 9 / 10), rel=RTOL_PERFECT_FRACTIONS)
    np.testing.assert_allclose(m, Chain.perfect(5).masses, rtol=RTOL_PERFECT_FRACTIONS)
    assert math.pi / scale == pytest.approx(math.sqrt(5) * math.pi, rel=RTOL_PERFECT_FRACTIONS)


@pytest.mark.parametrize("N", [3, 4, 5])
def test_small_designs_print_the_exact_fractions(N):
    design = perfect_design(N)
    assert design.chain == Chain.perfect(N, bulk=True)
    assert chain_for_case("perfect", N) == design.chain


def test_closed_form_in_fractions():
    """The free family's H is Krawtchouk's, a_k = sqrt(k (M - k)) / 2 with M = 2N - 1 sites: mass ratios
    m_(i+1)/m_i = a_(2i)^2 / a_(2i+1)^2, springs K_(i,i+1) = a_(2i)^2 m_i, all rational; N = 10 in fractions."""
    N, M = 10, 19
    a2 = [F(k * (M - k), 4) for k in range(1, M)]  # a_k^2, k = 1 .. M - 1
    masses, springs = [F(1)], []
    for i in range(1, N):
        springs.append(a2[2 * i - 2] * masses[-1])  # K_(i,i+1) = a_(2i-1)^2 m_i (free-chain indexing)
        masses.append(masses[-1] * a2[2 * i - 2] / a2[2 * i - 1])
    central_m, central_k = masses[N // 2], springs[(N + 1) // 2 - 1]  # springs[0] is K_12
    design = perfect_design(N)
    np.testing.assert_allclose(design.chain.masses, [float(m / central_m) for m in masses],
                               rtol=RTOL_PERFECT_FRACTIONS)
    np.testing.assert_allclose(design.chain.springs[1:-1], [float(k / central_k) for k in springs],
                               rtol=RTOL_PERFECT_FRACTIONS)


# ------------------------------------------------------------------ any N, free and with walls
@pytest.mark.parametrize(("N", "walls"), [(6, 0), (7, 0), (50, 0), (201, 0),
                                          pytest.param(2000, 0, marks=pytest.mark.slow),  # 6 s; N = 2000 below
                                          (6, 1), (7, 2), (100, 1), (101, 3), (300, 5)])
def test_designed_chain_has_the_prescribed_spectrum(N, walls):
    design = perfect_design(N, walls)
    assert_shape(design)
    assert_spectrum(design)
    assert abs(design.delta) < ATOL_PERFECT_TRANSFER


@pytest.mark.parametrize(("N", "walls"), [(6, 0), (50, 0), (2000, 0), (7, 1), (200, 1), (60, 3)])
def test_transmits_perfectly_at_T(N, walls):
    """alpha_N(T) = 1 from lcchain's own diagonalisation of B; not at 0.99 T; back at mass 1 at 2T."""
    design = perfect_design(N, walls)
    T = design.t_arrival
    alpha = transmission_amplitude(design.chain, np.array([T, 3 * T, 0.99 * T]), method="exact")
    assert alpha[0] == pytest.approx(1.0, abs=ATOL_PERFECT_TRANSFER)
    assert alpha[1] == pytest.approx(1.0, abs=ATOL_PERFECT_TRANSFER)
    assert alpha[2] < 1 - 1e-4


def test_hard_case_two_thousand_masses_with_walls():
    """N = 2000 tied to walls (j = 1): Newton on 2000 x 2000 matrices; mass ratio ~2e4."""
    design = perfect_design(2000, 1)
    assert_shape(design)
    assert_spectrum(design)
    spread = design.spread()
    assert spread["distinct_masses"] == 1000 and spread["distinct_springs"] == 1001
    assert transmission_amplitude(design.chain, design.t_arrival, method="exact") == pytest.approx(
        1.0, abs=ATOL_PERFECT_TRANSFER)


def test_spread_counts_the_values_a_builder_needs():
    """About N/2 distinct masses and springs (mirror symmetry), against four for the quasi-uniform chain."""
    spread = perfect_design(50).spread()
    assert spread["distinct_masses"] == 25 and spread["distinct_springs"] == 25
    assert spread["mass_min"] == 1.0 and spread["spring_max"] == 1.0
    assert spread["mass_max"] > 1.0 and spread["spring_min"] < 1.0


def test_spectrum_of_is_the_chain_spectrum():
    design = perfect_design(40, 1)
    np.testing.assert_allclose(spectrum_of(design.chain), svd_frequencies(design.chain), rtol=RTOL_SPECTRUM_OF_AGAINST_SVD)


@pytest.mark.parametrize(("frequencies", "free"), [(np.arange(2.0, 42.0), False),
                                                    (np.array([0.7, 1.9, 2.2, 3.5, 4.1, 6.0]), True)])
def test_the_recursion_and_newton_continuation_agree(frequencies, free):
    """Two independent routes to the same chain: the half recursion, and Newton continuation from the
    closed form (lcchain's fallback), meet to rounding."""
    from lcchain.theory.perfect import _continuation, _stieltjes, _tolerance

    N = frequencies.size + (1 if free else 0)
    sites = 2 * N - 1 if free else 2 * N + 1
    by_recursion = _stieltjes(frequencies)
    by_newton = _continuation(frequencies, free, _tolerance(sites))
    inner = by_newton[1:-1] if free else by_newton
    np.testing.assert_allclose(by_recursion, inner[: inner.size // 2], rtol=RTOL_STIELTJES_NEWTON)


def test_a_spectrum_given_by_hand():
    """Any distinct frequencies have a chain: a generic one, round trip through the chain's spectrum."""
    wanted = np.array([0.0, 0.7, 1.9, 2.2, 3.5, 4.1, 6.0])
    chain, scale = chain_from_spectrum(wanted)
    assert chain.is_symmetric and chain.is_free
    np.testing.assert_allclose(svd_frequencies(chain)[1:], wanted[1:] * scale, rtol=RTOL_PERFECT_SPECTRUM)


# ------------------------------------------------------------------ refusals
@pytest.mark.parametrize(("frequencies", "field", "words"), [
    ([0.0, 1.0, 1.0, 2.0], "frequencies[2]", "strictly ascending"),
    ([0.0, 2.0, 1.0], "frequencies[2]", "strictly ascending"),
    ([-1.0, 1.0, 2.0], "frequencies[0]", ">= 0"),
    ([0.0, 1.0], "frequencies", "at least 3"),
    ([0.0, float("nan"), 2.0], "frequencies[1]", "finite"),  # the value that is not finite, named
    ([0.0, 1.0, float("inf")], "frequencies[2]", "finite"),
    ("0 1 2", "frequencies", "ascending"),
])
def test_spectra_without_a_chain_are_refused(frequencies, field, words):
    with pytest.raises(ParameterError) as info:
        chain_from_spectrum(frequencies)
    assert info.value.field == field
    assert words in str(info.value)


@pytest.mark.parametrize(("N", "walls", "field"), [(2, 0, "N"), (20001, 0, "N"), (10, -1, "walls"),
                                                   (20001, 1, "N"), (4.5, 0, "N"), (10, True, "walls")])
def test_bad_sizes_are_refused(N, walls, field):
    with pytest.raises(ParameterError) as info:
        perfect_design(N, walls)
    assert info.value.field == field


def test_design_pickles():
    design = perfect_design(12, 1)
    again = pickle.loads(pickle.dumps(design))
    assert again.chain == design.chain and again.t_arrival == design.t_arrival


# ------------------------------------------------------------------ the command line
def _lcchain(*argv):
    return subprocess.run([sys.executable, "-m", "lcchain", *argv], capture_output=True, text=True, timeout=300)


def test_design_json_for_any_N():
    proc = _lcchain("design", "--case", "perfect", "--N", "40", "--json")
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    assert data["N"] == 40 and data["case"] == "perfect" and data["walls"] == 0
    assert len(data["masses"]) == 40 and len(data["springs"]) == 41
    assert data["springs"][0] == 0.0 == data["springs"][-1]
    assert abs(data["delta"]) < ATOL_DESIGNED_LOSS
    assert data["frequencies"][1] * data["t_arrival"] == pytest.approx(math.pi, rel=RTOL_ARRIVAL_TIMES_OMEGA)
    assert data["spread"]["distinct_masses"] == 20
    assert Chain(data["masses"], data["springs"]) == perfect_design(40).chain


def test_design_with_walls_prints_a_table():
    proc = _lcchain("design", "--case", "perfect", "--N", "9", "--walls", "1")
    assert proc.returncode == 0, proc.stderr
    assert "tied to walls (j = 1)" in proc.stdout and "arrival time T" in proc.stdout
    assert len([line for line in proc.stdout.splitlines() if line.strip().split(" ")[0].isdigit()]) == 10


def test_netlist_of_a_long_perfect_chain():
    proc = _lcchain("netlist", "--case", "perfect", "--N", "60")
    assert proc.returncode == 0, proc.stderr
    inductors = [line for line in proc.stdout.splitlines() if line.startswith("L")]
    assert len(inductors) == 60
    values = sorted({line.split()[3] for line in inductors})
    assert len(values) == 30  # N/2 distinct inductors


# ------------------------------------------------------------------ ngspice
@pytest.mark.ngspice
@pytest.mark.parametrize(("N", "walls"), [(100, 0), (30, 1)])
def test_ngspice_reaches_one(N, walls):
    """The ladder of a designed chain carries the whole pulse: I_N/I0 at the arrival reaches 1 within the
    integration error lcchain predicts for the step (and the arrival is where theory puts it)."""
    chain = chain_for_case("perfect", N, walls)
    report = lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.02, transits=1))
    arrival = report.comparison.arrivals[0]
    assert arrival.peak_theory == pytest.approx(1.0, abs=ATOL_PERFECT_TRANSFER)
    assert abs(arrival.peak_sim - 1.0) <= report.predicted_error
    assert arrival.t_theory == pytest.approx(perfect_design(N, walls).t_arrival, rel=RTOL_DESIGNED_ARRIVAL_TIME)
    assert report.integration_error <= report.predicted_error
