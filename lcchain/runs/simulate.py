"""One simulation of a chain, end to end: chain -> netlist -> ngspice -> comparison.

Two functions, as python-control has one per kind of input: :func:`simulate` takes a
:class:`~lcchain.runs.request.Request` (the whole simulation: effects, pulses, every loop...), and
:func:`simulate_chain` a chain with :class:`ChainOptions` (a kick or a displacement, the step or the accuracy, the
units and the engine), which it makes into that request.  :func:`simulate` is :func:`simulation_runs` (choose the
step or steps, write the netlists, describe the runs as :class:`~lcchain.runs.spec.RunSpec`) and then
:func:`run_simulation` (execute them with :func:`lcchain.runs.execute.execute`, combine an extrapolation, compare);
a caller may call the two apart, to keep the netlists before the simulator starts.  It holds no physics and no
ngspice handling of its own.
"""

from __future__ import annotations

import math
import os
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from ..circuit.ladder import Ladder
from ..circuit.netlist import SimulationOptions
from ..compare.extrapolate import (
    WEIGHTS,
    ExtrapolationPlan,
    interpolation_error,
)
from ..compare.metrics import Comparison, EffectCost
from ..compare.waveforms import Waveforms
from ..core.blas import fixed_blas_threads
from ..core.budget import Budget
from ..core.checks import callback, choice, instance, real
from ..core.errors import ParameterError, SimulationError
from ..core.frozen import FrozenMap
from ..core.json import JSONValue
from ..core.show import Figure, html_table, plot, short_repr
from ..core.types import DEFAULT_C0, DEFAULT_I0, DEFAULT_L0, EXCITATIONS, Backend, Excitation, Method
from ..spice.engine import Engine
from ..spice.engines import DEFAULT_ENGINE, engine_named
from ..spice.result import RunResult
from ..spice.simulator import Simulator
from ..theory.chain import Chain
from ..theory.modes import Modes
from .execute import RunRecord, execute
from .extrapolated import combined_record
from .request import Drive, Request, Transient, plan_request
from .spec import DEFAULT_TIMEOUT, RunSpec, Theory

if TYPE_CHECKING:
    import xarray as xr

#: ngspice runs of one extrapolation executed at once (each is single-threaded; never more than the cores).
MEMBER_THREADS = 2

__all__ = ["SimulationReport", "Extrapolation", "SimulationRuns", "ChainOptions", "simulate", "simulate_chain",
           "run_simulation", "simulation_runs", "simulation_spec",
           "simulator_wall_time"]


@dataclass(frozen=True, eq=False)
class Extrapolation:
    """How a simulation's result was made from one, two or three runs (:mod:`lcchain.compare.extrapolate`).

    Attributes
    ----------
    runs : int
        1 (no extrapolation), 2 or 3.
    steps : tuple of float
        Each run's fixed step (h, h/2, h/4), units of sqrt(L0 C0).
    members : tuple of RunRecord
        Each run, with its own error against theory.
    predicted_error : float or None
        The combination's predicted error, before any run.
    interpolation_error : float or None
        What bringing the finer runs onto the coarsest run's time points cost (on their models).
    reason : str
        Why extrapolation was not used when it was asked or considered ("" otherwise).
    plan : ExtrapolationPlan or None
        With --accuracy: the options weighed and the one chosen.
    digest : str
        SHA-256 of the combined signals (:func:`lcchain.runs.execute.waveform_digest`; "" for one run), as a
        study's store has it.
    """

    runs: int
    steps: tuple[float, ...]
    members: tuple[RunRecord, ...]
    predicted_error: float | None
    interpolation_error: float | None = None
    reason: str = ""
    plan: ExtrapolationPlan | None = None
    digest: str = ""

    def to_dict(self) -> dict[str, object]:  # its plan's to_dict is dict[str, object]
        members: list[JSONValue] = []
        for h, record in zip(self.steps, self.members, strict=True):
            metrics = record.metrics
            members.append({"dt": h, "points": record.run.points if record.run is not None else None,
                            "wall_s": record.wall_s, "digest": record.digest,
                            "max_abs_error": metrics.max_abs_error if metrics is not None else None,
                            "predicted_error": metrics.predicted_error if metrics is not None else None})
        return {"runs": self.runs, "weights": list(WEIGHTS[self.runs]), "dt": list(self.steps), "members": members,
                "predicted_error": self.predicted_error, "interpolation_error": self.interpolation_error,
                "grid": "the coarsest run's time points; each finer run brought onto them by an interpolating "
                        "spline of degree 7 through its own points",
                "reason": self.reason, "plan": self.plan.to_dict() if self.plan is not None else None}


@dataclass(frozen=True, eq=False)
class SimulationReport:
    """Everything one simulation produced.

    Attributes
    ----------
    chain, ladder, options : the simulated circuit and analysis
    excitation : str
    transits : int
    netlist : str
        The exact text that was run.
    run : RunResult
        Raw waveforms and simulator metadata.
    waveforms : Waveforms
        Dimensionless end signals.
    comparison : Comparison
    timings : Mapping[str, float]
        Seconds: ``netlist_and_modes_s`` choosing the step and writing the netlist; ``simulator_s`` the
        simulator processes' wall times summed (members of an extrapolation run two at a time, so this may
        exceed the time they took); ``simulator_wall_s`` the wall time during which at least one simulator
        process ran (:func:`simulator_wall_time`); ``execute_s`` running and comparing the runs;
        ``combine_s`` combining an extrapolation's members; ``total_s`` the whole call; ``overhead_s``
        lcchain's own wall time, ``total_s - simulator_wall_s``, never negative, and ``overhead_fraction``
        that over ``simulator_wall_s``.
    accuracy : float or None
        Requested accuracy (None when dt was given).
    predicted_error, integration_error, physics_error : float or None
        The error model's numbers (:mod:`lcchain.compare.accuracy`).
    record : RunRecord
        The unit of work's record (key, digest, versions).
    effects : EffectCost or None
        With effects that are no chain's (the run compared with the circuit's own theory): what they cost the
        pulse, the circuit's first arrival against the ideal chain's (:class:`lcchain.compare.metrics.EffectCost`).
    """

    chain: Chain
    ladder: Ladder
    options: SimulationOptions
    excitation: str
    transits: int
    netlist: str
    run: RunResult
    waveforms: Waveforms
    comparison: Comparison
    timings: Mapping[str, float] = field(default_factory=FrozenMap)
    accuracy: float | None = None
    predicted_error: float | None = None
    integration_error: float | None = None
    physics_error: float | None = None
    record: RunRecord | None = field(default=None, repr=False)
    extrapolation: Extrapolation | None = None
    effects: EffectCost | None = None

    @property
    def accuracy_met(self) -> bool | None:
        """Whether the requested accuracy was reached (None when dt was given instead)."""
        return None if self.accuracy is None else self.comparison.max_abs_error <= self.accuracy

    def _members(self) -> tuple[RunRecord, ...]:
        if self.extrapolation is not None:
            return self.extrapolation.members
        return (self.record,) if self.record is not None else ()

    @property
    def points(self) -> int:
        """The time points of all the runs (an extrapolation's members')."""
        return sum(m.run.points for m in self._members() if m.run is not None)

    @property
    def wall_s(self) -> float:
        """The simulator's seconds in all the runs, one after the other (an extrapolation's members')."""
        return sum(m.run.wall_s for m in self._members() if m.run is not None)

    def to_dict(self) -> dict[str, object]:  # its extrapolation's is dict[str, object]
        """The JSON report of ``lcchain simulate --json`` (points and wall_s: all the runs')."""
        run = self.run
        data: dict[str, object] = {
            "N": self.chain.N,
            "case": self.chain.name,
            "excitation": self.excitation,
            "dt": self.options.dt,
            "tstop": self.options.tstop,
            "transits": self.transits,
            "method": self.options.method,
            "L0": self.ladder.L0,
            "C0": self.ladder.C0,
            "backend": run.backend,
            "engine": run.engine,
            "engine_version": run.engine_version,
            "ngspice_version": run.ngspice_version,
            "netlist_sha256": run.netlist_sha256,
            "options": dict(run.options),
            "points": self.points,
            "wall_s": self.wall_s,
            "max_abs_error": self.comparison.max_abs_error,
            "max_abs_error_first": self.comparison.max_abs_error_first,
            "max_abs_error_last": self.comparison.max_abs_error_last,
            "arrivals": [a.to_dict() for a in self.comparison.arrivals],
            "timings": dict(self.timings),
            "accuracy": self.accuracy,
            "accuracy_met": self.accuracy_met,
            "predicted_error": self.predicted_error,
            "integration_error": self.integration_error,
            "physics_error": self.physics_error,
            "digest": (self.extrapolation.digest if self.extrapolation is not None and self.extrapolation.digest
                       else self.record.digest if self.record is not None else None),
            "extrapolation": self.extrapolation.to_dict() if self.extrapolation is not None else None,
        }
        if self.effects is not None:
            data["effects"] = self.effects.to_dict()
        return data

    def _rows(self) -> list[tuple[str, object]]:
        run, c = self.run, self.comparison
        coupled = f", coils coupled k = {self.chain.coupling:g}" if self.chain.coupled else ""
        runs = f", {self.extrapolation.runs} runs extrapolated" if self.extrapolation is not None and \
            self.extrapolation.runs > 1 else ""
        return [("chain", f"{self.chain.name}, N = {self.chain.N}{coupled}"),
                ("engine", f"{run.engine} {run.engine_version} ({run.backend}), {self.excitation}"),
                ("dt", f"{self.options.dt:.4g}{runs}, {self.transits} transit(s)"),
                ("max |simulation - theory|", c.max_abs_error),
                ("predicted error", "none" if self.predicted_error is None else self.predicted_error),
                ("accuracy", "not asked" if self.accuracy is None else
                 f"{self.accuracy:.3g} {'met' if self.accuracy_met else 'missed'}")]

    def __repr__(self) -> str:
        """A few lines (the arrays are in ``waveforms`` and ``comparison``; all of it: :meth:`to_dict`)."""
        return short_repr("SimulationReport", self._rows())

    def _repr_html_(self) -> str:
        return html_table("SimulationReport", self._rows())

    def plot(self, ax: object = None) -> Figure:
        """The end currents (or charges) over theory, the residual below, as ``lcchain simulate --plot`` draws.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Draw the far end's overlay into it (no residual panel).

        Returns
        -------
        matplotlib.figure.Figure
            Never shown; save it with ``fig.savefig(...)``.  matplotlib is imported here, not by ``import lcchain``.
        """
        return plot("simulation", self, ax=ax)

    def to_xarray(self) -> xr.Dataset:
        """The end loops, simulated and in theory (``first``, ``last``, ``theory_first``, ``theory_last``,
        dimensionless), as an xarray Dataset on ``time`` in seconds (``t`` beside it in units of sqrt(L0 C0)), the
        scalar summary of :meth:`to_dict` as attributes.  xarray is optional: ``pip install 'lcchain[data]'``."""
        from .datasets import simulation_dataset

        return simulation_dataset(self.waveforms, self.comparison, self.excitation, self.ladder.time_unit,
                                  self.to_dict())

def simulator_wall_time(runs: Sequence[tuple[float, float]]) -> float:
    """Seconds during which at least one of ``runs`` was running: the length of the union of the intervals
    ``[start, start + wall_s]``, each run given as ``(start, wall_s)`` (``time.perf_counter()`` when its
    ``execute`` began, and its simulator's process wall time).  The few microseconds ``execute`` spends before
    the process starts are counted as the simulator's; the union lies within the runs' ``execute`` calls, so
    the whole call's time minus it is never negative."""
    total, reached = 0.0, -math.inf
    for start, wall_s in sorted(runs):
        end = start + wall_s
        if end > reached:
            total += end - max(start, reached)
            reached = end
    return total


class _Cancelled(BaseException):
    """Raised in a member's progress callback to stop its ngspice when another member failed or was interrupted."""


@fixed_blas_threads  # held by this thread while the members' threads compute: one BLAS limit throughout
def _execute_members(specs: list[RunSpec], steps: tuple[float, ...], simulator: Simulator | None,
                     progress: Callable[[float], None] | None,
                     starts: list[float] | None = None) -> list[RunRecord]:
    """Execute the runs of an extrapolation, two at a time where the machine has the cores (batch backend).

    ``starts``, if given, receives each run's ``time.perf_counter()`` as its ``execute`` began, in the runs' order.

    The finest run (the longest) starts first; the others follow on the second thread.  If one fails or the
    caller is interrupted, the others are stopped from their progress callbacks (their ngspice groups are
    killed within :data:`lcchain.spice.processes.PROGRESS_INTERVAL`) before the exception propagates.
    """
    runs = len(specs)
    weights = [1.0 / h for h in steps]
    fractions = [0.0] * runs
    cancel = threading.Event()
    lock = threading.Lock()

    def watcher(i: int) -> Callable[[float], None]:
        def report(fraction: float) -> None:
            if cancel.is_set():
                raise _Cancelled
            if progress is not None:
                with lock:
                    fractions[i] = fraction
                    progress(sum(w * f for w, f in zip(weights, fractions, strict=True)) / sum(weights))
        return report

    if starts is not None:
        starts[:] = [0.0] * runs

    def one(i: int) -> RunRecord:
        if starts is not None:
            starts[i] = time.perf_counter()
        record = execute(specs[i], simulator, progress=watcher(i))
        if record.status != "ok":
            where = f" (the run at dt = {steps[i]:.4g}, {i + 1} of {runs})" if runs > 1 else ""
            raise SimulationError(record.reason + where, record.log_tail, record.status, record.engine)
        return record

    workers = min(runs, len(os.sched_getaffinity(0)), MEMBER_THREADS)
    if workers <= 1 or specs[0].backend not in engine_named(specs[0].engine).threaded_transports:
        return [one(i) for i in range(runs)]
    with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="lcchain-member") as pool:
        futures = {i: pool.submit(one, i) for i in reversed(range(runs))}
        try:
            return [futures[i].result() for i in range(runs)]
        except BaseException:
            cancel.set()
            for future in futures.values():
                future.cancel()
            raise


@dataclass(frozen=True)
class ChainOptions:
    """How :func:`simulate_chain` simulates a chain: everything but the chain, checked when made.

    A shorthand for the :class:`~lcchain.runs.request.Request` it makes (:meth:`request`): a kick or a
    displacement of loop 1, no effects, the two end loops saved.  Anything more (effects, a pulse, every loop,
    an AC sweep) is a Request, run by :func:`simulate`.

    Parameters
    ----------
    dt : float, optional
        Maximum time step in units of sqrt(L0 C0); give it or ``accuracy``.
    accuracy : float, optional
        Wanted max |simulation - theory| (dimensionless); dt is then
        :func:`lcchain.compare.accuracy.dt_for_accuracy` (give dt or accuracy, not both).
    extrapolate : {1, 2, 3}, optional
        Combine this many runs at dt, dt/2, dt/4 (Richardson: the dt^2 term, then the dt^4 term cancel).
        With ``accuracy`` and None, lcchain picks the cheapest of 1, 2 and 3 runs predicted to meet it; with
        ``dt`` and None, one run.  Gear falls back to one run, with the reason in ``report.extrapolation``.
    transits : int
        Arrivals to watch (1 = until the pulse reaches the far end).
    excitation : {"kick", "displacement"}
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    I0 : float
        Kick current (A); a displacement uses Q0 = I0 sqrt(L0 C0).
    backend : {"batch", "shared"}
    method : {"trap", "gear"}
    title : str, optional
        Netlist title (one line, validated).
    timeout : float
        Seconds before the simulator is killed.
    engine : str or Engine
        The circuit simulator, a name in :data:`lcchain.spice.engines.ENGINES` (``"ngspice"`` or
        ``"gnucap"``), or an :class:`~lcchain.spice.engine.Engine` itself (registered under its name, which the
        options keep); an engine without aligned steps (gnucap) refuses ``extrapolate`` > 1 and makes one run
        for an ``accuracy``.

    Raises
    ------
    ParameterError
        A value out of its range, naming the field, the value and what is allowed.
    """

    dt: float | None = None
    accuracy: float | None = None
    extrapolate: int | None = None
    transits: int = 1
    excitation: Excitation = "kick"
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0
    I0: float = DEFAULT_I0
    backend: Backend = "batch"
    method: Method = "trap"
    title: str | None = None
    timeout: float = DEFAULT_TIMEOUT
    engine: str | Engine = DEFAULT_ENGINE

    def __post_init__(self) -> None:
        # in the order a Request made of them checks them: the analysis and the drive check (and convert) their
        # own fields, then the engine is found, then the units and the transport
        choice("excitation", self.excitation, EXCITATIONS)
        object.__setattr__(self, "dt", self.transient.dt)
        object.__setattr__(self, "I0", Drive(self.excitation, self.I0).I0)
        engine = engine_named(self.engine)  # an Engine itself is registered under its name, which is kept
        object.__setattr__(self, "engine", engine.name)
        object.__setattr__(self, "L0", real("L0", self.L0, above=0.0, unit="henry"))
        object.__setattr__(self, "C0", real("C0", self.C0, above=0.0, unit="farad"))
        engine.check_transport("backend", self.backend)
        object.__setattr__(self, "timeout", real("timeout", self.timeout, above=0.0, unit="seconds"))

    @property
    def transient(self) -> Transient:
        """The transient analysis these options ask for."""
        return Transient(dt=self.dt, accuracy=self.accuracy, transits=self.transits, method=self.method,
                         extrapolate=self.extrapolate)

    def request(self, chain: Chain) -> Request:
        """The :class:`~lcchain.runs.request.Request` that simulates ``chain`` with these options."""
        instance("chain", chain, Chain)
        return Request(chain, self.transient, drive=Drive(self.excitation, self.I0), L0=self.L0, C0=self.C0,
                       backend=self.backend, title=self.title, timeout=self.timeout, engine=str(self.engine))


def simulation_spec(chain: Chain, options: ChainOptions, *, modes: Modes | None = None,
                    budget: Budget | None = None) -> tuple[RunSpec, Ladder, SimulationOptions]:
    """The one run :func:`simulate_chain` makes without extrapolation, described and not yet executed.

    The run's cost is estimated before anything else is computed, and a run beyond ``budget`` is refused
    (:class:`~lcchain.core.budget.BudgetError`).

    Parameters
    ----------
    chain : Chain
    options : ChainOptions
        As :func:`simulate_chain`'s (its ``extrapolate`` is set to 1).
    modes : Modes, optional
        Precomputed modes of ``chain``.
    budget : Budget, optional

    Returns
    -------
    spec, ladder, options
    """
    instance("options", options, ChainOptions)
    one = replace(options, extrapolate=1)
    plan = plan_request(one.request(chain), budget, modes=modes)
    return plan.specs[0], plan.ladder, plan.options()


@dataclass(frozen=True, eq=False)
class SimulationRuns:
    """The runs one simulation makes, described and not yet executed: one, or an extrapolation's members.

    Attributes
    ----------
    request : Request
        What was asked.
    steps : tuple of float
        Each run's fixed step, coarsest first (units of sqrt(L0 C0)).
    specs : tuple of RunSpec
        One per step (aligned steps when there are several).
    ladder, options : the coarsest run's circuit and analysis
    modes : Modes
    predicted_error : float or None
        The extrapolation's predicted error (None for one run: its spec's theory holds its own).
    reason : str
        Why extrapolation was not used when it was asked or considered ("" otherwise).
    plan : ExtrapolationPlan or None
        With ``accuracy``: the options weighed and the one chosen.
    plan_s : float
        Seconds spent choosing the steps and writing the netlists.
    """

    request: Request
    steps: tuple[float, ...]
    specs: tuple[RunSpec, ...]
    ladder: Ladder
    options: SimulationOptions
    modes: Modes
    predicted_error: float | None
    reason: str = ""
    plan: ExtrapolationPlan | None = None
    plan_s: float = 0.0

    @property
    def runs(self) -> int:
        return len(self.steps)


def simulation_runs(request: Request, *, modes: Modes | None = None, budget: Budget | None = None) -> SimulationRuns:
    """The runs :func:`simulate` makes (parameters as there): the step or steps chosen, every run's spec built.

    Raises
    ------
    ParameterError, BudgetError
        As :func:`simulate`, before anything runs.
    """
    clock = time.perf_counter()
    if isinstance(request, Chain):  # the one-argument form simulate had before: point to its new name
        raise ParameterError("request", f"a Chain ({request.name}, N = {request.N})", "a Request (a chain with "
                             "options: lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=...)))")
    instance("request", request, Request)
    if not isinstance(request.analysis, Transient):  # one line, pointing to the function that runs it
        raise ParameterError("analysis", type(request.analysis).__name__, "a Transient for lcchain.simulate "
                             "(an AC request: lcchain.spectrum(request), which returns a SpectrumReport)")
    plan = plan_request(request, budget, modes=modes)
    return SimulationRuns(request, plan.steps, plan.specs, plan.ladder, plan.options(), plan.modes,
                          plan.predicted_error, plan.reason, plan.accuracy_plan, time.perf_counter() - clock)


def simulate(request: Request, *, modes: Modes | None = None, budget: Budget | None = None,
             progress: Callable[[float], None] | None = None, simulator: Simulator | None = None
             ) -> SimulationReport:
    """Simulate a request's LC ladder in its engine and compare with theory.

    :func:`simulate_chain` is the shorthand for a chain and a few options; a request says the whole
    simulation (effects, pulses, every loop...).  It is :func:`simulation_runs` (plan) then
    :func:`run_simulation` (run and compare), which a caller may call apart, to keep the netlists before the
    simulator starts.

    Parameters
    ----------
    request : Request
        With a :class:`~lcchain.runs.request.Transient` analysis (an AC sweep: :func:`lcchain.spectrum`).
    modes : Modes, optional
        Precomputed modes of the request's nominal chain.
    budget : Budget, optional
        The most memory and time the run may take (default: :class:`~lcchain.core.budget.Budget`).
    progress : callable, optional
        Called with the fraction of the analysis the simulator has done (0 to 1).
    simulator : Simulator, optional
        Found once by the caller; found here for the request's backend when omitted.

    Raises
    ------
    BudgetError
        The run's estimated cost is beyond the budget (before anything runs).
    SimulationError
        The simulator failed or timed out (the reason and its output in the message).

    Warns
    -----
    lcchain.compare.accuracy.AccuracyWarning
        Gear over more than one transit; a dt whose predicted error exceeds 0.1.
    """
    instance("simulator", simulator, Simulator, optional=True)
    callback("progress", progress)
    return run_simulation(simulation_runs(request, modes=modes, budget=budget), progress=progress,
                          simulator=simulator)


def simulate_chain(chain: Chain, options: ChainOptions, *, budget: Budget | None = None,
                   progress: Callable[[float], None] | None = None, simulator: Simulator | None = None
                   ) -> SimulationReport:
    """Simulate a chain's LC ladder (kicked or displaced in loop 1) and compare with theory.

    ``simulate_chain(chain, ChainOptions(dt=0.05, transits=2))`` is
    ``simulate(ChainOptions(dt=0.05, transits=2).request(chain))``.

    Parameters
    ----------
    chain : Chain
    options : ChainOptions
        The step or the accuracy, the drive, the units, the engine.
    budget, progress, simulator
        As :func:`simulate`'s.

    Raises
    ------
    BudgetError, SimulationError
        As :func:`simulate`.

    Warns
    -----
    lcchain.compare.accuracy.AccuracyWarning
        As :func:`simulate`.
    """
    instance("options", options, ChainOptions)
    return simulate(options.request(chain), budget=budget, progress=progress, simulator=simulator)


def run_simulation(planned: SimulationRuns, *, progress: Callable[[float], None] | None = None,
                   simulator: Simulator | None = None) -> SimulationReport:
    """Run the runs :func:`simulation_runs` planned (two at a time where the machine has the cores), combine an
    extrapolation's members, and compare with theory (parameters as :func:`simulate`'s)."""
    instance("planned", planned, SimulationRuns)
    instance("simulator", simulator, Simulator, optional=True)
    callback("progress", progress)
    steps, runs, modes, plan, reason = planned.steps, planned.runs, planned.modes, planned.plan, planned.reason
    spec, ladder, options = planned.specs[0], planned.ladder, planned.options
    built = time.perf_counter()
    clock = built - planned.plan_s
    starts: list[float] = []
    records = _execute_members(list(planned.specs), steps, simulator, progress, starts)
    done = time.perf_counter()
    first = records[0]
    assert first.run is not None and first.signals is not None and first.metrics is not None
    result = first.run
    if runs == 1:
        signals, metrics = first.signals, first.metrics
        predicted = metrics.predicted_error
        extrapolation = Extrapolation(1, steps, (first,), predicted, None, reason, plan)
    else:
        predicted = planned.predicted_error
        assert isinstance(spec.theory, Theory)
        combined = combined_record(spec.theory, records, steps, predicted_error=predicted, modes=modes)
        assert combined.signals is not None and combined.metrics is not None
        signals, metrics = combined.signals, combined.metrics
        member_times = [r.signals.t for r in records if r.signals is not None]
        extrapolation = Extrapolation(runs, steps, tuple(records), predicted,
                                      interpolation_error(modes, member_times, signals.t, steps), reason, plan,
                                      combined.digest)
    compared = time.perf_counter()
    simulator_s = sum(r.run.wall_s for r in records if r.run is not None)
    simulating_s = simulator_wall_time([(start, r.run.wall_s if r.run is not None else 0.0)
                                        for start, r in zip(starts, records, strict=True)])
    timings = {
        "netlist_and_modes_s": built - clock,
        "simulator_s": simulator_s,
        "simulator_wall_s": simulating_s,
        "execute_s": done - built,
        "combine_s": compared - done,
        "total_s": compared - clock,
    }
    timings["overhead_s"] = timings["total_s"] - simulating_s
    timings["overhead_fraction"] = timings["overhead_s"] / simulating_s
    request = planned.request
    return SimulationReport(planned.ladder.chain, ladder, options, request.drive.kind, request.transient.transits,
                            spec.netlist, result,
                            signals.waveforms(), Comparison.of(metrics, signals), FrozenMap(timings),
                            accuracy=request.transient.accuracy, predicted_error=predicted,
                            integration_error=metrics.integration_error, physics_error=metrics.physics_error,
                            record=first, extrapolation=extrapolation, effects=metrics.effects)

