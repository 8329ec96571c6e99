"""One simulation of a chain, end to end: chain -> netlist -> ngspice -> comparison.

:func:`simulate` chooses the step (given, or from a wanted accuracy), writes
the netlist, describes the run as a :class:`~lcchain.runs.spec.RunSpec` and
executes it (:func:`lcchain.runs.execute.execute`): it holds no physics and no
ngspice handling of its own.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ..circuit.ladder import Ladder
from ..circuit.netlist import SimulationOptions, make_netlist, probe_names
from ..compare.accuracy import dt_for_accuracy, predicted_error, warn_if_unreliable
from ..compare.metrics import Comparison
from ..compare.waveforms import Waveforms
from ..core.blas import fixed_blas_threads
from ..core.budget import Budget, max_points, run_estimate
from ..core.checks import choice, real
from ..core.errors import ParameterError, SimulationError
from ..core.frozen import FrozenMap
from ..core.limits import MAX_DT
from ..core.types import BACKENDS, EXCITATIONS, Backend, Excitation, Method
from ..spice.runner import RunResult
from ..spice.simulator import Simulator
from ..theory.arrivals import stop_time
from ..theory.chain import Chain
from ..theory.modes import Modes
from ..theory.spectrum import normal_modes
from .execute import RunRecord, execute
from .spec import DEFAULT_TIMEOUT, RunSpec, Theory

__all__ = ["SimulationReport", "simulate", "simulation_spec"]


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
        Seconds spent choosing the step and writing the netlist, in ngspice,
        in the whole run call, comparing, and in total.
    accuracy : float or None
        Requested accuracy (None when dt was given).
    predicted_error, integration_error, physics_error : float or None
        The error model's numbers (:mod:`lcchain.compare.accuracy`).
    record : RunRecord
        The unit of work's record (key, digest, versions).
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

    @property
    def accuracy_met(self) -> bool | None:
        """Whether the requested accuracy was reached (None when dt was given instead)."""
        return None if self.accuracy is None else self.comparison.max_abs_error <= self.accuracy

    def to_dict(self) -> dict[str, Any]:
        """The JSON report of ``lcchain simulate --json``."""
        run = self.run
        return {
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
            "ngspice_version": run.ngspice_version,
            "netlist_sha256": run.netlist_sha256,
            "options": dict(run.options),
            "points": run.points,
            "wall_s": run.wall_s,
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
            "digest": self.record.digest if self.record is not None else None,
        }


@fixed_blas_threads
def simulation_spec(
    chain: Chain,
    *,
    dt: float | None = None,
    transits: int = 1,
    excitation: Excitation = "kick",
    L0: float = 10e-6,
    C0: float = 10e-9,
    I0: float = 1e-3,
    backend: Backend = "batch",
    method: Method = "trap",
    title: str | None = None,
    timeout: float = DEFAULT_TIMEOUT,
    modes: Modes | None = None,
    accuracy: float | None = None,
    budget: Budget | None = None,
) -> tuple[RunSpec, Ladder, SimulationOptions]:
    """The run :func:`simulate` makes, described and not yet executed (parameters as there).

    The run's cost is estimated before anything else is computed, and a run
    beyond ``budget`` is refused (:class:`~lcchain.core.budget.BudgetError`).

    Returns
    -------
    spec, ladder, options
    """
    if (dt is None) == (accuracy is None):
        raise ParameterError("dt/accuracy", (dt, accuracy), "exactly one of dt and accuracy")
    choice("backend", backend, BACKENDS)
    choice("excitation", excitation, EXCITATIONS)
    budget = budget if budget is not None else Budget()
    Ladder(chain, L0, C0)  # the component scale first: nothing is computed for a circuit ngspice cannot run
    modes = modes if modes is not None else normal_modes(chain)
    tstop = stop_time(modes, transits)
    cost = {"saved": 2, "compared": 2, "unknowns": 2 * chain.N}
    if accuracy is not None:
        dt = dt_for_accuracy(modes, accuracy, tstop, method=method, max_points=max_points(budget, **cost))
    dt = real("dt", dt, above=0.0, at_most=MAX_DT)
    run_estimate(points=tstop / dt, **cost).check(budget, "dt", dt, "a larger step, or fewer transits")
    text, ladder, options = make_netlist(chain, dt=dt, transits=transits, excitation=excitation, L0=L0, C0=C0,
                                         I0=I0, method=method, title=title, modes=modes, tstop=tstop)
    predicted = predicted_error(modes, options.dt, options.tstop, method=options.method)
    warn_if_unreliable(method=options.method, transits=transits, predicted=predicted)
    theory = Theory(chain, ladder.time_unit, I0=I0, excitation=excitation, transits=transits, dt=options.dt,
                    method=options.method, predicted_error=predicted, modes=modes)
    spec = RunSpec(text, tuple(probe_names(chain.N, "ends")), options.tstop * ladder.time_unit, backend=backend,
                   timeout=timeout, theory=theory, label=f"{chain.name} N={chain.N} dt={options.dt:.4g}")
    return spec, ladder, options


def simulate(
    chain: Chain,
    *,
    dt: float | None = None,
    transits: int = 1,
    excitation: Excitation = "kick",
    L0: float = 10e-6,
    C0: float = 10e-9,
    I0: float = 1e-3,
    backend: Backend = "batch",
    method: Method = "trap",
    title: str | None = None,
    timeout: float = DEFAULT_TIMEOUT,
    modes: Modes | None = None,
    accuracy: float | None = None,
    progress: Callable[[float], None] | None = None,
    simulator: Simulator | None = None,
    budget: Budget | None = None,
    on_spec: Callable[[RunSpec], None] | None = None,
) -> SimulationReport:
    """Simulate the chain's LC ladder in ngspice and compare with theory.

    Parameters
    ----------
    chain : Chain
    dt : float, optional
        Maximum time step in units of sqrt(L0 C0); give it or ``accuracy``.
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
        Seconds before ngspice is killed.
    modes : Modes, optional
        Precomputed modes of ``chain``.
    accuracy : float, optional
        Wanted max |simulation - theory| (dimensionless); dt is then
        :func:`lcchain.compare.accuracy.dt_for_accuracy` (give dt or accuracy, not both).
    progress : callable, optional
        Called with the fraction of the analysis ngspice has done (0 to 1).
    simulator : Simulator, optional
        Found once by the caller; found here for ``backend`` when omitted.
    budget : Budget, optional
        The most memory and time the run may take (default: :class:`~lcchain.core.budget.Budget`).
    on_spec : callable, optional
        Called with the run's spec before ngspice starts (the command line
        keeps the netlist there, so that a failed run still leaves it).

    Raises
    ------
    BudgetError
        The run's estimated cost is beyond the budget (before anything runs).
    SimulationError
        ngspice failed or timed out (the reason and ngspice's output in the message).

    Warns
    -----
    lcchain.compare.accuracy.AccuracyWarning
        Gear over more than one transit; a dt whose predicted error exceeds 0.1.
    """
    clock = time.perf_counter()
    spec, ladder, options = simulation_spec(chain, dt=dt, transits=transits, excitation=excitation, L0=L0, C0=C0,
                                            I0=I0, backend=backend, method=method, title=title, timeout=timeout,
                                            modes=modes, accuracy=accuracy, budget=budget)
    if on_spec is not None:
        on_spec(spec)
    built = time.perf_counter()
    record = execute(spec, simulator, progress=progress)
    done = time.perf_counter()
    if record.status != "ok":
        raise SimulationError(record.reason, record.log_tail, record.status)
    assert record.result is not None and record.signals is not None and record.metrics is not None
    result, metrics = record.result, record.metrics
    timings = {
        "netlist_and_modes_s": built - clock,
        "simulator_s": result.wall_s,
        "execute_s": done - built,
        "total_s": done - clock,
    }
    timings["overhead_s"] = timings["total_s"] - result.wall_s
    timings["overhead_fraction"] = timings["overhead_s"] / result.wall_s
    return SimulationReport(chain, ladder, options, excitation, transits, spec.netlist, result,
                            record.signals.waveforms(), Comparison.of(metrics, record.signals), FrozenMap(timings),
                            accuracy=accuracy, predicted_error=metrics.predicted_error,
                            integration_error=metrics.integration_error, physics_error=metrics.physics_error,
                            record=record)
