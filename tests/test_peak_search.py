"""The theory's peak search: Brent's searches side by side, on a response prepared once (issue 23).

A Monte Carlo sample's theory peak is refined by three bounded Brent
searches around the best grid points of the arrival's window; they used to
call the response ~75 times with one time each.  They now run side by side,
asking one time each per step, and the response evaluates those times
together.  Expected values come from scipy's own bounded Brent and from the
response called with one time at a time, as before.
"""

import numpy as np
import pytest
from helpers.tolerances import ATOL_PEAK_TIME_SEARCH
from scipy.optimize import minimize_scalar

from lcchain.theory.arrivals import _bounded_brent, arrival_window, maximum_in_window, refine_maxima
from lcchain.theory.chain import Chain
from lcchain.theory.exact import exact_modes
from lcchain.theory.response import prepare_response

# Both sides perform the same operations; a tolerance keeps the tests off the last bits all the same.
ATOL_SAME = 1e-13

EXCITATIONS = [("kick", None), ("displacement", None), ("pulse", ("gaussian", 0.4)), ("pulse", ("rect", 1.5))]


def _brent(f, lo, hi, xatol):
    search = _bounded_brent(lo, hi, xatol)
    points = [next(search)]
    try:
        while True:
            points.append(search.send(f(points[-1])))
    except StopIteration as stop:
        return points, stop.value


@pytest.mark.parametrize("seed", range(20))
def test_the_bounded_brent_generator_follows_scipys_points(seed):
    rng = np.random.default_rng(seed)
    weights, omega = rng.normal(size=12), rng.uniform(0.0, 3.0, 12)
    lo = rng.uniform(-50.0, 50.0)
    hi = lo + rng.uniform(1e-3, 5.0)

    def f(u):
        return -float(np.cos(omega * u) @ weights)

    asked = []
    expected = minimize_scalar(lambda u: asked.append(u) or f(u), bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-10})
    points, (x, value) = _brent(f, lo, hi, 1e-10)
    assert len(points) == len(asked) == expected.nfev
    np.testing.assert_allclose(points, asked, rtol=0, atol=ATOL_SAME)
    assert x == pytest.approx(expected.x, abs=ATOL_SAME) and value == pytest.approx(expected.fun, abs=ATOL_SAME)


def _pulse_chain():
    return Chain([1.3, 0.7, 1.1, 0.9, 1.6, 1.0, 0.8, 1.2], [0.8, 1.0, 1.2, 0.6, 1.1, 0.9, 1.0, 1.3, 0.0])


@pytest.mark.parametrize("Q", [None, 20.0])
@pytest.mark.parametrize("excitation, pulse", EXCITATIONS, ids=["kick", "displacement", "gaussian", "rect"])
def test_each_time_alone(excitation, pulse, Q):
    """Response.each gives every time the value of a call with that time alone, inside the pulse and after."""
    response = prepare_response(_pulse_chain(), excitation=excitation, Q=Q, pulse=pulse)
    t = np.array([7.3, 0.2, 0.9, 25.0, 1.45, 0.0, 3.1])
    alone = np.column_stack([response(np.array([time])) for time in t])
    np.testing.assert_allclose(response.each(t), alone, rtol=0, atol=ATOL_SAME)
    np.testing.assert_allclose(response.each(t), response(t), rtol=0, atol=ATOL_SAME)
    # times after the pulse only (a peak search's): the free oscillation's sum made once (Response._free)
    later = np.array([7.3, 25.0, 9.1, 12.0])
    alone = np.column_stack([response(np.array([time])) for time in later])
    np.testing.assert_allclose(response.each(later), alone, rtol=0, atol=ATOL_SAME)
    np.testing.assert_allclose(response.each(later[:1]), alone[:, :1], rtol=0, atol=ATOL_SAME)


@pytest.mark.parametrize("excitation, pulse", EXCITATIONS[2:], ids=["gaussian", "rect"])
def test_searches_side_by_side_find_what_one_search_at_a_time_finds(excitation, pulse):
    """The peak of a lossy pulse's first arrival: three searches side by side (each time evaluated with the
    others), against scipy's bounded Brent one search at a time on single-time calls, as the search was."""
    chain = _pulse_chain()
    response = prepare_response(chain, excitation=excitation, Q=50.0, pulse=pulse)
    transit = exact_modes(chain).transit_time()

    def last(times):
        return response(times)[-1]

    window = arrival_window(1, transit)
    grid = np.linspace(*window, 64)
    h = grid[1] - grid[0]
    intervals = [(max(window[0], grid[i] - h), min(window[1], grid[i] + h))
                 for i in np.argsort(last(grid))[::-1][:3]]
    together = refine_maxima(last, intervals, lambda times: response.each(times)[-1])
    for (lo, hi), (t, value) in zip(intervals, together, strict=True):
        centre = 0.5 * (lo + hi)
        alone = minimize_scalar(lambda u, c=centre: -float(last(np.array([c + u]))[0]),
                                bounds=(lo - centre, hi - centre), method="bounded",
                                options={"xatol": 1e-10 * max(1.0, hi - lo)})
        expected_t, expected_value = centre + alone.x, -alone.fun
        for edge, edge_value in zip((lo, hi), last(np.array([lo, hi])), strict=True):
            if edge_value > expected_value:
                expected_t, expected_value = edge, edge_value
        assert t == pytest.approx(expected_t, abs=ATOL_PEAK_TIME_SEARCH) and value == pytest.approx(expected_value, abs=ATOL_SAME)
    one_time_each = maximum_in_window(last, window, transit)
    side_by_side = maximum_in_window(last, window, transit, lambda times: response.each(times)[-1])
    assert side_by_side == pytest.approx(one_time_each, abs=ATOL_SAME)
    assert one_time_each[1] >= max(value for _, value in together) - ATOL_SAME
    assert one_time_each[1] > 0.1  # a pulse arrives: the search is not comparing zeros
