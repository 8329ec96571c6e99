"""Plans of many runs: what a study will run, decided and checked before anything runs.

A :class:`Plan` is an ordered tuple of :class:`Task` values, each a run spec
(:class:`~lcchain.runs.spec.RunSpec`) and the parameters that made it.  Every
spec is built here, in the parent: netlists written, steps chosen, tolerance
samples drawn from ``numpy.random.SeedSequence`` children and written into
each netlist as plain numbers, so the same plan gives the same runs on any
executor, host or attempt.

* :func:`sweep_plan`: the product of cases, sizes, steps or accuracies,
  transits and excitations (``lcchain sweep --case ... --N ...``);
* :func:`spectrum_sweep_plan`: the product of cases and sizes, each an AC
  sweep of the ladder's spectrum (``lcchain sweep --analysis ac ...``);
* :func:`scene_sweep_plan`: a scene with dotted keys varied, each tolerance
  sample a task of its own (``lcchain sweep SCENE.toml --vary ...``);
* :func:`batch_plan`: netlists lcchain did not write, run as they are
  (``lcchain batch``); each one lcchain will not run is a :class:`Refusal`,
  stored as a run of status ``"refused"`` while the others run (or, with
  ``strict``, refused before anything runs);
* :func:`netlist_sweep_plan`: one foreign netlist's ``.param`` or element
  values varied over lists, grids and seeded draws (``lcchain sweep --netlist
  FILE --vary ...``), each variant checked and run as a batch's netlist.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

from ..core import __version__
from ..core.budget import (
    RUN_START_SECONDS,
    SIMULATOR_BYTES,
    WARM_WORKER_BYTES,
    Budget,
    Estimate,
    accuracy_plan_seconds,
    chain_seconds,
    ngspice_seconds,
    run_estimate,
    sample_theory_seconds,
)
from ..core.checks import callback, instance, integer, real
from ..core.errors import ParameterError
from ..core.frozen import FrozenMap
from ..core.json import JSON, LooseJSON, LooseJSONObject
from ..core.limits import MAX_CIRCUIT_N, MAX_DESIGN_N, MAX_DT, MAX_TRANSITS, MIN_N
from ..core.types import DEFAULT_C0, DEFAULT_L0, Backend, Excitation
from ..runs.spec import DEFAULT_TIMEOUT, RunSpec, SpectrumTheory, Theory
from ..spice.engines import DEFAULT_ENGINE, ENGINES, find_engine
from ..spice.foreign import (
    ALLOW_CONTROL_HINT,
    allowed_netlist,
    analysis_of,
    includes_nothing,
    read_foreign,
)
from ..spice.inputs import shown_name
from ..spice.result import read_include
from ..spice.text import canonical_text
from .executors import EXECUTOR_TRAITS, executor_cost

if TYPE_CHECKING:
    from concurrent.futures import Executor

    from ..runs.request import Request, RequestPlan
    from ..spice.variants import Target
    from .vary import Vary

# A plan of foreign netlists (lcchain batch) needs none of the chains, requests and scenes: they load in the
# functions that plan them, so that a batch starts without them (issue 35, tests/test_imports.py).

__all__ = ["Task", "Combination", "Refusal", "Plan", "sweep_plan", "spectrum_sweep_plan", "scene_sweep_plan",
           "case_scene", "request_plan", "batch_plan", "netlist_sweep_plan", "parse_vary", "UnphysicalValueWarning"]


@dataclass(frozen=True)
class Task:
    """One run of a study.

    Attributes
    ----------
    index : int
        Its place in the plan (records are read back in this order).
    params : Mapping[str, object]
        The varied values that made it, by name (JSON values).
    spec : RunSpec
    seconds : float
        Its estimated wall time (for grouping short tasks, and the study's price).
    memory : float
        Its estimated memory where it runs, bytes: the run's arrays and comparison, and the simulator's process
        (the worker's own interpreter is the executor's, :func:`lcchain.studies.executors.executor_cost`).
    parts : Mapping or None
        A tolerance or preferred-value sample's realised part values, ``{"L": [L_1..L_N] (henry), "C": [C_01..
        C_N,N+1] (farad, None where a wall is a wire)}`` (:func:`realised_parts`); stored with its run's metrics.
        None for a nominal chain (its parts are the scene's).
    """

    index: int
    params: Mapping[str, object]
    spec: RunSpec
    seconds: float = 0.0
    memory: float = 0.0
    parts: Mapping[str, Sequence[float | None]] | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True, eq=False)
class Combination:
    """An extrapolation of a study: tasks of the plan (its members) combined into one result once all are stored.

    It is not run: :func:`lcchain.studies.run.run_plan` makes its record from the members' stored arrays
    (:func:`lcchain.runs.extrapolated.combined_record`) and stores it under its members' keys hashed
    (:meth:`Plan.keys`).

    Attributes
    ----------
    index : int
        Its place in the plan, after its members.
    params : Mapping[str, object]
        As its members', with ``dt`` the coarsest step and ``runs`` their number.
    members : tuple of int
        The members' task indices, coarsest first.
    steps : tuple of float
        The members' steps (units of sqrt(L0 C0)).
    theory : Theory
        The coarsest member's theory.
    predicted_error : float or None
    label : str
    """

    index: int
    params: Mapping[str, object]
    members: tuple[int, ...]
    steps: tuple[float, ...]
    theory: Theory
    predicted_error: float | None
    label: str = ""
    parts: Mapping[str, Sequence[float | None]] | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class Refusal:
    """A netlist of a batch that lcchain will not run: a row of the store with status ``"refused"`` and the
    refusal's one line, priced at no run.

    Attributes
    ----------
    index : int
        Its place in the plan (the batch's order).
    params : Mapping[str, object]
        ``{"netlist": path as given}``, as a task's.
    reason : str
        The refusal's words (:class:`~lcchain.core.errors.ParameterError`: the file, line and field).
    key : str
        Its row's key: the netlist's path as given and its text hashed (not the reason: a refusal for the budget
        names the budget, and a resume with another --max-time is the same batch), under ``refused``.
    label : str
        The file's name.
    """

    index: int
    params: Mapping[str, object]
    reason: str
    key: str
    label: str = ""


def _refusal_key(path: str, text: str) -> str:
    data = {"refused": path, "text": hashlib.sha256(text.encode("utf-8", "replace")).hexdigest(),
            "lcchain": __version__}
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode("utf-8")).hexdigest()


@dataclass(frozen=True)
class Plan:
    """Everything a study will run.

    Attributes
    ----------
    kind : {"sweep", "scene", "batch", "netlist"}
    description : Mapping
        What the user asked for (the command's axes), kept with the store.
    tasks : tuple of Task
        The runs.
    backend : {"batch", "shared"}
    axes : tuple of str
        The parameters that vary.
    combinations : tuple of Combination
        Extrapolations made from some of the tasks (their indices follow their members').
    engine : str
        The engine every run uses (:data:`lcchain.spice.engines.ENGINES`): one per study, found once.
    planning : float
        Priced seconds of the work done in the driver to make the plan (the sensitivities, each request's choice
        of steps, a Monte Carlo's theory): the study's price counts them with its runs.
    refusals : tuple of Refusal
        A batch's netlists that will not run: rows of the store (status ``"refused"``), no run, no price.
    """

    kind: str
    description: Mapping[str, JSON]
    tasks: tuple[Task, ...]
    backend: Backend = "batch"
    axes: tuple[str, ...] = field(default=())
    combinations: tuple[Combination, ...] = field(default=())
    engine: str = DEFAULT_ENGINE
    planning: float = 0.0
    refusals: tuple[Refusal, ...] = field(default=())

    def __post_init__(self) -> None:
        others = sorted({task.spec.engine for task in self.tasks} - {self.engine})
        if others:
            raise ParameterError("engine", others[0], f"one engine per study, {self.engine!r} (a study finds its "
                                 "engine once; run the other engine in a study of its own)")

    def limited(self, timeout: float) -> Plan:
        """The plan with no run allowed more than ``timeout`` seconds (``--timeout``): each run keeps the smaller of
        its own limit (a scene's come from their prices) and this one. A run's key does not hold its timeout, so a
        study resumes under another one."""
        timeout = real("timeout", timeout, above=0.0, unit="seconds")
        tasks = tuple(task if task.spec.timeout <= timeout else
                      replace(task, spec=replace(task.spec, timeout=timeout)) for task in self.tasks)
        return replace(self, tasks=tasks)

    def keys(self, ngspice_version: str) -> dict[int, str]:
        """Every row's key by index: each task's run, each combination's (its members' keys hashed) and each
        refusal's.  Made once for each version (a study asks for them for its keys, its rows and its fingerprint,
        each run's text hashed each time: 0.1 to 1 ms a run), kept beside the frozen fields."""
        made: dict[str, dict[int, str]] = self.__dict__.setdefault("_made_keys", {})
        if ngspice_version not in made:
            made[ngspice_version] = self._keys(ngspice_version)
        return dict(made[ngspice_version])

    def _keys(self, ngspice_version: str) -> dict[int, str]:
        keys = {task.index: task.spec.key(ngspice_version) for task in self.tasks}
        keys.update({refusal.index: refusal.key for refusal in self.refusals})
        for combination in self.combinations:
            from ..runs.extrapolated import combined_key

            keys[combination.index] = combined_key([keys[i] for i in combination.members])
        return dict(sorted(keys.items()))

    def rows(self, ngspice_version: str) -> list[tuple[str, dict[str, object], str]]:
        """(key, params, label) of every row in index order: what the store's tasks table holds."""
        keys = self.keys(ngspice_version)
        described = {task.index: (dict(task.params), task.spec.label) for task in self.tasks}
        described.update({c.index: (dict(c.params), c.label) for c in self.combinations})
        described.update({r.index: (dict(r.params), r.label) for r in self.refusals})
        return [(key, *described[index]) for index, key in keys.items()]

    def fingerprint(self, ngspice_version: str) -> str:
        """The plan's identity: its ordered row keys (which hold the lcchain and ngspice versions)."""
        return hashlib.sha256("\n".join(self.keys(ngspice_version).values()).encode()).hexdigest()

    def _runs(self) -> dict[str, Task]:
        """Each distinct run (a run that points share, once), by its key."""
        keys = self.keys("")
        return {keys[task.index]: task for task in self.tasks}

    def estimate(self) -> float:
        """Estimated seconds of all its runs together, on one worker (a run that points share, once)."""
        return sum(task.seconds for task in self._runs().values())

    def price(self, workers: int, executor: str = "process") -> Estimate:
        """What the whole study costs on ``workers`` of ``executor``: its planning, the executor's start and
        processes (:func:`lcchain.studies.executors.executor_cost`), its runs and their comparisons with theory
        (:func:`_compare_seconds`) shared among the workers, each
        worker holding the largest run (and a warm worker beside it, for transient runs), and the extrapolations
        combined in the driver."""
        distinct = list(self._runs().values())
        used = max(1, min(workers, len(distinct))) if EXECUTOR_TRAITS[executor].parallel else 1
        cost = executor_cost(executor, used, light=all(task.spec.theory is None for task in distinct))
        largest = max((task.memory for task in distinct), default=0.0)
        warm = WARM_WORKER_BYTES if any(task.spec.analysis in ENGINES[task.spec.engine].warm_analyses
                                        for task in distinct) else 0.0
        combining = sum(_combination_seconds(c) for c in self.combinations)
        runs = sum(task.seconds + _compare_seconds(task.spec) for task in distinct)
        seconds = self.planning + cost.start + runs / used + combining
        memory = (cost.fixed + used * (cost.per_worker + largest + warm)
                  + (largest if self.combinations else 0.0))  # the driver combines members' arrays
        return Estimate(f"{len(distinct)} runs on {used} worker{'s' if used > 1 else ''}", memory, seconds)

    def check(self, budget: Budget, workers: int, executor: str = "process", option: str | None = None) -> None:
        """Refuse a study whose planning, runs and workers would take more than the budget (time or memory),
        naming ``option`` (by default what the user gave that makes the runs: a sweep's axes, a scene's --vary, a
        batch's netlists)."""
        runs = len(self._runs())
        self.price(workers, executor).check(budget, option or self._made_by(), f"{runs} runs",
                                            "fewer runs, fewer or more workers, or a larger --max-time or "
                                            "--max-memory")

    def _made_by(self) -> str:
        made_by = _MADE_BY.get(self.kind)  # what the user gave that makes a plan of this kind's runs
        if made_by is not None:
            return made_by
        axes = [f"--{name}" for name in self.axes if name in ("case", "N", "dt", "accuracy", "transits", "excitation")]
        return " x ".join(axes) or "--N"


#: What the user gave that makes the runs of a plan of each kind (a sweep's: its axes' options).
_MADE_BY = {"batch": "NETLIST", "scene": "--vary/--samples", "netlist": "--vary/--samples"}


def _seconds(spec: RunSpec) -> float:
    """A run's wall time in its simulator from the cost model (what chooses its transport): unknowns x time
    points for a transient; for an AC run the engine's frequencies x unknowns and the fit
    (:func:`lcchain.compare.spectral.spectrum_estimate`)."""
    from ..compare.spectral import spectrum_estimate

    theory = spec.theory
    if isinstance(theory, SpectrumTheory) and spec.points is not None:
        whole = spectrum_estimate(spec.points, theory.chain.N, losses=theory.Q is not None,
                                  circuit=theory.circuit is not None)
        return whole.seconds * ENGINES[spec.engine].ac_relative_cost + RUN_START_SECONDS
    if isinstance(theory, Theory) and theory.dt is not None:
        points = spec.tstop / theory.time_unit / theory.dt
    else:
        return 0.1
    return ngspice_seconds(points, theory.unknowns) * ENGINES[spec.engine].relative_cost + RUN_START_SECONDS


def _points(spec: RunSpec, theory: Theory) -> float:
    """A transient's time points (adaptive steps: its tstop / 50 at the most)."""
    return spec.tstop / theory.time_unit / (theory.dt if theory.dt is not None else spec.tstop / theory.time_unit / 50)


def _compare_seconds(spec: RunSpec) -> float:
    """A transient run's comparison with the theory of its chain, beyond its simulator (its modes, the arrivals'
    refinement: :func:`lcchain.core.budget.sample_theory_seconds`; a sensitivity check's runs spent more there
    than in ngspice), and the circuit's own theory where the run has one. An AC run's fit is in :func:`_seconds`
    already."""
    theory = spec.theory
    if not isinstance(theory, Theory):
        return 0.0
    return sample_theory_seconds(theory.chain.N) + theory.circuit_cost(_points(spec, theory))[0]


def _memory(spec: RunSpec) -> float:
    """A run's memory where it runs: its arrays and their comparison (:func:`lcchain.core.budget.run_estimate`,
    an AC run's :func:`lcchain.compare.spectral.spectrum_estimate`) and the simulator's process."""
    from ..compare.spectral import spectrum_estimate

    theory = spec.theory
    if isinstance(theory, SpectrumTheory) and spec.points is not None:
        return spectrum_estimate(spec.points, theory.chain.N, losses=theory.Q is not None).memory
    if isinstance(theory, Theory) and theory.dt is not None:
        N, saved = theory.chain.N, len(spec.vectors)
        points = spec.tstop / theory.time_unit / theory.dt
        return run_estimate(points=points, saved=saved, compared=saved, unknowns=theory.unknowns, exact_N=N).memory \
            + SIMULATOR_BYTES + theory.circuit_cost(points)[1]
    return SIMULATOR_BYTES


def _combination_seconds(combination: Combination) -> float:
    """Combining an extrapolation in the driver: its members' arrays read back, combined on the coarsest grid,
    compared with theory (about a member's comparison)."""
    return RUN_START_SECONDS + sample_theory_seconds(combination.theory.chain.N)


def realised_parts(plan: RequestPlan, k: int) -> dict[str, list[float | None]] | None:
    """The k-th realised chain's part values, ``{"L": L_i in henry, "C": C_j in farad (None: a wire)}``
    (:class:`lcchain.circuit.ladder.Ladder`), when it is a tolerance or preferred-value sample; None when the
    plan runs the nominal chain itself."""
    from ..circuit.ladder import Ladder

    chain = plan.chains[k]
    if chain is plan.nominal:
        return None
    ladder = Ladder(chain, plan.request.L0, plan.request.C0)
    return ladder.parts()


def _add_runs(tasks: list[Task], combinations: list[Combination], params: Mapping[str, object],
              specs: Sequence[RunSpec], steps: Sequence[float], predicted_error: float | None,
              parts: Mapping[str, Sequence[float | None]] | None = None) -> None:
    """One point of a study: its run, or its extrapolation's members (``member`` 1, 2, 3, each with its own
    ``dt``) followed by their combination (``runs``, ``dt`` the coarsest step); ``parts``: its sample's."""
    index = len(tasks) + len(combinations)
    frozen = None if parts is None else FrozenMap(parts)
    if len(specs) == 1:
        tasks.append(Task(index, FrozenMap(params), specs[0], _seconds(specs[0]), _memory(specs[0]), frozen))
        return
    for i, (spec, h) in enumerate(zip(specs, steps, strict=True)):
        tasks.append(Task(index + i, FrozenMap({**params, "dt": h, "member": i + 1}), spec, _seconds(spec),
                          _memory(spec), frozen))
    theory = specs[0].theory
    assert isinstance(theory, Theory)  # an extrapolation's members are transients
    label = f"{specs[0].label} extrapolated from {len(specs)} runs"
    combinations.append(Combination(index + len(specs), FrozenMap({**params, "dt": steps[0], "runs": len(specs)}),
                                    tuple(range(index, index + len(specs))), tuple(steps), theory, predicted_error,
                                    label, frozen))


@dataclass(frozen=True)
class Planning:
    """How a plan is made, whatever it plans: the ``budget`` each run and the whole study are checked against
    (None: each run's own default, :class:`~lcchain.core.budget.Budget`), the ``workers`` the study will run on
    (its price shares the runs among them) and ``progress(done, total, what)`` while planning."""

    budget: Budget | None = None
    workers: int = 1
    progress: Callable[[int, int, str], None] | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        instance("budget", self.budget, Budget, optional=True)
        object.__setattr__(self, "workers", integer("workers", self.workers, at_least=1))
        if self.progress is not None:
            callback("progress", self.progress)


def _tuple(holder: object, name: str) -> None:
    """A frozen dataclass's sequence field kept as a tuple (a list given is copied: the plan cannot change)."""
    value = getattr(holder, name)
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise ParameterError(name, value, "a list of values")
    object.__setattr__(holder, name, tuple(value))


@dataclass(frozen=True)
class SweepAxes:
    """The axes of a transient sweep of named cases (``lcchain sweep --case ... --N ...``) and what every run of
    it shares: one task per (case, N, dt or accuracy, transits, excitation).

    Attributes
    ----------
    cases : sequence of str
        Named cases (:data:`lcchain.theory.cases.CHAIN_CASES`).
    Ns : sequence of int
        Sizes, :data:`~lcchain.core.limits.MIN_N` .. :data:`~lcchain.core.limits.MAX_CIRCUIT_N`.
    dts, accuracies : sequence of float
        Fixed steps (units of sqrt(L0 C0), 0 < dt <= :data:`~lcchain.core.limits.MAX_DT`) or accuracies
        (0 < accuracy < 1): one of the two, not both.
    transits : sequence of int
        Transits of the chain each run lasts, 1 .. :data:`~lcchain.core.limits.MAX_TRANSITS`.
    excitations : sequence of {"kick", "displacement"}
    L0, C0 : float
        The unit inductance (henry) and capacitance (farad).
    backend : {"batch", "shared"}
    timeout : float
        Each run's limit, seconds.
    extrapolate : int, optional
        Runs combined into each point (Richardson extrapolation).
    engine : str
        The engine every run uses (:data:`lcchain.spice.engines.ENGINES`).

    The axes are checked here, before anything is priced or designed; the values every run shares (units,
    backend, timeout, engine, extrapolate) by each run's own request, which names them as these fields do.
    """

    cases: Sequence[str]
    Ns: Sequence[int]
    dts: Sequence[float] = ()
    accuracies: Sequence[float] = ()
    transits: Sequence[int] = (1,)
    excitations: Sequence[Excitation] = ("kick",)
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0
    backend: Backend = "batch"
    timeout: float = DEFAULT_TIMEOUT
    extrapolate: int | None = None
    engine: str = DEFAULT_ENGINE

    def __post_init__(self) -> None:
        for name in ("cases", "Ns", "dts", "accuracies", "transits", "excitations"):
            _tuple(self, name)
        if bool(self.dts) == bool(self.accuracies):
            raise ParameterError("--dt/--accuracy", (list(self.dts), list(self.accuracies)),
                                 "steps or accuracies, not both")
        _check_axes(self.Ns, self.dts, self.accuracies, self.transits)


@dataclass(frozen=True)
class SpectrumAxes:
    """The axes of an AC sweep of named cases (``lcchain sweep --analysis ac --case ... --N ...``): one task per
    (case, N), each the ladder's spectrum over ``points`` frequencies (None: the request's default), with the unit
    inductance ``L0`` (henry) and capacitance ``C0`` (farad), each run's ``timeout`` (seconds) and ``engine``.
    The sizes are checked here (:data:`~lcchain.core.limits.MIN_N` .. :data:`~lcchain.core.limits.MAX_CIRCUIT_N`);
    ``points`` by each run's request, which also refuses too few to separate a chain's poles."""

    cases: Sequence[str]
    Ns: Sequence[int]
    points: int | None = None
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0
    timeout: float = DEFAULT_TIMEOUT
    engine: str = DEFAULT_ENGINE

    def __post_init__(self) -> None:
        _tuple(self, "cases")
        _tuple(self, "Ns")
        _check_axes(self.Ns, (), (), ())


def sweep_plan(axes: SweepAxes, planning: Planning | None = None, *, pool: Executor | None = None) -> Plan:
    """The product of the axes: one task per (case, N, dt or accuracy, transits, excitation).

    The study is priced from its axes first (:func:`_price_axes`), before any chain is designed; then every
    run is checked against ``planning.budget`` as :func:`lcchain.simulate` would.  With ``axes.extrapolate`` (or
    an accuracy that the cheapest way meets with several runs, as :func:`lcchain.simulate` chooses), a point is
    its members' tasks and their :class:`Combination`.

    ``pool``: the study's workers, already started (:func:`lcchain.studies.pools.started_pool`): the chains are
    designed there, all submitted at once, while this plans each point as its chain arrives (an optimal two-mass
    chain of N = 400 takes 0.28 s to design: 12 of them were 2.9 s in the driver before the first run).  The
    chains are the same bits wherever they are designed (theory runs under a fixed BLAS thread limit).
    """
    from ..runs.simulate import ChainOptions, simulation_runs
    from ..theory.cases import chain_for_case
    from ..theory.chain import Chain
    from ..theory.modes import Modes
    from ..theory.spectrum import normal_modes

    planning = planning if planning is not None else Planning()
    cases, Ns, dts, accuracies = axes.cases, axes.Ns, axes.dts, axes.accuracies
    transits, excitations, budget = axes.transits, axes.excitations, planning.budget
    steps = [("dt", v) for v in dts] + [("accuracy", v) for v in accuracies]
    combos = list(itertools.product(cases, Ns, steps, transits, excitations))
    priced = _price_axes(cases, Ns, steps, transits, len(combos), budget, planning.workers)
    chains: dict[tuple[str, int], tuple[Chain, Modes]] = {}
    designed = {} if pool is None else {(case, N): pool.submit(chain_for_case, case, N)
                                        for case, N in dict.fromkeys((case, N) for case, N, *_ in combos)}
    tasks: list[Task] = []
    combinations: list[Combination] = []
    for index, (case, N, (step, value), transit, excitation) in enumerate(combos):
        if planning.progress is not None:
            planning.progress(index, len(combos), f"planning {case} N={N}")
        if (case, N) not in chains:
            chain = designed[(case, N)].result() if designed else chain_for_case(case, N)
            chains[(case, N)] = (chain, normal_modes(chain))
        chain, modes = chains[(case, N)]
        options = ChainOptions(transits=transit, excitation=excitation, L0=axes.L0, C0=axes.C0,
                               backend=axes.backend, timeout=axes.timeout, extrapolate=axes.extrapolate,
                               dt=value if step == "dt" else None, accuracy=value if step == "accuracy" else None,
                               engine=axes.engine)
        runs = simulation_runs(options.request(chain), modes=modes, budget=budget)
        params: dict[str, JSON] = {"case": case, "N": N, step: value, "transits": transit, "excitation": excitation}
        if step == "accuracy":
            params["dt"] = runs.options.dt
        _add_runs(tasks, combinations, params, runs.specs, runs.steps, runs.predicted_error)
    description: dict[str, JSON] = {
        "command": "sweep", "case": list(cases), "N": list(Ns), "dt": list(dts), "accuracy": list(accuracies),
        "transits": list(transits), "excitation": list(excitations), "L0": axes.L0, "C0": axes.C0,
        "backend": axes.backend}
    if axes.extrapolate is not None:
        description["extrapolate"] = axes.extrapolate
    if axes.engine != DEFAULT_ENGINE:  # an ngspice study's description is what stores made before engines hold
        description["engine"] = axes.engine
    varied = tuple(name for name, values in (("case", cases), ("N", Ns), ("dt", dts), ("accuracy", accuracies),
                                             ("transits", transits), ("excitation", excitations)) if len(values) > 1)
    return Plan("sweep", FrozenMap(description), tuple(tasks), axes.backend, varied, tuple(combinations), axes.engine,
                priced)


def spectrum_sweep_plan(axes: SpectrumAxes, planning: Planning | None = None) -> Plan:
    """The product of cases and sizes, each an AC sweep of its spectrum (:class:`lcchain.runs.request.AC`).

    Priced from its axes first (the chains' designs), then each run by :func:`lcchain.runs.request.plan_request`
    (its frequencies x unknowns), which also refuses ``points`` too few to separate a chain's poles.
    """
    from ..runs.request import AC, Request, plan_request
    from ..theory.cases import chain_for_case

    planning = planning if planning is not None else Planning()
    cases, Ns, budget = axes.cases, axes.Ns, planning.budget
    combos = list(itertools.product(cases, Ns))
    priced = _price_axes(cases, Ns, [], (1,), len(combos), budget, planning.workers)
    tasks: list[Task] = []
    for index, (case, N) in enumerate(combos):
        if planning.progress is not None:
            planning.progress(index, len(combos), f"planning {case} N={N}")
        request = Request(chain_for_case(case, N), AC(axes.points), L0=axes.L0, C0=axes.C0, timeout=axes.timeout,
                          engine=axes.engine)
        try:
            spec = plan_request(request, budget).specs[0]
        except ParameterError as error:  # the chain of this point: its N on the axis, with its case
            if error.field != "chain":
                raise
            raise ParameterError("N", N, f"{error.allowed} ({case})") from None
        tasks.append(Task(index, FrozenMap({"case": case, "N": N}), spec, _seconds(spec), _memory(spec)))
    description: dict[str, JSON] = {"command": "sweep", "analysis": "ac", "case": list(cases), "N": list(Ns),
                                    "points": axes.points, "L0": axes.L0, "C0": axes.C0, "engine": axes.engine}
    varied = tuple(name for name, values in (("case", cases), ("N", Ns)) if len(values) > 1)
    return Plan("sweep", FrozenMap(description), tuple(tasks), "batch", varied, (), axes.engine, priced)


def _check_axes(Ns: Sequence[int], dts: Sequence[float], accuracies: Sequence[float], transits: Sequence[int]) -> None:
    """Refuse an axis value out of its range before the study is priced, naming its axis and the value (a NaN step
    used to reach the price and be refused as a study that would take forever)."""
    for N in Ns:
        integer("N", N, at_least=MIN_N, at_most=MAX_CIRCUIT_N)
    for dt in dts:
        real("dt", dt, above=0.0, at_most=MAX_DT, allowed=f"steps 0 < dt <= {MAX_DT:g} (units of sqrt(L0*C0))")
    for accuracy in accuracies:
        real("accuracy", accuracy, above=0.0, below=1.0, allowed="accuracies 0 < accuracy < 1")
    for transit in transits:
        integer("transits", transit, at_least=1, at_most=MAX_TRANSITS)


def _check_study(budget: Budget | None, field: str, what: str, planning: float, work: float, workers: int,
                 advice: str) -> float:
    """Refuse a study whose planning (in this process) and work (on ``workers``) exceed the budget, naming
    ``field``: the options whose values make the study (its axes); the planning's price, which the plan keeps
    (:attr:`Plan.planning`)."""
    Estimate(f"{what} to plan and run", 0.0, planning + work / max(1, workers)).check(
        budget if budget is not None else Budget(), field, what,
        f"fewer values on its axes, {advice}more workers, or a larger --max-time")
    return planning


def _price_axes(cases: Sequence[str], Ns: Sequence[int], steps: Sequence[tuple[str, float]], transits: Sequence[int],
                points: int, budget: Budget | None, workers: int) -> float:
    """Refuse a sweep whose planning (designs and modes, in this process) and fixed-step runs (on ``workers``)
    exceed the budget, from its axes alone: a 1000-value --N axis used to be planned for minutes before the
    plan's own price was known. Runs at an accuracy are left to the plan's own check (their step is chosen
    while planning). One run beyond the budget by itself is refused by its step (``dt``), the rest by the axes
    that multiply the runs."""
    planning = sum(chain_seconds(case, N) for case in set(cases) for N in set(Ns)) + 2e-4 * sum(Ns) * points / max(
        1, len(Ns))
    runs = 0.0
    budget = budget if budget is not None else Budget()
    for _case, N, (kind, value), transit in itertools.product(cases, Ns, steps, transits):
        if kind == "dt":  # the run lasts about (transits + 1/2) transits of about N
            one = ngspice_seconds((transit + 0.5) * N / value, 2 * N) + RUN_START_SECONDS
            Estimate(f"a run at N = {N}, {transit} transit{'s' if transit != 1 else ''}", 0.0, one).check(
                budget, "dt", value, "a larger step or --accuracy, or a larger --max-time")
            runs += one
        else:  # its step is chosen here, for its accuracy
            planning += accuracy_plan_seconds(N)
    axes = [name for name, values in (("case", cases), ("N", Ns), ("dt", [v for k, v in steps if k == "dt"]),
                                      ("accuracy", [v for k, v in steps if k == "accuracy"]),
                                      ("transits", transits)) if len(values) > 1]
    return _check_study(budget, " x ".join(f"--{name}" for name in axes) or "--N", f"{points} points", planning,
                        runs, workers, "")


def _price_scenes(datas: Sequence[Mapping[str, object]], budget: Budget | None, workers: int) -> float:
    """Refuse a scene sweep whose chains (designed here) and samples' theory (on ``workers``) exceed the budget,
    read from the varied scenes' tables alone, before any is planned. Each scene's own runs are priced when it
    is planned (:func:`lcchain.scenes.plan.scene_plan`)."""
    planning = work = 0.0
    for data in datas:
        chain = _table(data, "chain")
        N, case = chain.get("N"), chain.get("case", "two-mass")
        tolerance = _table(_table(data, "effects"), "tolerance")
        samples = tolerance.get("samples", 1)
        if not isinstance(N, int) or isinstance(N, bool) or not isinstance(samples, int) or N < 1 or samples < 1:
            continue  # the scene's own check names what is wrong
        planning += chain_seconds(str(case), min(N, MAX_DESIGN_N))
        analysis = data.get("analysis")
        if isinstance(analysis, dict) and analysis.get("accuracy") is not None:  # its step is chosen here
            planning += accuracy_plan_seconds(min(N, MAX_DESIGN_N))
        work += samples * (RUN_START_SECONDS + (sample_theory_seconds(N) if samples > 1 else 0.0))
    return _check_study(budget, "--vary/--samples", f"{len(datas)} scenes", planning, work, workers,
                        "fewer samples, ")


def parse_vary(text: str) -> tuple[str, list[object]]:
    """``KEY=V1,V2,...`` -> (dotted key, TOML values): ``chain.N=50,100`` -> ("chain.N", [50, 100]).

    Keys joined by ``+`` take the same value together, one axis:
    ``effects.tolerance.L+effects.tolerance.C=0.01,0.05``.
    """
    key, sep, values = text.partition("=")
    key = "+".join(part.strip() for part in key.split("+"))
    if not sep or not all(key.split("+")) or not values.strip():
        raise ParameterError("--vary", text, "KEY=V1,V2,... with a dotted scene key, e.g. chain.N=50,100 (keys "
                             "joined by + vary together)")
    entries = [raw.strip() for raw in values.split(",")]
    if not all(entries):  # "chain.N=50,,100" would run an axis of one value fewer than written, or a value ""
        empty = entries.index("") + 1
        raise ParameterError("--vary", text, f"KEY=V1,V2,... with no empty value (value {empty} of {len(entries)} "
                             "is empty)")
    import tomllib  # with datetime, 5 to 10 ms: a sweep's --vary only, not a batch's start

    from .vary import each_once

    parsed = []
    for raw in entries:
        try:
            parsed.append(tomllib.loads(f"v = {raw.strip()}")["v"])
        except tomllib.TOMLDecodeError:
            parsed.append(raw.strip())  # a bare word: a string (two-mass, gaussian)
    each_once(parsed, entries, text)
    return key, parsed


def _table(data: Mapping[str, object], key: str) -> Mapping[str, object]:
    """A scene's table under ``key``, or an empty one where it has none (or not a table: the scene's own check
    names it)."""
    table = data.get(key)
    return table if isinstance(table, dict) else {}


def _set(data: dict[str, object], key: str, value: object) -> None:
    for dotted in key.split("+"):
        _set_one(data, dotted, value)


def _set_one(data: dict[str, object], dotted: str, value: object) -> None:
    parts = dotted.split(".")
    table = data
    for part in parts[:-1]:
        inner = table.setdefault(part, {})
        if not isinstance(inner, dict):
            raise ParameterError("--vary", dotted, f"a key inside a table ({part} is not a table)")
        table = inner
    table[parts[-1]] = value


#: A scene made from the command line's options (``lcchain sweep --case ... --N ... --tolerance ...``).
_COMMAND_LINE = "the command line"


@dataclass(frozen=True)
class CasePoint:
    """One point of ``lcchain sweep --case --N``: a named ``case`` at ``N``, a fixed step ``dt`` (units of
    sqrt(L0 C0); 0.05 when neither is given) or an ``accuracy``, the ``transits`` the run lasts, its
    ``excitation``, the unit inductance ``L0`` (henry) and capacitance ``C0`` (farad), and the ``engine``.
    Its values are checked as the scene made of it (:func:`case_scene`) is parsed, under their scene keys."""

    case: str
    N: int
    dt: float | None = None
    accuracy: float | None = None
    transits: int = 1
    excitation: str = "kick"
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0
    engine: str = DEFAULT_ENGINE

    def __post_init__(self) -> None:
        if self.dt is not None and self.accuracy is not None:
            raise ParameterError("dt/accuracy", (self.dt, self.accuracy), "a step or an accuracy, not both")


def case_scene(point: CasePoint) -> LooseJSONObject:
    """The tables of the scene that runs ``point`` as ``lcchain sweep --case --N`` does (a step or an accuracy,
    transits, a drive, L0 and C0, an engine): what a Monte Carlo from the command line varies, with no scene file
    written."""
    analysis: LooseJSONObject = {"transits": point.transits, "engine": point.engine}
    analysis |= {"accuracy": point.accuracy} if point.accuracy is not None else \
        {"dt": 0.05 if point.dt is None else point.dt}
    return {"title": f"{point.case} chain, N = {point.N}, real parts", "chain": {"case": point.case, "N": point.N},
            "units": {"L0": point.L0, "C0": point.C0}, "excitation": {"kind": point.excitation},
            "analysis": analysis}


@dataclass(frozen=True)
class RealParts:
    """A scene's real parts set as the command line's options set them (:func:`lcchain.scenes.load.override_parts`):
    ``samples`` (``--samples``, 1 .. :data:`~lcchain.core.limits.MAX_SAMPLES`), the draw's ``seed`` (>= 0),
    ``tolerance`` (``{"L": tol, "C": tol}``, relative, 0 <= tol < 1) and a preferred-number ``series``
    (``"E12"``, ``"E24"``, ``"E96"``). Each is checked here, under its option's name."""

    samples: int | None = None
    seed: int | None = None
    tolerance: Mapping[str, float] | None = None
    series: str | None = None

    def __post_init__(self) -> None:
        if self.tolerance is not None:
            if not isinstance(self.tolerance, Mapping):
                raise ParameterError("--tolerance", self.tolerance, "L=TOL, C=TOL or one TOL for both")
            object.__setattr__(self, "tolerance", FrozenMap(self.tolerance))
        self.applied({})  # named as typed, and before any price (1e20 samples were priced as a study first)

    def applied(self, data: Mapping[str, LooseJSON]) -> LooseJSONObject:
        """A scene's tables with these parts set (the scene's other keys stay)."""
        from ..scenes.load import override_parts

        return override_parts(data, samples=self.samples, seed=self.seed, tolerance=self.tolerance,
                              series=self.series)


def scene_sweep_plan(path: str | Path | Mapping[str, LooseJSON], varies: Sequence[tuple[str, Sequence[object]]],
                     parts: RealParts | None = None, planning: Planning | None = None) -> Plan:
    """A scene with dotted keys varied (the product of their values); each tolerance sample is a task.

    ``path`` is the scene's file, or its tables themselves (a scene made from the command line's ``--case`` and
    ``--N``: :func:`case_scene`). ``parts`` set the scene's real parts as ``--samples``, ``--seed``,
    ``--tolerance`` and ``--series`` do (:class:`RealParts`). Priced from its axes first (:func:`_price_scenes`),
    before any scene is planned."""
    from ..scenes.load import load_scene, parse_scene
    from ..scenes.plan import scene_plan, scene_specs

    parts = parts if parts is not None else RealParts()
    planning = planning if planning is not None else Planning()
    budget, progress = planning.budget, planning.progress
    if isinstance(path, Mapping):
        scene, path = parse_scene(path, source=_COMMAND_LINE), _COMMAND_LINE
    else:
        scene = load_scene(path)
    base = scene.to_dict()
    if parts.applied({})["effects"]:
        base = parts.applied(base)
    keys = [key for key, _ in varies]
    named: dict[str, str] = {}
    for key in keys:  # one key in two --vary: the product would set it twice, and keep only the last
        for part in key.split("+"):
            if part in named:
                raise ParameterError("--vary", key, f"each scene key once (--vary {named[part]}=... names {part} "
                                     "already)")
            named[part] = key
    varied_keys = set(named)
    for key, other in (("analysis.dt", "accuracy"), ("analysis.accuracy", "dt")):
        if key in varied_keys and isinstance(base.get("analysis"), dict):
            base["analysis"].pop(other, None)  # varying one of the exclusive pair replaces the other (or its default)
    combos = list(itertools.product(*[values for _, values in varies])) if varies else [()]
    datas = []
    for values in combos:
        data = copy.deepcopy(base)
        for key, value in zip(keys, values, strict=True):
            _set(data, key, value)
        datas.append(data)
    from ..scenes.load import check_samples_spread

    check_samples_spread(parts.samples, datas)  # --samples with nothing to draw: each sample the nominal circuit
    priced = _price_scenes(datas, budget, planning.workers)
    tasks: list[Task] = []
    combinations: list[Combination] = []
    for n, (values, data) in enumerate(zip(combos, datas, strict=True)):
        params = dict(zip(keys, values, strict=True))
        if progress is not None:
            progress(n, len(combos), f"planning {params}")
        try:
            varied = parse_scene(data, source=str(path))
        except ParameterError as error:
            raise error.located(str(path)) from None
        plan = scene_plan(varied, budget)
        specs = scene_specs(varied, plan)
        for k in range(len(plan.chains)):
            task_params = {**params, "sample": k + 1} if len(plan.chains) > 1 else params
            _add_runs(tasks, combinations, task_params, specs[k * plan.runs:(k + 1) * plan.runs], plan.steps,
                      plan.predicted_error, realised_parts(plan, k))
    description = {"command": "sweep", "scene": str(path), "scene_data": base, "vary": dict(varies),
                   "samples": parts.samples, "seed": parts.seed} \
        | ({} if parts.tolerance is None else {"tolerance": dict(parts.tolerance)}) \
        | ({} if parts.series is None else {"series": parts.series})
    axes = tuple(keys) + (("sample",) if any("sample" in t.params for t in tasks) else ())
    engines = sorted({task.spec.engine for task in tasks}) or [scene.analysis.engine]
    if len(engines) > 1:
        raise ParameterError("--vary", f"analysis.engine={','.join(engines)}", "one engine per study (a study finds "
                             "its engine once): run each engine in a study of its own")
    return Plan("scene", FrozenMap(json.loads(json.dumps(description, default=str))), tuple(tasks),
                scene.analysis.backend, axes, tuple(combinations), engines[0], priced)


def request_plan(points: Sequence[tuple[Mapping[str, object], Request]], *, budget: Budget | None = None) -> Plan:
    """A study of requests made in Python: each point's params (its place on the study's axes, JSON values) and
    its :class:`~lcchain.runs.request.Request`, planned by :func:`lcchain.runs.request.plan_request`.

    Any request runs, effects of one's own included (docs/extending.md); run it with
    :func:`lcchain.studies.run.run_plan` into a store like any study.
    """
    from ..runs.request import Request, plan_request

    if not points:
        raise ParameterError("points", [], "at least one (params, Request) pair")
    tasks: list[Task] = []
    combinations: list[Combination] = []
    backends, engines = set(), set()
    names: dict[str, set[str]] = {}
    for params, request in points:
        instance("request", request, Request)
        backends.add(request.backend)
        engines.add(request.engine)
        for name, value in params.items():
            names.setdefault(name, set()).add(json.dumps(value, sort_keys=True, default=str))
        plan = plan_request(request, budget)
        for k in range(len(plan.chains)):
            task_params = {**params, "sample": k + 1} if len(plan.chains) > 1 else dict(params)
            _add_runs(tasks, combinations, task_params, plan.specs[k * plan.runs:(k + 1) * plan.runs], plan.steps,
                      plan.predicted_error, realised_parts(plan, k))
    if len(backends) > 1:
        raise ParameterError("backend", sorted(backends), "one backend for every request of a study")
    if len(engines) > 1:
        raise ParameterError("engine", sorted(engines), "one engine per study (a study finds its engine once)")
    axes = tuple(name for name, values in names.items() if len(values) > 1) + (
        ("sample",) if any("sample" in t.params for t in tasks) else ())
    description: dict[str, JSON] = {
        "command": "requests", "points": [json.loads(json.dumps(dict(p), default=str)) for p, _ in points]}
    return Plan("sweep", FrozenMap(description), tuple(tasks), backends.pop(), axes, tuple(combinations),
                engines.pop())


#: A batch's plan says how many netlists it has planned every this many (0.06 s of its plan at N = 10, 0.7 s at
#: N = 1000, by benchmarks/bench_plan.py's 0.24 and 2.9 ms a netlist).
PLANNED_EVERY = 256


def batch_plan(paths: Sequence[str | Path], *, allow_control: bool = False, backend: Backend = "batch",
               timeout: float = DEFAULT_TIMEOUT, budget: Budget | None = None, strict: bool = False,
               engine_version: Callable[[], str] | None = None, check: bool = False,
               progress: Callable[[int], None] | None = None) -> Plan:
    """Foreign netlists, checked and priced before anything runs.

    Every netlist, and every file it includes, must be a regular file (its
    includes inside its own folder) and pass the allow-list of
    :func:`lcchain.spice.foreign.allowed_netlist`, unless ``allow_control``
    (then it runs as it is). Each is priced from its analysis and what it holds
    (:func:`lcchain.spice.foreign.foreign_price`: elements, K lines, source edges,
    fast dynamics, expressions, text) and refused beyond ``budget``; its run gets
    its limits from its own price (:meth:`lcchain.spice.pricing.Price.limits`:
    a timeout, a raw file and a resident memory, a few times what was priced,
    within ``budget`` and ``timeout``) and is stopped past any of them. Every run
    happens in the sandbox of :mod:`lcchain.spice.sandbox`.

    A netlist refused by any of those checks is a :class:`Refusal` of the plan (its one line kept, its price
    none) and the others are its tasks; with ``strict``, or when every netlist is refused (nothing could run:
    bad input), the first refusal is raised instead, and nothing runs.
    The checks read text only, so a resumed batch makes them again, cheaply, and finds each refusal stored under
    its key (:attr:`Refusal.key`): it is neither run nor stored twice.

    With ``check``, each run's saved vectors are also compared with the netlist's exact response
    (:attr:`lcchain.runs.spec.RunSpec.check`): the largest error is stored as the measurement
    ``check_max_abs_error``.

    ``engine_version`` gives the version of the ngspice that will run the batch (:attr:`Simulator.version`),
    asked only when a netlist has an ``.ac dec`` card (:func:`lcchain.spice.foreign.log_sweep_count`); by
    default ngspice is found for ``backend``.  ``progress(done)`` is told how many netlists are planned, every
    :data:`PLANNED_EVERY` and once all are.
    """
    budget = budget if budget is not None else Budget()
    version = engine_version if engine_version is not None else _version_of(backend)
    runs = _ForeignRuns(backend, timeout, budget, version, trusted=allow_control, check=check)
    tasks = []
    refusals = []
    first: ParameterError | None = None
    for index, name in enumerate(paths):
        item, error = _batch_item(index, name, runs, strict)
        if isinstance(item, Task):
            tasks.append(item)
        else:
            first = first or error
            refusals.append(item)
        if progress is not None and (index + 1) % PLANNED_EVERY == 0:
            progress(index + 1)
    if progress is not None and len(paths) % PLANNED_EVERY:
        progress(len(paths))
    if first is not None and not tasks:  # nothing of it can run: bad input, as with strict
        raise first
    description: dict[str, JSON] = {"command": "batch", "netlists": [shown_name(str(p)) for p in paths],
                                    "allow_control": allow_control, "backend": backend}
    if check:
        description["check"] = True
    return Plan("batch", FrozenMap(description), tuple(tasks), backend, ("netlist",), refusals=tuple(refusals))


def _version_of(backend: Backend) -> Callable[[], str]:
    """The version of ngspice for ``backend``, found once when first asked."""
    found: list[str] = []

    def version() -> str:
        if not found:
            found.append(find_engine(DEFAULT_ENGINE, backend).version)
        return found[0]

    return version


@dataclass(frozen=True)
class _ForeignRuns:
    """How every foreign netlist of a plan runs: its ``backend``, each run's ``timeout`` (seconds; its price's
    limits within it), the ``budget`` each is priced against, the engine's ``version`` (asked only for an ``.ac
    dec`` card); ``trusted`` (``--allow-control``: run as it is, in its own folder) and ``check`` (compared with
    its exact response)."""

    backend: Backend
    timeout: float
    budget: Budget
    version: Callable[[], str]
    trusted: bool = False
    check: bool = False


def _batch_item(index: int, name: str | Path, runs: _ForeignRuns,
                strict: bool) -> tuple[Task | Refusal, ParameterError | None]:
    """One netlist of a batch planned: its task, or its refusal and why (raised with ``strict``).  Its row, its
    label and its messages name it as lcchain shows it (:func:`lcchain.spice.inputs.shown_name`: a name of bytes
    that are no UTF-8, or with a newline, escaped); the file is read by its own name."""
    path = Path(name)
    given = str(path)
    shown = shown_name(given)
    label = path.name if shown is given else Path(shown).name  # the name itself, most often: no second Path
    read: list[str] = []
    try:
        return _batch_task(index, path, shown, label, read, runs), None
    except ParameterError as error:
        if strict:
            raise
        return (Refusal(index, FrozenMap({"netlist": shown}), str(error), _refusal_key(shown, read[0] if read else ""),
                        label), error)


def _batch_task(index: int, path: Path, shown: str, label: str, read: list[str], runs: _ForeignRuns) -> Task:
    """One netlist of a batch checked, priced and made a task, or its refusal raised (``read`` gets its text
    once read: the refusal's key; ``shown`` and ``label``: its name in the task and in messages, and its label)."""
    text = read_include(path, "NETLIST")
    read.append(text)
    # its folder (the real file's) is asked for only to run it there or to find its includes: resolved only then
    folder = path.resolve().parent if runs.trusted or not includes_nothing(text) else path.parent
    run_text = canonical_text(text, shown) if runs.trusted else allowed_netlist(text, shown, folder, read_include)
    return _foreign_task(index, {"netlist": shown}, run_text, shown, label, runs,
                         cwd=str(folder) if runs.trusted else None)


def _foreign_task(index: int, params: Mapping[str, object], run_text: str, source: str, label: str,
                  runs: _ForeignRuns, *, cwd: str | None = None) -> Task:
    """A checked foreign netlist (what ngspice will receive) priced and made a task, or its refusal raised: its
    analysis, its price against the budget and its run's limits from that price."""
    backend, budget, version, trusted, check = runs.backend, runs.budget, runs.version, runs.trusted, runs.check
    read = read_foreign(run_text, source, version)  # its analysis, saves and price: its text searched once
    analysis, saved, price = read.analysis, read.saved, read.price
    if check:  # its exact reference too, in the worker beside the run
        from ..runs.check import check_estimate

        estimate = check_estimate(price, run_text, analysis, source)
    else:
        estimate = price.estimate
    estimate.check(budget, source, analysis.describe())
    limits = price.limits(budget, runs.timeout)
    try:
        spec = RunSpec(run_text, saved, analysis.tstop, backend=backend, timeout=limits.timeout,
                       cwd=cwd, trusted=trusted, foreign=True,
                       max_output_bytes=limits.max_output_bytes, max_resident_bytes=limits.max_resident_bytes,
                       label=label, analysis=analysis.kind, points=analysis.frequencies, check=check)
    except ParameterError as error:
        raise (error.renamed("--allow-control") if error.field == "trusted" else error).located(source) \
            from None
    return Task(index, FrozenMap(dict(params)), spec, estimate.seconds, estimate.memory + SIMULATOR_BYTES)


def _swept(error: ParameterError) -> ParameterError:
    """An allow-list refusal as a sweep says it: a sweep has no ``--allow-control``, so batch's hint goes."""
    if not error.allowed.endswith(ALLOW_CONTROL_HINT):
        return error
    return ParameterError(error.field, error.value, error.allowed.removesuffix(ALLOW_CONTROL_HINT)
                          + " (a sweep runs only what the allow-list accepts)", error.where)


@dataclass(frozen=True)
class NetlistSweep:
    """How a foreign netlist's variants are drawn and run (``lcchain sweep --netlist FILE``): ``samples`` draws of
    each distribution (``--samples``) from ``seed`` (``--seed``), each variant on ``backend`` within ``timeout``
    seconds (and its own price's limits); ``engine_version`` gives the version of the ngspice that will run them
    (asked only for an ``.ac dec`` card; by default ngspice is found for ``backend``). ``samples`` and ``seed``
    are checked with the --vary values they draw (:func:`lcchain.studies.vary.variant_points`)."""

    samples: int | None = None
    seed: int | None = None
    backend: Backend = "batch"
    timeout: float = DEFAULT_TIMEOUT
    engine_version: Callable[[], str] | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        real("timeout", self.timeout, above=0.0, unit="seconds")
        callback("engine_version", self.engine_version)


class UnphysicalValueWarning(UserWarning):
    """A sweep gives an element a value no real part has (a capacitance of 0 or less, a coupling beyond 1)."""


#: What a real part's value is, by element letter: ngspice runs a capacitor of -1 uF, or a K line of 1.5, as written
#: (the first has uses in models, the second ends in "timestep too small"); a sweep that writes one says so.
_REAL_PART: dict[str, tuple[str, Callable[[float], bool]]] = {
    **{letter: ("> 0", lambda value: value > 0) for letter in "RLC"},
    "K": ("of magnitude at most 1", lambda value: abs(value) <= 1)}


def _warn_unphysical(varies: Sequence[Vary], found: Mapping[str, Target], points: Sequence[Mapping[str, float]]
                     ) -> None:
    """Warn (one line each) where a sweep writes an element a value no real part has: a capacitance of 0 or
    less (a wide normal: draw, a lin: grid through 0), a coupling beyond 1.  The runs go as written: ngspice
    runs them, and a negative element is a model's tool; :func:`lcchain.runs.check` refuses them (its exact
    reference needs real parts)."""
    import warnings

    for vary in varies:
        target = found[vary.column]
        rule = _REAL_PART.get(target.name[:1].upper()) if target.kind == "element" else None
        if rule is None:
            continue
        wanted, real = rule
        values = [point[vary.column] for point in points if vary.column in point]
        odd = [value for value in values if not real(value)]
        if odd:
            warnings.warn(f"--vary {vary.spec}: {len(odd)} of {len(values)} runs give {target.name} a value no real "
                          f"part has (a value {wanted} is, and not {odd[0]:.6g}); ngspice runs them as written",
                          UnphysicalValueWarning, stacklevel=2)


def netlist_sweep_plan(path: str | Path, varies: Sequence[Vary], options: NetlistSweep | None = None,
                       planning: Planning | None = None) -> Plan:
    """A foreign netlist's ``.param`` or element values varied (``lcchain sweep --netlist FILE --vary ...``): one
    task per variant, each checked, priced and run as :func:`batch_plan` runs a netlist.

    The netlist (and every file it includes) passes the allow-list once
    (:func:`lcchain.spice.foreign.allowed_netlist`); each varied name is found in the text it returns
    (:func:`lcchain.spice.variants.find_target`: a name it does not define is refused, listing those it does);
    each variant is that text with the values replaced (:func:`lcchain.spice.variants.with_values`: numbers
    lcchain writes), checked by the allow-list again, and what comes back is what runs.  Its analysis and price
    are the variant's own: a variant beyond ``budget`` is a :class:`Refusal` (stored as ``refused``) while the
    others run; when every variant is refused, the first refusal is raised.

    Each task's params are its values by :attr:`lcchain.studies.vary.Vary.column` (and ``sample`` for drawn
    values, :func:`lcchain.studies.vary.variant_points`): the store's columns for them.
    """
    from ..spice.variants import find_target, netlist_targets, with_values
    from .vary import variant_points

    options = options if options is not None else NetlistSweep()
    planning = planning if planning is not None else Planning()
    samples, seed, backend, timeout, progress = (options.samples, options.seed, options.backend, options.timeout,
                                                 planning.progress)
    budget = planning.budget if planning.budget is not None else Budget()
    version = options.engine_version if options.engine_version is not None else _version_of(backend)
    runs = _ForeignRuns(backend, timeout, budget, version)
    path = Path(path)
    source = str(path)
    points = variant_points(varies, samples=samples, seed=seed)  # before the netlist: a bad --vary is the error
    text = read_include(path, "--netlist")
    try:
        base = allowed_netlist(text, source, path.resolve().parent, read_include)
    except ParameterError as error:
        raise _swept(error) from None
    analysis_of(base, source, version)  # a netlist without an analysis lcchain reads is bad input, not a refusal
    targets = netlist_targets(base)
    found = {vary.column: find_target(targets, vary.name, shown=vary.spec) for vary in varies}
    _warn_unphysical(varies, found, points)
    tasks: list[Task] = []
    refusals: list[Refusal] = []
    first: ParameterError | None = None
    for index, point in enumerate(points):
        label = f"{path.name} " + " ".join(f"{column}={value:.6g}" for column, value in point.items()
                                           if column in found)
        if progress is not None:
            progress(index, len(points), f"planning {label}")
        variant = with_values(base, {found[column]: value for column, value in point.items() if column in found})
        try:
            checked = allowed_netlist(variant, source, None)  # the same allow-list: what it returns runs
            tasks.append(_foreign_task(index, point, checked, source, label, runs))
        except ParameterError as refused:
            said = _swept(refused)
            first = first or said
            refusals.append(Refusal(index, FrozenMap(point), str(said), _refusal_key(source, variant), label))
    if progress is not None:
        progress(len(points), len(points), "planning")
    if first is not None and not tasks:  # nothing of it can run: bad input
        raise first
    description: dict[str, JSON] = {"command": "sweep", "netlist": source, "vary": [vary.spec for vary in varies],
                   "samples": samples, "seed": seed, "backend": backend}
    seen: dict[str, set[str]] = {}
    for point in points:
        for key, value in point.items():
            seen.setdefault(key, set()).add(repr(value))
    axes = tuple(key for key, values in seen.items() if len(values) > 1)
    return Plan("netlist", FrozenMap(description), tuple(tasks), backend, axes, refusals=tuple(refusals))
