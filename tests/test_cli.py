"""Command line: the issue's exact forms, JSON keys, exit codes, one-line errors."""

import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.digits import agrees_with_printed
from helpers.tolerances import ATOL_EFFECT_RUN

from lcchain.cli import main

ROOT = Path(__file__).resolve().parent.parent

DESIGN_KEYS = {"N", "case", "delta", "s", "t_arrival", "m1", "m2", "K12", "x", "y", "z"}


def run_cli(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


@pytest.mark.parametrize("case, extra", [("two-mass", {"r", "w"}), ("one-mass", {"Delta", "delta_uniform"})])
def test_design_json_keys(capsys, case, extra):
    status, out, _ = run_cli(capsys, "design", "--case", case, "--N", "300", "--json")
    assert status == 0
    data = json.loads(out)
    assert set(data) == DESIGN_KEYS | extra
    assert data["N"] == 300 and data["case"] == case
    assert data["t_arrival"] == pytest.approx(300 + data["s"])
    assert 0 < data["delta"] < 0.2


def test_table_layouts(capsys):
    status, out, _ = run_cli(capsys, "table", "--case", "two-mass", "--N", "3,4,10,100")
    assert status == 0
    lines = out.splitlines()
    assert lines[0].startswith("Table II")
    assert lines[1].split() == ["N", "r*", "w*", "delta*", "s*", "m1*", "m2*", "K12*"]
    # Table II, N = 100 row of the paper: the same digits printed, each value within one unit of the paper's
    # (the CLI rounds what the optimiser found; the paper's values are tested to their digits in test_tables)
    paper = ["100", "0.5873", "0.0972", "0.01555", "7.04", "4.275", "0.7079", "0.4157"]
    row = lines[-1].split()
    assert row[0] == "100" and [len(c) for c in row] == [len(c) for c in paper]
    assert all(agrees_with_printed(float(c), p, units=1) for c, p in zip(row[1:], paper[1:], strict=True)), row
    status, out, _ = run_cli(capsys, "table", "--case", "one-mass", "--N", "3,20", "--json")
    rows = json.loads(out)
    assert [r["N"] for r in rows] == [3, 20] and all(DESIGN_KEYS <= set(r) for r in rows)
    status, out, _ = run_cli(capsys, "table", "--case", "one-mass", "--N", "3,20", "--csv")
    header, *body = out.strip().splitlines()
    assert header.split(",")[:3] == ["N", "case", "delta"] and len(body) == 2


def test_asymptotic_json(capsys):
    status, out, _ = run_cli(capsys, "asymptotic", "--case", "two-mass", "--json")
    data = json.loads(out)
    assert {"alpha", "delta", "sigma", "tau", "coefficients"} <= set(data)
    assert agrees_with_printed(data["alpha"], "0.987153")  # Sec. V.A


@pytest.mark.parametrize(
    "argv, field",
    [
        (["design", "--case", "two-mass", "--N", "2"], "N = 2"),
        (["design", "--case", "three-mass", "--N", "10"], "--case"),
        (["design", "--case", "two-mass", "--N", "ten"], "--N"),
        (["table", "--case", "one-mass", "--N", "3,x"], "--N"),
        (["netlist", "--case", "perfect", "--N", "20001"], "N = 20001"),
        (["netlist", "--case", "uniform-free", "--N", "10", "--title", ".control"], "title"),
        (["netlist", "--case", "uniform-free", "--N", "10", "--dt", "0"], "dt"),
        (["netlist", "--case", "uniform-free", "--N", "10", "--L0", "-1"], "L0"),
        (["simulate", "--case", "uniform-free"], "--N"),
        (["netlist", "--chain", "/nonexistent/chain.json"], "--chain"),
        (["frobnicate"], "invalid choice"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(capsys, argv, field):
    status, out, err = run_cli(capsys, *argv)
    assert status == 2
    assert out == ""
    assert len(err.strip().splitlines()) == 1, err
    assert field in err and "Traceback" not in err


def test_chain_file_errors_name_the_file_and_field(capsys, tmp_path):
    path = tmp_path / "chain.json"
    path.write_text(json.dumps({"masses": [1, 1, -1], "springs": [0, 1, 1, 0]}))
    status, _, err = run_cli(capsys, "netlist", "--chain", str(path))
    assert status == 2 and str(path) in err and "masses[2]" in err
    path.write_text("{not json")
    status, _, err = run_cli(capsys, "netlist", "--chain", str(path))
    assert status == 2 and "valid JSON" in err


def test_netlist_command_writes_file(capsys, tmp_path):
    out = tmp_path / "ladder.cir"
    status, stdout, _ = run_cli(capsys, "netlist", "--case", "two-mass", "--N", "20", "--excitation",
                                "displacement", "--title", "my ladder", "-o", str(out))
    assert status == 0 and stdout == ""
    text = out.read_text()
    assert text.splitlines()[0] == "my ladder" and "made by: lcchain netlist" in text and text.endswith(".end\n")


def test_asymmetric_chain_file_accepted(capsys, tmp_path):
    path = tmp_path / "chain.json"
    path.write_text(json.dumps({"masses": [2.0, 1.0, 1.0, 0.7], "springs": [0, 0.5, 1, 2, 0.1]}))
    status, out, _ = run_cli(capsys, "netlist", "--chain", str(path))
    assert status == 0 and "C4_5 n4 0" in out


def test_console_script_module_entry_point():
    """`python -m lcchain.cli` behaves as the console script (no traceback on bad input)."""
    proc = subprocess.run([sys.executable, "-m", "lcchain.cli", "design", "--case", "two-mass", "--N", "1"],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr


def test_import_loads_neither_matplotlib_nor_pyspice():
    code = "import lcchain, sys; print(any(m.split('.')[0] in ('matplotlib', 'PySpice') for m in sys.modules))"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "False"


def test_the_parser_loads_no_physics_and_no_scipy():
    """``lcchain --help`` and ``--version`` build every subcommand's parser: none may import the studies, the runs
    or scipy's submodules to fill its help (a default read from studies/ once made --version take 0.66 s).  The
    study's options (``lcchain.studies.options``: dataclasses checked by ``core.checks``) are the one part of
    studies/ the command layer names as it builds a request, and they import nothing else of it."""
    code = ("import sys; from lcchain.cli.main import build_parser; build_parser(); "
            "print(sorted(m for m in sys.modules if m.startswith(('lcchain.studies', 'lcchain.runs', 'scipy.', "
            "'matplotlib'))))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert set(ast.literal_eval(proc.stdout.strip())) <= {"lcchain.studies", "lcchain.studies.options"}


def test_missing_ngspice_exits_3_with_install_command(tmp_path):
    """With no ngspice on PATH, simulate exits 3 and says how to install it."""
    env = {"PATH": str(tmp_path), "HOME": str(tmp_path), "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-m", "lcchain.cli", "simulate", "--case", "perfect", "--N", "3"],
                          capture_output=True, text=True, cwd=ROOT, env=env)
    assert proc.returncode == 3, proc.stderr
    assert "apt-get install ngspice" in proc.stderr and "Traceback" not in proc.stderr


@pytest.mark.ngspice
def test_doctor_reports_all_ok(capsys):
    status, out, _ = run_cli(capsys, "doctor")
    assert status == 0, out
    assert "FAIL" not in out and out.count("[ok  ]") >= 4


@pytest.mark.ngspice
def test_simulate_json_and_outputs(capsys, tmp_path):
    netlist, waveform, plot = tmp_path / "run.cir", tmp_path / "wave.csv", tmp_path / "overlay.png"
    status, out, err = run_cli(capsys, "simulate", "--case", "two-mass", "--N", "20", "--dt", "0.05",
                               "--transits", "2", "--json", "--netlist-out", str(netlist),
                               "--waveform-out", str(waveform), "--plot", str(plot))
    assert status == 0, err
    data = json.loads(out)
    for key in ("N", "dt", "backend", "ngspice_version", "wall_s", "max_abs_error", "arrivals"):
        assert key in data
    assert {"index", "t_theory", "t_sim", "peak_theory", "peak_sim"} <= set(data["arrivals"][0])
    assert netlist.read_text().startswith("lcchain two-mass chain N=20")
    header, first_row = waveform.read_text().splitlines()[:2]
    assert header == "t,first,last" and len(first_row.split(",")) == 3
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--case", "perfect", "--N", "3", "--plot", "{missing}/x.png"],
        ["simulate", "--case", "perfect", "--N", "3", "--waveform-out", "{missing}/w.csv"],
        ["run", "examples/scenes/cradle.toml", "--side-by-side", "{missing}/p.png"],
    ],
    ids=["plot", "waveform-out", "side-by-side"],
)
def test_output_in_a_missing_folder_is_refused_before_the_run(capsys, tmp_path, argv):
    missing = tmp_path / "no-such-folder"
    root = Path(__file__).resolve().parent.parent
    argv = [a.replace("{missing}", str(missing)).replace("examples/", f"{root}/examples/") for a in argv]
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""  # nothing ran
    err = captured.err.strip()
    assert "\n" not in err and "does not exist" in err and str(missing) in err, err


# ------------------------------------------------------ effect options from the registry (issue 30)
def test_simulate_has_an_option_for_every_registered_effect_that_states_one(capsys):
    from lcchain.circuit.effects import EFFECTS

    status, out, _ = run_cli(capsys, "simulate", "--help")
    assert status == 0
    options = [cls.option for cls in EFFECTS.values() if cls.option is not None]
    assert {"--Q", "--coupling", "--coil-capacitance", "--coil-resistance", "--capacitor-esr",
            "--capacitor-esl"} <= set(options)
    for option in options:
        assert f"{option} " in out, option
    said = " ".join(out.split())  # argparse wraps the help
    assert "ratio*C0 across every coil" in said and "L*L0 henry in series with every capacitor" in said


@pytest.mark.parametrize("option, value, allowed", [
    ("--coil-capacitance", "-1", "0 < ratio <= 1e+06 (capacitance / C0;"),
    ("--coil-resistance", "0", "0 < R <= 1e+06 (resistance / sqrt(L0/C0);"),
    ("--capacitor-esr", "-0.5", "0 < R <= 1e+06 (resistance / sqrt(L0/C0);"),
    ("--capacitor-esl", "0", "0 < L <= 1e+06 (inductance / L0;"),
    ("--capacitor-esr", "1e300", "0 < R <= 1e+06 (resistance / sqrt(L0/C0);"),  # NaN theory and exit 0 before
    ("--Q", "0.5", "1 <= Q <= 1e+10"),
])
def test_a_bad_effect_option_is_one_line_naming_it(capsys, option, value, allowed):
    status, out, err = run_cli(capsys, "simulate", "--case", "two-mass", "--N", "10", option, value)
    assert status == 2 and out == ""
    assert err.startswith(f"lcchain: {option} = {float(value)!r} is not allowed: expected ") and allowed in err
    assert err.count("\n") == 1 and "Traceback" not in err


@pytest.mark.ngspice
@pytest.mark.parametrize("option, value, card", [("--Q", "100", "R1 m1 n1 "), ("--coil-capacitance", "0.01", "CP1 "),
                                                  ("--capacitor-esr", "0.01", "RS1_2 n1 c1 ")])
def test_an_effect_option_reaches_the_netlist_and_runs(capsys, tmp_path, option, value, card):
    netlist = tmp_path / "run.cir"
    status, out, err = run_cli(capsys, "simulate", "--case", "two-mass", "--N", "10", "--dt", "0.02", option, value,
                               "--netlist-out", str(netlist), "--json")
    assert card in netlist.read_text()
    assert status == 0, err
    assert json.loads(out)["max_abs_error"] < ATOL_EFFECT_RUN


def test_each_command_listed_by_its_own_help():
    """``lcchain --help`` lists every command from main.COMMANDS without importing its module: each one-line help
    there is the one the command's own parser gives, and a command's parser built alone lists the others."""
    import argparse

    from lcchain.cli.main import COMMANDS, build_parser

    def helps(parser: argparse.ArgumentParser) -> dict[str, str | None]:
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        return {choice.dest: choice.help for choice in sub._choices_actions}

    listed = {name: help_ for name, (_, help_) in COMMANDS.items()}
    assert helps(build_parser()) == listed
    assert helps(build_parser("")) == listed == helps(build_parser("batch"))


def test_a_command_start_imports_no_other_command(tmp_path):
    """``lcchain batch --help`` imports cli.batch (and what it uses), not the other commands' modules."""
    code = ("import sys; from lcchain.cli.main import main; main(['batch', '--help']); "
            "print(sorted(m for m in sys.modules if m in ('lcchain.cli.report', 'lcchain.cli.simulate', "
            "'lcchain.cli.figures', 'lcchain.cli.batch')))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().splitlines()[-1] == "['lcchain.cli.batch']"


HOOKS = '''\
import atexit, sys


class TornDown:
    def __del__(self):
        sys.stderr.write("torn down\\n")


KEPT = TornDown()  # freed only by the interpreter's teardown
atexit.register(lambda: sys.stderr.write("exit handler ran\\n"))
'''


@pytest.mark.parametrize("argv, status", [(["--version"], 0), (["design", "--case", "two-mass", "--N", "0"], 2)])
def test_a_command_ends_after_its_exit_handlers_without_the_teardown(tmp_path, argv, status):
    """The command line ends its process once its output is flushed and its exit handlers have run (they end
    workers and flush logs), without the interpreter's teardown (20 to 25 ms a command): what a module still holds
    is not freed one object at a time, and the status and every word are as before."""
    (tmp_path / "sitecustomize.py").write_text(HOOKS)
    done = subprocess.run([sys.executable, "-m", "lcchain", *argv], capture_output=True, text=True, cwd=tmp_path,
                          env={**os.environ, "PYTHONPATH": str(tmp_path)})
    assert done.returncode == status, done.stderr
    assert done.stdout.startswith("lcchain ") if status == 0 else done.stderr.startswith("lcchain: ")
    assert "exit handler ran" in done.stderr
    assert "torn down" not in done.stderr


def test_a_command_ends_the_usual_way_where_other_code_or_a_closed_stream_needs_it(tmp_path):
    """The quick ending is the interpreter's alone: under a profiler (``python -m cProfile -m lcchain``) the
    profile is still printed after the command, and a command started with its output or its error stream closed
    ends with its own status, not a traceback."""
    profiled = subprocess.run([sys.executable, "-m", "cProfile", "-m", "lcchain", "--version"], capture_output=True,
                              text=True, cwd=tmp_path)
    assert profiled.returncode == 0 and "function calls" in profiled.stdout, profiled.stderr
    for closed, argv, status in ((1, ["--version"], 0), (2, ["--version"], 0),
                                 (1, ["design", "--case", "two-mass", "--N", "0"], 2)):
        done = subprocess.run([sys.executable, "-m", "lcchain", *argv], capture_output=True, text=True, cwd=tmp_path,
                              preexec_fn=lambda fd=closed: os.close(fd))
        assert done.returncode == status and "Traceback" not in done.stderr, (closed, argv, done.stderr)


def test_the_command_lines_process_starts_without_collecting_garbage(tmp_path):
    """The console script's process raises the young generation's threshold while it starts (Python's 700 collected
    45 times while a batch's modules loaded), and is back at Python's thresholds after its first collection; a
    program that imports lcchain keeps its own."""
    code = ("import gc, json, sys; before = gc.get_threshold(); import lcchain.cli.main; imported = gc.get_threshold(); "
            "sys.argv = ['lcchain', '--version']; from lcchain.__main__ import YOUNG_THRESHOLD, main\n"
            "def program(): main()  # called from a function: main leaves the ending to this program\n"
            "program(); started = gc.get_threshold()\n"
            "kept = [[] for _ in range(2 * YOUNG_THRESHOLD)]  # allocations enough for a collection\n"
            "print(json.dumps([before, imported, started, gc.get_threshold(), YOUNG_THRESHOLD]))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    before, imported, started, later, young = json.loads(done.stdout.strip().splitlines()[-1])
    assert imported == before
    assert young > before[0] and started == [young, *before[1:]]
    assert later == before


def test_an_error_is_taken_for_ctrl_c_only_when_ctrl_c_caused_it():
    """An interrupted class body's RuntimeError (raised from the KeyboardInterrupt) is Ctrl-C: 'lcchain:
    interrupted'; an error of its own raised while a Ctrl-C was being handled is not hidden behind it."""
    from lcchain.cli.main import _from_ctrl_c

    class Interrupting:
        def __set_name__(self, owner, name):
            raise KeyboardInterrupt

    with pytest.raises(RuntimeError) as interrupted:
        type("Loading", (), {"field": Interrupting()})
    assert _from_ctrl_c(interrupted.value)
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise TypeError("a bug in a clean-up") from None
    except TypeError as own:
        assert not _from_ctrl_c(own)


def test_json_output_is_json_when_a_number_is_not_finite(capsys: pytest.CaptureFixture[str]) -> None:
    """A mean of values near the largest float overflows: JSON has no infinity, so it is null, not ``Infinity``
    (which json.loads reads but strict readers, jq and JavaScript's JSON.parse, refuse)."""
    from lcchain.cli.common import emit_json

    emit_json({"mean": float("inf"), "std": float("nan"), "rows": [1.5, (-float("inf"), 2)], "n": 3})
    text = capsys.readouterr().out
    assert json.loads(text, parse_constant=lambda word: pytest.fail(f"{word} in {text}")) == {
        "mean": None, "std": None, "rows": [1.5, [None, 2]], "n": 3}


def test_a_design_s_rounding_noise_prints_as_zero_not_a_negative_zero(capsys: pytest.CaptureFixture[str]) -> None:
    """N = 3's optimal delta* is exactly 0, computed as -4.4e-16: its cell said -0.00000, a negative loss."""
    assert main(["design", "--case", "two-mass", "--N", "3"]) == 0
    row = capsys.readouterr().out.splitlines()[-1].split()
    assert row[0] == "3" and row[3] == "0.00000"


def test_a_count_of_one_is_singular() -> None:
    from lcchain.cli.common import plural

    assert [plural(n, "run") for n in (0, 1, 2)] == ["0 runs", "1 run", "2 runs"]


@pytest.mark.ngspice
def test_what_the_effects_cost_says_earlier_not_a_negative_later(capsys) -> None:
    """Coupled coils with losses bring the first arrival forward: "arriving 0.0342 sqrt(L0 C0) earlier", not
    "-0.0342 ... later"."""
    status, out, _ = run_cli(capsys, "simulate", "--case", "two-mass", "--N", "5", "--dt", "0.05", "--coupling",
                             "0.1", "--Q", "50")
    line = next(line for line in out.splitlines() if line.startswith("what the effects cost"))
    assert status == 0 and line.endswith("sqrt(L0 C0) earlier") and " -" not in line


def test_an_ac_scenes_spreads_print_na_where_no_two_modes_were_seen_to_space() -> None:
    # a circuit damped past what its sweep resolves: its spacing spread is NaN (None in the JSON), printed "nan"
    from lcchain.cli.run import _ratio_text, error_text

    assert _ratio_text(float("nan")) == _ratio_text(None) == error_text(float("nan")) == "n/a"
    assert _ratio_text(1.0195113767074728, 3) == "1.02" and _ratio_text(0.0) == "0"
