"""The report's rows designed on every core (issue 23): the same rows as designed here, the rows the report
reads, and no worker left behind by an interrupt or a kill."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from helpers.processes import as_from_a_terminal, descendants, dies_unless_in, gone, reaped

from lcchain.circuit.reference import REFERENCE_SET
from lcchain.report.build import check_figure_png, paper_figure_png, report_rows
from lcchain.report.figure_data import DesignRows
from lcchain.report.paper_figures import FIGURES
from lcchain.report.validation import paper_section
from lcchain.spice.simulator import Simulator
from lcchain.studies.background import Background, Job
from lcchain.studies.designs import design_row, design_task
from lcchain.studies.validation import (
    CHECKED_MAX_N,
    LARGE_CHECKS,
    check_jobs,
    installed_engines,
    run_check,
)

#: Seconds to wait for the pool's workers to start, and for them to die.
START_TIMEOUT, DEATH_TIMEOUT = 120.0, 10.0


def _without_seconds(row: dict) -> dict:
    return {k: v for k, v in row.items() if k != "seconds"}


def test_a_row_designed_by_the_pool_is_the_row_designed_here() -> None:
    pairs = [("one-mass", 5), ("two-mass", 6), ("one-mass", 200), ("two-mass", 50)]
    with Background([design_task(*pair) for pair in pairs], workers=2) as designs:
        assert designs.workers == 2
        pooled = {pair: designs.take(("row", *pair)) for pair in pairs}
    for pair in pairs:
        here = design_row(*pair)
        assert _without_seconds(pooled[pair]) == _without_seconds(here), pair
        assert pooled[pair]["seconds"] > 0


def test_rows_come_from_the_pool_into_the_cache(tmp_path: Path) -> None:
    pairs = [("one-mass", 7), ("two-mass", 8)]
    rows = DesignRows(tmp_path)
    assert rows.missing([*pairs, pairs[0]]) == pairs
    with Background([design_task(*pair) for pair in rows.missing(pairs)], workers=2) as designs:
        rows.design = lambda case, N: designs.take(("row", case, N))
        taken = rows.rows("one-mass", [7]) + rows.rows("two-mass", [8])
    again = DesignRows(tmp_path)  # read back from the file the pool's rows were saved in
    assert again.missing(pairs) == []
    assert again.rows("one-mass", [7]) + again.rows("two-mass", [8]) == taken
    assert again.computed == 0


def test_report_rows_are_every_row_the_quick_report_reads() -> None:
    read: list[tuple[str, int]] = []

    def design(case: str, N: int) -> dict:
        read.append((case, N))
        return design_row(case, N)  # type: ignore[arg-type]

    rows = DesignRows(design=design)
    paper_section(rows, quick=True)
    for figure in FIGURES:
        figure.build(rows, True)
    assert sorted(read) == sorted(report_rows(quick=True))
    assert len(read) == len(set(read))


def _command_line(pid: int) -> bytes:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:  # gone meanwhile
        return b""


def _workers(proc: subprocess.Popen[bytes]) -> dict[int, str]:
    """The report's descendants once its pool is up (two spawned workers, and what they started)."""
    deadline = time.monotonic() + START_TIMEOUT
    while time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        spawned = [pid for pid in descendants(proc.pid) if b"spawn_main" in _command_line(pid)]
        if len(spawned) >= 2:
            time.sleep(1.0)  # the workers take their first rows
            return descendants(proc.pid)
        time.sleep(0.1)
    proc.kill()
    raise AssertionError(f"the report's pool did not start within {START_TIMEOUT} s")



@pytest.mark.ngspice
@pytest.mark.parametrize(("signum", "status"), [(signal.SIGINT, 130), (signal.SIGKILL, -signal.SIGKILL)],
                         ids=["SIGINT", "SIGKILL"])
def test_no_worker_outlives_an_interrupted_report(tmp_path: Path, signum: int, status: int) -> None:
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch), XDG_CACHE_HOME=str(tmp_path / "cache"))
    proc = subprocess.Popen([sys.executable, "-m", "lcchain", "report", "--out", str(tmp_path / "out")],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=as_from_a_terminal, start_new_session=True)
    with reaped(proc):
        children = _workers(proc)
        if signum == signal.SIGINT:  # as Ctrl-C in a terminal: to the whole foreground group, workers included
            os.killpg(proc.pid, signum)
        else:  # lcchain alone; its workers must die by their parent-death signal
            proc.send_signal(signum)
        _, err = proc.communicate(timeout=60)
    assert proc.returncode == status, err.decode()
    assert b"Traceback" not in err, err.decode()
    left = [f"{pid} ({name})" for pid, name in children.items() if not gone(pid, DEATH_TIMEOUT)]
    assert left == [], f"outlived the report: {left}"
    assert not (tmp_path / "out").exists(), "an interrupted report wrote its page"


@pytest.mark.ngspice
def test_a_check_run_by_the_pool_is_the_check_run_here() -> None:
    simulators = [s for s in installed_engines() if s.engine == "ngspice"]
    jobs = [job for job in check_jobs(quick=True, simulators=simulators) if job.N <= 50]
    assert any(job.chain is None for job in jobs) and len(jobs) >= 4
    with Background([Job(i, job.cost, run_check, (job,)) for i, job in enumerate(jobs)], workers=2) as pool:
        pooled = [pool.take(i) for i in range(len(jobs))]
    for job, check in zip(jobs, pooled, strict=True):
        here = run_check(job)
        assert check.passed and here.passed, (check.reason, here.reason)
        assert (check.name, check.max_abs_error, check.predicted_error, check.tolerance, check.dt) == \
            (here.name, here.max_abs_error, here.predicted_error, here.tolerance, here.dt)
        for key in ("t", "sim", "theory", "residual"):
            assert check.curves[key].tobytes() == here.curves[key].tobytes(), (job.name, key)


def test_a_killed_background_worker_loses_no_task(caplog: pytest.LogCaptureFixture) -> None:
    """A worker killed from outside (the kernel, out of memory) breaks the pool: the tasks are then done here."""
    here = os.getpid()
    with Background([Job(i, 1.0, dies_unless_in, (here, i)) for i in range(4)], workers=2) as pool:
        workers = set(pool._pool._processes) if pool._pool is not None else set()  # type: ignore[attr-defined]
        taken = [pool.take(i) for i in range(4)]
    assert taken == [0, 1, 2, 3]
    assert "remaining tasks run in this process" in caplog.text
    assert workers and all(gone(pid) for pid in workers)


def _runs(jobs: list, engine: str) -> set[tuple[int, str, str]]:
    """(N, excitation, what) of an engine's reference runs (the scene left out)."""
    return {(job.N, job.excitation, job.what) for job in jobs if job.simulator.engine == engine and job.chain}


def test_the_checks_run_at_the_sizes_that_test_something() -> None:
    """Issue 35: every engine runs every reference chain up to CHECKED_MAX_N with both excitations, and the scene;
    above that only the default engine's LARGE_CHECKS run, and none with --quick.  (Descriptions of engines:
    nothing runs.)"""
    engines = [Simulator("batch", "/usr/bin/ngspice", "39"), Simulator("batch", "/usr/bin/gnucap", "x", engine="gnucap")]
    small = {(ref.N, excitation, f"{ref.case}, N = {ref.N}") for ref in REFERENCE_SET if ref.N <= CHECKED_MAX_N
             for excitation in ("kick", "displacement")}
    large = {(ref.N, excitation, f"{ref.case}, N = {ref.N}") for ref in REFERENCE_SET
             for name, excitation in LARGE_CHECKS if ref.name == name}
    assert len(large) == len(LARGE_CHECKS) and all(N > CHECKED_MAX_N for N, _, _ in large)
    assert len(small) < 2 * len(REFERENCE_SET)  # the rule leaves something out
    jobs = check_jobs(simulators=engines)
    assert _runs(jobs, "ngspice") == small | large
    assert _runs(jobs, "gnucap") == small
    assert sum(job.chain is None for job in jobs) == 2  # the scene, in each engine
    quick = check_jobs(quick=True, simulators=engines)
    assert _runs(quick, "ngspice") == _runs(quick, "gnucap") == small


def test_a_figure_drawn_by_the_pool_is_the_figure_drawn_here() -> None:
    """The report draws the paper's figures that need no row, and each check's figure, in its pool's workers:
    the same PNG bytes as drawn here."""
    cradle = next(figure for figure in FIGURES if figure.label == "cradle4")
    assert not cradle.uses_rows
    tasks = [Job("cradle4", 1.0, paper_figure_png, (cradle, None, True))]
    with Background(tasks, workers=2) as pool:
        pooled = pool.take("cradle4")
    assert pooled[:8] == b"\x89PNG\r\n\x1a\n" and pooled == paper_figure_png(cradle, None, True)


@pytest.mark.ngspice
def test_a_check_figure_drawn_by_the_pool_is_the_one_drawn_here() -> None:
    simulators = [s for s in installed_engines() if s.engine == "ngspice"]
    job = next(job for job in check_jobs(quick=True, simulators=simulators) if job.N == 20)
    check = run_check(job)
    with Background([Job(0, 1.0, check_figure_png, (check,)), Job(1, 1.0, check_figure_png, (check,))],
                    workers=2) as pool:
        pooled = pool.take(0)
    here = check_figure_png(check)
    assert here is not None and pooled == here
