"""The exact admittance a lossy AC run's envelope is compared with (lcchain.theory.spectrum.admittance_with_bound):
float64 with a running error bound, long double where that bound is too wide.  Checked against the test's own exact
rational evaluation (helpers.dense.rational_admittance): the error at each frequency is within the stated bound, in
both precisions, including at the resonances where the continued fraction cancels most."""

from __future__ import annotations

import numpy as np
import pytest
from helpers.dense import dense_modes, rational_admittance

from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.spectrum import admittance_with_bound


def _frequencies(chain: Chain, Q: float) -> np.ndarray:
    """Frequencies across the band, and on and around every resonance (a peak's half-power points) of the test's
    own dense eigensolution."""
    omega = dense_modes(chain)[0]
    omega = omega[omega > 0]
    top = 1.05 * float(omega[-1])
    return np.sort(np.concatenate((np.linspace(0.01, top, 23), omega, omega + 0.5 / Q, omega - 0.5 / Q)))


@pytest.mark.parametrize("case, N, Q, coupling", [("two-mass", 9, 1e3, 0.0), ("one-mass", 8, 1e4, 0.0),
                                                   ("two-mass", 7, 30.0, 0.2)])
def test_the_error_is_within_the_stated_bound_in_both_precisions(case, N, Q, coupling):
    chain = chain_for_case(case, N)
    if coupling:
        chain = Chain(chain.masses, chain.springs, coupling=coupling)
    omega = _frequencies(chain, Q)
    exact = np.array([rational_admittance(chain, w, Q) for w in omega])
    for rtol in (np.inf, 0.0):  # float64 everywhere, long double everywhere
        Y, bound = admittance_with_bound(chain, omega, Q, rtol=rtol)
        error = np.abs(Y - exact) / np.abs(exact)
        assert np.all(error <= bound), (rtol, float(np.max(error / bound)))
    fast, wide = admittance_with_bound(chain, omega, Q, rtol=np.inf)
    sharp, narrow = admittance_with_bound(chain, omega, Q, rtol=0.0)
    assert np.all(narrow < wide)  # long double's unit is 2^-11 of float64's
    mixed, bound = admittance_with_bound(chain, omega, Q, rtol=float(np.median(wide)))
    again = wide > np.median(wide)
    assert np.array_equal(mixed[~again], fast[~again]) and np.array_equal(mixed[again], sharp[again])
    assert np.array_equal(bound[~again], wide[~again])
