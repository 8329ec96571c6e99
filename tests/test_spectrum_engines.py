"""The AC analysis in every engine (issue 21, section 1): gnucap's spectrum, ngspice and gnucap on one netlist,
and the refusals (an engine without an AC analysis, an unknown engine).

gnucap runs for real.  Expected values: an independent dense eigen-solution of K u = omega^2 M u
(tests/helpers/dense.py), not lcchain's own modes; the targets are ngspice's (gnucap reaches them: measured
7e-15 for omega_n and 2e-15 for P_n on two-mass N = 20, benchmarks/spectrum.md "gnucap").
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers.dense import dense_modes
from helpers.tolerances import ATOL_SPECTRUM_P, RTOL_ENGINES_AC, RTOL_SPECTRUM_OMEGA

from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import ac_netlist_text
from lcchain.cli.main import main
from lcchain.core.budget import INTERPRETER_SECONDS, Budget, BudgetError, run_estimate
from lcchain.core.errors import ParameterError, SimulationError
from lcchain.runs.spectrum import OMEGA_WEIGHT_FLOOR, SpectrumOptions, measure_spectrum
from lcchain.spice.ac import AcJob, run_ac
from lcchain.spice.engines import ENGINES
from lcchain.spice.gnucap import read_ac_table
from lcchain.theory.cases import chain_for_case


def _ac_netlist(chain, points):
    return ac_netlist_text(Ladder(chain, 10e-6, 1e-6), points=points, omega_max=2.1)


@pytest.mark.gnucap
@pytest.mark.parametrize("chain", [chain_for_case("two-mass", 20), chain_for_case("perfect", 20, 1),
                                   chain_for_case("two-mass", 16).with_coupling(0.03)],
                         ids=["two-mass-20", "perfect-walled-20", "coupled-16"])
def test_gnucap_spectrum_matches_a_dense_eigen_solution(chain):
    report = measure_spectrum(chain, options=SpectrumOptions(engine="gnucap"))
    assert report.engine == "gnucap" and report.to_dict()["engine"] == "gnucap" and report.engine_version
    omega, P = dense_modes(chain)
    strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
    assert np.all(np.isfinite(report.omega[strong]))  # every mode that weighs at the ends is found
    error = np.abs(report.omega[strong] - omega[strong]) / np.where(omega[strong] > 0, omega[strong], 1.0)
    assert np.max(error) < RTOL_SPECTRUM_OMEGA
    assert np.max(np.abs(np.nan_to_num(report.P) - P)) < ATOL_SPECTRUM_P  # an unseen mode counts with P = 0


@pytest.mark.gnucap
@pytest.mark.ngspice
def test_ngspice_and_gnucap_agree_on_the_same_ac_netlist():
    chain = chain_for_case("uniform-bounded", 12)
    text = _ac_netlist(chain, 300)
    vectors = ("i(l1)", "i(l12)")
    ngspice, gnucap = (run_ac(AcJob(text, vectors, 300), engine=name) for name in ("ngspice", "gnucap"))
    assert (ngspice.engine, gnucap.engine) == ("ngspice", "gnucap")
    assert ngspice.netlist_sha256 == gnucap.netlist_sha256  # lcchain's text, whichever dialect ran
    assert np.allclose(gnucap.frequency, ngspice.frequency, rtol=RTOL_ENGINES_AC, atol=0.0)
    for name in vectors:
        a, b = ngspice.vectors[name], gnucap.vectors[name]
        assert a.dtype == b.dtype == np.complex128
        # the median: next to a pole the engines' frequencies (equal to 1e-15) already move |Y| by more
        assert np.median(np.abs(b - a) / np.abs(a)) < RTOL_ENGINES_AC


def test_the_gnucap_dialect_of_an_ac_netlist():
    text = _ac_netlist(chain_for_case("two-mass", 6), 64)
    lines = ENGINES["gnucap"].dialect(text, ["i(l1)", "i(l6)"]).splitlines()
    assert "V1 s1 0 DC 0 AC 1" in lines and not any("noopac" in line for line in lines)
    options = next(line for line in lines if line.startswith(".options")).split()
    assert {"numdgt=20", "short=1e-30"} <= set(options)  # every digit; no 1e-5 ohm in series with the source
    assert lines[-3:-1] == [".print ac ir(l1) ii(l1) ir(l6) ii(l6)", next(x for x in text.splitlines()
                                                                           if x.startswith(".ac"))]
    with pytest.raises(ParameterError, match="engine.*'.ac lin points f1 f2'"):
        ENGINES["gnucap"].dialect(text.replace(".ac lin", ".ac dec"), ["i(l1)"])
    with pytest.raises(ParameterError, match="one analysis"):
        ENGINES["gnucap"].dialect(text.replace(".end", ".tran 0.1 1 0 0.1 uic\n.end"), ["i(l1)"])


def test_gnucaps_ac_table_is_read_in_pairs():
    table = ("#Freq  ir(L1)  ii(L1)\n 1.K  250.n  -0.15915494309189535\n 2.K  0.  -79.577471545947675m\n")
    columns = read_ac_table(table)
    assert np.array_equal(columns["frequency"], [1e3, 2e3])
    assert np.array_equal(columns["i(l1)"], [250e-9 - 0.15915494309189535j, -0.079577471545947675j])
    with pytest.raises(SimulationError, match="cannot pair"):
        read_ac_table("#Freq  ir(L1)\n 1.K  250.n\n")


def test_an_unknown_engine_is_refused(capsys):
    with pytest.raises(ParameterError, match="engine"):
        measure_spectrum(chain_for_case("two-mass", 8), options=SpectrumOptions(engine="spectre"))
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--engine", "spectre"]) == 2
    err = capsys.readouterr().err
    assert "--engine" in err and "spectre" in err and err.count("\n") <= 2  # usage and one line


@pytest.mark.gnucap
def test_gnucap_runs_a_sweep_in_segments():
    """Several .ac cards (a sweep in segments, given out of order): every card's frequencies, in ascending order,
    each with the values a run of its card alone gives."""
    chain = chain_for_case("two-mass", 10)
    text = _ac_netlist(chain, 64)
    card = next(line for line in text.splitlines() if line.startswith(".ac"))
    low, high = ".ac lin 40 1000.0 150000.0", ".ac lin 24 150500.0 390000.0"
    alone = [run_ac(AcJob(text.replace(card, c), ["i(l10)"], n), engine="gnucap") for c, n in ((low, 40), (high, 24))]
    both = run_ac(AcJob(text.replace(card, f"{high}\n{low}"), ["i(l10)"], 64), engine="gnucap")
    assert np.array_equal(both.frequency, np.concatenate([r.frequency for r in alone]))
    assert np.array_equal(both.vectors["i(l10)"], np.concatenate([r.vectors["i(l10)"] for r in alone]))
    with pytest.raises(SimulationError, match="twice"):
        run_ac(AcJob(text.replace(card, f"{low}\n{low}"), ["i(l10)"], 80), engine="gnucap")


def test_gnucaps_sweep_is_priced_at_its_own_cost_before_it_runs():
    points = 200_000
    ngspice = run_estimate(points=points, saved=4, compared=4, unknowns=2 * 100)  # measure_spectrum's model
    between = ngspice.seconds * (1.0 + ENGINES["gnucap"].ac_relative_cost) / 2 + INTERPRETER_SECONDS
    budget = Budget(max_seconds=between)
    assert ngspice.fits(budget)  # ngspice's sweep would be allowed...
    with pytest.raises(BudgetError, match="points = 200000"):  # ...gnucap's, slower, is not
        measure_spectrum(chain_for_case("two-mass", 100), options=SpectrumOptions(points=points, engine="gnucap"), budget=budget)
