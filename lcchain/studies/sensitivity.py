"""``lcchain sensitivity --check``: the theory's dp/d ln x beside central differences of ngspice runs.

For each of the M most sensitive components two requests run, the component at 1 + h and at 1 - h and every
other part nominal (a corner of :class:`lcchain.circuit.effects.Tolerance` with one sign: the netlist and its
theory come from the same chain), at an accuracy that extrapolates.  Their peaks give

    FD = (p+ - p-) / (2 h),

whose error bar is the runs' part, (e+ + e-) / (2 h) with e the runs' predicted (else measured) error (for the
energy fraction e = p^2 L_N / L_1, 2 e / p times it), plus
the truncation of the central difference at h, |FD_theory - dp/d ln x|, from the exact theory of the same two
chains (each run's record holds it).  The check passes when |FD - dp/d ln x| is within that bar; it resolves
the sensitivity when the bar is below a tenth of |dp/d ln x| (at a maximum over a part, a perfect cradle's
energy, dp/d ln x = 0 and the difference is all truncation: it agrees, but says little).  h is chosen
so that the peak moves at least :data:`CHECK_MARGIN` times the runs' error: h = max(CHECK_STEP,
CHECK_MARGIN accuracy / |dp/d ln x|), at most :data:`CHECK_MAX_STEP`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

from ..circuit.effects import Tolerance
from ..circuit.sensitivity import Component, LadderSensitivity
from ..core.budget import Budget, Estimate, accuracy_plan_seconds, sensitivity_estimate
from ..core.checks import integer, real
from ..core.frozen import FrozenMap
from ..core.json import JSON, JSONDict
from ..core.limits import ACCURACY_FLOOR, SENSITIVITY_CHECK_ACCURACY
from ..core.types import ArrivalMetric
from ..runs.request import Request, Transient
from .plan import Plan, request_plan
from .stored import StoredRun

__all__ = ["CHECK_STEP", "CHECK_MAX_STEP", "CHECK_MARGIN", "CHECK_ACCURACY", "Check", "check_plan", "check_rows",
           "arrival_values"]

#: The smallest relative step of a component: truncation h^2 |p'''| / 6 stays near the runs' part at 1e-7.
CHECK_STEP = 0.01
#: The largest relative step (a weak component's peak change must still beat the runs' error).
CHECK_MAX_STEP = 0.1
#: How many times the runs' error the peak must move.
CHECK_MARGIN = 100.0
#: The runs' accuracy (max |simulation - theory|), met by extrapolated runs for N up to a few hundred.
CHECK_ACCURACY = SENSITIVITY_CHECK_ACCURACY


@dataclass(frozen=True)
class Check:
    """One component's finite difference in ngspice beside the theory.

    Attributes
    ----------
    component : Component
    step : float
        h, relative.
    peaks, errors : (float, float)
        The simulated peaks at 1 + h and 1 - h, and their runs' error bars.
    theory_fd : float
        The central difference of the exact theory of the same two chains.
    """

    component: Component
    step: float
    peaks: tuple[float, float]
    errors: tuple[float, float]
    theory_fd: float

    @property
    def fd(self) -> float:
        """(p+ - p-) / (2 h) from ngspice."""
        return (self.peaks[0] - self.peaks[1]) / (2.0 * self.step)

    @property
    def runs_error(self) -> float:
        return (self.errors[0] + self.errors[1]) / (2.0 * self.step)

    @property
    def truncation(self) -> float:
        return abs(self.theory_fd - self.component.relative)

    @property
    def error_bar(self) -> float:
        return self.runs_error + self.truncation

    @property
    def passed(self) -> bool:
        return abs(self.fd - self.component.relative) <= self.error_bar

    @property
    def resolved(self) -> bool:
        """Whether the error bar is below a tenth of the sensitivity (else agreement says little)."""
        return self.error_bar < 0.1 * abs(self.component.relative)

    def to_dict(self) -> JSONDict:
        return {"name": self.component.name, "step": self.step, "theory": self.component.relative, "fd": self.fd,
                "error_bar": self.error_bar, "runs_error": self.runs_error, "truncation": self.truncation,
                "theory_fd": self.theory_fd, "peaks": list(self.peaks), "passed": self.passed,
                "resolved": self.resolved}


def _step(component: Component, accuracy: float) -> float:
    wanted = CHECK_MARGIN * accuracy / max(abs(component.relative), 1e-300)
    return min(CHECK_MAX_STEP, max(CHECK_STEP, wanted))


def check_plan(sensitivity: LadderSensitivity, count: int, *, accuracy: float = CHECK_ACCURACY,
               budget: Budget | None = None, timeout: float = 3600.0) -> tuple[Plan, list[tuple[Component, float]]]:
    """The runs of the check: the ``count`` most sensitive components, each at 1 + h and 1 - h.

    Parameters
    ----------
    sensitivity : LadderSensitivity
    count : int
        M, 1 .. the ladder's components.
    accuracy : float
        Each run's max |simulation - theory| (>= :data:`lcchain.core.limits.ACCURACY_FLOOR`).
    budget : Budget, optional
    timeout : float
        Seconds before a run's simulator is killed.

    Returns
    -------
    plan, steps
        The study (params ``component`` and ``factor``), and each checked component with its h; the plan's
        ``planning`` counts the sensitivities and each request's choice of steps.

    Raises
    ------
    ParameterError
        ``count`` or ``accuracy`` out of range, or the planning alone beyond ``budget`` (naming ``--check``).
    """
    parts = sensitivity.components
    count = integer("--check", count, at_least=1, at_most=len(parts),
                    allowed=f"an integer from 0 (no ngspice runs) to {len(parts)}, the chain's parts")
    accuracy = real("--accuracy", accuracy, at_least=ACCURACY_FLOOR, below=1.0)
    ladder = sensitivity.ladder
    size = 2 * ladder.chain.N + 1
    steps = [(part, _step(part, accuracy)) for part in parts[:count]]
    planning = sensitivity_estimate(ladder.chain.N).seconds + 2 * count * accuracy_plan_seconds(ladder.chain.N)
    Estimate(f"choosing the steps of {2 * count} runs", 0.0, planning).check(
        budget if budget is not None else Budget(), "--check", count, "fewer components")
    points = []
    for part, h in steps:
        for sign in (1, -1):
            signs = tuple(sign if k == part.slot else 0 for k in range(size))
            request = Request(ladder.chain, Transient(accuracy=accuracy), effects=(Tolerance(h, h, corner=signs),),
                              L0=ladder.L0, C0=ladder.C0, timeout=timeout)
            points.append(({"component": part.name, "factor": 1.0 + sign * h}, request))
    plan = request_plan(points, budget=budget)
    description: dict[str, JSON] = {"command": "sensitivity --check", "metric": sensitivity.metric,
                                    "N": ladder.chain.N, "L0": ladder.L0, "C0": ladder.C0, "accuracy": accuracy,
                                    "chain": ladder.chain.to_dict(), "components": [part.name for part, _ in steps]}
    return replace(plan, description=FrozenMap(description), planning=planning), steps


def arrival_values(run: StoredRun, metric: ArrivalMetric = "peak") -> tuple[float, float, float]:
    """A finished, kicked run's first-arrival metric: simulated, in theory, and its error bar.

    The peak's error bar is the run's predicted error (else its measured max |simulation - theory|); the energy
    fraction e = p^2 L_N / L_1 (the record's ``energy_sim``) has the theory p_theory^2 L_N / L_1 and 2 e / p
    times that error bar.
    """
    metrics = run.metrics or {}
    arrival = metrics["arrivals"][0]
    error = metrics.get("predicted_error")
    error = float(error if error is not None else metrics["max_abs_error"])
    peak, theory = float(arrival["peak_sim"]), float(arrival["peak_theory"])
    if metric == "peak":
        return peak, theory, error
    ratio = float(arrival["energy_sim"]) / peak**2  # L_N / L_1 of the run's own circuit
    return peak**2 * ratio, theory**2 * ratio, 2.0 * abs(peak) * ratio * error


def check_rows(runs: Sequence[StoredRun], steps: Sequence[tuple[Component, float]],
               metric: ArrivalMetric = "peak") -> list[Check]:
    """Each checked component's finite difference from the store's finished runs (runs that failed: left out)."""
    results = {(run.params["component"], run.params["factor"]): arrival_values(run, metric) for run in runs
               if run.status == "ok" and not run.member and run.metrics}
    checks = []
    for part, h in steps:
        up, down = results.get((part.name, 1.0 + h)), results.get((part.name, 1.0 - h))
        if up is None or down is None:
            continue
        checks.append(Check(part, h, (up[0], down[0]), (up[2], down[2]), (up[1] - down[1]) / (2.0 * h)))
    return checks
