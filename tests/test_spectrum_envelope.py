"""The exact admittance a lossy AC run's envelope is compared with (lcchain.theory.spectrum.admittance_with_bound):
float64 with a running error bound, long double where that bound is too wide, double-double where long double's
still is.  Checked against the test's own exact rational evaluation (helpers.dense.rational_admittance and
exact_admittance): the error at each frequency is within the stated bound, in every arithmetic, including at the
resonances where the continued fraction cancels most."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from helpers.dense import dense_modes, exact_admittance, rational_admittance
from helpers.tolerances import DOUBLE_DOUBLE_SHARPER

from lcchain.compare.spectral import ENVELOPE_MARGIN, compare_envelope
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.spectrum import (
    _FEW_FREQUENCIES,
    _admittance_dd,
    _admittance_dd_few,
    _continued_fraction,
    admittance_with_bound,
)


def _chain(case: str, N: int, coupling: float) -> Chain:
    chain = chain_for_case(case, N)
    return Chain(chain.masses, chain.springs, coupling=coupling) if coupling else chain


def _frequencies(chain: Chain, Q: float) -> np.ndarray:
    """Frequencies across the band, and on and around every resonance (a peak's half-power points) of the test's
    own dense eigensolution."""
    omega = dense_modes(chain)[0]
    omega = omega[omega > 0]
    top = 1.05 * float(omega[-1])
    return np.sort(np.concatenate((np.linspace(0.01, top, 23), omega, omega + 0.5 / Q, omega - 0.5 / Q)))


@pytest.mark.parametrize("case, N, Q, coupling", [("two-mass", 9, 1e3, 0.0), ("one-mass", 8, 1e4, 0.0),
                                                   ("two-mass", 7, 30.0, 0.2)])
def test_the_error_is_within_the_stated_bound_in_every_arithmetic(case, N, Q, coupling):
    chain = _chain(case, N, coupling)
    omega = _frequencies(chain, Q)
    exact = np.array([rational_admittance(chain, w, Q) for w in omega])
    for rtol, start in ((np.inf, "float64"), (np.inf, "long double"), (0.0, "float64")):  # 0: double-double
        Y, bound = admittance_with_bound(chain, omega, Q, rtol=rtol, start=start)
        error = np.abs(Y - exact) / np.abs(exact)
        assert np.all(error <= bound), (rtol, start, float(np.max(error / bound)))
    fast, wide = admittance_with_bound(chain, omega, Q, rtol=np.inf)
    sharp, narrow = admittance_with_bound(chain, omega, Q, rtol=np.inf, start="long double")
    assert np.all(narrow < wide)  # long double's unit is 2^-11 of float64's
    mixed, bound = admittance_with_bound(chain, omega, Q, rtol=float(np.median(wide)))
    again = wide > np.median(wide)
    assert np.array_equal(mixed[~again], fast[~again]) and np.array_equal(mixed[again], sharp[again])
    assert np.array_equal(bound[~again], wide[~again])


def _relative_error(real: tuple[np.ndarray, np.ndarray], imag: tuple[np.ndarray, np.ndarray], k: int,
                    exact: tuple[Fraction, Fraction]) -> Fraction:
    """|Y - exact|^2 / |exact|^2 of the k-th double-double value, exactly (hi + lo taken as the rationals they are)."""
    dr = Fraction(float(real[0][k])) + Fraction(float(real[1][k])) - exact[0]
    di = Fraction(float(imag[0][k])) + Fraction(float(imag[1][k])) - exact[1]
    return (dr * dr + di * di) / (exact[0] * exact[0] + exact[1] * exact[1])


@pytest.mark.parametrize("case, N, Q, coupling", [("two-mass", 20, 10.0, 0.0), ("one-mass", 30, 1e4, 0.0),
                                                   pytest.param("two-mass", 40, 1e3, 0.0, marks=pytest.mark.slow),
                                                   pytest.param("two-mass", 60, 1e4, 0.0, marks=pytest.mark.slow),
                                                   ("uniform-bounded", 24, 100.0, 0.0), ("two-mass", 25, 30.0, 0.2)])
def test_the_double_double_value_is_within_its_bound_far_below_long_doubles(case, N, Q, coupling):
    """Before the rounding to float64: the double-double Y_11 against the exact rational one, at and between the
    peaks, within its own bound; that bound a unit ratio (2^-38) below long double's."""
    chain = _chain(case, N, coupling)
    omega = _frequencies(chain, Q)
    (real, imag), bound = _admittance_dd(chain, omega, Q)
    for k, w in enumerate(omega):
        squared = _relative_error(real, imag, k, exact_admittance(chain, float(w), Q))
        assert squared <= Fraction(float(bound[k])) ** 2, (float(w), float(squared) ** 0.5, float(bound[k]))
    long_double = _continued_fraction(chain, omega, Q, extended=True)[1]
    assert np.all(bound <= DOUBLE_DOUBLE_SHARPER * long_double)


def test_each_frequency_keeps_the_first_arithmetic_that_settles_it():
    """rtol between long double's bounds: the frequencies it settles are long double's bit for bit, the rest
    double-double's bit for bit, with double-double's (smaller) bound."""
    chain, Q = chain_for_case("one-mass", 30), 1e4
    omega = _frequencies(chain, Q)
    sharp, narrow = admittance_with_bound(chain, omega, Q, rtol=np.inf, start="long double")
    finest, tightest = admittance_with_bound(chain, omega, Q, rtol=0.0)
    rtol = float(np.median(narrow))
    mixed, bound = admittance_with_bound(chain, omega, Q, rtol=rtol, start="long double")
    again = narrow > rtol
    assert again.any() and not again.all()
    assert np.array_equal(mixed[~again], sharp[~again]) and np.array_equal(bound[~again], narrow[~again])
    assert np.array_equal(mixed[again], finest[again]) and np.all(bound[again] <= rtol)


def test_the_envelope_reference_is_ten_times_sharper_than_the_error_where_long_double_is_not():
    """A response off the exact one by 1e-13 (relative, at every frequency; no simulator: the comparison's choice of
    arithmetic alone), on a chain where long double's bound at the peaks is above a tenth of that: the comparison
    goes on to double-double there, and its bound ends ENVELOPE_MARGIN below the error it measures."""
    chain, Q = chain_for_case("one-mass", 30), 1e4
    omega = _frequencies(chain, Q)
    exact = np.array([complex(float(a), float(b)) for a, b in (exact_admittance(chain, float(w), Q) for w in omega)])
    offset = 1e-13
    y11 = exact * (1.0 + offset * np.exp(1j * np.arange(omega.size)))
    error, bound = compare_envelope(chain, omega, y11, Q)
    long_double = admittance_with_bound(chain, omega, Q, rtol=np.inf, start="long double")[1]
    assert float(np.max(long_double)) * ENVELOPE_MARGIN > error  # long double alone would not do
    assert bound * ENVELOPE_MARGIN <= error


@pytest.mark.parametrize("case, N, Q", [("two-mass", 40, 1e3), ("perfect", 30, None), ("one-mass", 25, 1e4)])
def test_a_few_frequencies_on_python_floats_give_the_same_double_doubles(case, N, Q):
    """The pass for a few frequencies (Python floats, one at a time) and the vectorised one: the same operations,
    the same values bit for bit, and within the bound of the exact rational admittance."""
    chain = chain_for_case(case, N)
    omega = _frequencies(chain, 1e3)[:: 7][:_FEW_FREQUENCIES]
    (real, imag), bound = _admittance_dd_few(chain, omega, Q)
    many = np.concatenate((omega, omega))  # above _FEW_FREQUENCIES: the vectorised pass
    (vector_real, vector_imag), _ = _admittance_dd(chain, many, Q)
    for ours, theirs in zip((*real, *imag), (*vector_real, *vector_imag), strict=True):
        assert np.array_equal(ours, theirs[:omega.size])
    if Q is not None:
        for k, w in enumerate(omega):
            squared = _relative_error(real, imag, k, exact_admittance(chain, float(w), Q))
            assert squared <= Fraction(float(bound[k])) ** 2
