"""Test-only lcchain plugin, installed apart from lcchain: an effect and an engine, found through entry points."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

from lcchain.circuit.effects import Effect
from lcchain.circuit.ladder import Ladder
from lcchain.core.checks import real
from lcchain.spice.job import Progress, RunJob
from lcchain.spice.ngspice.engine import Ngspice
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.result import RunResult
from lcchain.spice.simulator import Simulator


@dataclass(frozen=True)
class NodeLeakage(Effect):
    """``[effects.node_leakage]``: a resistor R sqrt(L0/C0) from every rail node to ground (the board's leakage)."""

    key: ClassVar[str] = "node_leakage"
    option: ClassVar[str | None] = "--node-leakage"
    option_help: ClassVar[str] = "a resistor R*sqrt(L0/C0) from every rail node to ground (R > 0)"
    R: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "R", real("effects.node_leakage.R", self.R, above=0.0,
                                           allowed="a finite number > 0 (resistance / sqrt(L0/C0))"))

    def to_ground(self, ladder: Ladder, node: int) -> tuple[tuple[str, float], ...]:
        return (("R", self.R * ladder.impedance),)


class RenamedNgspice(Ngspice):
    """ngspice under another name (its transient only)."""

    name: ClassVar[str] = "renamed-ngspice"
    runs_ac: ClassVar[bool] = False

    def find(self, backend="batch") -> Simulator:
        return dataclasses.replace(find_simulator(backend), engine=self.name)

    def dialect(self, netlist: str, vectors: Sequence[str]) -> str:
        return netlist

    def run(self, job: RunJob, simulator: Simulator, progress: Progress | None = None) -> RunResult:
        result = run(job, dataclasses.replace(simulator, engine="ngspice"), progress=progress)
        return dataclasses.replace(result, engine=self.name)
