"""A foreign netlist's ``.param`` and ``.meas`` cards (issue 31): run in the real ngspice, their values stored
and shown by ``lcchain results`` (table, CSV, JSON, --summary --metric NAME), to_dataframe and to_xarray.

Expected values are the closed forms of a first-order RC low-pass (any circuits text, e.g. Horowitz & Hill,
*The Art of Electronics*, 3rd ed., sec. 1.4): after a unit step v(t) = 1 - exp(-t / RC), so the 10-90 % rise
time is RC ln 9 and v(RC) = 1 - 1/e; in the AC sweep |H(f)| = 1 / sqrt(1 + (2 pi f RC)^2), so |H| falls to
-3 dB at f = sqrt(10^0.3 - 1) / (2 pi RC).
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

import pytest
from helpers.tolerances import RTOL_MEASURE_AC, RTOL_MEASURE_COARSE, RTOL_MEASURE_TRAN

from lcchain.cli import main
from lcchain.spice.foreign import allowed_netlist
from lcchain.studies.store import Store

pytestmark = pytest.mark.ngspice

R, C = 1e3, 2e-6  # ohm, farad: RC = 2 ms
RC = R * C

# .PARAMS and .param_c: ngspice 39 reads every word that starts with .param as one (the allow-list mirrors it)
TRANSIENT = """\
RC step: rise time and a value at a time
.param rv = 1k
.PARAMS half = {rv / 2}
.param_c cv = {2 * 1u * (half * 2) / rv}
V1 in 0 PULSE(0 1 0 1n 1n 1 2)
R1 in out {rv}
C1 out 0 {cv}
.tran 1u 10m
.meas tran trise trig v(out) val=0.1 rise=1 targ v(out) val=0.9 rise=1
.measure TRAN v_at_rc FIND v(out) AT={rv * cv}
.meas tran too_late find v(out) at=20m
.end
"""

SWEEP = """\
RC low-pass: the -3 dB frequency
.param rv = 1k
.param cv = 2u
V1 in 0 dc 0 ac 1
R1 in out {rv}
C1 out 0 {cv}
.ac dec 1000 1 100k
.meas ac f3db when vdb(out)=-3
.meas ac gain_1k find vdb(out) at=1k
.end
"""


def _results(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    capsys.readouterr()
    assert main(argv) == 0
    return capsys.readouterr().out


@pytest.fixture(scope="module")
def store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One batch of both netlists, run once for the tests below."""
    folder = tmp_path_factory.mktemp("meas")
    (folder / "step.cir").write_text(TRANSIENT, encoding="utf-8")
    (folder / "sweep.cir").write_text(SWEEP, encoding="utf-8")
    path = folder / "runs.sqlite"
    assert main(["batch", str(folder / "step.cir"), str(folder / "sweep.cir"), "--store", str(path), "--json"]) == 0
    return path


def test_the_checked_text_keeps_every_param_and_meas_card() -> None:
    assert allowed_netlist(TRANSIENT, "step.cir", None) == TRANSIENT
    assert allowed_netlist(SWEEP, "sweep.cir", None) == SWEEP


def test_meas_values_match_the_closed_forms_and_a_failed_one_is_missing_with_its_reason(store: Path) -> None:
    with Store(store, "read") as opened:
        step, sweep = opened.runs()
    assert step.status == sweep.status == "ok"
    assert step.measurements["trise"] == pytest.approx(RC * math.log(9.0), rel=RTOL_MEASURE_TRAN)
    assert step.measurements["v_at_rc"] == pytest.approx(1.0 - math.exp(-1.0), rel=RTOL_MEASURE_TRAN)
    assert step.measurements["too_late"] is None
    assert "out of interval" in step.measure_reasons["too_late"]
    corner = math.sqrt(10.0 ** 0.3 - 1.0) / (2.0 * math.pi * RC)
    assert sweep.measurements["f3db"] == pytest.approx(corner, rel=RTOL_MEASURE_AC)
    gain = -10.0 * math.log10(1.0 + (2.0 * math.pi * 1e3 * RC) ** 2)
    assert sweep.measurements["gain_1k"] == pytest.approx(gain, rel=RTOL_MEASURE_AC)
    assert sweep.measure_reasons == {}


def test_results_show_the_measurements_in_the_table_csv_and_json(store: Path, capsys) -> None:
    table = _results(["results", str(store)], capsys)
    head = table.splitlines()[1].split()
    assert {"trise", "v_at_rc", "too_late", "f3db", "gain_1k"} <= set(head)
    assert "too_late: ngspice: find(AT) : out of interval" in table
    rows = list(csv.DictReader(io.StringIO(_results(["results", str(store), "--csv"], capsys))))
    assert float(rows[0]["trise"]) == pytest.approx(RC * math.log(9.0), rel=RTOL_MEASURE_TRAN)
    assert rows[0]["too_late"] == "" and rows[1]["trise"] == ""
    shown = json.loads(_results(["results", str(store), "--json"], capsys))
    assert shown[0]["measurements"]["too_late"] is None
    assert "out of interval" in shown[0]["measure_reasons"]["too_late"]
    assert shown[1]["measurements"]["f3db"] == pytest.approx(
        math.sqrt(10.0 ** 0.3 - 1.0) / (2.0 * math.pi * RC), rel=RTOL_MEASURE_AC)


def test_a_measurement_name_is_a_metric_of_results_summary(store: Path, capsys) -> None:
    groups = json.loads(_results(["results", str(store), "--summary", "--metric", "trise", "--json"], capsys))
    step = next(group for group in groups if group["params"]["netlist"].endswith("step.cir"))
    assert step["n"] == 1
    assert step["mean"] == pytest.approx(RC * math.log(9.0), rel=RTOL_MEASURE_TRAN)
    assert "trise" in _results(["results", str(store), "--summary", "--metric", "trise"], capsys)
    capsys.readouterr()
    assert main(["results", str(store), "--summary", "--metric", "no_such"]) == 2
    assert "trise" in capsys.readouterr().err  # the refusal lists the measurements there are


def test_to_dataframe_and_to_xarray_have_one_column_per_measurement(store: Path) -> None:
    pytest.importorskip("pandas")
    pytest.importorskip("xarray")
    with Store(store, "read") as opened:
        frame = opened.to_dataframe()
        dataset = opened.to_xarray()
    for name in ("trise", "v_at_rc", "too_late", "f3db", "gain_1k"):
        assert name in frame.columns and name in dataset.data_vars
    assert frame["trise"].iloc[0] == pytest.approx(RC * math.log(9.0), rel=RTOL_MEASURE_TRAN)
    assert math.isnan(frame["too_late"].iloc[0]) and math.isnan(frame["f3db"].iloc[0])


def test_a_measured_run_is_priced_with_its_vectors_in_ngspice_memory() -> None:
    from lcchain.spice.foreign import MEASURED_BYTES_FACTOR, analysis_of, foreign_price

    plain = "\n".join(line for line in TRANSIENT.split("\n") if not line.lower().startswith(".meas")) + "\n"
    measured, unmeasured = (foreign_price(text, analysis_of(text, "step.cir"), 0) for text in (TRANSIENT, plain))
    kept = MEASURED_BYTES_FACTOR * unmeasured.output_bytes
    assert kept > 0
    # the .meas lines' own text costs a little besides (lcchain.spice.pricing: bytes of text)
    assert measured.simulator_memory >= unmeasured.simulator_memory + kept
    assert measured.memory >= unmeasured.memory + kept


def test_a_netlist_run_as_it_is_is_measured_too(tmp_path: Path) -> None:
    """--allow-control skips the allow-list, not the control block that makes ngspice measure."""
    (tmp_path / "step.cir").write_text(TRANSIENT, encoding="utf-8")
    store = tmp_path / "runs.sqlite"
    assert main(["batch", str(tmp_path / "step.cir"), "--store", str(store), "--allow-control", "--json"]) == 0
    with Store(store, "read") as opened:
        (run,) = opened.runs()
    assert run.measurements["trise"] == pytest.approx(RC * math.log(9.0), rel=RTOL_MEASURE_TRAN)


#: A measurement of a vector the circuit does not have, beside one it can make: ngspice 39 says "Error: no such
#: vector as v(nowhere)." and ".meas tran ghost ... failed!", runs on and exits 0.
GHOST = """\
RC step, and a measurement of a node it does not have
V1 in 0 PULSE(0 1 0 1n 1n 1 2)
R1 in out 1k
C1 out 0 2u
.tran 1u 10m
.meas tran ghost find v(nowhere) at=1m
.meas tran v_at_rc find v(out) at=2m
.end
"""


@pytest.mark.parametrize("transport", ["process", "warm"])
def test_a_measurement_named_error_is_a_value_not_a_failure(tmp_path: Path, transport: str) -> None:
    """ngspice prints it as "error = 6.321206e-01", which a line of ngspice's own errors also starts with."""
    netlist = GHOST.replace(".meas tran ghost find v(nowhere) at=1m", ".meas tran error find v(out) at=2m")
    (tmp_path / "named.cir").write_text(netlist, encoding="utf-8")
    path = tmp_path / "runs.sqlite"
    assert main(["batch", str(tmp_path / "named.cir"), "--store", str(path), "--transport", transport]) == 0
    with Store(path, "read") as opened:
        (run,) = opened.runs()
    assert run.status == "ok"
    assert run.measurements["error"] == pytest.approx(1.0 - math.exp(-1.0), rel=RTOL_MEASURE_TRAN)


def test_a_measurement_of_a_node_named_as_an_element_line_names_it(tmp_path: Path) -> None:
    """Node names hold - + : on element lines, in .save and in ngspice's .meas: a .meas of v(out-a) was refused."""
    netlist = ("odd nodes\nV1 in+ 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in+ n.1 100\nR2 n.1 out-a 100\nC1 out-a 0 1u\n"
               ".tran 2u 1m\n.meas tran va find v(out-a) at=1m\n.meas tran vb find v(in+) at=1m\n.end\n")
    (tmp_path / "odd.cir").write_text(netlist, encoding="utf-8")
    path = tmp_path / "runs.sqlite"
    assert main(["batch", str(tmp_path / "odd.cir"), "--store", str(path)]) == 0
    with Store(path, "read") as opened:
        (run,) = opened.runs()
    assert run.measurements["vb"] == pytest.approx(1.0, rel=RTOL_MEASURE_TRAN)
    # RC = 0.2 ms; a step of 2 us through the source's 1 us edge: 1.7e-5 of the value (what is tested is that
    # the measurement is made, of that node)
    assert run.measurements["va"] == pytest.approx(1.0 - math.exp(-5.0), rel=RTOL_MEASURE_COARSE)


@pytest.mark.parametrize("transport", ["process", "warm"])
def test_ngspices_line_numbers_are_the_netlists_with_a_measurement(tmp_path: Path, transport: str) -> None:
    """The control block that runs a .meas goes before .end: after the title it moved ngspice's "Error on line 3"
    to line 8."""
    netlist = ("bad line 3\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in a 1k * trailing star\nC1 a 0 1u\n"
               ".tran 2u 1m 0 2u\n.meas tran va find v(a) at=0.5m\n.end\n")
    (tmp_path / "bad.cir").write_text(netlist, encoding="utf-8")
    path = tmp_path / "runs.sqlite"
    assert main(["batch", str(tmp_path / "bad.cir"), "--store", str(path), "--transport", transport]) == 1
    with Store(path, "read") as opened:
        (run,) = opened.runs()
    assert run.status == "failed" and "line 3 " in run.reason, run.reason


@pytest.mark.parametrize("transport", ["process", "warm"])
def test_a_measurement_of_a_missing_vector_is_missing_and_the_run_stands(tmp_path: Path, transport: str) -> None:
    """Its "Error:" line is the measurement's reason, not the run's failure: the run, its waveform and its other
    measurements are kept, whichever transport ran it."""
    (tmp_path / "ghost.cir").write_text(GHOST, encoding="utf-8")
    path = tmp_path / "runs.sqlite"
    assert main(["batch", str(tmp_path / "ghost.cir"), "--store", str(path), "--transport", transport]) == 0
    with Store(path, "read") as opened:
        (run,) = opened.runs()
    assert run.status == "ok" and run.points is not None and run.points > 0
    assert run.measurements["ghost"] is None
    assert "no such vector as v(nowhere)" in run.measure_reasons["ghost"]
    assert run.measurements["v_at_rc"] == pytest.approx(1.0 - math.exp(-1.0), rel=RTOL_MEASURE_TRAN)


def test_a_measurement_named_as_a_study_metric_is_summarised_in_a_batch(tmp_path: Path,
                                                                        capsys: pytest.CaptureFixture[str]) -> None:
    """A batch's runs give no first-arrival peak of their own: --metric peak is its netlists' .meas peak there."""
    for k, resistance in enumerate(("1k", "2k")):
        (tmp_path / f"n{k}.cir").write_text(GHOST.replace(".meas tran ghost find v(nowhere) at=1m",
                                                          ".meas tran peak max v(out)").replace("1k", resistance))
    store = str(tmp_path / "s.sqlite")
    assert main(["batch", str(tmp_path / "n0.cir"), str(tmp_path / "n1.cir"), "--store", store]) == 0
    capsys.readouterr()
    assert main(["results", store, "--summary", "--metric", "peak"]) == 0
    said = capsys.readouterr().out
    assert "the netlists' measurement peak" in said and "first-arrival" not in said
    assert main(["results", store, "--summary", "--metric", "peak", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)
    # a 10 ms step through RC = 2 and 4 ms: the largest v(out) is 1 - exp(-10 / RC)
    assert sorted(g["max"] for g in groups) == pytest.approx(sorted(1.0 - math.exp(-10.0 / rc) for rc in (2.0, 4.0)),
                                                             rel=RTOL_MEASURE_TRAN)
