"""A study stopped by a full disk, a kill in a checkpoint or a read-only folder resumes (issue 29, item 3).

Each test runs a real ``lcchain sweep`` of eight tiny runs (real ngspice), stops
it the way the world does, and runs the same command again. It counts: the
runs stored before the stop are neither lost nor run again (their rows keep
their digest and the time they were stored), and the store ends holding the
whole plan.

What stops the study is real: a tmpfs that fills (its own, mounted under the
test's folder, with a filler file in it) and is then enlarged; a driver
killed with SIGKILL, and a checkpoint of its store killed midway by the kernel
(SIGXFSZ at its default action when the main file reaches a set size, so the
kill lands in the checkpoint every time); a folder made read-only (a
read-only bind mount as root, who ignores permission bits; ``chmod``
otherwise). Mounting needs root, as in CI; a test that needs it skips, saying
so, without.

Every case leaves a store whose committed runs are partly only in its
``-wal``, and whose main file is torn where a checkpoint stopped: SQLite reads
it whole, with its log, and so must lcchain (it once checked the main file
alone and called such a store malformed).
"""

from __future__ import annotations

import contextlib
import json
import os
import resource
import signal
import sqlite3
import stat
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from helpers.catalogue import tree
from helpers.netlists import stored_records
from helpers.processes import reaped

from lcchain.cli import main
from lcchain.core.errors import ParameterError
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import SweepAxes, sweep_plan
from lcchain.studies.run import run_plan

pytestmark = pytest.mark.ngspice

#: The study: eight runs of a few ms each in ngspice (the uniform free chain needs no design), about 16 kB of
#: arrays apiece in the store.
PLAN = 8
SWEEP = ["sweep", "--case", "uniform-free", "--N", "10,12,14,16,18,20,22,24", "--dt", "0.05", "--executor",
         "serial", "--store", "s.sqlite", "--json"]
#: Room left on the small disk for the store: its plan, its -shm and the log of a few runs, not eight.
ROOM = 128 * 1024


def _stored(path: Path) -> dict[str, tuple[str, float]]:
    """key -> (digest, when it was stored) of every run in the store, as SQLite reads it (with its log)."""
    with contextlib.closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True)) as db:
        return {key: (digest, finished) for key, digest, finished in
                db.execute("SELECT key, digest, finished FROM records")}


def _main(argv: list[str], folder: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    """The command run in ``folder`` as a user would; the folder's path is looked up afresh, so that a mount made
    on it since is the one seen."""
    with contextlib.chdir(folder):
        status = main(argv)
    out, err = capsys.readouterr()
    return status, out, err


def _said(err: str) -> list[str]:
    """What the command said on stderr, without its progress lines."""
    return [line for line in err.splitlines() if line.strip() and " runs, " not in line]


def _resumes(folder: Path, before: dict[str, tuple[str, float]], capsys: pytest.CaptureFixture[str]) -> None:
    """The same command again: it runs what is missing and nothing else, and the store holds the whole plan."""
    status, out, err = _main(SWEEP, folder, capsys)
    assert status == 0, err
    summary = json.loads(out)
    assert (summary["total"], summary["skipped"], summary["ran"], summary["ok"]) == (
        PLAN, len(before), PLAN - len(before), PLAN), summary
    after = _stored(folder / "s.sqlite")
    assert len(after) == PLAN
    assert {key: after[key] for key in before} == before  # not one stored run was run again, or lost


@pytest.fixture
def scratch(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A temporary folder for the commands (ngspice's files) inside the test's own, beside the study's."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setenv("TMPDIR", str(folder))
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


def _mount(*args: str) -> None:
    done = subprocess.run(["mount", *args], capture_output=True, text=True, timeout=30)
    if done.returncode != 0:
        raise OSError(done.stderr.strip() or f"mount {' '.join(args)} failed")


def _unmount(folder: Path) -> None:
    """Unmounted now, or (a file still open there after a failed assertion) detached now and gone once closed."""
    if subprocess.run(["umount", str(folder)], capture_output=True, timeout=30).returncode != 0:
        subprocess.run(["umount", "--lazy", str(folder)], capture_output=True, timeout=30, check=True)


@contextlib.contextmanager
def _tmpfs(folder: Path, size: int) -> Iterator[Callable[[str], None]]:
    """A tmpfs of ``size`` bytes mounted on ``folder``, unmounted at the end; yields ``remount(options)``."""
    if os.geteuid() != 0:
        pytest.skip("mounting a small tmpfs needs root (CI runs as root)")
    folder.mkdir()
    try:
        _mount("-t", "tmpfs", "-o", f"size={size},mode=0755", "tmpfs", str(folder))
    except OSError as error:
        pytest.skip(f"mount is not permitted here: {error}")
    try:
        yield lambda options: _mount("-o", f"remount,{options}", str(folder))
    finally:
        _unmount(folder)


@contextlib.contextmanager
def _read_only(folder: Path) -> Iterator[None]:
    """``folder`` read-only for this block: a read-only bind mount as root (who ignores permission bits), else
    ``chmod`` of the folder and its files."""
    if os.geteuid() == 0:
        try:
            _mount("--bind", str(folder), str(folder))
        except OSError as error:
            pytest.skip(f"a read-only bind mount is not permitted here: {error}")
        try:
            _mount("-o", "remount,bind,ro", str(folder))
            yield
        finally:
            _unmount(folder)
        return
    modes = {path: path.stat().st_mode for path in [folder, *folder.iterdir()]}
    try:
        for path, mode in modes.items():
            path.chmod(stat.S_IMODE(mode) & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))
        yield
    finally:
        for path, mode in modes.items():
            path.chmod(stat.S_IMODE(mode))


# ------------------------------------------------------------------ a full disk


def test_a_full_disk_resumes_with_no_run_lost_or_redone(tmp_path: Path, scratch: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    disk = tmp_path / "disk"
    with _tmpfs(disk, 1024 * 1024) as remount:
        free = os.statvfs(disk).f_bavail * os.statvfs(disk).f_frsize
        (disk / "filler").write_bytes(bytes(free - ROOM))
        status, out, err = _main(SWEEP, disk, capsys)
        said = _said(err)
        assert status == 1 and out == "" and "Traceback" not in err, err
        assert len(said) == 1 and "s.sqlite" in said[0], said
        assert "make room and run the same command to resume" in said[0]
        stored = _stored(disk / "s.sqlite")
        assert 1 <= len(stored) < PLAN
        status, out, err = _main(["results", "s.sqlite", "--json"], disk, capsys)  # what the user sees meanwhile
        assert status == 0, err
        assert [run["status"] for run in json.loads(out)].count("ok") == len(stored)
        remount("size=8m")  # the disk enlarged, the filler still on it
        _resumes(disk, stored, capsys)


# ------------------------------------------------------------------ a kill, then a kill in a checkpoint


def _stop_in_a_checkpoint(path: Path) -> None:
    """A checkpoint of the store killed midway: the kernel kills the checkpointing process (SIGXFSZ, its default
    action) when the main file would grow a page past its size, once the pages before are copied in."""
    limit = max(path.stat().st_size, Path(f"{path}-shm").stat().st_size) + 4096
    before = path.stat().st_size

    def small_files() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

    checkpoint = ("import signal, sqlite3, sys; signal.signal(signal.SIGXFSZ, signal.SIG_DFL); "
                  "sqlite3.connect(sys.argv[1]).execute('PRAGMA wal_checkpoint(TRUNCATE)').fetchall()")
    done = subprocess.run([sys.executable, "-B", "-c", checkpoint, str(path)], capture_output=True, text=True,
                          timeout=60, preexec_fn=small_files)
    assert done.returncode == -signal.SIGXFSZ, done.stderr
    assert path.stat().st_size > before  # the checkpoint was under way: pages of the log are in the main file


def _killed_study(folder: Path) -> dict[str, tuple[str, float]]:
    """The sweep's driver killed with SIGKILL once it stored two runs, then a checkpoint of its store killed
    midway; the runs stored, as SQLite reads them."""
    driver = subprocess.Popen([sys.executable, "-m", "lcchain", *SWEEP], cwd=folder, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE)
    with reaped(driver):
        deadline = time.monotonic() + 300  # a guard against a hung driver, not a measurement
        while driver.poll() is None and stored_records(folder / "s.sqlite") < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert driver.poll() is None, "the driver finished before it could be killed"
        driver.send_signal(signal.SIGKILL)
        driver.communicate(timeout=60)
    assert driver.returncode == -signal.SIGKILL
    stored = _stored(folder / "s.sqlite")
    assert 2 <= len(stored) < PLAN
    _stop_in_a_checkpoint(folder / "s.sqlite")
    assert _stored(folder / "s.sqlite") == stored  # the torn main file and its log hold every run still
    return stored


def test_a_kill_in_a_checkpoint_resumes_with_no_run_lost_or_redone(tmp_path: Path, scratch: Path,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    study = tmp_path / "study"
    study.mkdir()
    stored = _killed_study(study)
    _resumes(study, stored, capsys)


# ------------------------------------------------------------------ a read-only folder


def test_a_read_only_folder_resumes_with_no_run_lost_or_redone(tmp_path: Path, scratch: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    study = tmp_path / "study"
    study.mkdir()
    stored = _killed_study(study)
    before = tree(study)
    with _read_only(study):
        status, out, err = _main(["results", "s.sqlite", "--json"], study, capsys)
        assert status == 0, err
        assert [run["status"] for run in json.loads(out)].count("ok") == len(stored)
        status, out, err = _main(SWEEP, study, capsys)
        assert status == 2 and out == "" and len(_said(err)) == 1 and "Traceback" not in err, err
        assert "--store = 's.sqlite'" in err and "writable" in err
        with pytest.raises(ParameterError) as refused:  # from Python, past the command line's check of the folder
            run_plan(sweep_plan(SweepAxes(cases=["uniform-free"], Ns=list(range(10, 26, 2)), dts=[0.05])), study / "s.sqlite", RunOptions(executor="serial"))
        assert "s.sqlite" in str(refused.value) and "writable and run the same command" in str(refused.value)
    assert tree(study) == before
    # the store and its log copied to read-only media without the -shm: SQLite cannot read the log there, and
    # lcchain says so rather than read the torn main file alone
    (study / "s.sqlite-shm").unlink()
    before = tree(study)
    with _read_only(study):
        status, out, err = _main(["results", "s.sqlite", "--json"], study, capsys)
        assert status == 2 and out == "" and len(_said(err)) == 1 and "Traceback" not in err, err
        assert "s.sqlite-wal" in err and "writable" in err
    assert tree(study) == before
    _resumes(study, stored, capsys)
