"""Engines (issue 20, section 3): the protocol and registry, gnucap as the second engine, records and keys.

gnucap runs for real (no mocks) against exact theory and against ngspice on the same netlist.  Expected
values: the trapezoidal error model of :func:`lcchain.compare.accuracy.predicted_error` (gnucap at a fixed
step follows it as ngspice does: measured 0.91 to 1.003 times ngspice's error on N = 20 chains for
dt = 0.05 ... 0.001); the exact response of two coupled coils from the matrix exponential of
M di/dt = v, C dv/dt = -i.
"""

from __future__ import annotations

import hashlib
import json
import math
import pickle
from pathlib import Path

import numpy as np
import pytest
from helpers.processes import temporary_entries
from helpers.tolerances import (
    ACCURACY_COARSE,
    ATOL_WHOLE_STEPS,
    MAX_ENGINE_DIFFERENCE_FRACTION,
    MAX_GNUCAP_ERROR_DT_0_05,
    PREDICTION_FACTOR,
    RTOL_COUPLED_INITIAL_CURRENT,
    RTOL_GNUCAP_TSTOP,
)
from scipy.linalg import expm

import lcchain
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import SimulationOptions, netlist_text
from lcchain.cli import main
from lcchain.core import __version__
from lcchain.core.errors import ParameterError, SimulationError
from lcchain.runs.execute import execute
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.runs.spec import RunSpec
from lcchain.scenes.load import parse_scene
from lcchain.scenes.run import simulate_scene
from lcchain.spice.doctor import doctor
from lcchain.spice.engine import Engine
from lcchain.spice.engines import DEFAULT_ENGINE, ENGINES, find_engine, run_engine
from lcchain.spice.gnucap import coupled_initial_currents, read_table
from lcchain.spice.job import RunJob
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import SweepAxes, sweep_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store, engine_of, engine_text
from lcchain.theory.cases import chain_for_case

ROOT = Path(__file__).resolve().parent.parent
#: gnucap and ngspice on the same netlist: both follow the trapezoidal rule at (nearly) the same steps, so
#: they differ by a fraction of either one's error against theory (measured 0.05 to 0.3 of it).
ENGINE_DIFFERENCE_FRACTION = 0.5
#: Scales far from lcchain's defaults (I0 = 100 A: ~3 kV; L0 = C0 = 1: a 1 s time unit; L0 = 1 mH, C0 = 1 pF:
#: 31.6 kOhm), where gnucap's absolute defaults (vmax, dtmin, gmin) once cost it up to 240 times its prediction.
SCALES = [{"I0": 100.0}, {"L0": 1.0, "C0": 1.0, "I0": 1.0}, {"L0": 1e-3, "C0": 1e-12, "I0": 1e-6}]
#: Two coupled coils, 400 steps per period: the trapezoidal phase error after two periods (~1e-4) with margin.
ATOL_COUPLED = 1e-3

# --------------------------------------------------------------------------- the registry


def test_the_registry_maps_names_to_engines() -> None:
    # lcchain's own first, in order; an installed package's engines may follow (entry points)
    assert list(ENGINES)[:2] == ["ngspice", "gnucap"] and DEFAULT_ENGINE == "ngspice"
    for name, engine in ENGINES.items():
        assert isinstance(engine, Engine) and engine.name == name and engine.transports
    assert ENGINES["ngspice"].dialect("any text", ["i(l1)"]) == "any text"  # lcchain writes ngspice's dialect


def test_an_unknown_engine_or_transport_is_refused_naming_the_field() -> None:
    with pytest.raises(ParameterError, match=r"engine = 'spectre' is not allowed: expected ngspice \| gnucap"):
        find_engine("spectre")
    with pytest.raises(ParameterError, match=r"backend = 'shared' .*transports of engine gnucap"):
        find_engine("gnucap", "shared")


# --------------------------------------------------------------------------- the dialect (no simulator)


def _reference(name: str) -> str:
    return (ROOT / "netlists" / name).read_text()


def test_the_gnucap_dialect_of_a_reference_netlist() -> None:
    text = _reference("two-mass-N20.cir")
    dialect = ENGINES["gnucap"].dialect(text, ["i(l1)", "i(l20)"])
    lines = dialect.splitlines()
    assert lines[0] == "* lcchain ladder in gnucap's dialect"  # the user's title never reaches gnucap
    assert lines[-3:-1] == [".print tran i(l1) i(l20)", lines[-2]] and lines[-1] == ".end"
    assert lines[-2].startswith(".tran ") and "dtmax=" in lines[-2] and lines[-2].endswith(" uic")
    assert lines.index(".print tran i(l1) i(l20)") < lines.index(lines[-2])  # gnucap runs .tran as it reads it
    (options,) = [line for line in lines if line.startswith(".options")]
    assert "numdgt=14" in options and "method=trap" in options and "maxord" not in options
    assert "IC=" not in dialect and " ic=0.001" in dialect
    # the step is shortened to land on tstop: tstop is a whole number of steps, none longer than dt
    (tran,) = [line for line in text.splitlines() if line.startswith(".tran")]
    step, tstop = float(tran.split()[1]), float(tran.split()[2])
    h = float(lines[-2].split()[1])
    assert h <= step and tstop / h == pytest.approx(round(tstop / h), abs=ATOL_WHOLE_STEPS)
    assert ENGINES["gnucap"].dialect(text, ["i(l1)", "i(l20)"]) == dialect  # deterministic


@pytest.mark.parametrize("change, said", [
    (lambda t: t.replace(".end", "B1 s1 0 V=1.0*exp(-time)\n.end"), "behavioural source"),
    (lambda t: t.replace(".end", "V1 s1 0 PWL(0 1.0 1e-6 1.0 1.000001e-06 0)\n.end"), "PWL source"),
    (lambda t: t.replace("method=trap", "method=gear"), "method = 'gear'"),
    (lambda t: t.replace("trtol=7.0", "trtol=7.0 klu"), "the option 'klu'"),
    (lambda t: t.replace(".end", ".control\nrun\n.endc\n.end"), "the line '.control'"),
    (lambda t: t.replace(" uic", " 0 uic"), "the analysis"),
])
def test_the_gnucap_dialect_refuses_what_it_cannot_translate(change, said: str) -> None:
    with pytest.raises(ParameterError, match="engine = 'gnucap' is not allowed") as caught:
        ENGINES["gnucap"].dialect(change(_reference("two-mass-N20.cir")), ["i(l1)", "i(l20)"])
    assert said in str(caught.value) and caught.value.field == "engine"


def test_adaptive_and_aligned_steps_are_refused_with_gnucap() -> None:
    ladder = Ladder(chain_for_case("two-mass", 20))
    for options in (SimulationOptions(dt=0.05, tstop=30.0, aligned=True),
                    SimulationOptions(dt=0.05, tstop=30.0, stepping="adaptive")):
        with pytest.raises(ParameterError, match="adaptive or aligned steps"):
            RunSpec(netlist_text(ladder, options), ("i(l1)", "i(l20)"), 30.0 * ladder.time_unit, foreign=False,
                    engine="gnucap")


def test_coupled_initial_currents_are_flux_over_inductance() -> None:
    L = {"l1": 1e-5, "l2": 2e-5, "l3": 3e-5}
    k = [("l1", "l2", 0.03), ("l2", "l3", 0.02)]
    ic = coupled_initial_currents(L, {"l1": 1e-3}, k)
    assert ic["l1"] == 1e-3 and "l3" not in ic  # l3 is not coupled to the kicked coil
    assert ic["l2"] == pytest.approx(0.03 * math.sqrt(1e-5 * 2e-5) * 1e-3 / 2e-5, rel=RTOL_COUPLED_INITIAL_CURRENT)
    assert coupled_initial_currents(L, {"l1": 1e-3}, []) == {"l1": 1e-3}  # uncoupled: ic is the current


def test_read_table_takes_suffixes_drops_the_t0_row_and_refuses_messages() -> None:
    table = ("Gnucap : The Gnu Circuit Analysis Package\nmain version: master 2017.10.03\n"
             "* lcchain ladder in gnucap's dialect\n#Time                i(L1)               v(n3)\n"
             " 0.                  0.                  0.\n 15.811388300842n    999.75003019602u   -4.398E-18\n"
             " 31.622776601684n    1.                  2.5m\n")
    columns = read_table(table)
    assert list(columns) == ["time", "i(l1)", "v(n3)"]
    np.testing.assert_array_equal(columns["time"], [15.811388300842e-9, 31.622776601684e-9])
    np.testing.assert_array_equal(columns["v(n3)"], [-4.398e-18, 2.5e-3])
    with pytest.raises(SimulationError, match=r"gnucap reported: Q7: missing args") as caught:
        read_table(table.replace("#Time", "Q7: missing args -- need model name\n#Time"))
    assert "gnucap said" in str(caught.value)
    with pytest.raises(SimulationError, match="a row lcchain cannot read"):
        read_table(table + "incomplete:../e_storag.cc:147:differentiate\n")
    with pytest.raises(SimulationError, match="no table"):
        read_table("Gnucap : The Gnu Circuit Analysis Package\n")


# --------------------------------------------------------------------------- specs, keys, records, stores


def test_ngspice_keys_are_those_of_stores_made_before_engines() -> None:
    spec, _, _ = simulation_spec(chain_for_case("two-mass", 20), ChainOptions(dt=0.05))
    assert spec.engine == "ngspice"
    old = {"netlist": spec.netlist, "vectors": list(spec.vectors), "tstop": float(spec.tstop).hex(),
           "backend": spec.backend, "cwd": spec.cwd, "trusted": spec.trusted, "lcchain": __version__,
           "ngspice": "39", "theory": spec.theory.fingerprint() if spec.theory is not None else None}
    assert spec.key("39") == hashlib.sha256(json.dumps(old, sort_keys=True).encode("utf-8")).hexdigest()
    gnucap, _, _ = simulation_spec(chain_for_case("two-mass", 20), ChainOptions(dt=0.05, engine="gnucap"))
    assert gnucap.netlist == spec.netlist and gnucap.key("39") != spec.key("39")
    assert pickle.loads(pickle.dumps(gnucap)) == gnucap


def test_a_spec_is_checked_against_its_engine() -> None:
    spec, _, _ = simulation_spec(chain_for_case("two-mass", 20), ChainOptions(dt=0.05))
    with pytest.raises(ParameterError, match="engine = 'bogus'"):
        RunSpec(spec.netlist, spec.vectors, spec.tstop, foreign=False, engine="bogus")
    with pytest.raises(ParameterError, match="ngspice for a netlist lcchain did not write"):
        RunSpec(spec.netlist, spec.vectors, spec.tstop, engine="gnucap")  # foreign by default
    with pytest.raises(ParameterError, match="backend = 'shared'"):
        RunSpec(spec.netlist, spec.vectors, spec.tstop, foreign=False, backend="shared", engine="gnucap")


def test_the_store_column_holds_the_engine_and_reads_format_1() -> None:
    assert engine_text("ngspice", "39") == "ngspice 39" and engine_of("ngspice 39") == ("ngspice", "39")
    assert engine_of("39") == ("ngspice", "39")  # a format-1 store's ngspice row
    assert engine_of(engine_text("gnucap", "2017.10.03")) == ("gnucap", "2017.10.03")


# --------------------------------------------------------------------------- gnucap against theory and ngspice


@pytest.mark.gnucap
@pytest.mark.parametrize("case, N, dt, excitation, walls", [
    ("two-mass", 20, 0.05, "kick", 0),
    ("two-mass", 100, 0.05, "kick", 0),
    ("perfect", 100, 0.02, "kick", 0),
    ("two-mass", 100, 0.05, "displacement", 0),
    ("perfect", 50, 0.05, "kick", 1),
])
def test_gnucap_meets_the_predicted_error_against_exact_theory(case: str, N: int, dt: float, excitation: str,
                                                               walls: int) -> None:
    report = lcchain.simulate_chain(chain_for_case(case, N, walls), lcchain.ChainOptions(dt=dt, excitation=excitation, engine="gnucap"))
    achieved = report.comparison.max_abs_error
    assert report.predicted_error is not None
    assert achieved / PREDICTION_FACTOR <= report.predicted_error <= achieved * PREDICTION_FACTOR
    assert report.integration_error is None  # the error split models ngspice's start-up steps, not gnucap's
    data = report.to_dict()
    assert (data["engine"], data["backend"], data["ngspice_version"]) == ("gnucap", "batch", "")
    assert data["engine_version"] == find_engine("gnucap").version


@pytest.mark.gnucap
@pytest.mark.parametrize("scale", SCALES)
def test_gnucap_meets_the_predicted_error_at_any_scale(scale: dict) -> None:
    report = lcchain.simulate_chain(chain_for_case("perfect", 60), lcchain.ChainOptions(dt=0.005, engine="gnucap", **scale))
    achieved = report.comparison.max_abs_error
    assert report.predicted_error is not None
    assert achieved / PREDICTION_FACTOR <= report.predicted_error <= achieved * PREDICTION_FACTOR


@pytest.mark.gnucap
@pytest.mark.ngspice
def test_gnucap_and_ngspice_agree_on_the_same_netlist() -> None:
    spec, _, _ = simulation_spec(chain_for_case("perfect", 40), ChainOptions(dt=0.04, transits=2))
    results = {name: run_engine(RunJob(spec.netlist, spec.vectors, spec.tstop, foreign=False), find_engine(name))
               for name in ENGINES}
    gnucap, ngspice = results["gnucap"], results["ngspice"]
    assert (gnucap.engine, ngspice.engine) == ("gnucap", "ngspice") and gnucap.netlist_sha256 == ngspice.netlist_sha256
    assert gnucap.time[0] > 0 and gnucap.time[-1] == pytest.approx(spec.tstop, rel=RTOL_GNUCAP_TSTOP)
    I0 = 1e-3
    for name in spec.vectors:
        difference = np.max(np.abs(np.interp(gnucap.time, ngspice.time, ngspice.vectors[name])
                                   - gnucap.vectors[name])) / I0
        assert spec.theory is not None and spec.theory.predicted_error is not None
        assert difference < ENGINE_DIFFERENCE_FRACTION * spec.theory.predicted_error, (name, difference)


def _coupled_netlist(k: float, h: float, tstop: float) -> str:
    return (f"* two coupled coils\nL1 n1 0 1e-05 IC=0.001\nL2 n2 0 2e-05\nK1_2 L1 L2 {k!r}\nC1 n1 0 1e-08\n"
            f"C2 n2 0 2e-08\n.options method=trap maxord=2 reltol=0.001 abstol=1e-15 vntol=1e-14 chgtol=1e-25 "
            f"trtol=7.0\n.tran {h!r} {tstop!r} 0 {h!r} uic\n.save i(l1) i(l2)\n.end\n")


def _coupled_exact(k: float, t: np.ndarray) -> np.ndarray:
    """i(t) of L_j (1e-5, 2e-5 H) each across C_j (1e-8, 2e-8 F), coupled by k: M di/dt = v, C dv/dt = -i."""
    M = np.array([[1e-5, k * math.sqrt(2e-10)], [k * math.sqrt(2e-10), 2e-5]])
    C = np.diag([1e-8, 2e-8])
    A = np.block([[np.zeros((2, 2)), np.linalg.inv(M)], [-np.linalg.inv(C), np.zeros((2, 2))]])
    x0 = np.array([1e-3, 0.0, 0.0, 0.0])
    return np.array([(expm(A * s) @ x0)[:2] for s in t]).T


@pytest.mark.gnucap
@pytest.mark.ngspice
def test_coupled_coils_start_with_the_wanted_currents_in_both_engines() -> None:
    k, period = 0.03, 2 * math.pi * math.sqrt(1e-5 * 1e-8)
    h, tstop = period / 400, 2 * period
    I0 = 1e-3  # L1's IC= in _coupled_netlist
    text = _coupled_netlist(k, h, tstop)
    assert " ic=" in ENGINES["gnucap"].dialect(text, ["i(l1)", "i(l2)"]).split("L2 n2 0 2e-05")[1].splitlines()[0]
    for name in ENGINES:
        result = run_engine(RunJob(text, ["i(l1)", "i(l2)"], tstop, foreign=False), find_engine(name))
        exact = _coupled_exact(k, result.time)
        for row, vector in enumerate(("i(l1)", "i(l2)")):
            error = np.max(np.abs(result.vectors[vector] - exact[row])) / I0
            assert error < ATOL_COUPLED, (name, vector, error)
        first = result.vectors["i(l1)"][0] + result.vectors["i(l2)"][0]  # untranslated: 1/(1 + k) of I0
        assert first == pytest.approx(exact[0][0] + exact[1][0], abs=ATOL_COUPLED * I0)


@pytest.mark.gnucap
@pytest.mark.parametrize("effect", [{"effects": {"losses": {"Q": 50}}}, {"effects": {"walls": {"K0": 0.05}}},
                                    {"excitation": {"kind": "displacement"}},
                                    {"effects": {"tolerance": {"L": 0.05, "C": 0.05, "samples": 2, "seed": 3}}}])
def test_a_gnucap_scene_meets_its_accuracy(effect: dict) -> None:
    data = {"title": "gnucap scene", "chain": {"case": "two-mass", "N": 16},
            "excitation": {"kind": "kick", "I0": 1e-3}, "analysis": {"transits": 1, "accuracy": ACCURACY_COARSE,
                                                                      "engine": "gnucap"},
            "output": {"probes": "ends", "plots": []}}
    for table, values in effect.items():
        data[table] = {**data.get(table, {}), **values}
    scene = parse_scene(data, source="test.toml")
    assert scene.to_dict()["analysis"]["engine"] == "gnucap"
    result = simulate_scene(scene)
    assert result.report["engine"] == "gnucap" and result.report["ngspice_version"] is not None
    for record in result.report["samples"]:
        assert record["status"] == "ok" and record["engine"] == "gnucap"
        assert record["max_abs_error"] <= ACCURACY_COARSE


def test_an_ngspice_scene_writes_no_engine_key() -> None:  # scenes (and stores) made before engines stay the same
    data = {"chain": {"case": "two-mass", "N": 16}, "analysis": {"dt": 0.05}}
    assert "engine" not in parse_scene(data, source="t.toml").to_dict()["analysis"]


@pytest.mark.gnucap
def test_gnucap_accuracy_makes_one_run_and_meets_it() -> None:
    report = lcchain.simulate_chain(chain_for_case("two-mass", 40), lcchain.ChainOptions(accuracy=1e-3, engine="gnucap"))
    assert report.extrapolation is not None and report.extrapolation.runs == 1
    assert report.accuracy_met


# --------------------------------------------------------------------------- refusals


def test_extrapolation_with_gnucap_is_refused_naming_the_option() -> None:
    with pytest.raises(ParameterError, match=r"extrapolate = 2 is not allowed: expected 1 with engine gnucap"):
        lcchain.simulate_chain(chain_for_case("two-mass", 20), lcchain.ChainOptions(dt=0.05, extrapolate=2, engine="gnucap"))
    with pytest.raises(ParameterError, match=r"analysis.extrapolate = 3 .*engine gnucap"):
        parse_scene({"chain": {"case": "two-mass", "N": 16}, "analysis": {"extrapolate": 3, "engine": "gnucap"}},
                    source="t.toml")


@pytest.mark.parametrize("excitation, said", [({"kind": "pulse", "shape": "gaussian", "width": 0.3}, "behavioural"),
                                              ({"kind": "pulse", "shape": "rect", "width": 0.5}, "PWL source")])
def test_pulse_scenes_are_refused_with_gnucap_before_anything_runs(excitation: dict, said: str) -> None:
    scene = parse_scene({"chain": {"case": "two-mass", "N": 16}, "excitation": excitation,
                         "analysis": {"engine": "gnucap"}}, source="p.toml")
    with pytest.raises(ParameterError, match=r"^p\.toml: analysis\.engine = 'gnucap' is not allowed") as caught:
        simulate_scene(scene)
    assert said in str(caught.value)


def test_gear_with_gnucap_is_refused() -> None:
    with pytest.raises(ParameterError, match="method = 'gear'"):
        lcchain.simulate_chain(chain_for_case("two-mass", 20), lcchain.ChainOptions(dt=0.05, method="gear", engine="gnucap"))


@pytest.mark.gnucap
def test_a_foreign_netlist_never_runs_in_gnucap() -> None:
    text = _reference("two-mass-N20.cir")
    with pytest.raises(ParameterError, match="ngspice for a netlist lcchain did not write"):
        run_engine(RunJob(text, ["i(l1)"], 1e-6), find_engine("gnucap"))


@pytest.mark.parametrize("argv, said", [
    (["--engine", "gnucap", "--extrapolate", "2"], "--extrapolate = 2 is not allowed: expected 1 with engine gnucap"),
    (["--engine", "gnucap", "--method", "gear"], "engine = 'gnucap' is not allowed"),
])
def test_the_command_line_refuses_in_one_line(capsys, argv: list[str], said: str) -> None:
    status = main(["simulate", "--case", "two-mass", "--N", "20", "--dt", "0.05", *argv])
    err = capsys.readouterr().err
    assert status == 2 and said in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


# --------------------------------------------------------------------------- the command line, studies, doctor


@pytest.mark.gnucap
def test_simulate_engine_gnucap_on_the_command_line(capsys) -> None:
    status = main(["simulate", "--case", "two-mass", "--N", "20", "--dt", "0.05", "--engine", "gnucap", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert status == 0 and data["engine"] == "gnucap" and data["max_abs_error"] < MAX_GNUCAP_ERROR_DT_0_05


@pytest.mark.gnucap
def test_a_gnucap_sweep_stores_its_engine_and_resumes(tmp_path: Path) -> None:
    before = temporary_entries()
    path = tmp_path / "g.sqlite"
    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[20], dts=[0.05, 0.1], engine="gnucap"))
    assert plan.engine == "gnucap" and plan.description["engine"] == "gnucap"
    summary = run_plan(plan, path, RunOptions(executor="serial"))
    assert (summary.ran, summary.ok) == (2, 2)
    with Store(path, "read") as store:
        runs = store.runs()
        assert {(run.engine, run.ngspice_version) for run in runs} == {("gnucap", "")}
        assert all(run.engine_version == find_engine("gnucap").version for run in runs)
        assert store.meta()["engine"].startswith("gnucap ")
    again = run_plan(sweep_plan(SweepAxes(cases=["two-mass"], Ns=[20], dts=[0.05, 0.1], engine="gnucap")), path, RunOptions(executor="serial"))
    assert (again.skipped, again.ran) == (2, 0)
    with pytest.raises(ParameterError, match="holds another"):  # the ngspice study is another plan
        run_plan(sweep_plan(SweepAxes(cases=["two-mass"], Ns=[20], dts=[0.05, 0.1])), path, RunOptions(executor="serial"))
    assert temporary_entries() == before  # gnucap's folders and files are gone


@pytest.mark.gnucap
def test_a_record_of_a_gnucap_run_says_so() -> None:
    spec, _, _ = simulation_spec(chain_for_case("two-mass", 20), ChainOptions(dt=0.1, engine="gnucap"))
    record = execute(spec)
    assert record.ok and (record.engine, record.ngspice_version) == ("gnucap", "")
    assert record.summary()["engine"] == "gnucap" and record.key == spec.key(record.engine_version)
    with pytest.raises(ParameterError, match="simulator"):
        execute(spec, find_engine("ngspice"))


@pytest.mark.gnucap
def test_doctor_lists_every_engine() -> None:
    checks = {check.name: check for check in doctor()}
    for name in ENGINES:
        assert checks[f"engine {name}"].ok, checks[f"engine {name}"]
        assert checks[f"engine {name}"].required == (name == DEFAULT_ENGINE)


def test_a_gnucap_run_is_priced_at_its_own_cost() -> None:
    from lcchain.core.budget import INTERPRETER_SECONDS, Budget, BudgetError, run_estimate

    chain = chain_for_case("two-mass", 400)
    spec, _, options = simulation_spec(chain, ChainOptions(dt=0.02))
    seconds = run_estimate(points=options.tstop / 0.02, saved=2, compared=2, unknowns=800).seconds
    budget = Budget(max_seconds=INTERPRETER_SECONDS + 2 * seconds)  # ngspice fits, gnucap (6x) does not
    simulation_spec(chain, ChainOptions(dt=0.02), budget=budget)
    with pytest.raises(BudgetError, match="dt = 0.02"):
        simulation_spec(chain, ChainOptions(dt=0.02, engine="gnucap"), budget=budget)
    assert ENGINES["gnucap"].relative_cost > ENGINES["ngspice"].relative_cost == 1.0


@pytest.mark.gnucap
def test_a_gnucap_timeout_kills_it_and_leaves_nothing() -> None:
    import os

    from helpers.processes import descendants

    before = temporary_entries()
    spec, _, _ = simulation_spec(chain_for_case("two-mass", 400), ChainOptions(dt=0.002, transits=3))
    with pytest.raises(SimulationError, match="gnucap timed out after 0.3 s and was killed") as caught:
        run_engine(RunJob(spec.netlist, spec.vectors, spec.tstop, timeout=0.3, foreign=False), find_engine("gnucap"))
    assert caught.value.status == "timeout"
    assert "gnucap" not in descendants(os.getpid()).values() and temporary_entries() == before


@pytest.mark.ngspice
def test_a_missing_gnucap_is_exit_status_3_and_a_doctor_warning(capsys, monkeypatch, tmp_path: Path) -> None:
    import shutil

    folder = tmp_path / "bin"  # a PATH with ngspice and without gnucap
    folder.mkdir()
    ngspice = shutil.which("ngspice")
    assert ngspice is not None
    (folder / "ngspice").symlink_to(ngspice)
    monkeypatch.setenv("PATH", str(folder))
    status = main(["simulate", "--case", "two-mass", "--N", "20", "--dt", "0.1", "--engine", "gnucap"])
    err = capsys.readouterr().err
    assert status == 3 and "sudo apt-get install gnucap" in err and "Traceback" not in err
    assert main(["doctor"]) == 0
    out = capsys.readouterr().out
    assert "[warn] engine gnucap: SimulatorMissingError" in out and "[ok  ] engine ngspice" in out


def test_a_study_has_one_engine(tmp_path: Path) -> None:
    from lcchain.studies.plan import scene_sweep_plan

    scene = tmp_path / "s.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 16\n[analysis]\ndt = 0.1\n')
    with pytest.raises(ParameterError, match="one engine per study"):
        scene_sweep_plan(scene, [("analysis.engine", ["ngspice", "gnucap"])])
    assert scene_sweep_plan(scene, [("analysis.engine", ["gnucap"])]).engine == "gnucap"


@pytest.mark.ngspice
@pytest.mark.gnucap
def test_simulate_runs_one_netlist_in_both_engines_and_reports_their_difference(tmp_path, capsys) -> None:
    netlist = tmp_path / "kept.cir"
    argv = ["simulate", "--case", "perfect", "--N", "30", "--dt", "0.02", "--engine", "ngspice,gnucap",
            "--netlist-out", str(netlist), "--json"]
    assert main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert [e["engine"] for e in data["engines"]] == ["ngspice", "gnucap"]
    assert {e["netlist_sha256"] for e in data["engines"]} == {hashlib.sha256(netlist.read_bytes()).hexdigest()}
    difference = data["max_abs_difference"]["ngspice - gnucap"]
    errors = [e["max_abs_error"] for e in data["engines"]]
    # two independent integrators of one circuit: both meet the prediction, and they differ far less than either
    # differs from theory (their trapezoidal error is the same), yet not by nothing
    for engine in data["engines"]:
        assert engine["max_abs_error"] <= PREDICTION_FACTOR * engine["predicted_error"]
    assert 0 < difference < MAX_ENGINE_DIFFERENCE_FRACTION * min(errors)
    # a lossy chain has no predicted error: its table says so (it formatted None, a TypeError)
    assert main(["simulate", "--case", "two-mass", "--N", "6", "--dt", "0.02", "--engine", "ngspice,gnucap",
                 "--Q", "20"]) == 0
    assert all(line.split()[-1] == "none" for line in capsys.readouterr().out.splitlines()
               if line.startswith(("ngspice ", "gnucap ")))
    for bad, option in ((["--engine", "ngspice,ngspice"], "--engine"), (["--engine", "ngspice,spectre"], "--engine"),
                        (["--engine", "ngspice,gnucap", "--extrapolate", "2"], "--extrapolate"),
                        (["--engine", "ngspice,gnucap", "--plot", str(tmp_path / "p.png")], "--plot")):
        assert main(["simulate", "--case", "perfect", "--N", "10", "--dt", "0.05", *bad]) == 2
        assert option in capsys.readouterr().err
