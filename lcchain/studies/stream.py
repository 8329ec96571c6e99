"""A batch of foreign netlists planned with flat memory: its tasks on disk, not in the driver (issue 35).

:func:`lcchain.studies.plan.batch_plan` keeps every task (its checked text, ~2 KB a run) for the whole batch: 400 MB
of driver at 100,000 runs.  :func:`streamed_batch_plan` checks, prices and keys every netlist the same way
(:func:`lcchain.studies.plan._batch_item`, before anything runs: refusals, ``strict`` and the budget as there), but
keeps nothing of a run in the driver: the names are read as they are planned (a list file's lines, say), each row's
key, name, price and flags go to :class:`TaskSpool`'s private temporary SQLite database (its page cache bounded),
and the run itself, past the first :data:`HELD`, is pickled into its unnamed temporary file beside the store
(nothing of either outlives the driver, even killed).  The store writes the description's list of netlists from
the spool, a name at a time.
:func:`lcchain.studies.run.run_plan` reads the runs back one by one as the executor asks for them: a
:class:`~lcchain.spice.foreign.CheckedText` unpickled is checked again by the allow-list, so what runs is what was
checked, whatever happened to the spool or to the netlist's file meanwhile.

The executors whose runs go in this process's threads stream it (``serial``, ``process``: a batch's runs have no
theory, and go to threads); the others (Dask, an executor of one's own) take the whole plan.
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import sqlite3
import tempfile
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..core.budget import WARM_WORKER_BYTES, Budget, Estimate
from ..core.errors import LcchainError, ParameterError
from ..core.frozen import FrozenMap
from ..core.json import JSON
from ..core.types import Backend
from ..runs.spec import DEFAULT_TIMEOUT, RunSpec
from ..spice.engines import DEFAULT_ENGINE, ENGINES
from ..spice.inputs import shown_name
from .executors import EXECUTOR_TRAITS, executor_cost
from .plan import Plan, Refusal, Task, _batch_item, _compare_seconds, _ForeignRuns, _version_of

if TYPE_CHECKING:
    from .store import Row, SQLValue

__all__ = ["TaskSpool", "StreamedPlan", "streamed_batch_plan", "streams", "WINDOW", "HELD"]

#: Runs a batch keeps in memory as they were planned (at most ~5 MB of them) before it spools the rest: a run read
#: back from the spool has its text checked again by the allow-list (~0.3 ms, in the driver), which a batch of a
#: few thousand runs need not pay.
HELD = 2048
#: Netlists planned before their keys are made (the engine's version, which every key holds, is found meanwhile)
#: and runs read back from the spool at a time.
WINDOW = 256
#: The spool's SQLite page cache, KB: what its rows cost the driver, whatever the batch's size.
_CACHE_KB = 1024
_SPOOL_SCHEMA = """
CREATE TABLE rows (idx INTEGER PRIMARY KEY, key TEXT NOT NULL, path TEXT NOT NULL, run INTEGER NOT NULL,
                   warm INTEGER NOT NULL, seconds REAL NOT NULL, cost REAL NOT NULL, start_at INTEGER,
                   end_at INTEGER, first INTEGER NOT NULL, stored INTEGER NOT NULL, todo INTEGER NOT NULL);
CREATE TABLE seen (key TEXT PRIMARY KEY) WITHOUT ROWID;
"""


class TaskSpool:
    """A batch's rows in plan order, on disk: each run's spec pickled into an unnamed temporary file in ``folder``,
    and of every row (runs and refusals) its key, its netlist's path, its seconds, its price's seconds and flags in
    a private temporary SQLite database (SQLite's own temporary folder; a bounded page cache: nothing a row is kept
    in the driver).  A row's first appearance of its key is found as it is added (a UNIQUE table of the keys seen).
    """

    def __init__(self, folder: str | None = None) -> None:
        try:
            self._file = tempfile.TemporaryFile(dir=folder)
        except OSError:  # a folder it cannot write in (the store's: its own error comes where it is made)
            self._file = tempfile.TemporaryFile()
        self._end = 0  # where the spool file ends
        self._held: dict[int, RunSpec] = {}  # the first HELD runs by row, as they were planned
        self._rows = 0
        self.memory = 0.0  # the largest run's memory, bytes
        self.light = True  # no run has a theory to compute
        self._db = sqlite3.connect("", isolation_level=None, check_same_thread=False)  # deleted when closed
        self._db.execute(f"PRAGMA cache_size = -{_CACHE_KB}")
        self._db.execute("PRAGMA journal_mode = OFF")
        self._db.execute("PRAGMA synchronous = OFF")
        self._db.executescript(_SPOOL_SCHEMA)
        self._pending: list[tuple[object, ...]] = []  # rows not yet written (at most WINDOW)
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return self._rows

    def add(self, item: Task | Refusal, key: str, path: str) -> None:
        """A row: a run or a refusal, its key, and its netlist's name as given."""
        blob = b""
        index = self._rows
        if isinstance(item, Task):
            spec = item.spec
            if len(self._held) < HELD:
                self._held[index] = spec
            else:
                import pickle  # here: a batch of at most HELD runs never loads it (4 ms of its start)

                blob = pickle.dumps(spec, protocol=pickle.HIGHEST_PROTOCOL)
            self.memory = max(self.memory, item.memory)
            self.light = self.light and spec.theory is None
            engine = ENGINES[spec.engine]
            warm = int(spec.engine == engine.name and not spec.trusted and spec.analysis in engine.warm_analyses)
            seconds, cost, run = item.seconds, item.seconds + _compare_seconds(spec), 1
        else:
            warm, seconds, cost, run = 0, 0.0, 0.0, 0
        try:
            self._file.write(blob)
        except OSError as error:
            why = error.strerror or str(error)
            raise LcchainError(f"the batch's runs could not be spooled to disk beside its store ({why}): make room "
                               "and run the same command again") from None
        self._pending.append((index, key, path, run, warm, seconds, cost, self._end if blob else None,
                              self._end + len(blob) if blob else None))
        self._end += len(blob)
        self._rows += 1
        if len(self._pending) >= WINDOW:
            self._write()

    def _write(self) -> None:
        """The rows added since the last write, in one transaction; each row's ``first`` marks the first row of
        its key (two netlists of the same text, path and options are one run)."""
        if not self._pending:
            return
        with self._guard(), self._lock:
            self._db.execute("BEGIN")
            for row in self._pending:
                new = self._db.execute("INSERT OR IGNORE INTO seen VALUES (?)", (row[1],)).rowcount
                self._db.execute("INSERT INTO rows VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 0, 0)", (*row, new))
            self._db.execute("COMMIT")
        self._pending.clear()

    @contextlib.contextmanager
    def _guard(self) -> Iterator[None]:
        try:
            yield
        except sqlite3.Error as error:
            raise LcchainError(f"the batch's rows could not be spooled to the temporary folder (SQLite says: "
                               f"{error}): make room there (TMPDIR) and run the same command again") from None

    def _query(self, sql: str, args: Sequence[object] = ()) -> Iterator[Row]:
        """A query's rows as they are read (a window at a time: none held).  The runs are read back in an
        executor's thread while the driver asks for keys: each call into SQLite holds the spool's lock."""
        self._write()
        with self._guard():
            with self._lock:
                cursor = self._db.execute(sql, args)
            while True:
                with self._lock:
                    rows = cursor.fetchmany(WINDOW)
                if not rows:
                    break
                yield from rows

    def _one(self, sql: str, args: Sequence[object] = ()) -> Row:
        return next(self._query(sql, args))

    def key(self, index: int) -> str:
        found = next(self._query("SELECT key FROM rows WHERE idx = ?", (index,)), None)
        if found is None:
            raise IndexError(f"the spool has no row {index}")
        return str(found[0])

    def keys(self) -> Iterator[str]:
        """Each row's key, in plan order."""
        return (_text(key) for key, in self._query("SELECT key FROM rows ORDER BY idx"))

    def rows(self) -> Iterator[tuple[str, str]]:
        """Each row's (key, netlist's name as given), in plan order."""
        return ((_text(key), _text(path)) for key, path in self._query("SELECT key, path FROM rows ORDER BY idx"))

    def first(self) -> list[int]:
        """1 for each row whose key no earlier row has (a list: for tests and small batches)."""
        return [_int(first) for first, in self._query("SELECT first FROM rows ORDER BY idx")]

    def distinct(self) -> tuple[int, float]:
        """The distinct runs (refusals not counted) and their seconds together, with their comparisons (summed
        exactly, ``math.fsum``, a window of rows at a time)."""
        count = 0

        def costs() -> Iterator[float]:
            nonlocal count
            for cost, in self._query("SELECT cost FROM rows WHERE first AND run ORDER BY idx"):
                count += 1
                yield _real(cost)

        seconds = math.fsum(costs())
        return count, seconds

    def keyed(self) -> int:
        """The distinct keys of the rows (runs and refusals)."""
        return _int(self._one("SELECT COUNT(*) FROM rows WHERE first")[0])

    def any_warm(self) -> bool:
        return bool(self._one("SELECT EXISTS (SELECT 1 FROM rows WHERE warm)")[0])

    def mark_stored(self, stored_among: Callable[[list[str]], set[str]]) -> int:
        """Mark each row whose key ``stored_among`` (asked a window of keys at a time) finds stored, and each
        row to run now (the first of its key, a run, not stored); the distinct rows stored."""
        self._write()
        low = 0
        while True:
            window = list(self._query("SELECT idx, key FROM rows WHERE idx >= ? ORDER BY idx LIMIT ?",
                                      (low, WINDOW)))
            if not window:
                break
            held = stored_among([_text(key) for _, key in window])
            with self._guard(), self._lock:
                self._db.executemany("UPDATE rows SET stored = 1 WHERE idx = ?",
                                     [(index,) for index, key in window if key in held])
            low = _int(window[-1][0]) + 1
        with self._guard(), self._lock:
            self._db.execute("UPDATE rows SET todo = (first AND run AND NOT stored)")
        return _int(self._one("SELECT COUNT(*) FROM rows WHERE first AND stored")[0])

    def stored(self, index: int) -> bool:
        return bool(self._one("SELECT stored FROM rows WHERE idx = ?", (index,))[0])

    def todo(self) -> int:
        return _int(self._one("SELECT COUNT(*) FROM rows WHERE todo")[0])

    def chosen(self, below: float) -> bytes:
        """A byte a row: 1 for a row to run now whose engine's warm transport may carry it, priced below
        ``below`` seconds (:class:`~lcchain.studies.executors.RunMask`)."""
        chosen = bytearray(len(self))
        for index, in self._query("SELECT idx FROM rows WHERE todo AND warm AND seconds < ?", (below,)):
            chosen[_int(index)] = 1
        return bytes(chosen)

    def specs(self) -> Iterator[tuple[int, RunSpec]]:
        """The spec of each row to run now (:meth:`mark_stored`), in plan order: held, or read back from disk (and
        its text checked again) as it is asked for."""
        self._file.flush()
        for index, start, end in self._query("SELECT idx, start_at, end_at FROM rows WHERE todo ORDER BY idx"):
            if start is None:
                yield _int(index), self._held[_int(index)]
                continue
            self._file.seek(_int(start))  # the spool is this driver's own, unnamed file
            import pickle

            spec = pickle.loads(self._file.read(_int(end) - _int(start)))
            if not isinstance(spec, RunSpec):
                raise TypeError(f"row {index!r} of the spool is not a run")
            yield _int(index), spec

    def close(self) -> None:
        self._held.clear()
        self._pending.clear()
        self._file.close()
        with contextlib.suppress(sqlite3.Error):
            self._db.close()


def _int(value: SQLValue) -> int:
    if not isinstance(value, int):  # the spool is this driver's own: a wrong type is lcchain's error, not the user's
        raise TypeError(f"the spool holds {value!r} where a whole number belongs")
    return value


def _real(value: SQLValue) -> float:
    if not isinstance(value, int | float):
        raise TypeError(f"the spool holds {value!r} where a number belongs")
    return float(value)


def _text(value: SQLValue) -> str:
    if not isinstance(value, str):
        raise TypeError(f"the spool holds {value!r} where a text belongs")
    return value


@dataclass(frozen=True)
class StreamedPlan(Plan):
    """A batch's plan whose runs are on disk (:class:`TaskSpool`), keyed for the engine ``version``; its
    :attr:`~Plan.tasks` is empty, its :attr:`~Plan.refusals` hold every refusal."""

    spool: TaskSpool = field(default_factory=TaskSpool, compare=False, repr=False)
    version: str = ""

    #: The description's key that lists every row's netlist: the store writes it from the rows it stores
    #: (:meth:`lcchain.studies.store.Store.adopt`'s ``listed``), and the plan holds none of them.
    LISTED = ("netlists", "netlist")

    def keys(self, ngspice_version: str) -> dict[int, str]:
        raise TypeError("a streamed plan keeps no keys in memory: run it with lcchain.studies.run.run_plan")

    def rows(self, ngspice_version: str) -> list[tuple[str, dict[str, object], str]]:
        raise TypeError("a streamed plan keeps no rows in memory: see StreamedPlan.streamed_rows")

    def _keyed(self, ngspice_version: str) -> None:
        if ngspice_version != self.version:
            raise ParameterError("simulator", ngspice_version, f"the engine this batch was planned for, "
                                 f"version {self.version} (a run's key holds it)")

    def streamed_rows(self, ngspice_version: str) -> Iterator[tuple[str, dict[str, object], str]]:
        """(key, params, label) of every row in index order, made as the store's tasks table is written."""
        self._keyed(ngspice_version)
        for key, given in self.spool.rows():
            path = Path(given)  # as batch_plan's rows name it (``./n1.cir`` is ``n1.cir``): any executor's store
            yield key, {"netlist": str(path)}, path.name

    def netlists(self) -> Iterator[str]:
        """Every row's netlist as given, in plan order (the description's list, made as it is asked for)."""
        return (path for _, path in self.spool.rows())

    def fingerprint(self, ngspice_version: str) -> str:
        self._keyed(ngspice_version)
        digest = hashlib.sha256()
        for index, key in enumerate(self.spool.keys()):
            digest.update((b"\n" if index else b"") + key.encode())
        return digest.hexdigest()

    def distinct(self) -> tuple[int, float]:
        """The distinct runs (refusals not counted) and their seconds together, with their comparisons (summed
        exactly: ``math.fsum``)."""
        return self.spool.distinct()

    def estimate(self) -> float:
        return self.distinct()[1]

    def price(self, workers: int, executor: str = "process") -> Estimate:
        return self._priced(self.distinct(), workers, executor)

    def _priced(self, distinct: tuple[int, float], workers: int, executor: str) -> Estimate:
        runs, seconds = distinct
        used = max(1, min(workers, runs)) if EXECUTOR_TRAITS[executor].parallel else 1
        cost = executor_cost(executor, used, light=self.spool.light)
        warm = WARM_WORKER_BYTES if self.spool.any_warm() else 0.0
        return Estimate(f"{runs} runs on {used} worker{'s' if used > 1 else ''}",
                        cost.fixed + used * (cost.per_worker + self.spool.memory + warm),
                        self.planning + cost.start + seconds / used)

    def check(self, budget: Budget, workers: int, executor: str = "process", option: str | None = None) -> None:
        distinct = self.distinct()  # one pass over the spool's rows, for the price and its message
        self._priced(distinct, workers, executor).check(budget, option or self._made_by(), f"{distinct[0]} runs",
                                                        "fewer runs, fewer or more workers, or a larger --max-time "
                                                        "or --max-memory")


def streams(executor: object, workers: int) -> bool:
    """Whether a batch on ``executor`` with ``workers`` runs in this process's threads, and so can be streamed."""
    return EXECUTOR_TRAITS.accept("--executor", executor).threads_here(workers) > 0


def streamed_batch_plan(paths: Iterable[str | Path], key_version: Callable[[], str], *, allow_control: bool = False,
                        backend: Backend = "batch", timeout: float = DEFAULT_TIMEOUT, budget: Budget | None = None,
                        strict: bool = False, engine_version: Callable[[], str] | None = None, check: bool = False,
                        folder: str | None = None, progress: Callable[[int], None] | None = None) -> StreamedPlan:
    """:func:`lcchain.studies.plan.batch_plan`'s plan (the same checks, refusals, prices, keys and rows), its runs
    spooled to disk in ``folder`` (the store's; default the temporary folder) as they are planned.

    ``paths`` is read once, as the netlists are planned (a list file's lines, say: none of them is kept).
    ``key_version`` gives the version of the engine that will run the batch (every key holds it): asked once the
    first :data:`WINDOW` netlists are planned (an engine found meanwhile is not waited for).  The plan's
    description lists no netlist: the store lists them from its rows (:attr:`StreamedPlan.LISTED`).
    ``progress(done)`` is told how many netlists are planned as each :data:`WINDOW` of them is spooled, and once
    all are.
    """
    budget = budget if budget is not None else Budget()
    version = engine_version if engine_version is not None else _version_of(backend)
    runs = _ForeignRuns(backend, timeout, budget, version, trusted=allow_control, check=check)
    spool = TaskSpool(folder)
    refusals: list[Refusal] = []
    first: ParameterError | None = None
    window: list[tuple[Task | Refusal, str]] = []  # each with its netlist's name as given
    keyed = ""
    planned = 0
    try:
        for index, name in enumerate(paths):
            item, error = _batch_item(index, name, runs, strict)
            window.append((item, shown_name(str(name))))  # with its name as given (as lcchain shows it)
            if isinstance(item, Task):
                planned += 1
            else:
                first = first or error
                refusals.append(item)
            if len(window) >= WINDOW:
                keyed = keyed or key_version()
                _spool(spool, window, keyed)
                if progress is not None:
                    progress(index + 1)
        if first is not None and not planned:  # nothing of it can run: bad input, as with strict
            raise first
        keyed = keyed or key_version()
        rest = bool(window)
        _spool(spool, window, keyed)
        if rest and progress is not None:
            progress(planned + len(refusals))
    except BaseException:
        spool.close()
        raise
    # batch_plan's description, its list of netlists made by the store from the rows (in its place, as there)
    description: dict[str, JSON] = {"command": "batch", StreamedPlan.LISTED[0]: [],
                                    "allow_control": allow_control, "backend": backend}
    if check:
        description["check"] = True
    return StreamedPlan("batch", FrozenMap(description), (), backend, ("netlist",),
                        engine=DEFAULT_ENGINE, refusals=tuple(refusals), spool=spool, version=keyed)


def _spool(spool: TaskSpool, window: list[tuple[Task | Refusal, str]], version: str) -> None:
    for item, given in window:
        spool.add(item, item.spec.key(version) if isinstance(item, Task) else item.key, given)
    window.clear()
