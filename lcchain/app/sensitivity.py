"""``lcchain sensitivity`` as functions: which components move the first-arrival peak, and by how much, from
exact theory; with ``check``, ngspice's central differences against it (runs through a plan and a store)."""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..core.budget import Budget
from ..core.errors import ParameterError
from ..core.types import ArrivalMetric
from ..report.files import FIGURE_FORMATS
from .inputs import ChainOptions, Outputs, make_chain
from .studies import STORE_FORMATS, StudyOptions, StudyProgress, check_executor, study_workers

if TYPE_CHECKING:
    from ..circuit.sensitivity import Component, LadderSensitivity
    from ..studies.sensitivity import Check
    from ..theory.chain import Chain

__all__ = ["SensitivityRequest", "Sensitivity", "sensitivity", "write_plot", "METRIC_NAMES"]

#: How each metric is named: its symbol and what it is.
METRIC_NAMES = {"peak": ("p", "first-arrival peak p = max I_N/I_1(0)"),
                "energy": ("e", "first-arrival energy fraction e = p^2 L_N/L_1")}


@dataclass(frozen=True)
class SensitivityRequest:
    """The chain and its units, the ``metric``, the ``top`` rows (0: all), ``check`` components to run in ngspice
    at 1 +- h (each run to ``accuracy``; the runs kept in ``study.store`` when one is named), ``plot`` a figure;
    ``progress(label)`` gives the callback of the theory's fraction done, ``study_progress`` that of the runs."""

    chain: ChainOptions
    L0: float
    C0: float
    metric: ArrivalMetric = "peak"
    top: int = 10
    check: int = 0
    accuracy: float = 1e-4
    plot: str | None = None
    study: StudyOptions = field(default_factory=StudyOptions)
    budget: Budget = field(default_factory=Budget)
    progress: Callable[[str], Callable[[float], None]] | None = None
    study_progress: Callable[[StudyProgress], None] | None = None


@dataclass(frozen=True)
class Sensitivity:
    """The ladder's sensitivities (:class:`lcchain.circuit.sensitivity.LadderSensitivity`), the ``top`` components
    shown, each ngspice check (:class:`lcchain.studies.sensitivity.Check`), the figure still to write (its
    ``outputs``), and ``notes``: what the command says beside the result (the check's runs that failed)."""

    request: SensitivityRequest
    chain: Chain
    sensitivity: LadderSensitivity
    top: list[Component]
    checks: list[Check]
    outputs: Outputs
    notes: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        """Every check ran and agreed with the theory (True without checks)."""
        wanted = self.request.check
        return not wanted or (len(self.checks) >= wanted and all(check.passed for check in self.checks))


def _checks(request: SensitivityRequest, sensitivity: LadderSensitivity) -> tuple[list[Check], tuple[str, ...]]:
    """The check's runs through a plan and a store (the user's, or a temporary one), read back as rows; and the
    note that says how many failed, if any did."""
    from ..spice.scratch import scratch_folder
    from ..studies.options import RunHooks, RunOptions
    from ..studies.run import run_plan
    from ..studies.sensitivity import check_plan, check_rows
    from ..studies.store import Store

    study = request.study
    plan, steps = check_plan(sensitivity, request.check, accuracy=request.accuracy, budget=request.budget,
                             timeout=study.timeout)
    workers = study_workers(study)
    plan.check(request.budget, workers, study.executor, "--check")
    with contextlib.ExitStack() as stack:
        store = study.store or str(stack.enter_context(scratch_folder("check", watch=True)) / "check.sqlite")
        summary = run_plan(plan, store, RunOptions(study.executor, workers, study.scheduler, study.transport),
                           RunHooks(progress=request.study_progress))
        with Store(store, "read") as stored:
            rows = check_rows(stored.runs(), steps, sensitivity.metric)
    if summary.failed or summary.combined_failed:
        where = f"'lcchain results {study.store}' says why" if study.store else "keep them with --store FILE to see why"
        return rows, (f"{summary.failed + summary.combined_failed} of the check's runs failed ({where})",)
    return rows, ()


def sensitivity(request: SensitivityRequest) -> Sensitivity:
    """The sensitivities from exact theory, and the ngspice check when asked for (outputs checked first)."""
    from ..circuit.ladder import Ladder
    from ..circuit.sensitivity import ladder_sensitivity
    from ..core.budget import sensitivity_estimate
    from ..theory.sensitivity import SENSITIVITY_MAX_N

    outputs = Outputs(inputs={"--chain": request.chain.chain} if request.chain.chain else {})
    outputs.check("--plot", request.plot, FIGURE_FORMATS)
    outputs.check("--store", request.study.store, STORE_FORMATS)
    if request.top < 0:
        raise ParameterError("--top", request.top, "an integer >= 0 (0: every component)")
    if request.check < 0:
        raise ParameterError("--check", request.check, "an integer >= 0 (0: no ngspice runs)")
    if request.study.store and not request.check:
        raise ParameterError("--store", request.study.store, "only with --check M (the store keeps its runs)")
    check_executor(request.study)
    chain = make_chain(request.chain, request.budget, max_N=SENSITIVITY_MAX_N)
    sensitivity_estimate(chain.N).check(request.budget, "N", chain.N)  # --N, or the --chain FILE
    shown = None if request.progress is None else request.progress(f"sensitivities of {chain.N} masses")
    if shown is not None:  # one O(N^3) step: 5 s at N = 2000
        shown(0.0)
    result = ladder_sensitivity(Ladder(chain, request.L0, request.C0), metric=request.metric)
    if shown is not None:
        shown(1.0)
    top = list(result.components[: request.top or None])
    checks, notes = _checks(request, result) if request.check else ([], ())
    return Sensitivity(request, chain, result, top, checks, outputs, notes)


def write_plot(result: Sensitivity) -> bool:
    """Draw ``--plot`` (after the result was shown): dp/d ln x along the chain; returns whether it could not be
    written (said in a note of ``result.outputs``)."""
    request, chain, sensitivity, checks, outputs = (result.request, result.chain, result.sensitivity,
                                                    result.checks, result.outputs)
    if request.plot:
        from ..report.sensitivity import sensitivity_chart

        N = chain.N
        position = {part.name: part.slot + 1 if part.kind == "L" else part.slot - N + 0.5
                    for part in sensitivity.components}
        inductors = [(part.slot + 1, part.relative) for part in sensitivity.components if part.kind == "L"]
        capacitors = [(part.slot - N, part.relative) for part in sensitivity.components if part.kind == "C"]
        checked = [(position[c.component.name], c.fd, c.error_bar) for c in checks]
        outputs.write("--plot", lambda path: sensitivity_chart(
            sorted(inductors), sorted(capacitors), checked=checked,
            title=f"{chain.name} chain, N = {N}: sensitivity of the {METRIC_NAMES[request.metric][1]} = "
                  f"{sensitivity.value:.4f}", metric=METRIC_NAMES[request.metric][0],
            path=path))
    return bool(outputs.failed)
