"""Run a netlist in ngspice and return validated waveforms: ngspice's entry point, over its transports.

Two backends give the same :class:`RunResult` (bit-identical waveforms, tested):

``"batch"`` (default)
    ``ngspice -b -r /dev/fd/N``: the netlist arrives on standard input and the
    binary raw file goes to an inherited descriptor of an *unlinked* temporary
    file, read back with numpy.  No file or folder ever has a name, so nothing
    is left behind however lcchain ends (Ctrl-C, SIGTERM, SIGKILL, a full disk).
``"shared"``
    The ngspice shared library (``libngspice.so.0``) through PySpice's
    low-level ``NgSpiceShared``, in a child process
    (``python -m lcchain.spice.ngspice.shared_worker``) that exits after one run, so no
    simulator state survives between runs.  PySpice is imported only in that
    child: ``import lcchain`` never loads it.

Processes
---------
Every child starts in a session of its own (the terminal's Ctrl-C reaches
lcchain only), under ``setpriv --pdeathsig KILL`` where available (it dies
with lcchain, even on SIGKILL), and its whole process group is killed on a
timeout and on any exception on the way out (KeyboardInterrupt,
:class:`~lcchain.core.errors.Interrupted`).  ``HOME`` points to a folder that
does not exist, so no user ``~/.spiceinit`` changes a result.

Validation
----------
ngspice often exits 0 after an error, so every run is checked: exit status 0
(batch), no fatal line in ngspice's output (``Error...``, ``could not find a
valid modelname``, ``Timestep too small``, ``circuit not parsed``,
``simulation(s) aborted``; ``can't find model`` and ``singular matrix`` on
a warning line are ngspice's warnings, which it recovers from), more than zero points, last time point equal to
``tstop`` (relative 1e-9), every requested vector present, all values
finite.  A failure raises :class:`~lcchain.core.errors.SimulationError` with
the reason and the useful end of ngspice's output.  Beware: ngspice 39
silently accepts an inductor or capacitor line without a value (it uses a
default) and a missing node; only the netlist generator can prevent those.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ...core.errors import ParameterError, SimulationError
from ...core.frozen import FrozenMap
from ...core.types import Backend
from ..expressions import parameter_names
from ..foreign import CheckedText, allowed_netlist
from ..job import AcJob, Progress, RunJob, TransportJob
from ..log import failure_reason, fatal_lines, trim_log, useful_output
from ..measure import measure_names, read_measurements
from ..result import RunResult, TransientData, read_include, validate_columns
from ..simulator import Simulator
from ..text import canonical_text, parse_options
from .batch import run_batch
from .find import find_simulator
from .place import placement
from .transports import TRANSPORT_RUNS

if TYPE_CHECKING:
    import numpy as np

__all__ = ["run", "run_plot", "TRANSPORT_RUNS", "PLOT_TRANSPORTS"]

#: The transports that run any analysis and hand back each of its plots (``ngspice -b`` writes them all to its
#: raw file): :func:`run_plot`'s, and so the AC analysis's (:attr:`lcchain.spice.ngspice.engine.Ngspice.ac_transports`).
PLOT_TRANSPORTS: tuple[Backend, ...] = ("batch",)


def run(job: RunJob, simulator: Simulator | None = None, *, backend: Backend | None = None,
        progress: Progress | None = None) -> RunResult:
    """Run a transient netlist in ngspice and return validated waveforms.

    Parameters
    ----------
    job : RunJob
        The netlist, the vectors, ``tstop`` and the run's limits, checked (:class:`lcchain.spice.job.RunJob`).
        Unless ``job.trusted``, the netlist must pass :func:`lcchain.spice.foreign.allowed_netlist` (its
        includes, in ``job.cwd``, are inlined), and every transport runs the text it returns
        (:class:`lcchain.spice.job.TransportJob`); a :class:`~lcchain.spice.foreign.CheckedText` (that function's
        own output, which a batch's plan carries) is not checked again.  A ``job.foreign`` netlist runs in the
        sandbox of :mod:`lcchain.spice.sandbox` (scratch HOME and working folder, no init file, read-only file
        system, no network).  The job's ``max_output_bytes`` and ``max_resident_bytes`` are watched every
        :data:`~lcchain.spice.processes.WATCH_INTERVAL` seconds while it runs, on every transport.
    simulator : Simulator, optional
        From :func:`lcchain.spice.ngspice.find.find_simulator`; found here (for ``backend``) when omitted.
    backend : {"batch", "shared"}, optional
        Only when no simulator is given (default ``"batch"``), or equal to its backend.
    progress : callable, optional
        Called with the fraction of ``tstop`` simulated: 0.0 before, then (batch backend) about every
        :data:`PROGRESS_INTERVAL` seconds from ngspice's ``Reference value`` lines, and 1.0 after a successful
        run.  An exception it raises stops the run: ngspice's group is killed and the exception propagates (how
        a caller cancels a run from a thread).

    Returns
    -------
    RunResult
        Its ``data`` a :class:`~lcchain.spice.result.TransientData`.

    Raises
    ------
    ParameterError
        Bad arguments, or a netlist line lcchain does not run.
    SimulatorMissingError
        ngspice (or its shared library, or PySpice) is not installed.
    SimulationError
        ngspice failed, timed out (``status == "timeout"``), outgrew ``max_output_bytes`` or
        ``max_resident_bytes``, or its output failed validation.
    """
    if not isinstance(job, RunJob):
        raise ParameterError("job", type(job).__name__, "an lcchain.spice.job.RunJob")
    cwd = job.cwd
    # a CheckedText is the allow-list's own output (includes inlined): checked once, in the plan, and run as it is
    text = canonical_text(job.netlist, "netlist") if job.trusted else job.netlist \
        if isinstance(job.netlist, CheckedText) else \
        allowed_netlist(job.netlist, "netlist", Path(cwd) if cwd is not None else None, read_include)
    if simulator is None:
        simulator = find_simulator(backend or "batch")
    elif simulator.backend not in TRANSPORT_RUNS:
        raise ParameterError("simulator", simulator.backend,
                             f"one of ngspice's transports: {' | '.join(TRANSPORT_RUNS)}")
    elif backend is not None and backend != simulator.backend:
        raise ParameterError("backend", backend, f"the simulator's own backend, {simulator.backend!r}")
    checked = TransportJob.checked(text, job)
    if progress is not None:
        progress(0.0)
    with placement(simulator, job.foreign, str(cwd) if job.trusted and cwd is not None else None) as place:
        columns, log, wall = TRANSPORT_RUNS[simulator.backend].run(checked, simulator, place, progress)
    time_s, found = _validate(columns, log, job.vectors, job.tstop, text)
    if progress is not None:
        progress(1.0)
    return RunResult(
        data=TransientData(time_s, FrozenMap(found)),
        engine_version=simulator.version,
        netlist_sha256=hashlib.sha256(job.netlist.encode("utf-8")).hexdigest(),
        wall_s=wall,
        log=trim_log(log),
        engine=simulator.engine,
        measurements=FrozenMap(read_measurements(log, measure_names(text))),
        options=FrozenMap(parse_options(text)),
        backend=simulator.backend,
    )


def run_plot(job: AcJob, plot: str, simulator: Simulator) -> tuple[dict[str, np.ndarray], str, float]:
    """Run lcchain's own netlist text in ngspice's batch transport and read one plot of its raw file.

    The analyses other than the transient (:meth:`lcchain.spice.ngspice.Ngspice.run_ac`) go through here: the
    same discipline as :func:`run` (own process group, timeout, nothing left behind), no allow-list (lcchain's
    text, or a foreign one already through it: ``job.foreign`` runs it in the sandbox), no check of the plot's
    vectors (the caller's analysis knows them).

    Parameters
    ----------
    job : AcJob
        The netlist (text lcchain wrote, or a foreign one already checked) and the run's limits.
    plot : str
        The raw file's plot to read (:func:`lcchain.spice.ngspice.raw.read_raw`: ``"transient"``, ``"ac"``);
        an AC analysis's plots are read one after the other (a sweep in several ``.ac`` cards).
    simulator : Simulator
        ngspice's batch transport.

    Returns
    -------
    columns : dict
        The plot's vectors by canonical name (complex for an AC plot).
    log : str
        ngspice's output.
    wall_s : float
        ngspice's wall time, seconds.

    Raises
    ------
    ParameterError
        A simulator on a transport other than :data:`PLOT_TRANSPORTS`.
    SimulationError
        ngspice failed, timed out, printed a fatal line, or wrote no such plot.
    """
    if simulator.backend not in PLOT_TRANSPORTS:
        raise ParameterError("simulator", simulator.backend, f"ngspice's {' | '.join(PLOT_TRANSPORTS)} transport")
    with placement(simulator, job.foreign, None) as place:
        columns, log, wall = run_batch(TransportJob.checked(job.netlist, job, plot), simulator, place)
    _refuse_fatal(log, job.netlist)
    return columns, log, wall


def _refuse_fatal(log: str, text: str) -> None:
    """Raise what ngspice's output says made the run fail (:func:`lcchain.spice.log.fatal_lines`): a bare .param
    name as a value is ngspice's warning, which it uses (the netlist read only when ngspice warned)."""
    parameters = parameter_names(text) if "can't find model" in log else frozenset()
    if fatal_lines(log, parameters):
        raise SimulationError(failure_reason(log, "", parameters), useful_output(log))


def _validate(columns: dict[str, np.ndarray], log: str, names: Sequence[str], tstop: float,
              text: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    _refuse_fatal(log, text)
    return validate_columns(columns, log, names, tstop)

