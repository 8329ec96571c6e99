"""The validation report: the paper reproduced, the circuit validated, in one page and one JSON.

:func:`validation_report` computes everything (tables at every N of the
paper's list, the asymptotic constants, the perfect chains, the paper's slips;
ngspice runs of the reference chains with both excitations and of a scene
with losses and walls) and returns the report as data; :mod:`.html` renders
it.  Every number in the page comes from here, and ``report.json`` holds the
same content.
"""

from __future__ import annotations

import datetime
import math
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import __version__
from ..circuit.reference import REFERENCE_DT, REFERENCE_SET, reference_chain
from ..core.errors import SimulationError
from ..runs.execute import RunRecord
from ..runs.simulate import simulate
from ..scenes.load import parse_scene
from ..scenes.run import simulate_scene
from ..spice.simulator import find_simulator
from ..theory.asymptotic import asymptotic_optimum
from ..theory.chain import Chain
from ..theory.perfect import perfect_design
from .figure_data import FULL_N, DesignRows
from .paper import PRINTED_ASYMPTOTIC, PRINTED_COLUMNS, PRINTED_ROWS, compare_row, findings, last_digit_units

__all__ = ["REPORT_N", "QUICK_REPORT_N", "CircuitCheck", "circuit_checks", "paper_section", "validation_report",
           "MAX_UNITS_OFF"]

#: Every N of the report's tables (issue 12): one-mass up to 500000, two-mass up to 100000.
REPORT_N: dict[str, list[int]] = {"one-mass": [*FULL_N, 500000], "two-mass": list(FULL_N)}
#: With --quick: the paper's printed rows and a few more (a few seconds).
QUICK_REPORT_N: dict[str, list[int]] = {case: sorted({*PRINTED_ROWS[case], 30, 50, 200, 500})
                                        for case in ("one-mass", "two-mass")}
#: A computed cell may differ from the printed one by this many units of its last digit (the paper's own
#: rounding boundaries and coarse delay grid, see :func:`lcchain.report.paper.findings`); more is a failure.
MAX_UNITS_OFF = 1.5
#: A fixed-step run passes when its error is below this multiple of the trapezoidal error model's prediction
#: (plus a floor for ngspice's own rounding); the model is exact to a few per cent (benchmarks/accuracy.md).
PREDICTION_FACTOR = 1.5
ERROR_FLOOR = 1e-9
#: Points of each check's curves kept for the page (the figure), decimated evenly.
_CURVE_POINTS = 1500


# ------------------------------------------------------------------ the circuit
@dataclass
class CircuitCheck:
    """One ngspice run against the theory: the numbers, the verdict, and the end-loop curves for the page."""

    name: str
    what: str
    N: int
    excitation: str
    dt: float | None
    max_abs_error: float | None
    predicted_error: float | None
    tolerance: float
    passed: bool
    wall_s: float | None = None
    reason: str = ""
    curves: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "what": self.what, "kind": "circuit", "N": self.N, "excitation": self.excitation,
                "dt": self.dt, "passed": self.passed, "max_abs_error": self.max_abs_error,
                "predicted_error": self.predicted_error, "tolerance": self.tolerance, "wall_s": self.wall_s,
                "reason": self.reason}


def _curves(record: RunRecord) -> dict[str, Any]:
    """Loop N's simulation, theory and residual, decimated for a figure."""
    signals = record.signals
    if signals is None:
        return {}
    step = max(1, signals.t.size // _CURVE_POINTS)
    t = signals.t[::step]
    return {"t": t, "sim": signals.sim[-1][::step], "theory": signals.theory[-1][::step],
            "residual": (signals.sim[-1] - signals.theory[-1])[::step],
            "arrivals": [a.to_dict() for a in (record.metrics.arrivals if record.metrics else ())]}


def _check(name: str, what: str, N: int, excitation: str, dt: float | None, record: RunRecord | None,
           tolerance_of: Callable[[float | None], float], error: str = "") -> CircuitCheck:
    if record is None or not record.ok or record.metrics is None:
        reason = error or (record.reason if record is not None else "did not run")
        return CircuitCheck(name, what, N, excitation, dt, None, None, math.nan, False, reason=reason)
    metrics = record.metrics
    tolerance = tolerance_of(metrics.predicted_error)
    return CircuitCheck(name, what, N, excitation, dt, metrics.max_abs_error, metrics.predicted_error, tolerance,
                        bool(metrics.max_abs_error <= tolerance), record.wall_s, curves=_curves(record))


def _fixed_step_tolerance(predicted: float | None) -> float:
    return PREDICTION_FACTOR * (predicted or 0.0) + ERROR_FLOOR


#: The scene with losses and walls: the two-mass chain of N = 50 between weak walls, inductors of Q = 300,
#: kicked; ngspice's step from the accuracy asked for.
LOSSES_AND_WALLS_SCENE: dict[str, Any] = {
    "title": "Two-mass chain N = 50, walls K0 = 0.01, Q = 300, kick",
    "chain": {"case": "two-mass", "N": 50},
    "excitation": {"kind": "kick", "I0": 1e-3},
    "effects": {"losses": {"Q": 300.0}, "walls": {"K0": 0.01}},
    "analysis": {"transits": 2, "accuracy": 1e-4},
    "output": {"plots": []},
}


def circuit_checks(*, quick: bool = False, progress: Callable[[int, int, str], None] | None = None
                   ) -> list[CircuitCheck]:
    """ngspice against theory: every reference netlist's chain with a kick and with a displacement (dt = 0.05,
    one transit), then :data:`LOSSES_AND_WALLS_SCENE`.  ``quick`` leaves out the displacement runs of N = 1000.
    """
    simulator = find_simulator("batch")
    jobs: list[tuple[str, str, Chain, str]] = []
    for reference in REFERENCE_SET:
        chain = reference_chain(reference)
        for excitation in ("kick", "displacement"):
            if quick and excitation == "displacement" and chain.N >= 1000:
                continue
            what = f"{reference.case}, N = {reference.N}"
            jobs.append((f"{reference.name.removesuffix('.cir')} {excitation}", what, chain, excitation))
    total = len(jobs) + 1
    checks = []
    for i, (name, what, chain, excitation) in enumerate(jobs):
        if progress is not None:
            progress(i, total, name)
        try:
            report = simulate(chain, dt=REFERENCE_DT, excitation=excitation, simulator=simulator)  # type: ignore[arg-type]
            checks.append(_check(name, what, chain.N, excitation, REFERENCE_DT, report.record,
                                 _fixed_step_tolerance))
        except SimulationError as error:
            checks.append(_check(name, what, chain.N, excitation, REFERENCE_DT, None, _fixed_step_tolerance,
                                 str(error)))
    if progress is not None:
        progress(len(jobs), total, "scene with losses and walls")
    scene = parse_scene(LOSSES_AND_WALLS_SCENE, source="the report's scene")
    accuracy = float(LOSSES_AND_WALLS_SCENE["analysis"]["accuracy"])
    result = simulate_scene(scene, simulator=simulator)
    sample = result.samples[0] if result.samples else None
    checks.append(_check("two-mass-N50 walls+losses kick", "two-mass, N = 50, walls K0 = 0.01, Q = 300", 50, "kick",
                         result.report.get("dt"), sample.run if sample is not None else None,
                         lambda predicted: accuracy))
    if progress is not None:
        progress(total, total, "done")
    return checks


# ------------------------------------------------------------------ the paper
def _table(case: str, rows: DesignRows, Ns: list[int]) -> list[dict[str, Any]]:
    out = []
    for N in Ns:
        row = dict(rows.row(case, N))
        seconds = row.pop("seconds", None)
        cells = compare_row(case, row)
        worst = max((abs(c["units"]) for c in cells), default=None)
        out.append({"row": row, "seconds": seconds, "printed": cells, "worst_units": worst})
    return out


def _asymptotic() -> list[dict[str, Any]]:
    out = []
    for case, items in PRINTED_ASYMPTOTIC.items():
        optimum = asymptotic_optimum(case)  # type: ignore[arg-type]
        for key, printed, where in items:
            value = getattr(optimum, key) if key in ("alpha", "delta", "sigma", "tau") else optimum.coefficients[key]
            out.append({"case": case, "key": key, "printed": printed, "where": where, "computed": value,
                        "units": last_digit_units(value, printed)})
    return out


def _perfect() -> dict[str, Any]:
    small = []
    for N in (3, 4, 5):
        design = perfect_design(N)
        small.append({"N": N, "masses": design.chain.masses.tolist(), "springs": design.chain.springs.tolist(),
                      "t_arrival": design.t_arrival, "delta": design.delta})
    larger = []
    for N, walls in ((10, 0), (100, 0), (1000, 0), (100, 1)):
        design = perfect_design(N, walls)
        larger.append({"N": N, "walls": walls, "t_arrival": design.t_arrival, "delta": design.delta,
                       **design.spread()})
    return {"paper": small, "any_N": larger}


def paper_section(rows: DesignRows, *, quick: bool = False,
                  progress: Callable[[int, int, str], None] | None = None) -> dict[str, Any]:
    """Tables I and II at every N (``quick``: the printed ones and a few more), the constants, perfect chains,
    the slips; and one check per printed row (its worst cell within :data:`MAX_UNITS_OFF` units)."""
    sizes = QUICK_REPORT_N if quick else REPORT_N
    total = sum(len(v) for v in sizes.values())
    done = 0
    tables = {}
    for case, Ns in sizes.items():
        out = []
        for N in Ns:
            if progress is not None:
                progress(done, total, f"Table {'I' if case == 'one-mass' else 'II'}, N = {N}")
            out.extend(_table(case, rows, [N]))
            done += 1
        tables[case] = out
    if progress is not None:
        progress(total, total, "tables done")
    by_N = {case: {entry["row"]["N"]: entry["row"] for entry in entries} for case, entries in tables.items()}
    optima = {case: asymptotic_optimum(case) for case in ("one-mass", "two-mass")}
    checks = []
    for case, entries in tables.items():
        label = "Table I" if case == "one-mass" else "Table II"
        for entry in entries:
            if entry["printed"]:
                checks.append({"name": f"{label}, N = {entry['row']['N']}: every printed cell", "kind": "paper",
                               "passed": entry["worst_units"] <= MAX_UNITS_OFF,
                               "max_abs_error": entry["worst_units"], "tolerance": MAX_UNITS_OFF,
                               "unit": "units of the last printed digit"})
    return {"tables": tables, "columns": PRINTED_COLUMNS, "asymptotic": _asymptotic(), "perfect": _perfect(),
            "findings": findings(optima, by_N), "checks": checks}


# ------------------------------------------------------------------ the whole report
def validation_report(rows: DesignRows, *, quick: bool = False,
                      progress: Callable[[int, int, str], None] | None = None) -> dict[str, Any]:
    """Everything the page shows, as data (figures excepted: :mod:`.html` draws them from ``curves``)."""
    start = time.perf_counter()
    paper = paper_section(rows, quick=quick, progress=progress)
    circuit = circuit_checks(quick=quick, progress=progress)
    simulator = find_simulator("batch")
    checks = [*paper["checks"], *(c.to_dict() for c in circuit)]
    return {
        "title": "lcchain validation report",
        "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "lcchain_version": __version__,
        "ngspice_version": simulator.version,
        "machine": {"system": platform.system(), "release": platform.release(), "machine": platform.machine(),
                    "python": platform.python_version(), "numpy": np.__version__},
        "quick": quick,
        "passed": all(c["passed"] for c in checks),
        "checks": checks,
        "tables": {case: [entry["row"] for entry in entries] for case, entries in paper["tables"].items()},
        "paper": paper,
        "circuit": circuit,
        "seconds": time.perf_counter() - start,
    }
