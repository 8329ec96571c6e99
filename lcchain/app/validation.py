"""``lcchain report`` as a function: run the circuit's checks in ngspice, then render the whole report.

The rows of Tables I and II (most of a cold report's time) are designed meanwhile on every core, by a process
pool (:class:`lcchain.studies.designs.BackgroundDesigns`) opened before the circuit's checks start and closed,
its workers gone, when the report is written or abandoned.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from typing import Any

from ..report.build import build_report, report_rows
from ..report.figure_data import DesignRows
from ..studies.designs import BackgroundDesigns
from ..studies.validation import circuit_checks, installed_engines

__all__ = ["make_report"]


def make_report(out: str | os.PathLike[str], *, quick: bool = False, cache: str | os.PathLike[str] | None = None,
                progress: Callable[[int, int, str], None] | None = None,
                command: str = "lcchain report", workers: int | None = None) -> dict[str, Any]:
    """The validation report: every installed engine on the reference set
    (:func:`lcchain.studies.validation.circuit_checks`), then the paper's tables and figures and the page
    (:func:`lcchain.report.build.build_report`) in ``out``.

    The table rows not in ``cache`` are designed by ``workers`` processes (default: one per core; 1 designs
    them here, one after the other) while the circuit's checks run; the numbers are the same either way.
    """
    start = time.perf_counter()
    simulators = installed_engines()
    rows = DesignRows(cache)
    with BackgroundDesigns(rows.missing(report_rows(quick)), workers) as designs:
        rows.design = designs.take
        circuit = circuit_checks(quick=quick, progress=progress, simulators=simulators)
        return build_report(out, circuit, {s.engine: s.version for s in simulators}, quick=quick, cache=cache,
                            progress=progress, command=command, seconds=time.perf_counter() - start, rows=rows)
