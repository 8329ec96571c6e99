"""Run a netlist in ngspice and return validated waveforms.

Two backends give the same :class:`RunResult` (bit-identical waveforms, tested):

``"batch"`` (default)
    ``ngspice -b -r /dev/fd/N``: the netlist arrives on standard input and the
    binary raw file goes to an inherited descriptor of an *unlinked* temporary
    file, read back with numpy.  No file or folder ever has a name, so nothing
    is left behind however lcchain ends (Ctrl-C, SIGTERM, SIGKILL, a full disk).
``"shared"``
    The ngspice shared library (``libngspice.so.0``) through PySpice's
    low-level ``NgSpiceShared``, in a child process
    (``python -m lcchain.spice.shared_worker``) that exits after one run, so no
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

import contextlib
import hashlib
import math
import os
import re
import select
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

import numpy as np

from ..core.budget import show_bytes
from ..core.checks import choice, real
from ..core.errors import ParameterError, SimulationError
from ..core.frozen import FrozenArrays, FrozenMap
from ..core.limits import MAX_NETLIST_BYTES
from ..core.types import BACKENDS, Backend
from .foreign import allowed_netlist
from .inputs import read_input
from .log import LOG_MAX_CHARS, failure_reason, fatal_lines, trim_log, useful_output
from .measure import Measurements, measure_control, measure_names, read_measurements
from .processes import (
    MAX_LOG_BYTES,
    PACKAGE_ROOT,
    WATCH_INTERVAL,
    call_shared_worker,
    child_env,
    decode_worker_payload,
    kill_group,
    outgrown,
    read_all,
)
from .raw import read_raw
from .sandbox import SCRATCH, scratch_env
from .scratch import scratch_folder
from .simulator import Simulator, find_simulator
from .text import canonical_text, canonical_vector_name, circuit_lines, parse_options, require_canonical, text_digest
from .warm import worker_for

__all__ = ["RunResult", "run", "run_plot", "read_include", "check_arguments", "validate_columns", "exited",
           "TSTOP_RTOL", "LOG_MAX_CHARS", "PROGRESS_INTERVAL", "MAX_LOG_BYTES"]

#: Relative tolerance on the last time point versus the requested ``tstop``.
TSTOP_RTOL = 1e-9
#: Seconds between two looks at a running batch run, when there is something to look at (a progress callback,
#: a raw-file limit); its exit is seen at once.
PROGRESS_INTERVAL = 0.5

# Only complete lines (ngspice ends each with "\r"): a number cut by a partial write must not count.
_REFERENCE_VALUE = re.compile(rb"Reference value\s*:\s*([-+0-9.eE]+)[ \t]*[\r\n]")


@dataclass(frozen=True, eq=False)
class RunResult(FrozenArrays):
    """Waveforms and metadata of one transient run (in ngspice or another engine).

    Attributes
    ----------
    time : numpy.ndarray
        Time points in seconds (read-only), ending at ``tstop``.
    vectors : Mapping[str, numpy.ndarray]
        Requested vectors (read-only arrays, amperes or volts) keyed by their
        normalised name (:func:`lcchain.spice.text.canonical_vector_name`).
    engine_version : str
        The engine's version, e.g. ``"39"`` for ngspice.
    netlist_sha256 : str
        SHA-256 (hex) of the netlist text encoded as UTF-8.
    options : Mapping[str, str]
        The ``.options`` the netlist sets (:func:`lcchain.spice.text.parse_options`).
    wall_s : float
        Wall time of the simulator in seconds: the ``ngspice -b`` process for
        ``"batch"``, loading and running the circuit inside the child for
        ``"shared"`` (child start-up excluded).
    backend : str
        ``"batch"`` or ``"shared"``.
    points : int
        Number of time points.
    log : str
        The simulator's output without blank lines and resource chatter, trimmed to
        :data:`LOG_MAX_CHARS` characters.
    engine : str
        The engine's name (:data:`lcchain.spice.engines.ENGINES`), ``"ngspice"`` by default.
    measurements : Mapping[str, tuple[float | None, str]]
        The netlist's ``.meas`` results by name (lower case): (value, "") or (None, ngspice's reason)
        (:func:`lcchain.spice.measure.read_measurements`).
    """

    time: np.ndarray
    vectors: Mapping[str, np.ndarray]
    engine_version: str
    netlist_sha256: str
    options: Mapping[str, str]
    wall_s: float
    backend: str
    points: int
    log: str = field(repr=False)
    engine: str = "ngspice"
    measurements: Measurements = field(default_factory=FrozenMap)

    @property
    def ngspice_version(self) -> str:
        """ngspice's version when ngspice ran it, else "" (records made before engines had only this field)."""
        return self.engine_version if self.engine == "ngspice" else ""

    def metadata(self) -> dict[str, object]:
        """Everything but the arrays, as a JSON-serialisable dict.

        Returns
        -------
        dict
            Keys ``engine``, ``engine_version``, ``ngspice_version`` (as the
            property), ``netlist_sha256``, ``options``,
            ``wall_s``, ``backend``, ``points``, ``vectors`` (the names),
            ``t_end`` (last time point, s) and ``log``.
        """
        return {
            "engine": self.engine,
            "engine_version": self.engine_version,
            "ngspice_version": self.ngspice_version,
            "netlist_sha256": self.netlist_sha256,
            "options": dict(self.options),
            "wall_s": float(self.wall_s),
            "backend": self.backend,
            "points": int(self.points),
            "vectors": list(self.vectors),
            "t_end": float(self.time[-1]),
            "log": self.log,
        }


# --------------------------------------------------------------------------- arguments


def check_arguments(netlist: object, vectors: object, tstop: object, timeout: object,
                    max_output_bytes: object) -> tuple[str, list[str], float, float, float | None]:
    """A run's arguments, checked: the text, the canonical vector names (no ``time``), tstop, timeout, limit."""
    if not isinstance(netlist, str) or not netlist.strip():
        raise ParameterError("netlist", netlist, "non-empty netlist text")
    tstop = real("tstop", tstop, above=0.0, unit="seconds")
    timeout = real("timeout", timeout, above=0.0, unit="seconds")
    limit = None if max_output_bytes is None else real("max_output_bytes", max_output_bytes, above=0.0,
                                                        unit="bytes")
    if isinstance(vectors, str) or not isinstance(vectors, Sequence):
        raise ParameterError("vectors", vectors, "a sequence of vector names, not one string")
    names: list[str] = []
    for name in vectors:
        if not isinstance(name, str) or not name.strip() or re.search(r"\s", name.strip()):
            raise ParameterError("vectors", name, "an ngspice vector name such as 'i(l1)' or 'v(n3)'")
        key = canonical_vector_name(name)
        if key != "time" and key not in names:
            names.append(key)
    return netlist, names, tstop, timeout, limit


def read_include(path: Path, field: str) -> str:
    """A netlist's or an included file's text (the ``read`` of :func:`lcchain.spice.foreign.allowed_netlist`):
    a regular file of at most :data:`lcchain.core.limits.MAX_NETLIST_BYTES`."""
    return read_input(path, field, MAX_NETLIST_BYTES)


# --------------------------------------------------------------------------- running


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
        ``cwd``, are inlined), and ngspice receives the text it returns.
    vectors : Sequence[str]
        Vector names as saved, e.g. ``["i(l1)", "v(n3)"]`` or ``["l1#branch"]``;
        empty: every vector the raw file holds.
    tstop : float
        End time of the ``.tran`` analysis in seconds; the last time point
        must equal it.
    simulator : Simulator, optional
        From :func:`lcchain.spice.simulator.find_simulator`; found here (for
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
    text = canonical_text(netlist, "netlist") if trusted else \
        allowed_netlist(netlist, "netlist", Path(cwd) if cwd is not None else None, read_include)
    if simulator is None:
        simulator = find_simulator(choice("backend", backend or "batch", BACKENDS))
    elif simulator.engine != "ngspice":
        raise ParameterError("simulator", simulator.engine, "an ngspice simulator (other engines run through "
                             "lcchain.spice.engines.run_engine)")
    elif backend is not None and backend != simulator.backend:
        raise ParameterError("backend", backend, f"the simulator's own backend, {simulator.backend!r}")
    if progress is not None:
        progress(0.0)
    with _placement(simulator, foreign, str(cwd) if trusted and cwd is not None else None) as place:
        columns, log, wall = TRANSPORT_RUNS[simulator.backend](text, simulator, timeout, tstop, progress, place, limit,
                                                               resident)
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
        The raw file's plot to read (:func:`lcchain.spice.raw.read_raw`: ``"transient"``, ``"ac"``).
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
        A simulator other than ngspice's batch transport.
    SimulationError
        ngspice failed, timed out, printed a fatal line, or wrote no such plot.
    """
    if simulator.engine != "ngspice" or simulator.backend != "batch":
        raise ParameterError("simulator", f"{simulator.engine} {simulator.backend}", "ngspice's batch transport")
    with _placement(simulator, foreign, None) as place:
        columns, log, wall = _run_batch(netlist, simulator, timeout, 0.0, None, place, max_output_bytes,
                                        max_resident_bytes, plot=plot, joined=joined)
    if fatal_lines(log):
        raise SimulationError(failure_reason(log, ""), useful_output(log))
    return columns, log, wall


@dataclass(frozen=True)
class _Place:
    """Where a child runs: its command-line prefix, working folder and environment."""

    prefix: tuple[str, ...]
    cwd: str
    env: dict[str, str]


@contextlib.contextmanager
def _placement(simulator: Simulator, foreign: bool, own_folder: str | None) -> Iterator[_Place]:
    """lcchain's own netlists run in ``/`` with a HOME that does not exist; a foreign one in a scratch folder,
    in the sandbox where there is one (``own_folder``: a trusted netlist's folder, read-only there)."""
    if not foreign:
        yield _Place(simulator.launcher, own_folder or "/", child_env())
    elif simulator.sandbox.available:
        # What the run reads from the host's /tmp (the netlist's folder; an interpreter and lcchain installed
        # there, for the shared backend's child) is shown in the sandbox, whose /tmp is its own.
        shown = [own_folder] if own_folder else []
        shown += [p for p in dict.fromkeys((sys.prefix, PACKAGE_ROOT)) if Path(p).resolve().is_relative_to("/tmp")]
        prefix = (*simulator.launcher, *simulator.sandbox.command([], own_folder or SCRATCH, shown))
        yield _Place(prefix, "/", scratch_env(SCRATCH))
    else:
        with scratch_folder("scratch") as folder:
            scratch = str(folder)
            yield _Place(simulator.launcher, own_folder or scratch, scratch_env(scratch))


def _simulated_time(err: IO[bytes]) -> float | None:
    """The last ``Reference value : t`` ngspice wrote to stderr (its progress, in seconds)."""
    fd = err.fileno()
    size = os.fstat(fd).st_size
    tail = os.pread(fd, 256, max(0, size - 256))
    found = _REFERENCE_VALUE.findall(tail)
    return float(found[-1]) if found else None


def exited(proc: subprocess.Popen[bytes], pidfd: int | None, seconds: float) -> int | None:
    """ngspice's exit status as soon as it exits within ``seconds``, else None.

    A pidfd (Linux) wakes this the moment the child exits; Popen.wait with a timeout would sleep-poll it
    (1, 3, 7 ... 50 ms late), a delay that every short run paid in full.
    """
    if pidfd is None:
        try:
            return proc.wait(timeout=seconds)
        except subprocess.TimeoutExpired:
            return None
    ready, _, _ = select.select([pidfd], [], [], seconds)
    return proc.wait() if ready else None


def wait_watching(proc: subprocess.Popen[bytes], timeout: float, look: Callable[[], None] | None,
                  interval: float = PROGRESS_INTERVAL) -> int | None:
    """A child's exit status, or None after ``timeout`` seconds; ``look`` (which may raise to stop the run) is
    called every ``interval`` seconds while it runs, and without it the wait sleeps to the exit at once."""
    deadline = time.monotonic() + timeout
    try:
        pidfd: int | None = os.pidfd_open(proc.pid)
    except (AttributeError, OSError):  # not Linux, or an old kernel
        pidfd = None
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            status = exited(proc, pidfd, min(interval, left) if look is not None else left)
            if status is not None:
                return status
            if look is not None:
                look()
    finally:
        if pidfd is not None:
            with contextlib.suppress(OSError):
                os.close(pidfd)


def progress_reporter(progress: Callable[[float], None], tstop: float,
                      simulated: Callable[[], float | None]) -> Callable[[], None]:
    """A look that reports the fraction of ``tstop`` simulated so far (never going back)."""
    fraction = 0.0

    def report() -> None:
        nonlocal fraction
        t = simulated()
        fraction = max(fraction, min(max(t / tstop, 0.0), 1.0)) if t is not None else fraction
        progress(fraction)

    return report


def _wait(proc: subprocess.Popen[bytes], timeout: float, tstop: float, out: IO[bytes], err: IO[bytes],
          raw: IO[bytes], progress: Callable[[float], None] | None, limit: float | None,
          resident: float | None) -> int | None:
    """Exit status of ngspice, or None after the timeout; reports progress meanwhile and stops a run that
    outgrows its limits (:func:`~lcchain.spice.processes.outgrown`: its raw file past ``limit``, its output past
    :data:`MAX_LOG_BYTES`, its memory past ``resident``)."""
    report = progress_reporter(progress, tstop, lambda: _simulated_time(err)) if progress is not None else None
    watched = limit is not None or resident is not None

    def look() -> None:
        why = outgrown(proc.pid, "ngspice", printed=(out, err), output=raw, max_output_bytes=limit,
                       max_resident_bytes=resident) if watched else None
        if why is not None:
            kill_group(proc)
            raise SimulationError(why, "")
        if report is not None:  # at every poll, so that a caller can also stop the run from it
            report()

    return wait_watching(proc, timeout, look if (progress is not None or watched) else None,
                         WATCH_INTERVAL if watched else PROGRESS_INTERVAL)


def _run_batch(netlist: str, simulator: Simulator, timeout: float, tstop: float,
               progress: Callable[[float], None] | None, place: _Place, limit: float | None,
               resident: float | None = None, plot: str = "transient", joined: bool = False
               ) -> tuple[dict[str, np.ndarray], str, float]:
    with tempfile.TemporaryFile() as source, tempfile.TemporaryFile() as raw, \
            tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        fd = raw.fileno()
        # ngspice measures nothing in batch mode with -r: a netlist with .meas cards writes its raw file from
        # lcchain's control block instead (lcchain.spice.measure)
        measured = measure_control(require_canonical(netlist), f"/dev/fd/{fd}")
        text = measured if measured is not None else netlist
        source.write(require_canonical(text).encode("utf-8"))  # ngspice splits a file at LF, as the check did
        source.seek(0)
        command = [*place.prefix, simulator.executable, "-n", "-b",
                   *(("-r", f"/dev/fd/{fd}") if measured is None else ())]
        start = time.perf_counter()
        proc = subprocess.Popen(command, cwd=place.cwd, env=place.env, stdin=source, stdout=out, stderr=err,
                                pass_fds=(fd,), start_new_session=True)
        try:
            status = _wait(proc, timeout, tstop, out, err, raw, progress, limit, resident)
        finally:
            if proc.poll() is None:  # timed out, or interrupted: the whole group goes
                kill_group(proc)
        wall = time.perf_counter() - start
        log = (read_all(out) + b"\n" + read_all(err)).decode("utf-8", "replace")
        if status is None:
            raise SimulationError(f"ngspice timed out after {timeout:g} s and was killed", useful_output(log),
                                  "timeout")
        if status != 0:
            raise SimulationError(failure_reason(log, f"ngspice exited with status {status}"), useful_output(log))
        data = read_all(raw)
    if not data:
        raise SimulationError("ngspice wrote no raw file", useful_output(log))
    try:
        columns = read_raw(data, plot, joined=joined)
    except SimulationError as exc:
        raise SimulationError(exc.reason, useful_output(log)) from None
    return columns, log, wall


def _run_shared(netlist: str, simulator: Simulator, timeout: float, tstop: float,
                progress: Callable[[float], None] | None, place: _Place,
                limit: float | None, resident: float | None) -> tuple[dict[str, np.ndarray], str, float]:
    # One call in a child that exits after the run: no progress to report; its memory and output are watched.
    stdout, log, status = call_shared_worker(place.prefix, {"netlist": require_canonical(netlist),
                                                            "library": simulator.executable},
                                             timeout, place.cwd, "run", place.env, limit, resident)
    if limit is not None and len(stdout) > limit:
        raise SimulationError(f"the ngspice shared-library child's vectors grew past {show_bytes(limit)}, the most "
                              "this run may write (its price, within --max-memory)", useful_output(log))
    try:
        meta, arrays = decode_worker_payload(stdout)
    except Exception as exc:  # noqa: BLE001 - a crashed child leaves empty or partial bytes
        raise SimulationError(f"the shared-library child (exit status {status}) returned no result ({exc})",
                              useful_output(log)) from None
    if meta.get("lines") != text_digest(circuit_lines(netlist)):
        raise SimulationError("the shared-library child handed ngspice other lines than the ones lcchain checked",
                              useful_output(log))
    if meta["errors"]:
        raise SimulationError(failure_reason(log, "the ngspice shared library failed: " + "; ".join(meta["errors"])),
                              useful_output(log))
    if status != 0:
        raise SimulationError(failure_reason(log, f"the shared-library child exited with status {status}"),
                              useful_output(log))
    if meta["complex"]:
        raise SimulationError("the transient plot holds complex vectors; lcchain reads real data only",
                              useful_output(log))
    columns = {canonical_vector_name(name): arr for name, arr in zip(meta["names"], arrays, strict=True)}
    return columns, log, float(meta["wall_s"])


def _run_warm(netlist: str, simulator: Simulator, timeout: float, tstop: float,
              progress: Callable[[float], None] | None, place: _Place,
              limit: float | None, resident: float | None) -> tuple[dict[str, np.ndarray], str, float]:
    # This thread's long-lived worker (lcchain.spice.warm); no progress to report: studies send it short runs.
    worker = worker_for(simulator.executable, place.prefix, place.cwd, place.env, resident)
    return worker.run(netlist, timeout, limit, resident)


# --------------------------------------------------------------------------- output checks


#: ngspice's transports, by name: how each runs a netlist (how each is found: lcchain.spice.simulator).
_TransportRun = Callable[[str, Simulator, float, float, Callable[[float], None] | None, _Place, float | None,
                          float | None], tuple[dict[str, np.ndarray], str, float]]
TRANSPORT_RUNS: dict[str, _TransportRun] = {"batch": _run_batch, "shared": _run_shared, "warm": _run_warm}


def _validate(columns: dict[str, np.ndarray], log: str, names: list[str],
              tstop: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    if fatal_lines(log):
        raise SimulationError(failure_reason(log, ""), useful_output(log))
    return validate_columns(columns, log, names, tstop)


def validate_columns(columns: dict[str, np.ndarray], log: str, names: list[str], tstop: float,
                     engine: str = "ngspice") -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The time vector and the requested vectors of a run, checked: points, last time = tstop (within
    :data:`TSTOP_RTOL`), every name present, equal lengths, all finite; read-only float64 arrays.

    Raises
    ------
    SimulationError
        Naming what failed, with the useful end of the engine's output ``log``.
    """
    def fail(reason: str) -> SimulationError:
        return SimulationError(reason, useful_output(log), "failed", engine)

    if "time" not in columns:
        raise fail(f"{engine} returned no time vector (is there a .tran analysis?)")
    time_s = columns["time"]
    if time_s.size == 0:
        raise fail(f"{engine} returned zero time points")
    if not math.isclose(float(time_s[-1]), tstop, rel_tol=TSTOP_RTOL, abs_tol=0.0):
        raise fail(f"the last time point is {float(time_s[-1])!r} s, not tstop = {tstop!r} s")
    if not names:  # nothing named: every vector the engine saved
        names = sorted(key for key in columns if key != "time")
    missing = [name for name in names if name not in columns]
    if missing:
        available = ", ".join(sorted(k for k in columns if k != "time")) or "none"
        raise fail(f"requested vector(s) {', '.join(missing)} not in {engine}'s output (saved: {available}); "
                   "add them to the netlist's .save line")
    found: dict[str, np.ndarray] = {}
    for name in ["time", *names]:
        arr = np.ascontiguousarray(columns[name], dtype=np.float64)
        if arr.shape != time_s.shape:
            raise fail(f"vector {name} has {arr.size} points, time has {time_s.size}")
        if not np.all(np.isfinite(arr)):
            raise fail(f"vector {name} holds non-finite values")
        arr.flags.writeable = False
        found[name] = arr
    return found.pop("time"), found
