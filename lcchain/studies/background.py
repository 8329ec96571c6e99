"""Independent pieces of work done on every core while the caller does something else (issue 23).

:class:`Background` sends its tasks (a row of the paper's tables, a circuit check: any picklable function and
arguments) to a spawn process pool as soon as it is opened, the longest first by their estimated cost, so that
the longest do not finish last, alone on one core; :meth:`Background.take` then waits for one task's result.
A result is the one computed here, bit for bit: the theory runs under a fixed BLAS thread limit in every process
(:mod:`lcchain.core.blas`) and ngspice is deterministic.

The pool's workers are those of the study executors (:mod:`.pools`): they ignore Ctrl-C from their start
(they are started with it ignored) and die with their parent, and their simulators die with them; leaving the
block by an exception (an interrupt included), or with tasks nobody took, kills them rather than waiting.
A worker killed from outside (out of memory) breaks the pool: the tasks not yet taken are then done here.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Hashable, Iterable
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from types import TracebackType
from typing import Generic, TypeVar

from .executors import default_workers
from .pools import interrupts_held, kill_pool, spawn_pool

__all__ = ["Job", "Background"]

log = logging.getLogger(__name__)

#: What a job's function returns.
R = TypeVar("R", covariant=True)


@dataclass(frozen=True)
class Job(Generic[R]):
    """One piece of background work, ``function(*args)``, known by ``key``, estimated to take ``cost`` seconds (a
    study's run is a :class:`lcchain.studies.plan.Task`)."""

    key: Hashable
    cost: float
    function: Callable[..., R]
    args: tuple[object, ...] = ()


class Background:
    """Tasks done by a spawn process pool while the caller does other work; a context manager.

    Parameters
    ----------
    tasks : iterable of Job
        The work, sent longest first (a key given twice is done once).
    workers : int, optional
        Processes (default: one per core this process may use); with one (or fewer than two tasks) nothing is
        started and :meth:`take` does the task here.
    """

    def __init__(self, tasks: Iterable[Job[object]], workers: int | None = None):
        self._tasks = {task.key: task for task in tasks}
        self.workers = min(workers or default_workers(), len(self._tasks))
        self._futures: dict[Hashable, Future[object]] = {}
        self._pool: ProcessPoolExecutor | None = None
        if self.workers <= 1:
            return
        try:
            # the workers (started by the first submissions) inherit an ignored Ctrl-C from their first instant:
            # a terminal's Ctrl-C reaches the whole group, and a worker still importing would print a traceback
            with interrupts_held():
                self._pool = spawn_pool(self.workers)
                for task in sorted(self._tasks.values(), key=lambda task: -task.cost):
                    self._futures[task.key] = self._pool.submit(task.function, *task.args)
        except BaseException:
            self.close(finished=False)
            raise

    def __contains__(self, key: object) -> bool:
        return key in self._tasks

    def take(self, key: Hashable) -> object:
        """The result of the task ``key``: waits for it if the pool has it, else does it here (its exception,
        if it raised one, is raised here).  The tasks of one pool return different types: the caller, who knows
        the key's, narrows it."""
        future = self._futures.get(key)
        if future is not None:
            try:
                return future.result()
            except BrokenProcessPool:  # a worker was killed (out of memory?): the rest is done here, one by one
                log.warning("a background worker died; its remaining tasks run in this process")
                self._futures.clear()
                self.close(finished=False)
        task = self._tasks[key]
        return task.function(*task.args)

    def close(self, finished: bool = True) -> None:
        """Shut the pool down: waiting for it after a clean finish, killing its workers otherwise."""
        pool, self._pool = self._pool, None
        if pool is None:
            return
        if finished and all(future.done() for future in self._futures.values()):
            pool.shutdown(wait=True)
        else:  # interrupted, failed, or tasks nobody took: nothing may keep running
            kill_pool(pool)

    def __enter__(self) -> Background:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 traceback: TracebackType | None) -> None:
        self.close(finished=kind is None)
