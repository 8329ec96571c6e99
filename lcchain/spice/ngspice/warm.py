"""The ``"warm"`` transport: ngspice's shared library loaded once per worker, serving run after run.

An ``ngspice -b`` process costs about 6 ms of CPU before it reads a netlist;
a small circuit (N = 10) then computes in 2 to 3 ms.  A warm worker
(``python -m lcchain.spice.ngspice.warm_worker``, :mod:`ctypes` on ``libngspice.so.0``,
no PySpice) pays the start once and then runs each netlist for what ngspice
computes.  Its results are bit-identical to ``ngspice -b``'s raw files (tested),
so a run's key and digest do not depend on the transport that ran it: studies
choose it by a run's predicted cost (:data:`WARM_BELOW_SECONDS`, measured in
``benchmarks/batch.md``), and ``--transport`` overrides the choice.

Each thread of a process keeps its own worker (:func:`worker_for`), started
on its first run like any child (a session of its own, ``setpriv --pdeathsig
KILL``, ``HOME`` nowhere, in the sandbox for netlists lcchain did not write), and
replaced when it dies, when its memory passes :data:`MAX_WORKER_BYTES` or after
:data:`MAX_WORKER_RUNS` runs.  A crash of ngspice kills the worker, which fails
that run only; a run past its timeout kills the worker (status ``timeout``).

While a run goes the worker is watched as a ``ngspice -b`` process is
(:func:`lcchain.spice.processes.outgrown`, every
:data:`~lcchain.spice.processes.WATCH_INTERVAL` seconds): what ngspice prints
streams to a file of the parent's, and a run whose output passes
:data:`~lcchain.spice.processes.MAX_LOG_BYTES`, or whose worker's resident
memory passes the run's limit, kills the worker and fails with that reason.  A
worker already holding more than :data:`RESTART_SHARE` of a run's memory limit
(memory earlier runs freed but the process kept) is replaced before the run.
:func:`close_workers` ends them all (the executors call it when a study ends,
and on an interrupt, so that nothing keeps running).
"""

from __future__ import annotations

import atexit
import contextlib
import importlib
import json
import os
import select
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import replace
from typing import IO, TYPE_CHECKING, TypeAlias

from ...core.budget import show_bytes
from ...core.errors import SimulationError, SimulatorMissingError
from ..job import Progress, TransportJob
from ..log import failure_reason, useful_output
from ..processes import PACKAGE_ROOT, WATCH_INTERVAL, child_env, kill_group, outgrown, read_all, resident_bytes
from ..sandbox import likely_sandbox
from ..simulator import Simulator, child_launcher
from ..text import canonical_vector_name
from .locate import find_shared_library
from .place import Place, placement

if TYPE_CHECKING:  # the worker's module is the child's: the parent names its frames' types only
    import numpy as np

    from .warm_worker import Hello, RunHeader

__all__ = ["WarmWorker", "run_warm", "worker_for", "close_workers", "warm_simulator", "prestart_workers",
           "WARM_BELOW_SECONDS",
           "MAX_WORKER_BYTES", "MAX_WORKER_RUNS", "RESTART_SHARE"]

#: Runs priced under this (:func:`lcchain.spice.foreign.foreign_price`'s seconds, which are about three times what a
#: run takes) go warm when a study chooses (``--transport auto``): below it the saved start (the sandbox and a new
#: ngspice, about 10 to 20 ms of CPU a run) outweighs the library's slower big runs.  CPU a run (all processes),
#: ``benchmarks/transport_cpu.py``, warm against a process in the sandbox: priced 0.25 s (N = 100) 70 against
#: 81 ms, 0.48 s 152 against 167, 0.77 s 234 against 255, 1.59 s (N = 300) 594 against 545 (benchmarks/batch.md).
WARM_BELOW_SECONDS = 1.0
#: A worker whose resident memory passes this is replaced after its run (the library keeps ~0.6 KiB a run).
MAX_WORKER_BYTES = 512 * 2**20
#: A worker is replaced after this many runs, whatever its memory.
MAX_WORKER_RUNS = 20000
#: Seconds a worker may take to load the library and say hello.
START_TIMEOUT = 60.0
#: A worker that holds more than this share of a run's memory limit before the run starts is replaced first.
RESTART_SHARE = 0.5

_HEADER = struct.Struct("<Q")


class WarmWorker:
    """One worker process serving netlists from ngspice's shared library.

    Parameters
    ----------
    library : str
        Path of ``libngspice.so.0``.
    prefix : tuple of str
        Its command line's prefix (``setpriv``, the sandbox).
    cwd, env
        Its working folder and environment (``HOME`` nowhere; the package on ``PYTHONPATH`` is added here).
    greet : bool
        Wait for its hello (the library loaded, its version) before returning; False: the process is started and
        :meth:`greet` waits for it later, so that several workers start side by side.
    """

    def __init__(self, library: str, prefix: tuple[str, ...], cwd: str, env: dict[str, str],
                 greet: bool = True) -> None:
        env = dict(env)
        env["PYTHONPATH"] = os.pathsep.join(p for p in (PACKAGE_ROOT, env.get("PYTHONPATH")) if p)
        self._err: IO[bytes] = tempfile.TemporaryFile()
        worker = "lcchain.spice.ngspice.warm_worker"
        # -S: no site (the worker needs the standard library and lcchain, which PYTHONPATH names), 10 to 20 ms
        self.proc = subprocess.Popen([*prefix, sys.executable, "-S", "-P", "-m", worker, library], cwd=cwd, env=env,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._err,
                                     start_new_session=True)
        self.runs = 0
        self.rss = 0  # the worker's own, as it said after its last run
        self._wrappers: int | None = None  # setpriv's and bubblewrap's, read once (:meth:`resident`)
        self.alive = True
        self.library = library
        self.version = ""
        if greet:
            self.greet()

    def greet(self) -> str:
        """Wait for the worker's hello (once): the library's version.

        Raises
        ------
        SimulatorMissingError
            The library did not load (the worker is ended).
        """
        if self.version:
            return self.version
        try:
            hello: Hello = json.loads(self._frame(time.monotonic() + START_TIMEOUT, "starting"))
        except BaseException:
            self.close(kill=True)
            raise
        if "error" in hello:
            self.close(kill=True)
            raise SimulatorMissingError(f"ngspice's shared library {self.library} could not be loaded: "
                                        f"{hello['error']}")
        self.version = str(hello["version"])
        return self.version

    # -------------------------------------------------------------- frames
    def _read(self, size: int, deadline: float, what: str, watch: Callable[[], None] | None = None) -> bytes:
        assert self.proc.stdout is not None
        fd = self.proc.stdout.fileno()
        parts: list[bytes] = []
        while size:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(what)
            if not select.select([fd], [], [], min(left, WATCH_INTERVAL) if watch is not None else left)[0]:
                if watch is not None:
                    watch()
                continue
            part = os.read(fd, min(size, 1 << 20))
            if not part:
                raise EOFError(what)
            parts.append(part)
            size -= len(part)
        return b"".join(parts)

    def _frame(self, deadline: float, what: str, watch: Callable[[], None] | None = None) -> bytes:
        (size,) = _HEADER.unpack(self._read(_HEADER.size, deadline, what, watch))
        return self._read(size, deadline, what, watch)

    def resident(self) -> int:
        """The worker's resident memory now (its sandbox and launcher included), bytes: between runs, what it said
        after its last one, plus its launcher's and sandbox's, read from ``/proc`` once (they do not grow).  Asked
        before every run, /proc's walk of the worker's tree cost the driver 0.1 to 0.7 ms a run, CPU taken from
        the runs of a busy machine."""
        if not self.runs:
            return resident_bytes(self.proc.pid)
        if self._wrappers is None:
            self._wrappers = resident_bytes(self.proc.pid, leaves=False)  # all but the worker itself
        return self.rss + self._wrappers

    def _died(self, what: str) -> SimulationError:
        """The worker ended mid-run (ngspice crashed, or was killed): this run fails, the next starts a worker."""
        try:
            status = self.proc.wait(1.0)
        except subprocess.TimeoutExpired:
            status = None
        log = read_all(self._err).decode("utf-8", "replace")
        self.close(kill=True)
        status = self.proc.returncode if status is None else status
        how = (f"killed by {signal.Signals(-status).name}" if status is not None and status < 0
               and -status in signal.Signals._value2member_map_ else f"exit status {status}")
        return SimulationError(f"ngspice's shared library ended its worker while {what} ({how})", useful_output(log))

    # -------------------------------------------------------------- runs
    def run(self, job: TransportJob) -> tuple[dict[str, np.ndarray], str, float]:
        """Run one job's checked text: its vectors by canonical name, ngspice's output and its wall time (s).

        While it runs, what it prints and (with ``job.max_resident_bytes``) the worker's resident memory are
        watched (:func:`lcchain.spice.processes.outgrown`); its vectors may not pass ``job.max_output_bytes``.

        Raises
        ------
        SimulationError
            The library failed or asked to exit, the worker died (this run fails; the worker is replaced on
            the next), the run outlived its timeout (status ``"timeout"``, the worker killed), its output or
            memory outgrew its limits (the worker killed), or its vectors outgrew ``max_output_bytes``.
        """
        assert self.proc.stdin is not None
        _numpy_beside()
        timeout, limit, resident = job.timeout, job.max_output_bytes, job.max_resident_bytes
        data = job.text.encode("utf-8")
        self._err.seek(0)
        self._err.truncate()  # this run's output only (the worker writes at the offset the parent shares)
        deadline = time.monotonic() + timeout

        def look() -> None:
            why = outgrown(self.proc.pid, "ngspice's warm worker", printed=(self._err,), max_output_bytes=limit,
                           max_resident_bytes=resident)
            if why is not None:
                log = read_all(self._err).decode("utf-8", "replace")
                self.close(kill=True)
                raise SimulationError(why, useful_output(log))

        watch = look if limit is not None or resident is not None else None
        try:
            self.proc.stdin.write(_HEADER.pack(len(data)) + data)
            self.proc.stdin.flush()
            header: RunHeader = json.loads(self._frame(deadline, "running", watch))
            size = 8 * sum(int(length) for length in header["lengths"])
            if limit is not None and size > limit:  # not read at all: the worker goes with it
                self.close(kill=True)
                raise SimulationError(f"ngspice's vectors grew past {show_bytes(limit)}, the most this run may "
                                      "write (its price, within --max-memory)", "")
            values = self._frame(deadline, "sending the vectors", watch)
        except TimeoutError:
            self.close(kill=True)
            raise SimulationError(f"ngspice timed out after {timeout:g} s and its warm worker was killed", "",
                                  "timeout") from None
        except (EOFError, BrokenPipeError):
            raise self._died("running this netlist") from None
        except BaseException:  # interrupted mid-run, or stopped by its limits: the worker goes with it
            self.close(kill=True)
            raise
        self.runs += 1
        self.rss = int(header["rss"])
        log = read_all(self._err).decode("utf-8", "replace")
        if header["exit"] is not None:
            self.close(kill=True)
            raise SimulationError(failure_reason(log, f"ngspice exited with status {header['exit']}"),
                                  useful_output(log))
        if header.get("lines") != job.lines:  # the worker split the text other than the check: run nothing of it
            self.close(kill=True)
            raise SimulationError("the warm worker handed ngspice other lines than the ones lcchain checked", "")
        if header["errors"]:
            raise SimulationError(failure_reason(log, "the ngspice shared library failed: "
                                                 + "; ".join(header["errors"])), useful_output(log))
        import numpy as np  # loaded while the first run computed (_numpy_beside)

        columns: dict[str, np.ndarray] = {}
        offset = 0
        for name, length in zip(header["names"], header["lengths"], strict=True):
            columns[canonical_vector_name(name)] = np.frombuffer(values, np.float64, length, offset)
            offset += 8 * length
        return columns, log, float(header["wall_s"])

    @property
    def spent(self) -> bool:
        """Past its memory or run bound: replaced before the next run."""
        return self.rss > MAX_WORKER_BYTES or self.runs >= MAX_WORKER_RUNS

    def close(self, kill: bool = False) -> None:
        """End the worker: closing its input lets it exit by itself; ``kill`` (or a worker that does not exit
        within a second) kills its process group."""
        if not self.alive:
            return
        self._hang_up()
        self._end(kill)

    def _hang_up(self) -> None:
        """Close the worker's input: it ends its ngspice and exits (:meth:`_end` waits for it)."""
        self.alive = False
        with contextlib.suppress(OSError):
            assert self.proc.stdin is not None
            self.proc.stdin.close()

    def _end(self, kill: bool) -> None:
        if not kill:
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.proc.wait(1.0)
        if self.proc.poll() is None:
            kill_group(self.proc)
        with contextlib.suppress(OSError):
            assert self.proc.stdout is not None
            self.proc.stdout.close()
        self._err.close()
        with _lock:
            _workers.discard(self)


# ------------------------------------------------------------------ one worker per thread
_lock = threading.Lock()
#: A worker's library, placement prefix and folder: workers of one key are interchangeable.
WorkerKey: TypeAlias = tuple[str, tuple[str, ...], str]
_workers: set[WarmWorker] = set()
#: The workers :func:`warm_simulator` started (and checked the library's version with), by key, until threads take
#: them over, one each.
_spare: dict[WorkerKey, list[WarmWorker]] = {}
_local = threading.local()
#: The workers :func:`prestart_workers` started before the engine was found, by key: :func:`warm_simulator` adopts
#: those under the key it finds, and ends the others.
_guessed: dict[WorkerKey, list[WarmWorker]] = {}
_numpy_loader: threading.Thread | None = None


def _numpy_beside() -> None:
    """Import numpy in a thread of its own, once, as the first run is sent: its import (50 ms idle, 100 ms on a busy
    machine) then overlaps ngspice's run instead of delaying a batch's start (nothing before the first run needs
    it: tests/test_imports.py), and the run's reply finds it loaded (or waits on the import's lock)."""
    global _numpy_loader
    with _lock:
        if _numpy_loader is not None or "numpy" in sys.modules:
            return
        _numpy_loader = threading.Thread(target=importlib.import_module, args=("numpy",), name="lcchain-numpy")
    _numpy_loader.start()


def worker_for(library: str, prefix: tuple[str, ...], cwd: str, env: dict[str, str],
               resident: float | None = None) -> WarmWorker:
    """This thread's worker for that library and placement: started on first use, replaced when dead or spent,
    or (before a run whose memory limit is ``resident`` bytes) when it already holds more than
    :data:`RESTART_SHARE` of it."""
    key = (library, prefix, cwd)
    mine: dict[WorkerKey, WarmWorker] = _local.__dict__.setdefault("workers", {})
    worker = mine.get(key)
    if worker is not None and (not worker.alive or worker.spent or (
            resident is not None and worker.runs and worker.resident() > RESTART_SHARE * resident)):
        worker.close()
        worker = None
    if worker is None:
        with _lock:
            spares = _spare.get(key, [])
            worker = spares.pop(0) if spares else None
        if worker is None or not worker.alive:
            worker = WarmWorker(library, prefix, cwd, env)
            with _lock:
                _workers.add(worker)
        mine[key] = worker
    return worker


def close_workers(kill: bool = False) -> None:
    """End every warm worker of this process (every thread's)."""
    with _lock:
        workers = [worker for worker in _workers if worker.alive]
        _spare.clear()
        _guessed.clear()
    for worker in workers:  # every worker told first, then each waited for: they end side by side
        worker._hang_up()
    for worker in workers:
        worker._end(kill)


atexit.register(close_workers, True)


def prestart_workers(workers: int) -> None:
    """Start ``workers`` workers where a batch's foreign netlists will run warm if the sandbox works here, before
    ngspice is found: their start (20 to 40 ms) then overlaps ``ngspice -v`` and the sandbox's trial run instead
    of following them.  A guess that proves nothing: :func:`warm_simulator` adopts them only under the placement
    the found engine gives (same library, same sandbox), checks their version there, and ends them otherwise.
    Nothing is started without a shared library or bubblewrap."""
    if workers < 1:
        return
    try:
        library = find_shared_library()
    except SimulatorMissingError:
        return
    sandbox = likely_sandbox()
    if not sandbox.available:
        return
    guess = Simulator("warm", library, "", child_launcher(), sandbox)
    with placement(guess, True, None) as place:
        started = [WarmWorker(library, place.prefix, place.cwd, place.env, greet=False) for _ in range(workers)]
        key = (library, place.prefix, place.cwd)
    with _lock:
        _workers.update(started)
        _guessed.setdefault(key, []).extend(started)


def _adopt_guessed(key: WorkerKey | None) -> list[WarmWorker]:
    """The workers :func:`prestart_workers` started under ``key`` (not yet greeted); the others ended (all of them
    for None)."""
    with _lock:
        adopted = _guessed.pop(key, []) if key is not None else []
        others = [worker for workers in _guessed.values() for worker in workers]
        _guessed.clear()
    for worker in others:
        worker.close(kill=True)
    return [worker for worker in adopted if worker.alive]


def warm_simulator(simulator: Simulator, workers: int = 1) -> Simulator:
    """The warm transport for a batch simulator: the shared library, checked to be the same ngspice version
    (so that keys and results do not depend on the transport).

    Where the sandbox works, the workers that checked it are kept, ``workers`` of them (started side by side): the
    first threads to run a netlist lcchain did not write take them over instead of starting their own (a worker's
    start, 40 to 70 ms, off each thread's path to its first run).  Spares already kept and checked count: a study
    that started them while it planned (:class:`lcchain.studies.executors.EngineStart`) finds them here.

    Raises
    ------
    SimulatorMissingError
        No shared library, or one of another version than ``simulator``'s ngspice.
    """
    library = find_shared_library()
    warm = replace(simulator, backend="warm", executable=library)
    if not simulator.sandbox.available:
        _adopt_guessed(None)  # no sandbox: every worker started in it on a guess ended
        worker = WarmWorker(library, simulator.launcher, "/", child_env())
        worker.close()
        _same_version(worker, simulator)
        return warm
    # checked where a netlist lcchain did not write runs warm (in the sandbox, a placement that makes no folder)
    with placement(warm, True, None) as place:
        key = (library, place.prefix, place.cwd)
        with _lock:
            kept = [worker for worker in _spare.get(key, []) if worker.alive and worker.version == simulator.version]
        guessed = _adopt_guessed(key)
        wanted = max(0, workers - len(kept)) if kept else max(1, workers)
        for worker in guessed[wanted:]:
            worker.close(kill=True)
        started = guessed[:wanted]
        started += [WarmWorker(library, place.prefix, place.cwd, place.env, greet=False)
                    for _ in range(wanted - len(started))]
    with _lock:
        _workers.update(started)
    try:
        for worker in started:
            worker.greet()
            _same_version(worker, simulator)
    except BaseException:
        for worker in started:
            worker.close(kill=True)
        raise
    with _lock:
        _spare[key] = [*(worker for worker in _spare.get(key, []) if worker.alive), *started]
    return warm


def _same_version(worker: WarmWorker, simulator: Simulator) -> None:
    if worker.version != simulator.version:
        raise SimulatorMissingError(f"ngspice's shared library {worker.library} is version {worker.version}, the "
                                    f"ngspice program {simulator.version}: the warm transport would change results")


def run_warm(job: TransportJob, simulator: Simulator, place: Place,
             progress: Progress | None = None) -> tuple[dict[str, np.ndarray], str, float]:
    # This thread's long-lived worker (worker_for); no progress to report: studies send it short runs.
    worker = worker_for(simulator.executable, place.prefix, place.cwd, place.env, job.max_resident_bytes)
    return worker.run(job)

