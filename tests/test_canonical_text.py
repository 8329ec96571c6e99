"""One canonical text (issue 29): the lines the allow-list checks are the lines every transport hands ngspice.

The allow-list split a netlist at LF; the warm worker and PySpice split it with ``str.splitlines``, which also
breaks at U+2028, U+2029, NEL, form feed, vertical tab and the file separators, so a comment hiding one of those
before ``.include FILE`` passed the check and ran as a card.  Now a netlist is made canonical once
(:func:`lcchain.spice.text.canonical_text`), every transport splits it with
:func:`lcchain.spice.text.netlist_lines` and refuses a text that is not canonical, and the shared-library
workers tell the parent the digest of the lines they handed ``ngSpice_Circ``.  These tests feed the hostile
family to the check, to each transport and to ``lcchain batch`` with default options (the warm transport), with
real ngspice, bubblewrap and the warm worker.
"""

from __future__ import annotations

import functools
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from helpers.catalogue import MARKER, Case, run_case
from helpers.netlists import LADDER

import lcchain
from lcchain.cli import main
from lcchain.core.errors import ParameterError
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.spice.engines import engine_named
from lcchain.spice.foreign import allowed_netlist
from lcchain.spice.job import RunJob, TransportJob
from lcchain.spice.ngspice import warm
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.place import placement as _placement
from lcchain.spice.ngspice.runner import run
from lcchain.spice.ngspice.transports import TRANSPORT_RUNS
from lcchain.spice.result import read_include
from lcchain.spice.simulator import Simulator
from lcchain.spice.text import canonical_text, canonical_vector_name, circuit_lines, netlist_lines, text_digest
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import batch_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store

#: Every character Python's str.splitlines breaks at but LF, every other control character but tab, and a
#: byte-order mark past the start: each is refused wherever it stands, naming the line and the character.
HOSTILE = {
    "\u2028": "U+2028", "\u2029": "U+2029", "\x85": "U+0085", "\r": "U+000D", "\x0b": "U+000B",
    "\x0c": "U+000C", "\x1c": "U+001C", "\x1d": "U+001D", "\x1e": "U+001E", "\x00": "U+0000", "\x1b": "U+001B",
    "\x7f": "U+007F", "\x9b": "U+009B", "\ufeff": "U+FEFF",
}

#: Where the character hides: the title, a comment, an inline comment, the end of an element line, an include.
PLACES = ("title", "comment", "inline", "element", "included")


@functools.cache
def _spec(N: int = 10) -> tuple[str, tuple[str, ...], float]:
    spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", N), ChainOptions(dt=0.05, transits=1))
    return spec.netlist, spec.vectors, spec.tstop


def _hostile(netlist: str, char: str, place: str, secret: Path, folder: Path) -> str:
    """The netlist with ``char`` then ``.include SECRET`` (a file outside the netlist's folder) at ``place``."""
    payload = f"{char}.include {secret}"
    title, rest = netlist.split("\n", 1)
    if place == "title":
        return f"{title}{payload}\n{rest}"
    if place == "comment":
        return f"{title}\n* a comment{payload}\n{rest}"
    if place == "inline":
        return f"{title}\n{rest.replace(chr(10), f' ; note{payload}' + chr(10), 1)}"
    if place == "element":
        return f"{title}\n{rest.replace(chr(10), payload + chr(10), 1)}"
    (folder / "part.inc").write_text(f"* part{payload}\n")
    return f"{title}\n.include part.inc\n{rest}"


@pytest.fixture
def folders(tmp_path: Path) -> tuple[Path, Path]:
    folder = tmp_path / "netlists"
    folder.mkdir()
    secret = tmp_path / "secret.txt"
    secret.write_text("lcchain-secret-line\n")
    return folder, secret


@pytest.mark.parametrize("place", PLACES)
@pytest.mark.parametrize("char", list(HOSTILE), ids=list(HOSTILE.values()))
def test_every_hidden_line_break_is_refused_naming_its_line_and_character(char: str, place: str,
                                                                         folders: tuple[Path, Path]) -> None:
    folder, secret = folders
    netlist, _, _ = _spec()
    text = _hostile(netlist, char, place, secret, folder)
    with pytest.raises(ParameterError) as caught:
        allowed_netlist(text, "hostile.cir", folder, read_include)
    message = str(caught.value)
    assert HOSTILE[char] in message and "\n" not in message
    where = "part.inc: line 1" if place == "included" else f"hostile.cir: line {2 if place != 'title' else 1}"
    assert where in message, message


def test_the_canonical_text_keeps_what_ngspice_and_the_check_read_alike() -> None:
    netlist, _, _ = _spec()
    assert canonical_text(netlist, "n") is netlist  # lcchain's own text is canonical as it is
    assert canonical_text("\ufeff" + netlist, "n") == netlist  # a leading byte-order mark is dropped
    assert canonical_text(netlist.replace("\n", "\r\n"), "n") == netlist  # CRLF reads as LF
    assert canonical_text(netlist.encode("utf-8"), "n") == netlist
    assert circuit_lines(netlist) == netlist_lines(netlist) == netlist.split("\n")
    assert circuit_lines(netlist.rstrip("\n"))[-1] == ""  # ngSpice_Circ is handed a closing empty line
    with pytest.raises(ParameterError, match="U\\+000D"):
        netlist_lines(netlist.replace("\n", "\r\n"))  # a transport runs only a text already made canonical


@pytest.mark.parametrize("data, byte", [
    (b"\xc0\xae", "0xc0"),  # an overlong '.'
    (b"\xe0\x80\xae", "0xe0"),  # another overlong form
    (b"\xed\xa0\x80", "0xed"),  # a UTF-16 surrogate written as UTF-8
    (b"\xff\xfe", "0xff"),  # a UTF-16 byte-order mark
    (b"\x80", "0x80"),  # a lone continuation byte
])
def test_an_invalid_encoding_is_refused_naming_the_line(data: bytes, byte: str, tmp_path: Path) -> None:
    path = tmp_path / "bad.cir"
    path.write_bytes(b"title\n* fine\n* here " + data + b"include x\n.end\n")
    with pytest.raises(ParameterError) as caught:
        batch_plan([path])
    assert "line 3" in str(caught.value) and byte in str(caught.value) and "UTF-8" in str(caught.value)
    with pytest.raises(ParameterError, match="line 3"):
        canonical_text(path.read_bytes(), str(path))


@pytest.fixture(scope="module")
def simulators() -> Iterator[dict[str, Simulator]]:
    batch = find_simulator("batch")
    found = {"batch": batch, "warm": warm.warm_simulator(batch), "shared": find_simulator("shared")}
    yield found
    warm.close_workers(kill=True)


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "warm", "shared"])
def test_no_transport_runs_a_text_that_is_not_canonical(backend: str, simulators: dict[str, Simulator],
                                                        folders: tuple[Path, Path]) -> None:
    # A transport runs a TransportJob, and a TransportJob holds a canonical text only: a text no check made
    # canonical cannot be handed to any transport (refused, naming the line, before ngspice starts).
    folder, secret = folders
    netlist, vectors, tstop = _spec()
    simulator = simulators[backend]
    job = RunJob(netlist, vectors, tstop, foreign=True)
    for char in ("\u2028", "\x85", "\x0c", "\r"):
        text = _hostile(netlist, char, "comment", secret, folder)
        with pytest.raises(ParameterError, match="line 2"):
            TransportJob.checked(text, job)
        with pytest.raises(ParameterError, match="line 2"):
            TransportJob(text, tstop, 60.0, None, None)
    with _placement(simulator, True, None) as place:  # the transport itself runs the checked text it is given
        columns, _, _ = TRANSPORT_RUNS[backend].run(TransportJob.checked(netlist, job), simulator, place, None)
    assert {canonical_vector_name(v) for v in vectors} <= set(columns)
    result = run(job, simulator)  # and through the runner
    assert result.points > 10 and "lcchain-secret-line" not in result.log


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["warm", "shared"])
def test_the_workers_hand_ngspice_the_checked_lines(backend: str, simulators: dict[str, Simulator]) -> None:
    # The shared-library workers report the digest of the lines they gave ngSpice_Circ; the run fails unless it
    # is the digest of the checked text's lines.  Runs of a text with and without its last LF prove both ends.
    netlist, vectors, tstop = _spec()
    for text in (netlist, netlist.rstrip("\n")):
        assert text_digest(circuit_lines(text)) == text_digest(netlist.split("\n"))
        run(RunJob(text, vectors, tstop, foreign=True), simulators[backend])


#: Texts that differ from the plain netlist only in what canonical_text normalises or what every reader splits
#: alike: each must run to the same bits on every transport.
def _variants(netlist: str) -> dict[str, bytes]:
    title, rest = netlist.split("\n", 1)
    lines = netlist.split("\n")
    k = next(i for i in range(1, len(lines)) if lines[i][:1].isalpha())  # the first element line
    words = lines[k].split()
    continued = [*lines[:k], " ".join(words[:2]), "+ " + " ".join(words[2:]), *lines[k + 1:]]
    return {
        "plain": netlist.encode(),
        "continued": "\n".join(continued).encode(),
        "crlf": netlist.replace("\n", "\r\n").encode(),
        "bom": b"\xef\xbb\xbf" + netlist.encode(),
        "mixed": (title + "\r\n" + rest).encode(),
        "backslash": f"{title}\n* a comment ending in a backslash \\\n{rest}".encode(),
        "tabs": netlist.replace(" ", "\t", 3).encode(),
        "unicode comment": f"{title}\n* résumé — ω₀ √(LC) ✓\n{rest}".encode(),
    }


@pytest.mark.ngspice
def test_the_normalised_family_runs_alike_on_every_transport(tmp_path: Path,
                                                             simulators: dict[str, Simulator]) -> None:
    netlist, _, _ = _spec()
    paths = []
    for name, data in _variants(netlist).items():
        path = tmp_path / f"{name.replace(' ', '-')}.cir"
        path.write_bytes(data)
        paths.append(path)
    digests = {}
    for backend, transport in (("batch", "process"), ("batch", "warm"), ("shared", "process")):
        plan = batch_plan(paths, backend=backend)  # type: ignore[arg-type]
        texts = {Path(task.params["netlist"]).stem: task.spec.netlist for task in plan.tasks}
        assert texts["plain"] == texts["crlf"] == texts["bom"] == texts["mixed"]  # one canonical text, one run
        store = tmp_path / f"{backend}-{transport}.sqlite"
        summary = run_plan(plan, store, RunOptions(executor="serial", simulator=simulators[backend], transport=transport))
        assert summary.failed == 0 and summary.ok == summary.total == len(set(texts.values())), (backend, transport)
        with Store(store, "read") as opened:
            digests[backend, transport] = {r.key: r.digest for r in opened.runs()}
    first = next(iter(digests.values()))
    assert len(set(first.values())) == 1  # every variant ran the same circuit to the same bits
    assert all(set(found.values()) == set(first.values()) for found in digests.values())  # on every transport


@pytest.mark.ngspice
def test_a_default_batch_refuses_the_hidden_include_and_runs_nothing(tmp_path: Path,
                                                                     folders: tuple[Path, Path]) -> None:
    # 24 short netlists with no option: --transport auto picks the warm worker.  One hides an include behind
    # U+2028 in a comment; a --strict batch is refused naming it, a default one stores it as refused and runs
    # the others, and the secret reaches no output and no store.
    folder, secret = folders
    netlist, _, _ = _spec()
    paths = []
    for i in range(24):
        path = folder / f"n{i:02d}.cir"
        text = netlist.replace("\n", f" #{i}\n", 1)
        path.write_text(_hostile(text, "\u2028", "comment", secret, folder) if i == 17 else text)
        paths.append(path)
    store = tmp_path / "s.sqlite"
    done = subprocess.run([sys.executable, "-m", "lcchain", "batch", *map(str, paths), "--store", str(store),
                           "--strict"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert done.returncode == 2, done.stderr
    said = done.stderr.strip()
    assert len(said.splitlines()) == 1 and "n17.cir: line 2" in said and "U+2028" in said, said
    assert "lcchain-secret-line" not in done.stdout + done.stderr
    assert not store.exists() or b"lcchain-secret-line" not in store.read_bytes()
    good = [p for p in paths if p.name != "n17.cir"]
    done = subprocess.run([sys.executable, "-m", "lcchain", "batch", *map(str, good), "--store", str(store)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    carried = tmp_path / "carried.sqlite"
    done = subprocess.run([sys.executable, "-m", "lcchain", "batch", *map(str, paths), "--store", str(carried)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert done.returncode == 1, done.stderr
    (said,) = [line for line in done.stdout.splitlines() if line.startswith("refused ")]
    assert "n17.cir: line 2" in said and "U+2028" in said and "23 ok, 0 failed, 1 refused" in done.stdout
    assert "lcchain-secret-line" not in done.stdout + done.stderr
    wal = tmp_path / "carried.sqlite-wal"
    assert b"lcchain-secret-line" not in carried.read_bytes() + (wal.read_bytes() if wal.exists() else b"")


@pytest.mark.ngspice
def test_a_result_is_the_same_whatever_the_line_ends(simulators: dict[str, Simulator]) -> None:
    netlist, vectors, tstop = _spec()
    plain = run(RunJob(netlist, vectors, tstop, foreign=True), simulators["batch"])
    crlf = run(RunJob(netlist.replace("\n", "\r\n"), vectors, tstop, foreign=True), simulators["warm"])
    assert all(np.array_equal(plain.vectors[k], crlf.vectors[k]) for k in plain.vectors)
    assert plain.options == crlf.options


@pytest.mark.parametrize("engine", ["ngspice", "gnucap"])
def test_every_engine_reads_the_lines_at_lf_alone(engine: str) -> None:
    # gnucap's dialect and ngspice's AC plot read the text as the check does: a hidden separator is refused.
    netlist, vectors, _ = _spec()
    hidden = netlist.replace("\n", "\n* note\u2029.include /x\n", 1)
    with pytest.raises(ParameterError, match="U\\+2029"):
        engine_named(engine).dialect(hidden, vectors)


@pytest.mark.ngspice
def test_a_foreign_ac_sweep_runs_the_checked_text(tmp_path: Path, folders: tuple[Path, Path]) -> None:
    folder, secret = folders
    text = "ladder\nV1 1 0 AC 1\nL1 1 2 1e-3\nC1 2 0 1e-6\n.ac lin 20 100 10000\n.save i(l1)\n.end\n"
    good = folder / "ac.cir"
    good.write_text(text.replace("\n", "\r\n"))
    bad = folder / "hidden.cir"
    bad.write_text(text.replace("\nL1", f"\n* see\x85.include {secret}\nL1"))
    with pytest.raises(ParameterError, match="hidden.cir: line 3.*U\\+0085"):
        batch_plan([bad])
    plan = batch_plan([good])
    assert "\r" not in plan.tasks[0].spec.netlist
    summary = run_plan(plan, tmp_path / "ac.sqlite", RunOptions(executor="serial"))
    assert summary.ok == 1


# --------------------------------------------------------------------------- the catalogue's family

TOUCH = f"shell touch {{here}}/{MARKER}"


def _catalogue_netlist(char: str, place: str) -> dict[str, str | bytes]:
    hidden = f"{char}.control{char}{TOUCH}{char}.endc"
    body = LADDER.split("\n", 1)[1]
    texts: dict[str, str] = {
        "title": f"ladder{hidden}\n{body}",
        "comment": f"ladder\n* note{hidden}\n{body}",
        "inline": f"ladder\n{body.replace(chr(10), ' ; note' + hidden + chr(10), 1)}",
        "element": f"ladder\n{body.replace(chr(10), hidden + chr(10), 1)}",
        "included": f"ladder\n.include part.inc\n{body}",
    }
    files: dict[str, str | bytes] = {"n.cir": texts[place]}
    if place == "included":
        files["part.inc"] = f"* part{hidden}\n"
    return files


def _refused(said: list[str], files: dict[str, str | bytes]) -> Case:
    return Case(["batch", "n.cir", "--store", "s.sqlite"], said, files=files, family="canonical text")


#: Run by ``python tests/catalogue.py`` too: every hidden separator in a comment, U+2028 in every place, and the
#: invalid encodings, through ``lcchain batch`` as a user runs it.
CASES: dict[str, Case] = {
    **{f"{name} in a comment": _refused(["n.cir: line 2", name], _catalogue_netlist(char, "comment"))
       for char, name in HOSTILE.items()},
    **{f"U+2028 in the {place}": _refused(["part.inc: line 1" if place == "included" else
                                           f"n.cir: line {1 if place == 'title' else 2}", "U+2028"],
                                          _catalogue_netlist("\u2028", place))
       for place in PLACES if place != "comment"},
    **{f"invalid UTF-8 {data!r}": _refused(["n.cir", "line 2", "UTF-8"], {"n.cir": b"ladder\n* " + data + b"\n"
                                                                       + LADDER.split("\n", 1)[1].encode()})
       for data in (b"\xc0\xae", b"\xe0\x80\xae", b"\xed\xa0\x80", b"\x80", b"\xf8\x88\x80\x80\x80")},
    "a UTF-16 file": _refused(["n.cir", "line 1", "UTF-8"], {"n.cir": LADDER.encode("utf-16")}),
}


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_the_canonical_family_is_refused_cleanly(case: Case, tmp_path: Path) -> None:
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail
    assert not (tmp_path / "s.sqlite").exists()


@pytest.mark.parametrize("char", ["\u2028", "\x85", "\ufeff", "\r"], ids=["U+2028", "U+0085", "U+FEFF", "U+000D"])
def test_a_title_lcchain_writes_is_canonical_or_refused_naming_the_option(char: str,
                                                                          capsys: pytest.CaptureFixture[str]) -> None:
    # lcchain's own netlists reach the same transports: a title that would not be canonical is refused as --title.
    assert main(["netlist", "--case", "two-mass", "--N", "5", "--title", f"a{char}b"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lcchain: --title = ") and len(err.splitlines()) == 1


@pytest.mark.parametrize("title", ["T" * 401, "é" * 201, "A" * 100_000], ids=["401 bytes", "402 bytes of é",
                                                                              "100,000"])
def test_a_title_ngspice_cannot_hold_is_refused(title: str, tmp_path: Path) -> None:
    # ngspice 39 reads the title into a fixed buffer: 505 bytes abort it, a 100,000-character title spilled into
    # the next card (read as a transmission line). A canonical text's title holds at most 400 bytes, on every path.
    netlist, _, _ = _spec()
    text = title + "\n" + netlist.split("\n", 1)[1]
    for checked in (lambda: canonical_text(text, "n.cir"), lambda: allowed_netlist(text, "n.cir", None)):
        with pytest.raises(ParameterError, match="n.cir: line 1 .*a title of at most 400 bytes"):
            checked()
    assert canonical_text("T" * 400 + "\n" + netlist.split("\n", 1)[1], "n.cir")
