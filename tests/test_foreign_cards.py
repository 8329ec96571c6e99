"""The cards engineers write, in netlists lcchain did not write (issue 31): ``.subckt``/``.ends`` and ``X``,
``.model`` and its devices, ``.func``, ``.global``, ``.temp``, ``.op``, ``.dc`` and ``.lib`` sections.

Every hostile netlist below tries, through one of those cards, to run a command (it would create ``PWNED`` in the
test's own folder) or to read a file, a FIFO or a link out of its folder, or to make ngspice expand or substitute
without end: each is refused in one line naming the file, the line number and the line, before anything runs.
The prefixes of each word are checked against what ngspice 39 itself reads (:func:`test_a_word_passes_exactly_when
_ngspice_reads_it_as_that_command`), and the accepted forms run in the real ``lcchain batch`` with values checked
against hand computations:

* an RC low-pass after a unit step: v(t) = 1 - exp(-t / RC), so v(RC) = 1 - 1/e (any circuits text, e.g.
  Horowitz & Hill, *The Art of Electronics*, 3rd ed., sec. 1.4);
* a resistor's temperature coefficient: R(T) = R (1 + TC1 (T - TNOM)) with TNOM = 27 C (the ngspice 39 manual,
  sec. 3.2.7), here in a divider;
* a half-wave rectifier's peak: the diode's current (5 V - v) / R = IS (exp(v / VT) - 1) with VT = k T / q at
  27 C (the Shockley equation, ngspice manual sec. 7.1, with ngspice's constants k and q), and its reverse
  output -(5 V gmin + IS) R with ngspice's gmin = 1e-12 S across each junction.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from helpers.catalogue import MARKER, Case, run_case
from helpers.netlists import LADDER, fifo, link
from helpers.tolerances import ATOL_DC_SOLVE, RTOL_AC_LOWPASS, RTOL_DC_SOLVE, RTOL_MEASURE_TRAN, RTOL_REVERSE_LEAKAGE

from lcchain.cli import main
from lcchain.core.errors import ParameterError
from lcchain.core.limits import MAX_EXPANDED_ELEMENTS
from lcchain.spice.cards import MAX_SUBCKT_DEPTH, command_of, dc_points
from lcchain.spice.foreign import allowed_netlist, analysis_of, foreign_price
from lcchain.spice.pricing import read_contents
from lcchain.spice.result import read_include
from lcchain.studies.store import Store

TOUCH = f"shell touch {{here}}/{MARKER}"


def _with(*lines: str) -> str:
    """The good ladder netlist with lines put before its .end (the first of them is line 12)."""
    return LADDER.replace(".end\n", "\n".join(lines) + "\n.end\n")




def _batch(said: list[str], files: dict[str, str | bytes], make: Callable[[Path], None] | None = None) -> Case:
    return Case(["batch", "n.cir", "--store", "s.sqlite"], said, files=files, family="netlists", make=make)


def _line(number: int, *more: str) -> list[str]:
    return ["n.cir: line", f"line {number}", *more]


#: Sub-circuit s of one node (its body a resistor to ground), used by the instances below.
SUB = (".subckt s a params: r=1", "R1 a 0 {r}", ".ends s")
#: Ten nested sub-circuits each instantiating the next ten times (the last ten resistors): 10^10 resistors in 120
#: lines, nested no deeper than allowed.
BOMB = [line for k in range(9) for line in (f".subckt s{k} a", *[f"X{j} a s{k + 1}" for j in range(10)], ".ends")]
BOMB += [".subckt s9 a", *[f"R{j} a 0 1" for j in range(10)], ".ends", "X9 n1 s0"]
#: Six nested sub-circuits each instantiating the next ten times: 10^6 resistors, within the element limit.
MILLION = [line for k in range(5) for line in (f".subckt m{k} a", *[f"X{j} a m{k + 1}" for j in range(10)], ".ends")]
MILLION += [".subckt m5 a", *[f"R{j} a 0 1" for j in range(10)], ".ends", "X9 n1 m0"]
#: Sub-circuits nested one deeper than allowed, each instantiating the next once.
DEEP = [line for k in range(MAX_SUBCKT_DEPTH + 1) for line in (f".subckt d{k} a", f"X1 a d{k + 1}", ".ends")]
DEEP += [f".subckt d{MAX_SUBCKT_DEPTH + 1} a", "R1 a 0 1", ".ends", "X9 n1 d0"]
#: Functions each calling the last twice: ngspice 39 substitutes 2^18 bodies (it ran 20 s and was killed).
DOUBLING = [".func f0(x) = {x + x}"] + [f".func f{k}(x) = {{f{k - 1}(x) + f{k - 1}(x)}}" for k in range(1, 19)]

CASES: dict[str, Case] = {
    # ------------------------------------------------------------------ .subckt, .ends, X
    "a .subckt holding a .control": _batch(_line(13, "inside a .subckt"), {
        "n.cir": _with(".subckt s a", ".control", TOUCH, ".endc", ".ends")}),
    "a .subckt holding .controls (prefix)": _batch(_line(13), {
        "n.cir": _with(".subckt s a", ".controls", TOUCH, ".endcx", ".ends")}),
    "a .subckt holding a shell line": _batch(_line(13), {"n.cir": _with(".subckt s a", TOUCH, ".ends")}),
    "a .subckt holding an .include of /proc/self/environ": _batch(_line(13, "inside the netlist's folder"), {
        "n.cir": _with(".subckt s a", ".include /proc/self/environ", ".ends", "X1 n1 s")}),
    "a .subckt holding an .include of a FIFO": _batch(_line(13, "FIFO"), {
        "n.cir": _with(".subckt s a", ".include parts.inc", ".ends", "X1 n1 s")}, fifo("parts.inc")),
    "a .subckt holding an .include through a link out": _batch(_line(13, "inside the netlist's folder"), {
        "n.cir": _with(".subckt s a", ".include parts.inc", ".ends", "X1 n1 s")},
        link("parts.inc", "/proc/self/environ")),
    "an included .subckt holding a .control": _batch(["parts.inc: line 3"], {
        "n.cir": _with(".include parts.inc", "X1 n1 s"),
        "parts.inc": f".subckt s a\nR1 a 0 1\n.control\n{TOUCH}\n.endc\n.ends\n"}),
    "a .subckt header continued into .control": _batch(_line(12, ".subckt NAME"), {
        "n.cir": _with(".subckt s a", "+ .control", TOUCH, ".endc", ".ends")}),
    "an X line continued into .control": _batch(_line(15, "Xname"), {
        "n.cir": _with(*SUB, "X1 n1 s", "+ .control", TOUCH, ".endc")}),
    "an X line continued into .include": _batch(_line(15), {
        "n.cir": _with(*SUB, "X1 n1 s", "+ .include /etc/passwd")}),
    "an .ends continued into .control": _batch(_line(14), {
        "n.cir": _with(".subckt s a", "R1 a 0 1", ".ends", "+ .control", TOUCH, ".endc")}),
    "an X of an undefined sub-circuit": _batch(_line(12, "nosuch"), {"n.cir": _with("X1 n1 0 nosuch")}),
    "an X naming a /proc path": _batch(_line(12), {"n.cir": _with("X1 n1 0 /proc/self/environ")}),
    "an X parameter calling file()": _batch(_line(15, "file"), {"n.cir": _with(*SUB, "X1 n1 s r={file(1)}")}),
    "an X parameter calling table()": _batch(_line(15, "table"), {"n.cir": _with(*SUB, "X1 n1 s r = {table(1, 2)}")}),
    "an X parameter of a shell name": _batch(_line(15, "shell"), {"n.cir": _with(*SUB, "X1 n1 s r={shell}")}),
    "an X parameter of a string": _batch(_line(15), {"n.cir": _with(*SUB, f'X1 n1 s r="{TOUCH}"')}),
    "an X parameter of a path": _batch(_line(15), {"n.cir": _with(*SUB, "X1 n1 s r=/proc/self/environ")}),
    "an X parameter the .subckt does not declare": _batch(_line(15, "declares"), {
        "n.cir": _with(*SUB, "X1 n1 s file=1")}),
    "a .subckt default calling table()": _batch(_line(12, "table"), {
        "n.cir": _with(".subckt s a params: r={table(1, 2)}", "R1 a 0 {r}", ".ends", "X1 n1 s")}),
    "a sub-circuit instantiating itself": _batch(_line(13, "s -> s"), {
        "n.cir": _with(".subckt s a", "X1 a s", ".ends", "X9 n1 s")}),
    "two sub-circuits instantiating each other": _batch(_line(16, "s -> t -> s"), {
        "n.cir": _with(".subckt s a", "X1 a t", ".ends", ".subckt t a", "X1 a s", ".ends", "X9 n1 s")}),
    "10^10 elements in ten nested sub-circuits": _batch(_line(12 + len(BOMB) - 1, str(MAX_EXPANDED_ELEMENTS)), {
        "n.cir": _with(*BOMB)}),
    "sub-circuits nested too deep": _batch([f"at most {MAX_SUBCKT_DEPTH} deep"], {"n.cir": _with(*DEEP)}),
    "a .subckt never ended": _batch(_line(14, "inside a .subckt"), {"n.cir": _with(".subckt s a", "R1 a 0 1")}),
    "an .ends of no .subckt": _batch(_line(12, ".ends"), {"n.cir": _with(".ends")}),
    "an .end inside a .subckt": _batch(_line(13), {"n.cir": _with(".subckt s a", ".end", TOUCH, ".ends")}),
    "a .tran inside a .subckt": _batch(_line(13), {"n.cir": _with(".subckt s a", ".tran 1 2", ".ends")}),
    ".subcktx (ngspice 39 defines nothing)": _batch(_line(12), {"n.cir": _with(".subcktx s a", ".ends")}),
    "a million elements from six nested sub-circuits, priced past --max-time": Case(
        ["batch", "n.cir", "--store", "s.sqlite", "--max-time", "10s"], ["n.cir", "1000007 elements", "--max-time"],
        files={"n.cir": _with(*MILLION)}, family="netlists"),
    # ------------------------------------------------------------------ .model and devices
    "a .model parameter naming /proc": _batch(_line(12, ".model"), {
        "n.cir": _with(".model dx D (file=/proc/self/environ)", "D1 n1 0 dx")}),
    "a .model parameter of a string": _batch(_line(12), {"n.cir": _with(f'.model dx D (file="{TOUCH}")')}),
    "a .model parameter of a bare word": _batch(_line(12), {"n.cir": _with(".model dx D (is=environ)")}),
    "a .model parameter calling table()": _batch(_line(12, "table"), {
        "n.cir": _with(".model dx D (is={table(1, 2)})")}),
    "a .model of an XSPICE file source": _batch(_line(12), {
        "n.cir": _with(".model f filesource (file=1)", "A1 %v([n1]) f")}),
    "a .models (prefix) naming a FIFO": _batch(_line(12), {"n.cir": _with(".models dx D (file={here}/fifo)")},
                                                fifo("fifo")),
    "a .model continued into .control": _batch(_line(12), {
        "n.cir": _with(".model dx D (is=1e-14", "+ .control", TOUCH, ".endc")}),
    "a .model continued into .include": _batch(_line(12), {
        "n.cir": _with(".model dx D (is=1e-14)", "+ .include /etc/passwd")}),
    "a diode of no .model": _batch(_line(12, "a D line naming a .model of type D"), {
        "n.cir": _with("D1 n1 0 nosuch")}),
    "a diode of a BJT's .model": _batch(_line(13, "type D"), {"n.cir": _with(".model q NPN (bf=100)", "D1 n1 0 q")}),
    # ------------------------------------------------------------------ .func
    "a .func calling system()": _batch(_line(12, "system"), {
        "n.cir": _with(".func f(x) = {system(x)}", "R9 n1 0 {f(1)}")}),
    "a .func calling shell()": _batch(_line(12), {"n.cir": _with(f".func f(x) = {{shell({TOUCH[6:]})}}")}),
    "a .func naming a file": _batch(_line(12, "passwd"), {"n.cir": _with(".func f(x) = {x + /etc/passwd}")}),
    "a .func of a string": _batch(_line(12), {"n.cir": _with(f'.func f(x) = {{"{TOUCH}"}}')}),
    "a .funcx (prefix) calling file()": _batch(_line(12, "file"), {"n.cir": _with(".funcx f(x) = {file(x)}")}),
    "a .func continued into .include": _batch(_line(12), {
        "n.cir": _with(".func f(x) = {x", "+ .include /etc/passwd}")}),
    "a .func calling itself (ngspice 39 crashes)": _batch(_line(12, "f -> f"), {
        "n.cir": _with(".func f(x) = {f(x) + 1}", "R9 n1 0 {f(1)}")}),
    "two .func calling each other": _batch(_line(12, "f -> g -> f"), {
        "n.cir": _with(".func f(x) = {g(x)}", ".func g(x) = {f(x)}")}),
    "functions doubling 18 times": _batch(["n.cir: line", "written out"], {"n.cir": _with(*DOUBLING)}),
    "a call of an undefined function": _batch(_line(12, "nosuch"), {"n.cir": _with("R9 n1 0 {nosuch(1)}")}),
    "a .param calling an undefined function": _batch(_line(12, "environ"), {
        "n.cir": _with(".param p = {environ(1)}")}),
    # ------------------------------------------------------------------ .global, .temp, .op, .dc
    "a .global of a path": _batch(_line(12, ".global"), {"n.cir": _with(".global /proc/self/environ")}),
    "a .global continued into .control": _batch(_line(12), {
        "n.cir": _with(".global vdd", "+ .control", TOUCH, ".endc")}),
    "a .temp calling file()": _batch(_line(12, "file"), {"n.cir": _with(".temp {file(1)}")}),
    "a .temp of a path": _batch(_line(12, ".temp"), {"n.cir": _with(".temp /etc/passwd")}),
    ".tempx (ngspice 39 stops on it)": _batch(_line(12), {"n.cir": _with(".tempx 30")}),
    "an .op of a path": _batch(_line(12, ".op"), {"n.cir": _with(".op /etc/passwd")}),
    "an .op continued into .control": _batch(_line(12), {"n.cir": _with(".op", "+ .control", TOUCH, ".endc")}),
    ".opx (ngspice 39 stops on it)": _batch(_line(12), {"n.cir": _with(".opx")}),
    "a .dc of a step 0 (no end)": _batch(_line(12, ".dc"), {"n.cir": _with(".dc Vw0 0 1 0")}),
    "a .dc of 10^12 points": _batch(_line(12, "at most"), {"n.cir": _with(".dc Vw0 0 1e9 1e-3")}),
    "a .dc of a braced expression": _batch(_line(12), {"n.cir": _with(".dc Vw0 0 {table(1)} 0.1")}),
    "a .dc of a file name": _batch(_line(12), {"n.cir": _with(".dc /etc/passwd 0 1 0.1")}),
    ".dcx (ngspice 39 stops on it)": _batch(_line(12), {"n.cir": _with(".dcx Vw0 0 1 0.1")}),
    # ------------------------------------------------------------------ .lib sections
    "a .lib section that is missing": _batch(_line(12, "no section fast"), {
        "n.cir": _with(".lib m.lib fast"), "m.lib": ".lib typ\nR9 n1 0 1\n.endl typ\n"}),
    "a .lib section holding a .control": _batch(["m.lib: line 3"], {
        "n.cir": _with(".lib m.lib typ"), "m.lib": f".lib typ\nR9 n1 0 1\n.control\n{TOUCH}\n.endc\n.endl typ\n"}),
    "a .lib section holding a .lib of /etc/passwd": _batch(["m.lib: line 2"], {
        "n.cir": _with(".lib m.lib typ"), "m.lib": ".lib typ\n.lib /etc/passwd x\n.endl typ\n"}),
    "a .lib section that includes itself": _batch(["m.lib: line 3", "section TYP of this file includes itself"], {
        "n.cir": _with(".lib m.lib typ"), "m.lib": ".lib typ\nR9 n1 0 1\n.lib m.lib TYP\n.endl typ\n"}),
    "two .lib sections that include each other": _batch(["m.lib: line 5", "section a of this file includes itself"], {
        "n.cir": _with(".lib m.lib a"), "m.lib": ".lib a\n.lib m.lib b\n.endl a\n.lib b\n.lib m.lib a\n.endl b\n"}),
}


@pytest.mark.ngspice
@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_a_hostile_card_is_refused_before_anything_runs(case: Case, tmp_path: Path) -> None:
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail
    assert not (tmp_path / "s.sqlite").exists()


# --------------------------------------------------------------------------- what ngspice 39 reads

#: A sub-circuit R of 2 kOhm (its default 1 kOhm overridden), a model, a function, a global node, a temperature
#: and an operating point, each card's word in place of {w}: 1 V across 2 kOhm is -0.5 mA through V1.
_PREFIX_NETLISTS: dict[str, tuple[str, str]] = {
    ".subckt": ("t\n{w} RDIV a b params: r=1k\nR1 a b {{r}}\n.ends RDIV\nV1 1 0 1\nX1 1 0 RDIV r=2k\n.op\n.end\n",
                "-5.00000e-04"),
    ".ends": ("t\n.subckt RDIV a b params: r=1k\nR1 a b {{r}}\n{w} RDIV\nV1 1 0 1\nX1 1 0 RDIV r=2k\n.op\n.end\n",
              "-5.00000e-04"),
    ".model": ("t\n{w} RM R (r=2k)\nV1 1 0 1\nR1 1 0 RM\n.op\n.end\n", "-5.00000e-04"),
    ".func": ("t\n{w} twice(x) = {{2*x}}\nV1 1 0 1\nR1 1 0 {{twice(1k)}}\n.op\n.end\n", "-5.00000e-04"),
    ".global": ("t\n{w} vdd\n.subckt LOAD a\nR1 a vdd 2k\n.ends\nV1 vdd 0 1\nX1 0 LOAD\n.op\n.end\n", "-5.00000e-04"),
    # 1 kOhm at 127 C with TC1 = 0.01: 2 kOhm
    ".temp": ("t\n{w} 127\nV1 1 0 1\nR1 1 0 1k tc1=0.01\n.op\n.end\n", "-5.00000e-04"),
    ".op": ("t\nV1 1 0 1\nR1 1 0 2k\n{w}\n.end\n", "-5.00000e-04"),
    # a sweep prints nothing in batch mode: read as .dc, it writes a DC plot to the raw file
    ".dc": ("t\nV1 1 0 1\nR1 1 0 2k\n{w} V1 0 1 0.5\n.end\n", ""),
}
_VARIANTS = [(command, word) for command in _PREFIX_NETLISTS
             for word in (command, command.upper(), command + "x", command.upper() + "_X", command + "s",
                          command[:-1])]


@pytest.mark.ngspice
@pytest.mark.parametrize("command, word", _VARIANTS, ids=[w for _, w in _VARIANTS])
def test_a_word_passes_exactly_when_ngspice_reads_it_as_that_command(command: str, word: str,
                                                                      tmp_path: Path) -> None:
    """The allow-list's reading of a card's first word (:func:`lcchain.spice.cards.command_of`) against ngspice
    39's own: the netlist gives its expected current only where ngspice read the word as ``command``."""
    template, current = _PREFIX_NETLISTS[command]
    text = template.format(w=word)
    (tmp_path / "n.cir").write_text(text)
    done = subprocess.run(["ngspice", "-b", "-r", "n.raw", "n.cir"] if command == ".dc" else ["ngspice", "-b", "n.cir"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=60,
                          env={"PATH": os.environ["PATH"], "HOME": str(tmp_path)})
    if command == ".dc":
        raw = tmp_path / "n.raw"
        read_as_command = done.returncode == 0 and raw.exists() and b"DC transfer" in raw.read_bytes()
    else:
        read_as_command = done.returncode == 0 and re.search(rf"v1#branch\s+{current}\s", done.stdout) is not None
    try:
        allowed_netlist(text, "n.cir", None)
        accepted = True
    except ParameterError:
        accepted = False
    assert accepted == read_as_command, (done.stdout + done.stderr)[-600:]
    assert (command_of(word.lower()) == command) == accepted


def _real_plot(raw: bytes, name: str) -> dict[str, np.ndarray]:
    """The columns of the real plot ``name`` of an ngspice binary raw file (lcchain reads transient and AC plots
    only)."""
    while raw:
        head, _, raw = raw.partition(b"Binary:\n")
        fields = head.decode().split("\n")
        values = {line.partition(":")[0]: line.partition(":")[2].strip() for line in fields if ":" in line}
        count, points = int(values["No. Variables"]), int(values["No. Points"])
        start = fields.index("Variables:") + 1
        names = [line.split()[1] for line in fields[start:start + count]]
        data = np.frombuffer(raw[:8 * count * points], dtype=float).reshape(points, count)
        raw = raw[8 * count * points:]
        if values["Plotname"].startswith(name):
            return {n: data[:, k] for k, n in enumerate(names)}
    raise AssertionError(f"no {name} plot")


@pytest.mark.ngspice
def test_dc_sweeps_and_the_operating_point_run_as_counted(tmp_path: Path) -> None:
    """``.dc`` and ``.op`` of the checked text, in ngspice 39: the sweep has the points :func:`dc_points` counts
    (the second source nested in the first) and Ohm's law at each."""
    text = "a divider swept\nV1 1 0 1\nR1 1 0 1k\n.op\n.dc V1 1 0 -0.25 R1 1k 2k 500\n.end\n"
    checked = allowed_netlist(text, "n.cir", None)
    (tmp_path / "n.cir").write_text(checked)
    subprocess.run(["ngspice", "-b", "-r", "n.raw", "n.cir"], cwd=tmp_path, capture_output=True, timeout=60,
                   check=True, env={"PATH": os.environ["PATH"], "HOME": str(tmp_path)})
    raw = (tmp_path / "n.raw").read_bytes()
    sweep = _real_plot(raw, "DC transfer")
    assert len(sweep["i(v1)"]) == dc_points(".dc V1 1 0 -0.25 R1 1k 2k 500", most=100) == 15
    volts = np.tile([1.0, 0.75, 0.5, 0.25, 0.0], 3)  # the first source swept inside the second
    ohms = np.repeat([1e3, 1.5e3, 2e3], 5)
    assert np.allclose(sweep["i(v1)"], -volts / ohms, rtol=RTOL_DC_SOLVE, atol=ATOL_DC_SOLVE)
    assert _real_plot(raw, "Operating Point")["i(v1)"][0] == pytest.approx(-1e-3, rel=RTOL_DC_SOLVE)


@pytest.mark.parametrize("card, points", [(".dc V1 0 1 0.3", 4), (".dc V1 0 1 0.25", 5), (".dc I2 5 -5 -1", 11),
                                          (".dc TEMP -50 150 50", 5), (".dc V1 0 1 0.5 V2 0 3 1", 12),
                                          (".dc V1 0 1 -0.5", None), (".dc V1 0 1", None), (".dc V1 0 1e9 1", None)])
def test_dc_points_counts_a_sweep_as_ngspice_does(card: str, points: int | None) -> None:
    assert dc_points(card, most=1_000_000) == points


# --------------------------------------------------------------------------- what runs

#: Sub-circuits with parameters and a .func, a global node, .temp, .op and .dc beside the .tran, measured.
CARDS = """\
cards that engineers write
.param rbase = 1k
.FUNC twice(x) = {2 * x}
.globals vdd
.temp 127
.subckt RCF in out params: r=1k c=1u
R1 in out {r}
C1 out 0 {c}
.ENDS RCF
.subckt PULLUP out
R1 vdd out 1k tc1=1e-3
.endsPULLUP
V1 a 0 PULSE(0 1 0 1n 1n 1 2)
X1 a b RCF r={twice(rbase)}
X2 a c RCF r=1k c=2u
VDD vdd 0 1
X3 d PULLUP
R9 d 0 1k
.op
.dc V1 0 1 0.1
.tran 1u 2m
.meas tran vb find v(b) at=2m
.meas tran vc find v(c) at=2m
.meas tran vd find v(d) at=1m
.end
"""
#: A half-wave rectifier whose diode model comes from a .lib section, and its load from a .lib in that section.
RECTIFIER = """\
a half-wave rectifier, its parts from a library
.lib models.lib typ
V1 in 0 SIN(0 5 1k)
D1 in out DX
X1 out 0 LOAD
.tran 1u 1m
.meas tran vpeak max v(out)
.meas tran vlow min v(out)
.end
"""
LIBRARY = """\
* a model library: two corners
.lib typ
.model DX D (is=1e-14 n=1)
.lib parts/loads.lib loads
.endl typ
.lib slow
.model DX D (is=1e-12)
.endl slow
"""
LOADS = ".lib loads\n.subckt LOAD a b\nR1 a b 1k\n.ends LOAD\n.endl loads\n"
#: An RC low-pass in a sub-circuit swept in AC, with an .op and a .dc that ngspice runs after the sweep.
LOWPASS = """\
an RC low-pass swept, and its operating points
V1 in 0 dc 0 ac 1
X1 in out RCF r=2k
.subckt RCF a b params: r=1k
R1 a b {r}
C1 b 0 1u
.ends
.op
.dc V1 0 1 0.5
.ac dec 10 10 10k
.end
"""


def _shockley_peak(volts: float, ohms: float, saturation: float) -> float:
    """The output of a diode in series with ``ohms`` at ``volts`` (Newton on the Shockley equation at 27 C)."""
    thermal = 1.38064852e-23 * 300.15 / 1.6021766208e-19  # ngspice 39's CONSTboltz and CHARGE
    drop = 0.6
    for _ in range(60):
        residual = (volts - drop) / ohms - saturation * (math.exp(drop / thermal) - 1.0)
        slope = -1.0 / ohms - saturation / thermal * math.exp(drop / thermal)
        drop -= residual / slope
    return volts - drop


@pytest.fixture(scope="module")
def store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("cards")
    (folder / "cards.cir").write_text(CARDS)
    (folder / "rectifier.cir").write_text(RECTIFIER)
    (folder / "lowpass.cir").write_text(LOWPASS)
    (folder / "models.lib").write_text(LIBRARY)
    (folder / "parts").mkdir()
    (folder / "parts" / "loads.lib").write_text(LOADS)
    path = folder / "runs.sqlite"
    assert main(["batch", str(folder / "cards.cir"), str(folder / "rectifier.cir"), str(folder / "lowpass.cir"),
                 "--store", str(path), "--json"]) == 0
    return path


def test_the_checked_text_keeps_the_subckt_and_x_cards_as_written() -> None:
    """ngspice expands the sub-circuits: lcchain hands it the cards, byte for byte."""
    assert allowed_netlist(CARDS, "cards.cir", None) == CARDS  # the same characters (a CheckedText: a new object)


def test_a_lib_section_and_the_lib_it_holds_are_inlined(tmp_path: Path) -> None:
    (tmp_path / "models.lib").write_text(LIBRARY)
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "loads.lib").write_text(LOADS)
    checked = allowed_netlist(RECTIFIER, "rectifier.cir", tmp_path, read_include)
    assert ".model DX D (is=1e-14 n=1)" in checked and "is=1e-12" not in checked
    assert ".subckt LOAD a b" in checked and ".ends LOAD" in checked
    assert not [line for line in checked.split("\n") if line.lower().startswith(".lib")]


@pytest.mark.ngspice
def test_a_lib_section_may_include_another_section_of_its_own_file(tmp_path: Path) -> None:
    """A corner library's section often includes a common one of the same file: no cycle, as ngspice reads it.
    Section B holds R1 and includes section A's R8, both of 1 kOhm across 1 V: 2 mA through V1."""
    (tmp_path / "m.lib").write_text(".lib A\nR8 a 0 1k\n.endl A\n.lib B\nR1 a 0 1k\n.lib m.lib A\n.endl B\n")
    netlist = "t\n.lib m.lib B\nV1 a 0 1\n.tran 1u 10u\n.meas tran i1 avg i(V1)\n.end\n"
    checked = allowed_netlist(netlist, "n.cir", tmp_path, read_include)
    assert [line for line in checked.split("\n") if line.startswith("R")] == ["R1 a 0 1k", "R8 a 0 1k"]
    (tmp_path / "n.cir").write_text(netlist)
    store = tmp_path / "s.sqlite"
    assert main(["batch", str(tmp_path / "n.cir"), "--store", str(store), "--json"]) == 0
    with Store(store, "read") as opened:
        (record,) = opened.runs()
    assert record.status == "ok"
    current = record.measurements["i1"]
    assert current is not None and math.isclose(current, -2e-3, rel_tol=RTOL_DC_SOLVE)


@pytest.mark.ngspice
def test_subckts_funcs_globals_and_temp_give_the_hand_computed_values(store: Path) -> None:
    with Store(store, "read") as opened:
        cards, rectifier, _ = opened.runs()
    assert cards.status == rectifier.status == "ok"
    # X1: r = twice(rbase) = 2 kOhm, c = 1 uF; X2: 1 kOhm, 2 uF: both RC = 2 ms, read at 2 ms
    assert cards.measurements["vb"] == pytest.approx(1.0 - math.exp(-1.0), rel=RTOL_MEASURE_TRAN)
    assert cards.measurements["vc"] == pytest.approx(1.0 - math.exp(-1.0), rel=RTOL_MEASURE_TRAN)
    # the global vdd through 1 kOhm (1 + 1e-3 (127 - 27)) = 1.1 kOhm over 1 kOhm
    assert cards.measurements["vd"] == pytest.approx(1.0 / 2.1, rel=RTOL_MEASURE_TRAN)


@pytest.mark.ngspice
def test_a_diode_from_a_lib_section_rectifies_as_shockley_says(store: Path) -> None:
    with Store(store, "read") as opened:
        _, rectifier, _ = opened.runs()
    assert rectifier.measurements["vpeak"] == pytest.approx(_shockley_peak(5.0, 1e3, 1e-14), rel=RTOL_MEASURE_TRAN)
    reverse = -(5.0 * 1e-12 + 1e-14) * 1e3  # gmin and IS, reverse-biased, through the load
    assert rectifier.measurements["vlow"] == pytest.approx(reverse, rel=RTOL_REVERSE_LEAKAGE)


@pytest.mark.ngspice
def test_an_ac_sweep_beside_an_op_and_a_dc_is_the_one_stored(store: Path) -> None:
    """ngspice runs the .op and the .dc after the sweep; lcchain reads and stores the sweep: H = 1 / (1 + j w RC)
    with the instance's R = 2 kOhm."""
    with Store(store, "read") as opened:
        lowpass = opened.runs()[2]
        arrays = opened.waveforms(lowpass.key)
    assert lowpass.status == "ok" and lowpass.points == 31 and arrays is not None  # 3 decades of 10, both ends
    expected = 1.0 / (1.0 + 2j * np.pi * arrays["frequency"] * 2e3 * 1e-6)
    np.testing.assert_allclose(arrays["v(out)"], expected, rtol=RTOL_AC_LOWPASS)


def test_a_measured_ac_sweep_beside_an_op_is_refused() -> None:
    """ngspice 39 measures the last plot it made, the .op's or the .dc's: every .meas ac would come back empty."""
    text = LOWPASS.replace(".end\n", ".meas ac g1k find vdb(out) at=1k\n.end\n")
    with pytest.raises(ParameterError, match="line 8.*no .op or .dc beside a measured .ac"):
        analysis_of(allowed_netlist(text, "lowpass.cir", None), "lowpass.cir", lambda: "39")


# --------------------------------------------------------------------------- what it costs


def test_the_price_counts_every_copy_of_a_subckt() -> None:
    """Three levels of ten copies of an RC cell and a coupled pair: 1000 cells, counted as such."""
    text = ("t\n.subckt cell a\nR1 a m 1\nC1 m 0 1n\nL1 m 0 1u\nL2 a 0 1u\nK1 L1 L2 0.5\n.ends\n"
            + "".join(f".subckt g{k} a\n" + "".join(f"X{j} a {'cell' if k == 0 else f'g{k - 1}'}\n"
                                                     for j in range(10)) + ".ends\n" for k in range(3))
            + "V1 in 0 PULSE(0 1 0 1n 1n 1u 2u)\nX1 in g2\n.tran 1n 10u\n.end\n")
    contents = read_contents(allowed_netlist(text, "n.cir", None))
    assert contents.elements == 5 * 1000 + 1
    assert contents.reactive_elements == 3 * 1000
    assert contents.couplings == 1000
    assert contents.unknowns == 1000 * (1 + 2) + 1 + 1  # each cell's node m and two inductors; in; V1
    flat = read_contents("t\n.subckt cell a\nR1 a m 1\nC1 m 0 1n\nL1 m 0 1u\nL2 a 0 1u\nK1 L1 L2 0.5\n.ends\n"
                         "V1 in 0 PULSE(0 1 0 1n 1n 1u 2u)\nX1 in cell\n.tran 1n 10u\n.end\n")
    assert flat.elements == 6 and flat.unknowns == 5


def test_ten_levels_of_ten_copies_are_refused_before_a_price_or_a_run() -> None:
    with pytest.raises(ParameterError, match="once its sub-circuits are expanded"):
        allowed_netlist(_with(*BOMB), "n.cir", None)


def test_the_element_limit_holds_for_a_flat_body_too(monkeypatch: pytest.MonkeyPatch) -> None:
    """Past the limit in one body (no copies), the refusal names the first line beyond it; with copies, the
    instance that brings the most (a limit of 5 here, for a netlist of a few lines)."""
    import lcchain.spice.foreign as foreign

    monkeypatch.setattr(foreign, "MAX_EXPANDED_ELEMENTS", 5)
    flat = "t\n" + "".join(f"R{k} a 0 1\n" for k in range(6)) + ".tran 1 2\n.end\n"
    with pytest.raises(ParameterError, match=r"line 7 = 'R5 a 0 1'.*at most 5 elements"):
        allowed_netlist(flat, "n.cir", None)
    copies = "t\n.subckt s a\nR1 a 0 1\nR2 a 0 1\n.ends\nX1 n s\nX2 n s\nX3 n s\n.tran 1 2\n.end\n"
    with pytest.raises(ParameterError, match=r"line 6 = 'X1 n s'.*expanded"):
        allowed_netlist(copies, "n.cir", None)


def test_nonlinear_devices_and_operating_points_cost_more() -> None:
    """A diode costs more than the resistor in its place, a BSIM4 MOSFET more than a level-1 one, and an .op or
    a .dc beside the .tran adds its points."""
    base = "t\nV1 in 0 SIN(0 1 1k)\nR1 in n 1k\n{x}\n.tran 1u 1m\n.end\n"

    def price(x: str) -> float:
        text = allowed_netlist(base.replace("{x}", x), "n.cir", None)
        return foreign_price(text, analysis_of(text, "n.cir"), 0).seconds

    resistor = price("R2 n 0 1k")
    diode = price(".model dx D (is=1e-14)\nD1 n 0 dx")
    level1 = price(".model nm NMOS (level=1)\nM1 n n 0 0 nm")
    bsim = price(".model nm NMOS (level=54)\nM1 n n 0 0 nm")
    assert resistor < diode < level1 < bsim
    assert price("R2 n 0 1k\n.op\n.dc V1 0 1 0.001") > price("R2 n 0 1k\n.op") > resistor
    assert read_contents(allowed_netlist(base.replace("{x}", ".model q NPN (bf=100)\nQ1 n n 0 q"), "n.cir",
                                         None)).nonlinear == 1


@pytest.mark.parametrize("line, said", [(".param r0 = 1k rr = '2*r0'", "an expression in braces"),
                                        ("C2 n1 0 1\u00b5", "u for micro")])
def test_a_refused_character_says_what_to_write(line: str, said: str) -> None:
    """A quoted expression and the micro sign run in ngspice; the refusal says what lcchain runs instead."""
    from lcchain.core.errors import ParameterError
    from lcchain.spice.foreign import allowed_netlist

    with pytest.raises(ParameterError, match=said):
        allowed_netlist(LADDER.replace(".tran", f"{line}\n.tran", 1), "netlist", None)


def test_an_ac_sweep_of_one_frequency_is_read_as_ngspice_runs_it() -> None:
    """.ac lin 1 F F is one frequency, which ngspice runs; two points between equal ends are still refused."""
    from lcchain.core.errors import ParameterError
    from lcchain.spice.foreign import analysis_of

    text = "one f\nV1 in 0 DC 0 AC 1\nR1 in a 1k\nC1 a 0 1u\n.ac lin {count} 159.155 159.155\n.end\n"
    sweep = analysis_of(text.format(count=1), "netlist")
    assert (sweep.count, sweep.start, sweep.stop) == (1, 159.155, 159.155)
    with pytest.raises(ParameterError, match="FSTART < FSTOP"):
        analysis_of(text.format(count=2), "netlist")
