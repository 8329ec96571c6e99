"""``lcchain results`` on a store of AC runs, and ``lcchain sweep --analysis ac`` (issue 21, section 1).

Stored spectra are checked against an independent dense eigen-solution (tests/helpers/dense.py).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers.dense import dense_modes
from helpers.tolerances import ATOL_SPECTRUM_P, RTOL_SPECTRUM_OMEGA

from lcchain.circuit.effects import Tolerance
from lcchain.cli.main import main
from lcchain.compare.spectral import OMEGA_WEIGHT_FLOOR, SpectrumMetrics
from lcchain.runs.request import AC, Request
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import request_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store
from lcchain.theory.cases import chain_for_case


@pytest.fixture(scope="module")
def ac_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("ac") / "ac.sqlite"
    plan = request_plan([({"N": N}, Request(chain_for_case("perfect", N), AC(),
                                            effects=(Tolerance(L=0.01, C=0.01, samples=3, seed=1),)))
                         for N in (10, 14)])
    run_plan(plan, path, RunOptions(executor="serial"))
    return path


@pytest.mark.ngspice
def test_results_of_an_ac_store_show_the_spectral_metrics(ac_store: Path, capsys):
    assert main(["results", str(ac_store)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].endswith("6 runs: 6 ok")
    assert lines[1].split()[:9] == ["#", "status", "N", "sample", "points", "modes", "seen", "omega", "error"]
    first = lines[2].split()
    assert first[:4] == ["0", "ok", "10", "1"] and int(first[5]) == 10 and float(first[6]) < RTOL_SPECTRUM_OMEGA
    assert "spacing: (max - min) / mean of delta omega_n" in lines[-1]


@pytest.mark.ngspice
def test_the_summary_groups_a_spectral_metric_and_refuses_a_transients(ac_store: Path, capsys):
    assert main(["results", str(ac_store), "--summary", "--metric", "spacing", "--csv"]) == 0
    rows = capsys.readouterr().out.splitlines()
    assert rows[0] == "N,n,failed,mean,std,min,p05,median,max" and [r.split(",")[:2] for r in rows[1:]] == [
        ["10", "3"], ["14", "3"]]
    assert all(float(r.split(",")[3]) > 1e-4 for r in rows[1:])  # 1 % parts spread the equal spacing
    assert main(["results", str(ac_store), "--summary", "--metric", "peak"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--metric" in err and "omega | P | spacing" in err


@pytest.mark.ngspice
def test_an_ac_store_goes_to_netcdf_with_its_phasors(ac_store: Path, tmp_path: Path, capsys):
    xarray = pytest.importorskip("xarray")
    out = tmp_path / "ac.nc"
    assert main(["results", str(ac_store), "--netcdf", str(out), "--waveforms"]) == 0
    with xarray.open_dataset(out) as data, xarray.open_dataset(out, group="ac") as ac:
        # issue 33: each tolerance sample's realised parts, L_i on coil and C_j on capacitor, in henry and farad
        assert set(data.sizes) == {"N", "sample", "coil", "capacitor"}
        assert data["L"].attrs["units"] == "H" and data["C"].attrs["units"] == "F"
        names = {str(name) for name in data.data_vars}
        assert {"max_rel_error_omega", "spacing_spread"} <= names
        # issue 33: each phasor's parts as two variables, in amperes per volt, on the runs' own frequencies (Hz)
        assert ac["frequency"].attrs["units"] == "Hz" and ac.sizes["run"] == 6
        for part in ("real", "imag"):
            assert ac[f"i_l1_{part}"].attrs["units"] == "A" and np.isfinite(ac[f"i_l1_{part}"].values).all()
        assert not np.all(ac["i_l1_imag"].values == 0)


@pytest.mark.ngspice
def test_a_sweep_of_ac_analyses_stores_each_chains_spectrum(tmp_path: Path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["sweep", "--case", "perfect,two-mass", "--N", "8,12", "--analysis", "ac", "--store", "s.sqlite",
                 "--executor", "serial"]) == 0
    with Store(tmp_path / "s.sqlite", "read") as store:
        runs = store.runs()
    assert [(run.params["case"], run.params["N"]) for run in runs] == [
        ("perfect", 8), ("perfect", 12), ("two-mass", 8), ("two-mass", 12)]
    for run in runs:
        assert run.status == "ok" and run.metrics is not None
        metrics = SpectrumMetrics.from_dict(run.metrics)
        omega, P = dense_modes(chain_for_case(run.params["case"], run.params["N"]))
        strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
        error = np.abs(metrics.omega[strong] - omega[strong]) / np.where(omega[strong] > 0, omega[strong], 1.0)
        assert np.max(error) < RTOL_SPECTRUM_OMEGA and np.max(np.abs(metrics.P - P)) < ATOL_SPECTRUM_P


@pytest.mark.parametrize(("argv", "said"), [
    (["--analysis", "ac", "--dt", "0.1"], "--dt"),
    (["--analysis", "ac", "--transits", "2"], "--transits"),
    (["--analysis", "ac", "--points", "20", "--N", "24"], "at least"),
    (["--points", "200"], "--analysis ac"),
])
def test_bad_ac_sweeps_exit_2_with_one_line(tmp_path: Path, monkeypatch, capsys, argv, said):
    monkeypatch.chdir(tmp_path)
    sizes = [] if "--N" in argv else ["--N", "10"]
    assert main(["sweep", "--case", "perfect", *sizes, *argv, "--store", "s.sqlite"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and said in err
    assert not (tmp_path / "s.sqlite").exists()


@pytest.mark.ngspice
def test_the_samples_spacing_spread_is_drawn_by_group(ac_store: Path, tmp_path: Path, capsys):
    figure = tmp_path / "spacing.png"
    assert main(["results", str(ac_store), "--plot", str(figure), "--metric", "spacing"]) == 0
    assert figure.stat().st_size > 0
