"""``lcchain batch`` as a function: netlists lcchain did not write, checked, priced and run in a sandbox, into a
store."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

from ..core.budget import INTERPRETER_SECONDS, Budget
from .studies import PlannedStudy, StudyHooks, StudyOptions, StudyResult, check_study, run_study, study_workers

__all__ = ["BatchRequest", "batch", "listed_netlists"]


@dataclass(frozen=True)
class BatchRequest:
    """The netlist files; ``allow_control`` runs each as it is (still in the sandbox); ``strict`` stops at the
    first one lcchain will not run; ``check`` compares each run with the netlist's exact response; where the
    runs go (``study``, its store required) and the budget (its time: the whole batch's)."""

    netlists: tuple[str, ...]
    allow_control: bool = False
    strict: bool = False
    check: bool = False
    study: StudyOptions = field(default_factory=StudyOptions)
    budget: Budget = field(default_factory=Budget)


def listed_netlists(path: str, text: str | None = None) -> tuple[str, ...]:
    """The netlist file names a list holds (``lcchain batch --from LIST``): one a line, as given (relative to the
    current folder), blank lines skipped.  ``text``: the list already read (standard input); else the file at
    ``path``, a regular file of at most :data:`~lcchain.core.limits.MAX_NETLIST_LIST_BYTES`.  A batch of more
    names than a command line holds, and no copy of each name in the interpreter's own arguments."""
    from ..core.limits import MAX_NETLIST_LIST_BYTES
    from ..spice.inputs import read_input

    if text is None:
        text = read_input(path, "--from", MAX_NETLIST_LIST_BYTES)
    return tuple(line for line in text.splitlines() if line.strip())


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
    # ngspice found and its warm workers started while the netlists are read, checked and priced
    with EngineStart(DEFAULT_ENGINE, "batch", runs=0 if request.allow_control else len(request.netlists),
                     workers=study_workers(options), executor=options.executor,
                     transport=options.transport) as engine:
        from ..studies.plan import Plan, batch_plan  # numpy and the plan's modules load while the engine starts
        from ..studies.stream import StreamedPlan, streamed_batch_plan, streams

        plan: Plan
        if streams(options.executor, study_workers(options)):  # its runs in this process: read from disk as they go
            assert options.store is not None
            plan = streamed_batch_plan(list(request.netlists), lambda: engine.simulator().version,
                                       allow_control=request.allow_control, timeout=options.timeout, budget=budget,
                                       strict=request.strict, check=request.check,
                                       folder=str(Path(options.store).resolve().parent))
        else:
            plan = batch_plan(list(request.netlists), allow_control=request.allow_control, timeout=options.timeout,
                              budget=budget, strict=request.strict, check=request.check)
        left = budget.max_seconds - INTERPRETER_SECONDS - (time.monotonic() - started)
        try:
            return run_study(PlannedStudy(plan, max_seconds=max(left, 0.0)), options, budget, hooks,
                             simulator=engine.simulator())
        finally:
            if isinstance(plan, StreamedPlan):
                plan.spool.close()
