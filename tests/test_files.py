"""Output files: whole or not at all, under the name and with the mode a user expects.

Every test works inside its own ``tmp_path``: a special file is a FIFO made
there, never a device of the machine (CI runs as root, where a regression
could replace ``/dev/null`` itself).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from lcchain.core.errors import ParameterError
from lcchain.report.files import (
    atomic_path,
    check_inside,
    check_not_input,
    check_output,
    check_output_folder,
    same_file,
    write_text,
)


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "report.json"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as temporary:
        temporary.write_text("half")
        raise RuntimeError("interrupted")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["report.json"]


def test_a_new_file_gets_the_umask_mode_and_an_old_one_keeps_its_own(tmp_path: Path) -> None:
    umask = os.umask(0o022)
    try:
        fresh = write_text(tmp_path / "new.csv", "t,first,last\n")
        assert stat.S_IMODE(fresh.stat().st_mode) == 0o644
        kept = tmp_path / "kept.csv"
        kept.write_text("x")
        kept.chmod(0o600)
        write_text(kept, "y")
        assert stat.S_IMODE(kept.stat().st_mode) == 0o600 and kept.read_text() == "y"
    finally:
        os.umask(umask)


def test_a_special_file_is_written_in_place_not_replaced(tmp_path: Path) -> None:
    """A FIFO (what ``/dev/stdout`` is in a pipeline) receives the text; renaming over it would replace it."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # a reader is there: the writer's open does not wait
    try:
        write_text(fifo, "nothing")  # a few bytes: the pipe's buffer holds them until they are read
        assert os.read(reader, 100) == b"nothing"
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["pipe"]


def test_a_fifo_nobody_reads_is_an_error_not_a_wait(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="No such device"):
        write_text(fifo, "nothing")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_a_name_near_the_system_limit_is_written(tmp_path: Path) -> None:
    """The temporary name beside it is cut short, so a legal name never fails for want of room."""
    name = "n" * 251 + ".csv"
    check_output("--waveform-out", tmp_path / name)
    assert write_text(tmp_path / name, "x").read_text() == "x"


@pytest.mark.parametrize("name, formats, said", [
    ("plot", ("png",), ".png"), ("x.png/", None, "not a folder"), ("missing/x.png", ("png",), "does not exist"),
    ("n" * 300 + ".png", ("png",), "at most 255 bytes"),
])
def test_check_output_refuses_what_could_not_be_written_as_named(tmp_path: Path, name: str,
                                                                  formats: tuple[str, ...] | None, said: str) -> None:
    with pytest.raises(ParameterError, match=said.replace(".", r"\.")):
        check_output("--plot", f"{tmp_path}/{name}", formats)
    assert list(tmp_path.iterdir()) == []


def test_a_missing_folder_is_accepted_only_when_the_caller_makes_it_and_nothing_is_made(tmp_path: Path) -> None:
    check_output("output.report", tmp_path / "made" / "later" / "r.json", make_folder=True)
    (tmp_path / "file").write_text("x")
    with pytest.raises(ParameterError, match="is a file"):
        check_output("output.report", tmp_path / "file" / "below" / "r.json", make_folder=True)
    check_output_folder("--out", tmp_path / "a" / "b", parents=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


@pytest.mark.parametrize("name, said", [("", "empty name"), ("file", "this is a file"),
                                        ("missing/deeper", "does not exist")])
def test_check_output_folder_refuses_what_is_no_folder(tmp_path: Path, name: str, said: str) -> None:
    (tmp_path / "file").write_text("x")
    with pytest.raises(ParameterError, match=said):
        check_output_folder("--out", str(tmp_path / name) if name else "")


def test_an_input_is_recognised_under_another_name(tmp_path: Path) -> None:
    scene = tmp_path / "s.toml"
    scene.write_text("x")
    os.link(scene, tmp_path / "hard.toml")
    os.symlink(scene, tmp_path / "soft.toml")
    for other in ("s.toml", "./s.toml", "hard.toml", "soft.toml"):
        assert same_file(tmp_path / other, scene)
        with pytest.raises(ParameterError, match="SCENE reads"):
            check_not_input("--netlist-out", tmp_path / other, [("SCENE", str(scene))])
    assert not same_file(tmp_path / "new.cir", scene)


def test_a_symlinked_folder_that_leads_outside_is_refused(tmp_path: Path) -> None:
    inside, outside = tmp_path / "work", tmp_path / "elsewhere"
    inside.mkdir()
    outside.mkdir()
    os.symlink(outside, inside / "out")
    (inside / "sub").mkdir()
    check_inside("output.report", "sub/r.json", inside)
    with pytest.raises(ParameterError, match="stays in the current folder"):
        check_inside("output.report", "out/r.json", inside)
