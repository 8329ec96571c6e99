"""ngspice as an :class:`~lcchain.spice.engine.Engine`: lcchain's netlists are written in its dialect.

It wraps what was there before engines: :func:`lcchain.spice.ngspice.find.find_simulator` (both transports,
``ngspice -b`` and the shared library) and :func:`lcchain.spice.ngspice.runner.run` (the allow-list and the sandbox
for netlists lcchain did not write), unchanged.  Its AC analysis runs the netlist as it is in the batch transport
(:func:`lcchain.spice.ngspice.runner.run_plot`) and reads the raw file's complex AC plot.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import ClassVar

from ...core.types import AnalysisKind, Backend
from ..acdata import ac_result
from ..engine import Engine
from ..job import AcJob, Progress, RunJob
from ..result import RunResult
from ..simulator import Simulator
from ..text import require_canonical
from .find import INSTALL_COMMAND, find_simulator
from .runner import PLOT_TRANSPORTS, run, run_plot
from .transports import is_named_transport, named_transports
from .warm import WARM_BELOW_SECONDS, close_workers, prestart_workers, warm_simulator

__all__ = ["Ngspice"]


class Ngspice(Engine):
    """ngspice: the identity dialect, both transports, and foreign netlists (allow-list, sandbox)."""

    name: ClassVar[str] = "ngspice"
    transports: ClassVar[tuple[Backend, ...]] = ("batch", "shared")  # its own; user_transports adds plugins'
    install: ClassVar[str] = INSTALL_COMMAND
    runs_foreign: ClassVar[bool] = True
    extrapolates: ClassVar[bool] = True
    steps_modelled: ClassVar[bool] = True
    runs_ac: ClassVar[bool] = True
    ac_transports: ClassVar[tuple[Backend, ...]] = PLOT_TRANSPORTS
    threaded_transports: ClassVar[tuple[Backend, ...]] = ("batch",)
    warm_below_seconds: ClassVar[float] = WARM_BELOW_SECONDS
    warm_analyses: ClassVar[tuple[AnalysisKind, ...]] = ("transient",)  # an AC run goes through ngspice -b

    def user_transports(self) -> tuple[str, ...]:
        return named_transports()  # read from the registry: a plugin's transport is ngspice's too

    def takes_transport(self, name: str) -> bool:
        return is_named_transport(name)

    def find(self, backend: str = "batch") -> Simulator:
        return replace(find_simulator(backend), engine=self.name)  # a subclass under another name finds its own

    def dialect(self, netlist: str, vectors: Sequence[str]) -> str:
        return require_canonical(netlist)  # ngspice runs the text as it is, split at LF as it was checked

    def run(self, job: RunJob, simulator: Simulator, progress: Progress | None = None) -> RunResult:
        return run(job, simulator, progress=progress)

    def warm(self, simulator: Simulator, workers: int = 1) -> Simulator:
        return warm_simulator(simulator, workers)

    def prestart(self, workers: int) -> None:
        prestart_workers(workers)

    def release(self, kill: bool = False) -> None:
        close_workers(kill)

    def run_ac(self, job: AcJob, simulator: Simulator) -> RunResult:
        columns, log, wall = run_plot(job, "ac", simulator)  # every .ac card's plot, one after the other
        if "frequency" in columns:  # ngspice leaves the frequency's imaginary part undefined
            columns["frequency"] = columns["frequency"].real
        return ac_result(job, columns, log, simulator, wall)
