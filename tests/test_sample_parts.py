"""A Monte Carlo sample's realised part values are stored: ``results --json``'s ``parts``, and ``to_xarray``'s
``L`` and ``C`` (issue 33)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers.tolerances import RTOL_ARITHMETIC, RTOL_E24_MANTISSA, RTOL_TOLERANCE_BOUND

from lcchain.circuit.ladder import Ladder
from lcchain.cli import main
from lcchain.scenes.load import load_scene
from lcchain.scenes.plan import scene_plan
from lcchain.studies.store import Store

SCENE = ('[chain]\ncase = "two-mass"\nN = 8\n[units]\nL0 = 10e-6\nC0 = 10e-9\n[effects.tolerance]\nL = 0.05\n'
         'C = 0.05\nsamples = 3\nseed = 11\n[analysis]\nkind = "ac"\n[output]\nplots = []\n')


def test_each_samples_parts_are_stored(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "mc.toml"
    scene.write_text(SCENE)
    store = tmp_path / "mc.sqlite"
    assert main(["sweep", str(scene), "--samples", "3", "--seed", "11", "--store", str(store),
                 "--executor", "serial", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["ok"] == 3
    # the realised chains again, from the same seed, by the planner
    plan = scene_plan(load_scene(scene))
    ladders = [Ladder(chain, 10e-6, 10e-9) for chain in plan.chains]
    assert len(ladders) == 3
    assert main(["results", str(store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    runs = runs["runs"] if isinstance(runs, dict) else runs
    assert [run["params"]["sample"] for run in runs] == [1, 2, 3]
    for run, ladder in zip(runs, ladders, strict=True):
        np.testing.assert_allclose(run["parts"]["L"], ladder.inductances(), rtol=RTOL_ARITHMETIC)
        C = ladder.capacitances()
        assert run["parts"]["C"][0] is None and run["parts"]["C"][-1] is None  # free ends: wires
        np.testing.assert_allclose(run["parts"]["C"][1:-1], C[1:-1], rtol=RTOL_ARITHMETIC)
    assert runs[0]["parts"]["L"] != runs[1]["parts"]["L"]  # 5 %: every sample its own parts
    with Store(store, "read") as results:
        dataset = results.to_xarray()
        table = results.to_dataframe()
    assert dataset["L"].dims == ("sample", "coil") and dataset["L"].attrs["units"] == "H"
    assert dataset["C"].dims == ("sample", "capacitor") and dataset.sizes["capacitor"] == 9
    for k, ladder in enumerate(ladders):
        np.testing.assert_allclose(dataset["L"].values[k], ladder.inductances(), rtol=RTOL_ARITHMETIC)
        np.testing.assert_allclose(dataset["C"].values[k, 1:-1], ladder.capacitances()[1:-1], rtol=RTOL_ARITHMETIC)
        assert np.isnan(dataset["C"].values[k, [0, -1]]).all()
    assert "parts" not in table.columns and "L" not in table.columns  # the table stays one row of metrics per run


E24 = (1.0, 1.1, 1.2, 1.3, 1.5, 1.6, 1.8, 2.0, 2.2, 2.4, 2.7, 3.0, 3.3, 3.6, 3.9, 4.3, 4.7, 5.1, 5.6, 6.2, 6.8, 7.5,
       8.2, 9.1)  # IEC 60063, written out here


def _on_e24(value: float) -> bool:
    mantissa = value / 10.0 ** np.floor(np.log10(value))
    return bool(np.isclose(mantissa, E24, rtol=RTOL_E24_MANTISSA).any() or np.isclose(mantissa, 10.0, rtol=RTOL_E24_MANTISSA))


def test_a_monte_carlo_from_the_command_line_needs_no_scene(tmp_path: Path,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    """``sweep --case perfect --N 8 --tolerance 1% --series E24 --samples 3``: the scene comes from the options;
    the samples' parts are drawn around E24 values and stored."""
    store = tmp_path / "mc.sqlite"
    assert main(["sweep", "--case", "perfect", "--N", "8", "--tolerance", "1%", "--series", "E24", "--samples", "3",
                 "--seed", "5", "--dt", "0.1", "--store", str(store), "--executor", "serial", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["ok"] == 3
    assert main(["results", str(store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    runs = runs["runs"] if isinstance(runs, dict) else runs
    assert [run["params"]["sample"] for run in runs] == [1, 2, 3]
    for run in runs:
        L = np.array(run["parts"]["L"])
        assert L.size == 8  # N = 8: one axis value, in the study's description, not a parameter of each run
        # each part is an E24 value moved by at most its 1 % tolerance
        tolerance = 0.01
        nominal = [min((d * 10.0 ** e for d in E24 for e in range(-9, -3)), key=lambda v, x=x: abs(v - x))
                   for x in L]
        assert np.all(np.abs(L / np.array(nominal) - 1) <= tolerance + RTOL_TOLERANCE_BOUND)
        assert not all(_on_e24(x) for x in L)  # the tolerance moved them off the series
    assert runs[0]["parts"]["L"] != runs[1]["parts"]["L"]


@pytest.mark.parametrize(("given", "message"), [
    (["--tolerance", "150%"], "--tolerance L"),
    (["--tolerance", "1%", "--analysis", "ac"], "--analysis"),
    (["--vary", "chain.N=8,9"], "--vary"),
])
def test_a_command_line_monte_carlo_names_a_bad_option(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                       given: list[str], message: str) -> None:
    code = main(["sweep", "--case", "perfect", "--N", "8", *given, "--store", str(tmp_path / "s.sqlite")])
    err = capsys.readouterr().err
    assert code == 2 and message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("argv", [["run", "{scene}", "--samples", "3"],
                                  ["sweep", "--case", "two-mass", "--N", "10", "--samples", "5", "--store", "{store}"]])
def test_samples_with_no_tolerance_to_draw_from_are_refused(argv: list[str], tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    """Every sample would be the nominal circuit: run printed a spread of 0 over 3 identical runs, and the sweep
    ran one."""
    scene = tmp_path / "plain.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 10\n[output]\nplots = []\n')
    argv = [arg.replace("{scene}", str(scene)).replace("{store}", str(tmp_path / "s.sqlite")) for arg in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("lcchain: --samples = ") and "without a tolerance to draw from" in err
    assert not (tmp_path / "s.sqlite").exists()


def test_samples_of_a_sweep_through_a_tolerance_of_zero_are_planned(tmp_path: Path) -> None:
    """A sweep that varies the tolerance, 0 among its values, draws at its other points: its samples stand."""
    from lcchain.studies.plan import RealParts, scene_sweep_plan

    scene = tmp_path / "plain.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 8\n[output]\nplots = []\n')
    plan = scene_sweep_plan(scene, [("effects.tolerance.L+effects.tolerance.C", [0.0, 0.05])], RealParts(samples=2))
    assert len(plan.tasks) == 4


def test_a_scenes_counts_stay_integers_in_its_dataset() -> None:
    # points and modes seen are counts: integers when every sample gives one, floats (NaN) where a failed one lacks
    pytest.importorskip("xarray")
    from lcchain.runs.datasets import samples_dataset

    ok = {"sample": 1, "status": "ok", "points": 40, "modes_seen": 8, "max_rel_error_omega": 1e-9, "wall_s": 0.1}
    parts = [{"L": [1e-5], "C": [None]}] * 2
    dataset = samples_dataset("counts", [ok, dict(ok, sample=2, modes_seen=7)], parts)
    assert dataset["points"].dtype.kind == "i" and dataset["modes_seen"].values.tolist() == [8, 7]
    assert dataset["max_rel_error_omega"].dtype.kind == "f"
    failed = {"sample": 2, "status": "failed", "error": "ngspice stopped"}
    dataset = samples_dataset("counts", [ok, failed], parts)
    assert dataset["points"].dtype.kind == "f" and np.isnan(dataset["points"].values[1])
