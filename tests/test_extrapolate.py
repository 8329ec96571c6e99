"""Extrapolated ngspice runs (issue 14): checked against an exact solution that shares nothing with lcchain's.

The reference is numpy's dense ``eigh`` of the chain's mass-weighted stiffness matrix, built here from the
masses and springs (lcchain's theory uses closed forms or scipy's tridiagonal solvers): after a kick of loop 1,
the loop currents are v(t) = M^-1/2 cos(sqrt(B) t) M^1/2 e_1.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import lcchain
from lcchain.compare.extrapolate import (
    aligned_grid,
    combine,
    plan_for_accuracy,
    predicted_extrapolated_error,
    refusal,
)
from lcchain.core.errors import ParameterError
from lcchain.theory.arrivals import stop_time
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.spectrum import normal_modes

#: The prediction is made before any run; the issue asks for it within a factor 2 of what is achieved.
PREDICTION_FACTOR = 2.0


def exact_end_currents(chain: Chain, t: np.ndarray) -> np.ndarray:
    """Loop 1 and loop N currents over the kick, by dense diagonalisation (rows: first, last)."""
    m = np.asarray(chain.masses, dtype=float)
    k = np.asarray(chain.springs, dtype=float)
    K = np.diag(k[:-1] + k[1:]) - np.diag(k[1:-1], 1) - np.diag(k[1:-1], -1)
    s = 1.0 / np.sqrt(m)
    values, U = np.linalg.eigh(s[:, None] * K * s[None, :])
    omega = np.sqrt(np.clip(values, 0.0, None))
    start = U[0, :] * np.sqrt(m[0])  # U^T M^1/2 e_1
    rows = np.vstack([U[0, :] * s[0], U[-1, :] * s[-1]]) * start  # (2, N)
    return rows @ np.cos(np.multiply.outer(omega, t))


@pytest.mark.ngspice
@pytest.mark.parametrize(("N", "eps"), [(20, 1e-5), (20, 1e-7), (100, 1e-5), (100, 1e-7), (1000, 1e-5),
                                        (1000, 1e-7)])
def test_accuracy_is_met_on_the_first_try_against_an_independent_solution(N: int, eps: float) -> None:
    chain = chain_for_case("two-mass", N)
    report = lcchain.simulate(chain, accuracy=eps)
    x = report.extrapolation
    w = report.waveforms
    exact = exact_end_currents(chain, w.t)
    achieved = float(np.max(np.abs(np.vstack([w.first, w.last]) - exact)))
    assert achieved <= eps
    assert report.predicted_error / PREDICTION_FACTOR <= achieved <= report.predicted_error * PREDICTION_FACTOR
    assert abs(achieved - report.comparison.max_abs_error) <= 1e-3 * eps  # lcchain's theory agrees
    if N >= 100 and eps <= 1e-7:
        assert x.runs > 1, "extrapolation is the cheapest way to 1e-7 on these chains"
    if x.runs > 1:
        # every member on its own is far from eps: the combination did the work
        assert all(m.metrics.max_abs_error > 10 * eps for m in x.members)
        assert x.steps == tuple(x.steps[0] / 2**i for i in range(x.runs))
        assert all(m.metrics.integration_error < 1e-9 for m in x.members)  # ngspice = its trapezoidal model
        assert x.interpolation_error < 1e-3 * eps
        data = report.to_dict()["extrapolation"]
        assert [member["dt"] for member in data["members"]] == list(x.steps)
        assert all(member["wall_s"] > 0 and member["max_abs_error"] > 0 for member in data["members"])


@pytest.mark.ngspice
def test_aligned_runs_take_the_steps_the_model_predicts() -> None:
    chain = chain_for_case("two-mass", 20)
    modes = normal_modes(chain)
    for dt in (0.09, 0.0123):
        report = lcchain.simulate(chain, dt=dt, extrapolate=2, modes=modes)
        for h, member in zip(report.extrapolation.steps, report.extrapolation.members, strict=True):
            assert member.signals is not None
            t = np.asarray(member.signals.t)
            grid = aligned_grid(h, report.options.tstop)
            assert t.size == grid.size
            assert np.max(np.abs(t - grid)) <= 1e-9 * report.options.tstop


def test_the_combination_cancels_the_step_terms_of_a_model() -> None:
    # Three signals with errors c2 h^2 + c4 h^4 on shifted grids: a triple leaves only the h^6 part.
    t0 = np.linspace(0.0, 10.0, 201)
    times = [t0, np.linspace(0.0, 10.0, 401), np.linspace(0.0, 10.0, 801)]
    h = [0.1, 0.05, 0.025]
    signals = [np.sin(t)[None, :] * (1 + 0.3 * hh**2 + 0.2 * hh**4) for t, hh in zip(times, h, strict=True)]
    grid, combined, keep = combine(times, signals)
    assert keep.all() and np.array_equal(grid, t0)
    assert np.max(np.abs(combined[0] - np.sin(t0))) < 0.2 * 0.1**6
    _, pair, _ = combine(times[:2], signals[:2])
    assert np.max(np.abs(pair[0] - np.sin(t0))) > 0.2 * 0.1**6


def test_the_prediction_falls_with_the_order_of_the_combination() -> None:
    modes = normal_modes(chain_for_case("two-mass", 100))
    tstop = stop_time(modes, 1)
    one, pair, triple = (predicted_extrapolated_error(modes, 0.04, runs, tstop) for runs in (1, 2, 3))
    assert one > 100 * pair > 100 * triple
    halved = predicted_extrapolated_error(modes, 0.02, 2, tstop)
    assert 8 < pair / halved < 20  # h^4, with the start-up steps' h^3 remainder


@pytest.mark.ngspice
def test_gear_is_not_extrapolated_and_says_why() -> None:
    report = lcchain.simulate(chain_for_case("two-mass", 20), dt=0.05, method="gear", extrapolate=3)
    assert report.extrapolation.runs == 1 and "gear" in report.extrapolation.reason
    report = lcchain.simulate(chain_for_case("two-mass", 20), accuracy=1e-4, method="gear")
    assert report.extrapolation.runs == 1 and "gear" in report.extrapolation.reason
    assert report.comparison.max_abs_error <= 1e-4  # gear's own error model chose its step


def test_what_cannot_be_extrapolated_is_refused_with_a_reason() -> None:
    assert refusal() == ""
    assert "adaptive" in refusal(stepping="adaptive")
    assert "rect" in refusal(pulse=("rect", 2.0))
    assert refusal(pulse=("gaussian", 2.0)) == ""
    modes = normal_modes(chain_for_case("two-mass", 50))
    plan = plan_for_accuracy(modes, 1e-7, stop_time(modes, 1), refused=refusal(stepping="adaptive"))
    assert plan.runs == 1 and "adaptive" in plan.reason
    with pytest.raises(ParameterError, match="extrapolate"):
        plan_for_accuracy(modes, 1e-5, stop_time(modes, 1), extrapolate=4)
    with pytest.raises(ParameterError, match="extrapolate"):
        lcchain.simulate(chain_for_case("two-mass", 20), dt=0.05, extrapolate=True)  # type: ignore[arg-type]


def _cli(*argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "lcchain", *argv], capture_output=True, text=True, timeout=300)


@pytest.mark.ngspice
def test_the_command_line_reports_every_run() -> None:
    done = _cli("simulate", "--case", "two-mass", "--N", "100", "--accuracy", "1e-7")
    assert done.returncode == 0, done.stderr
    assert "extrapolated from 2 runs" in done.stdout or "extrapolated from 3 runs" in done.stdout
    assert "interpolation error" in done.stdout
    done = _cli("simulate", "--case", "two-mass", "--N", "50", "--dt", "0.05", "--extrapolate", "2", "--json")
    assert done.returncode == 0, done.stderr
    data = json.loads(done.stdout)
    x = data["extrapolation"]
    assert x["runs"] == 2 and x["dt"] == [0.05, 0.025] and len(x["members"]) == 2
    assert data["points"] == sum(member["points"] for member in x["members"])
    assert data["max_abs_error"] < min(member["max_abs_error"] for member in x["members"]) / 10
    done = _cli("simulate", "--case", "two-mass", "--N", "50", "--dt", "0.05", "--extrapolate", "4")
    assert done.returncode == 2 and "--extrapolate" in done.stderr and "Traceback" not in done.stderr


def _scene(tmp_path, body: str):
    from lcchain.scenes.load import load_scene

    path = tmp_path / "scene.toml"
    path.write_text(body)
    return load_scene(path)


@pytest.mark.ngspice
def test_a_scene_with_losses_is_extrapolated_to_its_accuracy(tmp_path) -> None:
    from lcchain.scenes.run import simulate_scene

    scene = _scene(tmp_path, '[chain]\ncase = "two-mass"\nN = 60\n[effects.losses]\nQ = 50\n'
                             '[analysis]\naccuracy = 1e-7\n')
    result = simulate_scene(scene)
    report = result.report
    x = report["samples"][0]["extrapolation"]
    assert x["runs"] > 1 and len(report["steps"]) == x["runs"]
    assert report["accuracy_met"] and report["max_abs_error"] <= 1e-7
    achieved = report["max_abs_error"]
    assert x["predicted_error"] / PREDICTION_FACTOR <= achieved <= x["predicted_error"] * PREDICTION_FACTOR
    assert all(member["max_abs_error"] > 10 * achieved for member in x["members"])


@pytest.mark.ngspice
def test_a_scene_with_a_rect_pulse_falls_back_to_one_run_and_says_why(tmp_path) -> None:
    from lcchain.scenes.run import simulate_scene

    body = ('[chain]\ncase = "two-mass"\nN = 20\n[excitation]\nkind = "pulse"\nshape = "{shape}"\nwidth = 0.5\n'
            '[analysis]\ndt = 0.02\nextrapolate = 2\n')
    rect = simulate_scene(_scene(tmp_path, body.format(shape="rect"))).report
    assert rect["steps"] == [0.02] and "rect" in rect["samples"][0]["extrapolation"]["reason"]
    gaussian = simulate_scene(_scene(tmp_path, body.format(shape="gaussian"))).report
    assert gaussian["steps"] == [0.02, 0.01] and gaussian["samples"][0]["extrapolation"]["reason"] == ""


def test_a_bad_extrapolate_in_a_scene_is_named(tmp_path) -> None:
    for value in ("4", "0", "1.5", "true"):
        with pytest.raises(ParameterError, match="analysis.extrapolate"):
            _scene(tmp_path, f'[chain]\ncase = "two-mass"\nN = 20\n[analysis]\nextrapolate = {value}\n')
