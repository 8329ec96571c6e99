"""``lcchain results`` on a store of AC runs (issue 21, section 1): spectral metrics, their summary, netCDF."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.tolerances import RTOL_SPECTRUM_OMEGA

from lcchain.circuit.effects import Tolerance
from lcchain.cli.main import main
from lcchain.runs.request import AC, Request
from lcchain.studies.plan import request_plan
from lcchain.studies.run import run_plan
from lcchain.theory.cases import chain_for_case


@pytest.fixture(scope="module")
def ac_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("ac") / "ac.sqlite"
    plan = request_plan([({"N": N}, Request(chain_for_case("perfect", N), AC(),
                                            effects=(Tolerance(L=0.01, C=0.01, samples=3, seed=1),)))
                         for N in (10, 14)])
    run_plan(plan, path, executor="serial")
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
    with xarray.open_dataset(out) as data:
        assert set(data.sizes) == {"N", "sample", "point"} and "frequency" in data.coords
        names = {str(name) for name in data.data_vars}
        assert {"max_rel_error_omega", "spacing_spread"} <= names
        assert any(name.endswith(".real") for name in names) and any(name.endswith(".imag") for name in names)
