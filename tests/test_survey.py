"""Issue 32, item 1: every mode, with its shape, from one AC run that drives every loop (real ngspice).

Each mode's frequency, shape and (with losses) quality factor against a dense eigensolution written here
(scipy.linalg.eigh of K and M built from the chain's masses and springs: tests/helpers/dense.py), not lcchain's
theory.  A perfect cradle's edge modes weigh 2^-(2N-3) at the ends, invisible to a drive in loop 1; a survey sees
them on the loops where they live.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers.dense import dense_shapes
from helpers.tolerances import RTOL_SURVEY_OMEGA, RTOL_SURVEY_Q, RTOL_SURVEY_SHAPE

from lcchain.compare.spectral import OMEGA_WEIGHT_FLOOR
from lcchain.core.errors import ParameterError
from lcchain.runs.survey import measure_modes
from lcchain.theory.cases import chain_for_case

pytestmark = pytest.mark.ngspice


def _check_every_mode(report, chain) -> None:
    omega, u = dense_shapes(chain)
    assert report.omega.shape == (chain.N,)
    moving = omega > 0
    assert np.all(np.abs(report.omega[moving] - omega[moving]) <= RTOL_SURVEY_OMEGA * omega[moving])
    assert np.all(report.omega[~moving] == 0.0)  # a free chain's translation stays at 0
    for n in range(chain.N):
        measured = report.shapes[:, n]
        exact = u[:, n] * np.sign(u[:, n] @ measured)  # eigh's sign is its own
        assert np.max(np.abs(measured - exact)) <= RTOL_SURVEY_SHAPE * np.max(np.abs(exact)), n
    assert report.resolved.all()


@pytest.mark.parametrize(("case", "N"), [("perfect", 24), ("two-mass", 30), ("uniform-bounded", 20)])
def test_every_mode_and_shape(case, N):
    chain = chain_for_case(case, N)
    report = measure_modes(chain)
    _check_every_mode(report, chain)


def test_perfect_cradle_edge_modes_and_spacing():
    """The modes a drive in loop 1 cannot see (end weight 2^-(2N-3) = 2.8e-14 at N = 24, far below the weight a
    loop-1 fit places to its targets) and the spacing's constancy over the whole band."""
    chain = chain_for_case("perfect", 24)
    report = measure_modes(chain)
    omega, u = dense_shapes(chain)
    weakest = int(np.argmin(np.abs(u[0] * u[-1])))
    assert abs(chain.masses[0] * u[0, weakest] * u[-1, weakest]) < OMEGA_WEIGHT_FLOOR  # unseen at the ends
    assert report.resolved[weakest]
    assert report.spacing_deviation <= RTOL_SURVEY_OMEGA


def test_lossy_chain_every_Q():
    """Losses proportional to the masses: every mode decays at 1/Q, so Q_n = omega_n Q; two-mass N = 20 at
    Q = 100 has its modes tens of widths apart."""
    chain = chain_for_case("two-mass", 20)
    Q = 100.0
    report = measure_modes(chain, Q=Q)
    _check_every_mode(report, chain)
    omega, _ = dense_shapes(chain)
    moving = omega > 0
    assert np.all(np.abs(report.Q[moving] - omega[moving] * Q) <= RTOL_SURVEY_Q * omega[moving] * Q)


def test_bad_Q_is_refused_by_name():
    with pytest.raises(ParameterError, match="Q"):
        measure_modes(chain_for_case("two-mass", 8), Q=-1.0)


@pytest.mark.slow
@pytest.mark.parametrize(("case", "N"), [("perfect", 200), ("two-mass", 200)])
def test_every_mode_at_200(case, N):
    chain = chain_for_case(case, N)
    report = measure_modes(chain)
    _check_every_mode(report, chain)
    if case == "perfect":
        assert report.spacing_deviation <= RTOL_SURVEY_OMEGA


def test_cli_shapes_json(capsys):
    """``lcchain spectrum --shapes --json``: the survey beside the loop-1 fit, each mode's shape over the loops."""
    import json

    from lcchain.cli.main import main

    assert main(["spectrum", "--case", "perfect", "--N", "10", "--shapes", "--json"]) == 0
    survey = json.loads(capsys.readouterr().out)["survey"]
    assert survey["resolved"] == 10
    chain = chain_for_case("perfect", 10)
    omega, u = dense_shapes(chain)
    for mode, exact, shape in zip(survey["modes"], omega, u.T, strict=True):
        assert abs(mode["omega"] - exact) <= RTOL_SURVEY_OMEGA * max(exact, 1.0)
        measured = np.asarray(mode["shape"])
        assert np.max(np.abs(measured - shape * np.sign(shape @ measured))) <= RTOL_SURVEY_SHAPE


def test_shapes_refuse_other_effects():
    from lcchain.circuit.effects import CoilResistance
    from lcchain.runs.spectrum import SpectrumOptions, measure_spectrum

    with pytest.raises(ParameterError, match="shapes"):
        measure_spectrum(chain_for_case("two-mass", 8), options=SpectrumOptions(shapes=True, effects=(CoilResistance(0.01),)))


def test_a_sweep_cut_into_several_runs_gives_the_same_modes(monkeypatch):
    """A survey larger than one run's share of values is cut into runs of the same frequencies (the engine's raw
    file stays small): the modes are the same as from one run, to rounding of a few frequencies' cards."""
    import lcchain.runs.survey as survey

    chain = chain_for_case("two-mass", 24)
    whole = measure_modes(chain)
    monkeypatch.setattr(survey, "RUN_VALUES", 24 * 40)
    cut = measure_modes(chain)
    assert cut.points == whole.points
    _check_every_mode(cut, chain)
    assert np.all(np.abs(cut.omega - whole.omega) <= RTOL_SURVEY_OMEGA * np.maximum(whole.omega, 1.0))


def test_coupled_coils_every_mode_and_no_losses():
    """Coupled coils: M is tridiagonal (mutual inductances), the shapes M-orthonormal all the same; their losses
    are not proportional to M, so a survey with --Q is refused by name."""
    chain = chain_for_case("two-mass", 16).with_coupling(0.2)
    _check_every_mode(measure_modes(chain), chain)
    with pytest.raises(ParameterError, match="Q"):
        measure_modes(chain, Q=100.0)
