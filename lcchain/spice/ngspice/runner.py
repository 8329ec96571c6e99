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
(batch), no fatal line in ngspice's output (``Error...``, ``can't find
model``, ``singular matrix``, ``Timestep too small``, ``circuit not parsed``,
``simulation(s) aborted``), more than zero points, last time point equal to
``tstop`` (relative 1e-9), every requested vector present, all values
finite.  A failure raises :class:`~lcchain.core.errors.SimulationError` with
the reason and the useful end of ngspice's output.  Beware: ngspice 39
silently accepts an inductor or capacitor line without a value (it uses a
default) and a missing node; only the netlist generator can prevent those.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from ...core.checks import choice, real
from ...core.errors import ParameterError, SimulationError
from ...core.frozen import FrozenMap
from ...core.types import BACKENDS, Backend
from ..foreign import CheckedText, allowed_netlist
from ..log import failure_reason, fatal_lines, trim_log, useful_output
from ..measure import measure_names, read_measurements
from ..result import RunResult, check_arguments, read_include, validate_columns
from ..simulator import Simulator
from ..text import canonical_text, parse_options
from .batch import run_batch
from .find import find_simulator
from .place import placement
from .transports import TRANSPORT_RUNS

__all__ = ["run", "run_plot", "TRANSPORT_RUNS", "PLOT_TRANSPORTS"]

#: The transports that run any analysis and hand back each of its plots (``ngspice -b`` writes them all to its
#: raw file): :func:`run_plot`'s, and so the AC analysis's (:attr:`lcchain.spice.ngspice.engine.Ngspice.ac_transports`).
PLOT_TRANSPORTS: tuple[Backend, ...] = ("batch",)


def run(
    netlist: str,
    vectors: Sequence[str],
    tstop: float,
    *,
    simulator: Simulator | None = None,
    backend: Backend | None = None,
    timeout: float = 600.0,
    progress: Callable[[float], None] | None = None,
    cwd: str | os.PathLike[str] | None = None,
    trusted: bool = False,
    foreign: bool = True,
    max_output_bytes: float | None = None,
    max_resident_bytes: float | None = None,
) -> RunResult:
    """Run a transient netlist in ngspice and return validated waveforms.

    Parameters
    ----------
    netlist : str
        Complete netlist text with one ``.tran`` analysis ending at ``tstop``
        and ``.save`` lines for the wanted vectors. Unless ``trusted``, it must
        pass :func:`lcchain.spice.foreign.allowed_netlist` (its includes, in
        ``cwd``, are inlined), and ngspice receives the text it returns; a
        :class:`~lcchain.spice.foreign.CheckedText` (that function's own
        output) is not checked again.
    vectors : Sequence[str]
        Vector names as saved, e.g. ``["i(l1)", "v(n3)"]`` or ``["l1#branch"]``;
        empty: every vector the raw file holds.
    tstop : float
        End time of the ``.tran`` analysis in seconds; the last time point
        must equal it.
    simulator : Simulator, optional
        From :func:`lcchain.spice.ngspice.find.find_simulator`; found here (for
        ``backend``) when omitted.
    backend : {"batch", "shared"}, optional
        Only when no simulator is given (default ``"batch"``).
    timeout : float
        Seconds after which ngspice's process group is killed.
    progress : callable, optional
        Called with the fraction of ``tstop`` simulated: 0.0 before, then
        (batch backend) about every :data:`PROGRESS_INTERVAL` seconds from
        ngspice's ``Reference value`` lines, and 1.0 after a successful run.
        An exception it raises stops the run: ngspice's group is killed and
        the exception propagates (how a caller cancels a run from a thread).
    cwd : path-like, optional
        The netlist's own folder: its ``.include`` files must lie inside it;
        None for a netlist that includes nothing.
    trusted : bool
        Skip the allow-list and run the netlist as it is, in ``cwd`` (the user
        said so: ``lcchain batch --allow-control``); it still runs in the
        sandbox when ``foreign``.
    foreign : bool
        The netlist was not written by lcchain: ngspice runs it in the
        sandbox of :mod:`lcchain.spice.sandbox` (scratch HOME and working
        folder, no init file, read-only file system, no network).
    max_output_bytes : float, optional
        Stop the run (a failure) when its raw file (the vectors, on the warm
        and shared transports) grows past this many bytes, or its output past
        :data:`MAX_LOG_BYTES`; checked every
        :data:`~lcchain.spice.processes.WATCH_INTERVAL` seconds while it runs.
    max_resident_bytes : float, optional
        Stop the run (a failure) when the simulator's processes hold more
        than this many bytes resident, checked as often (every transport).

    Returns
    -------
    RunResult

    Raises
    ------
    ParameterError
        Bad arguments, or a netlist line lcchain does not run.
    SimulatorMissingError
        ngspice (or its shared library, or PySpice) is not installed.
    SimulationError
        ngspice failed, timed out (``status == "timeout"``), outgrew
        ``max_output_bytes`` or ``max_resident_bytes``, or its output failed validation.
    """
    netlist, names, tstop, timeout, limit = check_arguments(netlist, vectors, tstop, timeout, max_output_bytes)
    resident = None if max_resident_bytes is None else real("max_resident_bytes", max_resident_bytes, above=0.0,
                                                            unit="bytes")
    # a CheckedText is the allow-list's own output (includes inlined): checked once, in the plan, and run as it is
    text = canonical_text(netlist, "netlist") if trusted else netlist if isinstance(netlist, CheckedText) else \
        allowed_netlist(netlist, "netlist", Path(cwd) if cwd is not None else None, read_include)
    if simulator is None:
        simulator = find_simulator(choice("backend", backend or "batch", BACKENDS))
    elif simulator.backend not in TRANSPORT_RUNS:
        raise ParameterError("simulator", simulator.backend,
                             f"one of ngspice's transports: {' | '.join(TRANSPORT_RUNS)}")
    elif backend is not None and backend != simulator.backend:
        raise ParameterError("backend", backend, f"the simulator's own backend, {simulator.backend!r}")
    if progress is not None:
        progress(0.0)
    with placement(simulator, foreign, str(cwd) if trusted and cwd is not None else None) as place:
        columns, log, wall = TRANSPORT_RUNS[simulator.backend].run(text, simulator, timeout, tstop, progress, place,
                                                                   limit, resident)
    time_s, found = _validate(columns, log, names, tstop)
    if progress is not None:
        progress(1.0)
    return RunResult(
        time=time_s,
        vectors=FrozenMap(found),
        engine_version=simulator.version,
        netlist_sha256=hashlib.sha256(netlist.encode("utf-8")).hexdigest(),
        options=FrozenMap(parse_options(text)),
        wall_s=wall,
        backend=simulator.backend,
        points=int(time_s.size),
        log=trim_log(log),
        engine=simulator.engine,
        measurements=FrozenMap(read_measurements(log, measure_names(text))),
    )


def run_plot(netlist: str, plot: str, *, simulator: Simulator, timeout: float = 600.0, foreign: bool = False,
             max_output_bytes: float | None = None, joined: bool = False,
             max_resident_bytes: float | None = None) -> tuple[dict[str, np.ndarray], str, float]:
    """Run lcchain's own netlist text in ngspice's batch transport and read one plot of its raw file.

    The analyses other than the transient (:meth:`lcchain.spice.ngspice.Ngspice.run_ac`) go through here: the
    same discipline as :func:`run` (own process group, timeout, nothing left behind), no allow-list (lcchain's
    text, or a foreign one already through it), no check of the plot's vectors (the caller's analysis knows them).

    Parameters
    ----------
    netlist : str
        Netlist text lcchain wrote.
    plot : str
        The raw file's plot to read (:func:`lcchain.spice.ngspice.raw.read_raw`: ``"transient"``, ``"ac"``).
    simulator : Simulator
        ngspice's batch transport.
    timeout : float
        Seconds after which ngspice's process group is killed.
    foreign : bool
        A netlist lcchain did not write, already through the allow-list: it runs in the sandbox.
    max_output_bytes : float, optional
        ngspice is stopped when its raw file outgrows this.
    joined : bool
        Every plot of that analysis one after the other (a sweep in several ``.ac`` cards), not only the last.
    max_resident_bytes : float, optional
        ngspice is stopped when its resident memory outgrows this.

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
    with placement(simulator, foreign, None) as place:
        columns, log, wall = run_batch(netlist, simulator, timeout, 0.0, None, place, max_output_bytes,
                                        max_resident_bytes, plot=plot, joined=joined)
    if fatal_lines(log):
        raise SimulationError(failure_reason(log, ""), useful_output(log))
    return columns, log, wall



def _validate(columns: dict[str, np.ndarray], log: str, names: list[str],
              tstop: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    if fatal_lines(log):
        raise SimulationError(failure_reason(log, ""), useful_output(log))
    return validate_columns(columns, log, names, tstop)

