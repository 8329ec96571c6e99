"""``lcchain sweep SCENE --worst-case``: the worst first arrival over the tolerance box, through the store.

Two methods (:data:`lcchain.core.types.WorstCaseMethod`):

``search`` (the default)
    :func:`lcchain.theory.worst_case.worst_case_search` looks for the lowest metric over the whole box, every
    part anywhere within its tolerance, in exact theory: exact gradients, a differenced Hessian, many starts,
    L-BFGS-B and a flip search on the vertices; it reports the worst found with a certificate (a bound proved for
    the quadratic model, and for the metric under a stated assumption) and its cost.  The worst point runs in
    ngspice (task ``search worst``) beside the nominal and the quick corners below.
``corners``
    Only the corners of the K parts that move the metric most at their tolerance (2^K, the others nominal) and
    the two corners the first-order signs predict to be the extremes
    (:func:`lcchain.circuit.sensitivity.corners`): a quick look, not a search (its worst can miss the box's
    worst by far: an optimal design's first derivatives vanish, and their signs predict nothing).

The scene's nominal circuit (rounded to its preferred values, if any) gives every component's sensitivity
(:func:`lcchain.circuit.sensitivity.ladder_sensitivity`).  Each point is the scene with its
``[effects.tolerance]`` set to that corner (:class:`lcchain.circuit.effects.Tolerance` ``corner``): the planner
realises it like a sample, so its netlist and its theory come from the same chain, and it is stored as a task
with params ``corner`` (its label) and ``signs``.  The nominal runs too.

The scene's Monte Carlo is compared in exact theory (each sample's own first-arrival peak, no simulation):
its worst sample should lie within the worst point.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..circuit.effects import PreferredValues, Tolerance, rounded
from ..circuit.elements import adds_elements
from ..circuit.ladder import Ladder
from ..circuit.sensitivity import Corner, LadderSensitivity, corners, ladder_sensitivity
from ..core.analyses import analysis_kind
from ..core.budget import (
    Budget,
    Estimate,
    accuracy_plan_seconds,
    sample_theory_seconds,
    sensitivity_estimate,
    worst_case_search_estimate,
)
from ..core.checks import choice
from ..core.errors import ParameterError
from ..core.frozen import FrozenMap
from ..core.json import JSON, LooseJSONObject
from ..core.types import WORST_CASE_METHODS, ArrivalMetric, WorstCaseMethod
from ..runs.request import RequestPlan, plan_request
from ..scenes.load import load_scene
from ..scenes.plan import scene_plan
from ..scenes.schema import Scene
from ..theory.arrivals import first_arrival
from ..theory.chain import Chain
from ..theory.sensitivity import energy_fraction
from ..theory.worst_case import ToleranceBox, WorstCaseSearch, worst_case_search
from .plan import Combination, Plan, Planning, Task, _add_runs, _compare_seconds, _seconds
from .sensitivity import arrival_values
from .stored import StoredRun

__all__ = ["WorstCase", "worst_case_plan", "worst_case_summary", "DEFAULT_COMPONENTS", "SEARCH_LABEL",
           "corners_label"]

#: Components moved together unless --components says otherwise: 2^2 corners.
DEFAULT_COMPONENTS = 2
#: The task of the search's worst point.
SEARCH_LABEL = "search worst"


def corners_label(components: int) -> str:
    """What the quick corners are, in words the output carries beside them."""
    return f"corners of the {components} most sensitive part{'s' if components != 1 else ''} (not a search)"


@dataclass(frozen=True)
class WorstCase:
    """What a worst-case study compares its stored runs with.

    Attributes
    ----------
    sensitivity : LadderSensitivity
        Of the nominal (rounded) circuit.
    corners : tuple of Corner
        In task order: the nominal, the 2^K corners, then the predicted max and min.
        With the method ``search``, the search's worst point second (label :data:`SEARCH_LABEL`).
    monte_carlo : tuple of float
        The exact first-arrival metric (the sensitivity's) of each of the scene's tolerance samples (empty
        with one sample).
    method : {"search", "corners"}
    components : int
        K of the quick corners.
    search : WorstCaseSearch or None
        The search's result (method ``search``).
    tolerance : (float, float)
        The relative tolerances of the inductors and the capacitors.
    """

    sensitivity: LadderSensitivity
    corners: tuple[Corner, ...]
    monte_carlo: tuple[float, ...]
    method: WorstCaseMethod = "search"
    components: int = DEFAULT_COMPONENTS
    search: WorstCaseSearch | None = None
    tolerance: tuple[float, float] = (0.0, 0.0)


def _signs_text(signs: Sequence[float]) -> str:
    """``"+0-..."``: one character per component, L_1..L_N then C_0_1..C_N_N+1; a point inside the box (a
    search's, rarely) as its positions, ``"+1,-0.37,0,..."``."""
    if all(float(s).is_integer() for s in signs):
        return "".join("-0+"[int(s) + 1] for s in signs)
    return ",".join("0" if s == 0 else f"{s:+.6g}" for s in signs)


def _refuse(scene: Scene, path: str) -> Tolerance:
    tolerance: Tolerance | None = scene.effects.get(Tolerance)
    if tolerance is None or not (tolerance.L or tolerance.C):
        raise ParameterError("--worst-case", path, "a scene with [effects.tolerance] L or C > 0 (the corners sit at "
                             "the tolerances)")
    if analysis_kind(scene.analysis.kind).swept:
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
    return tolerance


def _metric(chain: Chain, metric: ArrivalMetric) -> float:
    """A chain's first-arrival peak, or its energy fraction, in exact theory."""
    peak = first_arrival(chain).peak
    return peak if metric == "peak" else energy_fraction(peak, chain)


def worst_case_plan(path: str | Path, *, components: int = DEFAULT_COMPONENTS, metric: ArrivalMetric = "peak",
                    method: WorstCaseMethod = "search", planning: Planning | None = None) -> tuple[Plan, WorstCase]:
    """The worst case of a scene as a study, and what its summary compares it with.

    Parameters
    ----------
    path : path-like
        A scene with ``[effects.tolerance]`` (L or C > 0), kicked, without losses.
    components : int
        K, the parts moved together (2^K corners), 1 .. :data:`lcchain.core.limits.MAX_CORNER_COMPONENTS`.
    metric : {"peak", "energy"}
        What the corners are ranked and judged by: the first arrival's current peak or its energy fraction.
    method : {"search", "corners"}
        ``search``: the whole box searched in exact theory (its worst point runs beside the nominal and the
        quick corners); ``corners``: the quick corners alone.
    planning : Planning, optional
        The budget, and the runs' workers for the price.

    Raises
    ------
    ParameterError
        A scene without tolerances, not kicked or with losses; K out of range, or corners beyond the budget
        (naming ``--components``).
    """
    choice("--worst-case", method, WORST_CASE_METHODS)
    made = planning if planning is not None else Planning()
    budget = made.budget if made.budget is not None else Budget()
    workers = made.workers
    scene = load_scene(path)
    tolerance = _refuse(scene, str(path))
    monte_carlo = scene_plan(scene, budget)  # the samples (and the nominal) as the scene's own study has them
    request = monte_carlo.request
    series = request.effect(PreferredValues)
    nominal = monte_carlo.nominal
    if series is not None:
        nominal = rounded(nominal, request.L0, request.C0, series.series)
    sensitivity_estimate(nominal.N).check(budget, "--worst-case", str(path))
    sensitivity = ladder_sensitivity(Ladder(nominal, request.L0, request.C0), metric=metric)
    found = corners(sensitivity, components=components, tol_L=tolerance.L, tol_C=tolerance.C)
    quick = len(found)
    box = ToleranceBox(nominal, tolerance.L, tolerance.C)
    searching = worst_case_search_estimate(nominal.N, box.size)
    if method == "search":  # priced before anything runs, and on its own: its advice is the other method
        searching.check(budget, "--worst-case", method, "--worst-case corners (a quick look, not a search)")

    def corner_plan(corner: Corner) -> RequestPlan:
        effects = tuple(replace(tolerance, samples=1, corner=corner.signs) if effect == tolerance
                        else effect for effect in request.effects)
        return plan_request(replace(request, effects=effects), budget)

    N = nominal.N
    # planned here: the scene and each corner (each a request whose step is chosen for its accuracy: 259 corners
    # of N = 50 took a minute), the sensitivities, the search, and the Monte Carlo's samples in exact theory
    per_request = (accuracy_plan_seconds(N) if getattr(request.analysis, "accuracy", None) is not None else 0.0) \
        + 2e-4 * N + 3e-10 * N**3
    points = quick + (method == "search")
    planned = (sensitivity_estimate(N).seconds + (1 + points) * per_request
               + (searching.seconds if method == "search" else 0.0)
               + (request.samples * sample_theory_seconds(N) if request.samples > 1 else 0.0))
    first = corner_plan(found[0])
    each = sum(_seconds(spec) + _compare_seconds(spec) for spec in first.specs)
    what = f"{quick} corners" + (" and the search's worst" if method == "search" else "")
    Estimate(f"{what} on {workers} worker{'s' if workers > 1 else ''}", 0.0,
             planned + each * points / max(1, workers)).check(
        budget, "--components", components, "fewer --components (2^K corners)")
    search = None
    if method == "search":
        search = worst_case_search(box, metric, seed=tolerance.seed)
        tol = {"L": tolerance.L, "C": tolerance.C}
        predicted = sum(search.point[part.slot] * tol[part.kind] * part.relative for part in sensitivity.components)
        found.insert(1, Corner(SEARCH_LABEL, search.point, predicted))
    tasks: list[Task] = []
    combinations: list[Combination] = []
    for corner in found:
        runs = first if corner is found[0] else corner_plan(corner)
        _add_runs(tasks, combinations, {"corner": corner.label, "signs": _signs_text(corner.signs)}, runs.specs,
                  runs.steps, runs.predicted_error)
    values = tuple(_metric(chain, metric) for chain in monte_carlo.chains) if request.samples > 1 else ()
    description: dict[str, JSON] = {"command": "sweep --worst-case", "scene": str(path),
                                    "scene_data": scene.to_dict(), "method": method, "components": components,
                                    "metric": metric, "ranked": [part.name for part in sensitivity.components]}
    plan = Plan("scene", FrozenMap(description), tuple(tasks), request.backend, ("corner", "signs"),
                tuple(combinations), request.engine, planned)
    return plan, WorstCase(sensitivity, tuple(found), values, method, components, search,
                           (tolerance.L, tolerance.C))


def worst_case_summary(runs: Sequence[StoredRun], setup: WorstCase) -> LooseJSONObject:
    """The corners' metric from the store, the worst against the nominal, and the Monte Carlo beside them.

    Returns
    -------
    dict
        ``method``, ``metric``; ``corner_analysis``: the quick corners' label, K and worst row; ``search``
        (method ``search``): the search's worst in theory and in ngspice (``sim``), where (``signs``, and each
        part's nominal value, position in its tolerance and value), its certificate (``model_bound``,
        ``model_error``, ``bound``, ``gap``), ``starts``, ``local_optima``, ``evaluations`` and ``seconds``;
        ``corners``: label, simulated and theoretical value and the first-order prediction of each
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
        label = run.params["corner"]
        if label not in predicted:  # not a point of this study's plan
            continue
        simulated, theory, _ = arrival_values(run, metric)
        rows.append({"corner": label, "sim": simulated, "theory": theory,
                     "predicted": setup.sensitivity.value + predicted[label]})
    summary: LooseJSONObject = {"method": setup.method, "metric": metric, "corners": rows,
                               "nominal_theory": setup.sensitivity.value}
    quick = [row for row in rows if row["corner"] not in ("nominal", SEARCH_LABEL)]
    summary["corner_analysis"] = {"label": corners_label(setup.components), "components": setup.components,
                                  "worst": min(quick, key=lambda row: row["sim"]) if quick else None}
    if setup.search is not None:
        summary["search"] = _search_summary(setup, next((row for row in rows if row["corner"] == SEARCH_LABEL),
                                                        None))
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


def _search_summary(setup: WorstCase, row: LooseJSONObject | None) -> LooseJSONObject:
    """The search's result with its point named part by part, and its ngspice value once it ran."""
    assert setup.search is not None
    search = setup.search
    tolerance = dict(zip("LC", setup.tolerance, strict=True))
    parts = []
    for part in sorted(setup.sensitivity.components, key=lambda c: c.slot):
        position = search.point[part.slot]
        if position == 0.0:
            continue
        parts.append({"name": part.name, "nominal": part.value, "position": position,
                      "value": part.value * (1.0 + position * tolerance[part.kind])})
    summary = {**search.to_dict(), "signs": _signs_text(search.point), "parts": parts}
    if row is not None:
        summary.update(sim=row["sim"], theory=row["theory"])
    return summary
