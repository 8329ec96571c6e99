"""A batch's plan reads each netlist fast and decides exactly as it did (issue 35 item 1: "the allow-list and the
pricing at the speed of reading the files").

The plan of a foreign netlist takes three short cuts, each checked here against the way it was read before, on
every netlist the tests and the repository hold and on variants of each (:mod:`helpers.corpus`: blanks around the
cards, ``+`` continuations, upper case, CRLF, ``.meas``, ``.op`` and ``.dc`` cards):

* the dot-commands (analysis, ``.save``, ``.op``/``.dc``, ``.meas``) are found by one search of the text
  (:func:`lcchain.spice.text.dot_cards`) instead of a look at every line: compared with the per-line readers they
  replaced, written out below as they were;
* the common element line (an R, L, C, K, V, I or B line of plain characters) takes one match in the allow-list
  (``foreign._PLAIN_ELEMENT``), an inductor or a capacitor a short branch in the price (``pricing._PLAIN_REACTIVE``),
  a netlist without ``+`` lines is split into cards at once (``foreign._CONTINUED``) and an ASCII one is told
  canonical without a search (``text._CANONICAL_ASCII``): compared with the general path, which the tests take by
  emptying those (``monkeypatch``);
* :func:`lcchain.spice.foreign.read_foreign` reads the analysis, the saves and the price at once: compared with
  :func:`~lcchain.spice.foreign.analysis_of`, :func:`~lcchain.spice.text.saved_vectors` and
  :func:`~lcchain.spice.foreign.foreign_price` called one after the other, as the plan called them.

Each comparison is of the whole outcome: the text ngspice receives, the refusal's message, and every price, limit
and count.  The two ways do the same arithmetic on the same numbers in one process, so they agree exactly on any
machine: a difference in the last bit is a different decision path, which is what these tests are for.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from helpers.corpus import netlist_cases, variants

import lcchain.spice.foreign as foreign
import lcchain.spice.pricing as pricing
import lcchain.spice.text as text_module
from lcchain.core.budget import Budget
from lcchain.core.errors import ParameterError
from lcchain.spice.foreign import allowed_netlist, analysis_of, foreign_price, read_foreign
from lcchain.spice.measure import measure_names
from lcchain.spice.pricing import read_contents
from lcchain.spice.result import read_include
from lcchain.spice.text import canonical_text, logical_lines, netlist_lines, parse_options, saved_vectors
from lcchain.studies.plan import batch_plan

CASES = netlist_cases()
#: For the default run, every netlist that runs (the tests' own, the reference netlists) and every eighth bad or
#: hostile one (the whole corpus is ``slow``).
QUICK = [name for k, name in enumerate(CASES) if k % 8 == 0 or "::" not in name]


# --------------------------------------------------------------------------- the per-line readers, as they were

def _old_logical_lines(netlist: str) -> list[tuple[int, str]]:
    lines: list[tuple[int, str]] = []
    for number, raw in enumerate(netlist_lines(netlist), start=1):
        if raw.startswith("+") and lines:
            first, line = lines[-1]
            lines[-1] = (first, line + " " + raw[1:])
        else:
            lines.append((number, raw))
    return lines


def _old_saved_vectors(netlist: str) -> tuple[str, ...]:
    names: list[str] = []
    for _, line in _old_logical_lines(netlist):
        match = re.match(r"^\s*\.save\b(.*)$", line, re.IGNORECASE)
        if match:
            names += [w for w in match.group(1).split() if w.lower() not in ("all", "allv", "alli")]
    return tuple(dict.fromkeys(names))


def _old_analysis_cards(netlist: str) -> list[tuple[int, str]]:
    found: list[tuple[int, str]] = []
    for number, line in enumerate(netlist.split("\n"), start=1):
        word = line.split(None, 1)[0].lower() if line.strip() else ""
        if word in (".tran", ".ac"):
            found.append((number, line.strip()))
    return found


def _old_dot_words(netlist: str) -> list[tuple[int, str]]:
    """(line, first word) of every logical line but the title whose first word is .op or .dc."""
    found = []
    for number, line in _old_logical_lines(netlist)[1:]:
        word = line.split(None, 1)[0].lower() if line.strip() else ""
        if word in (".op", ".dc"):
            found.append((number, line))
    return found


def _dot_words(netlist: str) -> list[tuple[int, str]]:
    """:func:`_old_dot_words` of the cards :func:`lcchain.spice.text.dot_cards` finds."""
    return [(n, line) for n, _, line in text_module.dot_cards(netlist)
            if n > 1 and line.split(None, 1)[0].lower() in (".op", ".dc")]


def _old_measure_names(netlist: str) -> list[str]:
    card = re.compile(r"^\s*\.meas(?:ure)?\s+(?:tran|ac)\s+([A-Za-z_][A-Za-z0-9_]*)\b", re.IGNORECASE)
    names = []
    for line in netlist.split("\n"):
        match = card.match(line)
        if match:
            names.append(match.group(1).lower())
    return list(dict.fromkeys(names))


def _outcome(work: Callable[..., object], *args: object) -> str:
    """What ``work(*args)`` gives, or the refusal it raises (its message, field and value): compared as text."""
    try:
        return repr(work(*args))
    except ParameterError as error:
        return f"refused: {error} [{error.field!r} {error.value!r}]"


def _texts(case: str) -> Iterator[tuple[str, str | bytes]]:
    """Each top netlist of a case (its ``.cir`` files, or its one file) and its variants."""
    files = CASES[case]
    for top in [f for f in files if f.endswith(".cir")] or list(files)[:1]:
        content = files[top]
        if isinstance(content, bytes):
            yield top, content
        else:
            for written in variants(content).values():
                yield top, written


def _written(folder: Path, case: str, top: str, content: str | bytes) -> Path:
    for name, each in CASES[case].items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(each, bytes):
            path.write_bytes(each)
        else:
            path.write_text(each.replace("{here}", str(folder)), encoding="utf-8")
    path = folder / top
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_bytes(content.replace("{here}", str(folder)).encode("utf-8", "surrogatepass"))
    return path


def _readings(path: Path) -> dict[str, str]:
    """Every decision lcchain's plan makes of one netlist, by name: the allow-list's text or refusal, and, for
    the checked text and the text run as it is (``--allow-control``), what the plan reads of it."""
    found = {}
    try:
        raw = read_include(path, "NETLIST")
    except ParameterError as error:
        return {"read": str(error)}
    source = str(path)
    found["allowed"] = _outcome(lambda: str(allowed_netlist(raw, source, path.parent, read_include)))
    runs = {}
    try:
        runs["checked"] = allowed_netlist(raw, source, path.parent, read_include)
    except ParameterError:
        pass
    try:
        runs["as it is"] = canonical_text(raw, source)
    except ParameterError:
        pass
    for kind, text in runs.items():
        found[f"{kind}: logical lines"] = _outcome(logical_lines, text)
        found[f"{kind}: options"] = _outcome(parse_options, text)
        found[f"{kind}: contents"] = _outcome(read_contents, text, source)
        found[f"{kind}: read"] = _outcome(_read_alone, text, source)
    for trusted in (False, True):
        found[f"plan, trusted={trusted}"] = _outcome(_plan, path, trusted)
    return found


def _read_alone(text: str, source: str) -> tuple[object, ...]:
    """The analysis, the saves, the price and the limits, each read alone as the plan read them before."""
    analysis = analysis_of(text, source, lambda: "39")
    saved = saved_vectors(text)
    price = foreign_price(text, analysis, len(saved), source)
    return analysis, saved, price, price.limits(Budget(), 100.0)


def _plan(path: Path, trusted: bool) -> tuple[object, ...]:
    made = batch_plan([str(path)], allow_control=trusted, engine_version=lambda: "39")
    return tuple((t.seconds, t.memory, t.spec) for t in made.tasks), tuple(r.reason for r in made.refusals)


def _slow_path(monkeypatch: pytest.MonkeyPatch) -> None:
    """The general path everywhere: no line is plain, no ASCII text is canonical without a search, no run of
    lines is taken at once."""
    monkeypatch.setattr(foreign, "_PLAIN_ELEMENT", re.compile(r"(?!)"))
    monkeypatch.setattr(foreign, "_CONTINUED", re.compile(""))  # found everywhere: every line looked at
    monkeypatch.setattr(pricing, "_PLAIN_REACTIVE", frozenset())
    monkeypatch.setattr(text_module, "_CANONICAL_ASCII", b"")
    _no_runs(monkeypatch)


def _no_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """No run of lines taken at once: every line is odd (``odd_lines`` of no first byte), so the allow-list and the
    price's split into bodies look at each line, as they did before the runs."""
    monkeypatch.setattr(foreign, "_PLAIN_FIRST", b"")
    monkeypatch.setattr(pricing, "_LETTERS", b"")


def _compare_with_slow_path(names: list[str], folder: Path, monkeypatch: pytest.MonkeyPatch) -> int:
    written = []
    for k, name in enumerate(names):
        for j, (top, content) in enumerate(_texts(name)):
            written.append(_written(folder / f"{k}-{j}", name, top, content))
    fast = {path: _readings(path) for path in written}
    with monkeypatch.context() as patch:
        _slow_path(patch)
        slow = {path: _readings(path) for path in written}
    for path in written:
        for key, value in fast[path].items():
            assert value == slow[path][key], (path, key)
    return len(written)


def _runs_always(monkeypatch: pytest.MonkeyPatch) -> None:
    """Runs of lines taken at once in every text, however short (by default only from ``_RUNS_FROM`` lines)."""
    monkeypatch.setattr(foreign, "_RUNS_FROM", 0)
    monkeypatch.setattr(pricing, "_RUNS_FROM", 0)


@pytest.mark.parametrize("runs", [False, True])
@pytest.mark.parametrize("name", QUICK)
def test_the_short_cuts_decide_as_the_general_path(name: str, runs: bool, tmp_path: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    if runs:
        _runs_always(monkeypatch)
    assert _compare_with_slow_path([name], tmp_path, monkeypatch) > 0


@pytest.mark.slow
def test_the_short_cuts_decide_as_the_general_path_on_the_whole_corpus(tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    _runs_always(monkeypatch)
    assert _compare_with_slow_path(list(CASES), tmp_path, monkeypatch) > len(CASES)


def _every_text() -> Iterator[str]:
    for name in CASES:
        for _, content in _texts(name):
            if isinstance(content, str):
                yield content


def test_the_dot_commands_found_at_once_are_those_each_line_showed() -> None:
    """Analysis cards, ``.save``, ``.op``/``.dc`` and ``.meas`` found by one search, against the per-line readers
    they replaced; on canonical text and on text that is not (CR, form feed, NEL: the readers that never
    required it still read it, the others refuse it as they did)."""
    checked = 0
    for text in _every_text():
        for written in (text, text + "\n.op\n+ \n", text.replace("\n", "\n\x0c", 1), text.replace("\n", "\x85\n", 1)):
            assert foreign._analysis_cards(text_module.dot_cards(written, canonical=False)) == \
                _old_analysis_cards(written)
            assert measure_names(written) == _old_measure_names(written)
            assert _outcome(saved_vectors, written) == _outcome(_old_saved_vectors, written)
            assert _outcome(logical_lines, written) == _outcome(_old_logical_lines, written)
            assert _outcome(_dot_words, written) == _outcome(_old_dot_words, written)
            checked += 1
    assert checked > 4 * len(CASES)


@pytest.mark.parametrize("written", [
    "t\n.tran 1 2\n", "\n\n.tran 1 2\n+ 3 4\n  .save a\n+b\n", ".save x\nR1 a b 1\n.tran 1 2", " .x\n+\n+y",
    "t\n.ac lin 3 1 2\n.meas ac m max vm(1)\n.op\n", "t\r\n.tran 1 2\r\n", "t\n\u3000.tran 1 2\n", "",
    "t\n.SAVE all v(1)\n.Tran 1 2 uic\n.DC temp 0 1 1\n.OP\n+x\n",
])
def test_read_foreign_reads_as_the_three_readers_one_after_the_other(written: str) -> None:
    assert _outcome(_fused, written) == _outcome(_read_three, written)


def _read_three(text: str) -> tuple[object, ...]:
    return _read_alone(text, "netlist")[:3]


def _fused(text: str) -> tuple[object, ...]:
    read = read_foreign(text, "netlist", lambda: "39")
    return read.analysis, read.saved, read.price


def test_read_foreign_reads_every_netlist_of_the_corpus_as_the_three_readers() -> None:
    compared = 0
    for text in _every_text():
        try:
            run = canonical_text(text, "netlist")
        except ParameterError:
            continue
        assert _outcome(_fused, run) == _outcome(_read_three, run)
        compared += 1
    assert compared > len(CASES)


@pytest.mark.parametrize("stop", [1e-9, 1.0, 3.7, 5.13951923877983e-06, 1e12])
@pytest.mark.parametrize("max_step", [1e-12, 0.02, 1.2775601747080254e-08, 2.0])
def test_time_points_without_edges_are_those_of_the_general_count(stop: float, max_step: float) -> None:
    import numpy as np

    assert pricing._edge_points([], stop, max_step) == pricing._listed(np.empty(0), stop, max_step)


@pytest.mark.parametrize("line", [
    "R1 a 0 1k", "c2 A 0 1e-9", "L3 a b 1u IC=1", "K1 L1 L2 0.5", "V1 a 0 PULSE(0 1 0 1n 1n 1u 2u)", "I1 0 a 1m",
    "B1 a 0 V=1+2", "R", "R1 a 0 {rval}", "R1 a 0 1k ; note", "R1 a 0 1k $ note", "R1 a 0 1k\t", " R1 a 0 1k",
    "R1 a 0 1k\u00a0", "D1 a 0 nomodel", "Q1 c b e nomodel", "M1 d g s b nomodel", "X1 a b nosub", "S1 a 0 c 0 sw",
    "W1 a 0 vc nosw", "R1 a 0 \"1k\"", "R1 a 0 1k\\", "R1 a 0 1\u00e9", "E1 a 0 b 0 2", "R1 a 0 `1k`", "R1 a 0 1k{",
])
def test_a_line_the_allow_list_takes_as_plain_is_checked_as_the_general_path_checks_it(
        line: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Lines at the edge of ``_PLAIN_ELEMENT``: each in a small netlist, allowed or refused alike both ways."""
    netlist = f"title\n{line}\nR9 a 0 1\n.tran 1 2\n.end\n"
    fast = _outcome(lambda: str(allowed_netlist(netlist, "netlist", None)))
    with monkeypatch.context() as patch:
        _slow_path(patch)
        assert _outcome(lambda: str(allowed_netlist(netlist, "netlist", None))) == fast


# --------------------------------------------------------------------------- runs of lines taken at once

#: Characters the lines of the fuzzed texts below are made of: the edges of ``_PLAIN_ELEMENT`` (its letters, other
#: letters, blanks, braces, a comment, a character of neither class, non-ASCII ones, a lone surrogate, LF).
_PIECES = ["R", "L", "c", "k", "x", "X", ".", "*", "+", "1", "=", "(", " ", "\t", "{", "}", ";", "$", "\"", "~", "\u00e9",
           "\u3000", "\ud800", "\n", "\n", "\n"]


def _fuzzed(count: int) -> Iterator[str]:
    import random

    chosen = random.Random(35)
    for _ in range(count):
        yield "".join(chosen.choice(_PIECES) for _ in range(chosen.randint(0, 40)))


def _corpus_and_fuzz() -> Iterator[str]:
    yield from _every_text()
    yield from ("", "\n", "R", "R ", "R\n", " R", "\nR1 a b 1", "R1 a b 1\n\n", "x\tR\n\t")
    yield from _fuzzed(5000)


def test_the_lines_found_odd_at_once_are_those_each_line_shows() -> None:
    """``odd_lines`` (a search of the text) against a look at each line: the lines the allow-list's pattern does
    not match whole, and the lines that do not start with a letter (the price's split into bodies)."""
    letters = re.compile(r"[A-Za-z]")
    for written in _corpus_and_fuzz():
        lines = written.split("\n")
        assert text_module.odd_lines(written, foreign._PLAIN_FIRST, foreign._PLAIN_REST, blank_end=True) == \
            [k for k, line in enumerate(lines) if not foreign._PLAIN_ELEMENT.fullmatch(line)], written
        assert text_module.odd_lines(written, pricing._LETTERS) == \
            [k for k, line in enumerate(lines) if not letters.match(line)], written
        assert text_module.odd_lines(written, b"") == list(range(len(lines)))


def _allowed_and_contents(text: str) -> tuple[str, str]:
    return (_outcome(lambda: str(allowed_netlist(text, "netlist", None))),
            _outcome(lambda: read_contents(canonical_text(text, "netlist"), "netlist")))


@pytest.mark.parametrize("written", [
    "t\nR1 a 0 1\nC1 a 0 1n\n.subckt s p\nL1 p 0 1u\nC2 p 0 1n\n.ends\nX1 a s\nX2 a s\n.tran 1 2\n.end\n",
    "t\n.control\nR1 a 0 1\n.endc\nC1 a 0 1n\nL1 a 0 1u\n.tran 1 2\n", "\n\nt\nL1 a 0 1\n  C1 a 0 1n\n* c\n",
    "t\nR1 a 0 1\r\nC1 a 0 1n\n", "t\nC1 a 0 1n\u00e9\nC2 a 0 1n\n", "t\nC1 a 0 {c}\n.param c=1n\nL1 a 0 1u\n",
])
def test_runs_of_lines_decide_as_each_line_alone(written: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """The allow-list's text or refusal and the price's contents, with runs of lines taken at once and without."""
    _runs_always(monkeypatch)
    fast = _allowed_and_contents(written)
    with monkeypatch.context() as patch:
        _no_runs(patch)
        assert _allowed_and_contents(written) == fast


@pytest.mark.parametrize("limit", [1, 2, 3, 4, 5, 6])
def test_a_run_past_the_element_limit_is_refused_at_the_same_line(limit: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """The limit on element lines crossed inside a run: refused at the line one by one would refuse."""
    monkeypatch.setattr(foreign, "MAX_EXPANDED_ELEMENTS", limit)
    _runs_always(monkeypatch)
    netlist = "t\nR1 a 0 1\nC1 a 0 1n\n* c\nL1 a b 1u\nL2 b 0 1u\nC2 b 0 1n\n.tran 1 2\n"
    fast = _outcome(lambda: str(allowed_netlist(netlist, "netlist", None)))
    with monkeypatch.context() as patch:
        _no_runs(patch)
        assert _outcome(lambda: str(allowed_netlist(netlist, "netlist", None))) == fast
    assert "refused" in fast or limit >= 5


def _checked(text: str, folder: Path | None) -> str:
    return str(allowed_netlist(text, "n", folder, read_include))


def test_a_netlist_that_includes_nothing_is_checked_alike_without_its_folder(tmp_path: Path) -> None:
    """The plan resolves a netlist's folder only for its includes (or to run it there): a netlist that
    ``includes_nothing`` says holds none is checked alike with and without a folder."""
    compared = 0
    for written in _every_text():
        if foreign.includes_nothing(written):
            assert _outcome(_checked, written, tmp_path) == _outcome(_checked, written, None)
            compared += 1
    assert compared > len(CASES)
    assert not foreign.includes_nothing("t\n.INC x\n") and not foreign.includes_nothing("t\n .Lib x y\n")


def test_one_gap_counted_in_floats_is_the_numpy_count() -> None:
    """A netlist without breakpoints is priced by ``_one_gap_points`` (floats, so that a batch's plan loads no
    numpy): the same operations as :func:`lcchain.spice.pricing.gap_points` of one gap, so the same points, over
    gaps from far below to far above the largest step and the boundaries between its three regimes."""
    import numpy as np

    rng = np.random.default_rng(35)
    cases = [(10.0 ** rng.uniform(-15, 3), 10.0 ** rng.uniform(-15, 3)) for _ in range(20000)]
    cases += [(step * f, step) for step in (1e-9, 1.264911064067352e-08, 3.3) for f in (0.5, 0.75, 1.0, 2.0, 2.5)]
    for gap, step in cases:
        assert pricing._one_gap_points(gap, step) == float(pricing.gap_points(np.array([gap]), step).sum()), (gap, step)
