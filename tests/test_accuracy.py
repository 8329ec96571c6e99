"""The trapezoidal rule's error model (lcchain.accuracy) against real ngspice (issue 4).

Expected values: the trapezoidal rule rotates each normal mode by
2 atan(omega h / 2) per step (the Cayley map of q'' = -omega^2 q), so the
simulated waveform is the modal sum of Eq. e.utn with warped frequencies
(2/dt) atan(omega dt / 2); the numbers quoted in issue 4 (0.28 dt^2 over one
transit for optimal two-mass chains, gear 4 x trap).
"""

import json

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_TRAP_MODEL,
    ATOL_TRAP_STARTUP_CLOSED_FORM,
    ATOL_WARP_SERIES,
    ATOL_WARPED_DT_0_01,
    ATOL_WARPED_DT_0_1,
    GEAR_FACTOR_RANGE,
    MIN_INTEGRATION_ERROR_OF_A_BUG,
    MIN_TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT,
    PREDICTION_FACTOR,
    RTOL_PHYSICS_ERROR_IS_TOTAL,
    RTOL_STEP_ERROR_OF_A_BUG,
    TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT,
)

from lcchain.cli import main
from lcchain.compare.accuracy import (
    MAX_DT,
    SAFETY,
    AccuracyWarning,
    dt_for_accuracy,
    predicted_error,
    split_error,
    trap_response,
    warped_frequencies,
    warped_modes,
)
from lcchain.core.errors import ParameterError
from lcchain.runs.simulate import ChainOptions, simulate, simulate_chain
from lcchain.theory.arrivals import stop_time
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.modes import cosine_sum
from lcchain.theory.spectrum import normal_modes


@pytest.fixture(scope="module")
def n20():
    chain = chain_for_case("two-mass", 20)
    return chain, normal_modes(chain)


@pytest.fixture(scope="module")
def n100():
    chain = chain_for_case("two-mass", 100)
    return chain, normal_modes(chain)


# ------------------------------------------------------------------ pure model
def test_warped_frequencies_series_and_bounds():
    omega = np.linspace(0.0, 2.0, 41)
    dt = 0.01
    warped = warped_frequencies(omega, dt)
    assert np.all(warped <= omega) and warped[0] == 0.0
    # omega~ = omega - omega^3 dt^2 / 12 + O(dt^4)
    assert np.allclose(warped, omega - omega**3 * dt**2 / 12, atol=ATOL_WARP_SERIES)


def test_warped_modes_keep_weights(n20):
    _, modes = n20
    w = warped_modes(modes, 0.1)
    assert w.density is modes.density and w.transfer is modes.transfer
    assert np.all(w.omega < modes.omega + 1e-15)


def test_predicted_error_scales_as_dt_squared(n100):
    """Issue 4: about 0.28 dt^2 over one transit for the optimal two-mass chain."""
    _, modes = n100
    tstop = stop_time(modes, 1)
    for dt in (0.1, 0.05, 0.02):
        assert (MIN_TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT < predicted_error(modes, dt, tstop) / dt**2
                < TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT)
    assert predicted_error(modes, 0.05, tstop, method="gear") == pytest.approx(
        4 * predicted_error(modes, 0.05, tstop))


@pytest.mark.parametrize("accuracy", [1e-3, 1e-4, 1e-6])
def test_dt_for_accuracy_is_the_largest_step_meeting_the_target(n100, accuracy):
    _, modes = n100
    tstop = stop_time(modes, 1)
    dt = dt_for_accuracy(modes, accuracy, tstop)
    error = predicted_error(modes, dt, tstop)
    assert error <= SAFETY * accuracy
    assert error >= 0.9 * SAFETY * accuracy  # within a few % of the largest admissible dt
    assert dt_for_accuracy(modes, accuracy, tstop, method="gear") < dt


def test_dt_for_accuracy_caps_and_validates(n20):
    _, modes = n20
    assert dt_for_accuracy(modes, 0.9, stop_time(modes, 1)) == MAX_DT
    for bad in (0.0, -1e-3, 1.5, float("nan"), "1e-3"):
        with pytest.raises(ParameterError, match="accuracy"):
            dt_for_accuracy(modes, bad, 10.0)


def test_trap_response_on_a_uniform_grid_is_the_warped_sum(n20):
    """Without start-up steps (tstep None, first two steps only) the model is the warped modal sum."""
    _, modes = n20
    dt = 0.05
    t = dt * np.arange(1, 2001)
    model = trap_response(modes.transfer, modes.omega, t)
    # the first two steps are backward Euler: their amplitude factor is 1/sqrt(1+(omega dt)^2) each
    shrink = 1.0 / (1.0 + (modes.omega * dt) ** 2)
    phase = 2 * np.arctan(modes.omega * dt) + (t[:, None] - 2 * dt) * warped_frequencies(modes.omega, dt)
    expected = (np.cos(phase) * shrink) @ modes.transfer
    assert np.allclose(model[1:], expected[1:], atol=ATOL_TRAP_STARTUP_CLOSED_FORM)


# ------------------------------------------------------------------ against ngspice
@pytest.mark.ngspice
@pytest.mark.parametrize("dt, atol", [(0.1, ATOL_WARPED_DT_0_1), (0.01, ATOL_WARPED_DT_0_01)])
def test_warped_model_matches_ngspice(n20, dt, atol):
    chain, modes = n20
    report = simulate(ChainOptions(dt=dt).request(chain), modes=modes)
    w = report.waveforms
    warped = warped_modes(modes, dt)
    after = w.t > 3 * dt  # after the start-up steps
    for weights, signal in ((warped.transfer, w.last), (warped.density, w.first)):
        assert np.max(np.abs(signal - cosine_sum(weights, warped.omega, w.t))[after]) < atol
    # With ngspice's own steps (and its backward-Euler start-up steps) the model is exact to rounding.
    assert report.integration_error < ATOL_TRAP_MODEL
    assert report.physics_error == pytest.approx(report.comparison.max_abs_error, rel=RTOL_PHYSICS_ERROR_IS_TOTAL)


@pytest.mark.ngspice
@pytest.mark.parametrize("N, dt", [(20, 0.2), (100, 0.1), (100, 0.05)])
def test_predicted_error_matches_achieved(N, dt):
    chain = chain_for_case("two-mass", N)
    report = simulate_chain(chain, ChainOptions(dt=dt))
    achieved = report.comparison.max_abs_error
    assert achieved / PREDICTION_FACTOR <= report.predicted_error <= achieved * PREDICTION_FACTOR


@pytest.mark.ngspice
@pytest.mark.parametrize("accuracy", [1e-3, 1e-4])
def test_accuracy_is_met_on_n100(n100, accuracy):
    chain, modes = n100
    report = simulate(ChainOptions(accuracy=accuracy).request(chain), modes=modes)
    assert report.comparison.max_abs_error <= accuracy
    assert report.comparison.max_abs_error >= 0.5 * accuracy  # not a wastefully small step
    data = report.to_dict()
    assert data["accuracy"] == accuracy and data["dt"] == report.options.dt
    assert data["predicted_error"] <= SAFETY * accuracy


@pytest.mark.ngspice
def test_error_split_catches_a_chain_that_differs_from_the_theory(n20):
    """A mass 1e-3 off: the step's error hides it in the total, the integration error shows it."""
    chain, modes = n20
    dt = 0.1
    report = simulate(ChainOptions(dt=dt).request(chain), modes=modes)
    masses = np.array(chain.masses)
    masses[5] *= 1 + 1e-3
    wrong = normal_modes(Chain(masses, chain.springs))
    good = split_error(report.waveforms, modes, dt)
    bad = split_error(report.waveforms, wrong, dt)
    assert good.integration_error < ATOL_TRAP_MODEL
    assert bad.integration_error > MIN_INTEGRATION_ERROR_OF_A_BUG
    assert bad.physics_error == pytest.approx(good.physics_error, rel=RTOL_STEP_ERROR_OF_A_BUG)  # the step's error is unchanged
    assert bad.total_error < 2 * good.total_error  # ... and the total alone would not tell


@pytest.mark.ngspice
def test_gear_error_is_about_four_times_trap(n20):
    chain, modes = n20
    trap = simulate(ChainOptions(dt=0.05, method="trap").request(chain), modes=modes)
    gear = simulate(ChainOptions(dt=0.05, method="gear").request(chain), modes=modes)
    ratio = gear.comparison.max_abs_error / trap.comparison.max_abs_error
    assert GEAR_FACTOR_RANGE[0] < ratio < GEAR_FACTOR_RANGE[1]
    assert gear.integration_error is None and gear.to_dict()["physics_error"] is None


@pytest.mark.ngspice
def test_gear_over_several_transits_warns(n20):
    chain, modes = n20
    with pytest.warns(AccuracyWarning, match="gear loses energy"):
        simulate(ChainOptions(dt=0.1, transits=2, method="gear").request(chain), modes=modes)


@pytest.mark.ngspice
def test_coarse_step_warns():
    with pytest.warns(AccuracyWarning, match="meaningless"):
        report = simulate_chain(Chain.uniform_bounded(20), ChainOptions(dt=0.5))
    assert report.predicted_error > 0.1


def test_simulate_needs_exactly_one_of_dt_and_accuracy():
    with pytest.raises(ParameterError, match="dt/accuracy"):
        ChainOptions()
    with pytest.raises(ParameterError, match="dt/accuracy"):
        ChainOptions(dt=0.1, accuracy=1e-3)


# ------------------------------------------------------------------ command line
def run_cli(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_cli_accuracy_excludes_dt(capsys):
    status, _, err = run_cli(capsys, "simulate", "--case", "two-mass", "--N", "20", "--dt", "0.1",
                             "--accuracy", "1e-3")
    assert status == 2 and "--accuracy" in err and len(err.strip().splitlines()) == 1


@pytest.mark.ngspice
def test_cli_accuracy_json(capsys):
    status, out, err = run_cli(capsys, "simulate", "--case", "two-mass", "--N", "20", "--accuracy", "1e-4", "--json")
    assert status == 0 and err == ""
    data = json.loads(out)
    assert {"accuracy", "predicted_error", "integration_error", "physics_error"} <= set(data)
    accuracy = 1e-4  # asked for on the command line
    assert data["accuracy"] == accuracy and data["max_abs_error"] <= accuracy
    assert data["integration_error"] < ATOL_TRAP_MODEL


@pytest.mark.ngspice
def test_cli_prints_a_warning_as_one_line(capsys):
    status, _, err = run_cli(capsys, "simulate", "--case", "two-mass", "--N", "20", "--dt", "0.1",
                             "--method", "gear", "--transits", "2")
    assert status == 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("lcchain: warning:") and "gear loses energy" in lines[0]


@pytest.mark.ngspice
def test_bench_accuracy_quick_writes_its_files(tmp_path):
    from lcchain.report.bench import write_accuracy_bench
    from lcchain.studies.bench import bench_accuracy

    result = bench_accuracy([20], quick=True, targets=False)
    names = {p.rsplit("/", 1)[-1] for p in write_accuracy_bench(tmp_path, result)}
    assert names == {"records.csv", "records.json", "pareto.png", "summary.md"}
    kinds = {(r["method"], r["stepping"]) for r in result["records"]}
    assert kinds == {("trap", "fixed"), ("gear", "fixed"), ("trap", "adaptive"), ("gear", "adaptive"),
                     ("DOP853", "adaptive"), ("modal sum", "exact"), ("trap", "pair"), ("trap", "triple")}
    assert all(r["error"] > 0 and r["wall_s"] > 0 for r in result["records"])
    for runs in ("pair", "triple"):  # at the same coarsest step, the combination beats the single run by far
        for r in (r for r in result["records"] if r["stepping"] == runs):
            single = [s for s in result["records"] if s["stepping"] == "fixed" and s["method"] == "trap"
                      and s["dt"] == r["dt"]]
            assert not single or r["error"] < single[0]["error"] / 10
    assert (MIN_TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT < result["summary"]["fits"]["error_c"]["trap N=20"]
            < TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT)  # issue 4: 0.28
