"""What ``lcchain results`` prints after a study (issue 22): a table with a header, the study's axes only, and
for a batch of netlists each one's vectors, points and time; a metric the runs cannot give is refused."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest
from helpers.netlists import LADDER
from helpers.tolerances import MAX_PERFECT_RUN_LOSS

from lcchain.cli.main import main

pytestmark = pytest.mark.ngspice


@pytest.fixture(scope="module")
def batch_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("batch")
    paths = []
    for i, stop in enumerate((7.7, 7.8, 7.9)):
        path = folder / f"ladder{i}.cir"
        path.write_text(LADDER.replace(".tran 0.001 7.7", f".tran 0.001 {stop}"))
        paths.append(str(path))
    broken = folder / "broken.cir"
    broken.write_text(LADDER.replace("C23 n2 0 1.0\n", "C23 n2 0 1.0\nVa n2 0 1\nVb n2 0 2\n"))
    store = folder / "b.sqlite"
    assert main(["batch", *paths, str(broken), "--store", str(store), "--executor", "serial"]) == 1
    return store


def test_a_batch_store_shows_each_netlists_vectors_points_and_time(batch_store: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["results", str(batch_store)]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert lines[0].endswith("4 runs: 3 ok, 1 failed")
    assert lines[1].split() == ["#", "status", "netlist", "vectors", "points", "time", "(s)", "reason"]
    rows = [line.split() for line in lines[2:6]]
    for row, stop in zip(rows[:3], (7.7, 7.8, 7.9), strict=True):
        assert row[1] == "ok" and row[3:5] == ["i(l1)", "i(l3)"]
        assert int(row[5]) >= stop / 0.001  # at least one point per step
        assert 0 < float(row[6]) < 60
    assert rows[3][1] == "failed" and "singular" in lines[5].lower()
    assert "None" not in out and "-0.0" not in out and "{" not in out


def test_a_batch_store_has_no_summary_to_give(batch_store: Path, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    for extra in ([], ["--metric", "energy"]):
        assert main(["results", str(batch_store), "--summary", *extra]) == 2
        err = capsys.readouterr().err
        assert "--metric" in err and "no" in err and "batch of netlists" in err and "Traceback" not in err
    assert main(["results", str(batch_store), "--plot", str(batch_store.parent / "b.png")]) == 2
    assert not (batch_store.parent / "b.png").exists()


def test_a_sweep_table_shows_its_axes_and_a_plot_no_rows(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "s.sqlite"
    assert main(["sweep", "--case", "two-mass,perfect", "--N", "20,30", "--dt", "0.05", "--store", str(store),
                 "--executor", "serial", "--json"]) == 0
    capsys.readouterr()
    assert main(["results", str(store)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].split() == ["#", "status", "case", "N", "error", "predicted", "peak", "time", "(s)", "reason"]
    assert [line.split()[2:4] for line in lines[2:6]] == [["two-mass", "20"], ["two-mass", "30"], ["perfect", "20"],
                                                          ["perfect", "30"]]
    assert main(["results", str(store), "--plot", str(tmp_path / "s.png")]) == 0
    out = capsys.readouterr().out
    assert len(out.splitlines()) == 1 and "s.png" in out and (tmp_path / "s.png").stat().st_size > 10_000
    # the summary keeps 4 significant digits of a perfect cradle's tiny loss, and its CSV every digit
    assert main(["results", str(store), "--summary", "--metric", "loss", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)
    assert main(["results", str(store), "--summary", "--metric", "loss"]) == 0
    table = capsys.readouterr().out
    assert main(["results", str(store), "--summary", "--metric", "loss", "--csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert [float(row["mean"]) for row in rows] == [group["mean"] for group in groups]
    perfect = [group["mean"] for group in groups if group["params"]["case"] == "perfect"]
    assert perfect and all(0 < loss < MAX_PERFECT_RUN_LOSS for loss in perfect)
    assert all(f"{loss:.4g}" in table for loss in perfect) and "0.0000" not in table


def test_the_axes_are_what_every_point_varies_by() -> None:
    """A real-parts sweep whose N = 200 points were extrapolated: their dt and runs are no axes (the summary had
    blank dt and runs columns, the figure empty panels titled 'dt = None, runs = None')."""
    from lcchain.studies.stored import StoredRun, study_axes
    from lcchain.studies.summary import study_constants

    def run(index: int, **params: object) -> StoredRun:
        return StoredRun(index, f"k{index}", dict(params), "", "ok")

    runs = [run(0, case="perfect", N=50, sample=1, transits=1), run(1, case="perfect", N=50, sample=2, transits=1),
            run(2, case="perfect", N=200, sample=1, transits=1, dt=0.5, member=1),
            run(3, case="perfect", N=200, sample=1, transits=1, dt=0.25, member=2),
            run(4, case="perfect", N=200, sample=1, transits=1, dt=0.5, runs=2)]
    assert study_axes(runs) == ["N", "sample"]
    assert study_constants(runs) == {"case": "perfect", "transits": 1}


def test_every_export_writes_one_table(batch_store: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--csv and the data frame (Parquet, netCDF) are one table: the same columns, a failed run's reason in each,
    and no chain's metrics for netlists that have no chain (the CSV had fewer columns and called the reason
    'error'; the data frame had no reason, and all-NaN chain columns in units of I_1(0))."""
    pytest.importorskip("pandas")
    from lcchain.studies.store import Store

    capsys.readouterr()
    assert main(["results", str(batch_store), "--csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    with Store(batch_store) as store:
        frame = store.to_dataframe()
    assert list(rows[0]) == ["index", *frame.columns]
    assert not {"max_abs_error", "peak_sim", "t_theory"} & set(rows[0])
    broken = next(row for row in rows if row["netlist"].endswith("broken.cir"))
    assert broken["status"] == "failed" and "singular matrix" in broken["reason"]
    assert frame.loc[int(broken["index"]), "reason"] == broken["reason"]
    assert all(row["reason"] == "" for row in rows if row["status"] == "ok")


def test_a_netlist_sweeps_axes_claim_no_unit_they_may_not_have(tmp_path: Path) -> None:
    """Every axis was "1": a swept element's and a .param's unit is not known to the store (a .param named rload
    need not be ohms), so none is claimed, and the long name says so."""
    xarray = pytest.importorskip("xarray")
    netlist = tmp_path / "rc.cir"
    netlist.write_text("rc\n.param gain = 2k\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in out 1k\nC1 out 0 1u\n"
                       "R2 out 0 {gain}\n.tran 10u 1m\n.end\n")
    store, target = tmp_path / "s.sqlite", tmp_path / "s.nc"
    assert main(["sweep", "--netlist", str(netlist), "--vary", "R1=1k,2k", "--vary", "C1=1u,2u", "--vary",
                 "gain=1k,2k", "--store", str(store), "--executor", "serial"]) == 0
    assert main(["results", str(store), "--netcdf", str(target)]) == 0
    with xarray.open_dataset(target) as dataset:
        for axis in ("R1", "C1", "gain"):
            assert "units" not in dataset[axis].attrs and "not known" in dataset[axis].attrs["long_name"]
        assert "peak_sim" not in dataset


def test_a_scene_sweeps_axis_is_named_as_cf_names_things(tmp_path: Path) -> None:
    """units.L0 is no CF name (2.3: letters, digits, underscores): the file's axis is units_L0, in henries, its
    long_name the key as the scene writes it."""
    xarray = pytest.importorskip("xarray")
    scene = tmp_path / "s.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 10\n[analysis]\ndt = 0.05\n[output]\nplots = []\n')
    store, target = tmp_path / "s.sqlite", tmp_path / "s.nc"
    assert main(["sweep", str(scene), "--vary", "units.L0=1e-6,2e-6", "--store", str(store),
                 "--executor", "serial"]) == 0
    assert main(["results", str(store), "--netcdf", str(target)]) == 0
    with xarray.open_dataset(target) as dataset:
        assert list(dataset.dims) == ["units_L0"]
        assert dataset["units_L0"].attrs == {"long_name": "units.L0", "units": "H"}


def test_a_netlist_stores_summary_and_plot_say_what_to_ask(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The default --metric, on netlists without a theory, is said to be the default and the store's own .meas
    are offered; Store.plot() says the runs have no theory (it said no run had finished, naming --plot)."""
    from lcchain.core.errors import ParameterError
    from lcchain.studies.store import Store

    netlist = tmp_path / "rc.cir"
    netlist.write_text("rc\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in out 1k\nC1 out 0 1u\n.tran 10u 1m\n"
                       ".meas tran vmax max v(out)\n.end\n")
    store = tmp_path / "s.sqlite"
    assert main(["batch", str(netlist), "--store", str(store)]) == 0
    capsys.readouterr()
    assert main(["results", str(store), "--summary"]) == 2
    err = capsys.readouterr().err
    assert "--metric (default) = 'peak'" in err and "--metric vmax, a .meas of the netlists" in err
    with Store(store, "read") as opened, pytest.raises(ParameterError, match="its 1 finished runs have none"):
        opened.plot()
