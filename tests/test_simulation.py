"""The LC ladder in real ngspice against the chain's theory (no mocks)."""

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_DC_LEVEL,
    ATOL_PERFECT_PEAK,
    ATOL_PROBES_AT_START,
    ATOL_RUN_AGAINST_MODES,
    ATOL_SCALE_INVARIANCE,
    ATOL_SCALE_INVARIANCE_TIME,
    ATOL_SIMULATED_ARRIVAL_TIME,
    ATOL_TABLE_LOSS,
    MAX_ASYMMETRIC_RUN_ERROR,
    RTOL_CONSERVED,
    RTOL_WINDOW_END,
    TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT,
)

from lcchain.circuit.effects import Losses
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import Drive, NetlistOutput, SimulationOptions, netlist_text, probe_names
from lcchain.runs.simulate import ChainOptions, simulate_chain
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.runner import run
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import PERFECT_ARRIVAL, Chain
from lcchain.theory.spectrum import normal_modes, transmission_amplitude

pytestmark = pytest.mark.ngspice


@pytest.mark.parametrize("N", [3, 4, 5])
def test_perfect_chains_transmit_fully(N):
    """Sec. II.C: I_N/I0 = 1 at t = sqrt(3/2) pi, sqrt(11) pi/2, sqrt(5) pi."""
    report = simulate_chain(Chain.perfect(N), ChainOptions(dt=0.005, transits=1))
    w = report.waveforms
    at = np.interp(PERFECT_ARRIVAL[N], w.t, w.last)
    assert abs(at - 1.0) < ATOL_PERFECT_PEAK
    first = report.comparison.arrivals[0]
    assert abs(first.peak_sim - 1.0) < ATOL_PERFECT_PEAK
    assert first.t_sim == pytest.approx(PERFECT_ARRIVAL[N], abs=ATOL_SIMULATED_ARRIVAL_TIME)


@pytest.mark.parametrize("dt", [0.1, 0.05])
def test_two_mass_optimum_n100_within_step_prediction(dt):
    """Trap rule with fixed maximum step: error ~ 0.28 dt^2 over the first transit, Table II chain."""
    report = simulate_chain(chain_for_case("two-mass", 100), ChainOptions(dt=dt, transits=1))
    assert report.comparison.max_abs_error_last < TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT * dt**2
    # a wiring/sign/unit bug would be O(1): the error must also shrink like dt^2
    arrival = report.comparison.arrivals[0]
    assert arrival.peak_sim == pytest.approx(arrival.peak_theory, abs=TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT * dt**2)
    assert arrival.peak_theory == pytest.approx(1 - 0.01555, abs=ATOL_TABLE_LOSS)  # Table II, N = 100


def test_displacement_equals_kick_in_dimensionless_form():
    """Eq. e.qit vs e.dotqit: Q_N/Q_1(0) after a displacement is the same alpha_N as I_N/I_1(0) after a kick."""
    chain = chain_for_case("two-mass", 20)
    kick = simulate_chain(chain, ChainOptions(dt=0.02, transits=2, excitation="kick"))
    disp = simulate_chain(chain, ChainOptions(dt=0.02, transits=2, excitation="displacement"))
    bound = TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT * 2 * 0.02**2 * 4
    assert kick.comparison.max_abs_error < bound
    assert disp.comparison.max_abs_error < bound
    for a, b in zip(kick.comparison.arrivals, disp.comparison.arrivals, strict=True):
        assert a.peak_sim == pytest.approx(b.peak_sim, abs=bound)


def test_bounded_chain():
    """Uniform chain tied to walls (capacitors to ground) against its exact modes."""
    report = simulate_chain(Chain.uniform_bounded(20), ChainOptions(dt=0.02, transits=1))
    # uniform chains excite the whole band: 10-20 x the optimal chains' error (issue 4)
    assert report.comparison.max_abs_error < 20 * TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT * 0.02**2


def test_asymmetric_chain_uses_exact_modal_theory():
    chain = Chain([2.0, 1.0, 1.3, 0.8, 1.5], [0.0, 0.7, 1.0, 1.2, 0.9, 0.3])
    report = simulate_chain(chain, ChainOptions(dt=0.01, transits=2))
    assert report.comparison.max_abs_error < MAX_ASYMMETRIC_RUN_ERROR


def test_uniform_free_zero_mode_carries_constant_dc():
    """Free chain: sum_i L_i I_i (total momentum) stays L_1 I0; its zero mode is a DC current."""
    chain = Chain.uniform_free(20)
    ladder = Ladder(chain, 10e-6, 10e-9)
    options = SimulationOptions(dt=0.05, tstop=60.0)
    names = probe_names(chain.N, "all")
    result = run(RunJob(netlist_text(ladder, options, output=NetlistOutput(probes="all")), names, options.tstop * ladder.time_unit))
    momentum = sum(float(m) * result.vectors[name] for m, name in zip(chain.masses, names, strict=True)) / 1e-3
    assert np.max(np.abs(momentum - chain.masses[0])) < RTOL_CONSERVED
    # and the end current oscillates about the DC level I0 m1/M = I0/20
    report = simulate_chain(chain, ChainOptions(dt=0.05, transits=1))
    assert np.mean(report.waveforms.last) == pytest.approx(1 / 20, abs=ATOL_DC_LEVEL)


def test_same_dimensionless_result_at_any_component_scale():
    chain = chain_for_case("two-mass", 20)
    results = [simulate_chain(chain, ChainOptions(dt=0.05, L0=L0, C0=C0, I0=I0))
               for L0, C0, I0 in ((1.0, 1.0, 1.0), (10e-6, 10e-9, 1e-3), (1e-9, 1e-12, 1e-6))]
    # ngspice's start-up steps differ slightly at 1 H / 1 F (709 vs 711 points), so the
    # waveforms are compared through their error against theory at their own points.
    reference = results[1]
    for other in (results[0], results[2]):
        assert other.comparison.max_abs_error == pytest.approx(reference.comparison.max_abs_error,
                                                              abs=ATOL_SCALE_INVARIANCE)
        for a, b in zip(other.comparison.arrivals, reference.comparison.arrivals, strict=True):
            assert a.peak_sim == pytest.approx(b.peak_sim, abs=ATOL_SCALE_INVARIANCE)
            assert a.t_sim == pytest.approx(b.t_sim, abs=ATOL_SCALE_INVARIANCE_TIME)


def test_backends_bit_identical():
    chain = chain_for_case("two-mass", 20)
    batch = simulate_chain(chain, ChainOptions(dt=0.05, backend="batch"))
    shared = simulate_chain(chain, ChainOptions(dt=0.05, backend="shared"))
    assert np.array_equal(batch.run.time, shared.run.time)
    for name in batch.run.vectors:
        assert np.array_equal(batch.run.vectors[name], shared.run.vectors[name])
    assert batch.run.netlist_sha256 == shared.run.netlist_sha256


def test_report_records_run_metadata():
    report = simulate_chain(Chain.perfect(3), ChainOptions(dt=0.01, transits=3))
    data = report.to_dict()
    for key in ("N", "dt", "backend", "ngspice_version", "wall_s", "max_abs_error", "arrivals",
                "netlist_sha256", "options"):
        assert key in data
    assert [a["index"] for a in data["arrivals"]] == [1, 2, 3]
    assert [a["end"] for a in data["arrivals"]] == ["last", "first", "last"]
    assert data["options"]["method"] == "trap"
    # the run lasts the requested transits and no longer
    assert report.waveforms.t[-1] <= 3.5 * PERFECT_ARRIVAL[3] * (1 + RTOL_WINDOW_END)  # window end of arrival 3


def test_end_signal_is_alpha_not_something_else():
    """Guard against a swapped probe: the far end starts at 0, the near end at 1."""
    report = simulate_chain(chain_for_case("two-mass", 20), ChainOptions(dt=0.05))
    w = report.waveforms
    assert abs(w.last[0]) < ATOL_PROBES_AT_START and abs(w.first[0] - 1) < ATOL_PROBES_AT_START
    modes = normal_modes(report.chain)
    assert np.max(np.abs(w.last - transmission_amplitude(modes, w.t))) < ATOL_RUN_AGAINST_MODES


@pytest.mark.ngspice
@pytest.mark.parametrize("effects", [{"excitation": "kick"}, {"excitation": "displacement"},
                                     {"excitation": "pulse", "pulse": ("gaussian", 0.3), "effects": (Losses(40.0),)},
                                     {"excitation": "pulse", "pulse": ("rect", 0.5)},
                                     {"excitation": "kick", "coupling": 0.05}],
                         ids=["kick", "displacement", "gaussian-losses", "rect", "coupled"])
def test_pyspice_circuit_is_the_same_ladder(effects):
    """The PySpice Circuit for embedding simulates bit-identically to lcchain's own netlist."""
    from lcchain.spice.pyspice import circuit_from_netlist

    effects = dict(effects)
    coupling = effects.pop("coupling", 0.0)
    drive = Drive(effects.pop("excitation"), pulse=effects.pop("pulse", None))
    chain = Chain([1.7, 0.9, 1.0, 0.9, 1.7], [0.2, 0.8, 1.0, 1.0, 0.8, 0.0], coupling=coupling)
    ladder = Ladder(chain)
    options = SimulationOptions(dt=0.05, tstop=12.0)
    ours = netlist_text(ladder, options, drive, **effects)
    analysis = [line for line in ours.splitlines() if line.startswith((".options", ".tran", ".save"))]
    circuit_text = str(circuit_from_netlist(ours)) + "\n".join(analysis) + "\n.end\n"
    assert circuit_text != ours  # PySpice wrote it
    names = probe_names(chain.N)
    a = run(RunJob(ours, names, options.tstop * ladder.time_unit))
    b = run(RunJob(circuit_text, names, options.tstop * ladder.time_unit))
    assert np.array_equal(a.time, b.time)
    for name in names:
        assert np.array_equal(a.vectors[name], b.vectors[name])
