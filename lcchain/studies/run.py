"""Running a plan: its runs on an executor, each finished run stored at once, nothing run twice.

:func:`run_plan` is ``lcchain sweep`` and ``lcchain batch``: it opens the
store (refusing one made for another plan), skips every run already stored,
sends the others to the executor, and stores each record in its own
transaction the moment it arrives, so that a killed driver loses nothing that
finished and a restarted one redoes nothing.  :func:`run_specs` runs specs
without a store (``lcchain run --workers``) and returns the records in order.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..core.errors import ParameterError
from ..runs.execute import RunRecord
from ..runs.spec import RunSpec
from ..spice.simulator import Simulator, find_simulator
from .executors import default_workers, group_tasks, run_groups
from .plan import Plan
from .store import Store

__all__ = ["Summary", "Progress", "run_plan", "run_specs"]


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
class Summary:
    """What ``lcchain sweep --json`` prints.

    Attributes
    ----------
    total : int
        Runs in the plan.
    skipped : int
        Already in the store: not run again.
    ran : int
        Run now.
    ok, failed : int
        Of the runs in the store after this one, how many are ok, and how many
        failed or timed out.
    store : str
        The store's path.
    wall_s : float
    """

    total: int
    skipped: int
    ran: int
    ok: int
    failed: int
    store: str
    wall_s: float

    def to_dict(self) -> dict[str, Any]:
        return {"total": self.total, "skipped": self.skipped, "ran": self.ran, "ok": self.ok,
                "failed": self.failed, "store": self.store, "wall_s": self.wall_s}


def run_plan(plan: Plan, store: str | Path, *, executor: str = "process", workers: int | None = None,
             scheduler: str | None = None, simulator: Simulator | None = None,
             progress: Callable[[Progress], None] | None = None,
             on_resume: Callable[[int, int], None] | None = None) -> Summary:
    """Run a plan into a store, skipping what the store already holds.

    Parameters
    ----------
    plan : Plan
    store : path-like
        The ``.sqlite`` file; created when missing; refused when it holds another plan.
    executor : {"serial", "process", "dask"}
    workers : int, optional
        Processes (default: one per core).
    scheduler : str, optional
        ``tcp://host:port`` of a running Dask scheduler (``executor="dask"``).
    simulator : Simulator, optional
        Found once here for the plan's backend when omitted.
    progress : callable, optional
        Called with a :class:`Progress` after every finished group of runs.
    on_resume : callable, optional
        Called with (runs already stored, runs to do) before anything runs.
    """
    start = time.perf_counter()
    simulator = simulator if simulator is not None else find_simulator(plan.backend)
    keys = plan.keys(simulator.version)
    with Store(store) as results:
        results.adopt(plan.fingerprint(simulator.version), dict(plan.description),
                      [(key, dict(task.params), task.spec.label) for key, task in zip(keys, plan.tasks, strict=True)],
                      simulator.version)
        finished = results.finished()
        todo = [(task.index, task.spec, task.seconds) for task, key in zip(plan.tasks, keys, strict=True)
                if key not in finished]
        skipped = len(plan.tasks) - len(todo)
        if on_resume is not None:
            on_resume(skipped, len(todo))
        workers = workers or default_workers()
        done = failed = 0
        for group in run_groups(group_tasks(todo, executor, workers), simulator, executor=executor, workers=workers,
                                scheduler=scheduler):
            for index, record in group:
                if record.key != keys[index]:
                    raise ParameterError("--store", str(store), f"records under the plan's keys (run {index} came "
                                         f"back as {record.key[:12]}, expected {keys[index][:12]})")
                results.add(record)
                done += 1
                failed += not record.ok
            if progress is not None:
                progress(Progress(done, len(todo), failed, time.perf_counter() - start))
        runs = results.runs()
    return Summary(len(plan.tasks), skipped, done, sum(r.status == "ok" for r in runs),
                   sum(r.status in ("failed", "timeout") for r in runs), str(store), time.perf_counter() - start)


def run_specs(specs: Sequence[RunSpec], *, executor: str = "process", workers: int | None = None,
              scheduler: str | None = None, simulator: Simulator | None = None,
              progress: Callable[[Progress], None] | None = None) -> list[RunRecord]:
    """Run specs on an executor without a store; the records come back in the specs' order, signals kept."""
    start = time.perf_counter()
    if not specs:
        return []
    simulator = simulator if simulator is not None else find_simulator(specs[0].backend)
    workers = workers or default_workers()
    items = [(i, spec, 1.0) for i, spec in enumerate(specs)]
    records: dict[int, RunRecord] = {}
    failed = 0
    for group in run_groups(group_tasks(items, executor, workers), simulator, executor=executor, workers=workers,
                            scheduler=scheduler, keep_signals=True):
        for index, record in group:
            records[index] = record
            failed += not record.ok
        if progress is not None:
            progress(Progress(len(records), len(specs), failed, time.perf_counter() - start))
    return [records[i] for i in range(len(specs))]
