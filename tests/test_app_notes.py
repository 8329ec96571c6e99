"""app/ says what it has to say beside a result in notes, and the command line prints them (issue 34, item 3:
"cli only parses and prints").  A function of app/ called from Python writes nothing to stderr: a file it could
not write, an accuracy it missed, are lines of its result that the caller shows as it likes."""

from __future__ import annotations

import ast
import os
from pathlib import Path

import pytest

from lcchain.app.inputs import ChainOptions
from lcchain.app.netlist import NetlistRequest, netlist
from lcchain.app.simulate import SimulateRequest, simulate, write_outputs
from lcchain.cli import main

APP = Path(__file__).parent.parent / "lcchain" / "app"
#: app/ modules that still print a line of their own (none: run_scenes' lines are notes and a field since
#: issue 34's last round).
STILL_PRINTING: set[str] = set()


def _prints(path: Path) -> list[str]:
    """Where a module calls print() or names sys.stderr, as "file:line"."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        call = isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "print"
        stderr = isinstance(node, ast.Attribute) and node.attr == "stderr"
        if call or stderr:
            found.append(f"{path.name}:{node.lineno}")
    return found


def test_app_prints_nothing_of_its_own():
    found = [where for path in sorted(APP.glob("*.py")) if path.name not in STILL_PRINTING for where in _prints(path)]
    assert found == []
    assert all(_prints(APP / name) for name in STILL_PRINTING)  # an entry that no longer prints leaves the list


def test_an_unwritten_file_is_a_note_of_the_result_and_one_line_of_the_command(tmp_path, capsys):
    fifo = tmp_path / "n.cir"  # a FIFO nobody reads: opening it to write fails (ENXIO) once it passed the checks
    os.mkfifo(fifo)
    result = netlist(NetlistRequest(ChainOptions(case="perfect", N=4), 1e-5, 1e-8, output=str(fifo)))
    assert result.failed and len(result.notes) == 1
    assert result.notes[0].startswith(f"could not write {fifo} (--output): ")
    assert capsys.readouterr() == ("", "")  # said by the result, not printed
    status = main(["netlist", "--case", "perfect", "--N", "4", "--output", str(fifo)])
    out, err = capsys.readouterr()
    assert status == 1 and out == "" and err == f"lcchain: {result.notes[0]}\n"


@pytest.mark.ngspice
@pytest.mark.slow  # 10 to 30 s: a step small enough to nearly reach 1e-9 (test_bad_inputs' "accuracy not met")
def test_a_missed_accuracy_is_a_note(tmp_path, capsys):
    """A target one run at the chosen step just misses (uniform-bounded N = 10, 1e-9, one run, as
    test_bad_inputs' "accuracy not met" case): its note says so and write_outputs says the run failed."""
    request = SimulateRequest(ChainOptions(case="uniform-bounded", N=10), 1e-5, 1e-8, accuracy=1e-9, extrapolate=1,
                              waveform_out=str(tmp_path / "w.csv"))
    simulation = simulate(request)
    assert write_outputs(simulation) is True
    notes = simulation.outputs.take_notes()
    assert len(notes) == 1 and notes[0].startswith("--accuracy 1e-09 was not met: the run reached ")
    assert (tmp_path / "w.csv").is_file() and simulation.outputs.notes == []
    assert capsys.readouterr().err == ""


@pytest.mark.ngspice
def test_a_scene_file_not_written_is_a_note_and_the_side_by_side_figure_a_field(tmp_path, capsys, monkeypatch):
    from lcchain.app.scenes import RunRequest, run_scenes

    monkeypatch.chdir(tmp_path)
    scene = str(Path(__file__).parent.parent / "examples" / "scenes" / "cradle.toml")
    fifo = tmp_path / "n.cir"  # a FIFO nobody reads: the netlist cannot be written once the run is over
    os.mkfifo(fifo)
    run = run_scenes(RunRequest((scene,), netlist_out=str(fifo), side_by_side="pair.png"))
    assert run.failed_files == [scene] and not run.ok and run.side_by_side == "pair.png"
    notes = run.outputs.take_notes()
    assert len(notes) == 1 and notes[0].startswith(f"could not write {fifo} of {scene}: ")
    assert capsys.readouterr() == ("", "")  # said by the result, not printed
    status = main(["run", scene, "--netlist-out", str(fifo), "--side-by-side", "again.png"])
    out, err = capsys.readouterr()
    assert status == 1 and f"lcchain: {notes[0]}\n" in err and "wrote again.png\n" in out
