"""``lcchain check FILE`` as a function: a linear netlist's simulation against its exact response
(:func:`lcchain.runs.check.check_file`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..core.budget import Budget

if TYPE_CHECKING:
    from ..runs.check import CheckResult

__all__ = ["CheckRequest", "check"]


@dataclass(frozen=True)
class CheckRequest:
    """The netlist file, the wanted relative ``accuracy`` (None: 1e-6, for the suggested step only), the engine,
    the simulator's timeout in seconds, whether its ``.control`` blocks may run (in the sandbox), the budget."""

    netlist: str
    accuracy: float | None = None
    engine: str = "ngspice"
    timeout: float = 600.0
    allow_control: bool = False
    budget: Budget = field(default_factory=Budget)


def check(request: CheckRequest) -> CheckResult:
    """The :class:`lcchain.runs.check.CheckResult`: each saved vector's error, the step an accuracy needs."""
    from ..runs.check import CheckOptions, check_file

    return check_file(request.netlist, CheckOptions(accuracy=request.accuracy, engine=request.engine,
                                                    timeout=request.timeout, allow_control=request.allow_control,
                                                    budget=request.budget))
