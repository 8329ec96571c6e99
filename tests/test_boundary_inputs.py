"""The boundary with the user's files and the command line (issue 19, sections 2, 3, 5 and 6).

Input files (``--chain``, a scene) are read only when they are regular files
within their size limit and nest only a few levels; outputs never overwrite
an input, a scene's outputs stay in the current folder with symlinks followed,
and folders are made only after every check; a single-value option given
twice is refused; public functions refuse wrong types with ParameterError.

Every case works inside its own folder: a special file is a FIFO made there,
and a symlink that leads outside is left dangling, so that even a regression
could create nothing outside it.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from helpers.catalogue import Case, run_case

import lcchain
from lcchain.circuit.netlist import NetlistOutput
from lcchain.cli import main

SCENE = '[chain]\ncase = "two-mass"\nN = 6\n'
CHAIN = '{"masses": [1.5, 1.0, 1.5], "springs": [0, 1, 1, 0]}'
DEEP = 100_000


def fifo(name: str) -> Callable[[Path], None]:
    def make(folder: Path) -> None:
        os.mkfifo(folder / name)
    return make


def link(name: str, target: str, *, to_fifo: bool = False) -> Callable[[Path], None]:
    def make(folder: Path) -> None:
        if to_fifo:
            os.mkfifo(folder / target)
        os.symlink(target, folder / name)
    return make


def hard_link(name: str, target: str) -> Callable[[Path], None]:
    def make(folder: Path) -> None:
        os.link(folder / target, folder / name)
    return make


def sparse(name: str, size: int = 65 * 2**20) -> Callable[[Path], None]:
    def make(folder: Path) -> None:
        with open(folder / name, "wb") as handle:
            handle.truncate(size)
    return make


def _input(argv: list[str], said: list[str], **kw: object) -> Case:
    return Case(argv, said, family="input files", **kw)  # type: ignore[arg-type]


def _user(argv: list[str], said: list[str], **kw: object) -> Case:
    return Case(argv, said, family="user files", **kw)  # type: ignore[arg-type]


def _cli(argv: list[str], said: list[str], **kw: object) -> Case:
    return Case(argv, said, family="cli", **kw)  # type: ignore[arg-type]


LONG_NAME = "n" * 240 + ".cir"
CASES: dict[str, Case] = {
    # ------------------------------------------------------------------ input files: regular, bounded, shallow
    "chain a FIFO": _input(["netlist", "--chain", "c.json"], ["--chain", "c.json", "a FIFO"], make=fifo("c.json")),
    "chain a FIFO on simulate": _input(["simulate", "--chain", "c.json"], ["--chain", "a FIFO"],
                                       make=fifo("c.json")),
    "chain a folder": _input(["netlist", "--chain", "d"], ["--chain", "'d'", "a folder"], files={"d/keep": ""}),
    "chain a symlink to a FIFO": _input(["netlist", "--chain", "c.json"], ["--chain", "a FIFO"],
                                        make=link("c.json", "pipe", to_fifo=True)),
    "chain a dangling symlink": _input(["netlist", "--chain", "c.json"], ["--chain", "readable"],
                                       make=link("c.json", "nowhere.json")),
    "chain nested 100000 deep": _input(["netlist", "--chain", "c.json"], ["--chain", "c.json", "too deeply"],
                                       files={"c.json": "[" * DEEP}),
    "chain masses nested 100000 deep": _input(["netlist", "--chain", "c.json"], ["--chain", "too deeply"],
                                              files={"c.json": '{"masses": ' + "[" * DEEP + "]" * DEEP + "}"}),
    "chain masses nested 50 deep": _input(["netlist", "--chain", "c.json"], ["masses", "a list of numbers"],
                                          files={"c.json": '{"masses": ' + "[" * 50 + "1" + "]" * 50
                                                 + ', "springs": [0, 1, 0]}'}),
    "scene a FIFO": _input(["run", "s.toml"], ["s.toml", "a FIFO"], make=fifo("s.toml")),
    "scene a folder": _input(["run", "s.toml"], ["s.toml", "a folder"], files={"s.toml/keep": ""}),
    "scene a symlink to a FIFO": _input(["run", "s.toml"], ["s.toml", "a FIFO"],
                                        make=link("s.toml", "pipe", to_fifo=True)),
    "scene too large": _input(["run", "s.toml"], ["s.toml", "64 MiB"], make=sparse("s.toml")),
    "scene arrays nested 100000 deep": _input(["run", "s.toml"], ["s.toml", "too deeply"],
                                              files={"s.toml": SCENE + "x = " + "[" * DEEP + "\n"}),
    "scene tables nested 100000 deep": _input(["run", "s.toml"], ["s.toml", "too deeply"],
                                              files={"s.toml": "x = " + "{a = " * DEEP + "\n"}),
    "second scene a FIFO, first never runs": _input(["run", "a.toml", "b.toml"], ["b.toml", "a FIFO"],
                                                    files={"a.toml": SCENE}, make=fifo("b.toml")),
    "swept scene a FIFO": _input(["sweep", "s.toml", "--vary", "chain.N=6,8", "--store", "s.sqlite"],
                                 ["s.toml", "a FIFO"], make=fifo("s.toml")),
    # ------------------------------------------------------------------ user files: never destroyed
    "scene report is the scene": _user(["run", "s.json"], ["s.json", "output.report", "destroy"],
                                       files={"s.json": SCENE + '[output]\nreport = "s.json"\n'}),
    "scene report is the scene by another path": _user(["run", "s.json"], ["output.report", "s.json", "destroy"],
                                                       files={"s.json": SCENE + '[output]\nreport = "./s.json"\n'}),
    "scene report is another scene of the run": _user(["run", "a.toml", "b.json"], ["output.report", "b.json"],
                                                      files={"a.toml": SCENE + '[output]\nreport = "b.json"\n',
                                                             "b.json": SCENE}),
    "netlist-out the scene itself": _user(["run", "s.toml", "--netlist-out", "s.toml"],
                                          ["--netlist-out", "s.toml", "destroy"], files={"s.toml": SCENE}),
    "waveform-out the scene by another path": _user(["run", "s.toml", "--waveform-out", "./s.toml"],
                                                    ["--waveform-out", "destroy"], files={"s.toml": SCENE}),
    "netlist-out a hard link to the scene": _user(["run", "s.toml", "--netlist-out", "h.toml"],
                                                  ["--netlist-out", "h.toml", "destroy"], files={"s.toml": SCENE},
                                                  make=hard_link("h.toml", "s.toml")),
    "side-by-side a symlink to the scene": _user(["run", "s.toml", "--side-by-side", "p.png"],
                                                 ["--side-by-side", "p.png", "destroy"], files={"s.toml": SCENE},
                                                 make=link("p.png", "s.toml")),
    "netlist output the chain file": _user(["netlist", "--chain", "c.json", "-o", "c.json"],
                                           ["--output", "c.json", "--chain"], files={"c.json": CHAIN}),
    "simulate netlist-out the chain file": _user(["simulate", "--chain", "c.json", "--netlist-out", "./c.json"],
                                                 ["--netlist-out", "--chain", "destroy"], files={"c.json": CHAIN}),
    "simulate plot a symlink to the chain file": _user(["simulate", "--chain", "c.json", "--plot", "p.png"],
                                                       ["--plot", "p.png", "--chain"], files={"c.json": CHAIN},
                                                       make=link("p.png", "c.json")),
    "scene report through a symlink leading out": _user(["run", "s.toml"], ["output.report", "stays in the current"],
                                                        files={"s.toml": SCENE + '[output]\nreport = "out/r.json"\n'
                                                               'plots = []\n'},
                                                        make=link("out", "../lcchain-never-made")),
    "scene plot through a symlink leading out": _user(["run", "s.toml"], ["output.plots", "stays in the current"],
                                                      files={"s.toml": SCENE + '[output]\nreport = "out/r.json"\n'},
                                                      make=link("out", "../lcchain-never-made")),
    "refused scene makes no folder": _user(["run", "s.toml"], ["s.toml", "analysis.dt"],
                                           files={"s.toml": SCENE + '[analysis]\ndt = 1e-9\n[output]\n'
                                                  'report = "made/by/refusal/r.json"\n'}),
    "second scene refused, first scene's folder not made": _user(
        ["run", "a.toml", "b.toml"], ["b.toml", "chain.mass"],
        files={"a.toml": SCENE + '[output]\nreport = "made/a.json"\n', "b.toml": SCENE + "mass = 1\n"}),
    "scene report under a file": _user(["run", "s.toml"], ["output.plots", "f.txt", "is a file"],
                                       files={"s.toml": SCENE + '[output]\nreport = "f.txt/r.json"\n', "f.txt": "x"}),
    "refused bench makes no folder": _user(["bench", "accuracy", "--out", "new/bench", "--N", "2"], ["--N = 2"]),
    "bench into a file": _user(["bench", "accuracy", "--out", "f.txt", "--quick"], ["--out", "this is a file"],
                               files={"f.txt": "x"}),
    "reference-netlists into the current folder by an empty name": _user(["reference-netlists", "--out", ""],
                                                                         ["--out = ''", "folder name"]),
    "reference-netlists into a file": _user(["reference-netlists", "--out", "f.txt"], ["--out", "this is a file"],
                                            files={"f.txt": "x"}),
    "reference-netlists under a file": _user(["reference-netlists", "--out", "f.txt/sub"], ["--out", "is a file"],
                                             files={"f.txt": "x"}),
    "figures by an empty name": _user(["figures", "--out", ""], ["--out = ''", "folder name"]),
    "report by an empty name": _user(["report", "--out", "", "--quick"], ["--out = ''", "folder name"]),
    "plot by an empty name": _user(["simulate", "--case", "perfect", "--N", "4", "--plot", ""],
                                   ["--plot = ''", "file name"]),
    "scene netlist-out by an empty name": _user(["run", "s.toml", "--netlist-out", ""], ["--netlist-out", "file name"],
                                                files={"s.toml": SCENE}),
    "waveform-out a name too long": _user(["simulate", "--case", "perfect", "--N", "4", "--waveform-out",
                                           "w" * 300 + ".csv"], ["--waveform-out", "at most 255 bytes"]),
    "plot in a folder whose name is too long": _user(["simulate", "--case", "perfect", "--N", "4", "--plot",
                                                      "d" * 300 + "/p.png"], ["--plot", "File name too long"]),
    # ------------------------------------------------------------------ the command line
    "N given twice": _cli(["design", "--case", "two-mass", "--N", "10", "--N", "20"], ["--N", "more than once"]),
    "dt given twice on sweep": _cli(["sweep", "--case", "two-mass", "--N", "10", "--dt", "0.05", "--dt", "0.04",
                                     "--store", "s.sqlite"], ["--dt", "more than once"]),
    "case given twice": _cli(["netlist", "--case", "two-mass", "--case", "one-mass", "--N", "10"],
                             ["--case", "more than once"]),
    "max-memory given twice": _cli(["simulate", "--case", "perfect", "--N", "4", "--max-memory", "1G",
                                    "--max-memory", "2G"], ["--max-memory", "more than once"]),
    "store given twice": _cli(["sweep", "--case", "two-mass", "--N", "10", "--store", "a.sqlite", "--store",
                               "b.sqlite"], ["--store", "more than once"]),
    "L0 negative in exponent form": _cli(["netlist", "--case", "two-mass", "--N", "10", "--L0", "-1e-5"],
                                         ["--L0 = -1e-05", "> 0"]),
    "C0 negative in exponent form": _cli(["simulate", "--case", "perfect", "--N", "4", "--C0", "-1E-9"],
                                         ["--C0 = -1e-09", "> 0"]),
    "dt negative without a leading zero": _cli(["netlist", "--case", "two-mass", "--N", "10", "--dt", "-.5"],
                                               ["--dt = -0.5", "0 < dt"]),
    "accuracy minus infinity": _cli(["simulate", "--case", "perfect", "--N", "4", "--accuracy", "-inf"],
                                    ["--accuracy", "-inf", "finite"]),
    "workers 0 on run": _cli(["run", "s.toml", "--workers", "0"], ["--workers = 0", ">= 1"],
                             files={"s.toml": SCENE}),
    "workers -3 on run": _cli(["run", "s.toml", "--workers", "-3"], ["--workers = -3", ">= 1"],
                              files={"s.toml": SCENE}),
    "a long command line is shortened in the netlist": _cli(
        ["netlist", "--case", "two-mass", "--N", "10", "--title", "t" * 200, "-o", LONG_NAME], [], status=0,
        leaves=(LONG_NAME,)),
    "a file name with a newline is echoed, not refused": _cli(
        ["netlist", "--case", "two-mass", "--N", "10", "-o", "a\nb.cir"], [], status=0, leaves=("a\nb.cir",)),
}


@pytest.mark.ngspice
@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_the_boundary_holds(case: Case, tmp_path: Path) -> None:
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail


def test_a_repeated_option_that_takes_several_values_still_adds_up() -> None:
    """--vary is meant to be repeated (one axis each): the single-value rule leaves it alone."""
    from lcchain.cli.main import build_parser

    args = build_parser().parse_args(["sweep", "s.toml", "--vary", "chain.N=6,8", "--vary", "units.L0=1e-5",
                                      "--store", "s.sqlite"])
    assert args.vary == ["chain.N=6,8", "units.L0=1e-5"]


@pytest.mark.ngspice
def test_a_scene_writes_its_folder_after_it_ran_and_a_long_command_line_is_cut(tmp_path: Path) -> None:
    (tmp_path / "s.toml").write_text(SCENE + '[output]\nreport = "made/late/r.json"\nplots = []\n')
    outcome = run_case(Case(["run", "s.toml"], [], status=0, leaves=("made", "made/late", "made/late/r.json")),
                       tmp_path, main)
    assert outcome.kind == "clean", outcome.detail
    (tmp_path / "long").mkdir()
    outcome = run_case(CASES["a long command line is shortened in the netlist"], tmp_path / "long", main)
    assert outcome.kind == "clean", outcome.detail
    comment = (tmp_path / "long" / LONG_NAME).read_text().splitlines()[1]
    assert comment.startswith("* made by: lcchain netlist") and comment.endswith(" ...") and len(comment) <= 402


@pytest.mark.ngspice
def test_a_symlink_to_a_folder_outside_is_refused(tmp_path: Path) -> None:
    """The same rule with a real folder on the other side (both inside tmp_path): nothing is written there."""
    work, elsewhere = tmp_path / "work", tmp_path / "elsewhere"
    work.mkdir()
    elsewhere.mkdir()
    case = Case(["run", "s.toml"], ["output.plots", "stays in the current folder", str(elsewhere)],
                files={"s.toml": SCENE + '[output]\nreport = "out/r.json"\n'},
                make=lambda here: os.symlink(elsewhere, here / "out"))
    outcome = run_case(case, work, main)
    assert outcome.kind == "clean", outcome.detail
    assert list(elsewhere.iterdir()) == []


# ------------------------------------------------------------------ the Python API
CHAIN4 = lcchain.Chain.perfect(4)
API: dict[str, tuple[Callable[[], object], str]] = {
    "simulate with a budget as text": (lambda: lcchain.simulate_chain(CHAIN4, lcchain.ChainOptions(dt=0.05), budget="8G"), "budget"),
    "simulate with dt as text": (lambda: lcchain.simulate_chain(CHAIN4, lcchain.ChainOptions(dt="0.05")), "dt"),
    "simulate with modes as text": (lambda: lcchain.simulate(lcchain.ChainOptions(dt=0.05).request(CHAIN4), modes="x"), "modes"),
    "simulate with a simulator as text": (lambda: lcchain.simulate_chain(CHAIN4, lcchain.ChainOptions(dt=0.05), simulator="ngspice"),
                                          "simulator"),
    "simulate with a progress that is no function": (lambda: lcchain.simulate_chain(CHAIN4, lcchain.ChainOptions(dt=0.05), progress=1),
                                                     "progress"),
    "simulate a chain where a request goes": (lambda: lcchain.simulate(CHAIN4), "request"),
    "simulate a chain with its options as a dict": (lambda: lcchain.simulate_chain(CHAIN4, {"dt": 0.05}), "options"),
    "chain options with a negative L0": (lambda: lcchain.ChainOptions(dt=0.05, L0=-1.0), "L0"),
    "chain options with an unknown engine": (lambda: lcchain.ChainOptions(dt=0.05, engine="spectre"), "engine"),
    "simulate a chain given as text": (lambda: lcchain.simulate_chain("two-mass", lcchain.ChainOptions(dt=0.05)), "chain"),
    "execute a netlist string": (lambda: lcchain.execute("R1 1 0 1"), "spec"),
    "transmission amplitude of text": (lambda: lcchain.transmission_amplitude("x", [1.0]), "chain_or_modes"),
    "return amplitude of None": (lambda: lcchain.return_amplitude(None, [1.0]), "chain_or_modes"),
    "arrivals of a number": (lambda: lcchain.arrivals(3), "chain_or_modes"),
    "first arrival of text": (lambda: lcchain.first_arrival("x"), "chain_or_modes"),
    "normal modes of text": (lambda: lcchain.normal_modes("x"), "chain"),
    "normal modes by an unknown method": (lambda: lcchain.normal_modes(CHAIN4, method={"exact"}), "method"),
    "spectrum of text": (lambda: lcchain.spectrum_of("x"), "chain"),
    "predicted error of text": (lambda: lcchain.predicted_error("x", 0.05, 10.0), "modes"),
    "predicted error with ends as an object": (
        lambda: lcchain.predicted_error(lcchain.normal_modes(CHAIN4), 0.05, 10.0, ends=object()), "ends"),
    "predicted error with weights as text": (
        lambda: lcchain.predicted_error(lcchain.normal_modes(CHAIN4), 0.05, 10.0, weights="x"), "weights"),
    "dt for accuracy of text": (lambda: lcchain.dt_for_accuracy("x", 1e-3, 10.0), "modes"),
    "dt for accuracy with max points as text": (
        lambda: lcchain.dt_for_accuracy(lcchain.normal_modes(CHAIN4), 1e-3, 10.0, max_points="x"), "max_points"),
    "load scene 42": (lambda: lcchain.load_scene(42), "path"),
    "load scene bytes": (lambda: lcchain.load_scene(b"s.toml"), "path"),
    "simulate scene of text": (lambda: lcchain.simulate_scene("s.toml"), "scene"),
    "run scene of None": (lambda: lcchain.run_scene(None), "scene"),
    "a chain from a set": (lambda: lcchain.Chain({1.0, 2.0, 3.0}, [0, 1, 1, 0]), "masses"),
    "a chain from a generator": (lambda: lcchain.Chain((m for m in (1.0, 1.0, 1.0)), [0, 1, 1, 0]), "masses"),
    "a chain from a frozenset of springs": (lambda: lcchain.Chain([1.0, 1.0, 1.0], frozenset({0.0, 1.0})),
                                            "springs"),
    "a 7 TiB chain": (lambda: lcchain.Chain.from_rw(10**12, 0.5, 0.1), "N"),
    "a 7 TiB chain by x, y, z": (lambda: lcchain.Chain.from_xyz(10**12, 0.5, 0.1, 0.5), "N"),
    "closed form of a 7 TiB chain": (lambda: lcchain.closed_form_modes(10**12, 0.5, 0.1), "N"),
    "closed form with r as text": (lambda: lcchain.closed_form_modes(10, "x", 0.1), "r"),
    "closed form with w nan": (lambda: lcchain.closed_form_modes(10, 0.5, float("nan")), "w"),
    "options with extra as a number": (lambda: lcchain.SimulationOptions(0.05, 10.0, extra=1), "extra"),
    "options with ngspice defaults as text": (lambda: lcchain.SimulationOptions(0.05, 10.0, ngspice_defaults="abstol"),
                                              "ngspice_defaults"),
    "netlist with comments as None": (lambda: lcchain.netlist_text(lcchain.Ladder(CHAIN4), lcchain.SimulationOptions(0.05, 10.0), output=NetlistOutput(comments=None)), "comments"),
    "netlist with extra vectors as a number": (lambda: lcchain.netlist_text(lcchain.Ladder(CHAIN4), lcchain.SimulationOptions(0.05, 10.0), output=NetlistOutput(extra_vectors=3)), "extra_vectors"),
}


@pytest.mark.parametrize("call, field", API.values(), ids=API.keys())
def test_public_functions_refuse_wrong_types_by_name(call: Callable[[], object], field: str) -> None:
    with pytest.raises(lcchain.ParameterError) as info:
        call()
    assert info.value.field == field and "\n" not in str(info.value)


def test_an_ordered_sequence_is_still_a_chain() -> None:
    """Lists, tuples and numpy arrays keep working: only unordered or one-shot containers are refused."""
    masses = [1.5, 1.0, 1.5]
    for given in (masses, tuple(masses), np.array(masses)):
        assert lcchain.Chain(given, [0, 1, 1, 0]) == lcchain.Chain.perfect(3)
