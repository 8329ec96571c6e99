"""``lcchain batch`` as a function: netlists lcchain did not write, checked, priced and run in a sandbox, into a
store."""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from ..core.budget import INTERPRETER_SECONDS, Budget
from .studies import PlannedStudy, StudyHooks, StudyOptions, StudyResult, check_study, run_study, study_workers

__all__ = ["BatchRequest", "batch", "listed_names"]


@dataclass(frozen=True)
class BatchRequest:
    """The netlist files; ``listed``: a file that lists more, one name a line (:func:`listed_names`: read as the
    batch is planned, none of its names kept); ``allow_control`` runs each as it is (still in the sandbox);
    ``strict`` stops at the first one lcchain will not run; ``check`` compares each run with the netlist's exact
    response; where the runs go (``study``, its store required) and the budget (its time: the whole batch's)."""

    netlists: tuple[str, ...]
    allow_control: bool = False
    strict: bool = False
    check: bool = False
    study: StudyOptions = field(default_factory=StudyOptions)
    budget: Budget = field(default_factory=Budget)
    listed: str | None = None

    def names(self) -> Iterator[str]:
        """Every netlist's name: those given, then those listed (read from the list as they are asked for)."""
        yield from self.netlists
        if self.listed is not None:
            yield from listed_names(self.listed)

    def count(self) -> int:
        """How many netlists the batch has (the list read once through, and checked: one line naming it for a list
        lcchain cannot read)."""
        return len(self.netlists) + (sum(1 for _ in listed_names(self.listed)) if self.listed is not None else 0)


def listed_names(path: str, option: str = "--from") -> Iterator[str]:
    """The names the list at ``path`` holds, one a line, blank lines skipped, read a line at a time: a regular file
    of at most :data:`~lcchain.core.limits.MAX_NETLIST_LIST_BYTES` of UTF-8 text (else a
    :class:`~lcchain.core.errors.ParameterError` naming ``option`` and the path, as for any input file).  A batch
    of more names than a command line holds, with none of them kept, nor copied into the interpreter's own
    arguments."""
    from ..core.budget import show_bytes
    from ..core.errors import ParameterError
    from ..core.limits import MAX_NETLIST_LIST_BYTES
    from ..spice.inputs import open_input

    most = MAX_NETLIST_LIST_BYTES
    descriptor = open_input(path, option, most)  # a regular file of at most that size, never blocked by a FIFO
    with os.fdopen(descriptor, "rb", buffering=1 << 16) as handle:
        size = 0
        for number, data in enumerate(handle, 1):
            size += len(data)
            if size > most:  # it grew while being read
                raise ParameterError(option, path, f"a file of at most {show_bytes(most)}")
            try:
                line = data.decode("utf-8")
            except UnicodeDecodeError as error:  # strict, as read_input: a byte of the list not UTF-8
                raise ParameterError(option, path, f"UTF-8 text ({error.reason}: byte {data[error.start]:#04x} at "
                                     f"byte {size - len(data) + error.start}, line {number})") from None
            if number == 1:  # a byte-order mark opens the list, not its first name (as a netlist's is dropped)
                line = line.removeprefix("\ufeff")
            yield from (name for name in line.splitlines() if name.strip())


def batch(request: BatchRequest, hooks: StudyHooks | None = None) -> StudyResult:
    """A batch's --max-time is its whole budget: each run's own limits come from its price (batch_plan), and no run
    starts once the budget is spent (the runs left stay pending in the store). A netlist lcchain will not run is
    stored as refused and the others run; with ``strict`` the first refusal stops the batch (a ParameterError)."""
    from ..spice.engines import DEFAULT_ENGINE
    from ..studies.executors import EngineStart  # without numpy (tests/test_imports.py): it starts the engine first

    started = time.monotonic()
    check_study(request.study)
    budget = request.budget
    options = request.study
    count = request.count()
    if not count:
        from ..core.errors import ParameterError

        raise ParameterError("NETLIST", "none", "at least one netlist file, given or listed (--from LIST)")
    # ngspice found and its warm workers started while the netlists are read, checked and priced
    with EngineStart(DEFAULT_ENGINE, "batch", runs=0 if request.allow_control else count,
                     workers=study_workers(options), executor=options.executor,
                     transport=options.transport) as engine:
        from ..studies.plan import Plan, batch_plan  # numpy and the plan's modules load while the engine starts
        from ..studies.stream import StreamedPlan, streamed_batch_plan, streams

        plan: Plan
        told = [0]  # the netlists the plan has said it planned
        planning = hooks.planning if hooks is not None else None

        def progress(done: int) -> None:  # a list that grew since it was counted: never more done than total
            told[0] = done
            if planning is not None:
                planning(done, max(count, done))

        if streams(options.executor, study_workers(options)):  # its runs in this process: read from disk as they go
            assert options.store is not None
            plan = streamed_batch_plan(request.names(), lambda: engine.simulator(_load_the_runs).version,
                                       allow_control=request.allow_control, timeout=options.timeout, budget=budget,
                                       strict=request.strict, check=request.check,
                                       folder=str(Path(options.store).resolve().parent), progress=progress)
        else:
            plan = batch_plan(list(request.names()), allow_control=request.allow_control, timeout=options.timeout,
                              budget=budget, strict=request.strict, check=request.check, progress=progress)
        if planning is not None and 0 < told[0] < count:  # a list that shrank since it was counted: all told
            planning(told[0], told[0])
        left = budget.max_seconds - INTERPRETER_SECONDS - (time.monotonic() - started)
        try:
            return run_study(PlannedStudy(plan, max_seconds=max(left, 0.0)), options, budget, hooks,
                             simulator=engine.simulator())
        finally:
            if isinstance(plan, StreamedPlan):
                plan.spool.close()


def _load_the_runs() -> None:
    """Load what runs a plan (the store, the runs' records): done while the plan waits for the engine to start."""
    from ..studies import run  # noqa: F401
