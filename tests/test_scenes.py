"""Scenes in real ngspice: every effect against its exact theory, and nothing it did not ask for.

The reference of every scene is the exact linear response of the same
circuit (:func:`lcchain.theory.response.linear_response`); with ``accuracy = eps``
the step is chosen so that the error is below eps, and these tests hold it to
that.  The netlist tests read the text ngspice is given: an ideal scene is a
pure L-C ladder saving two currents, and each effect adds only its own lines.
"""

from __future__ import annotations

import copy
import csv
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from helpers.processes import temporary_entries
from helpers.tolerances import (
    ACCURACY_COARSE,
    ACCURACY_FINE,
    ATOL_CSV_PEAK,
    ATOL_PULSE_DELAY,
    ATOL_SPECTRUM_P,
    MIN_ERROR_WRONG_THEORY,
    RTOL_CSV_TIME,
    RTOL_MEAN_OF_SAMPLES,
    RTOL_NETLIST_VALUE,
    RTOL_ONE_OPERATION,
    RTOL_SPECTRUM_OMEGA,
    RTOL_STD_OF_SAMPLES,
)

from lcchain.app.scenes import SceneRun, run_scene
from lcchain.circuit.effects import E_SERIES
from lcchain.cli import main
from lcchain.core.errors import ParameterError
from lcchain.report.scenes import write_scene_outputs
from lcchain.runs.execute import execute
from lcchain.scenes.load import parse_scene
from lcchain.scenes.plan import scene_plan, scene_specs
from lcchain.scenes.run import scene_result
from lcchain.theory.arrivals import arrival_window

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
EXAMPLES = sorted(SCENES.glob("*.toml"))

N = 16
BASE = {
    "title": "test scene",
    "chain": {"case": "two-mass", "N": N},
    "excitation": {"kind": "kick", "I0": 1e-3},
    "analysis": {"transits": 1, "accuracy": ACCURACY_COARSE},
    "output": {"probes": "ends", "plots": []},
}
#: Each effect alone, as the scene file's tables.
EFFECTS = {
    "ideal": {},
    "displacement": {"excitation": {"kind": "displacement"}},
    "losses": {"effects": {"losses": {"Q": 50}}},
    "walls": {"effects": {"walls": {"K0": 0.05}}},
    "gaussian": {"excitation": {"kind": "pulse", "shape": "gaussian", "width": 0.3}},
    "rect": {"excitation": {"kind": "pulse", "shape": "rect", "width": 0.5}},
    "E24": {"effects": {"preferred_values": {"series": "E24"}}},
    "tolerance": {"effects": {"tolerance": {"L": 0.05, "C": 0.05, "samples": 3, "seed": 3}}},
    "all-probes": {"output": {"probes": "all"}},
    "uniform-bounded": {"chain": {"case": "uniform-bounded"}},
    "custom": {"chain": {"case": "custom", "N": 5, "masses": [2.0, 1.0, 1.5, 1.0, 3.0],
                         "springs": [0.0, 1.0, 0.7, 1.2, 1.0, 0.5]}},
}
#: Every effect at once.
COMBINED = {
    "excitation": {"kind": "pulse", "shape": "gaussian", "width": 0.3},
    "effects": {"losses": {"Q": 50}, "walls": {"K0": 0.05}, "preferred_values": {"series": "E24"},
                "tolerance": {"L": 0.05, "C": 0.05, "samples": 3, "seed": 3}},
    "analysis": {"transits": 2},
}


def _merge(base: dict, extra: dict) -> dict:
    out = copy.deepcopy(base)
    for key, value in extra.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _scene(*extras: dict):
    data = BASE
    for extra in extras:
        data = _merge(data, extra)
    return parse_scene(data, source="test")


def _elements(text: str) -> dict[str, list[str]]:
    """Element lines of a netlist grouped by their first letter (L, C, R, V, B, ...)."""
    groups: dict[str, list[str]] = {}
    for line in text.splitlines()[1:]:
        if line and line[0] not in "*.":
            groups.setdefault(line[0].upper(), []).append(line)
    return groups


def _saved(text: str) -> list[str]:
    (line,) = [x for x in text.splitlines() if x.startswith(".save")]
    return line.split()[1:]


def _tstop_seconds(text: str) -> float:
    (line,) = [x for x in text.splitlines() if x.startswith(".tran")]
    return float(line.split()[2])


def _netlist(scene) -> str:
    return scene_plan(scene).specs[0].netlist


# ------------------------------------------------------ against exact theory


@pytest.mark.ngspice
@pytest.mark.parametrize("effect", sorted(EFFECTS))
def test_each_effect_alone_meets_the_accuracy_against_exact_theory(effect: str) -> None:
    result = run_scene(_scene(EFFECTS[effect]), SceneRun(write_outputs=False))
    assert result.ok, result.report["samples"]
    for sample in result.samples:  # the theory computes every loop only when every loop is saved
        rows = sample.chain.N if effect == "all-probes" else 2
        assert sample.theory.shape == sample.sim.shape == (rows, sample.t.size)
    for record in result.report["samples"]:
        assert record["max_abs_error"] <= ACCURACY_COARSE, (effect, record["sample"], record["max_abs_error"])
        for a in record["arrivals"]:
            assert abs(a["peak_sim"] - a["peak_theory"]) <= ACCURACY_COARSE, (effect, a)


@pytest.mark.ngspice
def test_every_effect_combined_meets_a_fine_accuracy() -> None:
    scene = _scene(COMBINED, {"analysis": {"accuracy": ACCURACY_FINE}})
    result = run_scene(scene, SceneRun(write_outputs=False))
    assert result.ok, result.report["samples"]
    assert len(result.samples) == 3
    for record in result.report["samples"]:
        assert record["max_abs_error"] <= ACCURACY_FINE, record
    # The error is the step's, not a modelling gap: it shrinks as dt^2 when asked for less.
    coarse = run_scene(_scene(COMBINED), SceneRun(write_outputs=False))
    assert coarse.report["max_abs_error"] > 10 * result.report["max_abs_error"]


@pytest.mark.ngspice
def test_a_wrong_quality_factor_in_the_theory_is_caught(monkeypatch) -> None:
    # The comparison must be able to fail: the theory gets Q = 60 for a Q = 50 circuit (the runs import
    # prepare_response where they use it: patched in its own module).
    from lcchain.theory import response as response_module

    real = response_module.prepare_response

    def theory_off(*args, **kwargs):
        return real(*args, **{**kwargs, "Q": 60.0})

    monkeypatch.setattr(response_module, "prepare_response", theory_off)
    result = run_scene(_scene(EFFECTS["losses"]), SceneRun(write_outputs=False))
    assert result.report["max_abs_error"] > MIN_ERROR_WRONG_THEORY


@pytest.mark.ngspice
def test_every_loop_current_matches_its_theory() -> None:
    result = run_scene(_scene(EFFECTS["all-probes"], EFFECTS["displacement"]), SceneRun(write_outputs=False))
    (sample,) = result.samples
    assert sample.sim.shape == sample.theory.shape == (N, sample.t.size)
    worst = float(np.max(np.abs(sample.sim - sample.theory)))
    assert worst <= ACCURACY_COARSE
    assert result.report["max_abs_error"] == worst  # the report covers every loop, not only the ends


# ------------------------------------------------ only what the scene calls for


def test_an_ideal_scene_is_a_pure_lc_ladder_saving_two_currents() -> None:
    text = _netlist(_scene())
    groups = _elements(text)
    assert set(groups) == {"L", "C"}
    assert len(groups["L"]) == N and len(groups["C"]) == N - 1  # free ends: no wall capacitor
    assert _saved(text) == ["i(l1)", f"i(l{N})"]


@pytest.mark.parametrize(
    ("effect", "added"),
    [("losses", {"R": N}), ("walls", {"C": 2}), ("gaussian", {"B": 1}), ("rect", {"V": 1}),
     ("E24", {}), ("tolerance", {}), ("displacement", {})],
)
def test_each_effect_adds_only_its_own_elements(effect: str, added: dict) -> None:
    ideal = {k: len(v) for k, v in _elements(_netlist(_scene())).items()}
    text = _netlist(_scene(EFFECTS[effect]))
    counts = {k: len(v) for k, v in _elements(text).items()}
    expected = dict(ideal)
    for kind, extra in added.items():
        expected[kind] = expected.get(kind, 0) + extra
    assert counts == expected
    assert _saved(text) == ["i(l1)", f"i(l{N})"]


def test_probes_all_saves_every_loop_current_and_nothing_else() -> None:
    assert _saved(_netlist(_scene(EFFECTS["all-probes"]))) == [f"i(l{i})" for i in range(1, N + 1)]


@pytest.mark.parametrize("transits", [1, 3])
def test_the_analysis_lasts_the_requested_transits(transits: int) -> None:
    scene = _scene({"analysis": {"transits": transits}})
    plan = scene_plan(scene)
    assert plan.tstop == pytest.approx(arrival_window(transits, plan.transit_time)[1], rel=RTOL_ONE_OPERATION)
    unit = math.sqrt(scene.units.L0 * scene.units.C0)
    assert _tstop_seconds(_netlist(scene)) == pytest.approx(plan.tstop * unit, rel=RTOL_NETLIST_VALUE)


def test_preferred_values_are_in_the_series() -> None:
    text = _netlist(_scene(EFFECTS["E24"]))
    mantissas = set()
    for line in _elements(text)["L"] + _elements(text)["C"]:
        value = float(line.split()[3])
        mantissas.add(round(value / 10 ** math.floor(math.log10(value) + 1e-12), 9))
    assert mantissas <= set(E_SERIES["E24"])
    assert len(mantissas) > 1  # the optimal ends are rounded, not only the bulk values


def test_tolerance_samples_differ_and_repeat_with_their_seed() -> None:
    plan = scene_plan(_scene(EFFECTS["tolerance"]))
    again = scene_plan(_scene(EFFECTS["tolerance"]))
    other = scene_plan(_scene(EFFECTS["tolerance"], {"effects": {"tolerance": {"seed": 4}}}))
    masses = [tuple(c.masses) for c in plan.chains]
    assert len(set(masses)) == 3
    assert masses == [tuple(c.masses) for c in again.chains]
    assert masses != [tuple(c.masses) for c in other.chains]


def test_a_pulse_step_resolves_the_pulse() -> None:
    plan = scene_plan(_scene({"excitation": {"kind": "pulse", "shape": "gaussian", "width": 0.05}}))
    assert plan.dt <= 0.05 / 8


def test_large_realised_chains_are_refused_before_any_run() -> None:
    scene = _scene({"chain": {"N": 20_000}}, EFFECTS["tolerance"])
    with pytest.raises(ParameterError, match=r"chain.N = 20000 .*N <= 10000"):
        scene_plan(scene)


# ------------------------------------------------------- reports and failures


@pytest.mark.ngspice
def test_tolerance_report_has_one_record_per_sample_and_the_spread(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    scene = _scene(EFFECTS["tolerance"], EFFECTS["losses"],
                   {"output": {"report": "r.json", "plots": ["overlay", "histogram"]}})
    result = run_scene(scene)
    report = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert report["scene"] == scene.to_dict()
    assert report["ngspice_version"]
    assert [r["sample"] for r in report["samples"]] == [1, 2, 3]
    peaks = [r["arrivals"][0]["peak_sim"] for r in report["samples"]]
    spread = report["transmitted_peak"]
    assert spread["count"] == 3
    assert spread["worst"] == min(peaks) and spread["best"] == max(peaks)
    assert spread["mean"] == pytest.approx(np.mean(peaks), rel=RTOL_MEAN_OF_SAMPLES)
    assert spread["std"] == pytest.approx(np.std(peaks, ddof=1), rel=RTOL_STD_OF_SAMPLES) and spread["std"] > 0
    for record in report["samples"]:
        assert {"dt", "points", "netlist_sha256", "wall_s", "max_abs_error", "arrivals"} <= record.keys()
        for a in record["arrivals"]:
            # after a kick, the energy the end's inductor holds at the peak: at most the kick's, with losses less
            assert {"index", "end", "t_theory", "t_sim", "peak_theory", "peak_sim", "energy_sim"} == a.keys()
            assert 0 < a["energy_sim"] < 1
    assert {"ngspice", "total"} == report["wall_s"].keys()
    for name in ("r-overlay.png", "r-histogram.png"):
        assert (tmp_path / name).stat().st_size > 10_000
    assert "r.json" in result.files


@pytest.mark.ngspice
def test_a_failed_sample_is_recorded_and_the_others_still_run(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    scene = _scene(EFFECTS["tolerance"], {"output": {"report": "r.json"}})
    plan = scene_plan(scene)
    specs = scene_specs(scene, plan)
    # ngspice itself rejects the second sample's netlist (an unknown model); the others run as planned
    specs[1] = dataclasses.replace(specs[1], netlist=specs[1].netlist.replace(".end\n", "Q99 n1 0 1.0\n.end\n"),
                                   trusted=True)  # trusted: the allow-list would refuse a Q element before ngspice
    before = temporary_entries()
    result = scene_result(scene, plan, specs, [execute(spec) for spec in specs], total_s=0.0)
    assert not result.ok
    write_scene_outputs(result)
    records = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))["samples"]
    assert records[1]["status"] == "failed" and "model" in records[1]["error"]
    assert "error" not in records[0] and "error" not in records[2]
    assert records[2]["max_abs_error"] <= ACCURACY_COARSE
    assert temporary_entries() == before  # nothing of the failed run is left behind


# ------------------------------------------------------------- command line


@pytest.mark.ngspice
@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if p.stem == "real-parts" else p
                                  for p in EXAMPLES], ids=lambda p: p.stem)  # real-parts: 14 s, its 200 samples
def test_every_example_scene_runs_from_the_cli(path: Path, tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["run", str(path), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    if report.get("analysis") == "ac":  # a spectrum, each sample against its own chain's modes
        assert report["max_rel_error_omega"] < RTOL_SPECTRUM_OMEGA and report["max_abs_error_P"] < ATOL_SPECTRUM_P
    else:
        accuracy = report["scene"]["analysis"].get("accuracy")
        assert accuracy is not None and report["max_abs_error"] <= accuracy
    for name in report["files"]:
        assert (tmp_path / name).stat().st_size > 0, name
    plots = report["scene"]["output"].get("plots", ["overlay"])
    assert sum(name.endswith(".png") for name in report["files"]) == len(plots)


@pytest.mark.ngspice
def test_run_keeps_the_netlist_and_waveforms(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    scene_file = tmp_path / "s.toml"
    scene_file.write_text('title = "kept"\n[chain]\ncase = "perfect"\nN = 4\n[analysis]\ndt = 0.01\n'
                          '[output]\nplots = []\n', encoding="utf-8")
    assert main(["run", str(scene_file), "--netlist-out", "kept.cir", "--waveform-out", "kept.csv"]) == 0
    out = capsys.readouterr().out
    assert "max |simulation - theory|" in out and "wrote kept.cir" in out
    assert (tmp_path / "kept.cir").read_text(encoding="utf-8").startswith("kept\n")
    with open(tmp_path / "kept.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["t", "first", "last"]
    values = np.array(rows[1:], dtype=float)
    assert values[-1, 0] == pytest.approx(scene_plan(parse_scene({"chain": {"case": "perfect", "N": 4},
                                                                  "analysis": {"dt": 0.01}})).tstop, rel=RTOL_CSV_TIME)
    # the perfect N = 4 chain in bulk units (masses 5/3, 1, 1, 5/3) transmits the whole kick at sqrt(3) pi: the
    # paper's sqrt(11) pi / 2 for its masses 11/12 as large (times scale as sqrt(m))
    t_star = math.sqrt(3) * math.pi
    near = np.abs(values[:, 0] - t_star) < 0.05
    assert values[near, 2].max() == pytest.approx(1.0, abs=ATOL_CSV_PEAK)


@pytest.mark.ngspice
def test_side_by_side_of_the_uniform_and_optimal_scenes(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    pair = [str(SCENES / "uniform-vs-optimal-uniform.toml"), str(SCENES / "uniform-vs-optimal-optimal.toml")]
    assert main(["run", *pair, "--side-by-side", "pair.png", "--json"]) == 0
    reports = json.loads(capsys.readouterr().out)
    assert [r["scene"]["chain"]["case"] for r in reports] == ["uniform-free", "two-mass"]
    uniform, optimal = (r["arrivals"][0]["peak_sim"] for r in reports)
    assert optimal > 0.98 and uniform < 0.6  # the point of the paper, in ngspice
    assert (tmp_path / "pair.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ('[chain]\ncase = "two-mass"\nN = 2\n', "chain.N = 2"),
        ('[chain]\ncase = "two-mass"\nN = 20\ncolour = 1\n', "colour"),
        ('title = "a\\n.control"\n[chain]\ncase = "two-mass"\nN = 20\n', "title"),
    ],
)
def test_bad_scene_files_exit_2_with_one_line(tmp_path: Path, capsys, text: str, said: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and str(path) in err and said in err, err


def test_several_scenes_with_one_netlist_out_is_a_usage_error(capsys) -> None:
    assert main(["run", str(EXAMPLES[0]), str(EXAMPLES[1]), "--netlist-out", "x.cir"]) == 2
    assert "--netlist-out" in capsys.readouterr().err


def test_every_scene_file_is_checked_before_anything_runs(tmp_path: Path, capsys) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text('[chain]\ncase = "two-mass"\nN = 2\n', encoding="utf-8")
    assert main(["run", str(EXAMPLES[0]), str(bad)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""  # the good first scene did not run
    assert "chain.N = 2 is not allowed" in captured.err


@pytest.mark.ngspice
def test_a_short_rect_pulse_tends_to_the_kick() -> None:
    # g of unit area and width w -> 0 gives L_1 the current I0: a kick, delayed by about w / 2.
    kick = run_scene(_scene(), SceneRun(write_outputs=False)).report["arrivals"][0]
    width = 0.02
    pulse = run_scene(_scene({"excitation": {"kind": "pulse", "shape": "rect", "width": width}}),
                      SceneRun(write_outputs=False)).report["arrivals"][0]
    assert pulse["peak_sim"] == pytest.approx(kick["peak_sim"], abs=ACCURACY_COARSE)
    assert pulse["t_sim"] - kick["t_sim"] == pytest.approx(width / 2, abs=ATOL_PULSE_DELAY)


def test_scene_titles_say_the_size_once_and_a_pulse_peak_names_its_source() -> None:
    from lcchain.report.scenes import _with_size, peak_label

    title = _with_size("Newton's cradle, two-mass chain, N = 100", 100)
    assert title.count("N = 100") == 1
    assert _with_size("Bench cradle", 50) == "Bench cradle (N = 50)"
    assert "I_0" in peak_label("pulse") and "pulse source" in peak_label("pulse")
    assert "I_1(0)" in peak_label("kick")
