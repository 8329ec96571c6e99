"""``lcchain report`` as a function: run the circuit's checks in every engine, then render the whole report.

The checks and the rows of Tables I and II that are not in the cache (together most of a cold report's time)
are independent: they are done on every core by one process pool (:class:`lcchain.studies.background.Background`),
the longest first, while this process draws each check's figure and then the tables and the paper's figures as
their rows arrive.  The pool is closed, its workers and their simulators gone, when the report is written or
abandoned.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..core.types import DesignCase
from ..report.build import build_report, report_rows
from ..report.figure_data import DesignRows
from ..studies.background import Background, Job
from ..studies.designs import design_row, design_task
from ..studies.requirements import requirements_jobs, run_requirements
from ..studies.spectrum_checks import run_spectrum_check, spectrum_jobs
from ..studies.validation import check_jobs, installed_engines, run_check

__all__ = ["make_report", "ReportRequest", "report"]


@dataclass(frozen=True)
class ReportRequest:
    """``lcchain report``: the folder for index.html and report.json (created if missing), ``quick`` (the
    paper's printed rows and a few more, fewer simulator runs), ``cache`` whether rows of Tables I and II are
    kept and reused, ``progress(done, total, label)``, the ``command`` the page names."""

    out: str
    quick: bool = False
    cache: bool = True
    progress: Callable[[int, int, str], None] | None = None
    command: str = "lcchain report"


def report(request: ReportRequest) -> dict[str, Any]:
    """The output folder checked, then :func:`make_report`: the report's JSON (its checks, the seconds taken)."""
    from ..report.files import check_output_folder
    from .figures import cache_dir

    check_output_folder("--out", request.out)
    return make_report(request.out, quick=request.quick, cache=cache_dir(request.cache), progress=request.progress,
                       command=request.command)


def make_report(out: str | os.PathLike[str], *, quick: bool = False, cache: str | os.PathLike[str] | None = None,
                progress: Callable[[int, int, str], None] | None = None,
                command: str = "lcchain report", workers: int | None = None) -> dict[str, Any]:
    """The validation report: every installed engine on the reference set
    (:func:`lcchain.studies.validation.circuit_checks`), ngspice's spectra of the reference ladders
    (:func:`lcchain.studies.spectrum_checks.spectrum_jobs`) and the cradles' parts' requirements
    (:func:`lcchain.studies.requirements.requirements_jobs`), then the paper's tables and figures and the page
    (:func:`lcchain.report.build.build_report`) in ``out``.

    The checks, and the table rows not in ``cache``, are done by ``workers`` processes (default: one per core;
    1 does them here, one after the other); the numbers are the same either way.
    """
    start = time.perf_counter()
    simulators = installed_engines()
    jobs = check_jobs(quick=quick, simulators=simulators)
    spectra = spectrum_jobs(quick=quick, simulator=simulators[0])
    cradles = requirements_jobs(quick=quick)
    rows = DesignRows(cache)
    tasks = [Job(("check", i), job.cost, run_check, (job,)) for i, job in enumerate(jobs)]
    tasks += [Job(("spectrum", i), job.cost, run_spectrum_check, (job,)) for i, job in enumerate(spectra)]
    tasks += [Job(("requirements", i), job.cost, run_requirements, (job,)) for i, job in enumerate(cradles)]
    tasks += [design_task(case, N) for case, N in rows.missing(report_rows(quick))]
    with Background(tasks, workers) as background:

        def design(case: DesignCase, N: int) -> dict[str, Any]:
            key = ("row", case, N)
            return background.take(key) if key in background else design_row(case, N)

        rows.design = design
        keys = [("check", i) for i in range(len(jobs))] + [("spectrum", i) for i in range(len(spectra))]
        keys += [("requirements", i) for i in range(len(cradles))]
        labels = [job.label or job.name for job in jobs] + [job.label for job in spectra]
        labels += [job.label for job in cradles]
        results = []
        for i, (key, label) in enumerate(zip(keys, labels, strict=True)):
            if progress is not None:
                progress(i, len(keys), label)
            results.append(background.take(key))
        if progress is not None:
            progress(len(keys), len(keys), "done")
        spectrum_end = len(jobs) + len(spectra)
        return build_report(out, results[:len(jobs)], {s.engine: s.version for s in simulators}, quick=quick,
                            cache=cache, progress=progress, command=command, seconds=time.perf_counter() - start,
                            rows=rows, spectrum=results[len(jobs):spectrum_end],
                            requirements=results[spectrum_end:])
