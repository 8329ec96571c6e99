"""Worker processes that never outlive their driver: the spawn pools of the study executors and of the report.

A pool from :func:`spawn_pool` starts its workers with Ctrl-C ignored (the driver handles it) and with the kernel's
parent-death signal set, so that a killed driver takes its workers with it; :func:`kill_pool` stops one at once
(on an interrupt or an error nothing may keep running); :func:`interrupts_held` holds a Ctrl-C back while worker
processes start, so that none of them prints a traceback while importing.
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing
import os
import signal
import sys
import threading
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor

__all__ = ["spawn_pool", "started_pool", "kill_pool", "die_with_parent", "interrupts_held"]


def spawn_pool(workers: int) -> ProcessPoolExecutor:
    """A spawn process pool of ``workers`` processes that ignore Ctrl-C and die with this process."""
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                               initializer=die_with_parent, initargs=(os.getpid(),))


def _ready() -> None:
    """A worker's first task: what a study's run imports (the run, its comparison, the designs, scipy's BLAS), so
    that the worker is ready when its first run comes."""
    from ..core.blas import load_blas
    from ..runs import execute  # noqa: F401
    from ..theory import design  # noqa: F401

    load_blas()


@contextlib.contextmanager
def started_pool(workers: int) -> Iterator[ProcessPoolExecutor]:
    """A :func:`spawn_pool` whose workers start now, importing what a study's run needs while the driver does
    something else (plans the study: a sweep designs its chains on them); killed if the block raises, shut down
    otherwise."""
    pool = spawn_pool(workers)
    for _ in range(workers):  # each submit finds no idle worker and starts one (spawn pools start on demand)
        pool.submit(_ready)
    try:
        yield pool
    except BaseException:
        kill_pool(pool)
        raise
    pool.shutdown(wait=True)


def die_with_parent(parent: int) -> None:
    """Pool initializer: ignore Ctrl-C (the driver handles it) and die when the driver dies (Linux)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    if os.getppid() != parent:  # the driver died before the line above took effect
        os._exit(1)


def kill_pool(pool: ProcessPoolExecutor) -> None:
    """Stop a pool now: pending work cancelled, its worker processes killed and reaped."""
    processes = list(getattr(pool, "_processes", {}).values())  # the stdlib keeps no public handle on them
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.kill()
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(5)


@contextlib.contextmanager
def interrupts_held() -> Iterator[None]:
    """Ctrl-C ignored by worker processes started meanwhile (a pool, a local cluster), held back in the driver.

    A terminal sends Ctrl-C to the whole process group, and a Dask worker
    that gets it prints its traceback; the driver closes its workers itself.
    The workers inherit the ignored signal; the driver blocks it meanwhile, so
    that a Ctrl-C during the start arrives once the cluster can be closed
    whole (best effort: a thread that starts a process may unblock it).
    """
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        yield
        return
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
