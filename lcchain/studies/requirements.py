"""``lcchain requirements``: the parts' requirements from the circuit theory, with ngspice points on the curves.

The curves and the limits are :mod:`lcchain.circuit.requirements`' (exact).  ``check`` runs the ladder with a part
at a few of its curve's values in ngspice, at a fine fixed step, and measures the first arrival the same way from
the simulated current (a cubic spline through ngspice's points, maximised in the same window): those points sit on
the exact curves within the trapezoidal rule's error (:func:`point_agrees`).

The validation report's section "how good must the parts be" is one :class:`RequirementsJob` per cradle, run in
the report's pool by :func:`run_requirements` into a :class:`RequirementsCheck`; :mod:`lcchain.report.requirements`
renders it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them

from ..circuit import requirements as exact
from ..circuit.effects import Effect
from ..circuit.ladder import Ladder
from ..circuit.netlist import Drive, NetlistOutput, SimulationOptions, netlist_text
from ..circuit.requirements import GRID_POINTS, LOSS_TARGETS, PARTS, Arrival, Part, Requirement, requirements_cost
from ..core.blas import fixed_blas_threads
from ..core.budget import Budget, Estimate, run_estimate
from ..core.checks import integer, real
from ..core.errors import ParameterError, SimulationError
from ..core.json import JSONDict
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..spice.engines import find_engine, run_engine
from ..spice.job import RunJob
from ..spice.simulator import Simulator
from ..theory.arrivals import arrival_window, maximum_in_window
from ..theory.cases import chain_for_case
from ..theory.chain import Chain
from ..theory.spectrum import normal_modes

__all__ = ["CheckPoint", "check_points", "requirements_estimate", "point_agrees", "CHECK_DT", "ATOL_LOSS",
           "RTOL_LOSS", "RequirementsJob", "RequirementsCheck", "requirements_jobs", "run_requirements",
           "REPORT_CHECKS", "QUICK_REPORT_CHECKS", "QUICK_GRID_POINTS"]

#: The check runs' fixed step, units of sqrt(L0 C0): the energy's error is about (dt omega)^2 / 12 of the band's
#: fastest modes, a few 1e-5 here.
CHECK_DT = 0.01
#: An ngspice point agrees with the exact curve when |loss - theory| <= ATOL_LOSS + RTOL_LOSS |theory|: the step's
#: error (a few 1e-5) with a wide margin, and 1 % of the loss.
ATOL_LOSS = 1e-3
RTOL_LOSS = 0.01
#: ngspice points on each curve in the validation report, and with ``--quick``.
REPORT_CHECKS = 2
QUICK_REPORT_CHECKS = 1
#: Points of each curve with ``--quick`` (the limits are refined from them as from the full grid's, to the same
#: 1e-4 in log: only the curve drawn is coarser).
QUICK_GRID_POINTS = 7


@dataclass(frozen=True)
class CheckPoint:
    """One ngspice run on a curve: the part's value, the loss measured and the exact loss there."""

    part: str
    value: float
    loss: float
    theory: float

    def to_dict(self) -> dict[str, float | str]:
        return {"part": self.part, "value": self.value, "loss": self.loss, "theory": self.theory}


def point_agrees(point: CheckPoint) -> bool:
    """Whether ngspice's loss is the exact one within :data:`ATOL_LOSS` + :data:`RTOL_LOSS` of it (a NaN: no)."""
    return abs(point.loss - point.theory) <= ATOL_LOSS + RTOL_LOSS * abs(point.theory)


def _unknowns(chain: Chain) -> int:
    return 4 * chain.N  # rail nodes, coils and what a part adds to each cell


def requirements_estimate(chain: Chain, parts: Sequence[Part], checks: int, points: int = GRID_POINTS) -> Estimate:
    """The curves' theory (``points`` per curve before the limits are refined) and ``checks`` ngspice runs per
    part."""
    transit = normal_modes(chain).transit_time()
    stop = arrival_window(1, transit)[1]
    run = run_estimate(points=stop / CHECK_DT + 1, saved=1, compared=0, unknowns=_unknowns(chain))
    runs = checks * len(parts) + (1 if checks else 0)  # and the ideal ladder's, once
    seconds = requirements_cost(chain, parts, points) + runs * run.seconds
    return Estimate(f"{len(parts)} parts' curves at N = {chain.N} and {runs} ngspice runs",
                    run.memory + 64.0 * (3 * chain.N) ** 2, seconds)


def check_points(ladder: Ladder, requirements: Sequence[Requirement], count: int, *, budget: Budget,
                 progress: Callable[[float], None] | None = None) -> list[CheckPoint]:
    """``count`` of each curve's values (evenly through its grid, where the loss is between 1e-6 and 0.3; one: the
    middle one) run in ngspice, each loss measured against one ngspice run of the ideal ladder."""
    chain = ladder.chain
    transit = normal_modes(chain).transit_time()
    window = arrival_window(1, transit)
    simulator = find_engine("ngspice")
    options = SimulationOptions(dt=CHECK_DT, tstop=window[1])
    runs = []
    for requirement in requirements:
        # where the curve matters: between a thousandth of the 0.1 % target and well past the 1 % one
        candidates = [k for k, loss in enumerate(requirement.losses) if 1e-6 < loss < 0.3]
        # evenly from end to end; one alone in the middle (the first, where the loss is ~1e-6, told little)
        spots = [j / (count - 1) if count > 1 else 0.5 for j in range(count)]
        chosen = sorted({candidates[round(spot * (len(candidates) - 1))] for spot in spots}) if candidates else []
        runs += [(requirement, k) for k in chosen]
    if not runs:
        return []
    energy0 = _energy(ladder, (), options, window, transit, budget, simulator)
    points = []
    for done, (requirement, k) in enumerate(runs, start=1):
        built, effects = requirement.part.build(chain, requirement.values[k])
        energy = _energy(Ladder(built, ladder.L0, ladder.C0), effects, options, window, transit, budget, simulator)
        points.append(CheckPoint(requirement.part.key, requirement.values[k], 1.0 - energy / energy0,
                                 requirement.losses[k]))
        if progress is not None:
            progress(done / len(runs))
    return points


def _energy(ladder: Ladder, effects: tuple[Effect, ...], options: SimulationOptions, window: tuple[float, float],
            transit: float, budget: Budget, simulator: Simulator) -> float:
    chain = ladder.chain
    netlist = netlist_text(ladder, options, Drive(I0=1.0), effects=effects,
                           output=NetlistOutput(title=f"lcchain requirements, {chain.name}"))
    last = f"i(l{chain.N})"
    tstop = options.tstop * ladder.time_unit
    result = run_engine(RunJob(netlist, [last], tstop, foreign=False, timeout=max(1.0, budget.max_seconds)), simulator)
    t = result.time / ladder.time_unit
    spline = scipy.interpolate.CubicSpline(t, result.vectors[last])
    _, peak = maximum_in_window(lambda s: np.asarray(spline(s)), window, transit)
    return peak * peak * float(chain.masses[-1] / chain.masses[0]) if math.isfinite(peak) else math.nan


# ------------------------------------------------------------------ the validation report's section
@dataclass(frozen=True)
class RequirementsJob:
    """One cradle's requirements for the validation report (:func:`run_requirements`): the named chain, every part
    of :data:`~lcchain.circuit.requirements.PARTS` (each curve ``points`` long before its limits are refined) and
    ``checks`` ngspice points on each curve; frozen and picklable, so that it may run in another process (the chain
    is designed there).

    ``L0`` (H) and ``C0`` (F) set the physical units the requirements are stated in.
    """

    name: str
    what: str
    case: str
    N: int
    checks: int = REPORT_CHECKS
    points: int = GRID_POINTS
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0

    def __post_init__(self) -> None:
        object.__setattr__(self, "checks", integer("checks", self.checks, at_least=1))  # a check needs a point
        object.__setattr__(self, "points", integer("points", self.points, at_least=2))
        for key in ("L0", "C0"):
            object.__setattr__(self, key, real(key, getattr(self, key), above=0.0))

    @property
    def label(self) -> str:
        return f"requirements {self.name}"

    def chain(self) -> Chain:
        return chain_for_case(self.case, self.N)

    def estimate(self, chain: Chain | None = None) -> Estimate:
        """Its price: :func:`requirements_estimate` of every part (``chain``: the job's, if already made)."""
        return requirements_estimate(chain if chain is not None else self.chain(), PARTS, self.checks, self.points)

    @property
    def cost(self) -> float:
        """Seconds it takes, estimated (:meth:`estimate`; the chain is designed for it, 0.2 s at two-mass N = 100)."""
        return self.estimate().seconds


def requirements_jobs(*, quick: bool = False) -> list[RequirementsJob]:
    """The report's cradles: the optimal two-mass chain of N = 100 and the perfect cradle of N = 50, with
    :data:`REPORT_CHECKS` ngspice points per curve; ``quick``: :data:`QUICK_REPORT_CHECKS` and curves of
    :data:`QUICK_GRID_POINTS` (the same limits, to the refinement's 1e-4 in log)."""
    checks, points = (QUICK_REPORT_CHECKS, QUICK_GRID_POINTS) if quick else (REPORT_CHECKS, GRID_POINTS)
    return [RequirementsJob("two-mass-N100", "two-mass, N = 100", "two-mass", 100, checks, points),
            RequirementsJob("perfect-N50", "perfect cradle, N = 50", "perfect", 50, checks, points)]


@dataclass
class RequirementsCheck:
    """One cradle's requirements: the ideal first arrival, each part's curve and limits, ngspice's points on the
    curves, the verdict (every point agrees: :func:`point_agrees`), the price and the time taken.

    ``requirements`` is empty and ``reason`` says why when the job failed.
    """

    name: str
    what: str
    case: str
    ladder: Ladder
    ideal: Arrival | None
    requirements: list[Requirement]
    points: list[CheckPoint]
    passed: bool
    estimate_s: float
    wall_s: float | None = None
    reason: str = ""

    @property
    def N(self) -> int:
        return self.ladder.chain.N

    @property
    def worst(self) -> float | None:
        """The largest |ngspice - theory| over its tolerance among the points (None: no point)."""
        ratios = [abs(p.loss - p.theory) / (ATOL_LOSS + RTOL_LOSS * abs(p.theory)) for p in self.points]
        return max(ratios, default=None) if all(map(math.isfinite, ratios)) else math.inf

    def to_dict(self) -> JSONDict:
        """The section's numbers (``report.json``'s ``requirements``)."""
        ideal = None if self.ideal is None else {"time": self.ideal.time, "peak": self.ideal.peak,
                                                  "energy": self.ideal.energy}
        return {"name": self.name, "what": self.what, "case": self.case, "N": self.N, "L0": self.ladder.L0,
                "C0": self.ladder.C0, "targets": list(LOSS_TARGETS), "ideal": ideal,
                "parts": [r.to_dict(self.ladder) for r in self.requirements],
                "check": [point.to_dict() for point in self.points], "passed": self.passed,
                "estimate_s": self.estimate_s, "wall_s": self.wall_s, "reason": self.reason}

    def checks(self) -> list[JSONDict]:
        """The report's line for it: its ngspice points against the exact curves."""
        return [{"name": f"requirements {self.name}: ngspice on the exact curves", "what": self.what,
                 "kind": "requirements", "passed": self.passed, "max_abs_error": self.worst, "tolerance": 1.0,
                 "unit": f"× ({ATOL_LOSS:g} + {RTOL_LOSS:g} |loss|)", "wall_s": self.wall_s, "reason": self.reason}]


@fixed_blas_threads
def run_requirements(job: RequirementsJob, budget: Budget | None = None) -> RequirementsCheck:
    """Every part's curve and limits for the job's cradle (:func:`lcchain.circuit.requirements.requirement`) and
    ngspice's points on them (:func:`check_points`).

    Under one BLAS thread, as the theory: the same bits in the report's pool as here.
    """
    start = time.perf_counter()
    budget = budget if budget is not None else Budget()
    chain = job.chain()
    estimate = job.estimate(chain).seconds
    ladder = Ladder(chain, job.L0, job.C0)
    try:
        ideal = exact.first_arrival_energy(ladder)
        results = [exact.requirement(ladder, part, points=job.points) for part in PARTS]
        points = check_points(ladder, results, job.checks, budget=budget)
    except (SimulationError, ParameterError) as error:
        return RequirementsCheck(job.name, job.what, job.case, ladder, None, [], [], False, estimate,
                                 time.perf_counter() - start, str(error))
    passed = all(point_agrees(point) for point in points) and len(points) > 0
    reason = "" if points else "no point of any curve to run"
    return RequirementsCheck(job.name, job.what, job.case, ladder, ideal, results, points, passed, estimate,
                             time.perf_counter() - start, reason)
