"""The Python API refuses what it cannot use in one ParameterError naming the parameter, and takes numpy's scalars
where it takes numbers (found by a reading of the API as a scientist uses it)."""

from __future__ import annotations

import numpy as np
import pytest

import lcchain
from lcchain.app.scenes import SceneRun
from lcchain.core.errors import ParameterError
from lcchain.runs.simulate import ChainOptions, simulation_spec


def test_a_numpy_integer_of_transits_is_an_int_a_run_key_can_hold() -> None:
    """np.int64(2) was kept as given, and the run's key (JSON) failed with a bare TypeError."""
    assert type(lcchain.Transient(dt=0.05, transits=np.int64(2)).transits) is int
    assert type(lcchain.AC(points=np.int64(300)).points) is int
    chain = lcchain.chain_for_case("two-mass", 10)
    spec, _, _ = simulation_spec(chain, ChainOptions(dt=0.05, transits=np.int64(2)))
    assert type(spec.theory.transits) is int and spec.key("39") == simulation_spec(chain, ChainOptions(
        dt=0.05, transits=2))[0].key("39")
    assert type(SceneRun(write_outputs=False, workers=np.int64(2)).workers) is int


@pytest.mark.parametrize("t", ["12.2", ["12.2", "0"], True, None, [1.0, None], 10**400])
def test_a_time_that_is_text_a_boolean_or_none_is_refused(t: object) -> None:
    chain = lcchain.chain_for_case("two-mass", 10)
    for amplitude in (lcchain.transmission_amplitude, lcchain.return_amplitude):
        with pytest.raises(ParameterError, match=r"^t = .* expected times in units of sqrt\(m/K\)"):
            amplitude(chain, t)


@pytest.mark.parametrize(("call", "said"), [
    (lambda: lcchain.optimal_two_mass(10, progress="x"), "progress = 'str' is not allowed: expected a function"),
    (lambda: lcchain.spectrum(lcchain.Request(lcchain.chain_for_case("two-mass", 10), lcchain.AC()),
                              simulator="ngspice"), "simulator = 'str' is not allowed: expected a Simulator"),
    (lambda: lcchain.Chain([10**400] * 5, [0, 1, 1, 1, 1, 0]), "masses[0] = 1000"),
    (lambda: lcchain.chain_from_spectrum([0.0, float("nan"), 2.0]), "frequencies[1] = nan"),
    (lambda: lcchain.chain_from_spectrum([0, 1, 10**400]), "frequencies[2] = 1000"),
    (lambda: lcchain.arrivals(lcchain.chain_for_case("two-mass", 10), 10**9), "count = 1000000000 is not allowed: "
     "expected an integer from 1 to 1000"),
    (lambda: SceneRun(write_outputs=False, transport="pigeon"), "--transport = 'pigeon' is not allowed"),
    # refused where it is given, as dt is, not when a run is planned from it
    (lambda: lcchain.Transient(accuracy=2), "accuracy = 2 is not allowed: expected a number with 0 < accuracy < 1"),
    (lambda: lcchain.Transient(accuracy="1e-4"), "accuracy = '1e-4' is not allowed"),
    (lambda: lcchain.Transient(accuracy=1e-13), "accuracy = 1e-13 is not allowed: expected an accuracy >= 1e-09"),
])
def test_a_bad_argument_is_a_parameter_error_naming_it(call: object, said: str) -> None:
    with pytest.raises(ParameterError) as raised:
        call()  # type: ignore[operator]
    assert str(raised.value).startswith(said), str(raised.value)


def test_the_perfect_arrival_times_are_read_only() -> None:
    with pytest.raises(TypeError):
        lcchain.PERFECT_ARRIVAL[3] = 0.0  # type: ignore[index]
    assert lcchain.PERFECT_ARRIVAL[3] == pytest.approx(np.sqrt(1.5) * np.pi)


def test_a_plot_into_something_that_is_no_axes_is_a_parameter_error(tmp_path: object) -> None:
    """A Figure or a name given as ``ax`` was an AttributeError from deep inside matplotlib's calls."""
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from lcchain import plots

    modes = lcchain.normal_modes(lcchain.chain_for_case("two-mass", 10))
    figure = plt.figure()
    try:
        for ax in ("foo", figure):
            with pytest.raises(ParameterError, match=r"^ax = '(str|Figure)' is not allowed: expected a matplotlib Axes"):
                modes.plot(ax=ax)
        with pytest.raises(ParameterError, match="^ax = 'str'"):
            plots.overlay(plots.OverlayCurves(np.arange(3.0), np.zeros(3), np.arange(3.0), np.zeros(3)), ax="x")
        assert modes.plot(ax=figure.add_subplot()) is figure
    finally:
        plt.close(figure)


def test_an_arrival_and_a_design_hold_python_floats() -> None:
    """Their reprs read time=12.22..., not time=np.float64(12.22...) beside plain floats."""
    design = lcchain.optimal_design("two-mass", 10)
    arrival = lcchain.first_arrival(lcchain.chain_for_case("two-mass", 10))
    assert type(arrival.time) is float and type(arrival.window[0]) is float and type(design.s) is float
    assert "np." not in repr(design) and "np." not in repr(arrival)
