"""The AC analysis behind Request (issue 21, section 1): planned, executed and stored like a transient.

Every spectrum is checked against an independent dense eigen-solution of the run's own chain
(tests/helpers/dense.py), not lcchain's modes.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers.dense import dense_modes
from helpers.tolerances import ATOL_PERFECT_SPACING_SPREAD, ATOL_SPECTRUM_P, RTOL_SPECTRUM_OMEGA, RTOL_SPECTRUM_Q

from lcchain.circuit.effects import Losses, Tolerance
from lcchain.compare.spectral import OMEGA_WEIGHT_FLOOR, SpectrumMetrics
from lcchain.core.budget import INTERPRETER_SECONDS, Budget, BudgetError
from lcchain.core.errors import ParameterError
from lcchain.runs.execute import execute, waveform_digest
from lcchain.runs.request import AC, Request, Transient, plan_request
from lcchain.runs.spec import RunSpec, SpectrumTheory
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import request_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain


def _against_dense(chain: Chain, metrics: SpectrumMetrics) -> None:
    omega, P = dense_modes(chain)
    strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
    assert np.all(np.isfinite(metrics.omega[strong]))
    error = np.abs(metrics.omega[strong] - omega[strong]) / np.where(omega[strong] > 0, omega[strong], 1.0)
    assert np.max(error) < RTOL_SPECTRUM_OMEGA
    assert np.max(np.abs(metrics.P - P)) < ATOL_SPECTRUM_P


@pytest.mark.ngspice
def test_an_ac_request_runs_through_execute_against_a_dense_eigen_solution():
    chain = chain_for_case("two-mass", 16).with_coupling(0.02)
    plan = plan_request(Request(chain, AC()))
    assert len(plan.specs) == 1 and plan.points is not None and plan.tstop == 0.0
    spec = plan.specs[0]
    assert spec.analysis == "ac" and spec.points == plan.points and ".ac lin" in spec.netlist
    record = execute(spec)
    assert record.ok and record.spectrum is not None and record.run is not None and record.analysis == "ac"
    _against_dense(chain, record.spectrum)
    assert record.points == plan.points
    assert record.digest == waveform_digest(record.run.frequency, record.run.vectors, "frequency")
    summary = record.summary()
    assert summary["points"] == plan.points and summary["max_rel_error_omega"] < RTOL_SPECTRUM_OMEGA


@pytest.mark.ngspice
def test_each_tolerance_sample_is_compared_with_its_own_chain():
    """Real parts: each sample's spectrum against its own exact theory; the perfect cradle's equal spacing
    (spread 0 in theory, Eq. e.Pn's chain) is spread by the sampled values."""
    nominal = chain_for_case("perfect", 16)
    plan = plan_request(Request(nominal, AC(), effects=(Tolerance(L=0.02, C=0.02, samples=3, seed=4),)))
    assert len(plan.specs) == 3 and len({spec.netlist for spec in plan.specs}) == 3
    spreads = []
    for chain, spec in zip(plan.chains, plan.specs, strict=True):
        assert isinstance(spec.theory, SpectrumTheory) and spec.theory.chain is chain
        record = execute(spec)
        assert record.ok and record.spectrum is not None
        _against_dense(chain, record.spectrum)
        spreads.append(record.spectrum.spacing_spread)
    nominal_record = execute(plan_request(Request(nominal, AC())).specs[0])
    assert nominal_record.spectrum is not None and nominal_record.spectrum.spacing_spread < ATOL_PERFECT_SPACING_SPREAD
    assert min(spreads) > 100 * nominal_record.spectrum.spacing_spread


def test_a_grid_too_coarse_to_separate_two_poles_is_refused_naming_the_minimum():
    chain = chain_for_case("perfect", 24)
    needed = plan_request(Request(chain, AC())).points // 2  # the default is twice the minimum
    with pytest.raises(ParameterError, match=f"at least {needed} frequencies") as caught:
        plan_request(Request(chain, AC(points=needed - 1)))
    assert caught.value.field == "points"
    assert plan_request(Request(chain, AC(points=needed))).points == needed


def test_the_ac_price_is_in_frequencies_and_checked_first():
    with pytest.raises(BudgetError, match="frequencies"):
        # about 0.3 s of ngspice for 3354 frequencies (N = 400): beyond 0.1 s once the interpreter is counted
        plan_request(Request(chain_for_case("perfect", 400), AC()), Budget(max_seconds=INTERPRETER_SECONDS + 0.1))


@pytest.mark.parametrize(("request_of", "field"), [
    (lambda c: Request(c, AC(), backend="shared"), "backend"),
    (lambda c: Request(c, AC(points=3)), "points"),
    (lambda c: Request(c, AC(), comments=("a note",)), "comments"),
])
def test_what_an_ac_request_cannot_do_is_refused(request_of, field):
    with pytest.raises(ParameterError) as caught:
        plan_request(request_of(chain_for_case("two-mass", 8)))
    assert caught.value.field == field


@pytest.mark.ngspice
def test_a_study_of_ac_requests_stores_complex_arrays_and_their_digests(tmp_path):
    chain = chain_for_case("two-mass", 12)
    plan = request_plan([({"N": 12}, Request(chain, AC())),
                         ({"N": 10}, Request(chain_for_case("two-mass", 10), AC()))])
    path = tmp_path / "ac.sqlite"
    run_plan(plan, path, RunOptions(executor="serial"))
    with Store(path, "read") as store:
        runs = store.runs()
        assert [run.status for run in runs] == ["ok", "ok"] and all(run.spectral for run in runs)
        arrays = store.waveforms(runs[0].key)
        assert arrays is not None and arrays["frequency"].dtype == float and arrays["i(l12)"].dtype == complex
        assert runs[0].digest == waveform_digest(arrays["frequency"], {k: v for k, v in arrays.items()
                                                                       if k != "frequency"}, "frequency")
        again = execute(plan.tasks[0].spec)
        assert again.run is not None and again.digest == runs[0].digest  # the same bits, stored and rerun
        np.testing.assert_array_equal(arrays["i(l1)"], again.run.vectors["i(l1)"])
        assert runs[0].metrics is not None
        _against_dense(chain, SpectrumMetrics.from_dict(runs[0].metrics))
        data = store.to_xarray(waveforms=True)
    assert data["i(l1)"].dtype == complex and "frequency" in data.coords
    assert "max_rel_error_omega" in data and "max_abs_error" not in data


def test_transient_keys_do_not_depend_on_the_ac_fields():
    spec = plan_request(Request(chain_for_case("two-mass", 8), Transient(dt=0.05))).specs[0]
    assert spec.analysis == "transient" and spec.points is None
    ac = plan_request(Request(chain_for_case("two-mass", 8), AC())).specs[0]
    assert ac.key("39") != spec.key("39")


@pytest.mark.ngspice
def test_each_sample_has_its_own_sweep_on_the_samples_axis(tmp_path):
    """A tolerance sample's sweep is placed from its own poles (segments as fine as they are): its frequencies are
    a coordinate of each sample, on a shared point dimension when the samples have as many."""
    pytest.importorskip("xarray")
    request = Request(chain_for_case("perfect", 10), AC(), effects=(Tolerance(L=0.01, C=0.01, samples=2, seed=3),))
    specs = plan_request(request).specs
    assert len({spec.points for spec in specs}) == 1 and specs[0].netlist != specs[1].netlist
    run_plan(request_plan([({"N": 10}, request)]), tmp_path / "s.sqlite", RunOptions(executor="serial"))
    with Store(tmp_path / "s.sqlite", "read") as store:
        data = store.to_xarray(waveforms=True)
    points = specs[0].points
    assert dict(data["i(l1)"].sizes) == {"sample": 2, "point": points} and data["i(l1)"].dtype == complex
    frequency = data["frequency"].values
    assert frequency.shape == (2, points) and np.all(frequency > 0) and np.all(np.diff(frequency, axis=1) > 0)
    assert not np.array_equal(frequency[0], frequency[1])


@pytest.mark.ngspice
def test_an_ac_request_with_losses_fits_every_modes_decay_rate():
    """Losses go through the request as through the transient: the same resistors, and each mode's Q_n against
    omega_n Q, stored with the run's metrics."""
    chain = chain_for_case("two-mass", 12)
    plan = plan_request(Request(chain, AC(), effects=(Losses(Q=100.0),)))
    spec = plan.specs[0]
    assert isinstance(spec.theory, SpectrumTheory) and spec.theory.Q == 100.0
    assert sum(line.startswith("R") for line in spec.netlist.splitlines()) == chain.N
    record = execute(spec)
    assert record.ok and record.spectrum is not None and record.spectrum.losses == 100.0
    _against_dense(chain, record.spectrum)
    assert record.spectrum.max_rel_error_Q < RTOL_SPECTRUM_Q
    stored = SpectrumMetrics.from_dict(json.loads(json.dumps(record.spectrum.to_dict())))
    assert stored.losses == 100.0 and stored.max_rel_error_Q == record.spectrum.max_rel_error_Q


def test_an_ac_spec_runs_on_the_engines_program_only():
    """The shared library runs transients only: an AC spec with backend = "shared" is refused when it is made
    (batch_plan could make one and fail mid-study)."""
    spec = plan_request(Request(chain_for_case("two-mass", 8), AC())).specs[0]
    with pytest.raises(ParameterError) as caught:
        RunSpec(spec.netlist, spec.vectors, 0.0, backend="shared", analysis="ac", points=spec.points)
    assert caught.value.field == "backend"
