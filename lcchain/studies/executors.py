"""Where a study's runs execute: in this process, in a process pool, or on a Dask cluster.

Every executor takes groups of (index, spec) and yields (index, record)
pairs as groups finish; the driver stores them and reads them back in task
order, so results are bit-identical whichever executor ran them (theory is
computed under a fixed BLAS thread limit, and ngspice is deterministic).

* ``serial``: one run after the other, here.
* ``process`` (the default): a stdlib process pool with the spawn start
  method, one worker per core.  Each worker ignores Ctrl-C (the driver
  handles it), and on Linux asks the kernel to kill it when the driver dies
  (``prctl(PR_SET_PDEATHSIG, SIGKILL)``, checked against a race at start);
  its ngspice children die with it the same way.  On an interrupt the driver
  kills the pool's processes rather than waiting for them.
* ``dask``: a ``distributed.LocalCluster`` on 127.0.0.1 (one single-threaded
  process per worker), or an existing cluster at ``--scheduler``.  Dask is
  imported here only, and only when asked for (``pip install 'lcchain[dask]'``).
  Dask reschedules the tasks of a worker that dies.

Short runs are grouped so that each task sent is worth its overhead
(:data:`MIN_TASK_SECONDS`), while keeping several tasks per worker for
balance and progress.
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
import multiprocessing
import os
import signal
import sys
from collections.abc import Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import replace
from typing import Any, Literal, get_args

from ..core.errors import LcchainError, ParameterError, SimulatorMissingError
from ..runs.execute import RunRecord, execute
from ..runs.spec import RunSpec
from ..spice.simulator import Simulator, find_simulator

__all__ = ["ExecutorName", "EXECUTORS", "MIN_TASK_SECONDS", "run_groups", "group_tasks", "default_workers",
           "execute_group"]

#: The executors lcchain has.
ExecutorName = Literal["serial", "process", "dask"]
EXECUTORS: tuple[str, ...] = get_args(ExecutorName)
#: Seconds of runs worth sending as one task (Dask's overhead per task is a few ms; its documentation asks for
#: tasks of 100 ms and more).
MIN_TASK_SECONDS: dict[str, float] = {"serial": 0.0, "process": 0.05, "dask": 0.3}
#: Tasks per worker aimed at, at least, for balance and progress.
TASKS_PER_WORKER = 4

log = logging.getLogger("lcchain")

Group = list[tuple[int, RunSpec]]


def default_workers() -> int:
    """One worker per core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def group_tasks(items: Sequence[tuple[int, RunSpec, float]], executor: str, workers: int) -> list[Group]:
    """Consecutive runs grouped until a group is worth :data:`MIN_TASK_SECONDS`, keeping enough groups."""
    least = MIN_TASK_SECONDS[executor]
    if executor == "serial" or not items:
        return [[(index, spec)] for index, spec, _ in items]
    total = sum(seconds for _, _, seconds in items)
    # worth the minimum, unless that leaves fewer than TASKS_PER_WORKER groups per worker
    target = min(least, total / (TASKS_PER_WORKER * workers))
    groups: list[Group] = []
    current: Group = []
    held = 0.0
    for index, spec, seconds in items:
        current.append((index, spec))
        held += seconds
        if held >= target:
            groups.append(current)
            current, held = [], 0.0
    if current:
        groups.append(current)
    return groups


def execute_group(group: Group, simulator: Simulator, keep_signals: bool = False) -> list[tuple[int, RunRecord]]:
    """Run one group where it lands (a pool worker, a Dask worker): the unit of work, run by run.

    A worker whose ngspice is elsewhere finds its own; one whose ngspice has
    another version fails its runs (their keys would not be the study's).
    """
    if not os.path.exists(simulator.executable):
        found = find_simulator(simulator.backend)
        if found.version != simulator.version:
            reason = f"this worker's ngspice is {found.version}, the study's is {simulator.version}"
            return [(index, RunRecord(key=spec.key(simulator.version), status="failed", reason=reason,
                                      ngspice_version=found.version, label=spec.label)) for index, spec in group]
        simulator = found
    out = []
    for index, spec in group:
        record = execute(spec, simulator)
        out.append((index, record if keep_signals else replace(record, signals=None)))
    return out


# ------------------------------------------------------------------ process pool
def _die_with_parent(parent: int) -> None:
    """Pool initializer: ignore Ctrl-C (the driver handles it) and die when the driver dies (Linux)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    if os.getppid() != parent:  # the driver died before the line above took effect
        os._exit(1)


def _kill_pool(pool: ProcessPoolExecutor) -> None:
    processes = list(getattr(pool, "_processes", {}).values())  # the stdlib keeps no public handle on them
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.kill()
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(5)


#: Times a broken process pool (a worker killed, by the kernel or by hand) is rebuilt before the study stops.
POOL_RESTARTS = 3


def _process(groups: list[Group], simulator: Simulator, workers: int,
             keep_signals: bool) -> Iterator[list[tuple[int, RunRecord]]]:
    """A spawn process pool; a pool broken by a dead worker is rebuilt and the unfinished groups resubmitted."""
    context = multiprocessing.get_context("spawn")
    left = dict(enumerate(groups))
    for attempt in range(POOL_RESTARTS + 1):
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=_die_with_parent,
                                   initargs=(os.getpid(),))
        finished = False
        try:
            pending = {pool.submit(execute_group, group, simulator, keep_signals): number
                       for number, group in left.items()}
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    number = pending.pop(future)
                    result = future.result()
                    del left[number]
                    yield result
            finished = True
            return
        except BrokenProcessPool:
            if attempt == POOL_RESTARTS:
                message = (f"the process pool broke {attempt + 1} times (a worker was killed: out of memory?); "
                           "every finished run is in the store, run the same command to resume")
                raise LcchainError(message) from None
            log.warning("a pool worker died; restarting the pool for the %d unfinished groups", len(left))
        finally:
            if finished:
                pool.shutdown(wait=True)
            else:  # interrupted, or broken: nothing may keep running
                _kill_pool(pool)


# ------------------------------------------------------------------ Dask
def _dask(groups: list[Group], simulator: Simulator, workers: int, scheduler: str | None,
          keep_signals: bool) -> Iterator[list[tuple[int, RunRecord]]]:
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise SimulatorMissingError("the dask executor needs Dask, which is not installed; install it with: "
                                    "pip install 'lcchain[dask]'") from None
    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout=30)
        except OSError as error:
            raise ParameterError("--scheduler", scheduler, f"the address of a running Dask scheduler ({error})") \
                from None
    try:
        futures = [client.submit(execute_group, group, simulator, keep_signals, pure=False) for group in groups]
        for future in as_completed(futures):
            yield future.result()
            future.release()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def run_groups(groups: list[Group], simulator: Simulator, *, executor: str = "process", workers: int | None = None,
               scheduler: str | None = None, keep_signals: bool = False) -> Iterator[list[tuple[int, RunRecord]]]:
    """Execute groups of runs on an executor; yields each group's (index, record) pairs as it finishes."""
    if executor not in EXECUTORS:
        raise ParameterError("--executor", executor, " | ".join(EXECUTORS))
    if scheduler is not None and executor != "dask":
        raise ParameterError("--scheduler", scheduler, "nothing unless --executor dask")
    workers = workers or default_workers()
    if executor == "serial" or (executor == "process" and workers == 1):
        for group in groups:
            yield execute_group(group, simulator, keep_signals)
    elif executor == "process":
        yield from _process(groups, simulator, workers, keep_signals)
    else:
        yield from _dask(groups, simulator, workers, scheduler, keep_signals)


def describe(executor: str, workers: int, scheduler: str | None) -> dict[str, Any]:
    return {"executor": executor, "workers": workers, "scheduler": scheduler}
