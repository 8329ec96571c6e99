"""The validation report: the paper reproduced, the circuit validated, in one page and one JSON.

:func:`validation_report` computes the paper's half (tables at every N of the
paper's list, the asymptotic constants, the perfect chains, the paper's slips),
takes the circuit's half already run (ngspice on the reference chains with
both excitations and on a scene with losses and walls:
:mod:`lcchain.studies.validation`; the reference ladders' spectra:
:mod:`lcchain.studies.spectrum_checks`; the cradles' parts' requirements:
:mod:`lcchain.studies.requirements`), and returns the report as data;
:mod:`.html` renders it.  Every number in the page comes from here, and ``report.json`` holds the
same content.
"""

from __future__ import annotations

import datetime
import platform
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import NotRequired, TypedDict

import numpy as np

from ..core import __version__
from ..core.checks import instance, real
from ..core.frozen import FrozenMap
from ..core.json import JSONDict
from ..core.physical import physical_scales
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..studies.requirements import RequirementsCheck
from ..studies.spectrum_checks import SpectrumCheck
from ..studies.validation import CircuitCheck
from ..theory.asymptotic import asymptotic_optimum
from ..theory.design import DESIGN_TABLES
from ..theory.perfect import perfect_design
from .figure_data import FULL_N, DesignRow, DesignRows
from .paper import (
    PRINTED_ASYMPTOTIC,
    PRINTED_COLUMNS,
    PRINTED_ROWS,
    PrintedCell,
    compare_row,
    findings,
    last_digit_units,
)

__all__ = ["REPORT_N", "QUICK_REPORT_N", "CircuitCheck", "ValidationRuns", "paper_section", "validation_report",
           "MAX_UNITS_OFF"]

#: Every N of the report's tables (issue 12): one-mass up to 500000, two-mass up to 100000.
REPORT_N: dict[str, list[int]] = {"one-mass": [*FULL_N, 500000], "two-mass": list(FULL_N)}
#: With --quick: the paper's printed rows and a few more (a few seconds).
QUICK_REPORT_N: dict[str, list[int]] = {case: sorted({*PRINTED_ROWS[case], 30, 50, 200, 500})
                                        for case in ("one-mass", "two-mass")}
#: A computed cell may differ from the printed one by this many units of its last digit (the paper's own
#: rounding boundaries and coarse delay grid, see :func:`lcchain.report.paper.findings`); more is a failure.
MAX_UNITS_OFF = 1.5
# ------------------------------------------------------------------ the paper
class TableEntry(TypedDict):
    """A row of the report's Tables I and II: the design (its seconds beside it), and each cell the paper prints."""

    row: DesignRow
    seconds: float | None
    printed: list[PrintedCell]
    worst_units: float | None


class AsymptoticEntry(TypedDict):
    """A large-N constant the paper prints, against lcchain's."""

    case: str
    key: str
    printed: str
    where: str
    computed: float
    units: float


class PerfectEntry(TypedDict):
    """A perfect chain the paper prints (N = 3, 4, 5), recomputed."""

    N: int
    masses: list[float]
    springs: list[float]
    t_arrival: float
    delta: float


class Perfect(TypedDict):
    """The paper's perfect chains, and perfect chains of any N (their numbers and spreads, by name)."""

    paper: list[PerfectEntry]
    any_N: list[dict[str, float]]


class PaperSection(TypedDict):
    """:func:`paper_section`."""

    tables: dict[str, list[TableEntry]]
    columns: dict[str, tuple[str, ...]]
    asymptotic: list[AsymptoticEntry]
    perfect: Perfect
    findings: list[dict[str, str]]
    checks: list[JSONDict]


class ValidationReport(TypedDict):
    """:func:`validation_report`: everything the page shows (a report made by an older lcchain may lack the keys
    marked not required)."""

    title: str
    created: str
    lcchain_version: str
    ngspice_version: str
    engines: NotRequired[dict[str, str]]
    machine: dict[str, str]
    quick: bool
    physical: NotRequired[dict[str, float]]
    passed: NotRequired[bool]
    checks: list[JSONDict]
    tables: NotRequired[dict[str, list[DesignRow]]]
    paper: PaperSection
    circuit: list[CircuitCheck]
    spectrum: NotRequired[list[SpectrumCheck]]
    requirements: NotRequired[list[RequirementsCheck]]
    seconds: float


def _table(case: str, rows: DesignRows, Ns: list[int]) -> list[TableEntry]:
    out: list[TableEntry] = []
    for N in Ns:
        row = rows.row(case, N).copy()
        seconds = row.pop("seconds", None)
        cells = compare_row(case, row)
        worst = max((abs(c["units"]) for c in cells), default=None)
        out.append({"row": row, "seconds": seconds, "printed": cells, "worst_units": worst})
    return out


def _asymptotic() -> list[AsymptoticEntry]:
    out: list[AsymptoticEntry] = []
    for case, items in PRINTED_ASYMPTOTIC.items():
        optimum = asymptotic_optimum(case)  # type: ignore[arg-type]
        for key, printed, where in items:
            value = getattr(optimum, key) if key in ("alpha", "delta", "sigma", "tau") else optimum.coefficients[key]
            out.append({"case": case, "key": key, "printed": printed, "where": where, "computed": value,
                        "units": last_digit_units(value, printed)})
    return out


def _perfect() -> Perfect:
    small: list[PerfectEntry] = []
    for N in (3, 4, 5):
        design = perfect_design(N)
        small.append({"N": N, "masses": design.chain.masses.tolist(), "springs": design.chain.springs.tolist(),
                      "t_arrival": design.t_arrival, "delta": design.delta})
    larger: list[dict[str, float]] = []
    for N, walls in ((10, 0), (100, 0), (1000, 0), (100, 1)):
        design = perfect_design(N, walls)
        larger.append({"N": N, "walls": walls, "t_arrival": design.t_arrival, "delta": design.delta,
                       **design.spread()})
    return {"paper": small, "any_N": larger}


def paper_section(rows: DesignRows, *, quick: bool = False,
                  progress: Callable[[int, int, str], None] | None = None) -> PaperSection:
    """Tables I and II at every N (``quick``: the printed ones and a few more), the constants, perfect chains,
    the slips; and one check per printed row (its worst cell within :data:`MAX_UNITS_OFF` units)."""
    sizes = QUICK_REPORT_N if quick else REPORT_N
    total = sum(len(v) for v in sizes.values())
    done = 0
    tables: dict[str, list[TableEntry]] = {}
    for case, Ns in sizes.items():
        out: list[TableEntry] = []
        for N in Ns:
            if progress is not None:
                progress(done, total, f"{DESIGN_TABLES[case][0]}, N = {N}")
            out.extend(_table(case, rows, [N]))
            done += 1
        tables[case] = out
    if progress is not None:
        progress(total, total, "tables done")
    by_N = {case: {entry["row"]["N"]: entry["row"] for entry in entries} for case, entries in tables.items()}
    optima = {case: asymptotic_optimum(case) for case in ("one-mass", "two-mass")}
    checks: list[JSONDict] = []
    for case, entries in tables.items():
        label = DESIGN_TABLES[case][0]
        for entry in entries:
            worst = entry["worst_units"]  # None exactly when the paper prints no cell of the row
            if entry["printed"] and worst is not None:
                checks.append({"name": f"{label}, N = {entry['row']['N']}: every printed cell", "kind": "paper",
                               "passed": worst <= MAX_UNITS_OFF,
                               "max_abs_error": worst, "tolerance": MAX_UNITS_OFF,
                               "unit": "units of the last printed digit"})
    return {"tables": tables, "columns": PRINTED_COLUMNS, "asymptotic": _asymptotic(), "perfect": _perfect(),
            "findings": findings(optima, by_N), "checks": checks}


# ------------------------------------------------------------------ the whole report
@dataclass(frozen=True)
class ValidationRuns:
    """The circuit's half of the report, already run (the report renders it and runs nothing).

    Attributes
    ----------
    circuit : sequence of CircuitCheck
        The engines' runs on the reference chains and scenes (:func:`lcchain.studies.validation.circuit_checks`,
        by :mod:`lcchain.app.validation`).
    engines : mapping of str to str
        Each engine that ran, by name, and its version.
    spectrum : sequence of SpectrumCheck
        The AC measurements (:func:`lcchain.studies.spectrum_checks.run_spectrum_check`).
    requirements : sequence of RequirementsCheck
        The cradles' parts (:func:`lcchain.studies.requirements.run_requirements`).
    seconds : float
        What they took, wall seconds (>= 0).
    """

    circuit: Sequence[CircuitCheck]
    engines: Mapping[str, str]
    spectrum: Sequence[SpectrumCheck] = ()
    requirements: Sequence[RequirementsCheck] = ()
    seconds: float = 0.0

    def __post_init__(self) -> None:
        for name, cls in (("circuit", CircuitCheck), ("spectrum", SpectrumCheck),
                          ("requirements", RequirementsCheck)):
            items = tuple(getattr(self, name))
            for i, item in enumerate(items):
                instance(f"{name}[{i}]", item, cls)
            object.__setattr__(self, name, items)
        instance("engines", self.engines, (Mapping,))
        object.__setattr__(self, "engines", FrozenMap(self.engines))
        real("seconds", self.seconds, at_least=0.0, unit="seconds")


def validation_report(rows: DesignRows, runs: ValidationRuns, *, quick: bool = False,
                      progress: Callable[[int, int, str], None] | None = None,
                      paper: PaperSection | None = None) -> ValidationReport:
    """Everything the page shows, as data (figures excepted: :mod:`.html` draws them from ``curves``).

    ``runs`` are the circuit's checks, spectra and cradles already made (:class:`ValidationRuns`): every one of
    their checks counts in the verdict.  ``paper`` is :func:`paper_section` of the same rows if already made
    (default: made here).
    """
    start = time.perf_counter()
    paper = paper if paper is not None else paper_section(rows, quick=quick, progress=progress)
    circuit, spectrum, requirements = list(runs.circuit), list(runs.spectrum), list(runs.requirements)
    engines = runs.engines
    checks: list[JSONDict] = [*paper["checks"], *(c.to_dict() for c in circuit),
                              *(line for c in spectrum for line in c.checks()),
                              *(line for c in requirements for line in c.checks())]
    return {
        "title": "lcchain validation report",
        "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "lcchain_version": __version__,
        "ngspice_version": engines.get("ngspice", ""),
        "engines": dict(engines),
        "machine": {"system": platform.system(), "release": platform.release(), "machine": platform.machine(),
                    "python": platform.python_version(), "numpy": np.__version__},
        "quick": quick,
        "physical": physical_scales(DEFAULT_L0, DEFAULT_C0),
        "passed": all(c["passed"] for c in checks),
        "checks": checks,
        "tables": {case: [entry["row"] for entry in entries] for case, entries in paper["tables"].items()},
        "paper": paper,
        "circuit": circuit,
        "spectrum": spectrum,
        "requirements": requirements,
        "seconds": runs.seconds + time.perf_counter() - start,
    }
