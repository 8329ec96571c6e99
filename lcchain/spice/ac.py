"""An AC analysis of lcchain's own ladder: complex vectors against frequency, in any engine that has one.

:func:`run_ac` takes a checked :class:`~lcchain.spice.job.AcJob` and dispatches by ``simulator.engine`` to
:meth:`lcchain.spice.engine.Engine.run_ac` (ngspice: :mod:`lcchain.spice.ngspice`; gnucap:
:mod:`lcchain.spice.gnucap`), which runs the AC netlist (:func:`lcchain.circuit.netlist.ac_netlist_text`) with
the runner's discipline and returns the frequencies and the complex vectors, checked
(:func:`lcchain.spice.acdata.ac_result`): every vector present, as many points as asked, all finite.
"""

from __future__ import annotations

from ..core.errors import ParameterError
from .acdata import AcResult
from .engines import DEFAULT_ENGINE, ac_engine, find_engine
from .job import AcJob
from .result import RunResult
from .simulator import Simulator

__all__ = ["AcResult", "AcJob", "run_ac"]


def run_ac(job: AcJob, simulator: Simulator | None = None, *, engine: str | None = None) -> RunResult:
    """Run lcchain's AC netlist in an engine and return its complex vectors.

    Parameters
    ----------
    job : AcJob
        The netlist (written by :func:`lcchain.circuit.netlist.ac_netlist_text`, ngspice's dialect), the vectors
        (e.g. ``("i(l1)", "i(l20)")``), the frequencies its ``.ac`` cards ask for, the run's limits, and whether
        the netlist is foreign (lcchain did not write it: already through
        :func:`lcchain.spice.foreign.allowed_netlist`, it runs in the sandbox of an engine that ``runs_foreign``;
        with no vectors named, every vector it saved is read).
    simulator : Simulator, optional
        The engine's batch transport (its ``engine`` chooses the engine); found for ``engine`` when omitted.
    engine : str, optional
        Only without a simulator, or equal to its engine (default ``"ngspice"``).

    Returns
    -------
    RunResult
        Its ``data`` an :class:`~lcchain.spice.result.AcData`: the frequencies (Hz) and the complex vectors.

    Raises
    ------
    ParameterError
        An engine without an AC analysis, or a simulator of another engine than ``engine``.
    SimulatorMissingError
        The engine is not installed.
    SimulationError
        The engine failed, timed out, or its output is not the analysis asked for.
    """
    if not isinstance(job, AcJob):
        raise ParameterError("job", type(job).__name__, "an lcchain.spice.job.AcJob")
    if simulator is None:
        simulator = find_engine(ac_engine(engine or DEFAULT_ENGINE).name)
    elif engine is not None and engine != simulator.engine:
        raise ParameterError("engine", engine, f"the simulator's own engine, {simulator.engine!r}")
    return ac_engine(simulator.engine).run_ac(job, simulator)
