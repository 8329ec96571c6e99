"""Hard cases that must stay numerically sound (issue 4), in real ngspice and in theory.

Each large case has a smaller companion; both run in CI (the large ones take
8 s together: 10 transits of N = 100 with trap and gear, N = 10000 in
ngspice, the closed form at N = 500000, 200 transits of the perfect N = 4).
Expected values: energy
and the zero mode are conserved by the ideal ladder (and exactly by the
trapezoidal rule, a Cayley map); the perfect chains of Sec. II.C transmit
fully at every odd multiple of their transit time (equally spaced
frequencies); sum_n P_n = 1 (Eq. e.Pn); the closed form (Eqs. e.kn1, e.Pk)
against exact diagonalisation.
"""

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_AMPLITUDE_BOUND,
    ATOL_BEFORE_ARRIVAL,
    ATOL_CLOSED_FORM_EXTREME,
    ATOL_DENSITY_SUM,
    ATOL_LATER_ARRIVAL_PEAK,
    ATOL_LATER_ARRIVAL_TIME,
    ATOL_SCALE_INVARIANCE,
    ATOL_TRAP_MODEL,
    ATOL_TRAP_MODEL_LONG,
    MIN_ENERGY_LOSS_GEAR,
    PREDICTION_FACTOR,
    RTOL_CONSERVED,
    RTOL_ENERGY_TRAP,
)

from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import NetlistOutput, SimulationOptions, netlist_text, probe_names
from lcchain.compare.accuracy import AccuracyWarning, predicted_error, trap_response
from lcchain.compare.waveforms import normalise
from lcchain.core.errors import ParameterError
from lcchain.runs.simulate import ChainOptions, simulate_chain
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.runner import run
from lcchain.studies.bench import ladder_energy
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.closed_form import closed_form_modes
from lcchain.theory.exact import exact_modes
from lcchain.theory.spectrum import normal_modes, transmission_amplitude


# ------------------------------------------------------------------ uniform chains
@pytest.mark.ngspice
@pytest.mark.parametrize("chain", [Chain.uniform_free(50), Chain.uniform_bounded(50)], ids=["free", "bounded"])
def test_uniform_chains(chain):
    """A kicked uniform end excites the whole band: a larger step error, still exactly the model's."""
    report = simulate_chain(chain, ChainOptions(dt=0.02))
    assert report.integration_error < ATOL_TRAP_MODEL
    achieved = report.comparison.max_abs_error
    assert achieved / PREDICTION_FACTOR <= report.predicted_error <= achieved * PREDICTION_FACTOR


# ------------------------------------------------------------------ energy over many transits
def _energy_case(N, transits):
    chain = chain_for_case("two-mass", N)
    trap = ladder_energy(chain, method="trap", dt=0.1, transits=transits)
    gear = ladder_energy(chain, method="gear", dt=0.3, transits=transits)
    assert np.max(np.abs(trap["energy"] - 1.0)) < RTOL_ENERGY_TRAP
    assert 1.0 - gear["energy"][-1] > MIN_ENERGY_LOSS_GEAR
    # the zero mode of the free chain (total momentum sum L_i I_i) is kept by both
    assert np.max(np.abs(trap["momentum"] - 1.0)) < RTOL_CONSERVED
    # (at dt = 0.3 over 10 transits gear's predicted error is also "meaningless": warn on gear alone here)
    with pytest.warns(AccuracyWarning, match="gear loses energy"):
        simulate_chain(chain, ChainOptions(dt=0.05, transits=2, method="gear"))


@pytest.mark.ngspice
def test_ten_transits_energy_short():
    _energy_case(20, 10)


@pytest.mark.ngspice
def test_ten_transits_energy():
    _energy_case(100, 10)


@pytest.mark.ngspice
def test_zero_mode_of_a_free_uniform_chain():
    """Sum L_i I_i is constant (the translation mode), also where the pulse reflects."""
    result = ladder_energy(Chain.uniform_free(30), method="trap", dt=0.05, transits=3)
    assert np.max(np.abs(result["momentum"] - 1.0)) < RTOL_CONSERVED


# ------------------------------------------------------------------ component scale
@pytest.mark.ngspice
def test_nanohenry_picofarad_microampere():
    """nH / pF / uA: tolerances scaled to the circuit keep the dimensionless result."""
    chain = chain_for_case("two-mass", 20)
    small = simulate_chain(chain, ChainOptions(dt=0.05, L0=1e-9, C0=1e-12, I0=1e-6))
    bulk = simulate_chain(chain, ChainOptions(dt=0.05))
    assert small.integration_error < ATOL_TRAP_MODEL
    assert np.max(np.abs(small.waveforms.last - bulk.waveforms.last)) < ATOL_SCALE_INVARIANCE


# ------------------------------------------------------------------ very long ladders, short runs
def _long_ladder(N, tstop=30.0, dt=0.1):
    chain = chain_for_case("two-mass", N)
    modes = normal_modes(chain)
    ladder = Ladder(chain)
    text = netlist_text(ladder, SimulationOptions(dt=dt, tstop=tstop), output=NetlistOutput(title=f"long ladder N={N}"))
    names = probe_names(N, "ends")
    result = run(RunJob(text, names, tstop * ladder.time_unit, timeout=1800.0))
    w = normalise(result.time, result.vectors[names[0]], result.vectors[names[1]], time_unit=ladder.time_unit,
                  excitation="kick", I0=1e-3)
    model = trap_response(modes.density, modes.omega, w.t, tstep=dt)
    assert np.max(np.abs(w.first - model)) < ATOL_TRAP_MODEL
    assert np.max(np.abs(w.last)) < ATOL_BEFORE_ARRIVAL  # the pulse is nowhere near the far end yet


@pytest.mark.ngspice
def test_long_ladder_short_run_short():
    _long_ladder(2000)


@pytest.mark.ngspice
def test_long_ladder_short_run():
    _long_ladder(10000)


# ------------------------------------------------------------------ theory at extreme N and (r, w)
EXTREME_RW = [(1e-3, 1e-3), (1e-3, 1.0), (1.0, 1e-3), (1 - 1e-9, 1 - 1e-9), (1.9, 1.9)]


def _closed_form_sound(N, r, w):
    modes = closed_form_modes(N, r, w)
    assert np.all(np.isfinite(modes.omega)) and np.all(np.isfinite(modes.density))
    assert abs(modes.density.sum() - 1.0) < ATOL_DENSITY_SUM
    assert np.all(np.diff(modes.omega) > 0) and modes.omega[-1] < 2.0
    T = modes.transit_time()
    alpha = transmission_amplitude(modes, np.linspace(0.8 * T, 1.2 * T, 201))
    assert np.all(np.isfinite(alpha)) and np.max(np.abs(alpha)) <= 1.0 + ATOL_AMPLITUDE_BOUND


@pytest.mark.parametrize("r, w", EXTREME_RW)
def test_theory_at_n_100000(r, w):
    _closed_form_sound(100_000, r, w)


@pytest.mark.parametrize("r, w", EXTREME_RW)
def test_theory_at_n_500000(r, w):
    _closed_form_sound(500_000, r, w)


@pytest.mark.parametrize("r, w", EXTREME_RW + [(2e-6 / (1 + 1e-6), 1.0)], ids=lambda v: f"{v:.3g}")
def test_closed_form_agrees_with_exact_near_the_limits(r, w):
    """Uniform limit r, w -> 1; edge of validity: K12 = r/(2-r) = 1e-6, or m1 = r/((2-r) w) = 1e-6."""
    N = 500
    exact = exact_modes(Chain.from_rw(N, r, w))
    closed = closed_form_modes(N, r, w)
    assert not np.isnan(exact.omega).any()
    assert abs(exact.density.sum() - 1.0) < ATOL_DENSITY_SUM
    assert np.max(np.abs(exact.omega - closed.omega)) < ATOL_CLOSED_FORM_EXTREME
    assert np.max(np.abs(exact.density - closed.density)) < ATOL_CLOSED_FORM_EXTREME


def test_vanishing_end_mass():
    """m1 = 1e-6: a mode leaves the band; the closed form refuses, exact diagonalisation stays sound."""
    chain = Chain.from_rw(500, 1.0, 1e6)
    exact = exact_modes(chain)
    assert np.all(np.isfinite(exact.omega)) and abs(exact.density.sum() - 1.0) < ATOL_DENSITY_SUM
    assert exact.omega[-1] > 2.0  # the localised mode of the light end mass
    with pytest.raises(ParameterError, match="outside the band"):
        closed_form_modes(500, 1.0, 1e6)


@pytest.mark.ngspice
def test_near_uniform_chain_in_ngspice():
    chain = Chain.from_rw(50, 1 - 1e-9, 1 - 1e-9)
    report = simulate_chain(chain, ChainOptions(dt=0.05))
    assert report.integration_error < ATOL_TRAP_MODEL


# ------------------------------------------------------------------ the perfect chain stays periodic
def _perfect_periodic(transits, dt, atol_model=ATOL_TRAP_MODEL):
    chain = Chain.perfect(4)
    report = simulate_chain(chain, ChainOptions(dt=dt, transits=transits))
    T = np.sqrt(11) * np.pi / 2  # Sec. II.C: alpha_4 = 1 at t = sqrt(11) pi / 2, and then at every odd multiple
    for a in report.comparison.arrivals:
        assert a.t_theory == pytest.approx(a.index * T, abs=ATOL_LATER_ARRIVAL_TIME)  # a flat maximum: time to ~sqrt(eps)
        assert a.peak_theory == pytest.approx(1.0, abs=ATOL_LATER_ARRIVAL_PEAK)
        assert abs(a.peak_sim - 1.0) <= report.predicted_error
    assert report.integration_error < atol_model


@pytest.mark.ngspice
def test_perfect_chain_twenty_transits():
    _perfect_periodic(20, 0.02)


@pytest.mark.ngspice
def test_perfect_chain_two_hundred_transits():
    _perfect_periodic(200, 0.005, ATOL_TRAP_MODEL_LONG)


# ------------------------------------------------------------------ a step too coarse to mean anything
@pytest.mark.ngspice
def test_meaningless_step_warns():
    chain = Chain.uniform_free(20)
    with pytest.warns(AccuracyWarning, match="meaningless"):
        report = simulate_chain(chain, ChainOptions(dt=0.5))
    assert report.predicted_error > 0.1
    # the warning is about the step, not the circuit: the model still holds exactly
    assert report.integration_error < ATOL_TRAP_MODEL


def test_predicted_error_of_the_coarse_step_is_large():
    modes = exact_modes(Chain.uniform_free(20))
    assert predicted_error(modes, 0.5, 60.0) > 0.1
