"""Prices that hold on every surface (issue 29, section 2): an AC run priced from what its fit holds, a study's
pool workers and planning, and ``lcchain results`` exports, each refused past ``--max-memory`` or ``--max-time``
in one line naming the option, the price and the limit, before any work.

The prices are checked for their structure (what they grow with, what they count); their ratios to what was
measured are in ``benchmarks/pricing.md``, not in an assert a loaded machine could break.
"""

from __future__ import annotations

import pytest

from lcchain.cli.main import main
from lcchain.compare.sections import ONE_WINDOW, WINDOW_SECTIONS
from lcchain.compare.spectral import spectrum_estimate
from lcchain.compare.spectrum import fit_sections
from lcchain.core.budget import (
    DEFAULT_MAX_MEMORY,
    INTERPRETER_BYTES,
    POOL_WORKER_BYTES,
    export_estimate,
)
from lcchain.studies.plan import SweepAxes, sweep_plan
from lcchain.studies.store import Store

#: A worst case of a small ladder at a fixed step: 2^2 + 3 corners that run in well under a second each.
SCENE = """[chain]
case = "two-mass"
N = 12
[effects.tolerance]
L = 0.05
C = 0.02
samples = 1
seed = 3
[analysis]
dt = 0.05
"""


def _refused(capsys: pytest.CaptureFixture[str], argv: list[str], *said: str) -> str:
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    for words in said:
        assert words in err, (words, err)
    return err


def test_the_fit_prices_its_window_of_sections() -> None:
    """Up to 128 modes the fit moves every section at once, its N modes and the spurious poles of a sweep much
    finer than the poles; beyond, a window and its halo."""
    assert fit_sections(350, 20) == 20  # the default sweep of N = 20, fitted whole
    assert 20 < fit_sections(100_000, 20) <= ONE_WINDOW
    assert fit_sections(10**6, 20) == ONE_WINDOW
    assert fit_sections(26_094, 2000) == fit_sections(10**6, 2000) == WINDOW_SECTIONS < ONE_WINDOW


def test_an_ac_price_grows_with_frequencies_times_sections() -> None:
    """Memory grows with the frequencies, faster than them while the window widens; time in proportion to them
    (the fit from theory's poles is O(frequencies x N)); both with losses."""
    prices = [spectrum_estimate(points, 20) for points in (5_000, 50_000, 500_000)]
    assert prices[0].memory < prices[1].memory < prices[2].memory
    assert prices[2].memory / prices[1].memory > 10 and prices[2].seconds / prices[1].seconds > 9
    lossless, lossy = spectrum_estimate(50_000, 100), spectrum_estimate(50_000, 100, losses=True)
    assert lossy.memory > lossless.memory and lossy.seconds > lossless.seconds
    assert spectrum_estimate(10**6, 20).total_memory > DEFAULT_MAX_MEMORY  # issue 29: priced 283 MiB, ran past 5 GiB


def test_a_spectrum_past_its_memory_is_refused_before_ngspice_starts(capsys) -> None:
    _refused(capsys, ["spectrum", "--case", "two-mass", "--N", "20", "--points", "1000000"],
             "--points = 1000000", "--max-memory", "GiB")
    _refused(capsys, ["spectrum", "--case", "two-mass", "--N", "20", "--points", "50000", "--max-memory", "300M"],
             "--points = 50000", "--max-memory", "300 MiB")


def test_a_study_prices_its_pool_workers() -> None:
    """Each pool worker is an interpreter of its own holding a run; the driver alone runs one worker's runs."""
    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[10, 12, 14, 16], dts=[0.05]))
    one, two, four = (plan.price(workers, "process") for workers in (1, 2, 4))
    assert two.memory - one.memory >= 2 * POOL_WORKER_BYTES and four.memory > two.memory
    assert plan.price(4, "serial").memory == one.memory  # serial: no worker whatever --workers says
    assert plan.price(2, "dask").memory > two.memory and plan.price(2, "dask").seconds > two.seconds
    assert plan.price(8, "process").memory == four.memory  # four runs keep at most four workers busy
    assert one.seconds > sum(task.seconds for task in plan.tasks) - 1e-12  # its runs, and their planning


def test_a_study_past_max_memory_is_refused_naming_its_workers(capsys, tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    argv = ["sweep", "--case", "two-mass", "--N", "10,12", "--dt", "0.05", "--store", "s.sqlite"]
    _refused(capsys, [*argv, "--workers", "2", "--max-memory", "250M"], "--N = '2 runs'", "2 runs on 2 workers",
             "--max-memory")
    assert not (tmp_path / "s.sqlite").exists()


def test_a_check_whose_planning_is_past_max_time_is_refused_before_it_plans(capsys) -> None:
    """40 requests of N = 200, each planning its steps for an accuracy: tens of seconds before any run."""
    _refused(capsys, ["sensitivity", "--case", "two-mass", "--N", "200", "--check", "20", "--max-time", "10"],
             "--check = 20", "choosing the steps of 40 runs", "--max-time")


def test_a_worst_case_prices_the_planning_of_its_corners(capsys, tmp_path) -> None:
    scene = tmp_path / "w.toml"
    scene.write_text(SCENE.replace("dt = 0.05", "accuracy = 1e-4").replace("N = 12", "N = 30"))
    _refused(capsys, ["sweep", str(scene), "--worst-case", "--components", "8", "--max-time", "30",
                      "--store", str(tmp_path / "w.sqlite")], "--components = 8", "259 corners", "--max-time")
    assert not (tmp_path / "w.sqlite").exists()


def test_an_export_price_grows_with_its_grid_and_waveforms() -> None:
    base = export_estimate(runs=259, cells=259, metrics=1e5, files=True)
    waves = export_estimate(runs=259, cells=259, metrics=1e5, stored=7e6, dense=259 * 1058 * 24.0, files=True)
    grid = export_estimate(runs=259, cells=259**2, metrics=1e5, stored=7e6, dense=259**2 * 1058 * 24.0, files=True)
    assert base.memory < waves.memory < grid.memory and base.seconds < waves.seconds < grid.seconds
    assert grid.total_memory > 2 * 259**2 * 1058 * 24.0 + INTERPRETER_BYTES  # the variables and the writer's copy


@pytest.mark.ngspice
def test_results_exports_are_priced_and_a_worst_case_is_one_grid_of_corners(capsys, tmp_path) -> None:
    scene, store = tmp_path / "w.toml", tmp_path / "w.sqlite"
    scene.write_text(SCENE)
    assert main(["sweep", str(scene), "--worst-case", "corners", "--components", "2", "--store", str(store),
                 "--executor", "serial"]) == 0
    capsys.readouterr()
    with Store(store, "read") as stored:
        size = stored.export_size(waveforms=True)
    assert size.runs == size.cells == 1 + 4 + 2  # one point per corner: its signs go along, not across
    assert size.longest > 0 and size.per_point == 3 * 8  # time and the two end currents
    target = tmp_path / "w.nc"
    _refused(capsys, ["results", str(store), "--netcdf", str(target), "--waveforms", "--max-memory", "100M"],
             f"--netcdf = '{target}'", "7 runs and their waveforms on a grid of 7 points", "--max-memory")
    assert not target.exists()
    # the table alone is priced within the smallest budget lcchain takes (the interpreter's own 96 MiB and a little)
    assert main(["results", str(store), "--json", "--max-memory", "97M"]) == 0
    capsys.readouterr()
    xarray = pytest.importorskip("xarray")
    assert main(["results", str(store), "--netcdf", str(target), "--waveforms"]) == 0
    with xarray.open_dataset(target) as dataset, xarray.open_dataset(target, group="transient") as waves:
        assert dict(dataset.sizes) == {"corner": 7}
        assert dataset["signs"].dims == ("corner",) and "signs" in dataset.coords
        assert waves.sizes["run"] == 7 and waves.sizes["obs"] <= 7 * size.longest


def test_results_takes_the_budget_options(capsys) -> None:
    """``results`` has --max-memory and --max-time like every command that does real work."""
    assert main(["results", "--help"]) == 0
    out = capsys.readouterr().out
    assert "--max-memory" in out and "--max-time" in out


def test_a_scene_on_workers_prices_them(capsys, tmp_path) -> None:
    """``lcchain run SCENE --workers 2``: each worker an interpreter of its own holding a sample's run."""
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE.replace("samples = 1", "samples = 8"))
    _refused(capsys, ["run", str(scene), "--workers", "2", "--max-memory", "250M"], "--workers = 2",
             "8 runs on 2 workers", "--max-memory")
