"""One simulation, end to end: chain -> netlist -> ngspice -> comparison.

This is the orchestration the command line and scenes share; it holds no
physics of its own.  It never talks to ngspice except through
:func:`lcchain.ngspice.run`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

from .arrivals import arrival_window
from .chain import Chain
from .compare import Comparison, Waveforms, compare, normalise
from .errors import ParameterError
from .modes import Modes, normal_modes
from .netlist import Ladder, SimulationOptions, netlist_text, probe_names
from .types import BACKENDS, Backend, Excitation

__all__ = ["SimulationReport", "simulate", "stop_time", "make_netlist"]


def stop_time(modes: Modes, transits: int) -> float:
    """End of the last arrival's search window: the run lasts the requested transits and no longer."""
    if isinstance(transits, bool) or not isinstance(transits, int) or not 1 <= transits <= 1000:
        raise ParameterError("transits", transits, "an integer from 1 to 1000")
    return arrival_window(transits, modes.transit_time())[1]


def make_netlist(
    chain: Chain,
    *,
    dt: float,
    transits: int = 1,
    excitation: Excitation = "kick",
    L0: float = 10e-6,
    C0: float = 10e-9,
    I0: float = 1e-3,
    method: str = "trap",
    title: str | None = None,
    comments: tuple[str, ...] = (),
    modes: Modes | None = None,
) -> tuple[str, Ladder, SimulationOptions]:
    """The netlist that :func:`simulate` runs (parameters as there).

    Returns
    -------
    text, ladder, options
    """
    modes = modes if modes is not None else normal_modes(chain)
    ladder = Ladder(chain, L0, C0)
    options = SimulationOptions(dt=dt, tstop=stop_time(modes, transits), method=method)
    title = title if title is not None else f"lcchain {chain.name} chain N={chain.N}, {excitation}"
    text = netlist_text(ladder, options, excitation=excitation, I0=I0, title=title, comments=comments)
    return text, ladder, options


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
    run : lcchain.ngspice.RunResult
        Raw waveforms and simulator metadata.
    waveforms : Waveforms
        Dimensionless end signals.
    comparison : Comparison
    timings : dict
        Seconds spent building the netlist, in the simulator, reading and
        validating its output, and computing theory and comparison.
    """

    chain: Chain
    ladder: Ladder
    options: SimulationOptions
    excitation: str
    transits: int
    netlist: str
    run: object
    waveforms: Waveforms
    comparison: Comparison
    timings: dict = field(default_factory=dict)
    #: Requested accuracy (None when dt was given) and the error model's
    #: numbers (lcchain.accuracy): predicted, integration and physics error.
    accuracy: float | None = None
    predicted_error: float | None = None
    integration_error: float | None = None
    physics_error: float | None = None

    def to_dict(self) -> dict:
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
            "predicted_error": self.predicted_error,
            "integration_error": self.integration_error,
            "physics_error": self.physics_error,
        }


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
    method: str = "trap",
    title: str | None = None,
    timeout: float = 3600.0,
    modes: Modes | None = None,
    accuracy: float | None = None,
    progress: Callable[[float], None] | None = None,
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
        :func:`lcchain.accuracy.dt_for_accuracy` (give dt or accuracy, not both).
    progress : callable, optional
        Called with the fraction of the analysis ngspice has done (0 to 1),
        as :func:`lcchain.ngspice.run` reports it.

    Warns
    -----
    lcchain.accuracy.AccuracyWarning
        Gear over more than one transit; a dt whose predicted error exceeds 0.1.
    """
    from . import ngspice
    from .accuracy import dt_for_accuracy, predicted_error, split_error, warn_if_unreliable

    if (dt is None) == (accuracy is None):
        raise ParameterError("dt/accuracy", (dt, accuracy), "exactly one of dt and accuracy")

    if backend not in BACKENDS:
        raise ParameterError("backend", backend, " | ".join(BACKENDS))
    clock = time.perf_counter()
    modes = modes if modes is not None else normal_modes(chain)
    if accuracy is not None:
        dt = dt_for_accuracy(modes, accuracy, stop_time(modes, transits), method=method)
    text, ladder, options = make_netlist(chain, dt=dt, transits=transits, excitation=excitation, L0=L0, C0=C0,
                                         I0=I0, method=method, title=title, modes=modes)
    tstop = options.tstop
    predicted = predicted_error(modes, options.dt, tstop, method=options.method)
    warn_if_unreliable(method=options.method, transits=transits, predicted=predicted)
    names = probe_names(chain.N, "ends")
    built = time.perf_counter()
    result = ngspice.run(text, names, tstop * ladder.time_unit, backend=backend, timeout=timeout, progress=progress)
    ran = time.perf_counter()
    waveforms = normalise(result.time, result.vectors[names[0]], result.vectors[names[1]],
                          time_unit=ladder.time_unit, excitation=excitation, I0=I0)
    comparison = compare(waveforms, modes, transits)
    split = split_error(waveforms, modes, options.dt, method=options.method,
                        exact=(comparison.theory_first, comparison.theory_last))
    done = time.perf_counter()
    timings = {
        "netlist_and_modes_s": built - clock,
        "simulator_s": result.wall_s,
        "run_call_s": ran - built,
        "compare_s": done - ran,
        "total_s": done - clock,
    }
    timings["overhead_fraction"] = (timings["total_s"] - result.wall_s) / result.wall_s
    return SimulationReport(chain, ladder, options, excitation, transits, text, result, waveforms, comparison, timings,
                            accuracy=accuracy, predicted_error=predicted, integration_error=split.integration_error,
                            physics_error=split.physics_error)
