"""The circuit half of the validation report: ngspice against theory on the reference set (runs, no rendering).

:func:`circuit_checks` simulates the reference netlists' chains with a kick
and with a displacement (at the sizes :func:`check_jobs` gives, and says why), and a
scene with losses and walls, and returns one :class:`CircuitCheck` per run (the
numbers, the verdict and decimated curves);
:mod:`lcchain.report.validation` renders them beside the paper's tables.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TypedDict

import numpy as np

from ..circuit.reference import REFERENCE_DT, REFERENCE_SET, reference_chain
from ..core.errors import SimulationError, SimulatorMissingError
from ..core.json import JSONDict, LooseJSONObject
from ..core.types import EXCITATIONS, Excitation
from ..runs.execute import RunRecord
from ..runs.simulate import ChainOptions, simulate_chain
from ..scenes.load import parse_scene
from ..scenes.run import simulate_scene
from ..spice.engines import DEFAULT_ENGINE, ENGINES, find_engine
from ..spice.simulator import Simulator
from ..theory.chain import Chain

__all__ = ["CircuitCheck", "CheckJob", "check_jobs", "run_check", "circuit_checks", "installed_engines",
           "LOSSES_AND_WALLS_SCENE", "PREDICTION_FACTOR", "ERROR_FLOOR", "CHECKED_MAX_N", "LARGE_CHECKS"]

#: A fixed-step run passes when its error is below this multiple of the trapezoidal error model's prediction
#: (plus a floor for ngspice's own rounding); the model is exact to a few per cent (benchmarks/accuracy.md).
PREDICTION_FACTOR = 1.5
ERROR_FLOOR = 1e-9
#: The sizes the checks run at (issue 35: a run at N = 1000 costs a hundred times one at N = 100, and must test
#: something the smaller ones do not).  Every engine runs every reference chain up to this N with both excitations
#: (the perfect, uniform, one-mass and two-mass chains, free and bounded; a kick starts the circuit from its coils,
#: a displacement from its capacitors) and the scene with losses and walls: an engine's dialect and integrator
#: meet every kind of card there, and the cards at N = 1000 are the same.
CHECKED_MAX_N = 100
#: The runs above :data:`CHECKED_MAX_N`, by the default engine only: the one-mass chain of N = 1000 with a kick.
#: Its error grows with N (measured in ngspice: 1.16e-3, 1.26e-3, 1.48e-3 at N = 20, 100, 1000), so its
#: largest N is the set's largest error; the two-mass chain's does not (7.67e-4, 7.28e-4, 7.28e-4), a
#: displacement's error at N = 1000 was the kick's to three digits, and gnucap's errors there were its errors at
#: N = 100 within the same growth (two-mass 7.20e-4 and 7.27e-4): those seven runs cost 51 s of CPU (ngspice
#: 4.3 s, gnucap 9.4 s a run) and measured nothing new.
LARGE_CHECKS: tuple[tuple[str, Excitation], ...] = (("one-mass-N1000.cir", "kick"),)
#: Points of each check's curves kept for the page (the figure), decimated evenly.
_CURVE_POINTS = 1500


class CheckCurves(TypedDict, total=False):
    """A check's loop N for the page's figure, decimated (none when the run gave no signals): the times, the
    simulation, the theory and their difference (units of sqrt(L0 C0) and of the excitation), and each arrival
    compared (:meth:`lcchain.compare.metrics.ArrivalComparison.to_dict`)."""

    t: np.ndarray
    sim: np.ndarray
    theory: np.ndarray
    residual: np.ndarray
    arrivals: list[LooseJSONObject]


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
    curves: CheckCurves = field(default_factory=lambda: CheckCurves())
    engine: str = "ngspice"

    def to_dict(self) -> JSONDict:
        return {"name": self.name, "what": self.what, "kind": "circuit", "N": self.N, "excitation": self.excitation,
                "dt": self.dt, "passed": self.passed, "max_abs_error": self.max_abs_error,
                "predicted_error": self.predicted_error, "tolerance": self.tolerance, "wall_s": self.wall_s,
                "reason": self.reason, "engine": self.engine}


def _curves(record: RunRecord) -> CheckCurves:
    """Loop N's simulation, theory and residual, decimated for a figure."""
    signals = record.signals
    if signals is None:
        return CheckCurves()
    step = max(1, signals.t.size // _CURVE_POINTS)
    t = signals.t[::step]
    return {"t": t, "sim": signals.sim[-1][::step], "theory": signals.theory[-1][::step],
            "residual": (signals.sim[-1] - signals.theory[-1])[::step],
            "arrivals": [a.to_dict() for a in (record.metrics.arrivals if record.metrics else ())]}


def _check(job: CheckJob, dt: float | None, record: RunRecord | None, tolerance_of: Callable[[float | None], float],
           error: str = "") -> CircuitCheck:
    """The job's run judged: its error against ``tolerance_of`` its predicted error (failed, with ``error`` or
    the record's reason, when it did not run or has no metrics)."""
    name, what, N, excitation, engine = job.name, job.what, job.N, job.excitation, job.simulator.engine
    if record is None or not record.ok or record.metrics is None:
        reason = error or (record.reason if record is not None else "did not run")
        return CircuitCheck(name, what, N, excitation, dt, None, None, math.nan, False, reason=reason, engine=engine)
    metrics = record.metrics
    tolerance = tolerance_of(metrics.predicted_error)
    return CircuitCheck(name, what, N, excitation, dt, metrics.max_abs_error, metrics.predicted_error, tolerance,
                        bool(metrics.max_abs_error <= tolerance), record.wall_s, curves=_curves(record),
                        engine=engine)


def _scene_tolerance(predicted: float | None) -> float:
    return float(LOSSES_AND_WALLS_SCENE["analysis"]["accuracy"])


def _fixed_step_tolerance(predicted: float | None) -> float:
    return PREDICTION_FACTOR * (predicted or 0.0) + ERROR_FLOOR


#: The scene with losses and walls: the two-mass chain of N = 50 between weak walls, inductors of Q = 300,
#: kicked; ngspice's step from the accuracy asked for.
LOSSES_AND_WALLS_SCENE: LooseJSONObject = {
    "title": "Two-mass chain N = 50, walls K0 = 0.01, Q = 300, kick",
    "chain": {"case": "two-mass", "N": 50},
    "excitation": {"kind": "kick", "I0": 1e-3},
    "effects": {"losses": {"Q": 300.0}, "walls": {"K0": 0.01}},
    "analysis": {"transits": 2, "accuracy": 1e-4},
    "output": {"plots": []},
}


def installed_engines() -> list[Simulator]:
    """Every registered engine found on this machine (batch transport), the default first; the default must be."""
    found = [find_engine(DEFAULT_ENGINE)]
    for name in ENGINES:
        if name == DEFAULT_ENGINE:
            continue
        try:
            found.append(find_engine(name))
        except SimulatorMissingError:
            continue
    return found


@dataclass(frozen=True)
class CheckJob:
    """One circuit check to run (:func:`run_check`): a reference chain with an excitation at
    :data:`~lcchain.circuit.reference.REFERENCE_DT`, or (``chain`` None) :data:`LOSSES_AND_WALLS_SCENE`; frozen
    and picklable, so that it may run in another process."""

    name: str
    what: str
    N: int
    excitation: Excitation
    chain: Chain | None
    simulator: Simulator
    label: str = ""  #: what progress says while it runs (default: its name)

    @property
    def cost(self) -> float:
        """Rough seconds it takes, for the order checks are sent to a pool in (measured: ngspice about 7 s at
        N = 1000 with one transit at dt = 0.05, quadratic in N), times its engine's ``relative_cost``: an engine
        is priced by what it says of itself, not by its name."""
        return 7.0 * ENGINES[self.simulator.engine].relative_cost * (self.N / 1000.0) ** 2 + 0.05


def check_jobs(*, quick: bool = False, simulators: Sequence[Simulator] | None = None) -> list[CheckJob]:
    """The checks of :func:`circuit_checks`, in its order, each engine's after the one before: the reference
    chains up to :data:`CHECKED_MAX_N` and (not with ``quick``) the default engine's :data:`LARGE_CHECKS`, then
    the scene."""
    simulators = list(simulators) if simulators is not None else installed_engines()
    references: list[tuple[str, str, Chain, Excitation, bool]] = []
    for reference in REFERENCE_SET:
        chain = reference_chain(reference) if reference.N <= CHECKED_MAX_N or not quick else None
        for excitation in EXCITATIONS:
            large = (reference.name, excitation) in LARGE_CHECKS
            if chain is None or (reference.N > CHECKED_MAX_N and not large):
                continue
            what = f"{reference.case}, N = {reference.N}"
            references.append((f"{reference.name.removesuffix('.cir')} {excitation}", what, chain, excitation,
                               large))
    jobs = []
    for simulator in simulators:
        default = simulator.engine == DEFAULT_ENGINE
        suffix = "" if default else f" ({simulator.engine})"
        jobs += [CheckJob(name + suffix, what, chain.N, excitation, chain, simulator)
                 for name, what, chain, excitation, large in references if default or not large]
        jobs.append(CheckJob("two-mass-N50 walls+losses kick" + suffix, "two-mass, N = 50, walls K0 = 0.01, Q = 300",
                             50, "kick", None, simulator, "scene with losses and walls" + suffix))
    return jobs


def run_check(job: CheckJob) -> CircuitCheck:
    """Run one check in its engine and judge it against the theory."""
    engine = job.simulator.engine
    if job.chain is not None:
        try:
            options = ChainOptions(dt=REFERENCE_DT, excitation=job.excitation, engine=engine)
            report = simulate_chain(job.chain, options, simulator=job.simulator)
            return _check(job, REFERENCE_DT, report.record, _fixed_step_tolerance)
        except SimulationError as error:
            return _check(job, REFERENCE_DT, None, _fixed_step_tolerance, str(error))
    data = dict(LOSSES_AND_WALLS_SCENE, analysis={**LOSSES_AND_WALLS_SCENE["analysis"], "engine": engine})
    scene = parse_scene(data, source="the report's scene")
    result = simulate_scene(scene, simulator=job.simulator)
    sample = result.samples[0] if result.samples else None
    return _check(job, result.report.get("dt"), sample.run if sample is not None else None, _scene_tolerance)


def circuit_checks(*, quick: bool = False, progress: Callable[[int, int, str], None] | None = None,
                   simulators: Sequence[Simulator] | None = None) -> list[CircuitCheck]:
    """Each engine against theory: every reference netlist's chain with a kick and with a displacement
    (dt = 0.05, one transit), then :data:`LOSSES_AND_WALLS_SCENE`, in every engine installed
    (:func:`installed_engines`) or those given, at the sizes of :func:`check_jobs`.  ``quick`` leaves out the
    runs of N = 1000.

    The checks are :func:`check_jobs`, run one after the other by :func:`run_check`.
    """
    jobs = check_jobs(quick=quick, simulators=simulators)
    checks = []
    for done, job in enumerate(jobs):
        if progress is not None:
            progress(done, len(jobs), job.label or job.name)
        checks.append(run_check(job))
    if progress is not None:
        progress(len(jobs), len(jobs), "done")
    return checks
