"""AC scenes (issue 21, section 1): ``[analysis] kind = "ac"``, its refusals, its report and its plots.

Each sample's spectrum is checked against an independent dense eigen-solution of that sample's chain
(tests/helpers/dense.py).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers.dense import dense_modes
from helpers.tolerances import ATOL_SPECTRUM_P, RTOL_SPECTRUM_OMEGA, RTOL_SPECTRUM_Q

from lcchain.cli.main import main
from lcchain.compare.spectral import OMEGA_WEIGHT_FLOOR
from lcchain.core.errors import ParameterError
from lcchain.scenes.load import parse_scene
from lcchain.scenes.run import simulate_scene

AC_SCENE = {"title": "AC", "chain": {"case": "perfect", "N": 12}, "analysis": {"kind": "ac"}}


def _with(**tables):
    data = json.loads(json.dumps(AC_SCENE))
    for name, table in tables.items():
        data.setdefault(name, {}).update(table)
    return data


@pytest.mark.parametrize(("tables", "field"), [
    ({"analysis": {"dt": 0.05}}, "analysis.dt"),
    ({"analysis": {"transits": 1}}, "analysis.transits"),  # refused even at a transient's default
    ({"analysis": {"method": "trap"}}, "analysis.method"),
    ({"analysis": {"accuracy": 1e-3}}, "analysis.accuracy"),
    ({"analysis": {"extrapolate": 1}}, "analysis.extrapolate"),
    ({"analysis": {"points": 3}}, "analysis.points"),
    ({"analysis": {"kind": "dc"}}, "analysis.kind"),
    ({"analysis": {"kind": "transient", "points": 100}}, "analysis.points"),
    ({"output": {"plots": ["overlay"]}}, "output.plots"),
    ({"output": {"plots": ["spacing"]}}, "output.plots"),  # a spread needs samples
    ({"output": {"probes": "all"}}, "output.probes"),
    ({"excitation": {"kind": "pulse", "shape": "gaussian", "width": 0.2}}, "excitation"),
])
def test_a_transients_keys_and_plots_are_refused_with_an_ac_analysis(tables, field):
    with pytest.raises(ParameterError) as caught:
        parse_scene(_with(**tables))
    assert caught.value.field == field


def test_an_ac_scene_draws_its_spectrum_by_default_and_round_trips():
    scene = parse_scene(AC_SCENE)
    assert scene.analysis.kind == "ac" and scene.output.plots == ("spectrum",)
    data = scene.to_dict()
    assert not {"transits", "accuracy", "dt", "method", "extrapolate"} & set(data["analysis"])
    assert parse_scene(data) == scene
    transient = parse_scene({"chain": {"case": "perfect", "N": 12}}).to_dict()
    assert "kind" not in transient["analysis"]  # a transient's table is what it was before AC scenes


@pytest.mark.ngspice
def test_each_sample_of_an_ac_tolerance_scene_against_its_own_chain():
    scene = parse_scene(_with(effects={"tolerance": {"L": 0.02, "C": 0.02, "samples": 3, "seed": 2}},
                              output={"plots": ["spectrum", "spacing"]}))
    result = simulate_scene(scene)
    assert result.ok and len(result.samples) == 3
    for sample in result.samples:
        spectrum = sample.run.spectrum
        assert spectrum is not None
        omega, P = dense_modes(sample.chain)
        strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
        assert np.max(np.abs(spectrum.omega[strong] - omega[strong]) / np.where(omega[strong] > 0, omega[strong], 1.0)) \
            < RTOL_SPECTRUM_OMEGA
        assert np.max(np.abs(spectrum.P - P)) < ATOL_SPECTRUM_P
    report = result.report
    assert report["spacing_spread"]["count"] == 3
    assert report["spacing_spread"]["min"] > 100 * report["spacing_spread"]["theory_nominal"]


@pytest.mark.ngspice
def test_an_ac_scene_from_the_cli_writes_its_plots_and_report(tmp_path: Path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "ac.toml"
    scene.write_text('# AC\n[chain]\ncase = "two-mass"\nN = 10\n[effects.tolerance]\nL = 0.01\nC = 0.01\n'
                     'samples = 2\n[analysis]\nkind = "ac"\n[output]\nreport = "out/ac.json"\n'
                     'plots = ["spectrum", "spacing"]\n')
    assert main(["run", str(scene), "--waveform-out", "spectrum.csv"]) == 0
    out = capsys.readouterr().out
    assert "AC sweep of" in out and "spacing spread" in out
    report = json.loads((tmp_path / "out" / "ac.json").read_text())
    assert report["max_rel_error_omega"] < RTOL_SPECTRUM_OMEGA
    assert (tmp_path / "out" / "ac-spectrum.png").stat().st_size > 0
    assert (tmp_path / "out" / "ac-spacing.png").stat().st_size > 0
    header = (tmp_path / "spectrum.csv").read_text().splitlines()[0]
    assert header.startswith("frequency_hz,re(i(l1)),im(i(l1))")


@pytest.mark.ngspice
def test_an_ac_scene_lossy_through_its_parts_alone_prints_its_summary(tmp_path: Path, monkeypatch, capsys):
    """A capacitor's ESR makes the circuit lossy with no Q of the chain's: the summary read report['Q'] (KeyError)."""
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "esr.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 6\n[effects.capacitor_esr]\nR = 0.01\n[analysis]\n'
                     'kind = "ac"\n[output]\nplots = []\n')
    assert main(["run", str(scene)]) == 0
    assert "the circuit's losses: max |Q_n - theory| / theory" in capsys.readouterr().out


def test_a_bad_ac_scene_exits_2_with_one_line(tmp_path: Path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "bad.toml"
    scene.write_text('# bad\n[chain]\ncase = "perfect"\nN = 24\n[analysis]\nkind = "ac"\npoints = 20\n')
    assert main(["run", str(scene)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "analysis.points" in err and "at least" in err


@pytest.mark.ngspice
def test_a_lossy_ac_scene_reports_each_samples_quality_factors():
    """[effects.losses] in an AC scene: every sample's Q_n against omega_n Q, the worst in the summary."""
    scene = parse_scene(_with(effects={"losses": {"Q": 100.0}, "tolerance": {"L": 0.01, "C": 0.01, "samples": 3,
                                                                              "seed": 2}}))
    result = simulate_scene(scene)
    report = result.report
    assert report["Q"] == 100.0 and len(report["samples"]) == 3
    assert report["max_rel_error_Q"] == max(record["max_rel_error_Q"] for record in report["samples"])
    assert 0.0 < report["max_rel_error_Q"] < RTOL_SPECTRUM_Q
    for sample in result.samples:  # each against an independent dense solution of its own chain
        omega, _ = dense_modes(sample.chain)
        metrics = sample.run.spectrum
        assert metrics is not None and metrics.losses == 100.0
        strong = np.isfinite(metrics.omega) & (omega > 0)
        np.testing.assert_allclose(metrics.Q[strong], omega[strong] * 100.0, rtol=RTOL_SPECTRUM_Q)
