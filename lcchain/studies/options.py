"""What running a study takes beside its plan: where its runs execute (:class:`RunOptions`), what its caller is
shown while they do (:class:`RunHooks`, :class:`Progress`).

Light to import (no executor, no simulator): the command layer builds these before anything runs.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..core.checks import callback, real

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

    from ..spice.simulator import Simulator
    from .executors import Executor

__all__ = ["Progress", "RunOptions", "RunHooks"]


@dataclass(frozen=True)
class Progress:
    """Where a study is: given to the progress callback after every finished group of runs."""

    done: int
    total: int
    failed: int
    elapsed: float

    @property
    def remaining(self) -> float | None:
        """Seconds left at the pace so far (None before the first run finished)."""
        if self.done == 0 or self.done >= self.total:
            return None if self.done == 0 else 0.0
        return self.elapsed / self.done * (self.total - self.done)


@dataclass(frozen=True)
class RunOptions:
    """Where and how a study's runs execute (:func:`lcchain.studies.run.run_plan`,
    :func:`lcchain.studies.run.run_specs`).

    Attributes
    ----------
    executor : {"serial", "process", "dask"} or Executor
        An :class:`~lcchain.studies.executors.Executor` of one's own is used as given.
    workers : int, optional
        Processes, >= 1 (default: one per core).
    scheduler : str, optional
        ``tcp://host:port`` of a running Dask scheduler (a remote executor only).
    transport : {"auto", "process", "warm"}
        How each ngspice run starts: warm shared-library workers for runs predicted short (``"auto"``), a
        process per run, or warm workers for all (:func:`~lcchain.studies.executors.choose_transports`). Keys
        and results do not depend on it.
    retry_failed : bool
        Run again the runs stored as failed or timed out (a run killed from outside, say).
    wait : bool
        Wait for another driver writing the store to finish, instead of refusing it.
    max_seconds : float, optional
        The study's time budget from its start, seconds (>= 0): no run starts after it and a run still going then
        is stopped; neither is stored (:attr:`~lcchain.studies.run.Summary.pending`), so the same call runs them.
    simulator : Simulator, optional
        Found once for the plan's engine and backend when omitted.
    pool : ProcessPoolExecutor, optional
        The process executor's workers, started while the plan was made
        (:func:`~lcchain.studies.pools.started_pool`); its owner shuts it down.

    The executor, its workers and scheduler, the transport and the time budget are checked here, each under its
    option's name (``--executor``, ``--workers``, ``--scheduler``, ``--transport``, ``--max-time``).
    """

    executor: str | Executor = "process"
    workers: int | None = None
    scheduler: str | None = None
    transport: str = "auto"
    retry_failed: bool = False
    wait: bool = False
    max_seconds: float | None = None
    simulator: Simulator | None = field(default=None, compare=False)
    pool: ProcessPoolExecutor | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        from .executors import check_executor, check_transport

        check_executor(self.executor, self.workers, self.scheduler)
        check_transport(self.transport)
        if self.max_seconds is not None:
            real("--max-time", self.max_seconds, at_least=0.0, unit="seconds")


@dataclass(frozen=True)
class RunHooks:
    """What the caller shows while a study runs: ``progress`` with each :class:`Progress`,
    ``on_resume(skipped, todo)`` when the store holds runs already, ``on_wait(pid)`` while another writer holds
    it (pid None when unknown); ``planning(done, total)`` as a batch's netlists are read, checked and priced
    before any run (every few hundred, and once all are: 100,000 netlists take about 30 s); ``verbose`` lets
    Dask's own log through."""

    progress: Callable[[Progress], None] | None = None
    on_resume: Callable[[int, int], None] | None = None
    on_wait: Callable[[int | None], None] | None = None
    verbose: bool = False
    planning: Callable[[int, int], None] | None = None

    def __post_init__(self) -> None:
        for name in ("progress", "on_resume", "on_wait", "planning"):
            callback(name, getattr(self, name))
