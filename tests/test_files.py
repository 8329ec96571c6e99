"""Output files: whole or not at all, under the name and with the mode a user expects."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from lcchain.core.errors import ParameterError
from lcchain.report.files import atomic_path, check_output, write_text


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


def test_a_device_is_written_in_place_not_replaced(tmp_path: Path) -> None:
    write_text("/dev/null", "nothing")
    assert Path("/dev/null").is_char_device()


@pytest.mark.parametrize("name, formats, said", [
    ("plot", ("png",), ".png"), ("x.png/", None, "not a folder"), ("missing/x.png", ("png",), "does not exist"),
])
def test_check_output_refuses_what_could_not_be_written_as_named(tmp_path: Path, name: str,
                                                                  formats: tuple[str, ...] | None, said: str) -> None:
    with pytest.raises(ParameterError, match=said.replace(".", r"\.")):
        check_output("--plot", f"{tmp_path}/{name}", formats)
    assert list(tmp_path.iterdir()) == []
