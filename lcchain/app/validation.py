"""``lcchain report`` as a function: run the circuit's checks in ngspice, then render the whole report."""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from typing import Any

from ..report.build import build_report
from ..studies.validation import circuit_checks, installed_engines

__all__ = ["make_report"]


def make_report(out: str | os.PathLike[str], *, quick: bool = False, cache: str | os.PathLike[str] | None = None,
                progress: Callable[[int, int, str], None] | None = None,
                command: str = "lcchain report") -> dict[str, Any]:
    """The validation report: every installed engine on the reference set
    (:func:`lcchain.studies.validation.circuit_checks`), then the paper's tables and figures and the page
    (:func:`lcchain.report.build.build_report`) in ``out``."""
    start = time.perf_counter()
    simulators = installed_engines()
    circuit = circuit_checks(quick=quick, progress=progress, simulators=simulators)
    return build_report(out, circuit, {s.engine: s.version for s in simulators}, quick=quick, cache=cache,
                        progress=progress, command=command, seconds=time.perf_counter() - start)
