"""``lcchain requirements``: the parts' requirements from the circuit theory, with ngspice points on the curves.

The curves and the limits are :mod:`lcchain.circuit.requirements`' (exact).  ``check`` runs the ladder with a part
at a few of its curve's values in ngspice, at a fine fixed step, and measures the first arrival the same way from
the simulated current (a cubic spline through ngspice's points, maximised in the same window): those points sit on
the exact curves within the trapezoidal rule's error.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.interpolate

from ..circuit.effects import Effect
from ..circuit.ladder import Ladder
from ..circuit.netlist import SimulationOptions, netlist_text
from ..circuit.requirements import Part, Requirement, requirements_cost
from ..core.budget import Budget, Estimate, run_estimate
from ..spice.engines import find_engine, run_engine
from ..spice.simulator import Simulator
from ..theory.arrivals import arrival_window, maximum_in_window
from ..theory.chain import Chain
from ..theory.spectrum import normal_modes

__all__ = ["CheckPoint", "check_points", "requirements_estimate", "CHECK_DT"]

#: The check runs' fixed step, units of sqrt(L0 C0): the energy's error is about (dt omega)^2 / 12 of the band's
#: fastest modes, a few 1e-5 here.
CHECK_DT = 0.01


@dataclass(frozen=True)
class CheckPoint:
    """One ngspice run on a curve: the part's value, the loss measured and the exact loss there."""

    part: str
    value: float
    loss: float
    theory: float

    def to_dict(self) -> dict[str, float | str]:
        return {"part": self.part, "value": self.value, "loss": self.loss, "theory": self.theory}


def _unknowns(chain: Chain) -> int:
    return 4 * chain.N  # rail nodes, coils and what a part adds to each cell


def requirements_estimate(chain: Chain, parts: Sequence[Part], checks: int) -> Estimate:
    """The curves' theory and ``checks`` ngspice runs per part."""
    transit = normal_modes(chain).transit_time()
    stop = arrival_window(1, transit)[1]
    run = run_estimate(points=stop / CHECK_DT + 1, saved=1, compared=0, unknowns=_unknowns(chain))
    runs = checks * len(parts) + (1 if checks else 0)  # and the ideal ladder's, once
    seconds = requirements_cost(chain, parts) + runs * run.seconds
    return Estimate(f"{len(parts)} parts' curves at N = {chain.N} and {runs} ngspice runs",
                    run.memory + 64.0 * (3 * chain.N) ** 2, seconds)


def check_points(ladder: Ladder, requirements: Sequence[Requirement], count: int, *, budget: Budget,
                 progress: Callable[[float], None] | None = None) -> list[CheckPoint]:
    """``count`` of each curve's values (evenly through its grid, where the loss is between 1e-6 and 0.3) run in
    ngspice, each loss measured against one ngspice run of the ideal ladder."""
    chain = ladder.chain
    transit = normal_modes(chain).transit_time()
    window = arrival_window(1, transit)
    simulator = find_engine("ngspice")
    options = SimulationOptions(dt=CHECK_DT, tstop=window[1])
    runs = []
    for requirement in requirements:
        # where the curve matters: between a thousandth of the 0.1 % target and well past the 1 % one
        candidates = [k for k, loss in enumerate(requirement.losses) if 1e-6 < loss < 0.3]
        chosen = sorted({candidates[round(j * (len(candidates) - 1) / max(count - 1, 1))] for j in range(count)}) \
            if candidates else []
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
    netlist = netlist_text(ladder, options, I0=1.0, effects=effects, title=f"lcchain requirements, {chain.name}")
    last = f"i(l{chain.N})"
    tstop = options.tstop * ladder.time_unit
    result = run_engine(netlist, [last], tstop, simulator=simulator, foreign=False,
                        timeout=max(1.0, budget.max_seconds))
    t = result.time / ladder.time_unit
    spline = scipy.interpolate.CubicSpline(t, result.vectors[last])
    _, peak = maximum_in_window(lambda s: np.asarray(spline(s)), window, transit)
    return peak * peak * float(chain.masses[-1] / chain.masses[0]) if math.isfinite(peak) else math.nan
