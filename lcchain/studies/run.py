"""Running a plan: its runs on an executor, each finished run stored at once, nothing run twice.

:func:`run_plan` is ``lcchain sweep`` and ``lcchain batch``: it checks its
options, opens the store for this driver alone (refusing one that another
driver writes, or waiting for it, and one made for another plan), starts the
executor (a Dask scheduler that cannot be reached leaves no store behind),
then makes the store, whole, skips every run already stored (failed ones too,
unless ``retry_failed``), stores a batch's refusals (each once: a resumed
batch finds them stored, and ``retry_failed`` leaves them: nothing of them
could run), sends the others to the executor, and stores each
record in its own transaction the moment it arrives, so that a killed driver
loses nothing that finished and a restarted one redoes nothing.  An
extrapolation's members are tasks like any other; its combination is made in
the driver, from the members' stored arrays, as soon as the last of them is
stored (after a restart too).  A batch planned to disk (:class:`~lcchain.studies.stream.StreamedPlan`) runs
the same way with nothing kept a run but its key and a few bytes: its rows written from an iterator, what is
stored asked a window of keys at a time, its summary counted by the store.  :func:`run_specs` runs specs without a
store
(``lcchain run --workers``) and returns the records in order.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from ..core.budget import Budget
from ..core.errors import LcchainError, ParameterError
from ..core.json import JSONDict
from ..runs.execute import RunRecord, loop_sims
from ..runs.spec import RunSpec
from ..spice.engines import find_engine
from .executors import (
    RunMask,
    RunStream,
    choose_transports,
    choose_transports_by,
    default_workers,
    group_tasks,
    open_executor,
    run_groups,
)
from .options import Progress, RunHooks, RunOptions
from .plan import Combination, Plan, Refusal, Task, _memory, _seconds
from .store import Store, engine_text
from .stream import StreamedPlan

if TYPE_CHECKING:
    import numpy as np

    from ..spice.engine import Engine

__all__ = ["Summary", "Progress", "RunOptions", "RunHooks", "run_plan", "run_specs", "check_specs"]


@dataclass(frozen=True)
class Summary:
    """What ``lcchain sweep --json`` prints.

    Attributes
    ----------
    total : int
        Runs in the plan (distinct runs: points that share a member share its run).
    skipped : int
        Already in the store: not run again.
    ran : int
        Run now.
    ok, failed : int
        Of the runs in the store after this one, how many are ok, and how many
        failed or timed out.
    refused : int
        Netlists of a batch that lcchain would not run (:class:`~lcchain.studies.plan.Refusal`), counted in
        ``total`` and stored with their reason.
    store : str
        The store's path.
    wall_s : float
    combined, combined_failed : int
        Extrapolations the store holds combined (each made from its member runs, counted above), and those
        that failed (a member failed, or the members could not be combined: made again on the next run).
    pending : int
        Runs not started, or stopped, because the study's time budget (``max_seconds``) was spent: not stored, so
        the same command runs them.
    refusals : tuple of (str, str)
        Each refusal's netlist (as given) and reason, as the store holds them, in the batch's order: one a refused
        run (a netlist named twice is one refusal, as it would be one run), so that there are ``refused`` of them.
    """

    total: int
    skipped: int
    ran: int
    ok: int
    failed: int
    store: str
    wall_s: float
    combined: int = 0
    combined_failed: int = 0
    pending: int = 0
    refused: int = 0
    refusals: tuple[tuple[str, str], ...] = ()

    @property
    def complete(self) -> bool:
        """Every run ok (none refused) and every extrapolation combined."""
        return self.failed == 0 and self.refused == 0 and self.ok == self.total and self.combined_failed == 0

    def to_dict(self) -> JSONDict:
        return {"total": self.total, "skipped": self.skipped, "ran": self.ran, "ok": self.ok,
                "failed": self.failed, "combined": self.combined, "combined_failed": self.combined_failed,
                "pending": self.pending, "refused": self.refused,
                "refusals": [{"netlist": netlist, "reason": reason} for netlist, reason in self.refusals],
                "store": self.store, "wall_s": self.wall_s}


def run_plan(plan: Plan, store: str | Path, options: RunOptions | None = None,
             hooks: RunHooks | None = None) -> Summary:
    """Run a plan into a store, skipping what the store already holds.

    Parameters
    ----------
    plan : Plan
    store : path-like
        The ``.sqlite`` file; made (whole) when missing; refused when it is not an lcchain store, holds another
        plan, or another driver writes it.
    options : RunOptions, optional
        Where and how the runs execute (the executor, its workers, the transport, the time budget, whether to
        wait for another driver and to retry failed runs); by default a process per core.
    hooks : RunHooks, optional
        What the caller is shown: :class:`Progress` after every finished group of runs, (runs already stored,
        runs to do) before anything runs, another driver's pid before waiting for it; Dask's log with
        ``verbose``.
    """
    start = time.perf_counter()
    options = options if options is not None else RunOptions()
    hooks = hooks if hooks is not None else RunHooks()
    if isinstance(plan, StreamedPlan):
        return _run_streamed(plan, store, options, hooks, start)
    executor, scheduler, progress = options.executor, options.scheduler, hooks.progress
    deadline = None if options.max_seconds is None else time.time() + options.max_seconds
    simulator = options.simulator if options.simulator is not None else find_engine(plan.engine, plan.backend)
    keys = plan.keys(simulator.version)
    fingerprint, description = plan.fingerprint(simulator.version), dict(plan.description)
    rows = plan.rows(simulator.version)
    workers = options.workers or default_workers()
    with Store(store, wait=options.wait, on_wait=hooks.on_wait) as results:
        results.check_plan(fingerprint, description, len(rows), engine_text(simulator.engine, simulator.version))
        results.check_runs()  # every stored row read, and checked, before anything starts (none kept)
        with open_executor(simulator, executor=executor, workers=workers, scheduler=scheduler,
                           verbose=hooks.verbose, scratch=str(Path(store).resolve().parent), pool=options.pool) as run:
            results.adopt(fingerprint, description, rows, engine_text(simulator.engine, simulator.version))
            finished = results.finished() - (results.failed() if options.retry_failed else set())
            refused = {refusal.key: refusal for refusal in plan.refusals if refusal.key not in finished}
            # one transaction: nothing of them ran (no engine, no time), and a resume finds them stored
            if refused:
                results.add_many([(RunRecord(key=key, status="refused", reason=refusal.reason,
                                             label=refusal.label), None) for key, refusal in refused.items()])
            finished |= refused.keys()
            # each tolerance or preferred-value sample's realised L_i and C_j, stored with its run's metrics
            parts = {keys[task.index]: dict(task.parts) for task in plan.tasks if task.parts is not None}
            todo: dict[str, tuple[int, RunSpec, float]] = {}  # one run per key: two points may share a member
            for task in plan.tasks:
                if keys[task.index] not in finished:
                    todo.setdefault(keys[task.index], (task.index, task.spec, task.seconds))
            distinct = {keys[task.index] for task in plan.tasks} | {refusal.key for refusal in plan.refusals}
            skipped = len((distinct & finished) - refused.keys())  # a refusal stored now was not stored before
            if hooks.on_resume is not None:
                hooks.on_resume(skipped, len(todo))
            combining = _Combiner(plan, keys, results)
            combining.ready(finished)  # members stored by an earlier, interrupted run
            done = failed = 0
            transports = replace(choose_transports(list(todo.values()), simulator, workers, options.transport),
                                 deadline=deadline)
            for group in run(group_tasks(list(todo.values()), executor, workers), transports):
                for index, record in group:
                    if record.key != keys[index]:
                        raise ParameterError("--store", str(store), f"records under the plan's keys (run {index} "
                                             f"came back as {record.key[:12]}, expected {keys[index][:12]})")
                results.add_many([(record, None) for _, record in group], parts=parts)
                for _, record in group:
                    finished.add(record.key)
                    done += 1
                    failed += not record.ok
                combining.ready(finished)
                if progress is not None:
                    progress(Progress(done, len(todo), failed, time.perf_counter() - start))
        stored = results.statuses()
    status = {key: stored.get(key, ("pending", ""))[0] for key in keys.values()}
    combined = [status[keys[c.index]] for c in plan.combinations]
    refusals = tuple((str(r.params.get("netlist", r.label)), stored[r.key][1]) for r in _each_once(plan.refusals))
    return Summary(len(distinct), skipped, done, sum(status[key] == "ok" for key in distinct),
                   sum(status[key] in ("failed", "timeout") for key in distinct), str(store),
                   time.perf_counter() - start, combined.count("ok"), len(combined) - combined.count("ok"),
                   len(todo) - done, sum(status[key] == "refused" for key in distinct), refusals)


def _each_once(refusals: Sequence[Refusal]) -> Iterable[Refusal]:
    """A plan's refusals, each key once, in the batch's order (a netlist named twice is refused once)."""
    return {refusal.key: refusal for refusal in refusals}.values()


def _run_streamed(plan: StreamedPlan, store: str | Path, options: RunOptions, hooks: RunHooks,
                  start: float) -> Summary:
    """:func:`run_plan` of a batch whose runs are on disk (:mod:`lcchain.studies.stream`): the same store, rows,
    skips and summary, with nothing kept a run but a byte or two (what is stored is asked of the store a window of
    keys at a time, the runs are read back from the spool as the executor asks for them, and the summary is counted
    by the store)."""
    executor, progress, spool = options.executor, hooks.progress, plan.spool
    deadline = None if options.max_seconds is None else time.time() + options.max_seconds
    simulator = options.simulator if options.simulator is not None else find_engine(plan.engine, plan.backend)
    engine = engine_text(simulator.engine, simulator.version)
    fingerprint, description = plan.fingerprint(simulator.version), dict(plan.description)
    workers = options.workers or default_workers()
    rows = len(spool)
    listed = (plan.LISTED[0], plan.netlists)
    with Store(store, wait=options.wait, on_wait=hooks.on_wait) as results:
        results.check_plan(fingerprint, description, rows, engine, listed=listed)
        results.check_runs()  # every stored row read, and checked, before anything starts (none kept)
        with open_executor(simulator, executor=executor, workers=workers, scheduler=options.scheduler,
                           verbose=hooks.verbose, scratch=str(Path(store).resolve().parent), pool=options.pool) as run:
            results.adopt(fingerprint, description, plan.streamed_rows(simulator.version), engine, count=rows,
                          listed=listed)
            # what is stored, asked of the store a window of keys at a time (failed ones not, with retry_failed)
            skipped = spool.mark_stored(lambda keys: results.stored_among(keys, options.retry_failed))
            # one transaction: nothing of them ran (no engine, no time), and a resume finds them stored
            refused = {refusal.key: refusal for refusal in plan.refusals if not spool.stored(refusal.index)}
            if refused:
                results.add_many([(RunRecord(key=key, status="refused", reason=refusal.reason,
                                             label=refusal.label), None) for key, refusal in refused.items()])
            distinct, count = spool.keyed(), spool.todo()
            if hooks.on_resume is not None:
                hooks.on_resume(skipped, count)

            def able(engine: Engine, by_cost: bool) -> tuple[RunMask, int]:
                chosen = spool.chosen(engine.warm_below_seconds if by_cost else float("inf"))
                return RunMask(chosen), chosen.count(1)

            transports = replace(choose_transports_by(able, simulator, workers, options.transport),
                                 deadline=deadline)
            done = failed = 0
            for group in run(RunStream(spool.specs()), transports):
                for index, record in group:
                    if record.key != spool.key(index):
                        raise ParameterError("--store", str(store), f"records under the plan's keys (run {index} "
                                             f"came back as {record.key[:12]}, expected {spool.key(index)[:12]})")
                results.add_many([(record, None) for _, record in group])
                done += len(group)
                failed += sum(not record.ok for _, record in group)
                if progress is not None:
                    progress(Progress(done, count, failed, time.perf_counter() - start))
        counts = results.status_counts()
        reasons = results.reasons([refusal.key for refusal in plan.refusals])
    refusals = tuple((str(r.params.get("netlist", r.label)), reasons[r.key]) for r in _each_once(plan.refusals))
    return Summary(distinct, skipped, done, counts.get("ok", 0), counts.get("failed", 0) + counts.get("timeout", 0),
                   str(store), time.perf_counter() - start, 0, 0, count - done, counts.get("refused", 0), refusals)


class _Combiner:
    """Makes each extrapolation's record from its members' stored arrays once they are all stored."""

    def __init__(self, plan: Plan, keys: dict[int, str], store: Store):
        self.keys, self.store = keys, store
        done = {key for key, (status, _) in store.statuses().items() if status == "ok"} if plan.combinations else set()
        # a failed combination is made again: it costs no ngspice run, and its members may be fine
        self.pending = [c for c in plan.combinations if keys[c.index] not in done]

    def ready(self, finished: set[str]) -> None:
        waiting = []
        for combination in self.pending:
            if all(self.keys[i] in finished for i in combination.members):
                record, points = self._record(combination)
                parts = combination.parts
                self.store.add(record, points, parts=None if parts is None else dict(parts))
                finished.add(self.keys[combination.index])
            else:
                waiting.append(combination)
        self.pending = waiting

    def _record(self, combination: Combination) -> tuple[RunRecord, int]:
        """The combination's record and its members' points together; a failed record, never an exception, for
        members that cannot be combined (one bad point cannot stop a study)."""
        from ..runs.extrapolated import combined_record  # a study with combinations only: not a batch's

        member_keys = [self.keys[i] for i in combination.members]
        stored = self.store.records(member_keys)
        members = [run.record() for run in stored]
        points = sum(run.points or 0 for run in stored)
        try:
            sims = None
            if all(member.ok for member in members):
                sims = [self._sims(combination, key) for key in member_keys]
            record = combined_record(combination.theory, members, combination.steps,
                                     predicted_error=combination.predicted_error, sims=sims)
        except Exception as error:  # stored as this point's failure: one bad point cannot stop a study
            why = str(error) if isinstance(error, LcchainError) else f"{type(error).__name__}: {error}"
            record = RunRecord(key=self.keys[combination.index], status="failed", reason="its runs could not be "
                               f"combined: {why}", wall_s=sum(m.wall_s for m in members),
                               total_s=sum(m.total_s for m in members), engine=members[0].engine,
                               engine_version=members[0].engine_version)
        return replace(record, label=combination.label), points

    def _sims(self, combination: Combination, key: str) -> tuple[np.ndarray, np.ndarray]:
        arrays = self.store.waveforms(key)
        if arrays is None:
            raise ParameterError("--store", str(self.store.path), f"the arrays of the stored run {key[:12]}")
        time_s = arrays.pop("time")
        return loop_sims(combination.theory, time_s, arrays)


def check_specs(specs: Sequence[RunSpec], budget: Budget, *, executor: str = "process", workers: int | None = None,
                option: str = "--workers") -> None:
    """Refuse specs whose runs, on ``workers`` of ``executor`` (each worker an interpreter of its own holding a
    run, :meth:`lcchain.studies.plan.Plan.price`), exceed the budget; the refusal names ``option``."""
    workers = workers or default_workers()
    tasks = tuple(Task(i, {}, spec, _seconds(spec), _memory(spec)) for i, spec in enumerate(specs))
    backend, engine = (specs[0].backend, specs[0].engine) if specs else ("batch", "ngspice")
    Plan("scene", {}, tasks, backend, engine=engine).price(workers, executor).check(
        budget, option, workers, "fewer workers, or a larger --max-memory or --max-time")


def run_specs(specs: Sequence[RunSpec], options: RunOptions | None = None,
              hooks: RunHooks | None = None) -> list[RunRecord]:
    """Run specs on an executor without a store; the records come back in the specs' order, signals kept.
    ``options`` and ``hooks`` as for :func:`run_plan` (of the options, the executor, its workers and scheduler,
    the transport and the simulator; runs with a theory are priced by the transport's choice, others count as
    long)."""
    start = time.perf_counter()
    if not specs:
        return []
    options = options if options is not None else RunOptions()
    hooks = hooks if hooks is not None else RunHooks()
    executor, progress = options.executor, hooks.progress
    simulator = options.simulator if options.simulator is not None else find_engine(specs[0].engine,
                                                                                    specs[0].backend)
    workers = options.workers or default_workers()
    items = [(i, spec, _seconds(spec) if spec.theory is not None else 1.0) for i, spec in enumerate(specs)]
    transports = choose_transports(items, simulator, workers, options.transport)
    records: dict[int, RunRecord] = {}
    failed = 0
    for group in run_groups(group_tasks(items, executor, workers), simulator, executor=executor, workers=workers,
                            scheduler=options.scheduler, keep_signals=True, verbose=hooks.verbose,
                            transports=transports):
        for index, record in group:
            records[index] = record
            failed += not record.ok
        if progress is not None:
            progress(Progress(len(records), len(specs), failed, time.perf_counter() - start))
    return [records[i] for i in range(len(specs))]
