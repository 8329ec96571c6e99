"""A catalogue of bad and hostile inputs, each refused the same way (issue 10).

Every case runs the command line in this process, in a folder of its own:
it must exit 2 (bad input; 1 for a run that failed, 3 for a missing
simulator) with one line on stderr naming the option or key, the value and
what is allowed, print no traceback, write no output file, leave nothing in
the temporary folder, and leave no simulator running.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from helpers.catalogue import Case, run_case
from helpers.tolerances import RTOL_FLOAT32

import lcchain
from lcchain.cli import main

ROOT = Path(__file__).resolve().parent.parent
CHAIN = {"masses": [1.5, 1.0, 1.5], "springs": [0, 1, 1, 0]}
SCENE = '[chain]\ncase = "two-mass"\nN = 10\n'


def sparse(name: str, size: int = 65 * 2**20) -> Callable[[Path], None]:
    """A file of ``size`` bytes on paper and nothing on disk."""
    def make(folder: Path) -> None:
        with open(folder / name, "wb") as handle:
            handle.truncate(size)
    return make


def _chain(**changes: object) -> str:
    return json.dumps({**CHAIN, **changes})


CASES: dict[str, Case] = {
    # ------------------------------------------------------------------ command-line arguments
    "N below 3": Case(["design", "--case", "two-mass", "--N", "2"], ["--N = 2", "an integer from 3"]),
    "unknown design case": Case(["design", "--case", "three-mass", "--N", "10"], ["--case", "three-mass"]),
    "N not a number": Case(["design", "--case", "two-mass", "--N", "ten"], ["--N", "ten"]),
    "design beyond the time budget": Case(["design", "--case", "two-mass", "--N", "10000000", "--max-time", "10min"],
                                          ["--N = 10000000", "15 min", "10 min"]),
    "design beyond the documented maximum": Case(["design", "--case", "one-mass", "--N", "20000000"],
                                                 ["--N = 20000000", "10000000"]),
    "table N list with a word": Case(["table", "--case", "one-mass", "--N", "3,x"], ["--N", "3,x"]),
    "table N list with 2": Case(["table", "--case", "one-mass", "--N", "3,2"], ["--N = 2"]),
    "perfect N 2": Case(["netlist", "--case", "perfect", "--N", "2"], ["--N = 2"]),
    "perfect cradle too long": Case(["design", "--case", "perfect", "--N", "20001"], ["--N = 20001", "20000"]),
    "perfect walls negative": Case(["design", "--case", "perfect", "--N", "10", "--walls", "-1"],
                                   ["--walls = -1", "J >= 0"]),
    "walls on an optimum": Case(["design", "--case", "two-mass", "--N", "10", "--walls", "1"],
                                ["--walls = 1", "--case perfect"]),
    "walls on a uniform netlist": Case(["netlist", "--case", "uniform-free", "--N", "10", "--walls", "2"],
                                       ["--walls = 2", "--case perfect"]),
    "perfect walls too long": Case(["netlist", "--case", "perfect", "--N", "20001", "--walls", "1"],
                                   ["--N = 20001", "20000"]),
    "perfect walls beyond the time budget": Case(["design", "--case", "perfect", "--N", "20000", "--walls", "1",
                                                  "--max-time", "10s"], ["--N = 20000", "--max-time"]),
    "title starting with .control": Case(["netlist", "--case", "uniform-free", "--N", "10", "--title", ".control"],
                                         ["--title", ".control", "dot-command"]),
    "title over two lines": Case(["netlist", "--case", "uniform-free", "--N", "10", "--title", "a\n.control"],
                                 ["--title", "newline"]),
    "title with a control character": Case(["netlist", "--case", "uniform-free", "--N", "10", "--title", "a\x1bb"],
                                           ["--title"]),
    "dt zero": Case(["netlist", "--case", "uniform-free", "--N", "10", "--dt", "0"], ["--dt = 0.0", "0 < dt <= 1"]),
    "dt above 1": Case(["netlist", "--case", "uniform-free", "--N", "10", "--dt", "2"], ["--dt = 2.0"]),
    "dt nan": Case(["netlist", "--case", "uniform-free", "--N", "10", "--dt", "nan"], ["--dt", "finite"]),
    "dt a word": Case(["netlist", "--case", "uniform-free", "--N", "10", "--dt", "small"], ["--dt", "small"]),
    "L0 negative": Case(["netlist", "--case", "uniform-free", "--N", "10", "--L0", "-1"], ["--L0 = -1.0", "> 0"]),
    "L0 huge": Case(["simulate", "--case", "perfect", "--N", "4", "--L0", "1e30"], ["--L0 = 1e+30", "time unit"]),
    "C0 tiny": Case(["simulate", "--case", "perfect", "--N", "4", "--C0", "1e-40"], ["--C0 = 1e-40", "time unit"]),
    "missing N": Case(["simulate", "--case", "uniform-free"], ["--N", "--case and --N"]),
    "missing case": Case(["simulate", "--N", "10"], ["--case", "--case and --N"]),
    "unknown command": Case(["frobnicate"], ["invalid choice"]),
    "dt 1e-9": Case(["simulate", "--case", "perfect", "--N", "4", "--dt", "1e-9"],
                    ["--dt = 1e-09", "TiB", "8 GiB", "--max-memory"]),
    "accuracy 1e-300": Case(["simulate", "--case", "perfect", "--N", "4", "--accuracy", "1e-300"],
                            ["--accuracy = 1e-300", ">= 1e-09"]),
    "accuracy 2": Case(["simulate", "--case", "perfect", "--N", "4", "--accuracy", "2"], ["--accuracy = 2.0"]),
    "accuracy and dt": Case(["simulate", "--case", "perfect", "--N", "4", "--accuracy", "0.01", "--dt", "0.05"],
                            ["--accuracy", "either --dt or --accuracy"]),
    "transits 0": Case(["simulate", "--case", "perfect", "--N", "4", "--transits", "0"], ["--transits = 0"]),
    "transits 1001": Case(["simulate", "--case", "perfect", "--N", "4", "--transits", "1001"],
                          ["--transits = 1001", "1000"]),
    # --dt was not typed: the refusal names the chain the user gave, at the default step
    "a run beyond the time budget": Case(["simulate", "--case", "two-mass", "--N", "1000", "--transits", "1000"],
                                         ["--N = 1000", "default step --dt 0.05", "1 h"]),
    "a run beyond the time budget at a typed step": Case(["simulate", "--case", "two-mass", "--N", "1000",
                                                          "--transits", "1000", "--dt", "0.05"],
                                                         ["--dt = 0.05", "1 h"]),
    "max memory not a size": Case(["simulate", "--case", "perfect", "--N", "4", "--max-memory", "1.5Q"],
                                  ["--max-memory", "1.5Q"]),
    "max time not a duration": Case(["simulate", "--case", "perfect", "--N", "4", "--max-time", "forever"],
                                    ["--max-time", "forever"]),
    "N beyond the circuit maximum": Case(["simulate", "--case", "uniform-free", "--N", "200000"],
                                         ["--N = 200000", "100000"]),
    "backend unknown": Case(["simulate", "--case", "perfect", "--N", "4", "--backend", "spectre"], ["--backend"]),
    "method unknown": Case(["simulate", "--case", "perfect", "--N", "4", "--method", "euler"], ["--method"]),
    "excitation pulse on simulate": Case(["simulate", "--case", "perfect", "--N", "4", "--excitation", "pulse"],
                                         ["--excitation"]),
    # ------------------------------------------------------------------ chain files
    "chain with case": Case(["simulate", "--chain", "c.json", "--case", "perfect"], ["--case", "--chain"],
                            files={"c.json": _chain()}),
    "chain with N": Case(["netlist", "--chain", "c.json", "--N", "4"], ["--N = 4", "--chain"],
                         files={"c.json": _chain()}),
    "chain file missing": Case(["netlist", "--chain", "missing.json"], ["--chain", "missing.json"]),
    "chain file not JSON": Case(["netlist", "--chain", "c.json"], ["--chain", "valid JSON"], files={"c.json": "{no"}),
    "chain file empty": Case(["netlist", "--chain", "c.json"], ["--chain", "valid JSON"], files={"c.json": ""}),
    "chain file not UTF-8": Case(["netlist", "--chain", "c.json"], ["--chain", "UTF-8"],
                                 files={"c.json": '{"masses": [1, 1, 1], "springs": [0, 1, 1, 0], "name": "\xe9"}'
                                        .encode("latin-1")}),
    "chain file huge": Case(["netlist", "--chain", "big.json"], ["--chain", "64 MiB"], make=sparse("big.json")),
    "chain file a list": Case(["netlist", "--chain", "c.json"], ["chain", "an object"], files={"c.json": "[1, 2]"}),
    "chain negative mass": Case(["netlist", "--chain", "c.json"], ["masses[2]", "> 0"],
                                files={"c.json": _chain(masses=[1, 1, -1])}),
    "chain inner spring zero": Case(["netlist", "--chain", "c.json"], ["springs[1]", "inner spring"],
                                    files={"c.json": _chain(springs=[0, 0, 1, 0])}),
    "chain spring count": Case(["netlist", "--chain", "c.json"], ["springs", "N+1"],
                               files={"c.json": _chain(springs=[0, 1, 0])}),
    "chain masses as text": Case(["netlist", "--chain", "c.json"], ["masses"],
                                 files={"c.json": _chain(masses=["1", 1, 1])}),
    "chain masses as booleans": Case(["netlist", "--chain", "c.json"], ["masses"],
                                     files={"c.json": _chain(masses=[True, True, True])}),
    "chain unknown key": Case(["netlist", "--chain", "c.json"], ["mass", "only the keys"],
                              files={"c.json": _chain(mass=[1])}),
    "chain beyond the circuit maximum": Case(["netlist", "--chain", "c.json"], ["--chain", "100000 masses"],
                                             files={"c.json": json.dumps({"masses": [1.0] * 100_001,
                                                                          "springs": [0.0] + [1.0] * 100_000 + [0.0]})}),
    # ------------------------------------------------------------------ output paths
    "plot not a figure name": Case(["simulate", "--case", "perfect", "--N", "4", "--plot", "p.txt"],
                                   ["--plot", "p.txt", ".png"]),
    "plot in /proc": Case(["simulate", "--case", "perfect", "--N", "4", "--plot", "/proc/x.png"],
                          ["--plot", "/proc/x.png", "writable"]),
    "plot a FIFO without a figure name": Case(["simulate", "--case", "perfect", "--N", "4", "--plot", "p"],
                                              ["--plot", "'p'", ".png"], make=lambda here: os.mkfifo(here / "p")),
    "plot in a missing folder": Case(["simulate", "--case", "perfect", "--N", "4", "--plot", "no/x.png"],
                                     ["--plot", "does not exist"]),
    "plot is a folder": Case(["simulate", "--case", "perfect", "--N", "4", "--plot", "d.png"],
                             ["--plot", "not a folder"], files={"d.png/keep": ""}),
    "netlist-out is a folder": Case(["simulate", "--case", "perfect", "--N", "4", "--netlist-out", "d"],
                                    ["--netlist-out", "not a folder"], files={"d/keep": ""}),
    "waveform-out in a missing folder": Case(["simulate", "--case", "perfect", "--N", "4", "--waveform-out",
                                              "no/w.csv"], ["--waveform-out", "does not exist"]),
    "two outputs one file": Case(["simulate", "--case", "perfect", "--N", "4", "--netlist-out", "x.out",
                                  "--waveform-out", "x.out"], ["--waveform-out", "--netlist-out writes it too"]),
    "netlist output a folder": Case(["netlist", "--case", "perfect", "--N", "4", "-o", "d"], ["--output"],
                                    files={"d/keep": ""}),
    "side-by-side without a figure name": Case(["run", "s.toml", "--side-by-side", "outs"],
                                               ["--side-by-side", "outs", ".png"], files={"s.toml": SCENE}),
    # ------------------------------------------------------------------ scene files
    "scene report climbing out": Case(["run", "s.toml"], ["output.report", "../../etc/x.json", "stays in"],
                                      files={"s.toml": SCENE + '[output]\nreport = "../../etc/x.json"\n'}),
    "scene report absolute": Case(["run", "s.toml"], ["output.report", "/r.json", "no leading /"],
                                  files={"s.toml": SCENE + '[output]\nreport = "{here}/r.json"\n'}),
    "scene report not json": Case(["run", "s.toml"], ["output.report", "r.txt", ".json"],
                                  files={"s.toml": SCENE + '[output]\nreport = "r.txt"\n'}),
    "two scenes one output": Case(["run", "da/exp.toml", "db/exp.toml"], ["exp-overlay.png", "writes it too"],
                                  files={"da/exp.toml": SCENE, "db/exp.toml": SCENE}),
    "scene wall spring 1e12": Case(["run", "s.toml"], ["s.toml", "analysis.accuracy", "time points", "dt^2 law"],
                                   files={"s.toml": '[chain]\ncase = "perfect"\nN = 4\n[effects.walls]\nK0 = 1e12\n'}),
    "scene dt 1e-9": Case(["run", "s.toml"], ["s.toml", "analysis.dt", "1e-09", "TiB"],
                          files={"s.toml": SCENE + "[analysis]\ndt = 1e-9\n"}),
    "scene L0 huge": Case(["run", "s.toml"], ["s.toml", "units.L0", "1e+30"],
                          files={"s.toml": SCENE + "[units]\nL0 = 1e30\n"}),
    "scene accuracy 1e-300": Case(["run", "s.toml"], ["s.toml", "analysis.accuracy", "1e-300"],
                                  files={"s.toml": SCENE + "[analysis]\naccuracy = 1e-300\n"}),
    "scene unknown key": Case(["run", "s.toml"], ["s.toml", "chain.mass", "unknown key"],
                              files={"s.toml": SCENE + "mass = 3\n"}),
    "scene not UTF-8": Case(["run", "s.toml"], ["s.toml", "UTF-8"],
                            files={"s.toml": ('title = "\xe9"\n' + SCENE).encode("latin-1")}),
    "scene not TOML": Case(["run", "s.toml"], ["s.toml", "line 1"], files={"s.toml": "[chain\n"}),
    "scene title with .include": Case(["run", "s.toml"], ["s.toml", "title", "dot-command"],
                                      files={"s.toml": 'title = ".include /etc/passwd"\n' + SCENE}),
    "scene N beyond the maximum": Case(["run", "s.toml"], ["s.toml", "chain.N = 200000"],
                                       files={"s.toml": '[chain]\ncase = "uniform-free"\nN = 200000\n'}),
    "scene too many samples": Case(["run", "s.toml"], ["s.toml", "effects.tolerance.samples = 10000", "1 h"],
                                   files={"s.toml": '[chain]\ncase = "two-mass"\nN = 1000\n[effects.tolerance]\n'
                                                    'L = 0.01\nsamples = 10000\n'}),
    "scene missing": Case(["run", "missing.toml"], ["missing.toml", "readable"]),
    # ------------------------------------------------------------------ figures and the report
    "figures into a file": Case(["figures", "--out", "f.txt"], ["--out = 'f.txt'", "a folder (this is a file)"],
                                files={"f.txt": "x"}),
    "figures under a missing folder": Case(["figures", "--out", "no/such/dir"], ["--out", "does not exist"]),
    # a cradle on stiff walls rings near 2e6: ngspice steps far below dt (a 40 s run), priced by its modes
    "a walled cradle past --max-time": Case(["simulate", "--case", "perfect", "--N", "6", "--walls", "1000000",
                                            "--dt", "0.05", "--max-time", "3s"], ["--dt = 0.05", "can afford"]),
    "figures into standard output": Case(["figures", "--out", "-", "--quick"], ["--out = '-'", "standard output"]),
    "the accuracy benchmark into standard output": Case(["bench", "accuracy", "--out", "-"],
                                                        ["--out = '-'", "standard output"]),
    "figures in an unknown format": Case(["figures", "--out", "figs", "--format", "gif"], ["--format", "gif"]),
    "report into a file": Case(["report", "--out", "r.html", "--quick"], ["--out = 'r.html'", "a folder"],
                               files={"r.html": "x"}),
    "report without a folder": Case(["report", "--quick"], ["--out"]),
    # (a well-formed name may be a .meas of the store's netlists: checked against the store, test_measurements.py)
    "an unknown summary metric": Case(["results", "s.sqlite", "--summary", "--metric", "speed/s"],
                                      ["--metric", "speed/s"]),
    "a metric with nothing to show it": Case(["results", "s.sqlite", "--metric", "energy"],
                                             ["--metric = 'energy'", "only with --summary or --plot"]),
    # ------------------------------------------------------------------ runs that fail, and a missing simulator
    "accuracy not met": Case(["simulate", "--case", "uniform-bounded", "--N", "10", "--accuracy", "1e-9",
                              "--extrapolate", "1"],
                             ["--accuracy 1e-09 was not met", "reached"], status=1),
    # a FIFO nobody reads stands for a full disk: the file cannot be written when the run is over
    "waveform-out a FIFO nobody reads": Case(["simulate", "--case", "perfect", "--N", "4", "--waveform-out", "w.csv"],
                                             ["could not write w.csv", "--waveform-out", "No such device"], status=1,
                                             make=lambda here: os.mkfifo(here / "w.csv")),
    "shared library path unreadable": Case(["simulate", "--case", "perfect", "--N", "4", "--backend", "shared"],
                                           ["NGSPICE_LIBRARY_PATH", "/nonexistent/libngspice.so"], status=3,
                                           env={"NGSPICE_LIBRARY_PATH": "/nonexistent/libngspice.so"}),
}


#: Cases of 10 s and more (a stiff chain's accuracy search; a run to 1e-9), run with the slow tests to keep the
#: README's test command under 10 minutes; the same refusals' faster kin stay in it.
SLOW_CASES = {"scene wall spring 1e12", "accuracy not met"}


@pytest.mark.ngspice
@pytest.mark.parametrize("case", [pytest.param(case, marks=pytest.mark.slow) if name in SLOW_CASES else case
                                  for name, case in CASES.items()], ids=CASES.keys())
def test_bad_input_is_refused_cleanly(case: Case, tmp_path: Path) -> None:
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail


# ------------------------------------------------------------------ the Python API

API: dict[str, tuple[Callable[[], object], str]] = {
    "masses as text": (lambda: lcchain.Chain(["1", "1", "1", "1"], [0, 1, 1, 1, 0]), "masses[0]"),
    "masses as booleans": (lambda: lcchain.Chain([True] * 4, [0, 1, 1, 1, 0]), "masses[0]"),
    "r as text": (lambda: lcchain.Chain.from_rw(100, r="0.5", w=0.1), "r"),  # type: ignore[arg-type]
    "N as a float": (lambda: lcchain.Chain.from_rw(100.0, r=0.5, w=0.1), "N"),  # type: ignore[arg-type]
    "a nan time": (lambda: lcchain.transmission_amplitude(lcchain.Chain.perfect(4), [np.nan, 1.0]), "t[0]"),
    "a negative response time": (lambda: lcchain.linear_response(lcchain.Chain.perfect(4), [-1.0]), "t[0]"),
    "L0 as a boolean": (lambda: lcchain.Ladder(lcchain.Chain.perfect(4), L0=True), "L0"),
    "dt as text": (lambda: lcchain.SimulationOptions(dt="0.05", tstop=10.0), "dt"),  # type: ignore[arg-type]
    "N as a float in a scene": (lambda: lcchain.parse_scene({"chain": {"case": "two-mass", "N": 50.0}}), "chain.N"),
    "an empty run": (lambda: lcchain.RunSpec("", ("i(l1)",), 1.0), "netlist"),
    "a negative time unit": (lambda: lcchain.Theory(lcchain.Chain.perfect(4), -1.0), "time_unit"),
}


@pytest.mark.parametrize("call, field", API.values(), ids=API.keys())
def test_the_python_api_refuses_what_is_not_a_number(call: Callable[[], object], field: str) -> None:
    with pytest.raises(lcchain.ParameterError) as info:
        call()
    assert info.value.field == field and "\n" not in str(info.value)


@pytest.mark.ngspice
def test_numpy_scalars_are_numbers() -> None:
    report = lcchain.simulate_chain(lcchain.Chain.perfect(4), lcchain.ChainOptions(dt=np.float32(0.05), L0=np.float64(1e-5)))
    assert report.options.dt == pytest.approx(0.05, rel=RTOL_FLOAT32)


def test_a_closed_pipe_ends_quietly() -> None:
    """``lcchain table --json | head -2``: no 'Broken pipe' message, the status of a SIGPIPE."""
    with subprocess.Popen([sys.executable, "-m", "lcchain", "table", "--case", "one-mass", "--N",
                           ",".join(str(n) for n in range(3, 40)), "--json"], cwd=ROOT, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE) as proc:
        assert proc.stdout is not None and proc.stderr is not None
        proc.stdout.close()  # the reader goes away before the table is printed
        err = proc.stderr.read().decode()
        assert proc.wait(timeout=120) == 141 and "Broken pipe" not in err and "Traceback" not in err
        assert all(line.startswith("lcchain: one-mass table ") for line in err.splitlines()), err  # progress only


def test_version() -> None:
    done = subprocess.run([sys.executable, "-m", "lcchain", "--version"], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0 and done.stdout.strip() == f"lcchain {lcchain.__version__}"
