"""Stores several people and programs can share, and a Dask that leaves nothing behind (issue 19, sections 4, 5).

With real ngspice, real SQLite files and real processes: ``results`` changes
nothing (read-only media included); a file that is not an lcchain store is
refused before a byte of it is written; one driver writes a store at a time
(a second is refused naming the first, or waits); a corrupt page, a tampered
row and a full disk are one line each and lose nothing committed; a failed run
runs again with ``--retry-failed``; options are checked before a store
exists; a Dask sweep leaves nothing in TMPDIR and says nothing of Dask
without ``-v``.

Tests run as root, where file permissions do not bind: read-only media are
made with a read-only bind mount (bubblewrap) instead of ``chmod``.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import socket
import sqlite3
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers.catalogue import Case, run_case, tree
from helpers.netlists import stored_records
from helpers.processes import descendants, temporary_entries

from lcchain.cli import main
from lcchain.core.errors import LcchainError, ParameterError
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import SweepAxes, sweep_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store

pytestmark = pytest.mark.ngspice

ROOT = Path(__file__).resolve().parent.parent
#: The smallest study with arrays: two runs of a four-mass chain (a few ms each in ngspice).
TINY = ["--case", "two-mass", "--N", "4", "--dt", "0.05,0.04"]


def _store(folder: Path, name: str = "s.sqlite") -> Path:
    path = folder / name
    summary = run_plan(sweep_plan(SweepAxes(cases=["two-mass"], Ns=[4], dts=[0.05, 0.04])), path, RunOptions(executor="serial"))
    assert summary.ok == 2
    return path


def _make_store(folder: Path) -> None:
    _store(folder)


def _tampered(*statements: str) -> Callable[[Path], None]:
    """A store changed outside lcchain by these SQL statements."""

    def make(folder: Path) -> None:
        with sqlite3.connect(_store(folder)) as db:
            for statement in statements:
                db.execute(statement)
        db.close()

    return make


def _corrupt(folder: Path) -> None:
    """A store whose pages after the first were partly overwritten (a disk that lost them)."""
    path = _store(folder)
    size = path.stat().st_size
    with path.open("r+b") as file:
        for page in range(1, size // 4096):
            file.seek(page * 4096)
            file.write(b"\xa5" * 64)


def _foreign(folder: Path) -> None:
    with sqlite3.connect(folder / "o.sqlite") as db:
        db.execute("CREATE TABLE users (name TEXT)")
        db.execute("INSERT INTO users VALUES ('ada')")
    db.close()


def _fifo(folder: Path) -> None:
    os.mkfifo(folder / "f.sqlite")


def _folder(folder: Path) -> None:
    (folder / "d.sqlite").mkdir()


NETLIST = (ROOT / "netlists" / "perfect-N3.cir").read_text()
SWEEP = ["sweep", *TINY, "--executor", "serial", "--store"]

CASES: dict[str, Case] = {
    # -------------------------------------------------- what is not an lcchain store is refused, untouched
    "sweep into someone's SQLite database": Case([*SWEEP, "o.sqlite"], ["--store", "o.sqlite", "users"],
                                                 make=_foreign, family="stores"),
    "batch into someone's SQLite database": Case(["batch", "n.cir", "--store", "o.sqlite"],
                                                 ["--store", "o.sqlite", "lcchain store"],
                                                 files={"n.cir": NETLIST}, make=_foreign, family="stores"),
    "sweep into an empty file": Case([*SWEEP, "e.sqlite"], ["--store", "e.sqlite", "empty file"],
                                     files={"e.sqlite": b""}, family="stores"),
    "sweep into a text file": Case([*SWEEP, "t.sqlite"], ["--store", "t.sqlite", "not an SQLite database"],
                                   files={"t.sqlite": "my notes\n"}, family="stores"),
    "sweep into a FIFO": Case([*SWEEP, "f.sqlite"], ["--store", "f.sqlite", "FIFO"], make=_fifo, family="stores"),
    "sweep into a folder": Case([*SWEEP, "d.sqlite"], ["--store", "d.sqlite", "folder"], make=_folder,
                                family="stores"),
    "sweep into a dangling link": Case([*SWEEP, "l.sqlite"], ["--store", "l.sqlite", "link"],
                                       make=lambda f: (f / "l.sqlite").symlink_to(f / "gone.sqlite"),
                                       family="stores"),
    "sweep into a store with another table": Case([*SWEEP, "s.sqlite"], ["--store", "s.sqlite", "extra"],
                                                  make=_tampered("CREATE TABLE extra (x)"), family="stores"),
    "sweep into a store with a trigger": Case([*SWEEP, "s.sqlite"], ["--store", "s.sqlite", "lcchain store"],
                                              make=_tampered("CREATE TRIGGER t AFTER INSERT ON records BEGIN "
                                                             "DELETE FROM records; END"), family="stores"),
    "sweep into a store of another format": Case([*SWEEP, "s.sqlite"], ["--store", "s.sqlite", "format 1"],
                                                 make=_tampered("UPDATE meta SET value = '9' WHERE name = "
                                                                "'format'"), family="stores"),
    "results of a missing store": Case(["results", "missing.sqlite"], ["STORE", "missing.sqlite", "existing"],
                                       family="stores"),
    "results of someone's SQLite database": Case(["results", "o.sqlite"], ["STORE", "users"], make=_foreign,
                                                 family="stores"),
    "results of an empty file": Case(["results", "e.sqlite"], ["STORE", "empty file"], files={"e.sqlite": b""},
                                     family="stores"),
    "results of a text file": Case(["results", "t.sqlite"], ["STORE", "not an SQLite database"],
                                   files={"t.sqlite": "my notes\n"}, family="stores"),
    "results of a FIFO": Case(["results", "f.sqlite"], ["STORE", "FIFO"], make=_fifo, family="stores"),
    "results of a folder": Case(["results", "d.sqlite"], ["STORE", "folder"], make=_folder, family="stores"),
    # -------------------------------------------------- read-only: results changes nothing
    "results of a store": Case(["results", "s.sqlite"], [], status=0, make=_make_store,
                               one_line=False, family="stores"),
    "results --summary of a store": Case(["results", "s.sqlite", "--summary", "--json"], [], status=0,
                                         make=_make_store, one_line=False, family="stores"),
    # -------------------------------------------------- corrupt pages and tampered rows: one line, what to do
    "results of a corrupt store": Case(["results", "s.sqlite"], ["STORE", "s.sqlite", "malformed", "restore"],
                                       make=_corrupt, family="stores"),
    "sweep into a corrupt store": Case([*SWEEP, "s.sqlite"], ["--store", "s.sqlite", "malformed", "restore"],
                                       make=_corrupt, family="stores"),
    "results of metrics that are not JSON": Case(["results", "s.sqlite"], ["STORE", "s.sqlite", "not JSON",
                                                                           "restore"],
                                                 make=_tampered("UPDATE records SET metrics = '{oops'"),
                                                 family="stores"),
    "sweep into metrics that are not JSON": Case([*SWEEP, "s.sqlite"], ["--store", "not JSON", "restore"],
                                                 make=_tampered("UPDATE records SET metrics = '{oops'"),
                                                 family="stores"),
    "results of an unknown status": Case(["results", "s.sqlite"], ["STORE", "status", "restore"],
                                         make=_tampered("UPDATE records SET status = 'done'"), family="stores"),
    "results of params that are a list": Case(["results", "s.sqlite"], ["STORE", "not a JSON object"],
                                              make=_tampered("UPDATE tasks SET params = '[1, 2]'"),
                                              family="stores"),
    "results of a wall time that is text": Case(["results", "s.sqlite"], ["STORE", "wrong type", "restore"],
                                                make=_tampered("UPDATE records SET wall_s = 'fast'"),
                                                family="stores"),
    "results of a task label that is a blob": Case(["results", "s.sqlite"], ["STORE", "wrong type", "restore"],
                                                   make=_tampered("UPDATE tasks SET label = X'00'"),
                                                   family="stores"),
    "sweep into a description that is not JSON": Case(
        ["sweep", "--case", "one-mass", "--N", "4", "--executor", "serial", "--store", "s.sqlite"],
        ["--store", "description", "not JSON"],
        make=_tampered("UPDATE meta SET value = '{' WHERE name = 'description'"), family="stores"),
    # -------------------------------------------------- options are checked before a store exists
    "scheduler with a broken IPv6 address": Case([*SWEEP[:-3], "--executor", "dask", "--scheduler", "tcp://[::1",
                                                  "--store", "s.sqlite"], ["--scheduler", "tcp://[::1"],
                                                 family="stores"),
    "scheduler port that is not a number": Case([*SWEEP[:-3], "--executor", "dask", "--scheduler",
                                                 "localhost:notaport", "--store", "s.sqlite"],
                                                ["--scheduler", "notaport"], family="stores"),
    "scheduler over http": Case([*SWEEP[:-3], "--executor", "dask", "--scheduler", "http://127.0.0.1:8786",
                                 "--store", "s.sqlite"], ["--scheduler", "http://"], family="stores"),
    "scheduler with a path": Case([*SWEEP[:-3], "--executor", "dask", "--scheduler", "tcp://127.0.0.1:8786/x",
                                   "--store", "s.sqlite"], ["--scheduler", "HOST:PORT"], family="stores"),
    "scheduler port zero": Case([*SWEEP[:-3], "--executor", "dask", "--scheduler", "127.0.0.1:0",
                                 "--store", "s.sqlite"], ["--scheduler", "HOST:PORT"], family="stores"),
    "scheduler without dask": Case([*SWEEP[:-3], "--scheduler", "tcp://127.0.0.1:8786", "--store", "s.sqlite"],
                                   ["--scheduler", "--executor dask"], family="stores"),
    "scheduler on batch": Case(["batch", "n.cir", "--executor", "dask", "--scheduler", "tcp://[::1",
                                "--store", "s.sqlite"], ["--scheduler"], files={"n.cir": NETLIST},
                               family="stores"),
    "workers zero": Case([*SWEEP[:-3], "--workers", "0", "--store", "s.sqlite"], ["--workers = 0", ">= 1"],
                         family="stores"),
    "workers negative": Case([*SWEEP[:-3], "--workers", "-3", "--store", "s.sqlite"], ["--workers = -3"],
                             family="stores"),
    "study beyond its time budget": Case([*SWEEP, "s.sqlite", "--max-time", "0.001s"], ["--max-time"],
                                         family="stores"),
}


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_bad_stores_and_study_options_are_refused_cleanly(case: Case, tmp_path: Path) -> None:
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail


# ------------------------------------------------------------------ read-only


def test_results_reads_a_store_a_driver_is_writing(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A writer holds the lock and its WAL: results still reads every committed run, and adds no file."""
    path = _store(tmp_path)
    with Store(path):  # a driver, holding the store (its -wal and -shm exist meanwhile)
        listing = sorted(os.listdir(tmp_path))
        assert main(["results", str(path), "--json"]) == 0
        assert sorted(os.listdir(tmp_path)) == listing
    assert [run["status"] for run in json.loads(capsys.readouterr().out)] == ["ok", "ok"]


def test_results_leaves_the_store_as_it_was(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _store(tmp_path)
    before = (path.read_bytes(), path.stat().st_mtime_ns, sorted(os.listdir(tmp_path)))
    for extra in ([], ["--json"], ["--csv"], ["--summary"], ["--summary", "--metric", "energy"]):
        assert main(["results", str(path), *extra]) == 0
    capsys.readouterr()
    assert (path.read_bytes(), path.stat().st_mtime_ns, sorted(os.listdir(tmp_path))) == before


def _bwrap_works() -> bool:
    bwrap = shutil.which("bwrap")
    if bwrap is None:
        return False
    done = subprocess.run([bwrap, "--dev-bind", "/", "/", "true"], capture_output=True, timeout=30)
    return done.returncode == 0


def _format_1(path: Path) -> None:
    """The store as lcchain wrote it before there were engines (format 1): the engine's column and meta row were
    named ``ngspice_version`` and held ngspice's version alone."""
    with sqlite3.connect(path) as db:
        db.execute("ALTER TABLE records RENAME COLUMN engine TO ngspice_version")
        db.execute("UPDATE records SET ngspice_version = substr(ngspice_version, 9) "
                   "WHERE ngspice_version LIKE 'ngspice %'")
        db.execute("UPDATE meta SET name = 'ngspice_version', value = substr(value, 9) WHERE name = 'engine'")
        db.execute("UPDATE meta SET value = '1' WHERE name = 'format'")
    db.close()


def test_a_format_1_store_reads_as_it_did_and_a_study_migrates_it(tmp_path: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    path = _store(tmp_path)
    assert main(["results", str(path), "--json"]) == 0
    made = json.loads(capsys.readouterr().out)
    _format_1(path)
    before = path.read_bytes()
    assert main(["results", str(path), "--json"]) == 0  # read as it is, and left so
    assert json.loads(capsys.readouterr().out) == made and path.read_bytes() == before
    assert {(run["engine"], run["engine_version"]) for run in made} == {("ngspice", made[0]["engine_version"])}
    again = run_plan(sweep_plan(SweepAxes(cases=["two-mass"], Ns=[4], dts=[0.05, 0.04])), path, RunOptions(executor="serial"))
    assert (again.skipped, again.ran) == (2, 0)  # resumed: every run kept
    with sqlite3.connect(path) as db:
        columns = [row[1] for row in db.execute("PRAGMA table_info(records)")]
        engines = {row[0] for row in db.execute("SELECT engine FROM records")}
        meta = dict(db.execute("SELECT name, value FROM meta").fetchall())
    db.close()
    assert "engine" in columns and "ngspice_version" not in columns
    assert engines == {f"ngspice {made[0]['engine_version']}"}
    assert meta["format"] == "2" and meta["engine"] == f"ngspice {made[0]['engine_version']}"
    assert main(["results", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == made


def test_a_store_of_an_unknown_format_is_refused_naming_the_formats(tmp_path: Path) -> None:
    path = _store(tmp_path)
    with sqlite3.connect(path) as db:
        db.execute("UPDATE meta SET value = '9' WHERE name = 'format'")
    db.close()
    with pytest.raises(ParameterError, match="format 1 or 2 .this one is 9"):
        Store(path, "read")


def test_results_works_on_read_only_media(tmp_path: Path) -> None:
    """The store's folder mounted read-only (as a CD or a read-only share would be): results reads it."""
    if not _bwrap_works():
        pytest.skip("bubblewrap cannot make a read-only mount here (install it with bash .ci/setup)")
    path = _store(tmp_path)
    with Store(path) as store:
        assert len(store.runs()) == 2  # and closed: nothing beside it, as a copied store would be
    before = tree(tmp_path)
    read_only = ["bwrap", "--dev-bind", "/", "/", "--ro-bind", str(tmp_path), str(tmp_path), sys.executable, "-m",
                 "lcchain"]
    done = subprocess.run([*read_only, "results", str(path), "--json"], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert [run["status"] for run in json.loads(done.stdout)] == ["ok", "ok"]
    refused = subprocess.run([*read_only, *SWEEP, str(path)], cwd=tmp_path, capture_output=True, text=True,
                             timeout=120)
    assert refused.returncode == 2 and "Traceback" not in refused.stderr and "--store" in refused.stderr
    assert tree(tmp_path) == before


# ------------------------------------------------------------------ one driver at a time


def _sweep(tmp_path: Path, *extra: str) -> subprocess.Popen[str]:
    command = [sys.executable, "-m", "lcchain", "sweep", "--case", "two-mass,one-mass", "--N", "40,60,80",
               "--dt", "0.05,0.04", "--executor", "serial", "--store", "s.sqlite", "--json", *extra]
    return subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_a_second_driver_is_refused_naming_the_first(tmp_path: Path) -> None:
    path = _store(tmp_path)
    with Store(path):  # this process writes the store
        done = subprocess.run([sys.executable, "-m", "lcchain", *SWEEP, str(path)], cwd=tmp_path,
                              capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr
    assert str(path) in done.stderr and f"another lcchain (pid {os.getpid()}) is writing it" in done.stderr
    assert "--wait" in done.stderr


def test_wait_waits_for_the_driver_writing_the_store(tmp_path: Path) -> None:
    path = _store(tmp_path)
    holder = Store(path)
    try:
        waiting = subprocess.Popen([sys.executable, "-m", "lcchain", *SWEEP, str(path), "--wait", "--json"],
                                   cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert waiting.stderr is not None
        line = waiting.stderr.readline()  # said before it waits
        assert f"(pid {os.getpid()}) is writing {path}: waiting" in line
        assert waiting.poll() is None
    finally:
        holder.close()
    out, err = waiting.communicate(timeout=120)
    assert waiting.returncode == 0, err
    assert (json.loads(out)["skipped"], json.loads(out)["ran"]) == (2, 0)


@pytest.mark.parametrize("wait", [pytest.param(False, marks=pytest.mark.slow), True])  # 4 s each: one in the fast set
def test_two_drivers_started_together_never_run_a_run_twice(tmp_path: Path, wait: bool) -> None:
    """Whichever way the race goes: each run is run once, the one refused says why in a line, none crashes."""
    drivers = [_sweep(tmp_path, *(["--wait"] if wait else [])) for _ in range(2)]
    results = [(d.wait(timeout=300), *d.communicate()) for d in drivers]
    ran = 0
    for status, out, err in results:
        assert "Traceback" not in err and "IntegrityError" not in err
        if status == 2:
            assert not wait and "another lcchain (pid" in err and "is writing it" in err and "s.sqlite" in err
        else:
            assert status == 0, err
            ran += json.loads(out)["ran"]
    assert ran == 12
    assert 0 in [status for status, _, _ in results]
    with sqlite3.connect(tmp_path / "s.sqlite") as db:
        assert db.execute("SELECT COUNT(*) FROM records").fetchone()[0] == 12
    db.close()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.sqlite"]  # no lock file, no hidden store left


# ------------------------------------------------------------------ made whole or not at all


def test_a_store_exists_only_once_it_holds_its_whole_plan(tmp_path: Path) -> None:
    path = tmp_path / "s.sqlite"
    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[4], dts=[0.05, 0.04]))
    with Store(path) as store:  # opened for writing, and closed before a plan was adopted
        assert store.runs() == [] and os.listdir(tmp_path) == []
    assert os.listdir(tmp_path) == []
    leftover = tmp_path / ".s.sqlite.dead.new"  # a driver killed while it made the store, long ago
    leftover.write_bytes(b"half a store")
    os.utime(leftover, (time.time() - 3600, time.time() - 3600))
    run_plan(plan, path, RunOptions(executor="serial"))
    assert sorted(os.listdir(tmp_path)) == ["s.sqlite"]
    with sqlite3.connect(f"file:{path}?mode=ro", uri=True) as db:
        assert db.execute("SELECT COUNT(*) FROM tasks").fetchone()[0] == 2
        assert db.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    db.close()


def test_an_unreachable_scheduler_leaves_no_store(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("distributed")
    from lcchain.studies import executors

    monkeypatch.setattr(executors, "SCHEDULER_TIMEOUT", 2.0)  # a refused port is retried until then
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]  # closed again below: nothing listens there
    with pytest.raises(ParameterError) as error:
        run_plan(sweep_plan(SweepAxes(cases=["two-mass"], Ns=[4], dts=[0.05])), tmp_path / "s.sqlite", RunOptions(executor="dask", scheduler=f"tcp://127.0.0.1:{port}"))
    assert error.value.field == "--scheduler" and "running Dask scheduler" in str(error.value)
    assert os.listdir(tmp_path) == []


# ------------------------------------------------------------------ tampered arrays, a full disk, failed runs


@pytest.mark.parametrize("change, said", [("arrays = X'00'", "not lcchain's .npz"), ("arrays = 'text'", "not lcchain's .npz"),
                                          ("digest = '" + "0" * 64 + "'", "do not match its digest")])
def test_tampered_arrays_are_refused_by_name(tmp_path: Path, change: str, said: str) -> None:
    path = _store(tmp_path)
    with Store(path, "read") as store:
        key = store.runs()[0].key
        assert store.waveforms(key) is not None
    with sqlite3.connect(path) as db:
        db.execute(f"UPDATE records SET {change} WHERE key = ?", (key,))
    db.close()
    with Store(path, "read") as store, pytest.raises(ParameterError) as error:
        store.waveforms(key)
    assert said in str(error.value) and str(path) in str(error.value) and "restore it" in str(error.value)


def test_a_full_disk_keeps_every_committed_run(tmp_path: Path) -> None:
    """The store may not grow past 60 kB (RLIMIT_FSIZE: what a full disk looks like to SQLite)."""
    argv = ["sweep", "--case", "two-mass", "--N", ",".join(map(str, range(4, 12))), "--dt", "0.05",
            "--executor", "serial", "--store", "s.sqlite"]

    def small_files() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (60_000, 60_000))

    full = subprocess.run([sys.executable, "-m", "lcchain", *argv], cwd=tmp_path, capture_output=True, text=True,
                          timeout=300, preexec_fn=small_files)
    lines = [line for line in full.stderr.splitlines() if "runs, " not in line]  # without the progress
    assert full.returncode == 1 and "Traceback" not in full.stderr, full.stderr
    assert len(lines) == 1 and "s.sqlite" in lines[0] and "run the same command to resume" in lines[0]
    with Store(tmp_path / "s.sqlite", "read") as store:
        kept = [run.digest for run in store.runs() if run.status == "ok"]
    assert 1 <= len(kept) < 8
    resumed = subprocess.run([sys.executable, "-m", "lcchain", *argv, "--json"], cwd=tmp_path, capture_output=True,
                             text=True, timeout=300)
    summary = json.loads(resumed.stdout)
    assert resumed.returncode == 0 and (summary["skipped"], summary["ok"]) == (len(kept), 8)
    with Store(tmp_path / "s.sqlite", "read") as store:
        assert [run.digest for run in store.runs()][:len(kept)] == kept


def test_a_run_killed_from_outside_runs_again_with_retry_failed(tmp_path: Path) -> None:
    argv = [sys.executable, "-m", "lcchain", "sweep", "--case", "two-mass", "--N", "4,200", "--dt", "0.01",
            "--executor", "serial", "--store", "s.sqlite"]
    driver = subprocess.Popen(argv, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    killed = None
    while killed is None and driver.poll() is None and time.monotonic() < deadline:
        ngspice = [pid for pid, name in descendants(driver.pid).items() if name == "ngspice"]
        if ngspice and stored_records(tmp_path / "s.sqlite") == 1:  # the first run is stored: this is the N = 200 one
            os.kill(ngspice[0], 9)
            killed = ngspice[0]
        time.sleep(0.02)
    out, _ = driver.communicate(timeout=120)
    assert killed is not None, "the second run's ngspice was not caught"
    assert driver.returncode == 1 and "1 ok, 1 failed" in out and "--retry-failed" in out
    again = subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert again.returncode == 1 and "0 ran now" in again.stdout and "--retry-failed" in again.stdout
    retried = subprocess.run([*argv, "--retry-failed", "--json"], cwd=tmp_path, capture_output=True, text=True,
                             timeout=120)
    summary = json.loads(retried.stdout)
    assert retried.returncode == 0, retried.stderr
    assert (summary["skipped"], summary["ran"], summary["ok"], summary["failed"]) == (1, 1, 2, 0)


# ------------------------------------------------------------------ Dask: nothing left, nothing said


def test_a_dask_sweep_leaves_nothing_and_says_nothing_of_dask(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch))
    command = [sys.executable, "-m", "lcchain", "sweep", *TINY, "--executor", "dask", "--workers", "2",
               "--store", "s.sqlite"]
    done = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "2 ok" in done.stdout
    said = [line for line in done.stderr.splitlines() if line.strip()]
    # progress only (on a pipe, and only once the study has lasted 2 s): nothing of Dask's
    assert all(line.startswith("lcchain: ") and " runs, " in line for line in said), said
    assert os.listdir(scratch) == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.sqlite", "tmp"]
    verbose = subprocess.run([sys.executable, "-m", "lcchain", "-v", *command[3:-1], "v.sqlite"], cwd=tmp_path,
                             env=env, capture_output=True, text=True, timeout=300)
    assert verbose.returncode == 0 and "Scheduler" in verbose.stderr  # Dask's own words, with -v only
    assert os.listdir(scratch) == []


def test_a_dask_sweep_in_process_leaves_nothing_in_the_temporary_folder(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    before = temporary_entries()
    summary = run_plan(sweep_plan(SweepAxes(cases=["two-mass"], Ns=[4], dts=[0.05, 0.04])), tmp_path / "s.sqlite", RunOptions(executor="dask", workers=2))
    assert summary.ok == 2
    assert temporary_entries() - before == set()


def test_a_closed_store_says_it_is_closed_not_damaged(tmp_path: Path) -> None:
    """Used after its with block: the object is closed, the file is intact (it used to be called damaged, with the
    advice to restore it from a copy)."""
    path = _store(tmp_path)
    with Store(path, "read") as store:
        runs = len(store.runs())
    for read in (store.runs, store.meta):
        with pytest.raises(LcchainError, match="this Store was closed") as raised:
            read()
        assert "intact" not in str(raised.value) and "restore" not in str(raised.value)
    with Store(path, "read") as store:
        assert len(store.runs()) == runs
