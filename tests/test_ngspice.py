"""Tests of lcchain.spice against the real ngspice 39 (no mocks of the simulator)."""

from __future__ import annotations

import json
import math
import os
import random
import re
from pathlib import Path

import numpy as np
import pytest
from helpers.netlists import LADDER
from helpers.processes import temporary_entries
from helpers.tolerances import RTOL_WARNED_MEASURE

from lcchain.core.errors import ParameterError, SimulationError
from lcchain.spice import doctor as doctor_module
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice import batch
from lcchain.spice.ngspice.find import find_simulator, ngspice_version
from lcchain.spice.ngspice.raw import read_raw
from lcchain.spice.ngspice.runner import run
from lcchain.spice.result import TSTOP_RTOL, RunResult
from lcchain.spice.text import canonical_vector_name, logical_lines, parse_options

TSTOP = 7.7
KICK = 1.0
#: Perfect transfer time of the N=3 perfect chain, t = sqrt(3/2)*pi (paper, perfect chain with N=3).
T_TRANSFER = math.sqrt(1.5) * math.pi
#: Agreement of ngspice (trapezoidal, 1 ms step, reltol 1e-6) with the exact transfer.
RTOL_SPICE_TRANSFER = 1e-4
#: Timeout used to provoke a kill: far below the run time of the endless netlist below.
TIMEOUT_KILL_S = 0.5

ENDLESS = LADDER.replace(".tran 0.001 7.7 0 0.001 uic", ".tran 1e-7 1e6 0 1e-7 uic")


@pytest.fixture
def leaves_nothing_behind():
    """The run names no file: nothing new appears in the temporary folder."""
    before = temporary_entries()
    yield
    assert temporary_entries() - before == set()


@pytest.fixture(scope="module")
def batch_result() -> RunResult:
    return run(RunJob(LADDER, ["i(l1)", "i(l3)"], TSTOP))


# --------------------------------------------------------------------------- pure helpers


@pytest.mark.parametrize(
    ("written", "key"),
    [("i(L1)", "i(l1)"), ("l1#branch", "i(l1)"), ("L1#BRANCH", "i(l1)"), ("v(N3)", "v(n3)"), ("n3", "v(n3)"),
     ("time", "time"), ("@l1[i]", "@l1[i]")],
)
def test_canonical_vector_name(written: str, key: str) -> None:
    assert canonical_vector_name(written) == key


def test_parse_options_reads_every_options_line() -> None:
    text = "* t\n.OPTIONS method=trap reltol = 1e-6\n+ abstol=1e-12\n.opt noinit\n.option reltol=1e-7\n.end\n"
    assert parse_options(text) == {"method": "trap", "reltol": "1e-7", "abstol": "1e-12", "noinit": "true"}


def _options_of_every_line(text: str) -> dict[str, str]:
    """parse_options as it read every logical line (before it read the dot cards alone): the reference."""
    options: dict[str, str] = {}
    for _, line in logical_lines(text):
        match = re.match(r"^\s*\.opt(ion|ions)?\b(.*)$", line, re.IGNORECASE)
        if match:
            for token in re.sub(r"\s*=\s*", "=", match.group(2).strip()).split():
                key, sep, value = token.partition("=")
                options[key.lower()] = value if sep else "true"
    return options


def test_parse_options_reads_what_a_look_at_every_line_reads() -> None:
    """Only dot cards are read: lines joined by "+", an options card as the title, indented, continued by a line
    that starts with ".", an element continued by "+.opt", a text without a final LF: as every line read."""
    pieces = [".options a=1", "  .OPT b = 2", "\t.option c", "+ d=4", "+.opt e=5", "R1 1 0 1k", "+ .opt f=6",
              ".optionsx g=7", ".opt", "* .opt h=8", "", ".tran 1 2", "+", ".options reltol=1e-3 a=9", " \t", "  .opt\tk=1 "]
    rng = random.Random(35)
    for _ in range(4000):
        text = "\n".join(rng.choice(pieces) for _ in range(rng.randrange(1, 8))) + rng.choice(["", "\n"])
        assert parse_options(text) == _options_of_every_line(text), text
    with pytest.raises(ParameterError):
        parse_options("* t\r\n.options a=1\n")


@pytest.mark.parametrize("line", [".control", "  .CONTROL", ".endc", "shell rm -rf ~", "SHELL echo",
                                  ".include /etc/passwd", ".lib /etc/passwd x", ".inc 'x.cir'", ".controls"])
def test_lines_outside_the_allow_list_are_refused_by_both_backends(line: str) -> None:
    netlist = LADDER.replace(".end\n", f"{line}\n.end\n")
    for backend in ("batch", "shared"):
        with pytest.raises(ParameterError, match="netlist: line 12"):
            run(RunJob(netlist, ["i(l1)"], TSTOP), backend=backend)


def test_bad_arguments_are_parameter_errors() -> None:
    with pytest.raises(ParameterError, match="backend"):
        run(RunJob(LADDER, ["i(l1)"], TSTOP), backend="spectre")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="tstop"):
        run(RunJob(LADDER, ["i(l1)"], -1.0))
    with pytest.raises(ParameterError, match="vectors"):
        run(RunJob(LADDER, "i(l1)", TSTOP))


def _raw_file(tmp_path: Path, flags: str, points: int, values: np.ndarray) -> Path:
    header = (
        "Title: t\nDate: now\nPlotname: Transient Analysis\n"
        f"Flags: {flags}\nNo. Variables: 2\nNo. Points: {points}\n"
        "Variables:\n\t0\ttime\ttime\n\t1\tl1#branch\tcurrent\nBinary:\n"
    )
    path = tmp_path / "x.raw"
    path.write_bytes(header.encode() + values.astype(np.float64).tobytes())
    return path


def test_read_raw_parses_binary_and_normalises_names(tmp_path: Path) -> None:
    path = _raw_file(tmp_path, "real", 3, np.array([0.0, 1.0, 0.5, 2.0, 1.0, 3.0]))
    columns = read_raw(path)
    assert np.array_equal(columns["time"], [0.0, 0.5, 1.0])
    assert np.array_equal(columns["i(l1)"], [1.0, 2.0, 3.0])


def test_read_raw_refuses_complex_and_truncated(tmp_path: Path) -> None:
    with pytest.raises(SimulationError, match="complex"):
        read_raw(_raw_file(tmp_path, "complex", 1, np.zeros(4)))
    with pytest.raises(SimulationError, match="truncated"):
        read_raw(_raw_file(tmp_path, "real", 5, np.zeros(4)))


# --------------------------------------------------------------------------- real runs


@pytest.mark.ngspice
def test_batch_run_returns_vectors_and_metadata(batch_result: RunResult) -> None:
    result = batch_result
    assert set(result.vectors) == {"i(l1)", "i(l3)"}
    assert result.points == result.time.size > 0
    assert all(v.shape == result.time.shape for v in result.vectors.values())
    assert math.isclose(result.time[-1], TSTOP, rel_tol=TSTOP_RTOL)
    assert not result.time.flags.writeable
    assert not any(v.flags.writeable for v in result.vectors.values())
    assert result.backend == "batch"
    assert result.ngspice_version == ngspice_version()
    assert result.options == {"method": "trap", "reltol": "1e-6", "abstol": "1e-12", "chgtol": "1e-20", "maxord": "2"}
    meta = result.metadata()
    assert json.loads(json.dumps(meta)) == meta
    assert {"ngspice_version", "netlist_sha256", "options", "wall_s", "backend", "points", "log"} <= set(meta)
    assert len(meta["netlist_sha256"]) == 64
    assert meta["wall_s"] > 0


@pytest.mark.ngspice
def test_batch_run_transfers_the_kick_perfectly(batch_result: RunResult) -> None:
    # Perfect N=3 chain: loop 3 carries the whole kick at T, loop 1 has it back at 2T.
    t, i1, i3 = batch_result.time, batch_result.vectors["i(l1)"], batch_result.vectors["i(l3)"]
    assert np.interp(T_TRANSFER, t, i3) / KICK == pytest.approx(1.0, rel=RTOL_SPICE_TRANSFER)
    assert np.interp(2 * T_TRANSFER, t, i1) / KICK == pytest.approx(1.0, rel=RTOL_SPICE_TRANSFER)
    assert np.max(np.abs(i3)) / KICK == pytest.approx(1.0, rel=RTOL_SPICE_TRANSFER)


@pytest.mark.ngspice
def test_shared_backend_is_bit_identical_to_batch(batch_result: RunResult) -> None:
    shared_simulator = find_simulator("shared")
    results = [run(RunJob(LADDER, ["i(l1)", "i(l3)"], TSTOP), shared_simulator) for _ in range(3)]
    for shared in results:  # repeated runs leak no state: identical every time
        assert shared.backend == "shared"
        assert shared.ngspice_version == batch_result.ngspice_version
        assert np.array_equal(shared.time, batch_result.time)
        assert shared.vectors.keys() == batch_result.vectors.keys()
        for name, values in batch_result.vectors.items():
            assert np.array_equal(shared.vectors[name], values), name


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "shared"])
def test_both_save_syntaxes_give_the_same_keys(backend: str) -> None:
    netlist = LADDER.replace(".save i(l1) i(l3)", ".save l1#branch v(n1) I(L3)")
    seen: list[float] = []
    result = run(RunJob(netlist, ["l1#branch", "v(n1)", "i(l3)"], TSTOP), backend=backend, progress=seen.append)
    assert set(result.vectors) == {"i(l1)", "v(n1)", "i(l3)"}
    assert seen == [0.0, 1.0]


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "shared"])
@pytest.mark.parametrize(
    ("broken", "said"),
    [
        (LADDER.replace("C12 n1 0 1.0", "Q12 n1 0 1.0"), "could not find a valid modelname"),
        (LADDER.replace("L2 n1 n2 1.0", "L2 n1 n2 1.0.0"), "can't find model"),
        (LADDER.replace("0.001 uic", "0.001 uicx"), "unknown parameter on .tran"),
        (LADDER.replace("C12 n1 0 1.0", "C12 n1 0 1.0\nC99 n7 n8 1.0"), "Timestep too small"),
    ],
    ids=["unknown-element", "bad-value", "bad-tran", "floating-node"],
)
def test_bad_netlist_raises_with_ngspice_message(backend: str, broken: str, said: str, leaves_nothing_behind) -> None:
    # trusted: what ngspice itself says (a Q element would not get past the allow-list)
    with pytest.raises(SimulationError) as info:
        run(RunJob(broken, ["i(l1)", "i(l3)"], TSTOP, trusted=True), backend=backend)
    assert said in str(info.value)
    assert info.value.status == "failed" and info.value.reason and said in info.value.reason + info.value.log_tail


WARNED: dict[str, tuple[str, float | None]] = {
    # a bare .param name as a value: ngspice warns "can't find model 'c0'", and uses the parameter
    "parameter": ("bare parameter\n.param c0 = 1u\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in a 1k\nC1 a 0 c0\n"
                  ".tran 2u 1m 0 2u\n.meas tran va find v(a) at=0.5m\n.end\n", None),
    # a node between two capacitors: "Warning: singular matrix", then gmin stepping finds the operating point
    "capacitive node": ("capacitive node\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nC1 a 0 1u\nC2 a in 1u\n"
                        ".tran 2u 1m 0 2u\n.meas tran va find v(a) at=0.5m\n.end\n", 0.5),
}


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "warm"])
@pytest.mark.parametrize("case", WARNED)
def test_a_run_ngspice_warned_of_and_finished_stands(backend: str, case: str, leaves_nothing_behind) -> None:
    """ngspice's warnings it recovers from are no failure: a batch failed these finished runs, losing their
    waveforms and their .meas values (a broken value, 'L2 a b 1.0.0', still fails: test_bad_netlist_...)."""
    from lcchain.spice.ngspice import warm

    netlist, expected = WARNED[case]
    simulator = find_simulator("batch")
    if backend == "warm":
        simulator = warm.warm_simulator(simulator)
    try:
        value, reason = run(RunJob(netlist, ["v(a)"], 1e-3), simulator).measurements["va"]
        if expected is None:  # the parameter's value, as the same netlist with {c0} gives it
            braced = RunJob(netlist.replace("a 0 c0", "a 0 {c0}"), ["v(a)"], 1e-3)
            expected, _ = run(braced, simulator).measurements["va"]
    finally:
        warm.close_workers()
    assert value == pytest.approx(expected, rel=RTOL_WARNED_MEASURE) and not reason


@pytest.mark.ngspice
def test_an_interpolated_run_reads_the_same_on_both_transports(leaves_nothing_behind) -> None:
    """With .options interp, ngspice 39's -r raw file holds 16 points more than its header counts, and the run
    failed ("no 'Binary:' section"): its raw file is written from what ngspice holds, as a .meas run's is."""
    from lcchain.spice.ngspice import warm

    netlist = "RC\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in a 1k\nC1 a 0 1n\n.tran 2u 100u\n.options interp\n.end\n"
    batch = find_simulator("batch")
    try:
        results = [run(RunJob(netlist, ["v(a)"], 1e-4), simulator) for simulator in (batch, warm.warm_simulator(batch))]
    finally:
        warm.close_workers()
    for result in results:
        assert result.points == 51 and result.time[0] == 0.0 and result.time[-1] == pytest.approx(1e-4)
    assert (results[0].vectors["v(a)"] == results[1].vectors["v(a)"]).all()


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "shared"])
def test_vector_not_saved_is_named(backend: str, leaves_nothing_behind) -> None:
    with pytest.raises(SimulationError, match=re.escape("i(l2)")):
        run(RunJob(LADDER, ["i(l1)", "i(l2)"], TSTOP), backend=backend)


@pytest.mark.ngspice
def test_wrong_tstop_is_detected(leaves_nothing_behind) -> None:
    with pytest.raises(SimulationError, match="tstop"):
        run(RunJob(LADDER, ["i(l1)"], 2 * TSTOP))


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "shared"])
def test_timeout_kills_the_simulator(backend: str, leaves_nothing_behind) -> None:
    with pytest.raises(SimulationError, match="timed out") as info:
        run(RunJob(ENDLESS, ["i(l1)"], 1e6, timeout=TIMEOUT_KILL_S), backend=backend)
    assert info.value.status == "timeout"


@pytest.mark.ngspice
def test_doctor_is_all_ok_here() -> None:
    checks = doctor_module.doctor()
    assert [c.name for c in checks] == [
        "ngspice executable", "batch run", "sandbox for foreign netlists", "ngspice shared library", "PySpice",
        "shared run", "engine ngspice", "engine gnucap"]
    ngspice = [c for c in checks if c.name != "engine gnucap"]  # gnucap's line: tests/test_engines.py
    assert all(c.ok for c in ngspice), [c for c in ngspice if not c.ok]
    assert [c.name for c in checks if c.required] == ["ngspice executable", "batch run", "engine ngspice"]


@pytest.mark.ngspice
def test_batch_run_reports_its_progress(monkeypatch) -> None:
    # ngspice -b writes "Reference value : t" to stderr as it goes; run() turns it into fractions of tstop.
    from lcchain.circuit.netlist import ChainNetlist, make_netlist
    from lcchain.theory.cases import chain_for_case

    monkeypatch.setattr(batch, "PROGRESS_INTERVAL", 0.02)
    text, ladder, options = make_netlist(chain_for_case("two-mass", 300), ChainNetlist(dt=0.02, transits=1))
    seen: list[float] = []
    run(RunJob(text, ["i(l1)", "i(l300)"], options.tstop * ladder.time_unit), progress=seen.append)
    assert seen[0] == 0.0 and seen[-1] == 1.0
    assert any(0.0 < f < 1.0 for f in seen), seen
    assert seen == sorted(seen)


def test_a_raw_file_missing_on_a_full_temporary_folder_says_so(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """ngspice writes its raw file to an unnamed file of the temporary folder: when that file system is (nearly)
    full, the run's failure says where to make room (the statistics of a full one stand in for it: a test mounts
    nothing)."""
    with (tmp_path / "raw").open("wb") as raw:
        assert batch._full(raw.fileno()) == ""  # the test's own folder has room
        full = os.statvfs_result((4096, 4096, 100, 0, 0, 10, 0, 0, 0, 255))
        monkeypatch.setattr(batch.os, "fstatvfs", lambda fd: full)
        said = batch._full(raw.fileno())
    assert said.startswith(": the temporary folder ") and "(TMPDIR) has 0 B free" in said and "make room" in said
