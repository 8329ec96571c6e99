"""Extrapolated ngspice runs (issue 14): checked against an exact solution that shares nothing with lcchain's.

The reference is numpy's dense ``eigh`` of the chain's mass-weighted stiffness matrix, built here from the
masses and springs (lcchain's theory uses closed forms or scipy's tridiagonal solvers): after a kick of loop 1,
the loop currents are v(t) = M^-1/2 cos(sqrt(B) t) M^1/2 e_1.
"""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_TRAP_MODEL_MEMBERS,
    RTOL_ALIGNED_GRID,
    RTOL_HALVED_STEP,
    RTOL_INTERPOLATION_OF_ACCURACY,
    RTOL_MEAN_OF_SAMPLES,
    RTOL_THEORY_OF_ACCURACY,
)

import lcchain
from lcchain.compare.extrapolate import (
    AccuracyOptions,
    aligned_grid,
    combine,
    plan_for_accuracy,
    predicted_extrapolated_error,
    refusal,
)
from lcchain.core.errors import ParameterError
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import SweepAxes
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
@pytest.mark.parametrize(("N", "eps"), [(20, 1e-5), (20, 1e-7), (100, 1e-5), (100, 1e-7),
                                        pytest.param(1000, 1e-5, marks=pytest.mark.slow),  # 8 s
                                        pytest.param(1000, 1e-7, marks=pytest.mark.slow)])  # 16 s
def test_accuracy_is_met_on_the_first_try_against_an_independent_solution(N: int, eps: float) -> None:
    chain = chain_for_case("two-mass", N)
    report = lcchain.simulate_chain(chain, lcchain.ChainOptions(accuracy=eps))
    x = report.extrapolation
    w = report.waveforms
    exact = exact_end_currents(chain, w.t)
    achieved = float(np.max(np.abs(np.vstack([w.first, w.last]) - exact)))
    assert achieved <= eps
    assert report.predicted_error / PREDICTION_FACTOR <= achieved <= report.predicted_error * PREDICTION_FACTOR
    assert abs(achieved - report.comparison.max_abs_error) <= RTOL_THEORY_OF_ACCURACY * eps  # lcchain's theory agrees
    if N >= 100 and eps <= 1e-7:
        assert x.runs > 1, "extrapolation is the cheapest way to 1e-7 on these chains"
    if x.runs > 1:
        # every member on its own is far from eps: the combination did the work
        assert all(m.metrics.max_abs_error > 10 * eps for m in x.members)
        assert x.steps == tuple(x.steps[0] / 2**i for i in range(x.runs))
        assert all(m.metrics.integration_error < ATOL_TRAP_MODEL_MEMBERS for m in x.members)  # ngspice = its trapezoidal model
        assert x.interpolation_error < RTOL_INTERPOLATION_OF_ACCURACY * eps
        data = report.to_dict()["extrapolation"]
        assert [member["dt"] for member in data["members"]] == list(x.steps)
        assert all(member["wall_s"] > 0 and member["max_abs_error"] > 0 for member in data["members"])


@pytest.mark.ngspice
def test_aligned_runs_take_the_steps_the_model_predicts() -> None:
    chain = chain_for_case("two-mass", 20)
    modes = normal_modes(chain)
    for dt in (0.09, 0.0123):
        report = lcchain.simulate(lcchain.ChainOptions(dt=dt, extrapolate=2).request(chain), modes=modes)
        for h, member in zip(report.extrapolation.steps, report.extrapolation.members, strict=True):
            assert member.signals is not None
            t = np.asarray(member.signals.t)
            grid = aligned_grid(h, report.options.tstop)
            assert t.size == grid.size
            assert np.max(np.abs(t - grid)) <= RTOL_ALIGNED_GRID * report.options.tstop


def test_the_combination_cancels_the_step_terms_of_a_model() -> None:
    # Three signals with errors c2 h^2 + c4 h^4 on shifted grids: a triple leaves only the h^6 part.
    t0 = np.linspace(0.0, 10.0, 201)
    times = [t0, np.linspace(0.0, 10.0, 401), np.linspace(0.0, 10.0, 801)]
    h = [0.1, 0.05, 0.025]
    c2, c4 = 0.3, 0.2
    signals = [np.sin(t)[None, :] * (1 + c2 * hh**2 + c4 * hh**4) for t, hh in zip(times, h, strict=True)]
    grid, combined, keep = combine(times, signals)
    assert keep.all() and np.array_equal(grid, t0)
    assert np.max(np.abs(combined[0] - np.sin(t0))) < c4 * h[0]**6
    _, pair, _ = combine(times[:2], signals[:2])
    assert np.max(np.abs(pair[0] - np.sin(t0))) > c4 * h[0]**6


def test_the_prediction_falls_with_the_order_of_the_combination() -> None:
    modes = normal_modes(chain_for_case("two-mass", 100))
    tstop = stop_time(modes, 1)
    one, pair, triple = (predicted_extrapolated_error(modes, 0.04, runs, tstop) for runs in (1, 2, 3))
    assert one > 100 * pair > 100 * triple
    halved = predicted_extrapolated_error(modes, 0.02, 2, tstop)
    assert 8 < pair / halved < 20  # h^4, with the start-up steps' h^3 remainder


@pytest.mark.ngspice
def test_gear_is_not_extrapolated_and_says_why() -> None:
    report = lcchain.simulate_chain(chain_for_case("two-mass", 20), lcchain.ChainOptions(dt=0.05, method="gear", extrapolate=3))
    assert report.extrapolation.runs == 1 and "gear" in report.extrapolation.reason
    accuracy = 1e-4
    report = lcchain.simulate_chain(chain_for_case("two-mass", 20), lcchain.ChainOptions(accuracy=accuracy, method="gear"))
    assert report.extrapolation.runs == 1 and "gear" in report.extrapolation.reason
    assert report.comparison.max_abs_error <= accuracy  # gear's own error model chose its step


def test_what_cannot_be_extrapolated_is_refused_with_a_reason() -> None:
    assert refusal() == ""
    assert "adaptive" in refusal(stepping="adaptive")
    assert "rect" in refusal(pulse=("rect", 2.0))
    assert refusal(pulse=("gaussian", 2.0)) == ""
    modes = normal_modes(chain_for_case("two-mass", 50))
    plan = plan_for_accuracy(modes, 1e-7, stop_time(modes, 1), AccuracyOptions(refused=refusal(stepping="adaptive")))
    assert plan.runs == 1 and "adaptive" in plan.reason
    with pytest.raises(ParameterError, match="extrapolate"):
        plan_for_accuracy(modes, 1e-5, stop_time(modes, 1), AccuracyOptions(extrapolate=4))
    with pytest.raises(ParameterError, match="extrapolate"):
        lcchain.simulate_chain(chain_for_case("two-mass", 20), lcchain.ChainOptions(dt=0.05, extrapolate=True))  # type: ignore[arg-type]


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

    accuracy = 1e-7
    scene = _scene(tmp_path, '[chain]\ncase = "two-mass"\nN = 60\n[effects.losses]\nQ = 50\n'
                             f'[analysis]\naccuracy = {accuracy!r}\n')
    result = simulate_scene(scene)
    report = result.report
    x = report["samples"][0]["extrapolation"]
    assert x["runs"] > 1 and len(report["steps"]) == x["runs"]
    assert report["accuracy_met"] and report["max_abs_error"] <= accuracy
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


# ---------------------------------------------------------------- sweeps: the members are tasks of the store

@pytest.mark.ngspice
def test_a_sweep_runs_the_members_as_tasks_and_stores_what_simulate_gives(tmp_path) -> None:
    from lcchain.studies.plan import sweep_plan
    from lcchain.studies.run import run_plan
    from lcchain.studies.store import Store

    chain = chain_for_case("two-mass", 40)
    accuracy = 1e-6
    report = lcchain.simulate_chain(chain, lcchain.ChainOptions(accuracy=accuracy))
    x = report.extrapolation
    assert x is not None and x.runs == 2  # the cheapest way to 1e-6 at N = 40 is a pair
    summary = run_plan(sweep_plan(SweepAxes(cases=["two-mass"], Ns=[40], accuracies=[accuracy])), tmp_path / "s.sqlite", RunOptions(executor="process", workers=2))
    assert (summary.total, summary.ran, summary.ok, summary.combined) == (2, 2, 2, 1)
    with Store(tmp_path / "s.sqlite") as store:
        runs = store.runs()
        combined_arrays = store.waveforms(runs[2].key)
    assert [run.params.get("member") for run in runs] == [1, 2, None] and runs[2].params["runs"] == 2
    assert [run.kind for run in runs] == ["member", "member", "combined"]
    assert [run.params["dt"] for run in runs] == [*x.steps, x.steps[0]]
    assert [run.digest for run in runs[:2]] == [member.digest for member in x.members]
    # the combination made from the store's arrays is the one simulate made from its runs
    assert runs[2].digest == x.digest and runs[2].metrics is not None
    assert runs[2].metrics["max_abs_error"] == report.comparison.max_abs_error <= accuracy
    assert runs[2].metrics["predicted_error"] == x.predicted_error
    assert runs[2].points == sum(run.points for run in runs[:2])
    assert combined_arrays is not None and sorted(combined_arrays) == ["loop0", "loop1", "time"]


def _sweep_to_the_middle(store_path, stored: int):
    """A sweep whose driver died after ``stored`` of its member runs were stored: they are stored by hand."""
    from lcchain.runs.execute import execute
    from lcchain.spice.ngspice.find import find_simulator
    from lcchain.studies.plan import sweep_plan
    from lcchain.studies.store import Store

    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[30], dts=[0.05], extrapolate=3))
    simulator = find_simulator("batch")
    with Store(store_path) as store:
        store.adopt(plan.fingerprint(simulator.version), dict(plan.description), plan.rows(simulator.version),
                    simulator.version)
        for task in plan.tasks[:stored]:
            store.add(execute(task.spec, simulator))
    return plan


@pytest.mark.ngspice
@pytest.mark.parametrize("stored", [1, 3])
def test_a_resumed_sweep_combines_members_stored_before_the_crash(tmp_path, stored: int) -> None:
    from lcchain.studies.run import run_plan
    from lcchain.studies.store import Store

    clean = run_plan(_sweep_to_the_middle(tmp_path / "clean.sqlite", 0), tmp_path / "clean.sqlite", RunOptions(executor="serial"))
    plan = _sweep_to_the_middle(tmp_path / "resumed.sqlite", stored)
    resumed = run_plan(plan, tmp_path / "resumed.sqlite", RunOptions(executor="serial"))
    assert (clean.ran, clean.combined) == (3, 1)
    assert (resumed.skipped, resumed.ran, resumed.ok, resumed.combined) == (stored, 3 - stored, 3, 1)
    with Store(tmp_path / "clean.sqlite") as a, Store(tmp_path / "resumed.sqlite") as b:
        assert [run.digest for run in a.runs()] == [run.digest for run in b.runs()]
        assert len(b.runs()) == 4 and b.runs()[3].params["runs"] == 3


@pytest.mark.ngspice
def test_points_sharing_a_member_run_it_once(tmp_path) -> None:
    from lcchain.studies.plan import sweep_plan
    from lcchain.studies.run import run_plan

    # the pair at 0.04 ends with an aligned run at 0.02, the pair at 0.02 starts with it
    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[20], dts=[0.04, 0.02], extrapolate=2))
    summary = run_plan(plan, tmp_path / "s.sqlite", RunOptions(executor="serial"))
    assert (summary.total, summary.ran, summary.ok, summary.combined) == (3, 3, 3, 2) and summary.complete
    assert plan.estimate() < sum(task.seconds for task in plan.tasks)  # the shared run is priced once
    again = run_plan(plan, tmp_path / "s.sqlite", RunOptions(executor="serial"))
    assert (again.total, again.skipped, again.ran) == (3, 3, 0)


@pytest.mark.ngspice
def test_a_failed_member_fails_its_combination_and_names_the_run(tmp_path) -> None:
    from lcchain.studies.plan import sweep_plan
    from lcchain.studies.run import run_plan
    from lcchain.studies.store import Store

    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[2000], dts=[0.01], extrapolate=2, timeout=0.5))
    summary = run_plan(plan, tmp_path / "s.sqlite", RunOptions(executor="serial"))
    assert (summary.ok, summary.failed, summary.combined, summary.combined_failed) == (0, 2, 0, 1)
    with Store(tmp_path / "s.sqlite") as store:
        combined = store.runs()[2]
    assert combined.status == "timeout" and "(the run at dt = 0.01, 1 of 2)" in combined.reason


@pytest.mark.ngspice
def test_a_scene_sweep_extrapolates_each_sample_and_sums_up_the_combinations(tmp_path, capsys) -> None:
    from lcchain.cli import main
    from lcchain.scenes.run import simulate_scene

    body = ('[chain]\ncase = "two-mass"\nN = 16\n[effects.tolerance]\nL = 0.02\nsamples = 3\nseed = 4\n'
            '[analysis]\ndt = 0.05\nextrapolate = 2\n[output]\nplots = []\n')
    scene = _scene(tmp_path, body)
    alone = simulate_scene(scene).report
    store = tmp_path / "v.sqlite"
    status = main(["sweep", str(tmp_path / "scene.toml"), "--vary", "units.L0=10e-6", "--store", str(store),
                   "--executor", "serial", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert status == 0 and (summary["total"], summary["ok"], summary["combined"]) == (6, 6, 3)
    assert main(["results", str(store), "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    combined = [row for row in rows if "runs" in row["params"]]
    assert [row["digest"] for row in combined] == [sample["digest"] for sample in alone["samples"]]
    assert main(["results", str(store), "--summary", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)
    assert len(groups) == 1 and groups[0]["n"] == 3  # the members are ingredients, not samples
    assert groups[0]["mean"] == pytest.approx(alone["transmitted_peak"]["mean"], rel=RTOL_MEAN_OF_SAMPLES)


def test_an_extrapolate_beside_a_scene_is_refused(tmp_path) -> None:
    _scene(tmp_path, '[chain]\ncase = "two-mass"\nN = 16\n')
    done = _cli("sweep", str(tmp_path / "scene.toml"), "--extrapolate", "2", "--store", str(tmp_path / "s.sqlite"))
    assert done.returncode == 2 and "--extrapolate" in done.stderr and "analysis.extrapolate" in done.stderr
    assert "Traceback" not in done.stderr and not (tmp_path / "s.sqlite").exists()


@pytest.mark.ngspice
def test_members_that_cannot_be_combined_make_a_failed_row_not_a_crash(tmp_path, capsys) -> None:
    import sqlite3

    from lcchain.cli import main
    from lcchain.studies.store import Store

    path = tmp_path / "s.sqlite"
    argv = ["sweep", "--case", "two-mass", "--N", "20,30", "--dt", "0.05", "--extrapolate", "2", "--store", str(path),
            "--executor", "serial", "--json"]
    assert main(argv) == 0 and json.loads(capsys.readouterr().out)["combined"] == 2
    with Store(path) as store:
        runs = store.runs()
    with sqlite3.connect(path) as db:  # the first point's arrays stripped, its combination dropped
        db.execute("UPDATE records SET arrays = NULL WHERE key = ?", (runs[1].key,))
        db.execute("DELETE FROM records WHERE key = ?", (runs[2].key,))
    for _ in range(2):  # a failed combination is made again on the next run, and fails again: no crash
        assert main(argv) == 1  # a study with a failed combination is not a success
        again = json.loads(capsys.readouterr().out)
        assert (again["ran"], again["ok"], again["combined"], again["combined_failed"]) == (0, 4, 1, 1)
    with Store(path) as store:
        rows = store.runs()
    assert rows[2].status == "failed" and "could not be combined" in rows[2].reason and runs[1].key[:12] in rows[2].reason
    assert rows[5].status == "ok" and rows[5].digest == runs[5].digest
    assert main(["results", str(path), "--csv"]) == 0
    table = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert (table[2]["index"], table[2]["kind"], table[2]["status"]) == ("2", "combined", "failed")
    assert "could not be combined" in table[2]["reason"]  # why, beside the row (the table every export writes)
    with sqlite3.connect(path) as db:  # the same command, planned otherwise (as another lcchain would)
        db.execute("UPDATE meta SET value = 'another' WHERE name = 'plan'")
    assert main(argv) == 2
    assert "holds this very study as another lcchain or engine planned it" in capsys.readouterr().err


@pytest.mark.ngspice
def test_netlist_out_keeps_every_run_of_an_extrapolation(tmp_path, capsys) -> None:
    """Issue 22: --netlist-out under extrapolation kept the coarsest run's netlist only, silently."""
    from lcchain.cli.main import main

    target = tmp_path / "x.cir"
    (tmp_path / "x-run3.cir").write_text("* the user's own file\n")
    assert main(["simulate", "--case", "two-mass", "--N", "20", "--dt", "0.1", "--extrapolate", "3",
                 "--netlist-out", str(target)]) == 0
    err = capsys.readouterr().err
    steps = []
    for path in (target, tmp_path / "x-run2.cir"):
        tran = next(line for line in path.read_text().splitlines() if line.startswith(".tran"))
        steps.append(float(tran.split()[4]))  # TMAX, the step lcchain sets
    assert steps[1] == pytest.approx(steps[0] / 2, rel=RTOL_HALVED_STEP)
    assert (tmp_path / "x-run3.cir").read_text() == "* the user's own file\n"  # never replaced
    assert "x-run3.cir exists" in err and "x-run2.cir" in err
