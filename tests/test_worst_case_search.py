"""The worst case over the whole tolerance box (issue 32 item 4): lcchain's search against a brute force over
every corner, written here independently of lcchain (the chain's matrices by hand, numpy.linalg.eigh, the
first-arrival peak from a fine grid and Newton steps); the Hessian's accuracy; the certificate's model bound.

The issue's independent check (all 2^15 corners of N = 8 chains with 5 % parts) found corners worse than the
old K-corner analysis in each case and, for the perfect cradle's energy, a worst loss of 1.35 % against 0.53 %
reported: the search must find the brute force's worst.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from helpers.tolerances import ATOL_WORST_CASE, RTOL_HESSIAN_STEP, RTOL_HESSIAN_VALUES
from helpers.worst_brute import brute_force

from lcchain.circuit.effects import Tolerance, cornered
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.sensitivity import corners, ladder_sensitivity
from lcchain.core.errors import ParameterError
from lcchain.theory.arrivals import first_arrival
from lcchain.theory.cases import chain_for_case
from lcchain.theory.sensitivity import energy_fraction
from lcchain.theory.worst_case import (
    ToleranceBox,
    metric_gradient,
    metric_hessian,
    quadratic_lower_bound,
    worst_case_search,
)

TOL = 0.05  # 5 % parts, as the check



#: N = 8 and 9 (2^15 and 2^17 corners, 2 to 6 s each on a loaded machine) in the slow command, but for the
#: issue's own case, the perfect cradle's energy at N = 8.
CASES = [pytest.param(case, N, metric, id=f"{case}-N{N}-{metric}",
                      marks=[pytest.mark.slow] if N >= 8 and (case, N, metric) != ("perfect", 8, "energy") else [])
         for case in ("two-mass", "perfect") for N in (6, 7, 8, 9) for metric in ("peak", "energy")]


@pytest.mark.parametrize("case, N, metric", CASES)
def test_the_search_finds_no_corner_worse_than_the_brute_force_worst(case, N, metric):
    chain = chain_for_case(case, N)
    values, signs = brute_force(np.asarray(chain.masses), np.asarray(chain.springs), TOL, metric)
    box = ToleranceBox(chain, TOL, TOL)
    assert box.size == 2 * N - 1 == signs.shape[1]  # N inductors and the N - 1 inner capacitors (free ends)
    found = worst_case_search(box, metric)
    brute = float(np.min(values))
    assert found.worst <= brute + ATOL_WORST_CASE, (found.worst, brute)
    # and the two evaluations agree where the search says its worst is (the search's point is a corner here)
    assert found.vertex
    where = np.asarray(found.point)[box.slots]
    row = int(np.flatnonzero(np.all(signs == where, axis=1))[0])
    assert abs(values[row] - found.worst) <= ATOL_WORST_CASE
    # the certificate's bound lies below every corner, and the gradient's corner is no better than the search
    assert found.bound <= brute <= found.gradient_corner + ATOL_WORST_CASE
    assert found.model_bound - found.model_error == pytest.approx(found.bound)
    assert found.worst < found.nominal and found.evaluations > 2 * box.size


def test_the_perfect_cradles_worst_is_beyond_what_the_quick_corners_say():
    """The design is optimal: its first derivatives vanish, so their signs predict nothing (issue 32: a loss of
    1.35 % against the 0.53 % the corners of the two most sensitive parts and the predicted ones reported)."""
    chain = chain_for_case("perfect", 8)
    found = worst_case_search(ToleranceBox(chain, TOL, TOL), "energy")
    sensitivity = ladder_sensitivity(Ladder(chain, 1e-5, 1e-8), metric="energy")
    quick = min(energy_fraction(first_arrival(chain_at).peak, chain_at)
                for corner in corners(sensitivity, components=2, tol_L=TOL, tol_C=TOL)
                for chain_at in [cornered(chain, 1e-5, 1e-8, signs=corner.signs, tol_L=TOL, tol_C=TOL)])
    assert 1.0 - found.worst > 2.0 * (1.0 - quick)
    assert len(found.local_optima) > 1 and found.local_optima[0] == pytest.approx(found.worst)


def test_the_hessian_of_the_exact_gradient_is_accurate():
    box = ToleranceBox(chain_for_case("two-mass", 7), TOL, TOL)
    z = np.random.default_rng(3).uniform(-0.5, 0.5, box.size)

    def gradient(point):
        return metric_gradient(box, point, "energy")[1]

    def value(point):
        return metric_gradient(box, point, "energy")[0]

    H, asymmetry = metric_hessian(gradient, z)
    half, _ = metric_hessian(gradient, z, step=5e-4)
    scale = float(np.max(np.abs(H)))
    assert np.max(np.abs(H - half)) <= RTOL_HESSIAN_STEP * scale and asymmetry <= RTOL_HESSIAN_STEP * scale
    h = 1e-2  # from the metric's values alone: no gradient involved
    for i, j in ((0, 0), (0, box.size - 1), (3, 9)):
        e_i, e_j = np.eye(box.size)[i] * h, np.eye(box.size)[j] * h
        second = (value(z + e_i + e_j) - value(z + e_i - e_j) - value(z - e_i + e_j) + value(z - e_i - e_j)) / (
            4 * h * h)
        assert abs(second - H[i, j]) <= RTOL_HESSIAN_VALUES * scale, (i, j, second, H[i, j])


def test_the_model_bound_holds_for_random_quadratics():
    rng = np.random.default_rng(11)
    corners = np.array(list(itertools.product((-1.0, 1.0), repeat=8)))
    inside = rng.uniform(-1.0, 1.0, (4000, 8))
    for _ in range(8):
        A = rng.normal(size=(8, 8))
        H = A + A.T + rng.normal() * 3 * np.eye(8)
        g = rng.normal(size=8)
        f0 = float(rng.normal())
        points = np.vstack([corners, inside])
        q = f0 + points @ g + 0.5 * np.einsum("pi,ij,pj->p", points, H, points)
        lowest = float(np.min(q))
        assert quadratic_lower_bound(f0, g, H)[0] <= lowest + 1e-12  # the whole box's relaxation
        lower, upper, nodes = quadratic_lower_bound(f0, g, H, nodes=500)  # and the branch and bound's
        assert lower <= lowest + 1e-12 and nodes > 1


def test_a_corner_may_lie_inside_the_box_and_nowhere_else():
    assert Tolerance(L=0.05, C=0.05, corner=(1, -0.25, 0)).corner == (1, -0.25, 0)
    for corner in ((1, 1.5), (True, 0), (float("nan"),), ("+",)):
        with pytest.raises(ParameterError, match="effects.tolerance.corner"):
            Tolerance(L=0.05, C=0.05, corner=corner)
    with pytest.raises(ParameterError, match="tolerance"):
        ToleranceBox(chain_for_case("two-mass", 6), 0.0, 0.0)
    with pytest.raises(ParameterError, match="metric"):
        worst_case_search(ToleranceBox(chain_for_case("two-mass", 6), TOL, TOL), "loss")  # type: ignore[arg-type]
