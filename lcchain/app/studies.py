"""What every study's command shares (``sweep``, ``batch``, ``run``, ``sensitivity --check``): where and how
its runs execute, and the store they go into.  Light to import: studies/ is imported on first use."""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from ..core.budget import Budget
from ..core.json import LooseJSONObject
from ..studies.options import RunHooks
from .inputs import Outputs

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

    from ..spice.simulator import Simulator
    from ..studies.plan import Plan
    from ..studies.run import Summary
    from ..studies.worst_case import WorstCase

__all__ = ["STORE_FORMATS", "StudyOptions", "StudyHooks", "PlannedStudy", "StudyResult", "study_workers",
           "check_executor", "check_study", "run_study", "dask_quiet"]

#: The file endings a store may have.
STORE_FORMATS = ("sqlite", "sqlite3", "db")


@dataclass(frozen=True)
class StudyOptions:
    """Where and how a study's runs execute: the ``executor`` (serial, process, dask) on ``workers`` (None: one
    per core), an existing Dask ``scheduler``, the ``transport`` of each ngspice run, a run's ``timeout`` in
    seconds; the ``store`` and, for a store the user names, whether to ``wait`` for another writer and to run
    again the runs it holds as failed (``retry_failed``)."""

    executor: str = "process"
    workers: int | None = None
    scheduler: str | None = None
    transport: str = "auto"
    timeout: float = 3600.0
    store: str | None = None
    wait: bool = False
    retry_failed: bool = False


def study_workers(options: StudyOptions) -> int:
    """The workers a study runs on: ``workers``, or one per core (serial: one)."""
    from ..studies.executors import EXECUTOR_TRAITS, default_workers

    traits = EXECUTOR_TRAITS.get(options.executor)  # an unknown name is refused by check_executor
    return 1 if traits is not None and not traits.parallel else options.workers or default_workers()


def check_executor(options: StudyOptions) -> None:
    """Refuse an executor, its workers or its scheduler before anything runs."""
    from ..studies.executors import check_executor as check

    check(options.executor, options.workers, options.scheduler)


#: Loggers of Dask and the libraries under it: their records reach the terminal only with -v.
_DASK_LOGGERS = ("distributed", "dask", "tornado", "bokeh", "asyncio")


class _NotDask(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return not record.name.startswith(_DASK_LOGGERS)


@contextlib.contextmanager
def dask_quiet(verbose: bool) -> Iterator[None]:
    """Dask logs its cluster's life at INFO through the root logger: shown with -v only."""
    if verbose:
        yield
        return
    quiet = _NotDask()
    handlers = list(logging.getLogger().handlers)
    for handler in handlers:
        handler.addFilter(quiet)
    try:
        yield
    finally:
        for handler in handlers:
            handler.removeFilter(quiet)


class StudyProgress(Protocol):
    """Where a study is, as its progress callback gets it (:class:`lcchain.studies.run.Progress`): runs done of
    the total, and how many failed."""

    @property
    def done(self) -> int: ...

    @property
    def total(self) -> int: ...

    @property
    def failed(self) -> int: ...


#: What the caller shows while a study runs (progress, a resumed store, a wait for another writer, Dask's log):
#: the studies' own hooks (:class:`lcchain.studies.options.RunHooks`), under the name the commands use.
StudyHooks = RunHooks


@dataclass(frozen=True)
class PlannedStudy:
    """A study's plan (:class:`lcchain.studies.plan.Plan`), the seconds its runs may still start in (None: the
    whole budget is the plan's to price), and a worst case's setup (what its summary compares)."""

    plan: Plan
    max_seconds: float | None = None
    worst_case: WorstCase | None = None


@dataclass(frozen=True)
class StudyResult:
    """The study's summary (:class:`lcchain.studies.run.Summary`) and, for a worst case, what it found
    (:func:`lcchain.studies.worst_case.worst_case_summary`)."""

    summary: Summary
    worst_case: LooseJSONObject | None = None


def check_study(options: StudyOptions) -> None:
    """Everything a study's options can be checked for without running it: before the store is touched."""
    Outputs().check("--store", options.store, STORE_FORMATS)
    check_executor(options)


def run_study(planned: PlannedStudy, options: StudyOptions, budget: Budget, hooks: StudyHooks | None = None,
              pool: ProcessPoolExecutor | None = None, simulator: Simulator | None = None) -> StudyResult:
    """Price the plan for its workers, run it into ``options.store`` (resumed; ``pool``: the process executor's
    workers, started while the plan was made; ``simulator``: the engine, found while the plan was made), and read
    a worst case's summary."""
    from ..studies.options import RunOptions
    from ..studies.run import run_plan

    hooks = hooks or StudyHooks()
    assert options.store is not None
    workers = study_workers(options)
    planned.plan.check(budget, workers, options.executor)
    with dask_quiet(hooks.verbose):
        run = RunOptions(options.executor, workers, options.scheduler, options.transport, options.retry_failed,
                         options.wait, planned.max_seconds, pool=pool, simulator=simulator)
        summary = run_plan(planned.plan, options.store, run, hooks)
    worst = None
    if planned.worst_case is not None:
        from ..studies.store import Store
        from ..studies.worst_case import worst_case_summary

        with Store(options.store, "read") as store:
            worst = worst_case_summary(store.runs(), planned.worst_case)
    return StudyResult(summary, worst)
