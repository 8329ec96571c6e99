"""The first-arrival peak's sensitivities (lcchain.theory.sensitivity) against central finite differences of
lcchain's own exact theory (first_arrival of the perturbed chain: an independent route, a peak search on new
modes, where the sensitivities perturb the nominal modes)."""

import numpy as np
import pytest

from lcchain.circuit.effects import with_walls
from lcchain.core.budget import Budget, sensitivity_estimate
from lcchain.core.errors import ParameterError
from lcchain.theory.arrivals import first_arrival
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.sensitivity import SENSITIVITY_MAX_N, peak_sensitivity

#: Relative step of the finite differences: truncation h^2 |p'''| / 6 ~ 1e-11 and rounding eps / h ~ 1e-11.
FD_STEP = 1e-5
#: What the finite differences justify on dp/d ln x: a hundred times their truncation and rounding (the
#: differences seen are 4e-11 to 2e-10).
FD_TOLERANCE = 1e-8


def _peak(masses, springs, coupling):
    return first_arrival(Chain(masses, springs, coupling=coupling)).peak


def _central(chain):
    """dp/d ln m_i and dp/d ln K_j by central differences of first_arrival (free ends: 0)."""
    h = FD_STEP
    relative_m, relative_k = [], []
    for i in range(chain.N):
        m_up, m_down = np.array(chain.masses), np.array(chain.masses)
        m_up[i] *= 1 + h
        m_down[i] *= 1 - h
        relative_m.append((_peak(m_up, chain.springs, chain.coupling)
                           - _peak(m_down, chain.springs, chain.coupling)) / (2 * h))
    for j in range(chain.N + 1):
        k_up, k_down = np.array(chain.springs), np.array(chain.springs)
        k_up[j] *= 1 + h
        k_down[j] *= 1 - h
        relative_k.append(0.0 if chain.springs[j] == 0 else (
            _peak(chain.masses, k_up, chain.coupling) - _peak(chain.masses, k_down, chain.coupling)) / (2 * h))
    return np.array(relative_m), np.array(relative_k)


CASES = {
    "two-mass N=12": lambda: chain_for_case("two-mass", 12),
    "one-mass N=9": lambda: chain_for_case("one-mass", 9),
    "perfect N=7": lambda: chain_for_case("perfect", 7),
    "perfect N=6 walls j=1": lambda: chain_for_case("perfect", 6, 1),
    "two-mass N=10, walls K0=0.3": lambda: with_walls(chain_for_case("two-mass", 10), 0.3),
    "two-mass N=10, coupled k=0.2": lambda: chain_for_case("two-mass", 10).with_coupling(0.2),
    "asymmetric N=8": lambda: Chain([1.3, 0.9, 1.1, 1.0, 1.0, 0.8, 1.2, 1.6], [0.0, 0.9, 1.1, 1.0, 1.0, 0.95, 1.2,
                                                                             0.7, 0.2]),
}


@pytest.mark.parametrize("make", CASES.values(), ids=CASES.keys())
def test_sensitivities_match_finite_differences_of_exact_theory(make):
    chain = make()
    sensitivity = peak_sensitivity(chain)
    assert sensitivity.peak == pytest.approx(first_arrival(chain).peak, abs=1e-12)
    relative_m, relative_k = _central(chain)
    np.testing.assert_allclose(sensitivity.relative_masses, relative_m, rtol=0, atol=FD_TOLERANCE)
    np.testing.assert_allclose(sensitivity.relative_springs, relative_k, rtol=0, atol=FD_TOLERANCE)
    # the peak depends on them: a test of zeros would pass the comparison above
    assert np.max(np.abs(sensitivity.relative_masses)) > 0.1


@pytest.mark.parametrize("make", CASES.values(), ids=CASES.keys())
def test_relative_sensitivities_sum_to_zero(make):
    # scaling every mass (or every spring) only rescales time: the peak does not move
    sensitivity = peak_sensitivity(make())
    scale = np.max(np.abs(sensitivity.relative_masses))
    assert abs(sensitivity.relative_masses.sum()) < 1e-12 * max(1.0, scale) * sensitivity.chain.N
    assert abs(sensitivity.relative_springs.sum()) < 1e-12 * max(1.0, scale) * sensitivity.chain.N


def test_free_ends_have_no_relative_sensitivity_but_a_wall_spring_would_move_the_peak():
    sensitivity = peak_sensitivity(chain_for_case("two-mass", 10))
    assert sensitivity.springs[0] != 0.0  # a small wall spring would change the peak
    assert sensitivity.relative_springs[0] == sensitivity.relative_springs[-1] == 0.0


def test_refused_and_priced():
    with pytest.raises(ParameterError, match="N <= 2000"):
        peak_sensitivity(Chain.uniform_free(SENSITIVITY_MAX_N + 1))
    with pytest.raises(ParameterError, match="chain"):
        peak_sensitivity([1.0, 1.0])  # type: ignore[arg-type]
    assert sensitivity_estimate(2000).fits(Budget())
    assert not sensitivity_estimate(2000).fits(Budget(max_seconds=2.0))
