"""``lcchain report`` as a function: run the circuit's checks in every engine, then render the whole report.

The checks, the rows of Tables I and II that are not in the cache and the paper's figures that need no row are
independent: they are done on every core by one process pool (:class:`lcchain.studies.background.Background`),
the longest first, and each check's figure (and each cradle's chart) is drawn in the process that ran it.  This
process meanwhile takes the rows as they arrive and draws the paper's figures made of them, then renders the
page.  The pool is closed, its workers and their simulators gone, when the report is written or abandoned.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from typing import Protocol, TypeVar

from ..core.json import LooseJSONObject
from ..core.types import DesignCase
from ..report.build import (
    ReportOptions,
    ReportParts,
    ValidationRuns,
    build_report,
    check_figure_png,
    paper_figure_png,
    report_rows,
    requirements_figure_png,
)
from ..report.figure_data import DesignRows
from ..report.paper_figures import FIGURES
from ..report.validation import paper_section
from ..studies.background import Background, Job
from ..studies.designs import design_row, design_task
from ..studies.requirements import RequirementsCheck, RequirementsJob, requirements_jobs, run_requirements
from ..studies.spectrum_checks import SpectrumCheck, run_spectrum_check, spectrum_jobs
from ..studies.validation import CheckJob, CircuitCheck, check_jobs, installed_engines, run_check
from ..theory.design import DESIGN_TABLES

__all__ = ["make_report", "HERE_S", "ReportRequest", "report"]

#: A row of Tables I and II estimated to take at most this (seconds, :func:`lcchain.studies.designs.design_cost`:
#: two-mass up to N = 2000, one-mass up to N = 10000: 80 rows, 8.7 s of CPU in all, measured) is designed here
#: while the pool does the longer work, rather than queued behind it: the figures made of the rows can then be
#: drawn here before the pool is done.
HERE_S = 0.5

T = TypeVar("T")


class _Named(Protocol):
    @property
    def name(self) -> str: ...


#: A check or a cradle: a result whose figure is kept under its name.
Checked = TypeVar("Checked", bound=_Named)


def _expected(key: Hashable, found: object, kind: type[T]) -> T:
    """A background task's result, of the type its key's task returns."""
    if not isinstance(found, kind):
        raise TypeError(f"the background task {key!r} returned a {type(found).__name__}, not a {kind.__name__}")
    return found


def _drawn_pair(key: Hashable, found: object, kind: type[T]) -> tuple[T, bytes | None]:
    """A task's (result, its figure's PNG or None), as :func:`_check_drawn` and :func:`_cradle_drawn` return them."""
    result, png = _expected(key, found, tuple)
    if png is not None and not isinstance(png, bytes):
        raise TypeError(f"the background task {key!r} returned a {type(png).__name__} for its figure, not bytes")
    return _expected(key, result, kind), png


def _check_drawn(job: CheckJob) -> tuple[CircuitCheck, bytes | None]:
    """A check run, and its figure drawn where it ran (its curves need not travel to be drawn)."""
    check = run_check(job)
    return check, check_figure_png(check)


def _cradle_drawn(job: RequirementsJob) -> tuple[RequirementsCheck, bytes | None]:
    """A cradle's requirements, and their chart drawn where they were computed."""
    cradle = run_requirements(job)
    return cradle, requirements_figure_png(cradle)

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


def report(request: ReportRequest) -> LooseJSONObject:
    """The output folder checked, then :func:`make_report`: the report's JSON (its checks, the seconds taken)."""
    from ..report.files import check_output_folder
    from .figures import cache_dir

    check_output_folder("--out", request.out)
    return make_report(request.out, quick=request.quick, cache=cache_dir(request.cache), progress=request.progress,
                       command=request.command)


def make_report(out: str | os.PathLike[str], *, quick: bool = False, cache: str | os.PathLike[str] | None = None,
                progress: Callable[[int, int, str], None] | None = None,
                command: str = "lcchain report", workers: int | None = None) -> LooseJSONObject:
    """The validation report: every installed engine on the reference set
    (:func:`lcchain.studies.validation.check_jobs`), ngspice's spectra of the reference ladders
    (:func:`lcchain.studies.spectrum_checks.spectrum_jobs`) and the cradles' parts' requirements
    (:func:`lcchain.studies.requirements.requirements_jobs`), then the paper's tables and figures and the page
    (:func:`lcchain.report.build.build_report`) in ``out``.

    The checks, the table rows not in ``cache`` and the paper's figures that need no row are done by ``workers``
    processes (default: one per core; 1 does them here, one after the other); the numbers are the same either way.
    """
    start = time.perf_counter()
    simulators = installed_engines()
    jobs = check_jobs(quick=quick, simulators=simulators)
    spectra = spectrum_jobs(quick=quick, simulator=simulators[0])
    cradles = requirements_jobs(quick=quick)
    rows = DesignRows(cache)
    needed = report_rows(quick)
    alone = [figure for figure in FIGURES if not figure.uses_rows]
    tasks: list[Job[object]] = [Job(("check", i), job.cost, _check_drawn, (job,)) for i, job in enumerate(jobs)]
    tasks += [Job(("spectrum", i), job.cost, run_spectrum_check, (job,)) for i, job in enumerate(spectra)]
    tasks += [Job(("requirements", i), job.cost, _cradle_drawn, (job,)) for i, job in enumerate(cradles)]
    tasks += [Job(("paper", figure.label), figure.seconds, paper_figure_png, (figure, None, quick))
              for figure in alone]
    tasks += [task for task in (design_task(case, N) for case, N in rows.missing(needed)) if task.cost > HERE_S]
    with Background(tasks, workers) as background:

        def design(case: DesignCase, N: int) -> LooseJSONObject:
            key = ("row", case, N)
            return _expected(key, background.take(key), dict) if key in background else design_row(case, N)

        rows.design = design
        # the rows first (the short ones designed here, while the pool has the long ones), then the paper's half
        # and the figures made of them, while the pool does the rest
        ordered = sorted(needed, key=lambda pair: ("row", *pair) in background)
        for i, (case, N) in enumerate(ordered):
            if progress is not None:
                progress(i, len(ordered), f"{DESIGN_TABLES[case][0]}, N = {N}")
            rows.row(case, N)
        paper = paper_section(rows, quick=quick)
        figures = {f"paper:{figure.label}": paper_figure_png(figure, rows, quick)
                   for figure in FIGURES if figure.uses_rows}
        labels = [job.label or job.name for job in jobs] + [job.label for job in spectra]
        labels += [job.label for job in cradles] + [f"Fig. {figure.label}" for figure in alone]
        total, done = len(labels), 0

        def take(key: Hashable) -> object:
            nonlocal done
            if progress is not None:
                progress(done, total, labels[done])
            done += 1
            return background.take(key)

        def drawn(kind: str, count: int, made_of: type[Checked]) -> list[Checked]:
            """The pool's results of one kind in order, each figure it drew kept under ``KIND:NAME``."""
            made = []
            for i in range(count):
                result, png = _drawn_pair((kind, i), take((kind, i)), made_of)
                made.append(result)
                if png is not None:
                    figures[f"{kind}:{result.name}"] = png
            return made

        circuit = drawn("check", len(jobs), CircuitCheck)
        spectrum = [_expected(("spectrum", i), take(("spectrum", i)), SpectrumCheck) for i in range(len(spectra))]
        requirements = drawn("requirements", len(cradles), RequirementsCheck)
        for figure in alone:
            figures[f"paper:{figure.label}"] = _expected(("paper", figure.label), take(("paper", figure.label)), bytes)
        if progress is not None:
            progress(total, total, "done")
        runs = ValidationRuns(circuit, {s.engine: s.version for s in simulators}, spectrum, requirements,
                              time.perf_counter() - start)
        return build_report(out, runs, ReportOptions(quick, cache, command), ReportParts(rows, figures, paper),
                            progress)
