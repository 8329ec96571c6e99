"""Where a study's runs execute: in this process, in a process pool, or on a Dask cluster.

Every executor takes groups of (index, spec) and yields (index, record)
pairs as groups finish; the driver stores them and reads them back in task
order, so results are bit-identical whichever executor ran them (theory is
computed under a fixed BLAS thread limit, and ngspice is deterministic).

* ``serial``: one run after the other, here.
* ``process`` (the default): a stdlib process pool with the spawn start
  method, one worker per core; for runs with no theory to compute (a batch
  of netlists, whose work is all in the simulator's own processes) threads of
  this process drive one simulator each instead, with no pool to start.  Each worker ignores Ctrl-C (the driver
  handles it), and on Linux asks the kernel to kill it when the driver dies
  (``prctl(PR_SET_PDEATHSIG, SIGKILL)``, checked against a race at start);
  its ngspice children die with it the same way.  On an interrupt the driver
  kills the pool's processes rather than waiting for them.
* ``dask``: a ``distributed.LocalCluster`` on 127.0.0.1 (one single-threaded
  process per worker), or an existing cluster at ``--scheduler``.  Dask is
  imported here only, and only when asked for (``pip install 'lcchain[dask]'``).
  Dask reschedules the tasks of a worker that dies.  The local cluster keeps
  its scratch space in a folder of its own (beside the store) removed once it
  has closed, or by a watcher when the driver is killed outright; its
  workers ignore Ctrl-C (the driver closes them), and their logs stay quiet
  unless ``verbose``.

:func:`open_executor` starts an executor (a Dask cluster is started, or
reached, there) before a study writes anything, so that a scheduler that
cannot be reached leaves no store behind; :func:`check_executor` checks the
options before that, without a network.

Short runs are grouped so that each task sent is worth its overhead
(:attr:`Executor.min_task_seconds`), while keeping several tasks per worker for
balance and progress.

The transport of each run (:func:`choose_transports`): short ngspice runs go
to warm shared-library workers (:mod:`lcchain.spice.ngspice.warm`), one per worker
thread or process, where a new ``ngspice -b`` process would cost more than the
run; their keys and results are those of ``ngspice -b`` (bit-identical).
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import os
import queue
import sys
import threading
import time
import urllib.parse
from collections.abc import Callable, Container, Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, TypeAlias

from ..core.budget import (
    DASK_SCHEDULER_BYTES,
    DASK_START_SECONDS,
    DASK_WORKER_BYTES,
    INTERPRETER_SECONDS,
    POOL_START_SECONDS,
    POOL_TRACKER_BYTES,
    POOL_WORKER_BYTES,
)
from ..core.errors import ExtraMissingError, LcchainError, ParameterError, SimulatorMissingError
from ..core.registry import Registry
from ..core.types import EXECUTORS, TRANSPORT_CHOICES, Backend, ExecutorName, TransportChoice
from ..runs.spec import RunSpec
from ..spice.engines import engine_named, find_engine
from ..spice.scratch import scratch_folder
from ..spice.simulator import Simulator

if TYPE_CHECKING:  # multiprocessing's pool takes ~10 ms to import, which a batch never uses; Dask is optional
    from concurrent.futures import ProcessPoolExecutor

    from distributed import Client

    from ..runs.execute import RunRecord  # imported where runs execute: the engine starts before numpy loads
    from ..spice.engine import Engine

__all__ = ["ExecutorName", "EXECUTORS", "ExecutorTraits", "EXECUTOR_TRAITS", "DEFAULT_EXECUTOR",
           "SCHEDULER_SCHEMES", "run_groups", "open_executor",
           "check_executor", "group_tasks", "default_workers", "execute_group", "Transports", "choose_transports",
           "WARM_MIN_RUNS_PER_WORKER", "choose_transports_by", "RunMask", "RunStream", "ExecutorCost",
           "executor_cost", "Executor", "RunnerFactory", "EngineStart", "SWITCH_SECONDS", "prompt_handoffs"]

@dataclass(frozen=True)
class ExecutorTraits:
    """What an executor is, as a study asks it (what it does and what it costs are the rest of its
    :class:`Executor`).

    Attributes
    ----------
    parallel : bool
        Its runs go side by side in workers; otherwise one after the other in this process, as one worker.
    remote : bool
        It may reach workers elsewhere (``--scheduler ADDRESS``).
    """

    parallel: bool
    remote: bool


#: The executor a study uses unless told otherwise; the serial executor asked for several workers uses it too.
DEFAULT_EXECUTOR = "process"
#: The protocols a Dask scheduler address may name (``HOST:PORT`` alone is ``tcp``).
SCHEDULER_SCHEMES = ("tcp", "tls")
#: Seconds to reach a Dask scheduler before it counts as unreachable.
SCHEDULER_TIMEOUT = 30.0
#: Tasks per worker aimed at, at least, for balance and progress.
TASKS_PER_WORKER = 4

log = logging.getLogger("lcchain")

#: Runs a thread of a threaded study has waiting beside the one it runs (:func:`_threaded`).
RUNS_AHEAD = 4

#: The interpreter's thread switch interval (s) while a study's driver threads wait on its children
#: (:func:`prompt_handoffs`).
SWITCH_SECONDS = 1e-4

#: Short runs a study sends to warm workers only when there are at least this many per worker: a worker's start
#: (about 70 ms) is then paid back several times over.
WARM_MIN_RUNS_PER_WORKER = 10

Group = list[tuple[int, RunSpec]]


@dataclass(frozen=True)
class Transports:
    """How a study's runs are carried: which go to warm shared-library workers (and the simulator that runs them
    there), and the study's deadline.

    A run's key and results do not depend on it (the warm transport is checked to be the same ngspice).

    Attributes
    ----------
    warm : Simulator, optional
    runs : container of int
        The runs that go warm (a :class:`RunMask` for a streamed batch: a byte a run).
    deadline : float, optional
        The wall-clock time (``time.time()``) the study's time budget ends at: no run starts after it, a run
        started before it is stopped at it, and neither is returned (they stay pending in the store, for the same
        command to run).
    """

    warm: Simulator | None = None
    runs: Container[int] = frozenset()
    deadline: float | None = None

    def simulator_for(self, index: int, simulator: Simulator) -> Simulator:
        """The simulator run ``index`` uses: warm when chosen and its library is on this machine."""
        if self.warm is not None and index in self.runs and os.path.exists(self.warm.executable):
            return self.warm
        return simulator


#: What an open executor is: groups (and their transports) in, each group's (index, record) pairs out as it
#: finishes.
Runner: TypeAlias = "Callable[[Iterable[Group], Transports], Iterator[list[tuple[int, RunRecord]]]]"


@dataclass(frozen=True)
class _TransportChoice:
    """What a ``--transport`` choice asks of a study: whether runs may go warm, chosen by their predicted cost,
    and whether a missing warm transport is an error."""

    warm: bool
    by_cost: bool
    required: bool


_TRANSPORT_CHOICES: dict[str, _TransportChoice] = {
    "auto": _TransportChoice(warm=True, by_cost=True, required=False),
    "process": _TransportChoice(warm=False, by_cost=False, required=False),
    "warm": _TransportChoice(warm=True, by_cost=False, required=True)}


def check_transport(transport: str) -> TransportChoice:
    if transport not in TRANSPORT_CHOICES:
        raise ParameterError("--transport", transport, " | ".join(TRANSPORT_CHOICES))
    return transport


def choose_transports(items: Sequence[tuple[int, RunSpec, float]], simulator: Simulator, workers: int,
                      transport: str = "auto") -> Transports:
    """The runs that go to the engine's warm transport (:meth:`lcchain.spice.engine.Engine.warm`: ngspice's shared
    library, :mod:`lcchain.spice.ngspice.warm`).

    ``"process"``: none. ``"warm"``: every run that can (runs of the study's engine on its default transport, of
    an analysis its warm transport runs (:attr:`~lcchain.spice.engine.Engine.warm_analyses`), of netlists checked
    by the allow-list). ``"auto"``: those predicted under the engine's
    :attr:`~lcchain.spice.engine.Engine.warm_below_seconds`, when there are at least
    :data:`WARM_MIN_RUNS_PER_WORKER` per worker and the warm transport is here (for ngspice: a shared library of
    this ngspice's version; otherwise every run starts its own process, as before).

    Raises
    ------
    ParameterError
        An unknown ``transport``.
    SimulatorMissingError
        ``"warm"`` asked for, and no shared library of this ngspice's version.
    """
    def able(engine: Engine, by_cost: bool) -> tuple[frozenset[int], int]:
        chosen = frozenset(index for index, spec, seconds in items
                           if spec.engine == engine.name and not spec.trusted and spec.analysis in engine.warm_analyses
                           and (not by_cost or seconds < engine.warm_below_seconds))
        return chosen, len(chosen)

    return choose_transports_by(able, simulator, workers, transport)


def choose_transports_by(able: Callable[[Engine, bool], tuple[Container[int], int]], simulator: Simulator,
                         workers: int, transport: str = "auto") -> Transports:
    """:func:`choose_transports` for runs that are not all at hand (a streamed batch's): ``able(engine, by_cost)``
    gives the runs the engine's warm transport may carry (only those predicted under its
    :attr:`~lcchain.spice.engine.Engine.warm_below_seconds` when ``by_cost``) and their number."""
    choice = _TRANSPORT_CHOICES[check_transport(transport)]
    engine = engine_named(simulator.engine, "simulator.engine")
    if not choice.warm or not engine.warm_below_seconds or simulator.backend != engine.default_transport:
        return Transports()
    runs, count = able(engine, choice.by_cost)
    if choice.by_cost and count < WARM_MIN_RUNS_PER_WORKER * workers:
        return Transports()
    if not count:
        return Transports()
    try:
        warm = engine.warm(simulator, workers)
    except SimulatorMissingError as error:
        if choice.required:
            raise SimulatorMissingError(f"--transport {transport}: {error}") from None
        log.info("warm transport not used: %s", error)
        return Transports()
    return Transports(warm, runs)


class RunMask:
    """Runs chosen by index, a byte a run (a frozenset of a batch's 100,000 indices held 6 MB for the whole
    batch)."""

    __slots__ = ("_flags",)

    def __init__(self, flags: bytes) -> None:
        self._flags = bytes(flags)

    def __contains__(self, index: object) -> bool:
        return isinstance(index, int) and 0 <= index < len(self._flags) and self._flags[index] == 1

    def __reduce__(self) -> tuple[type[RunMask], tuple[bytes]]:
        return RunMask, (self._flags,)


class RunStream:
    """A batch's runs made as an executor asks for them (each a group of one), none with a theory to compute:
    an executor holds only those it has started or queued (:data:`RUNS_AHEAD` a thread)."""

    light = True

    def __init__(self, runs: Iterable[tuple[int, RunSpec]]) -> None:
        self._runs = iter(runs)

    def __iter__(self) -> Iterator[Group]:
        return ([run] for run in self._runs)


@contextlib.contextmanager
def prompt_handoffs() -> Iterator[None]:
    """The interpreter's thread switch interval at most :data:`SWITCH_SECONDS` within the block (restored after).

    A driver's thread woken by a child (a warm worker's reply, ``ngspice -v``'s exit, a worker's hello) needs the
    GIL to hand the child its next run; with Python's 5 ms default it waited for the main thread's slice (the plan,
    the store) to end, up to 5 ms at every step, while a core stood idle.  At 0.1 ms a batch of 40 distinct
    N = 100 netlists took 3 % less wall time (``benchmarks/batch.md``); smaller intervals gained nothing more.
    """
    with _HANDOFFS.lock:  # one setting for the process: the blocks of two threads may end in any order
        if not _HANDOFFS.blocks:
            _HANDOFFS.found = sys.getswitchinterval()
            sys.setswitchinterval(min(_HANDOFFS.found, SWITCH_SECONDS))
        _HANDOFFS.blocks += 1
    try:
        yield
    finally:
        with _HANDOFFS.lock:
            _HANDOFFS.blocks -= 1
            if not _HANDOFFS.blocks:  # the last block out restores what the first one in found
                sys.setswitchinterval(_HANDOFFS.found)


class _Handoffs:
    """:func:`prompt_handoffs`' state: the blocks inside, and the interval the first of them found."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.blocks = 0
        self.found = 0.0


_HANDOFFS = _Handoffs()


class EngineStart:
    """A study's engine found, and its warm workers started, in a thread of their own while the driver plans.

    Before a study's first run its engine must be found (``ngspice -v``, the sandbox's trial run) and, when its
    runs go warm, the shared library's workers started and their version checked: about 0.1 s of waiting, which
    the plan (reading, checking and pricing every netlist: CPU in this thread) can hide.  Workers are started
    (:meth:`lcchain.spice.engine.Engine.warm`, one per thread that will run) only when the study's runs will
    likely go warm: ``transport`` not ``"process"``, an executor whose runs go in this process's threads, and, for
    ``"auto"``, at least :data:`WARM_MIN_RUNS_PER_WORKER` runs a worker; :func:`choose_transports` then finds them
    started.  A worker started for nothing (every run priced long) is ended with the study.

    Use it as a context manager around the plan and the study: :meth:`simulator` waits for the engine (and raises
    what finding it raised); a block left by an exception (a refused plan, an interrupt) ends the workers.
    """

    def __init__(self, engine: str, backend: Backend, *, runs: int, workers: int, executor: str | Executor,
                 transport: str) -> None:
        threads = EXECUTOR_TRAITS.accept("executor", executor).threads_here(workers)
        choice = _TRANSPORT_CHOICES.get(transport)
        enough = runs >= (WARM_MIN_RUNS_PER_WORKER * threads if choice is not None and choice.by_cost else 1)
        self._spares = threads if choice is not None and choice.warm and threads and enough else 0
        self._engine, self._backend = engine, backend
        self._found: list[Simulator] = []
        self._failed: list[BaseException] = []
        self._prestarted: list[Engine] = []
        self._ready, self._done = threading.Event(), threading.Event()
        self._thread = threading.Thread(target=self._start, name="lcchain-engine-start", daemon=True)
        self._handoffs = contextlib.ExitStack()

    def _start(self) -> None:
        try:
            self._find()
        finally:
            self._ready.set()
        # The workers die with the thread that started them (``setpriv --pdeathsig`` is the parent *thread*'s
        # death): this one waits for the study's end.
        self._done.wait()

    def _find(self) -> None:
        try:
            named = engine_named(self._engine)
            if self._spares and named.warm_below_seconds and self._backend == named.default_transport:
                self._prestarted.append(named)
                named.prestart(self._spares)  # the workers start beside ngspice -v and the sandbox's trial
            simulator = find_engine(self._engine, self._backend)
            self._found.append(simulator)
            engine = engine_named(simulator.engine, "simulator.engine")
            if self._spares and engine.warm_below_seconds and simulator.backend == engine.default_transport:
                engine.warm(simulator, self._spares)
        except SimulatorMissingError as error:
            if not self._found:  # no warm transport is no error: the runs start their own processes
                self._failed.append(error)
        except BaseException as error:  # raised where the driver asks for the engine
            self._failed.append(error)

    def __enter__(self) -> EngineStart:
        self._handoffs.enter_context(prompt_handoffs())  # the engine's thread steps on as each child answers
        try:
            self._thread.start()
        except BaseException:
            self._handoffs.close()
            raise
        return self

    def __exit__(self, kind: object, error: object, traceback: object) -> None:
        try:
            self._ready.wait()
            if kind is not None:  # what was started for the study ends with it (an engine not found, a refused plan)
                ended = [engine_named(self._found[0].engine, "simulator.engine")] if self._found else []
                for engine in {id(engine): engine for engine in (*ended, *self._prestarted)}.values():
                    engine.release(kill=True)
            self._done.set()
            self._thread.join()
        finally:
            self._handoffs.close()

    def simulator(self, while_waiting: Callable[[], object] | None = None) -> Simulator:
        """The engine, found (waits for it).  ``while_waiting``, when the engine is not found yet, is called first:
        work the caller does next anyway (loading the runs' modules), done while the engine starts.

        Raises
        ------
        SimulatorMissingError, ParameterError
            As :func:`lcchain.spice.engines.find_engine`.
        """
        if while_waiting is not None and not self._ready.is_set():
            while_waiting()
        self._ready.wait()
        if self._failed:
            raise self._failed[0]
        return self._found[0]


def check_scheduler(address: str) -> str:
    """A Dask scheduler's address as ``SCHEME://HOST:PORT`` (``HOST:PORT`` is tcp), or a ParameterError."""
    allowed = f"the address of a Dask scheduler, [{' | '.join(SCHEDULER_SCHEMES)}://]HOST:PORT"
    text = address if "://" in address else f"tcp://{address}"
    try:
        parts = urllib.parse.urlsplit(text)
        port, host = parts.port, parts.hostname
    except ValueError as error:
        raise ParameterError("--scheduler", address, f"{allowed} ({error})") from None
    if parts.scheme not in SCHEDULER_SCHEMES:
        raise ParameterError("--scheduler", address, f"{allowed} (not {parts.scheme}://)")
    if not host or port is None or not 0 < port < 65536 or parts.path or parts.query or parts.fragment \
            or parts.username is not None or not address.isprintable():
        raise ParameterError("--scheduler", address, allowed)
    return text


def check_executor(executor: str | Executor, workers: int | None = None, scheduler: str | None = None) -> None:
    """Refuse an unknown executor, workers below 1, or a scheduler that is no address or not for Dask."""
    EXECUTOR_TRAITS.accept("--executor", executor)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ParameterError("--workers", workers, "an integer >= 1")
    if scheduler is not None:
        if not EXECUTOR_TRAITS.accept("--executor", executor).remote:
            remote = " | ".join(name for name, traits in EXECUTOR_TRAITS.items() if traits.remote)
            raise ParameterError("--scheduler", scheduler, f"nothing unless --executor {remote}")
        check_scheduler(scheduler)


def default_workers() -> int:
    """One worker per core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def group_tasks(items: Sequence[tuple[int, RunSpec, float]], executor: str | Executor, workers: int) -> list[Group]:
    """Consecutive runs grouped until a group is worth its executor's :attr:`Executor.min_task_seconds`, keeping
    enough groups; the longest groups first (stable among equals), so that the last group to finish is a short
    one: a sweep of N = 300 to 410 in plan order ended on its longest run, with the other worker idle."""
    chosen = EXECUTOR_TRAITS.accept("--executor", executor)
    least = chosen.min_task_seconds
    if not chosen.parallel or not items:
        return [[(index, spec)] for index, spec, _ in items]
    total = sum(seconds for _, _, seconds in items)
    # worth the minimum, unless that leaves fewer than TASKS_PER_WORKER groups per worker
    target = min(least, total / (TASKS_PER_WORKER * workers))
    groups: list[tuple[float, Group]] = []
    current: Group = []
    held = 0.0
    for index, spec, seconds in items:
        current.append((index, spec))
        held += seconds
        if held >= target:
            groups.append((held, current))
            current, held = [], 0.0
    if current:
        groups.append((held, current))
    return [group for _, group in sorted(groups, key=lambda g: -g[0])]


def execute_group(group: Group, simulator: Simulator, keep_signals: bool = False,
                  transports: Transports = Transports(),
                  progress: Callable[[float], None] | None = None) -> list[tuple[int, RunRecord]]:
    """Run one group where it lands (a pool worker, a Dask worker, a thread): the unit of work, run by run.

    A worker whose engine is elsewhere finds its own; one whose engine has
    another version fails its runs (their keys would not be the study's).
    """
    from ..runs.execute import RunRecord, execute

    if not os.path.exists(simulator.executable):
        engine = engine_named(simulator.engine, "simulator.engine")
        found = find_engine(engine.name, engine.transport_for(simulator.backend))
        if found.version != simulator.version:
            reason = f"this worker's {simulator.engine} is {found.version}, the study's is {simulator.version}"
            return [(index, RunRecord(key=spec.key(simulator.version), status="failed", reason=reason,
                                      engine=simulator.engine, engine_version=found.version, label=spec.label))
                    for index, spec in group]
        simulator = found
    out = []
    for index, spec in group:
        cut = False  # the study's deadline, not the run's own timeout, bounds this run
        if transports.deadline is not None:
            left = transports.deadline - time.time()
            if left <= 0:
                continue  # the study's time is spent: the run stays pending
            if left < spec.timeout:
                spec, cut = replace(spec, timeout=left), True
        record = execute(spec, transports.simulator_for(index, simulator), progress=progress)
        if cut and record.status == "timeout":
            continue  # stopped by the study's deadline: pending, not the run's own failure
        out.append((index, record if keep_signals else replace(record, signals=None)))
    return out


# ------------------------------------------------------------------ process pool
#: Times a broken process pool (a worker killed, by the kernel or by hand) is rebuilt before the study stops.
POOL_RESTARTS = 3


def _process(groups: Iterable[Group], simulator: Simulator, workers: int, keep_signals: bool,
             transports: Transports, started: ProcessPoolExecutor | None = None
             ) -> Iterator[list[tuple[int, RunRecord]]]:
    """A spawn process pool (``started``: one whose workers started before, while the study was planned); a pool
    broken by a dead worker is rebuilt and the unfinished groups resubmitted."""
    # here, not at the top: multiprocessing and its pool take ~10 ms to import, which a serial batch never uses
    from concurrent.futures.process import BrokenProcessPool

    from .pools import kill_pool, spawn_pool

    left = dict(enumerate(groups))
    for attempt in range(POOL_RESTARTS + 1):
        pool = started if attempt == 0 and started is not None else spawn_pool(workers)
        finished = False
        try:
            pending = {pool.submit(execute_group, group, simulator, keep_signals, transports): number
                       for number, group in left.items()}
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    number = pending.pop(future)
                    result = future.result()
                    del left[number]
                    yield result
            finished = True
            return
        except BrokenProcessPool:
            if attempt == POOL_RESTARTS:
                message = (f"the process pool broke {attempt + 1} times (a worker was killed: out of memory?); "
                           "every finished run is in the store, run the same command to resume")
                raise LcchainError(message) from None
            log.warning("a pool worker died; restarting the pool for the %d unfinished groups", len(left))
        finally:
            if finished:
                if pool is not started:  # a started pool is its owner's to shut down
                    pool.shutdown(wait=True)
            else:  # interrupted, or broken: nothing may keep running
                kill_pool(pool)


# ------------------------------------------------------------------ threads
class _Stopped(BaseException):
    """Raised in a worker thread once its study stopped: past every ``except Exception``, and never seen."""


def _light(groups: Iterable[Group]) -> bool:
    """Runs with no theory to compute: lcchain's work on each is reading and checking what the simulator wrote."""
    if isinstance(groups, RunStream):
        return groups.light
    return all(spec.theory is None for group in groups for _, spec in group)


def _threaded(groups: Iterable[Group], simulator: Simulator, workers: int, keep_signals: bool,
              transports: Transports) -> Iterator[list[tuple[int, RunRecord]]]:
    """Threads of this process, each driving one simulator child at a time: no pool to start or feed.

    Each run is its own task (a thread costs microseconds per task); each finished task is put on a queue as it
    finishes, and whatever the queue holds is yielded together (stored in one transaction).  Waiting on the
    queue costs the same whatever the batch's size: ``concurrent.futures.wait`` on the pending tasks locked and
    scanned every one of them each time, a cost a run that grew with the batch.  At most
    :data:`RUNS_AHEAD` runs a thread wait their turn, the others are handed over as runs finish (in the groups'
    order): a submitted run holds about 2 KB until it is done, 200 MB for 100,000.  On the way out (the end, an
    error, an interrupt) no new run starts, a running batch child is killed at its next look (its progress callback
    raises, within :data:`~lcchain.spice.processes.PROGRESS_INTERVAL`), warm workers are killed, and the threads
    are joined: nothing keeps running.
    """
    stop = threading.Event()

    def cancel(fraction: float) -> None:
        if stop.is_set():
            raise _Stopped

    def one(index: int, spec: RunSpec) -> list[tuple[int, RunRecord]]:
        if stop.is_set():
            raise _Stopped
        return execute_group([(index, spec)], simulator, keep_signals, transports, cancel)

    pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="lcchain-run")
    finished = False
    done: queue.SimpleQueue[Future[list[tuple[int, RunRecord]]]] = queue.SimpleQueue()
    runs = ((index, spec) for group in groups for index, spec in group)

    def hand_over(count: int) -> int:
        handed = 0
        for index, spec in itertools.islice(runs, count):
            pool.submit(one, index, spec).add_done_callback(done.put)
            handed += 1
        return handed

    with prompt_handoffs():  # a thread whose worker answered hands it the next run at once
        try:
            left = hand_over((RUNS_AHEAD + 1) * workers)
            while left:
                ready = [done.get()]
                with contextlib.suppress(queue.Empty):
                    while True:
                        ready.append(done.get_nowait())
                left += hand_over(len(ready)) - len(ready)
                yield [pair for future in ready for pair in future.result()]  # stored together: one disk sync
            finished = True
        finally:
            stop.set()
            if not finished:
                engine_named(simulator.engine, "simulator.engine").release(kill=True)
            pool.shutdown(wait=True, cancel_futures=True)


# ------------------------------------------------------------------ Dask
@contextlib.contextmanager
def _dask(workers: int, scheduler: str | None, verbose: bool, scratch: str | None = None) -> Iterator[Client]:
    """A Dask client: on a LocalCluster whose scratch space is removed after it closed, or on ``scheduler``.

    The scratch space is a folder of the driver's own (:func:`lcchain.spice.scratch.scratch_folder`) in
    ``scratch`` (the store's folder; default the temporary folder), watched: if the driver is killed outright,
    a watcher removes it, and the next start removes any a dead driver left.  The workers' temporary folder is
    inside it, so what a killed worker leaves (a simulator's folder) goes with it.
    """
    try:
        import dask
        from distributed import Client, LocalCluster
    except ImportError:
        raise ExtraMissingError("dask", "dask", "the dask executor") from None
    from .pools import interrupts_held

    quiet = logging.INFO if verbose else logging.CRITICAL
    with contextlib.ExitStack() as stack:
        if scheduler is None:
            folder = stack.enter_context(scratch_folder("dask", scratch, watch=True, hidden=scratch is not None))
            temporary = folder / "tmp"
            temporary.mkdir()
            # the scheduler takes its scratch space from Dask's configuration, the workers from local_directory
            stack.enter_context(dask.config.set({"temporary-directory": str(folder)}))
            with interrupts_held():
                cluster = stack.enter_context(LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                                           host="127.0.0.1", dashboard_address=None,
                                                           silence_logs=quiet, local_directory=str(folder),
                                                           env={"TMPDIR": str(temporary)}))
                client = stack.enter_context(Client(cluster))
        else:
            try:
                client = stack.enter_context(Client(check_scheduler(scheduler), timeout=SCHEDULER_TIMEOUT))
            except OSError as error:
                raise ParameterError("--scheduler", scheduler, "the address of a running Dask scheduler "
                                     f"({error})") from None
        yield client


def _on_dask(client: Client, groups: Iterable[Group], simulator: Simulator, keep_signals: bool,
             transports: Transports) -> Iterator[list[tuple[int, RunRecord]]]:
    from distributed import as_completed as completed

    futures = [client.submit(execute_group, group, simulator, keep_signals, transports, pure=False)
               for group in groups]
    try:
        for future in completed(futures):
            yield future.result()
            future.release()
    finally:  # stopped early (an error, an interrupt): nothing may keep running for this study
        unfinished = [future for future in futures if not future.done()]
        if unfinished:
            client.cancel(unfinished)


@contextlib.contextmanager
def open_executor(simulator: Simulator, *, executor: str | Executor = "process", workers: int | None = None,
                  scheduler: str | None = None, keep_signals: bool = False, verbose: bool = False,
                  scratch: str | None = None, pool: ProcessPoolExecutor | None = None) -> Iterator[Runner]:
    """An executor, started (a Dask cluster up, or its scheduler reached) before the block runs.

    Parameters
    ----------
    simulator : Simulator
    executor : {"serial", "process", "dask"} or Executor
        An :class:`Executor` of one's own is used as given (registered under its ``name`` the first time).
    workers : int, optional
        Processes (default: one per core).
    scheduler : str, optional
        ``tcp://host:port`` of a running Dask scheduler (``executor="dask"``).
    keep_signals : bool
        Records keep their compared signals (not needed when the arrays are stored).
    verbose : bool
        Dask's workers log what they do (otherwise nothing below CRITICAL).
    scratch : str, optional
        A folder for an executor's scratch space (a local Dask cluster's): the store's, so that nothing of
        the study is made in the temporary folder; default the temporary folder.
    pool : ProcessPoolExecutor, optional
        The study's process workers, started before (:func:`lcchain.studies.pools.started_pool`, while the study
        was planned): the process executor runs on them instead of starting its own; the others ignore it.

    Yields
    ------
    callable
        Takes groups of (index, spec) and their :class:`Transports`, yields each group's (index, record) pairs
        as it finishes. Warm workers this process started are ended when the block ends.
    """
    check_executor(executor, workers, scheduler)
    try:
        runner = EXECUTOR_TRAITS.accept("--executor", executor).runner
        with runner(simulator, workers or default_workers(), scheduler, keep_signals, verbose, scratch, pool) as run:
            yield run
    finally:
        engine_named(simulator.engine, "simulator.engine").release()


@contextlib.contextmanager
def _serial_runner(simulator: Simulator, workers: int, scheduler: str | None, keep_signals: bool,
                   verbose: bool, scratch: str | None, pool: ProcessPoolExecutor | None) -> Iterator[Runner]:
    yield lambda groups, transports: (execute_group(group, simulator, keep_signals, transports) for group in groups)


@contextlib.contextmanager
def _process_runner(simulator: Simulator, workers: int, scheduler: str | None, keep_signals: bool,
                    verbose: bool, scratch: str | None, pool: ProcessPoolExecutor | None) -> Iterator[Runner]:
    def run(groups: Iterable[Group], transports: Transports) -> Iterator[list[tuple[int, RunRecord]]]:
        if workers == 1:  # one worker: no pool to start
            return (execute_group(group, simulator, keep_signals, transports) for group in groups)
        if _light(groups):  # all the work is in the simulator's processes: threads drive them
            return _threaded(groups, simulator, workers, keep_signals, transports)
        return _process(groups, simulator, workers, keep_signals, transports, pool)

    yield run


@contextlib.contextmanager
def _dask_runner(simulator: Simulator, workers: int, scheduler: str | None, keep_signals: bool,
                 verbose: bool, scratch: str | None, pool: ProcessPoolExecutor | None) -> Iterator[Runner]:
    with _dask(workers, scheduler, verbose, scratch) as client:
        yield lambda groups, transports: _on_dask(client, groups, simulator, keep_signals, transports)


@dataclass(frozen=True)
class ExecutorCost:
    """What an executor costs beside its runs, for a study's price (:meth:`lcchain.studies.plan.Plan.price`).

    Attributes
    ----------
    per_worker : float
        Bytes each worker process holds before any run (0: the runs happen in the driver, or its threads).
    fixed : float
        Bytes beside the workers (a pool's resource tracker, a local Dask scheduler).
    start : float
        Seconds before the first run can start (the workers' interpreters and imports).
    """

    per_worker: float = 0.0
    fixed: float = 0.0
    start: float = 0.0


def _pool_cost(workers: int, light: bool) -> ExecutorCost:
    """One worker: the driver runs them. Runs with no theory: the driver's threads. Else a spawn pool, whose
    workers start in parallel, one per core (more take turns)."""
    if workers == 1 or light:
        return ExecutorCost()
    rounds = -(-workers // default_workers())
    return ExecutorCost(POOL_WORKER_BYTES, POOL_TRACKER_BYTES, POOL_START_SECONDS * rounds)


def _dask_cost(workers: int, light: bool) -> ExecutorCost:
    rounds = -(-workers // default_workers())
    return ExecutorCost(DASK_WORKER_BYTES, DASK_SCHEDULER_BYTES, DASK_START_SECONDS + INTERPRETER_SECONDS * rounds)


def _no_cost(workers: int, light: bool) -> ExecutorCost:
    return ExecutorCost()


#: A context manager (simulator, workers, scheduler, keep_signals, verbose, scratch, pool) that yields a runner
#: (``scratch``: where it may make a scratch folder, or None for the temporary folder; ``pool``: a process pool
#: already started, which an executor may run on or ignore).
RunnerFactory = Callable[[Simulator, int, str | None, bool, bool, str | None, "ProcessPoolExecutor | None"],
                         contextlib.AbstractContextManager[Runner]]


def _no_threads_here(workers: int) -> int:
    return 0


def _one_thread_here(workers: int) -> int:
    return 1


def _a_thread_a_worker(workers: int) -> int:
    return workers


@dataclass(frozen=True)
class Executor(ExecutorTraits):
    """An executor: where a study's runs execute, what it costs and what it is (its traits).

    Attributes
    ----------
    name : str
        The name ``--executor`` and a study's record give it.
    runner : callable
        A :data:`RunnerFactory`: the context manager that starts it and yields its runner.
    cost : callable
        ``(workers, light) -> ExecutorCost``: what it costs beside its runs, given its workers and whether its
        runs are light (no theory to compute).
    min_task_seconds : float
        Seconds of runs worth sending as one task (Dask's overhead per task is a few ms; its documentation asks
        for tasks of 100 ms and more).
    threads_here : callable
        ``workers -> threads``: how many of this process's threads run a batch's runs (whose warm workers a study
        may start while it plans: :class:`EngineStart`); 0 where the runs go to other processes.
    """

    name: str = ""
    runner: RunnerFactory = _serial_runner
    cost: Callable[[int, bool], ExecutorCost] = _no_cost
    min_task_seconds: float = 0.0
    threads_here: Callable[[int], int] = _no_threads_here


def _admit(name: str, loaded: object) -> Executor:
    """An ``lcchain.executors`` entry point's object (or an executor given as itself): an Executor of that
    name."""
    if not isinstance(loaded, Executor) or loaded.name != name or not name:
        raise TypeError(f"{loaded!r} is not an Executor named {name!r}")
    return loaded


#: Each executor, by name (the default, :data:`DEFAULT_EXECUTOR`, among them), then those of the
#: ``lcchain.executors`` entry points.  To add one: its :class:`Executor` here and its name in
#: :data:`lcchain.core.types.ExecutorName` (a test checks the two agree).
EXECUTOR_TRAITS: Registry[Executor] = Registry(
    "lcchain.executors",
    {"serial": Executor(parallel=False, remote=False, name="serial", runner=_serial_runner, cost=_no_cost,
                        threads_here=_one_thread_here),
     "process": Executor(parallel=True, remote=False, name="process", runner=_process_runner, cost=_pool_cost,
                         min_task_seconds=0.05, threads_here=_a_thread_a_worker),
     "dask": Executor(parallel=True, remote=True, name="dask", runner=_dask_runner, cost=_dask_cost,
                      min_task_seconds=0.3)},
    _admit, "an lcchain.studies.executors.Executor, named as the entry point",
    name_of=lambda part: str(getattr(part, "name", "")))


def executor_cost(executor: str | Executor, workers: int, light: bool = False) -> ExecutorCost:
    """What ``executor`` with ``workers`` costs beside its runs (its :attr:`Executor.cost`)."""
    check_executor(executor, workers)
    return EXECUTOR_TRAITS.accept("--executor", executor).cost(workers, light)


def run_groups(groups: list[Group], simulator: Simulator, *, executor: str | Executor = "process",
               workers: int | None = None, scheduler: str | None = None, keep_signals: bool = False,
               verbose: bool = False,
               transports: Transports = Transports()) -> Iterator[list[tuple[int, RunRecord]]]:
    """Execute groups of runs on an executor; yields each group's (index, record) pairs as it finishes."""
    with open_executor(simulator, executor=executor, workers=workers, scheduler=scheduler,
                       keep_signals=keep_signals, verbose=verbose) as run:
        yield from run(groups, transports)


def describe(executor: str, workers: int, scheduler: str | None) -> dict[str, str | int | None]:
    return {"executor": executor, "workers": workers, "scheduler": scheduler}
