"""The circuit half of the validation report: ngspice against theory on the reference set (runs, no rendering).

:func:`circuit_checks` simulates every reference netlist's chain with a kick
and with a displacement, and a scene with losses and walls, and returns one
:class:`CircuitCheck` per run (the numbers, the verdict and decimated curves);
:mod:`lcchain.report.validation` renders them beside the paper's tables.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from ..circuit.reference import REFERENCE_DT, REFERENCE_SET, reference_chain
from ..core.errors import SimulationError
from ..core.types import EXCITATIONS, Excitation
from ..runs.execute import RunRecord
from ..runs.simulate import simulate
from ..scenes.load import parse_scene
from ..scenes.run import simulate_scene
from ..spice.simulator import Simulator, find_simulator
from ..theory.chain import Chain

__all__ = ["CircuitCheck", "circuit_checks", "LOSSES_AND_WALLS_SCENE", "PREDICTION_FACTOR", "ERROR_FLOOR"]

#: A fixed-step run passes when its error is below this multiple of the trapezoidal error model's prediction
#: (plus a floor for ngspice's own rounding); the model is exact to a few per cent (benchmarks/accuracy.md).
PREDICTION_FACTOR = 1.5
ERROR_FLOOR = 1e-9
#: Points of each check's curves kept for the page (the figure), decimated evenly.
_CURVE_POINTS = 1500


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


def circuit_checks(*, quick: bool = False, progress: Callable[[int, int, str], None] | None = None,
                   simulator: Simulator | None = None) -> list[CircuitCheck]:
    """ngspice against theory: every reference netlist's chain with a kick and with a displacement (dt = 0.05,
    one transit), then :data:`LOSSES_AND_WALLS_SCENE`.  ``quick`` leaves out the displacement runs of N = 1000.
    """
    simulator = simulator if simulator is not None else find_simulator("batch")
    jobs: list[tuple[str, str, Chain, Excitation]] = []
    for reference in REFERENCE_SET:
        chain = reference_chain(reference)
        for excitation in EXCITATIONS:
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
            report = simulate(chain, dt=REFERENCE_DT, excitation=excitation, simulator=simulator)
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
