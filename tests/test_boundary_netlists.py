"""Netlists lcchain did not write (issue 19, section 1): only what lcchain understands runs, in a sandbox.

Each hostile netlist tries to create ``PWNED`` in the test's own folder (an
absolute path, ``{here}``): a clean refusal names the file, the line number
and the line, and nothing runs. Every one of these ran a command or read a
file with the old deny-list; the allow-list refuses them for not being
allowed, not for being known.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers.catalogue import MARKER, Case, run_case
from helpers.netlists import LADDER, fifo, link
from helpers.tolerances import RTOL_POINTS_RATIO

import lcchain
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import Drive, NetlistOutput, SimulationOptions, netlist_text
from lcchain.cli import main
from lcchain.core.budget import BYTES_PER_VALUE
from lcchain.core.errors import ParameterError, SimulationError
from lcchain.spice.foreign import allowed_netlist, foreign_price, transient_of
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.runner import run
from lcchain.spice.result import read_include
from lcchain.spice.sandbox import find_sandbox
from lcchain.spice.text import saved_vectors

ROOT = Path(__file__).resolve().parent.parent
GOOD = LADDER  # the perfect N=3 chain in henry and farad, loop 1 kicked with 1 A
TOUCH = f"shell touch {{here}}/{MARKER}"


def _with(*lines: str) -> str:
    """The good netlist with lines put before its .end."""
    return GOOD.replace(".end\n", "\n".join(lines) + "\n.end\n")




def _batch(said: list[str], files: dict[str, str | bytes], make: Callable[[Path], None] | None = None,
           argv: tuple[str, ...] = ()) -> Case:
    return Case(["batch", "n.cir", "--store", "s.sqlite", *argv], said, files=files, family="netlists", make=make)


def _line(number: int) -> list[str]:
    return ["n.cir: line", f"line {number}"]


CASES: dict[str, Case] = {
    # ------------------------------------------------------------------ control blocks in disguise
    ".control": _batch(_line(12), {"n.cir": _with(".control", TOUCH, ".endc")}),
    ".controls ... .endcx (prefix match)": _batch(_line(12), {"n.cir": _with(".controls", TOUCH, ".endcx")}),
    ".CONTROL_X ... .ENDC_X": _batch(_line(12), {"n.cir": _with(".CONTROL_X", TOUCH, ".ENDC_X")}),
    "indented .control": _batch(_line(12), {"n.cir": _with("   .control", TOUCH, ".endc")}),
    "tab before .control": _batch(_line(12), {"n.cir": _with("\t.control", TOUCH, ".endc")}),
    ".control after .end": _batch(["n.cir: line 13"], {"n.cir": GOOD + f".control\n{TOUCH}\n.endc\n"}),
    "first line *ng_script": _batch(["n.cir: line 1", "title"], {"n.cir": f"*ng_script\n{TOUCH}\n"}),
    "first line *NG_SCRIPT": _batch(["n.cir: line 1"], {"n.cir": f"*NG_SCRIPT_WITH_PARAMS\n{TOUCH}\n"}),
    "blank lines, then *ng_script": _batch(["n.cir: line 3"], {"n.cir": f"\n\n*ng_script\n{TOUCH}\n"}),
    "blank first line, then .control": _batch(["n.cir: line 2"], {"n.cir": f"\n.control\n{TOUCH}\n.endc\n" + GOOD}),
    "title .control": _batch(["n.cir: line 1"], {"n.cir": f".control\n{TOUCH}\n.endc\n" + GOOD}),
    "*# command comment": _batch(_line(12), {"n.cir": _with(f"*# {TOUCH[6:]}")}),
    "a source line": _batch(_line(12), {"n.cir": _with("source helper.txt"), "helper.txt": f"{TOUCH}\n"}),
    "a shell line": _batch(_line(12), {"n.cir": _with(TOUCH)}),
    "continuation of the title": _batch(["n.cir: line 2"], {"n.cir": f"title\n+ .control\n{TOUCH}\n.endc\n"}),
    "continuation into .options": _batch(_line(12), {"n.cir": _with(".options reltol=1e-3", "+ .control", TOUCH)}),
    "a lone carriage return": _batch(_line(12), {"n.cir": _with(f"R9 n1 0 1\r.control\r{TOUCH}\r.endc")}),
    "a NUL byte": _batch(_line(12), {"n.cir": _with("R9 n1 0 1\0.control")}),
    "unknown dot-command .exec": _batch(_line(12), {"n.cir": _with(f".exec {TOUCH}")}),
    ".measures (ngspice 39 refuses it too)": _batch(_line(12), {"n.cir": _with(".measures tran x max i(l1)")}),
    ".mea (prefix)": _batch(_line(12), {"n.cir": _with(".mea tran x max i(l1)")}),
    ".par (ngspice 39 stops on it)": _batch(_line(12), {"n.cir": _with(".par x=1")}),
    ".title": _batch(_line(12), {"n.cir": _with(".title .control")}),
    "unknown option filetype": _batch(_line(12) + ["filetype"], {"n.cir": _with(".options filetype=ascii")}),
    "a subcircuit call": _batch(_line(12), {"n.cir": _with("X1 n1 0 sub")}),
    "an XSPICE element": _batch(_line(12), {"n.cir": _with("A1 n1 0 model")}),
    "quotes in a value": _batch(_line(12), {"n.cir": _with('.param x="$(touch PWNED)"')}),
    "a backslash": _batch(_line(12), {"n.cir": _with("R9 n1 0 1\\")}),
    # ------------------------------------------------------------------ .param and expressions (issue 31)
    ".param x = {table(...)}": _batch(_line(12) + ["table"], {"n.cir": _with(".param x = {table(1, 2, 3)}")}),
    ".PARAMS x = {file(...)} (prefix)": _batch(_line(12) + ["file"], {"n.cir": _with(".PARAMS x = {file(1)}")}),
    ".param_x with a shell name": _batch(_line(12) + ["shell"], {"n.cir": _with(".param_x y = {shell}")}),
    ".param a string": _batch(_line(12), {"n.cir": _with(f'.param x = {{"{TOUCH}"}}')}),
    ".param a backtick": _batch(_line(12), {"n.cir": _with(f".param x = {{`{TOUCH}`}}")}),
    ".param $(...)": _batch(_line(12), {"n.cir": _with(f".param x = {{$({TOUCH})}}")}),
    ".param a /proc path": _batch(_line(12), {"n.cir": _with(".param x = {1/proc/self/environ}")}),
    ".param a path to a FIFO": _batch(_line(12), {"n.cir": _with(".param x = {{here}/fifo}")}, fifo("fifo")),
    ".param a function definition": _batch(_line(12), {"n.cir": _with(".param f(x) = {x*2}")}),
    ".param a nested brace": _batch(["n.cir: line 13", "nested"], {"n.cir": _with(".param x = 1", "R9 n1 0 {{x}}")}),
    ".param include trick": _batch(["n.cir: line 13"], {"n.cir": _with(".param x = {1}", ".include {x}")}),
    "a random draw in a value": _batch(_line(12) + ["agauss"], {"n.cir": _with("R9 n1 0 {agauss(1, 0.1, 3)}")}),
    "a value of an unknown name": _batch(_line(12) + ["home"], {"n.cir": _with("R9 n1 0 {home}")}),
    "a continuation into a .param": _batch(_line(12) + ["table"], {
        "n.cir": _with(".param x = 1", "+ y = {table(1, 2)}")}),
    "a continuation of a .param into .control": _batch(_line(12), {
        "n.cir": _with(".param x = 1", "+ .control", TOUCH, ".endc")}),
    "an included .param through a link": _batch(["p.inc: line 1", "table"], {
        "n.cir": _with(".include link.inc"), "p.inc": ".param x = {table(1, 2)}\n"}, link("link.inc", "p.inc")),
    "too many .param names": _batch(["at most"], {"n.cir": _with(*[f".param p{k} = {k}" for k in range(1001)])}),
    "a too long expression": _batch(_line(12), {"n.cir": _with(".param x = {" + "+".join(["1"] * 300) + "}")}),
    # ------------------------------------------------------------------ .meas (issue 31)
    ".meas param='...'": _batch(_line(12), {"n.cir": _with(f".meas tran x param='{TOUCH}'")}),
    ".meas a dc analysis": _batch(_line(12), {"n.cir": _with(".meas dc x max i(l1)")}),
    ".meas into a file": _batch(_line(12), {"n.cir": _with(".meas tran x max i(l1) >{here}/PWNED")}),
    ".meas of a /proc vector": _batch(_line(12), {"n.cir": _with(".meas tran x find v(/proc/self/fd/0) at=1")}),
    ".meas a table value": _batch(_line(12) + ["table"], {"n.cir": _with(".meas tran x when i(l1)={table(1)}")}),
    ".meas a word lcchain does not know": _batch(_line(12), {"n.cir": _with(".meas tran x max i(l1) shell")}),
    ".meas a continuation into .control": _batch(_line(12), {"n.cir": _with(".meas tran x max i(l1)", "+ .control",
                                                                            TOUCH, ".endc")}),
    ".meas one name twice": _batch(["line 13", "once"], {"n.cir": _with(".meas tran x max i(l1)",
                                                                         ".meas tran x min i(l1)")}),
    ".MEASURE of an included file with a .control": _batch(["m.inc: line 2"], {
        "n.cir": _with(".include m.inc"), "m.inc": f".MEASURE tran x max i(l1)\n.control\n{TOUCH}\n.endc\n"}),
    "--title *ng_script": Case(["netlist", "--case", "uniform-free", "--N", "10", "--title", "*ng_script"],
                               ["--title", "*ng_script"], family="netlists"),
    "--title *#": Case(["simulate", "--case", "perfect", "--N", "4", "--title", "*# shell touch PWNED"],
                       ["--title"], family="netlists"),
    "a scene title *NG_SCRIPT": Case(["run", "s.toml"], ["s.toml", "title"], family="netlists", files={
        "s.toml": 'title = "*NG_SCRIPT"\n[chain]\ncase = "two-mass"\nN = 10\n'}),
    # ------------------------------------------------------------------ includes
    ".inc_x of a system file (prefix match)": _batch(_line(12), {"n.cir": _with(".inc_x /etc/passwd")}),
    ".include of a system file": _batch(_line(12) + ["inside the netlist's folder"],
                                        {"n.cir": _with(".include /etc/passwd")}),
    ".lib of a system file": _batch(_line(12), {"n.cir": _with(".lib /etc/passwd typ")}),
    ".include climbing out": _batch(_line(12), {"n.cir": _with(".include ../outside.cir")}),
    ".include through a link out": _batch(_line(12), {"n.cir": _with(".include parts.inc")},
                                          link("parts.inc", "../outside/parts.inc")),  # dangling: reads nothing
    "an included .control block": _batch(["parts.inc: line 2"], {"n.cir": _with(".include parts.inc"),
                                                                 "parts.inc": f"R9 n1 0 1\n.control\n{TOUCH}\n.endc\n"}),
    "a nested include of a system file": _batch(["b.inc: line 1"], {"n.cir": _with(".include a.inc"),
                                                                    "a.inc": ".include b.inc\n",
                                                                    "b.inc": ".include /etc/passwd\n"}),
    "an include of a FIFO": _batch(_line(12) + ["FIFO"], {"n.cir": _with(".include parts.inc")}, fifo("parts.inc")),
    "an include of a folder": _batch(_line(12) + ["folder"], {"n.cir": _with(".include sub"), "sub/x": ""}),
    "an include of itself": _batch(["n.cir: line 12", "cycle"], {"n.cir": _with(".include n.cir")}),
    "an include that is missing": _batch(_line(12), {"n.cir": _with(".include missing.inc")}),
    "an include not UTF-8": _batch(["UTF-8"], {"n.cir": _with(".include p.inc"), "p.inc": b"* \xff\xfe\n"}),
    "a .lib section that is missing": _batch(["typ"], {"n.cir": _with(".lib parts.lib typ"),
                                                       "parts.lib": ".lib fast\nR9 n1 0 1\n.endl\n"}),
    "a .control block in a .lib section": _batch(["parts.lib: line 3"], {
        "n.cir": _with(".lib parts.lib typ"), "parts.lib": f".lib typ\nR9 n1 0 1e9\n.control\n{TOUCH}\n.endc\n.endl\n"}),
    "one include a thousand times": _batch(["in all"], {"n.cir": _with(*[".include big.inc"] * 1000),
                                                        "big.inc": ("* " + "x" * 998 + "\n") * 100}),
    "includes nested nine deep": _batch(["8 deep"], {"n.cir": _with(".include i1.inc"),
                                                     **{f"i{k}.inc": f".include i{k + 1}.inc\n" for k in range(1, 10)},
                                                     "i10.inc": "R9 n1 0 1\n"}),
    # ------------------------------------------------------------------ the netlist file itself
    "a netlist that is a FIFO": _batch(["NETLIST", "FIFO"], {}, fifo("n.cir")),
    "a netlist that is a folder": _batch(["NETLIST", "folder"], {"n.cir/x": ""}),
    "a netlist not UTF-8": _batch(["NETLIST", "UTF-8"], {"n.cir": GOOD.encode() + b"* \xff\n"}),
    "a netlist without .tran": _batch(["n.cir", ".tran"], {"n.cir": GOOD.replace(".tran", "* no tran")}),
    # ------------------------------------------------------------------ priced from its own .tran
    "a femtosecond step for a second": _batch(["n.cir", "--max-time", "--max-memory"],
                                              {"n.cir": _with(".tran 1e-15 1").replace(".tran 0.001", "* was")}),
    # (a --max-time below the interpreter's own start, 0.8 s, is refused by itself: this netlist costs more than 1 s)
    "beyond a small --max-time": Case(["batch", "n.cir", "--store", "s.sqlite", "--max-time", "1"],
                                      ["n.cir", "--max-time"], files={"n.cir": GOOD.replace(".tran 0.001 7.7",
                                                                                             ".tran 1e-05 7.7")},
                                      family="netlists"),
    "a --max-time below the interpreter's start": Case(["batch", "n.cir", "--store", "s.sqlite", "--max-time",
                                                        "0.001"], ["--max-time", "'0.001'", "0.8 s"],
                                                       files={"n.cir": GOOD}, family="netlists"),
    "a second, dearer .tran": _batch(["n.cir: line 12", "one analysis"], {"n.cir": _with(".tran 1e-15 1")}),
    "an .ac beside the .tran": _batch(["n.cir: line 12", "one analysis"], {"n.cir": _with(".ac dec 10 1 1e6")}),
    "an infinite stop time": _batch(["n.cir: line 10", "finite"], {
        "n.cir": GOOD.replace(".tran 0.001 7.7", ".tran 0.001 1e999")}),
    "a negative step": _batch(["n.cir: line 10", "0 < TSTEP"], {"n.cir": GOOD.replace(".tran 0.001", ".tran -0.001")}),
    ".tran with a parameter": _batch(["n.cir: line", ".tran"], {
        "n.cir": GOOD.replace(".tran 0.001", ".param h=0.001\n.tran {h}")}),
}


@pytest.mark.ngspice
@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_a_hostile_netlist_is_refused_before_anything_runs(case: Case, tmp_path: Path) -> None:
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail
    assert not (tmp_path / "s.sqlite").exists()


# --------------------------------------------------------------------------- what is allowed


@pytest.mark.parametrize("path", sorted((ROOT / "netlists").glob("*.cir")), ids=lambda p: p.name)
def test_lcchains_own_netlists_pass_byte_for_byte(path: Path) -> None:
    text = path.read_text()
    assert allowed_netlist(text, path.name, None) == text  # the same characters (a CheckedText: a new object)


@pytest.mark.parametrize("excitation, pulse", [("kick", None), ("displacement", None), ("pulse", ("gaussian", 0.2)),
                                               ("pulse", ("rect", 0.2))])
def test_every_effect_lcchain_writes_passes_byte_for_byte(excitation: str, pulse: tuple[str, float] | None) -> None:
    """Losses, walls, pulses (a B source, a PWL source), every loop saved: all inside the allow-list."""
    walled = lcchain.Chain([1.5, 1.0, 1.0, 1.5], [0.2, 1.0, 1.0, 1.0, 0.2])
    for chain, Q, probes in ((lcchain.Chain.perfect(5), None, "all"), (walled, 50.0, "ends")):
        text = netlist_text(Ladder(chain), SimulationOptions(dt=0.05, tstop=10.0), Drive(kind=excitation, pulse=pulse), effects=() if Q is None else (lcchain.Losses(Q),), output=NetlistOutput(probes=probes))  # type: ignore[arg-type]
        assert allowed_netlist(text, "own", None) == text


def test_includes_are_inlined_and_the_result_is_what_ngspice_sees(tmp_path: Path) -> None:
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "caps.inc").write_text("* the capacitors\nC9 n1 0\n+ 1e-9 ; inline comment\n.end\n")
    (tmp_path / "parts.lib").write_text(".lib typ\nR9 n2 0 1e9\n.endl\n.lib fast\nR9 n2 0 1\n.endl\n")
    text = _with(".include models/caps.inc", ".lib 'parts.lib' typ")
    inlined = allowed_netlist(text, "n.cir", tmp_path, read_include)
    assert "C9 n1 0 1e-9\n" in inlined and "R9 n2 0 1e9\n" in inlined and "R9 n2 0 1\n" not in inlined
    assert ".include" not in inlined.replace("* lcchain: .include", "") and inlined.count(".end") == 1
    assert allowed_netlist(inlined, "again", None) == inlined  # what ngspice sees passes on its own


@pytest.mark.ngspice
def test_an_included_netlist_runs_as_its_inlined_twin(tmp_path: Path) -> None:
    lines = GOOD.splitlines(keepends=True)
    parts = [line for line in lines if line[:1] in "LC"]
    (tmp_path / "ladder.inc").write_text("".join(parts))
    split = "".join(line for line in lines if line not in parts).replace(".options", ".include ladder.inc\n.options")
    tstop = transient_of(GOOD, "good").stop
    whole = run(RunJob(GOOD, saved_vectors(GOOD), tstop))
    included = run(RunJob(split, saved_vectors(GOOD), tstop, cwd=tmp_path))
    for name, values in whole.vectors.items():
        assert included.vectors[name].tolist() == values.tolist()


@pytest.mark.parametrize("text", [_with(".control", "echo", ".endc"), "*ng_script\necho\n", _with("*# echo")])
def test_execute_refuses_what_batch_refuses(text: str) -> None:
    """``execute(RunSpec(...))`` from Python gets the same allow-list: the old API ran a .controls block."""
    with pytest.raises(ParameterError, match="line"):
        lcchain.execute(lcchain.RunSpec(text, ("i(l1)",), 1.0))


# --------------------------------------------------------------------------- the sandbox


def _sandbox_or_skip() -> None:
    if not find_sandbox().available:
        reason = f"no sandbox here: {find_sandbox().why_not}"
        if os.environ.get("CI"):
            pytest.fail(reason + " (CI installs bubblewrap in .ci/setup)")
        pytest.skip(reason)


@pytest.mark.ngspice
def test_a_netlist_run_as_it_is_cannot_write_outside_its_scratch(tmp_path: Path) -> None:
    """--allow-control runs the control block, but in the sandbox: its own folder, HOME and /tmp stay untouched."""
    _sandbox_or_skip()
    (tmp_path / "sub").mkdir()
    targets = [tmp_path / MARKER, tmp_path / "sub" / MARKER]
    commands = " ; ".join(f"touch {t}" for t in targets)
    (tmp_path / "n.cir").write_text(_with(".control", "run", f"shell {commands} ; touch {MARKER} ; "
                                          f"echo x > $HOME/{MARKER} ; echo sandboxed-shell-ran", ".endc"))
    before = sorted(p.name for p in tmp_path.rglob("*"))
    status = main(["batch", str(tmp_path / "n.cir"), "--allow-control", "--store", str(tmp_path / "s.sqlite"),
                   "--executor", "serial"])
    assert status == 0
    assert not any(t.exists() for t in targets)
    assert sorted(p.name for p in tmp_path.rglob("*") if "sqlite" not in p.name) == before


@pytest.mark.ngspice
def test_the_sandbox_changes_no_result() -> None:
    tstop = transient_of(GOOD, "good").stop
    inside = run(RunJob(GOOD, saved_vectors(GOOD), tstop, foreign=True))
    outside = run(RunJob(GOOD, saved_vectors(GOOD), tstop, foreign=False))
    assert inside.time.tolist() == outside.time.tolist()
    for name, values in outside.vectors.items():
        assert inside.vectors[name].tolist() == values.tolist()


# --------------------------------------------------------------------------- priced and watched


def test_a_netlist_is_priced_from_its_own_transient() -> None:
    text = GOOD.replace(".tran 0.001 7.7 0 0.001 uic", ".tran 1e-3 10")
    transient = transient_of(text, "n.cir")
    assert transient.max_step == pytest.approx(1e-3) and transient.points == pytest.approx(10001)
    default = transient_of(GOOD.replace(".tran 0.001 7.7 0 0.001 uic", ".tran 1 10"), "n.cir")
    assert default.max_step == pytest.approx(0.2)  # ngspice's own default: (tstop - tstart) / 50
    cheap, dear = (foreign_price(t, transient_of(t, "n"), 2) for t in
                   (text, text.replace(".tran 1e-3 10", ".tran 1e-6 10")))
    assert dear.points == pytest.approx(1000 * cheap.points, rel=RTOL_POINTS_RATIO)
    # time points x their cost, plus a fixed part (the start, the set-up, the text) that is the same for both
    per_point = (dear.seconds - cheap.seconds) / (dear.points - cheap.points)
    assert per_point > 0 and 0 < cheap.seconds - per_point * cheap.points < 0.1
    per_point = (dear.memory - cheap.memory) / (dear.points - cheap.points)
    assert per_point >= BYTES_PER_VALUE * 3 and 0 < cheap.memory - per_point * cheap.points < 64 * 2**20


@pytest.mark.ngspice
def test_a_raw_file_that_outgrows_its_budget_stops_the_run() -> None:
    long = GOOD.replace(".tran 0.001 7.7 0 0.001 uic", ".tran 1e-6 100 0 1e-6 uic")  # 1e8 points, minutes
    with pytest.raises(SimulationError, match="raw file grew past"):
        run(RunJob(long, ["i(l1)"], 100.0, max_output_bytes=2e6))
