"""Issue 32 items 3 and 5: a survey of every loop says the modes losses merge, and measures the rest (real ngspice).

Around the boundary of the Q range the lossy fit separates modes in, two-mass N = 20 to 40 (and one-mass N = 30) from
Q far below it (every mode merged) to three times above (none): the merged set is the loop-1 fit's rule
(:func:`lcchain.compare.spectral.merged_modes`) computed here from the test's own dense eigensolution
(tests/helpers/dense.py: scipy.linalg.eigh of K and M), not lcchain's modes.  No merged mode is reported as resolved
or given a value; every other mode is held to the survey's targets; every loop's current over the sweep is compared
with the chain's exact one; the JSON holds no NaN or infinity; ``lcchain spectrum --shapes`` says the merged modes,
the same as the loop-1 fit's, and exits 0 without an error of a mode it did not measure.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
from helpers.dense import dense_shapes
from helpers.tolerances import (
    RTOL_LOOP_CURRENTS,
    RTOL_SURVEY_CURRENTS,
    RTOL_SURVEY_OMEGA,
    RTOL_SURVEY_Q,
    RTOL_SURVEY_SHAPE,
)

from lcchain.compare.spectral import LOSSY_GAP_Q, LOSSY_GAP_Q_WEAK, LOSSY_WEAK_RATIO, merged_modes
from lcchain.compare.survey import survey_amplitudes
from lcchain.runs.survey import measure_modes
from lcchain.theory.cases import chain_for_case
from lcchain.theory.exact import driven_modes
from lcchain.theory.spectrum import loop_currents

pytestmark = pytest.mark.ngspice


def _boundary(omega: np.ndarray, P: np.ndarray) -> float:
    """The lowest Q the lossy fit separates every mode at: LOSSY_GAP_Q over the smallest gap (LOSSY_GAP_Q_WEAK where
    one of the two weighs less than LOSSY_WEAK_RATIO of the other at the ends), and 1 over the lowest moving mode."""
    weight = np.abs(P)
    ratio = np.minimum(weight[1:], weight[:-1]) / np.maximum(weight[1:], weight[:-1])
    per_gap = np.where(ratio < LOSSY_WEAK_RATIO, LOSSY_GAP_Q_WEAK, LOSSY_GAP_Q) / np.diff(omega)
    return max(float(np.max(per_gap)), 1.0 / float(omega[omega > 0][0]))


def _expected(chain, fraction: float) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Q = ``fraction`` of the boundary; the modes merged there (half-power bands overlapping a neighbour's, or
    reaching zero frequency, below the boundary; none above), the dense frequencies and shapes."""
    omega, u = dense_shapes(chain)
    lowest = _boundary(omega, chain.masses[0] * u[0] * u[-1])
    Q = max(1.0, fraction * lowest)  # the losses' own range: Q >= 1
    gaps = np.diff(omega)
    nearest = np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf])
    merged = ((nearest * Q < 1.0) | ((omega > 0) & (omega * Q < 1.0))) if Q < lowest else np.zeros(omega.size, bool)
    return Q, merged, omega, u


# (case, N, Q as a fraction of the boundary): 0.1 every mode merged, 0.6 and 0.9 some, 1.1 and 3 none; two-mass
# N = 100 at Q = 10.5 and 105 (the boundary is 210), about the benchmark's rows at Q = 10 (every mode merged) and 100
FAMILY = [(case, N, fraction) for case, N in (("two-mass", 20), ("two-mass", 30), ("two-mass", 40))
          for fraction in (0.1, 0.6, 0.9, 1.1, 3.0)] + [("one-mass", 30, 0.6), ("one-mass", 30, 1.1),
                                                         ("two-mass", 100, 0.05), ("two-mass", 100, 0.5)]


@pytest.mark.parametrize(("case", "N", "fraction"), FAMILY)
def test_merged_modes_are_said_and_the_rest_measured(case, N, fraction):
    chain = chain_for_case(case, N)
    Q, merged, omega, u = _expected(chain, fraction)
    report = measure_modes(chain, Q=Q)
    assert np.array_equal(report.merged_modes, merged)
    assert np.array_equal(report.merged_modes, merged_modes(driven_modes(chain), Q))  # the loop-1 fit's own
    assert (fraction < 1.0) == bool(merged.any())  # the family straddles the boundary
    assert not (report.resolved & merged).any()
    assert np.all(np.isnan(report.omega[merged])) and np.all(np.isnan(report.shapes[:, merged]))
    measured = ~merged
    assert report.resolved[measured].all() and report.failure == ""
    moving = measured & (omega > 0)
    assert np.all(np.abs(report.omega[moving] - omega[moving]) <= RTOL_SURVEY_OMEGA * omega[moving])
    for n in np.flatnonzero(measured):
        exact = u[:, n] * np.sign(u[:, n] @ report.shapes[:, n])  # eigh's sign is its own
        assert np.max(np.abs(report.shapes[:, n] - exact)) <= RTOL_SURVEY_SHAPE * np.max(np.abs(exact)), n
    separated = report.separated
    assert not (separated & merged).any()
    assert np.all(np.abs(report.Q[separated] - omega[separated] * Q) <= RTOL_SURVEY_Q * omega[separated] * Q)
    if merged.any():
        assert report.envelope_error is not None and report.envelope_error < RTOL_SURVEY_CURRENTS
    else:
        assert report.envelope_error is None
    data = report.to_dict()
    json.dumps(data, allow_nan=False)  # never inf, never NaN
    assert data["merged"] == [int(n) + 1 for n in np.flatnonzero(merged)]
    assert data["measured"] == int(measured.sum()) and data["resolved"] == int(measured.sum())
    for mode in data["modes"]:
        if mode["merged"]:
            assert mode["omega"] is None and mode["omega_error"] is None and mode["shape"] is None
            assert mode["shape_error"] is None and mode["Q"] is None and not mode["resolved"]
    if not measured.any():  # nothing measured: no error to give, not an error of 0
        assert data["max_rel_error_omega"] is None and data["max_shape_error"] is None
        assert math.isnan(report.max_rel_error_omega) and report.sweeps == 0


def test_a_measured_mode_off_its_target_fails_and_a_merged_one_does_not():
    """The survey fails on a measured mode outside the targets, never on a merged one (it has no value)."""
    chain = chain_for_case("two-mass", 20)
    Q, merged, _, _ = _expected(chain, 0.9)
    report = measure_modes(chain, Q=Q)
    assert merged.any() and report.failure == ""
    n = int(np.flatnonzero(~merged)[0])
    if report.omega[n] == 0.0:  # a free chain's translation: the next
        n = int(np.flatnonzero(~merged)[1])
    omega = report.omega.copy()
    omega[n] *= 1.0 + 1e3 * RTOL_SURVEY_OMEGA
    off = replace(report, omega=omega)
    assert f"n = {n + 1}" in off.failure and "merged by the losses" in off.failure


def test_cli_says_the_merged_modes_as_the_loop_1_fit_does(capsys):
    """``lcchain spectrum --shapes`` at a Q where some modes merge: the survey's merged list is the loop-1 fit's,
    its table has no value and no error for them, and it exits 0."""
    from lcchain.cli.main import main

    chain = chain_for_case("two-mass", 20)
    Q, merged, _, _ = _expected(chain, 0.6)
    args = ["spectrum", "--case", "two-mass", "--N", "20", "--Q", repr(Q), "--shapes"]
    assert main(args + ["--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["survey"]["merged"] == data["merged"] == [int(n) + 1 for n in np.flatnonzero(merged)]
    assert main(args) == 0
    out = capsys.readouterr().out
    survey = out[out.index("every-loop survey"):]
    assert "merged by the losses (said, not measured): n = " in survey
    assert "nan" not in survey and "inf" not in survey


def test_cli_every_mode_merged_is_said_not_compared(capsys):
    """Every mode merged: the survey fits nothing, says so, compares the loops' currents, and exits 0 (as
    ``lcchain spectrum`` without --shapes does: 'no mode is resolved ... not compared')."""
    from lcchain.cli.main import main

    chain = chain_for_case("two-mass", 20)
    Q, merged, _, _ = _expected(chain, 0.1)
    assert merged.all()
    assert main(["spectrum", "--case", "two-mass", "--N", "20", "--Q", repr(Q), "--shapes"]) == 0
    captured = capsys.readouterr()
    survey = captured.out[captured.out.index("every-loop survey"):]
    assert "no mode is measured: omega_n, the shapes, P_n and Q_n are not compared" in survey
    assert "n = 1-20 (20 of 20 modes)" in survey and "max rel. error of the loops' currents" in survey
    assert "nan" not in survey and "inf" not in survey and captured.err == ""


@pytest.mark.parametrize(("chain", "Q"), [(chain_for_case("two-mass", 16), 100.0), (chain_for_case("perfect", 12), 1000.0),
                                          (chain_for_case("two-mass", 16).with_coupling(0.2), 50.0)],
                         ids=["two-mass", "perfect", "coupled"])
def test_loop_currents_are_the_dense_solution(chain, Q):
    """The reference merged modes are measured by: every loop's current from the tridiagonal's elimination against
    numpy.linalg.solve of the dense K - omega^2 M + j omega M / Q written here (coupled coils: M tridiagonal)."""
    m, K = chain.masses, chain.springs
    mutual = chain.coupling * np.sqrt(m[:-1] * m[1:])
    M = np.diag(m) + np.diag(mutual, 1) + np.diag(mutual, -1)
    S = np.diag(K[:-1] + K[1:]) - np.diag(K[1:-1], 1) - np.diag(K[1:-1], -1)
    omega = np.linspace(0.013, 2.2, 3001)
    b = survey_amplitudes(chain.N)
    dense = np.array([np.linalg.solve(S - w * w * M + 1j * w / Q * M, b) for w in omega])
    got = loop_currents(chain, omega, b, Q)
    assert np.max(np.max(np.abs(got - dense), axis=1) / np.max(np.abs(dense), axis=1)) <= RTOL_LOOP_CURRENTS


def test_a_pole_start_is_a_class_and_pickles() -> None:
    """PoleStart was wrapped by the BLAS-thread decorator (a function in its place): its instances could not be
    pickled to another process, nor told by isinstance."""
    import pickle

    from lcchain.compare.survey import PoleStart

    start = PoleStart(np.array([1.0, 2.0]), np.array([0.1, 0.2]), np.array([False, True]), np.array([True, False]),
                      np.zeros((2, 2)))
    copy = pickle.loads(pickle.dumps(start))
    assert isinstance(copy, PoleStart)
    assert np.array_equal(copy.x, start.x) and np.array_equal(copy.fixed_gamma, start.fixed_gamma)
