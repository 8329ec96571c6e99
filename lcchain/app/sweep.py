"""``lcchain sweep`` as functions: many runs, the product of comma-list axes, or a scene or a netlist varied, or a
scene's worst case, planned (:func:`plan_sweep`) and run into a store (:func:`sweep`)."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..core.analyses import analysis_kind
from ..core.budget import INTERPRETER_SECONDS, Budget
from ..core.errors import ParameterError
from ..core.json import LooseJSON
from ..core.types import BACKENDS, DEFAULT_C0, DEFAULT_L0, ArrivalMetric, Backend, Excitation, WorstCaseMethod
from ..spice.engines import DEFAULT_ENGINE
from .studies import PlannedStudy, StudyHooks, StudyOptions, StudyResult, run_study, study_workers

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

    from ..studies.plan import Plan, RealParts

__all__ = ["SweepRequest", "plan_sweep", "sweep"]


@dataclass(frozen=True)
class SweepRequest:
    """What ``lcchain sweep`` asks, as its options name it: a ``scene`` file (varied by ``vary``, or its
    ``worst_case`` searched), a foreign ``netlist`` (varied by ``vary``), or lists of cases, sizes, steps or
    accuracies, transits and excitations (each list an axis) with the units, backend, engine and ``analysis``;
    real parts (``tolerance``, ``series``, ``samples``, ``seed``); where the runs go (``study``, its store
    required) and the budget; ``variants_progress`` a netlist sweep's variants as they are checked."""

    scene: str | None = None
    netlist: str | None = None
    case: list[str] | None = None
    N: list[int] | None = None
    dt: list[float] | None = None
    accuracy: list[float] | None = None
    extrapolate: int | None = None
    transits: list[int] | None = None
    excitation: list[Excitation] | None = None
    analysis: str = "transient"
    points: int | None = None
    L0: float | None = None  # None: DEFAULT_L0 (and given with SCENE.toml or --netlist, refused: theirs hold)
    C0: float | None = None  # None: DEFAULT_C0
    backend: Backend = "batch"
    engine: str | None = None
    vary: list[str] = field(default_factory=list)
    tolerance: dict[str, float] | None = None
    series: str | None = None
    samples: int | None = None
    seed: int | None = None
    worst_case: WorstCaseMethod | None = None
    components: int | None = None
    metric: ArrivalMetric | None = None
    study: StudyOptions = field(default_factory=StudyOptions)
    budget: Budget = field(default_factory=Budget)
    variants_progress: Callable[..., None] | None = None


def sweep(request: SweepRequest, hooks: StudyHooks | None = None) -> StudyResult:
    """Plan the sweep and run it into ``request.study.store``; with ``worst_case``, which corner is worst."""
    from .studies import check_study

    check_study(request.study)
    if _pool_first(request):
        from ..studies.pools import started_pool

        # the pool's workers start now and design the chains while the driver plans (issue 35)
        with started_pool(study_workers(request.study)) as pool:
            return run_study(plan_sweep(request, pool), request.study, request.budget, hooks, pool=pool)
    return run_study(plan_sweep(request), request.study, request.budget, hooks)


def _pool_first(request: SweepRequest) -> bool:
    """A sweep of cases and sizes whose transient runs go to a local pool of several workers: the pool starts
    before the plan, which designs the chains on it."""
    from ..studies.executors import EXECUTOR_TRAITS

    traits = EXECUTOR_TRAITS.get(request.study.executor)
    parts = any(v is not None for v in (request.samples, request.seed, request.tolerance, request.series))
    return (request.worst_case is None and request.components is None and request.metric is None
            and request.netlist is None and not request.scene and not request.vary and bool(request.case)
            and bool(request.N) and not parts and not analysis_kind(request.analysis).swept
            and traits is not None and traits.parallel and not traits.remote and study_workers(request.study) > 1)


def plan_sweep(request: SweepRequest, pool: ProcessPoolExecutor | None = None) -> PlannedStudy:
    """The sweep's plan, checked against its options, before anything runs (the store is not touched); ``pool``:
    a transient sweep's started process pool (:func:`lcchain.studies.pools.started_pool`), which designs its
    chains."""
    from ..studies.plan import Planning, parse_vary, scene_sweep_plan

    budget = request.budget
    if request.worst_case is not None or request.components is not None or request.metric is not None:
        return _worst_case(request, budget)
    if request.netlist is not None:
        return _netlist_sweep(request, budget)
    if request.scene:
        given = [o for o, v in (("--case", request.case), ("--N", request.N), ("--dt", request.dt),
                                ("--accuracy", request.accuracy), ("--extrapolate", request.extrapolate),
                                ("--engine", request.engine), ("--points", request.points), *_scene_says(request))
                 if v is not None]
        if given:
            raise ParameterError(given[0], getattr(request, given[0].lstrip("-")), "nothing with SCENE.toml (the scene "
                                 "says the chain and the analysis, [analysis] kind = \"ac\" included; vary its keys "
                                 "with --vary, e.g. analysis.extrapolate=1,2)")
        plan = scene_sweep_plan(request.scene, [parse_vary(v) for v in request.vary], _real_parts(request),
                                Planning(budget, study_workers(request.study))).limited(request.study.timeout)
    else:
        if request.vary:
            raise ParameterError("--vary", request.vary, "nothing without SCENE.toml (without one, the axes are "
                                 "--case, --N, --dt or --accuracy, --transits and --excitation lists)")
        if not request.case or not request.N:
            raise ParameterError("--case" if not request.case else "--N", None, "--case and --N lists (or SCENE.toml)")
        parts = any(v is not None for v in (request.samples, request.seed, request.tolerance, request.series))
        plan = _parts_sweep(request, budget) if parts else _SWEEPS[request.analysis](request, budget, pool)
    return PlannedStudy(plan)


def _netlist_sweep(request: SweepRequest, budget: Budget) -> PlannedStudy:
    """``sweep --netlist FILE --vary NAME=...``: a foreign netlist's values varied, each variant run as a batch's
    netlist; as for a batch, --max-time is the whole budget (runs not started within it stay pending)."""
    from ..studies.plan import NetlistSweep, Planning, netlist_sweep_plan
    from ..studies.vary import parse_netlist_vary

    started = time.monotonic()
    given = [o for o, v in (("SCENE.toml", request.scene), ("--case", request.case), ("--N", request.N),
                            ("--dt", request.dt),
                            ("--accuracy", request.accuracy), ("--extrapolate", request.extrapolate),
                            ("--engine", request.engine), ("--points", request.points),
                            ("--tolerance", request.tolerance),
                            ("--series", request.series), ("--transits", request.transits),
                            ("--excitation", request.excitation), ("--L0", request.L0), ("--C0", request.C0),
                            ("--analysis", request.analysis if analysis_kind(request.analysis).swept else None))
             if v is not None]
    if given:
        value = request.scene if given[0] == "SCENE.toml" else getattr(request, given[0].lstrip("-"))
        raise ParameterError(given[0], value, "nothing with --netlist (the netlist says its circuit and its "
                             "analysis; vary its .param or element values with --vary NAME=...)")
    assert request.netlist is not None  # plan_sweep came here for it
    plan = netlist_sweep_plan(request.netlist, [parse_netlist_vary(v) for v in request.vary],
                              NetlistSweep(request.samples, request.seed, request.backend, request.study.timeout),
                              Planning(budget, progress=request.variants_progress))
    left = budget.max_seconds - INTERPRETER_SECONDS - (time.monotonic() - started)
    return PlannedStudy(plan, max_seconds=max(left, 0.0))


def _real_parts(request: SweepRequest) -> RealParts:
    """The real parts the options set (``--samples``, ``--seed``, ``--tolerance``, ``--series``), checked."""
    from ..studies.plan import RealParts

    return RealParts(request.samples, request.seed, request.tolerance, request.series)


def _parts_sweep(request: SweepRequest, budget: Budget) -> Plan:
    """``sweep --case C --N N --tolerance 1% --series E24 --samples 200``: a Monte Carlo of real parts with no scene
    file, the scene made from the options (:func:`lcchain.studies.plan.case_scene`), each list of them an axis."""
    from ..studies.plan import CasePoint, Planning, case_scene, scene_sweep_plan

    if analysis_kind(request.analysis).swept:
        raise ParameterError("--analysis", request.analysis, "transient with --tolerance, --series or --samples and "
                             "no scene (an AC Monte Carlo: a scene file with [analysis] kind = \"ac\")")
    if request.points is not None:
        raise ParameterError("--points", request.points, "nothing without --analysis ac")
    cases, Ns = request.case or [], request.N or []  # both given: checked by plan_sweep
    steps: tuple[str, Sequence[LooseJSON]] = ("analysis.accuracy", request.accuracy) if request.accuracy else \
        ("analysis.dt", request.dt or [0.05])
    axes: list[tuple[str, Sequence[LooseJSON]]] = [("chain.case", cases), ("chain.N", Ns), steps,
                                             ("analysis.transits", request.transits or [1]),
                                             ("excitation.kind", request.excitation or ["kick"])]
    base = case_scene(CasePoint(cases[0], Ns[0], dt=request.dt[0] if request.dt else None,
                                accuracy=request.accuracy[0] if request.accuracy else None,
                                L0=_bulk(request)[0], C0=_bulk(request)[1], engine=request.engine or DEFAULT_ENGINE))
    if request.extrapolate is not None:
        base["analysis"]["extrapolate"] = request.extrapolate
    base["analysis"]["backend"] = request.backend
    varies = [(key, list(values)) for key, values in axes if len(values) > 1]
    for key, values in axes:
        if len(values) == 1:
            section, name = key.split(".")
            base[section][name] = values[0]
    return scene_sweep_plan(base, varies, _real_parts(request),
                            Planning(budget, study_workers(request.study))).limited(request.study.timeout)


def _scene_says(request: SweepRequest) -> tuple[tuple[str, LooseJSON], ...]:
    """The options a scene file says itself (its analysis, drive, transport and bulk units): given with SCENE.toml,
    refused."""
    return (("--analysis", request.analysis if analysis_kind(request.analysis).swept else None),
            ("--transits", request.transits), ("--excitation", request.excitation),
            ("--backend", None if request.backend == BACKENDS[0] else request.backend),
            ("--L0", request.L0), ("--C0", request.C0))


def _bulk(request: SweepRequest) -> tuple[float, float]:
    """The chain's bulk inductance and capacitance (henry, farad): the options', or lcchain's defaults."""
    return (request.L0 if request.L0 is not None else DEFAULT_L0, request.C0 if request.C0 is not None else DEFAULT_C0)


def _worst_case(request: SweepRequest, budget: Budget) -> PlannedStudy:
    """``sweep SCENE --worst-case``: the corners run like the scene's samples, then which is worst."""
    from ..studies.plan import Planning
    from ..studies.worst_case import DEFAULT_COMPONENTS, worst_case_plan

    if request.worst_case is None:
        option = "--components" if request.components is not None else "--metric"
        raise ParameterError(option, getattr(request, option.lstrip("-")), "only with --worst-case")
    if not request.scene:
        raise ParameterError("SCENE.toml", None, "a scene file with --worst-case")
    given = [o for o, v in (("--case", request.case), ("--N", request.N), ("--dt", request.dt),
                            ("--accuracy", request.accuracy), ("--extrapolate", request.extrapolate),
                            ("--engine", request.engine), ("--vary", request.vary),
                            ("--samples", request.samples), ("--seed", request.seed), ("--points", request.points),
                            ("--tolerance", request.tolerance), ("--series", request.series),
                            ("--netlist", request.netlist),
                            *_scene_says(request))
             if v is not None and v != []]
    if given:
        raise ParameterError(given[0], getattr(request, given[0].lstrip("-")), "nothing with --worst-case (the scene "
                             "says the circuit and its [effects.tolerance]; the corners replace the samples)")
    plan, setup = worst_case_plan(request.scene, components=request.components if request.components is not None else
                                  DEFAULT_COMPONENTS, metric=request.metric or "peak", method=request.worst_case,
                                  planning=Planning(budget, study_workers(request.study)))

    return PlannedStudy(plan, worst_case=setup)


def _transient_sweep(request: SweepRequest, budget: Budget, pool: ProcessPoolExecutor | None = None) -> Plan:
    from ..studies.plan import Planning, SweepAxes, sweep_plan

    if request.points is not None:
        raise ParameterError("--points", request.points, "nothing without --analysis ac (a transient's steps are --dt "
                             "or --accuracy)")
    axes = SweepAxes(cases=request.case or [], Ns=request.N or [],
                     dts=request.dt or ([] if request.accuracy else [0.05]), accuracies=request.accuracy or [],
                     transits=request.transits or [1], excitations=request.excitation or ["kick"], L0=_bulk(request)[0],
                     C0=_bulk(request)[1], backend=request.backend, timeout=request.study.timeout,
                     extrapolate=request.extrapolate, engine=request.engine or DEFAULT_ENGINE)
    return sweep_plan(axes, Planning(budget, study_workers(request.study)), pool=pool)


def _ac_sweep(request: SweepRequest, budget: Budget, pool: ProcessPoolExecutor | None = None) -> Plan:
    from ..studies.plan import Planning, SpectrumAxes, spectrum_sweep_plan

    given = [o for o in ("--dt", "--accuracy", "--extrapolate", "--transits", "--excitation")
             if getattr(request, o.lstrip("-")) is not None] + (["--backend"] if request.backend != BACKENDS[0] else [])
    if given:
        raise ParameterError(given[0], getattr(request, given[0].lstrip("-")), "nothing with --analysis ac (a "
                             "transient's option; an AC sweep has --points)")
    axes = SpectrumAxes(cases=request.case or [], Ns=request.N or [], points=request.points, L0=_bulk(request)[0],
                        C0=_bulk(request)[1], timeout=request.study.timeout, engine=request.engine or DEFAULT_ENGINE)
    return spectrum_sweep_plan(axes, Planning(budget, study_workers(request.study)))


#: How ``lcchain sweep --case ... --N ...`` plans each ``--analysis``.
_SWEEPS: dict[str, Callable[[SweepRequest, Budget, ProcessPoolExecutor | None], Plan]] = {
    "transient": _transient_sweep, "ac": _ac_sweep}


