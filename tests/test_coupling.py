"""Coupled neighbouring coils (issue 20): the tridiagonal mass matrix in theory, K elements in the netlist.

The exact theory of a coupled chain (modes of K u = omega^2 M u) is checked against an independent
integration of the equations of motion, and ngspice against it within the accuracy model's prediction.
"""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest
from helpers.tolerances import (
    ACCURACY_COARSE,
    ATOL_COUPLED_ODE,
    ATOL_DENSITY_SUM,
    ATOL_DOP853_COUPLED,
    MIN_COUPLING_EFFECT,
    PREDICTION_FACTOR,
    RTOL_DOP853_COUPLED,
)
from scipy.integrate import solve_ivp

import lcchain
from lcchain.circuit.effects import EFFECTS, Coupling, Losses, tolerance_samples, with_walls
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import SimulationOptions, netlist_text
from lcchain.cli.main import main
from lcchain.core.errors import ParameterError
from lcchain.runs.spec import Theory
from lcchain.theory.arrivals import first_arrival
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.exact import exact_modes
from lcchain.theory.response import linear_response


def _matrices(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Mass and stiffness matrices written out from the definition (bulk units), independently of lcchain."""
    m, K, k = chain.masses, chain.springs, chain.coupling
    mutual = k * np.sqrt(m[:-1] * m[1:])
    M = np.diag(m) + np.diag(mutual, 1) + np.diag(mutual, -1)
    S = np.diag(K[:-1] + K[1:]) - np.diag(K[1:-1], 1) - np.diag(K[1:-1], -1)
    return M, S


def _integrate(chain: Chain, t: np.ndarray, start: np.ndarray, force=None) -> np.ndarray:
    """Loop currents (velocities) from M Q'' + S Q = F(t), Q(0) = 0, Q'(0) = start, by DOP853."""
    M, S = _matrices(chain)
    N = chain.N
    A = np.linalg.solve(M, S)
    Minv_e1 = np.linalg.solve(M, np.eye(N)[0] * chain.masses[0])

    def rhs(time, y):
        acceleration = -A @ y[:N]
        if force is not None:
            acceleration = acceleration + Minv_e1 * force(time)
        return np.concatenate((y[N:], acceleration))

    y0 = np.concatenate((np.zeros(N), start))
    solution = solve_ivp(rhs, (0.0, t[-1]), y0, t_eval=t, rtol=RTOL_DOP853_COUPLED, atol=ATOL_DOP853_COUPLED, method="DOP853",
                         max_step=0.05 if force is not None else np.inf)
    return solution.y[N:]


@pytest.mark.parametrize("case, N, k", [("two-mass", 16, 0.03), ("perfect", 12, -0.04), ("uniform-bounded", 9, 0.2)])
def test_coupled_response_matches_an_independent_integration(case, N, k):
    chain = chain_for_case(case, N).with_coupling(k)
    t = np.linspace(0.0, 3.0 * N, 400)
    kicked = _integrate(chain, t, np.eye(N)[0])
    assert np.max(np.abs(linear_response(chain, t) - kicked[[0, -1]])) < ATOL_COUPLED_ODE
    assert np.max(np.abs(linear_response(chain, t, loops="all") - kicked)) < ATOL_COUPLED_ODE
    # a rect pulse is a force m_1 g(t) on mass 1: through the coupled mass matrix it moves loop 2 at once too
    width = 0.5
    pushed = _integrate(chain, t, np.zeros(N), force=lambda time: 1.0 / width if time < width else 0.0)
    late = t >= 2 * width  # away from the pulse's discontinuity, which the integrator steps over
    response = linear_response(chain, t[late], excitation="pulse", pulse=("rect", width))
    assert np.max(np.abs(response - pushed[[0, -1]][:, late])) < ATOL_COUPLED_ODE
    assert abs(exact_modes(chain).density.sum() - 1.0) < ATOL_DENSITY_SUM


def test_coupling_changes_the_arrival_and_zero_coupling_changes_nothing():
    chain = chain_for_case("two-mass", 40)
    same = chain.with_coupling(0.0)
    assert same == chain and not same.coupled
    t = np.linspace(0.0, 80.0, 50)
    assert np.array_equal(linear_response(same, t), linear_response(chain, t))
    peak = first_arrival(chain).peak
    for k in (-0.05, 0.05):
        assert abs(first_arrival(chain.with_coupling(k)).peak - peak) > MIN_COUPLING_EFFECT


def test_coupled_chain_round_trips_and_effects_keep_the_coupling():
    chain = chain_for_case("two-mass", 10).with_coupling(0.02)
    assert pickle.loads(pickle.dumps(chain)) == chain
    assert Chain.from_dict(chain.to_dict()) == chain
    assert chain != chain.with_coupling(0.03) and "coupling" not in chain_for_case("two-mass", 10).to_dict()
    assert with_walls(chain, 0.1).coupling == 0.02
    assert {s.coupling for s in tolerance_samples(chain, 10e-6, 10e-9, samples=3, seed=1, tol_L=0.05,
                                                  tol_C=0.05, series="E24")} == {0.02}
    assert EFFECTS["coupling"] is Coupling and Coupling(0.02).realise(chain_for_case("two-mass", 10), 1, 1) == chain


def test_netlist_couples_each_pair_of_neighbouring_coils():
    chain = chain_for_case("perfect", 6).with_coupling(-0.1)
    text = netlist_text(Ladder(chain), SimulationOptions(dt=0.05, tstop=10.0))
    lines = [line for line in text.splitlines() if line.startswith("K")]
    assert lines == [f"K{i}_{i + 1} L{i} L{i + 1} -0.1" for i in range(1, 6)]
    plain = netlist_text(Ladder(chain_for_case("perfect", 6)), SimulationOptions(dt=0.05, tstop=10.0))
    assert [line for line in text.splitlines() if not line.startswith("K")] == plain.splitlines()


@pytest.mark.parametrize("value, field", [(0.5, "coupling"), (-0.5, "coupling"), (float("nan"), "coupling"),
                                          ("0.1", "coupling"), (True, "coupling")])
def test_bad_coupling_is_refused_naming_the_field(value, field):
    with pytest.raises(ParameterError, match=field):
        chain_for_case("two-mass", 10).with_coupling(value)
    with pytest.raises(ParameterError, match="effects.coupling.k"):
        Coupling(value)


def test_losses_with_coupling_are_refused_not_guessed():
    chain = chain_for_case("two-mass", 10).with_coupling(0.02)
    with pytest.raises(ParameterError, match="Q"):
        linear_response(chain, [0.0, 1.0], Q=50.0)
    with pytest.raises(ParameterError, match="Q"):
        Theory(chain, 1e-7, Q=50.0)
    # the netlist itself can be written (a user may simulate it), the theory cannot
    assert "R1 " in netlist_text(Ladder(chain), SimulationOptions(dt=0.05, tstop=5.0), effects=(Losses(50.0),))


@pytest.mark.ngspice
@pytest.mark.parametrize("case, N, k, excitation", [("two-mass", 30, 0.03, "kick"), ("perfect", 24, -0.05, "kick"),
                                                    ("two-mass", 20, 0.1, "displacement")])
def test_ngspice_matches_the_coupled_theory_within_the_predicted_error(case, N, k, excitation):
    chain = chain_for_case(case, N).with_coupling(k)
    report = lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.02, transits=2, excitation=excitation))
    assert report.netlist.count("\nK") == N - 1
    assert report.predicted_error is not None
    assert report.comparison.max_abs_error <= PREDICTION_FACTOR * report.predicted_error
    # the uncoupled theory would be far off: the comparison can fail
    plain = linear_response(chain_for_case(case, N), report.waveforms.t, excitation=excitation)
    assert np.max(np.abs(plain[1] - report.waveforms.last)) > 10 * report.comparison.max_abs_error


@pytest.mark.ngspice
def test_coupled_scene_and_cli(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the scene's report and plots are written beside the working folder
    scene = tmp_path / "coupled.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 30\n[excitation]\nkind = "pulse"\nshape = "gaussian"\n'
                     'width = 0.2\n[effects.coupling]\nk = 0.03\n[effects.tolerance]\nL = 0.02\nsamples = 2\n'
                     f'[analysis]\naccuracy = {ACCURACY_COARSE}\n[output]\nreport = "r.json"\n')
    assert main(["run", str(scene), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["max_abs_error"] <= ACCURACY_COARSE
    lossy = tmp_path / "lossy.toml"
    lossy.write_text(scene.read_text().replace("[effects.tolerance]", "[effects.losses]\nQ = 50\n[effects.tolerance]"))
    # coupled coils with losses: no chain's theory, the circuit's own (issue 30)
    assert main(["run", str(lossy), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["max_abs_error"] <= ACCURACY_COARSE
    for argv, name in ((["--coupling", "0.7"], "--coupling"), (["--coupling", "0.02", "--N", "2500"], "--N")):
        base = ["simulate", "--case", "two-mass", "--N", "20", "--dt", "0.05"]
        assert main(base + argv) == 2
        assert name in capsys.readouterr().err
    assert main(["netlist", "--case", "two-mass", "--N", "5", "--coupling", "0.02", "-o", str(tmp_path / "n.cir")]) == 0
    assert (tmp_path / "n.cir").read_text().count("\nK") == 4


@pytest.mark.ngspice
@pytest.mark.gnucap
@pytest.mark.parametrize("k", [0.03, -0.05])
def test_both_engines_match_the_coupled_theory(k):
    """--coupling in theory and in both engines: gnucap reads a coupled coil's ic= as flux over inductance, and
    its dialect translates the kick's currents (lcchain.spice.gnucap)."""
    chain = chain_for_case("two-mass", 30).with_coupling(k)
    reports = {engine: lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.02, transits=2, engine=engine)) for engine in ("ngspice", "gnucap")}
    for engine, report in reports.items():
        assert report.run.engine == engine
        assert report.predicted_error is not None
        assert report.comparison.max_abs_error <= PREDICTION_FACTOR * report.predicted_error
