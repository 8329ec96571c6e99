"""``lcchain sweep SCENE --worst-case``: the corners of the components that matter most, through the store.

The scene's nominal circuit (rounded to its preferred values, if any) gives every component's sensitivity
(:func:`lcchain.circuit.sensitivity.ladder_sensitivity`); the K parts that move the first-arrival peak most at
their tolerance give 2^K corners, each part at +- its tolerance and the others nominal, and the sensitivities'
signs give the two corners predicted to be the extremes with every part at its tolerance
(:func:`lcchain.circuit.sensitivity.corners`).  Each corner is the scene with its ``[effects.tolerance]`` set
to that corner (:class:`lcchain.circuit.effects.Tolerance` ``corner``): the planner realises it like a sample,
so its netlist and its theory come from the same chain, and it is stored as a task with params ``corner``
(its label) and ``signs``.  The nominal runs too.

The scene's Monte Carlo is compared in exact theory (each sample's own first-arrival peak, no simulation):
its worst sample should lie within the worst corner.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..circuit.effects import PreferredValues, Tolerance, rounded
from ..circuit.elements import adds_elements
from ..circuit.ladder import Ladder
from ..circuit.sensitivity import Corner, LadderSensitivity, corners, ladder_sensitivity
from ..core.budget import Budget, Estimate, accuracy_plan_seconds, sample_theory_seconds, sensitivity_estimate
from ..core.errors import ParameterError
from ..core.frozen import FrozenMap
from ..core.types import ArrivalMetric
from ..runs.request import plan_request
from ..scenes.load import load_scene
from ..scenes.plan import scene_plan
from ..theory.arrivals import first_arrival
from ..theory.chain import Chain
from ..theory.sensitivity import energy_fraction
from .plan import Combination, Plan, Task, _add_runs, _compare_seconds, _seconds
from .sensitivity import arrival_values
from .store import StoredRun

__all__ = ["WorstCase", "worst_case_plan", "worst_case_summary", "DEFAULT_COMPONENTS"]

#: Components moved together unless --components says otherwise: 2^2 corners.
DEFAULT_COMPONENTS = 2


@dataclass(frozen=True)
class WorstCase:
    """What a worst-case study compares its stored runs with.

    Attributes
    ----------
    sensitivity : LadderSensitivity
        Of the nominal (rounded) circuit.
    corners : tuple of Corner
        In task order: the nominal, the 2^K corners, then the predicted max and min.
    monte_carlo : tuple of float
        The exact first-arrival metric (the sensitivity's) of each of the scene's tolerance samples (empty
        with one sample).
    """

    sensitivity: LadderSensitivity
    corners: tuple[Corner, ...]
    monte_carlo: tuple[float, ...]


def _signs_text(signs: Sequence[int]) -> str:
    """``"+0-..."``: one character per component, L_1..L_N then C_0_1..C_N_N+1."""
    return "".join("-0+"[s + 1] for s in signs)


def _refuse(scene: Any, path: str) -> Tolerance:
    tolerance = scene.effects.get(Tolerance)
    if tolerance is None or not (tolerance.L or tolerance.C):
        raise ParameterError("--worst-case", path, "a scene with [effects.tolerance] L or C > 0 (the corners sit at "
                             "the tolerances)")
    if scene.analysis.kind != "transient":
        raise ParameterError("analysis.kind", scene.analysis.kind, '"transient" with --worst-case (the corners are '
                             "judged by the first arrival's peak)", path)
    if scene.excitation.kind != "kick":
        raise ParameterError("excitation.kind", scene.excitation.kind, '"kick" with --worst-case (the '
                             "sensitivities are the kicked ladder's first-arrival peak)", path)
    adder = next((effect for effect in scene.effects.present() if adds_elements(effect)), None)
    if adder is not None:  # losses, a real part, any effect's own element: not the lossless ladder's
        raise ParameterError(f"effects.{adder.key}", adder, "no effect that adds elements with --worst-case (the "
                             "sensitivities and the Monte Carlo's peaks are the ideal ladder's)", path)
    if tolerance.corner is not None:
        raise ParameterError("effects.tolerance.corner", list(tolerance.corner), "none with --worst-case (it "
                             "makes the corners)", path)
    assert isinstance(tolerance, Tolerance)  # the registry's entry for the key tolerance
    return tolerance


def _metric(chain: Chain, metric: ArrivalMetric) -> float:
    """A chain's first-arrival peak, or its energy fraction, in exact theory."""
    peak = first_arrival(chain).peak
    return peak if metric == "peak" else energy_fraction(peak, chain)


def worst_case_plan(path: str | Path, *, components: int = DEFAULT_COMPONENTS, metric: ArrivalMetric = "peak",
                    budget: Budget | None = None, workers: int = 1) -> tuple[Plan, WorstCase]:
    """The corners of a scene as a study, and what its summary compares them with.

    Parameters
    ----------
    path : path-like
        A scene with ``[effects.tolerance]`` (L or C > 0), kicked, without losses.
    components : int
        K, the parts moved together (2^K corners), 1 .. :data:`lcchain.core.limits.MAX_CORNER_COMPONENTS`.
    metric : {"peak", "energy"}
        What the corners are ranked and judged by: the first arrival's current peak or its energy fraction.
    budget : Budget, optional
    workers : int
        The runs' workers, for the price.

    Raises
    ------
    ParameterError
        A scene without tolerances, not kicked or with losses; K out of range, or corners beyond the budget
        (naming ``--components``).
    """
    budget = budget if budget is not None else Budget()
    scene = load_scene(path)
    tolerance = _refuse(scene, str(path))
    monte_carlo = scene_plan(scene, budget)  # the samples (and the nominal) as the scene's own study has them
    request = monte_carlo.request
    series = request.effect(PreferredValues)
    nominal = monte_carlo.nominal
    if isinstance(series, PreferredValues):
        nominal = rounded(nominal, request.L0, request.C0, series.series)
    sensitivity_estimate(nominal.N).check(budget, "--worst-case", str(path))
    sensitivity = ladder_sensitivity(Ladder(nominal, request.L0, request.C0), metric=metric)
    found = corners(sensitivity, components=components, tol_L=tolerance.L, tol_C=tolerance.C)

    def corner_plan(corner: Corner) -> Any:
        effects = tuple(replace(tolerance, samples=1, corner=corner.signs) if isinstance(effect, Tolerance)
                        else effect for effect in request.effects)
        return plan_request(replace(request, effects=effects), budget)

    N = nominal.N
    # planned here: the scene and each corner (each a request whose step is chosen for its accuracy: 259 corners
    # of N = 50 took a minute), the sensitivities, and the Monte Carlo's samples in exact theory
    per_request = (accuracy_plan_seconds(N) if getattr(request.analysis, "accuracy", None) is not None else 0.0) \
        + 2e-4 * N + 3e-10 * N**3
    planning = (sensitivity_estimate(N).seconds + (1 + len(found)) * per_request
                + (request.samples * sample_theory_seconds(N) if request.samples > 1 else 0.0))
    first = corner_plan(found[0])
    each = sum(_seconds(spec) + _compare_seconds(spec) for spec in first.specs)
    Estimate(f"{len(found)} corners on {workers} worker{'s' if workers > 1 else ''}", 0.0,
             planning + each * len(found) / max(1, workers)).check(budget, "--components", components,
                                                                    "fewer --components (2^K corners)")
    tasks: list[Task] = []
    combinations: list[Combination] = []
    for corner in found:
        plan = first if corner is found[0] else corner_plan(corner)
        _add_runs(tasks, combinations, {"corner": corner.label, "signs": _signs_text(corner.signs)}, plan.specs,
                  plan.steps, plan.predicted_error)
    values = tuple(_metric(chain, metric) for chain in monte_carlo.chains) if request.samples > 1 else ()
    description = {"command": "sweep --worst-case", "scene": str(path), "scene_data": scene.to_dict(),
                   "components": components, "metric": metric, "ranked": [part.name for part in sensitivity.components]}
    plan = Plan("scene", FrozenMap(description), tuple(tasks), request.backend, ("corner", "signs"),
                tuple(combinations), request.engine, planning)
    return plan, WorstCase(sensitivity, tuple(found), values)


def worst_case_summary(runs: Sequence[StoredRun], setup: WorstCase) -> dict[str, Any]:
    """The corners' metric from the store, the worst against the nominal, and the Monte Carlo beside them.

    Returns
    -------
    dict
        ``metric``; ``corners``: label, simulated and theoretical value and the first-order prediction of each
        finished corner; ``nominal``, ``worst`` and ``best`` (those rows); ``worst_change`` (worst - nominal,
        simulated); ``monte_carlo`` (samples, worst and whether it lies within the worst corner, in theory),
        when the scene has samples.
    """
    metric = setup.sensitivity.metric
    predicted = {corner.label: corner.predicted for corner in setup.corners}
    rows = []
    for run in runs:
        if run.member or run.status != "ok" or not run.metrics:
            continue
        simulated, theory, _ = arrival_values(run, metric)
        label = run.params["corner"]
        rows.append({"corner": label, "sim": simulated, "theory": theory,
                     "predicted": setup.sensitivity.value + predicted[label]})
    summary: dict[str, Any] = {"metric": metric, "corners": rows, "nominal_theory": setup.sensitivity.value}
    nominal = next((row for row in rows if row["corner"] == "nominal"), None)
    if rows:
        worst = min(rows, key=lambda row: row["sim"])
        best = max(rows, key=lambda row: row["sim"])
        summary.update(worst=worst, best=best)
        if nominal is not None:
            summary.update(nominal=nominal, worst_change=worst["sim"] - nominal["sim"])
    if setup.monte_carlo and rows:
        lowest = min(row["theory"] for row in rows)
        mc = float(np.min(setup.monte_carlo))
        summary["monte_carlo"] = {"samples": len(setup.monte_carlo), "worst": mc, "within": bool(mc >= lowest),
                                  "worst_corner_theory": lowest}
    return summary
