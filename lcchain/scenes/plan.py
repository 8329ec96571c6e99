"""Turning a scene into runs: its request, planned by :func:`lcchain.runs.request.plan_request`.

The scene (:mod:`lcchain.scenes.schema`, no physics there) says the same as a
:class:`~lcchain.runs.request.Request` with a file behind it: :func:`scene_request`
translates one into the other, and the one planner of every simulation chooses
the steps, realises the chains (walls, coupling, preferred values, tolerance
samples), writes the netlists (only the elements the effects need) and gives
every realised circuit its own exact theory.  Errors are named by the scene's
keys and file.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..circuit.effects import Losses
from ..core.budget import Budget, chain_seconds
from ..core.errors import ParameterError
from ..core.types import AnalysisKind, PulseShape
from ..runs.request import AC, ACCURACY_LOOPS, Analysis, Drive, Request, RequestPlan, Transient, plan_request
from ..runs.spec import RunSpec
from ..theory.cases import chain_for_case, named_case
from ..theory.chain import Chain
from .schema import Scene

__all__ = ["ScenePlan", "case_chain", "scene_request", "scene_plan", "scene_specs", "losses_and_pulse",
           "ACCURACY_LOOPS"]

#: What a scene's plan is: the request's plan.
ScenePlan = RequestPlan


def case_chain(scene: Scene) -> Chain:
    """The chain of the scene's case (or its custom masses and springs), before any effect."""
    spec = scene.chain
    if named_case(spec.case) is not None:
        return chain_for_case(spec.case, spec.N)
    assert spec.masses is not None and spec.springs is not None  # a custom chain: its own masses and springs
    return Chain(np.array(spec.masses), np.array(spec.springs), name=spec.case)


def _transient(scene: Scene) -> Analysis:
    analysis = scene.analysis
    return Transient(dt=analysis.dt, accuracy=analysis.accuracy, transits=analysis.transits, method=analysis.method,
                     extrapolate=analysis.extrapolate, probes=scene.output.probes)


#: The request's analysis for each ``[analysis] kind``.
ANALYSES: dict[AnalysisKind, Callable[[Scene], Analysis]] = {
    "transient": _transient,
    "ac": lambda scene: AC(points=scene.analysis.points),
}


def scene_request(scene: Scene, chain: Chain | None = None) -> Request:
    """The request a scene makes (``chain``: its case's chain, when already made)."""
    excitation, units, analysis = scene.excitation, scene.units, scene.analysis
    _, pulse = losses_and_pulse(scene)
    return Request(chain if chain is not None else case_chain(scene), ANALYSES[analysis.kind](scene),
                   drive=Drive(excitation.kind, excitation.I0, pulse),
                   effects=scene.effects.present(), L0=units.L0, C0=units.C0, backend=analysis.backend,
                   title=scene.title, engine=analysis.engine)


def losses_and_pulse(scene: Scene) -> tuple[float | None, tuple[PulseShape, float] | None]:
    """The scene's quality factor (None: no losses) and pulse (shape, width) (None: no pulse)."""
    excitation = scene.excitation
    losses = scene.effects.get(Losses)
    Q = losses.Q if losses is not None else None
    if excitation.kind != "pulse":
        return Q, None
    assert excitation.shape is not None and excitation.width is not None  # the schema requires them for a pulse
    return Q, (excitation.shape, excitation.width)


#: Internal names of what a scene sets, and the scene keys the user wrote.
_SCENE_KEYS = {"L0": "units.L0", "C0": "units.C0", "K0": "effects.walls.K0", "dt": "analysis.dt",
               "accuracy": "analysis.accuracy", "N": "chain.N", "coupling": "effects.coupling.k",
               "engine": "analysis.engine", "extrapolate": "analysis.extrapolate", "points": "analysis.points",
               "backend": "analysis.backend", "I0": "excitation.I0", "transits": "analysis.transits",
               "pulse width": "excitation.width"}


def scene_plan(scene: Scene, budget: Budget | None = None) -> ScenePlan:
    """Chains, stop time, steps and run specs of a scene (no simulation), within a budget.

    Raises
    ------
    ParameterError
        Named by the scene's key and file, for a scene that cannot run: a
        component scale ngspice cannot take, exact theory beyond
        :data:`lcchain.core.limits.EXACT_MAX_N`, losses with coupled coils.
    BudgetError
        The scene's estimated cost (per run, and its samples together) is beyond ``budget``.
    """
    try:
        chain = case_chain(scene)
        return plan_request(scene_request(scene, chain), budget,
                            design_seconds=chain_seconds(scene.chain.case, chain.N))
    except ParameterError as error:
        named = error.renamed(_SCENE_KEYS[error.field]) if error.field in _SCENE_KEYS else error
        if error.field == "chain":  # the chain itself (its time scale, its poles): the keys that make it
            named = error.renamed("chain.N" if named_case(scene.chain.case) is not None
                                  else "chain.masses/chain.springs")
        raise named.located(scene.source) from None


def scene_specs(scene: Scene, plan: ScenePlan) -> list[RunSpec]:
    """The run specs of the scene's realised circuits, each with its own exact theory.

    One per sample, or with extrapolation :attr:`ScenePlan.runs` per sample, coarsest first
    (:func:`lcchain.scenes.run.scene_result` combines them).
    """
    return list(plan.specs)
