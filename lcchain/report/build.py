"""``lcchain figures`` and ``lcchain report`` as functions: compute, draw, write (atomically, at the end)."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..core.checks import instance, text_line
from ..core.errors import ParameterError
from ..core.json import LooseJSONObject
from ..core.types import DesignCase
from ..studies.requirements import RequirementsCheck
from ..studies.validation import CircuitCheck
from .figure_data import FULL_N, QUICK_N, DesignRows
from .files import write_text
from .html import figure_png, render_html, report_json
from .paper_figures import FIGURES, AnyPaperFigure, make_figures
from .plots import OverlayCurves, overlay
from .requirements import requirements_figures
from .spectrum import spectrum_figures
from .validation import QUICK_REPORT_N, REPORT_N, PaperSection, ValidationRuns, validation_report

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["ReportOptions", "ReportParts", "ValidationRuns", "build_figures", "build_report", "report_rows",
           "check_figure_png", "paper_figure_png",
           "requirements_figure_png"]

Progress = Callable[[int, int, str], None]


def build_figures(out: str | os.PathLike[str], *, quick: bool = False, fmt: str = "png",
                  cache: str | os.PathLike[str] | None = None, progress: Progress | None = None) -> list[Path]:
    """Every figure of the paper into ``out`` (created if missing): ``<label>.<fmt>``."""
    return make_figures(out, quick=quick, fmt=fmt, rows=DesignRows(cache), progress=progress)


def _check_figure(check: CircuitCheck) -> Figure:
    curves = check.curves
    ylabel = "$Q_N\\,/\\,Q_1(0)$" if check.excitation == "displacement" else "$I_N\\,/\\,I_1(0)$"
    figure = overlay(OverlayCurves(curves["t"], curves["sim"], curves["t"], curves["theory"],
                                   residual=curves["residual"], arrivals=curves["arrivals"]),
                     title=f"{check.name} ({check.what})", ylabel=ylabel)
    figure.set_size_inches(5.6, 3.8)
    return figure


def check_figure_png(check: CircuitCheck) -> bytes | None:
    """A circuit check's figure as the page shows it (None: the check has no curves); a function of its own, so
    that it may be drawn in the process that ran the check."""
    return figure_png(_check_figure(check), dpi=90) if check.curves else None


def paper_figure_png(figure: AnyPaperFigure, rows: DesignRows | None, quick: bool) -> bytes:
    """One of the paper's figures as the page shows it (``rows`` None for a figure that uses none)."""
    return figure_png(figure.build(rows, quick))


def requirements_figure_png(check: RequirementsCheck) -> bytes | None:
    """A cradle's chart of its parts' requirements as the page shows it (None: its study failed)."""
    figure = requirements_figures([check]).get(check.name)
    return None if figure is None else figure_png(figure, dpi=90)


def report_rows(quick: bool = False) -> list[tuple[DesignCase, int]]:
    """Every row of Tables I and II the report reads: its tables' (:data:`.validation.REPORT_N`, or
    :data:`.validation.QUICK_REPORT_N`) and its figures' (:data:`.figure_data.FULL_N` or ``QUICK_N`` for both
    cases, two-mass N = 20 and 100 for Fig. Pk20-100), each once; a row left out is designed when read."""
    tables = QUICK_REPORT_N if quick else REPORT_N
    figures = QUICK_N if quick else FULL_N
    cases: tuple[DesignCase, ...] = ("one-mass", "two-mass")
    pairs = [(case, N) for case in cases for N in tables[case]]
    pairs += [(case, N) for case in cases for N in figures] + [("two-mass", 20), ("two-mass", 100)]
    return list(dict.fromkeys(pairs))


@dataclass(frozen=True)
class ReportOptions:
    """How the report is made: ``quick`` (the paper's printed rows and a few more, instead of every N of
    :data:`.validation.REPORT_N`), where the designed rows are kept between runs (``cache``, a folder; None: not
    kept), and the ``command`` the page says made it."""

    quick: bool = False
    cache: str | os.PathLike[str] | None = None
    command: str = "lcchain report"

    def __post_init__(self) -> None:
        if not isinstance(self.quick, bool):
            raise ParameterError("quick", self.quick, "True or False")
        text_line("command", self.command, 1000)


@dataclass(frozen=True)
class ReportParts:
    """What of the report was made already, elsewhere (the processes that ran the checks): ``rows`` gives the
    tables' rows (None: ``DesignRows(cache)``, designed as they are read); ``figures`` are PNGs drawn
    (:func:`check_figure_png` as ``check:<name>``, :func:`paper_figure_png` as ``paper:<label>``,
    :func:`requirements_figure_png` as ``requirements:<name>``), not drawn again; ``paper`` is
    :func:`lcchain.report.validation.paper_section` of ``rows``."""

    rows: DesignRows | None = field(default=None, compare=False)
    figures: Mapping[str, bytes] = field(default_factory=dict)
    paper: PaperSection | None = None

    def __post_init__(self) -> None:
        instance("rows", self.rows, DesignRows, optional=True)
        instance("figures", self.figures, (Mapping,))
        if self.paper is not None and self.rows is None:
            raise ParameterError("paper", "a paper section", "the rows it was made of too (rows=...)")


def build_report(out: str | os.PathLike[str], runs: ValidationRuns, options: ReportOptions | None = None,
                 made: ReportParts | None = None, progress: Progress | None = None) -> LooseJSONObject:
    """Compute the paper's half of the validation report, render it with the circuit's runs, spectra and the
    cradles' parts' requirements (already made, ``runs``), then write ``out/index.html`` and ``out/report.json``;
    return it as data.

    The circuit's figures are drawn first, so that rows still being designed elsewhere
    (:class:`lcchain.studies.background.Background`) are not waited for meanwhile; what ``made`` holds is not
    made again.
    """
    options = options if options is not None else ReportOptions()
    made = made if made is not None else ReportParts()
    quick, circuit, spectrum, requirements = options.quick, runs.circuit, runs.spectrum, runs.requirements
    rows = made.rows if made.rows is not None else DesignRows(options.cache)
    drawn = dict(made.figures)
    pngs: dict[str, bytes] = {}
    for check in circuit:
        key = f"check:{check.name}"
        png = drawn[key] if key in drawn else check_figure_png(check)
        if png is not None:
            pngs[key] = png
    report = validation_report(rows, runs, quick=quick, progress=progress, paper=made.paper)
    for label, figure in spectrum_figures(spectrum, rows).items():
        pngs[f"spectrum:{label}"] = figure_png(figure)
    for cradle in requirements:
        key = f"requirements:{cradle.name}"
        png = drawn[key] if key in drawn else requirements_figure_png(cradle)
        if png is not None:
            pngs[key] = png
    for i, paper_figure in enumerate(FIGURES):
        if progress is not None:
            progress(i, len(FIGURES), f"Fig. {paper_figure.label}")
        key = f"paper:{paper_figure.label}"
        pngs[key] = drawn[key] if key in drawn else paper_figure_png(paper_figure, rows, quick)
    if progress is not None:
        progress(len(FIGURES), len(FIGURES), "writing")
    page = render_html(report, pngs, [(f.label, f.caption) for f in FIGURES], command=options.command)
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    write_text(folder / "report.json", report_json(report))
    write_text(folder / "index.html", page)
    returned: LooseJSONObject = dict(report)  # the command layer reads it by key
    return returned
