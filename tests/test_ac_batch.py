"""``lcchain batch`` of foreign ``.ac`` netlists (issue 21, section 1): allowed, priced, run and stored complex.

The stored phasor I_1 is checked against a direct solve of the ladder's loop equations written out here,
(j omega L + S / (j omega C0)) I = V e_1, with S the stiffness matrix built from the chain's springs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers.netlists import LADDER

from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import ac_netlist_text
from lcchain.cli.main import main
from lcchain.studies.store import Store
from lcchain.theory.cases import chain_for_case

L0, C0 = 1e-5, 1e-8
#: A direct solve and ngspice's AC analysis agree to about 1e-12 relative away from the poles.
RTOL_DIRECT_SOLVE = 1e-8


def _netlist(folder: Path, N: int = 6) -> tuple[Path, np.ndarray, np.ndarray]:
    chain = chain_for_case("two-mass", N)
    path = folder / "n.cir"
    path.write_text(ac_netlist_text(Ladder(chain, L0, C0), points=200, omega_max=2.2, title="a foreign ladder"))
    K = chain.springs
    S = np.diag(K[:-1] + K[1:]) - np.diag(K[1:-1], 1) - np.diag(K[1:-1], -1)
    return path, chain.masses * L0, S


@pytest.mark.ngspice
def test_a_foreign_ac_netlist_runs_in_batch_and_its_phasors_are_stored(tmp_path: Path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    path, inductances, S = _netlist(tmp_path)
    assert main(["batch", str(path), "--store", "s.sqlite", "--executor", "serial"]) == 0
    assert main(["results", "s.sqlite"]) == 0
    out = capsys.readouterr().out
    assert "i(l1) i(l6)     200" in out and "an .ac netlist's frequencies" in out
    with Store(tmp_path / "s.sqlite", "read") as store:
        run = store.runs()[0]
        arrays = store.waveforms(run.key)
    assert run.status == "ok" and run.points == 200 and arrays is not None
    frequency, current = arrays["frequency"], arrays["i(l1)"]
    assert current.dtype == complex and frequency.size == 200
    direct = []
    for f in frequency:
        jw = 2j * np.pi * f
        Z = np.diag(jw * inductances) + S / (jw * C0)
        direct.append(np.linalg.solve(Z, np.eye(len(inductances))[0])[0])
    # ngspice's i(l1) flows from s1 into the ladder: V1's + terminal drives it, the same sign as the solve
    np.testing.assert_allclose(current, np.array(direct), rtol=RTOL_DIRECT_SOLVE)


@pytest.mark.parametrize(("card", "said"), [
    (".ac log 10 1 1e6", "lin|dec|oct"),
    (".ac dec 10 0 1e6", "0 < FSTART"),
    (".ac lin 0 1 1e6", "1 <= N"),
    (".ac lin 10 1e6 1", "FSTART < FSTOP"),
])
def test_an_ac_card_lcchain_cannot_count_is_refused_with_one_line(tmp_path: Path, monkeypatch, capsys, card, said):
    monkeypatch.chdir(tmp_path)
    path, _, _ = _netlist(tmp_path)
    text = path.read_text()
    path.write_text("\n".join(card if line.startswith(".ac ") else line for line in text.splitlines()) + "\n")
    assert main(["batch", str(path), "--store", "s.sqlite"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "line" in err and said in err
    assert not (tmp_path / "s.sqlite").exists()


def test_an_ac_netlist_is_not_run_with_allow_control(tmp_path: Path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    path, _, _ = _netlist(tmp_path)
    assert main(["batch", str(path), "--store", "s.sqlite", "--allow-control"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--allow-control" in err and "n.cir" in err


@pytest.mark.ngspice
def test_a_batch_of_tran_and_ac_netlists_reads_back_on_one_point_axis(tmp_path: Path, monkeypatch):
    """A store of a transient and an AC run: their arrays share the ``point`` dimension, and ``frequency`` and
    ``time`` are coordinates (a frequency dimension would claim the transient's points as frequencies)."""
    pytest.importorskip("xarray")
    monkeypatch.chdir(tmp_path)
    path, _, _ = _netlist(tmp_path)
    (tmp_path / "t.cir").write_text(LADDER)
    assert main(["batch", str(path), "t.cir", "--store", "s.sqlite", "--executor", "serial"]) == 0
    with Store(tmp_path / "s.sqlite", "read") as store:
        data = store.to_xarray(waveforms=True)
        runs = {run.params["netlist"]: run for run in store.runs()}
    assert "point" in data.dims and "frequency" not in data.dims and "frequency" in data.coords
    points = {run.points for run in runs.values()}
    assert data.sizes["point"] == max(points) and len(points) == 2


@pytest.mark.ngspice
def test_a_batch_of_tran_and_ac_netlists_goes_to_cf_netcdf_in_two_groups(tmp_path: Path, monkeypatch, capsys):
    """Issue 33: the transient and the AC run in groups of their own, a unit on every numeric variable and
    coordinate, the AC phasor's parts as two variables, the transient never in a ``*_real`` variable, the
    engine's name apart from its version, and no padding: the file is about the size of the points it holds."""
    xarray = pytest.importorskip("xarray")
    monkeypatch.chdir(tmp_path)
    path, _, _ = _netlist(tmp_path)
    (tmp_path / "t.cir").write_text(LADDER)
    assert main(["batch", str(path), "t.cir", "--store", "s.sqlite", "--executor", "serial"]) == 0
    assert main(["results", "s.sqlite", "--netcdf", "s.nc", "--waveforms"]) == 0
    capsys.readouterr()
    with Store(tmp_path / "s.sqlite", "read") as store:
        runs = {run.params["netlist"]: run for run in store.runs()}
        stored = {name: store.waveforms(run.key) for name, run in runs.items()}
    with xarray.open_dataset("s.nc") as root, xarray.open_dataset("s.nc", group="transient") as tran, \
            xarray.open_dataset("s.nc", group="ac") as ac:
        assert root.attrs["Conventions"] == "CF-1.10" and root.attrs["title"] and "lcchain" in root.attrs["history"]
        assert set(root["engine"].values) == {"ngspice"} and all(v for v in root["engine_version"].values)
        for dataset in (root, tran, ac):
            for name in dataset.variables:
                if dataset[name].dtype.kind in "fiu":
                    assert "units" in dataset[name].attrs, name
        assert tran["time"].attrs["units"] == "s" and ac["frequency"].attrs["units"] == "Hz"
        assert not any(str(name).endswith(("_real", "_imag", ".real")) for name in tran.variables)
        (transient,) = [arrays for arrays in stored.values() if "time" in arrays]
        (phasors,) = [arrays for arrays in stored.values() if "frequency" in arrays]
        for vector, values in transient.items():
            if vector != "time":
                saved = tran[vector.replace("(", "_").replace(")", "")]
                assert saved.attrs["units"] in ("A", "V") and np.array_equal(saved.values, values)
        for vector, values in phasors.items():
            if vector != "frequency":
                name = vector.replace("(", "_").replace(")", "")
                np.testing.assert_array_equal(ac[f"{name}_real"].values, values.real)
                np.testing.assert_array_equal(ac[f"{name}_imag"].values, values.imag)
                # a foreign netlist's phasors are for its sources' own AC magnitudes, not per volt
                assert "per volt" not in ac[f"{name}_real"].attrs["long_name"]
                assert "AC magnitudes of the circuit's sources" in ac[f"{name}_real"].attrs["long_name"]
    held = sum(values.nbytes for arrays in stored.values() for values in arrays.values())
    assert (tmp_path / "s.nc").stat().st_size < held + 64 * 1024  # the points, once, and headers
