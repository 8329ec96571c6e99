"""A Monte Carlo sample's realised part values are stored: ``results --json``'s ``parts``, and ``to_xarray``'s
``L`` and ``C`` (issue 33)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers.tolerances import RTOL_ARITHMETIC

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
