"""``lcchain batch --from LIST``: the netlists a file (or standard input) lists, one name a line, beside those
given; more names than a command line holds, and none copied into the interpreter's own arguments."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.netlists import RC_NETLIST

from lcchain.app.batch import listed_names
from lcchain.cli.main import main


def rc_netlists(folder: Path, count: int) -> list[str]:
    names = []
    for i in range(count):
        path = folder / f"rc{i}.cir"
        path.write_text(RC_NETLIST.replace("R1 in out 1000", f"R1 in out {1000 + i}"))
        names.append(path.name)
    return names


def test_a_list_is_its_lines_without_the_blank_ones(tmp_path: Path) -> None:
    (tmp_path / "names.txt").write_bytes(b"a.cir\n\n  \nsub dir/b c.cir\r\nd.cir")
    assert tuple(listed_names(str(tmp_path / "names.txt"))) == ("a.cir", "sub dir/b c.cir", "d.cir")


@pytest.mark.ngspice
def test_listed_and_given_netlists_run_together(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    names = rc_netlists(tmp_path, 3)
    Path("names.txt").write_text(f"{names[0]}\n\n{names[1]}\n")
    assert main(["batch", "--from", "names.txt", names[2], "--store", "s.sqlite"]) == 0
    assert "3 ok" in capsys.readouterr().out


@pytest.mark.ngspice
def test_names_piped_to_standard_input(tmp_path: Path) -> None:
    names = rc_netlists(tmp_path, 2)
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    done = subprocess.run([sys.executable, "-m", "lcchain", "batch", "--from", "-", "--store", "s.sqlite"],
                          input="\n".join(names) + "\n", capture_output=True, text=True, cwd=tmp_path, env=env)
    assert done.returncode == 0, done.stderr
    assert "2 ok" in done.stdout


@pytest.mark.parametrize(("argv", "said"), [
    (["batch", "--store", "s.sqlite"], ["NETLIST", "--from LIST"]),
    (["batch", "--from", "missing.txt", "--store", "s.sqlite"], ["--from", "missing.txt", "readable file"]),
    (["batch", "--from", ".", "--store", "s.sqlite"], ["--from", "regular file"]),
])
def test_no_netlist_or_a_bad_list_is_one_line(argv: list[str], said: list[str], tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(word in err for word in said), err
    assert not (tmp_path / "s.sqlite").exists()


@pytest.mark.parametrize(("data", "said"), [(b"\xff\xfe.cir\n", "UTF-8"), (None, "at most")],
                         ids=["not UTF-8", "endless"])
def test_bad_names_on_standard_input_are_one_line(data: bytes | None, said: str, tmp_path: Path) -> None:
    """Standard input is read up to the list's limit: a stream without end (here the limit and one byte more) is
    refused, not read on."""
    from lcchain.core.limits import MAX_NETLIST_LIST_BYTES

    given = data if data is not None else b"a" * (MAX_NETLIST_LIST_BYTES + 1)
    done = subprocess.run([sys.executable, "-m", "lcchain", "batch", "--from", "-", "--store", "s.sqlite"],
                          input=given, capture_output=True, cwd=tmp_path)
    err = done.stderr.decode().strip()
    assert done.returncode == 2 and len(err.splitlines()) == 1 and "--from" in err and said in err, err
    assert not (tmp_path / "s.sqlite").exists()


def test_a_byte_order_mark_opens_a_list_and_is_no_part_of_its_first_name(tmp_path: Path) -> None:
    (tmp_path / "names.txt").write_bytes(b"\xef\xbb\xbfa.cir\nb.cir\n")
    assert tuple(listed_names(str(tmp_path / "names.txt"))) == ("a.cir", "b.cir")


@pytest.mark.ngspice
def test_a_listed_name_with_a_nul_byte_is_refused_and_the_others_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """A list written by ``find -print0``: its NUL-joined names name no file, refused as a missing one is."""
    monkeypatch.chdir(tmp_path)
    names = rc_netlists(tmp_path, 2)
    Path("names.txt").write_bytes(f"{names[0]}\n{names[1]}\0other.cir\n".encode())
    assert main(["batch", "--from", "names.txt", "--store", "s.sqlite"]) == 1
    said = capsys.readouterr().out.splitlines()
    assert "1 ok" in said[0] and "1 refused" in said[0]
    assert said[1:] == [f"refused {names[1]}\\x00other.cir: NETLIST = '{names[1]}\\x00other.cir' is not allowed: "
                        "expected the name of a file (a name holds no NUL byte)"]
