"""``lcchain figures`` and ``lcchain report`` as functions: compute, draw, write (atomically, at the end)."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..studies.validation import CircuitCheck
from .figure_data import DesignRows
from .files import write_text
from .html import figure_png, render_html, report_json
from .paper_figures import FIGURES, make_figures
from .plots import overlay
from .validation import validation_report

__all__ = ["build_figures", "build_report"]

Progress = Callable[[int, int, str], None]


def build_figures(out: str | os.PathLike[str], *, quick: bool = False, fmt: str = "png",
                  cache: str | os.PathLike[str] | None = None, progress: Progress | None = None) -> list[Path]:
    """Every figure of the paper into ``out`` (created if missing): ``<label>.<fmt>``."""
    return make_figures(out, quick=quick, fmt=fmt, rows=DesignRows(cache), progress=progress)


def _check_figure(check: Any) -> Any:
    curves = check.curves
    ylabel = "$Q_N\\,/\\,Q_1(0)$" if check.excitation == "displacement" else "$I_N\\,/\\,I_1(0)$"
    figure = overlay(curves["t"], curves["sim"], curves["t"], curves["theory"], residual=curves["residual"],
                     arrivals=curves["arrivals"], title=f"{check.name} ({check.what})", ylabel=ylabel)
    figure.set_size_inches(5.6, 3.8)
    return figure


def build_report(out: str | os.PathLike[str], circuit: Sequence[CircuitCheck], engines: Mapping[str, str], *,
                 quick: bool = False, cache: str | os.PathLike[str] | None = None, progress: Progress | None = None,
                 command: str = "lcchain report", seconds: float = 0.0) -> dict[str, Any]:
    """Compute the paper's half of the validation report, render it with the circuit's runs (already made), then
    write ``out/index.html`` and ``out/report.json``; return it as data."""
    rows = DesignRows(cache)
    report = validation_report(rows, circuit, engines, quick=quick, progress=progress, seconds=seconds)
    figures: dict[str, bytes] = {}
    for i, paper_figure in enumerate(FIGURES):
        if progress is not None:
            progress(i, len(FIGURES), f"Fig. {paper_figure.label}")
        figures[f"paper:{paper_figure.label}"] = figure_png(paper_figure.build(rows, quick))
    for check in report["circuit"]:
        if check.curves:
            figures[f"check:{check.name}"] = figure_png(_check_figure(check), dpi=90)
    if progress is not None:
        progress(len(FIGURES), len(FIGURES), "writing")
    page = render_html(report, figures, [(f.label, f.caption) for f in FIGURES], command=command)
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    write_text(folder / "report.json", report_json(report))
    write_text(folder / "index.html", page)
    return report
