"""The result store: one SQLite file that survives a crash, never mixes two studies and is written by one driver.

* stdlib ``sqlite3`` in WAL mode with ``synchronous = NORMAL``: every
  finished run is committed to the log when it returns, so killing the
  driver (Ctrl-C or SIGKILL) loses no finished run; the disk is synced at
  each checkpoint, not at each commit (a commit's sync was the largest
  per-run cost of a batch of short runs, 2 ms a run), so only a crash of
  the machine itself can lose the last runs, which the same command runs
  again.
* One driver writes a store at a time: it holds an exclusive ``flock`` on the
  store file itself for as long as it is open for writing (nothing is left
  beside the store; the kernel drops the lock when the driver dies).  A second
  writer is refused, naming the first one's pid, or waits (``wait=True``).
* A store is made whole or not at all: a new one is built under a hidden name
  beside it (``.NAME.*.new``) with its plan in one transaction, then linked
  under its own name; until :meth:`Store.adopt` nothing exists on disk.  (A
  driver killed in those milliseconds can leave the hidden file: the next
  store made in that folder removes it.)
* What is opened is checked against what lcchain writes (an allow-list): a
  regular file, SQLite's header, exactly the tables ``meta``, ``tasks`` and
  ``records`` with their columns, and this :data:`FORMAT`.  Anything else
  (someone's database, an empty file, a text file, a FIFO, a folder) is
  refused before a byte of it is written.
* ``mode="read"`` (``lcchain results``) opens it read-only and changes
  nothing: no lock, no WAL switch, no ``-wal`` or ``-shm`` file made (the
  file is opened ``immutable`` while no ``-wal`` beside it holds anything;
  read-only media work).
* A store is always read as SQLite reads it: with its write-ahead log.  A
  driver stopped by a full disk, a kill or a read-only folder leaves
  committed runs in ``NAME-wal`` and, when it stopped in a checkpoint, a main
  file that is whole only together with that log; neither the check of a
  store a driver will write nor ``results`` looks at the main file alone
  then, so the same command resumes it.
* A corrupt page, a row changed outside lcchain (metrics that are not JSON,
  arrays that are not ``.npz`` or do not match their digest), a full disk: a
  one-line error that names the store and what to do; what was committed
  stays.

* A run is stored under its key (:meth:`lcchain.runs.spec.RunSpec.key`: the
  netlist text, saved vectors, stop time, backend, theory, engine, lcchain and
  engine versions); a study that finds its key stored skips the run.
* The engine that ran it is in the ``engine`` column (and the meta row of
  that name): its name and version (``"ngspice 39"``, ``"gnucap
  2017.10.03"``; :func:`engine_text`, :func:`engine_of`).  A store of format
  1 (before there were engines, the column was ``ngspice_version`` and held
  ngspice's version alone, ``"39"``) is read as it is, and migrated in one
  transaction when a study opens it to write.
* The store remembers the plan it was made for (the ordered task keys): a
  different plan, or the same one under another ngspice, is refused rather
  than mixed in silently.
* An extrapolation (:class:`lcchain.studies.plan.Combination`) is a row of its
  own after its member runs, under its members' keys hashed; its arrays are the
  combined signals it was compared by (dimensionless time, ``loop0``, ...) and
  its points the members' together.

Tables: ``meta`` (format, plan fingerprint, description, versions),
``tasks`` (index, key, params, label) and ``records`` (key, status, reason,
log tail, digest, times, versions, metrics as JSON, the saved arrays as a
numpy ``.npz``).  A netlist's ``.meas`` results are in its metrics' JSON, under
``"measurements"`` (name -> value, null where ngspice could not make it) and
``"measure_reasons"`` (name -> ngspice's reason): no new column, so a store
written before them opens and reads as it did.
"""

from __future__ import annotations

import contextlib
import fcntl
import io
import json
import os
import secrets
import sqlite3
import stat
import time
import urllib.parse
import zipfile
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Literal, TypeAlias

from ..core import __version__
from ..core.analyses import analysis_kind
from ..core.errors import LcchainError, ParameterError, clipped
from ..core.json import JSON, LooseJSONObject
from ..core.show import Figure, html_table, plot, short_repr
from ..core.types import RUN_STATUSES
from ..runs.execute import RunRecord, waveform_digest
from ..spice.engines import DEFAULT_ENGINE
from ..spice.inputs import file_kind
from ..spice.measure import measurement_fields
from .exports import ExportSize, export_size, to_dataframe, to_xarray
from .stored import ARRAY_AXES, PARTS, StoredRun, study_dims

if TYPE_CHECKING:
    import numpy as np
    import pandas as pd
    import xarray as xr

__all__ = ["Store", "StoreMode", "FORMAT", "engine_text", "engine_of"]

#: Keys asked of the records table in one query (SQLite allows 32,766 parameters since 3.32, 999 before).
_KEYS_A_QUERY = 500
#: Version of the store's tables.
FORMAT = "2"
#: The column (and meta row) that holds the engine, by store format: format 1 named it for ngspice, and held
#: ngspice's version alone (``"39"``), another engine's name and version (``"gnucap 2017.10.03"``).
_ENGINE_COLUMN = {"1": "ngspice_version", FORMAT: "engine"}
#: How a store is opened: to read it (``lcchain results``) or to run a study into it.
StoreMode = Literal["read", "write"]

_SCHEMA = """
CREATE TABLE meta (name TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE tasks (idx INTEGER PRIMARY KEY, key TEXT NOT NULL, params TEXT NOT NULL, label TEXT);
CREATE TABLE records (
    key TEXT PRIMARY KEY, status TEXT NOT NULL, reason TEXT, log_tail TEXT, digest TEXT,
    wall_s REAL, total_s REAL, engine TEXT, lcchain_version TEXT, points INTEGER,
    metrics TEXT, arrays BLOB, finished REAL
);
"""
#: The tables a store holds, and their columns: anything else is not an lcchain store.
_TABLES = {
    "meta": ("name", "value"),
    "tasks": ("idx", "key", "params", "label"),
    "records": ("key", "status", "reason", "log_tail", "digest", "wall_s", "total_s", "engine",
                "lcchain_version", "points", "metrics", "arrays", "finished"),
}
#: Format 1 to this one, in one transaction: the engine's column and meta row renamed, ngspice's bare versions
#: given its name.
_MIGRATE = ("ALTER TABLE records RENAME COLUMN ngspice_version TO engine",
            "UPDATE records SET engine = 'ngspice ' || engine WHERE engine IS NOT NULL AND instr(engine, ' ') = 0",
            "UPDATE meta SET name = 'engine', value = CASE WHEN instr(value, ' ') = 0 THEN 'ngspice ' || value "
            "ELSE value END WHERE name = 'ngspice_version'",
            f"UPDATE meta SET value = '{FORMAT}' WHERE name = 'format'")
_HEADER = b"SQLite format 3\x00"
#: What a record's status may be (:data:`lcchain.core.types.RunStatus`); a store made before there were refusals
#: simply holds none.
_STATUSES = RUN_STATUSES
#: Seconds after which a hidden ``.NAME.*.new`` that no driver holds is a leftover of a killed one.
_STALE_SECONDS = 60.0
#: What a store's owner can do about a row or a page that is not as lcchain wrote it.
_RESTORE = "restore it from a copy, or run the study into a new store"
#: A value as SQLite gives it back: TEXT, INTEGER, REAL, BLOB or NULL; a row is a tuple of them, each narrowed to
#: its column's type where it is read (a store changed outside lcchain is refused).
SQLValue: TypeAlias = str | int | float | bytes | None
Row: TypeAlias = tuple[SQLValue, ...]


#: A key of a plan's description whose list is given item by item (:meth:`Store.adopt`), and what gives them.
Listed: TypeAlias = tuple[str, Callable[[], Iterable[JSON]]]
#: A placeholder no description holds, where a listed key's items go.
_LISTED_HERE = "\x00listed\x00"


class _Closed(LcchainError):
    """A :class:`Store` used after it was closed: the object, not its file (which is intact)."""


def _differences(held: JSON, wanted: JSON) -> str:
    """What differs between the study a store holds and this one, by the descriptions' top-level names, at most
    three (``"; this one differs in check: true, the store's none"``), or "" when either is no object."""
    if not isinstance(held, dict) or not isinstance(wanted, dict):
        return ""
    names = [name for name in dict.fromkeys([*wanted, *held]) if held.get(name) != wanted.get(name)]

    def shown(where: dict[str, JSON], name: str) -> str:
        return clipped(json.dumps(where[name]), 80) if name in where else "none"

    said = "; ".join(f"{name}: {shown(wanted, name)}, the store's {shown(held, name)}" for name in names[:3])
    return f"; this one differs in {said}" if said else ""


def _described(description: Mapping[str, JSON], listed: Listed | None) -> str:
    """The description's JSON text, as ``json.dumps`` writes it; a ``listed`` key's list written an item at a
    time (a batch's 100,000 netlists: their text alone, never a Python list of them)."""
    if listed is None:
        return json.dumps(description)
    key, items = listed
    before, _, after = json.dumps({**description, key: _LISTED_HERE}).partition(json.dumps(_LISTED_HERE))
    text = io.StringIO()
    text.write(before + "[")
    for at, item in enumerate(items()):
        text.write((", " if at else "") + json.dumps(item))
    text.write("]" + after)
    return text.getvalue()


def engine_text(engine: str, version: str) -> str:
    """What the ``engine`` column (and meta row) holds: the engine's name and version (``"ngspice 39"``)."""
    return f"{engine} {version}"


def engine_of(text: str) -> tuple[str, str]:
    """(engine, version) from :func:`engine_text`'s text, or from a format-1 store's column, where ngspice's
    version stood alone (``"39"``: ngspice versions hold no space)."""
    engine, space, version = text.partition(" ")  # "ngspice ": a refused run's, which no engine ran (version "")
    return (engine, version) if space else (DEFAULT_ENGINE, text)


def _uri(path: Path, immutable: bool) -> str:
    """SQLite's read-only URI of a file (``immutable``: no lock, no ``-shm`` file, and no look at the ``-wal``:
    only for a file whose log holds nothing, see :func:`_logged`)."""
    return (f"file:{urllib.parse.quote(str(path.absolute()))}?mode=ro" + ("&immutable=1" if immutable else ""))


def _logged(path: Path) -> bool:
    """Whether a write-ahead log beside the store may hold pages its main file lacks: a ``-wal`` that is not
    empty.  (SQLite empties or removes it only once every page it held is in the main file; a ``-wal`` that
    cannot be looked at may hold anything.)"""
    try:
        return os.stat(f"{path}-wal").st_size > 0
    except FileNotFoundError:
        return False
    except OSError:
        return True


def _cannot_open(error: sqlite3.Error) -> bool:
    return getattr(error, "sqlite_errorname", "") == "SQLITE_CANTOPEN"


def _holder(descriptor: int) -> int | None:
    """The pid holding a flock on this file, from Linux's ``/proc/locks`` (None when it cannot be told)."""
    info = os.fstat(descriptor)
    device = f"{os.major(info.st_dev):02x}:{os.minor(info.st_dev):02x}:{info.st_ino}"
    try:
        lines = Path("/proc/locks").read_text().splitlines()
    except OSError:
        return None
    for line in lines:
        fields = line.split()
        if len(fields) >= 6 and fields[1] == "FLOCK" and fields[5] == device:
            with contextlib.suppress(ValueError):
                return int(fields[4])
    return None


def _array_headers(blob: bytes) -> dict[str, tuple[int, int]]:
    """Each saved array's (points, bytes per value) from a run's ``.npz`` without reading its values."""
    import numpy as np
    with zipfile.ZipFile(io.BytesIO(blob)) as archive:
        with archive.open("names.npy") as handle:
            names = [str(n) for n in np.lib.format.read_array(handle, allow_pickle=False)]
        sizes = {}
        for i, name in enumerate(names):
            with archive.open(f"v{i}.npy") as handle:
                version = np.lib.format.read_magic(handle)
                reader = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                          else np.lib.format.read_array_header_2_0)
                shape, _, dtype = reader(handle)
            sizes[name] = (int(np.prod(shape)), 16 if np.dtype(dtype).kind == "c" else 8)
    return sizes


def _saved(values: np.ndarray) -> np.ndarray:
    """A stored array as lcchain wrote it: complex128 (an AC run's vectors) or float64; nothing else."""
    import numpy as np
    if values.dtype.kind not in "fc":
        raise ValueError("not a float or complex array")
    return np.asarray(values, dtype=complex if values.dtype.kind == "c" else float)


def _arrays(record: RunRecord) -> bytes | None:
    """The saved arrays: ngspice's (time in seconds, each vector; an AC run's frequency in Hz and its complex
    vectors), or for an extrapolation, which has no run of its own, the combined signals it was compared by
    (dimensionless time, ``loop0``, ``loop1``...)."""
    import numpy as np
    if record.run is not None:
        arrays = {analysis_kind(record.run.analysis).axis: record.run.data.axis, **record.run.vectors}
    elif record.signals is not None:
        arrays = {"time": record.signals.t, **{f"loop{i}": row for i, row in enumerate(record.signals.sim)}}
    else:
        return None
    buffer = io.BytesIO()
    np.savez(buffer, names=np.array(list(arrays)), **{f"v{i}": a for i, a in  # type: ignore[arg-type]
                                                      enumerate(arrays.values())})
    return buffer.getvalue()


class Store:
    """A study's results in one SQLite file.

    Parameters
    ----------
    path : path-like
        The ``.sqlite`` file.
    mode : {"write", "read"}
        ``"write"`` (a study runs into it): an existing store is checked and
        locked for this driver alone; a missing one is made by :meth:`adopt`,
        whole.  ``"read"``: an existing store, opened read-only; nothing is
        created, locked or changed.
    wait : bool
        ``mode="write"`` only: wait for another driver writing the store to
        finish, instead of refusing it.
    on_wait : callable, optional
        Called with the other driver's pid (None when unknown) before waiting.
    option : str
        The option that named the store, for messages (``"--store"``).

    Raises
    ------
    ParameterError
        The path is not an lcchain store (another SQLite database, an empty
        or a text file, a FIFO, a folder), is missing (``mode="read"``), or
        another driver writes it (unless ``wait``).
    """

    def __init__(self, path: str | Path, mode: StoreMode = "write", *, wait: bool = False,
                 on_wait: Callable[[int | None], None] | None = None, option: str = "--store"):
        if mode not in ("read", "write"):
            raise ParameterError("mode", mode, "read | write")
        self.path = Path(path)
        self.mode = mode
        self.option = option
        self._lock: int | None = None  # the flock'd descriptor of a store this driver writes
        self._engine_column = _ENGINE_COLUMN[FORMAT]  # a format-1 store read as it is names it otherwise
        self._immutable: tuple[int, int, int] | None = None  # (inode, size, mtime) of a file read immutable
        self._db: sqlite3.Connection
        self._wait, self._on_wait = wait, on_wait
        try:
            if mode == "read":
                self._open_read()
            else:
                self._open_write()
        except BaseException:
            self.close()
            raise

    # ------------------------------------------------------------------ opening
    def _refuse(self, allowed: str) -> ParameterError:
        return ParameterError(self.option, str(self.path), allowed)

    def _regular(self) -> os.stat_result | None:
        """The store's stat when it is a regular file, None when missing; refused when anything else."""
        try:
            info = os.stat(self.path)
        except FileNotFoundError:
            if os.path.lexists(self.path):
                raise self._refuse("an lcchain store (this is a symbolic link to nothing)") from None
            return None
        except OSError as error:
            raise self._refuse(f"a store lcchain can open ({error.strerror})") from None
        if not stat.S_ISREG(info.st_mode):
            raise self._refuse(f"an lcchain store (this is {file_kind(info.st_mode)})")
        return info

    def _check_bytes(self, descriptor: int) -> None:
        """Refuse an empty file or one that is not SQLite, from its first bytes (read through ``descriptor``)."""
        if os.fstat(descriptor).st_size == 0:
            raise self._refuse("an lcchain store (this is an empty file)")
        if os.pread(descriptor, len(_HEADER), 0) != _HEADER:
            raise self._refuse("an lcchain store (this is not an SQLite database)")

    def _check_tables(self, db: sqlite3.Connection) -> dict[str, str]:
        """Refuse a database whose tables are not lcchain's, of another format or without a plan; its meta."""
        objects = db.execute("SELECT type, name FROM sqlite_master").fetchall()
        other = sorted(name for kind, name in objects if not (kind == "table" and name in _TABLES) and
                       not (kind == "index" and name.startswith("sqlite_autoindex_")))
        tables = {name for kind, name in objects if kind == "table"}
        if other or tables != set(_TABLES):
            shown = ", ".join(other or sorted(tables)) or "nothing"
            raise self._refuse(f"an lcchain store (this SQLite database holds {shown})")
        meta = dict(db.execute("SELECT name, value FROM meta").fetchall())
        column = _ENGINE_COLUMN.get(meta.get("format", ""))
        if column is None:
            raise self._refuse(f"a store of format {' or '.join(_ENGINE_COLUMN)} (this one is "
                               f"{meta.get('format', 'of none')})")
        for table, columns in _TABLES.items():
            found = tuple(row[1] for row in db.execute(f"PRAGMA table_info({table})"))
            if found != tuple(column if name == "engine" else name for name in columns):
                raise self._refuse(f"an lcchain store (its table {table} has the columns {', '.join(found)})")
        self._engine_column = column
        if "plan" not in meta:
            raise self._refuse("a store made by lcchain sweep or batch (this one holds no plan: remove it)")
        return meta

    def _check_file(self, descriptor: int) -> None:
        """The allow-list check of an existing file, before anything is written to it: with its write-ahead log,
        as the driver will read it (this driver holds the lock: no other lcchain starts a log meanwhile)."""
        self._check_bytes(descriptor)
        immutable = not _logged(self.path)
        with self._guard(), contextlib.closing(sqlite3.connect(_uri(self.path, immutable), uri=True)) as db:
            self._check_tables(db)

    def _open_read(self) -> None:
        if self._regular() is None:
            raise self._refuse("an existing store made by lcchain sweep or batch")
        descriptor = self._open_descriptor()
        try:
            self._check_bytes(descriptor)
        finally:
            os.close(descriptor)  # before SQLite opens the file: closing a descriptor drops its POSIX locks
        self._connect_read()

    def _connect_read(self) -> None:
        """Read-only, with the write-ahead log as SQLite reads it; ``immutable`` (no lock, no file made) only while
        the ``-wal`` holds nothing, and opened again with the log should a driver start one meanwhile."""
        with self._guard():
            self._immutable = self._snapshot() if not _logged(self.path) else None
            db = sqlite3.connect(_uri(self.path, self._immutable is not None), uri=True, isolation_level=None)
            try:
                try:
                    self._check_tables(db)
                except sqlite3.DatabaseError:
                    if not self._stale():
                        raise
                    db.close()
                    self._immutable = None
                    db = sqlite3.connect(_uri(self.path, False), uri=True, isolation_level=None)
                    self._check_tables(db)
            except BaseException:
                db.close()
                raise
            self._db = db

    def _snapshot(self) -> tuple[int, int, int]:
        info = os.stat(self.path)
        return (info.st_ino, info.st_size, info.st_mtime_ns)

    def _stale(self) -> bool:
        """Whether a file read ``immutable`` was changed, or given a log, since it was opened."""
        if self._immutable is None:
            return False
        try:
            return self._snapshot() != self._immutable or _logged(self.path)
        except OSError:
            return True

    def _open_descriptor(self) -> int:
        try:
            return os.open(self.path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
        except OSError as error:
            raise self._refuse(f"a store lcchain can open ({error.strerror})") from None

    def _open_write(self) -> None:
        while True:
            if self._regular() is None:  # made by adopt(), whole; until then nothing exists on disk
                self._db = sqlite3.connect(":memory:", isolation_level=None)
                self._db.executescript(_SCHEMA)
                return
            descriptor = self._open_descriptor()
            try:
                if not stat.S_ISREG(os.fstat(descriptor).st_mode):
                    raise self._refuse(f"an lcchain store (this is {file_kind(os.fstat(descriptor).st_mode)})")
                self._take_lock(descriptor)
                still = self._regular()
                if still is None or still.st_ino != os.fstat(descriptor).st_ino:  # replaced while this waited
                    os.close(descriptor)
                    continue
                self._check_file(descriptor)
            except BaseException:
                os.close(descriptor)
                raise
            self._lock = descriptor
            with self._guard():
                self._db = sqlite3.connect(self.path, timeout=60.0, isolation_level=None)
                self._db.execute("PRAGMA journal_mode=WAL")
                self._db.execute("PRAGMA synchronous=NORMAL")
                if self._engine_column != _ENGINE_COLUMN[FORMAT]:
                    self._migrate()
            return

    def _migrate(self) -> None:
        """A format-1 store to this format, in one transaction (this driver holds the lock): every run in it is
        kept, and a failure leaves it as it was."""
        self._db.execute("BEGIN IMMEDIATE")
        try:
            for statement in _MIGRATE:
                self._db.execute(statement)
            self._db.execute("COMMIT")
        except BaseException:
            with contextlib.suppress(sqlite3.Error):
                self._db.execute("ROLLBACK")
            raise
        self._engine_column = _ENGINE_COLUMN[FORMAT]

    def _take_lock(self, descriptor: int) -> None:
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return
        except BlockingIOError:
            pid = _holder(descriptor)
        who = f"lcchain (pid {pid})" if pid is not None else "lcchain"
        if not self._wait:
            raise self._refuse(f"a store no other lcchain is writing (another {who} is writing it now: let it "
                               "finish, or add --wait to wait for it)")
        if self._on_wait is not None:
            self._on_wait(pid)
        fcntl.flock(descriptor, fcntl.LOCK_EX)

    def close(self) -> None:
        db = getattr(self, "_db", None)
        if db is not None:
            with contextlib.suppress(sqlite3.Error):
                db.close()
        if self._lock is not None:  # after SQLite's own descriptor: closing ours drops the process's POSIX locks
            os.close(self._lock)
            self._lock = None

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ errors
    @contextlib.contextmanager
    def _guard(self) -> Iterator[None]:
        """SQLite's errors as one line naming the store and what to do."""
        try:
            yield
        except sqlite3.Error as error:
            raise self._problem(error) from None

    def _problem(self, error: sqlite3.Error) -> LcchainError:
        said = str(error)
        if isinstance(error, sqlite3.ProgrammingError) and "closed" in said:  # the object, not the file
            return _Closed(f"{self.path}: this Store was closed (its with block, or close(), ended it): open "
                           "the store again to use it")
        if _cannot_open(error) and _logged(self.path):  # read-only media, a -wal and no -shm
            return self._refuse(f"a store whose write-ahead log SQLite can read ({self.path.name}-wal holds runs "
                                f"not yet in {self.path.name}, and SQLite cannot share it without "
                                f"{self.path.name}-shm in a read-only folder): make the folder writable, or "
                                "copy the store with its -wal into one")
        if isinstance(error, sqlite3.OperationalError) and ("full" in said or "I/O" in said):
            return LcchainError(f"{self.path}: the store could not be written (SQLite says: {said}); every run "
                                "stored before this is kept: make room and run the same command to resume")
        if "readonly" in said or "read-only" in said or (self.mode == "write" and _cannot_open(error)):
            return self._refuse(f"a store lcchain can write (SQLite says: {said}); every run stored in it is kept: "
                                "make it and its folder writable and run the same command to resume")
        if "locked" in said or "busy" in said:
            return self._refuse(f"a store no other program is writing (SQLite says: {said})")
        if isinstance(error, sqlite3.DatabaseError) and not isinstance(error, sqlite3.OperationalError):
            return self._refuse(f"an intact lcchain store (SQLite says: {said}): {_RESTORE}")
        return LcchainError(f"{self.path}: SQLite says: {said}")

    def _tampered(self, what: str) -> ParameterError:
        return self._refuse(f"a store whose rows are as lcchain wrote them ({what}: it was changed outside "
                            f"lcchain): {_RESTORE}")

    def _rows(self, sql: str, args: Sequence[SQLValue] = ()) -> list[Row]:
        """A query's rows; a store read ``immutable`` that a driver started writing meanwhile (new runs in its
        log, its main file torn by a checkpoint) is read again, with its log."""
        with self._guard():
            try:
                rows = self._db.execute(sql, args).fetchall()
            except sqlite3.DatabaseError:
                if not self._stale():
                    raise
                rows = None
            if rows is None or self._stale():
                self._db.close()
                self._connect_read()
                rows = self._db.execute(sql, args).fetchall()
        return rows

    def _count(self, sql: str) -> int:
        """A query's one integer (a COUNT, a SUM)."""
        value = self._rows(sql)[0][0]
        if not isinstance(value, int):
            raise self._tampered(f"{sql!r} gave {str(value)[:20]!r}, not a count")
        return value

    def _blob(self, key: str, value: SQLValue) -> bytes:
        """A run's saved arrays as stored: bytes, else refused."""
        if not isinstance(value, bytes):
            raise self._tampered(f"the arrays of run {key[:12]} are not lcchain's .npz")
        return value

    # ------------------------------------------------------------------ the plan
    def meta(self) -> dict[str, str]:
        meta = {}
        for name, value in self._rows("SELECT name, value FROM meta"):
            if not isinstance(name, str) or not isinstance(value, str):
                raise self._tampered(f"its meta row {str(name)[:20]!r} is not text")
            meta[name] = value
        return meta

    def check_plan(self, fingerprint: str, description: Mapping[str, JSON], rows: int, engine: str, *,
                   listed: Listed | None = None) -> None:
        """Refuse a store that holds another plan (nothing is written); ``listed`` as for :meth:`adopt` (read only
        when the store holds another plan, to tell whether it is this study as another engine planned it).

        Raises
        ------
        ParameterError
            The store holds another plan.
        """
        meta = self.meta()
        if "plan" not in meta or meta["plan"] == fingerprint:
            return
        try:
            held_plan, this_plan = json.loads(meta.get("description", "null")), json.loads(_described(description,
                                                                                                       listed))
        except json.JSONDecodeError:
            raise self._tampered("its description is not JSON") from None
        if held_plan == this_plan:
            held = self._count("SELECT COUNT(*) FROM tasks")
            held_by = meta.get(self._engine_column, "?")
            raise self._refuse("a new store: it holds this very study as another lcchain or engine planned it "
                               f"({held} rows; lcchain {meta.get('lcchain_version', '?')}, {held_by}; now {rows} "
                               f"rows, {engine}), and lcchain never mixes two")
        raise self._refuse("a new store, or the store of this very study: it holds another "
                           f"({clipped(meta.get('description', '?'), 200)}, {meta.get(self._engine_column, '?')}"
                           f"{_differences(held_plan, this_plan)}), and lcchain never mixes two")

    def adopt(self, fingerprint: str, description: Mapping[str, JSON],
              tasks: Iterable[tuple[str, Mapping[str, object], str]], engine: str, *,
              count: int | None = None, listed: Listed | None = None) -> None:
        """Make this the store of a plan, or check that it already is.

        A new store is made whole: built under a hidden name beside it, its plan
        written in one transaction, then linked under its own name.

        Parameters
        ----------
        fingerprint : str
            The plan's fingerprint (its ordered task keys, hashed).
        description : dict
            What the user asked for, in words and values (for ``lcchain results``).
        tasks : iterable of (key, params, label)
            The plan's tasks in order (read once, as they are written, when ``count`` is given).
        count : int, optional
            How many ``tasks`` holds (by default its length).
        engine : str
            The engine's name and version (:func:`engine_text`).
        listed : (str, callable), optional
            A key of ``description`` whose list is too long to hold (a batch's netlists), and what gives its
            items, read once as the description is written: its value in ``description`` is a placeholder.

        Raises
        ------
        ParameterError
            The store holds another plan, or another driver made it meanwhile and writes it.
        """
        if self.mode != "write":
            raise self._refuse("a store opened for writing")
        count = count if count is not None else len(tasks) if isinstance(tasks, Sequence) else None
        if count is None:
            raise TypeError("adopt: the count of tasks given as an iterator")
        self.check_plan(fingerprint, description, count, engine, listed=listed)
        if "plan" in self.meta():
            return
        meta = (("format", FORMAT), ("plan", fingerprint), ("description", _described(description, listed)),
                ("created", time.strftime("%Y-%m-%dT%H:%M:%S")), ("lcchain_version", __version__),
                ("engine", engine))
        rows = ((i, key, json.dumps(params), label) for i, (key, params, label) in enumerate(tasks))
        self._remove_leftovers()
        hidden = self.path.parent / f".{self.path.name}.{secrets.token_hex(4)}.new"
        try:
            descriptor = os.open(hidden, os.O_RDWR | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC, 0o666)
        except OSError as error:
            raise self._refuse(f"a file lcchain can create ({error.strerror})") from None
        linked = False
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX)
            with self._guard(), contextlib.closing(sqlite3.connect(hidden, isolation_level=None)) as db:
                db.execute("PRAGMA journal_mode=MEMORY")  # no journal file: a half-built store is thrown away
                db.execute("BEGIN")
                for statement in _SCHEMA.split(";"):
                    if statement.strip():
                        db.execute(statement)
                db.executemany("INSERT INTO meta VALUES (?, ?)", meta)
                db.executemany("INSERT INTO tasks VALUES (?, ?, ?, ?)", rows)
                db.execute("COMMIT")
                db.execute("PRAGMA journal_mode=WAL")
            os.fsync(descriptor)
            try:
                os.link(hidden, self.path)
                linked = True
            except FileExistsError:
                pass
        except OSError as error:
            os.close(descriptor)
            raise LcchainError(f"{self.path}: the store could not be made ({error.strerror or error}); nothing was "
                               "written under its name: make room and run the same command again") from None
        except BaseException:
            os.close(descriptor)
            raise
        finally:
            with contextlib.suppress(OSError):
                os.unlink(hidden)
        if not linked:  # another driver made it first: its lock decides
            os.close(descriptor)
            self._db.close()
            self._open_write()
            # it holds a plan now, which adopt checks (an iterator of tasks is read already: none is written)
            self.adopt(fingerprint, description, tasks if isinstance(tasks, Sequence) else (), engine, count=count,
                       listed=listed)
            return
        with contextlib.suppress(OSError):
            folder = os.open(self.path.parent, os.O_RDONLY | os.O_DIRECTORY)
            try:
                os.fsync(folder)
            finally:
                os.close(folder)
        self._db.close()
        self._lock = descriptor
        with self._guard():
            self._db = sqlite3.connect(self.path, timeout=60.0, isolation_level=None)
            self._db.execute("PRAGMA synchronous=NORMAL")

    def _remove_leftovers(self) -> None:
        """Hidden stores that a driver killed while making them left beside this one (no driver holds them)."""
        prefix = f".{self.path.name}."
        try:
            names = [n for n in os.listdir(self.path.parent) if n.startswith(prefix) and n.endswith(".new")]
        except OSError:
            return
        for name in names:
            leftover = self.path.parent / name
            try:
                descriptor = os.open(leftover, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | os.O_NOFOLLOW)
            except OSError:
                continue
            try:
                info = os.fstat(descriptor)
                if not stat.S_ISREG(info.st_mode) or time.time() - info.st_mtime < _STALE_SECONDS:
                    continue
                fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)  # held: a driver is making it now
                os.unlink(leftover)
            except OSError:
                pass
            finally:
                os.close(descriptor)

    def description(self) -> LooseJSONObject:
        try:
            described = json.loads(self.meta().get("description", "{}"))
        except json.JSONDecodeError:
            raise self._tampered("its description is not JSON") from None
        return described if isinstance(described, dict) else {}

    # ------------------------------------------------------------------ records
    def finished(self) -> set[str]:
        """The keys of every run stored (ok, failed, timed out, or refused)."""
        return {key for key, in self._rows("SELECT key FROM records") if isinstance(key, str)}

    def failed(self) -> set[str]:
        """The keys of every run stored as failed or timed out (``--retry-failed`` runs them again)."""
        return {key for key, in self._rows("SELECT key FROM records WHERE status IN ('failed', 'timeout')")
                if isinstance(key, str)}

    def stored_among(self, keys: Sequence[str], retry_failed: bool = False) -> set[str]:
        """Those of ``keys`` stored (ok, failed, timed out or refused; with ``retry_failed``, not failed or timed
        out): asked a window of keys at a time, so that a study holds no set of every stored key."""
        found: set[str] = set()
        skip = " AND status NOT IN ('failed', 'timeout')" if retry_failed else ""
        for start in range(0, len(keys), _KEYS_A_QUERY):
            window = keys[start:start + _KEYS_A_QUERY]
            marks = ", ".join("?" * len(window))
            found.update(key for key, in self._rows(f"SELECT key FROM records WHERE key IN ({marks}){skip}",
                                                    window) if isinstance(key, str))
        return found

    def status_counts(self) -> dict[str, int]:
        """How many of the plan's runs are stored under each status (a key the plan holds twice, once: the records
        of a store are its plan's)."""
        counts: dict[str, int] = {}
        for status, count in self._rows("SELECT status, COUNT(*) FROM records GROUP BY status"):
            if not isinstance(status, str) or status not in _STATUSES or not isinstance(count, int):
                raise self._tampered(f"a run has the status {str(status)[:20]!r}")
            counts[status] = count
        return counts

    def reasons(self, keys: Sequence[str]) -> dict[str, str]:
        """The stored reason of each of ``keys`` stored."""
        found: dict[str, str] = {}
        for start in range(0, len(keys), _KEYS_A_QUERY):
            window = keys[start:start + _KEYS_A_QUERY]
            marks = ", ".join("?" * len(window))
            for key, reason in self._rows(f"SELECT key, reason FROM records WHERE key IN ({marks})", window):
                if not isinstance(key, str) or not isinstance(reason, str | None):
                    raise self._tampered(f"run {str(key)[:12]} has a key or reason that is not text")
                found[key] = reason or ""
        return found

    def add(self, record: RunRecord, points: int | None = None, *,
            parts: Mapping[str, Sequence[float | None]] | None = None) -> None:
        """Store one finished run, in one transaction (in the log when this returns: a killed driver keeps it);
        ``points`` when it has no result of its own (an extrapolation: its members' points together); ``parts``: its
        sample's realised part values (``{"L": [...], "C": [...]}``, :func:`lcchain.studies.plan.realised_parts`)."""
        self.add_many([(record, points)], parts=None if parts is None else {record.key: parts})

    def add_many(self, records: Sequence[tuple[RunRecord, int | None]], *,
                 parts: Mapping[str, Mapping[str, Sequence[float | None]]] | None = None) -> None:
        """Store finished runs in one transaction (in the log when this returns): what finished together is
        committed together (each (record, points) as for :meth:`add`; ``parts`` by key: a sample's realised part
        values, kept in its metrics under :data:`PARTS`)."""
        if self.mode != "write" or self._lock is None:
            raise self._refuse("a store that holds a plan, opened for writing (adopt one first)")
        rows = []
        for record, points in records:
            judged = record.metrics if record.metrics is not None else record.spectrum
            metrics = judged.to_dict() if judged is not None else None
            if record.measurements:  # beside any theory's metrics: an old store opens and reads them the same
                metrics = {**(metrics or {}), **measurement_fields(record.measurements)}
            if parts is not None and record.key in parts:  # a key of the metrics: an old store opens the same
                metrics = {**(metrics or {}), PARTS: dict(parts[record.key])}
            rows.append((record.key, record.status, record.reason, record.log_tail, record.digest, record.wall_s,
                         record.total_s, engine_text(record.engine, record.engine_version), record.lcchain_version,
                         record.points if record.points is not None else points,
                         json.dumps(metrics) if metrics is not None else None, _arrays(record), time.time()))
        with self._guard():
            self._db.execute("BEGIN")
            try:
                self._db.executemany("INSERT OR REPLACE INTO records VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                                     rows)
                self._db.execute("COMMIT")
            except BaseException:
                with contextlib.suppress(sqlite3.Error):
                    self._db.execute("ROLLBACK")
                raise

    @property
    def _select(self) -> str:
        return ("SELECT t.idx, t.key, t.params, t.label, r.status, r.reason, r.log_tail, r.digest, r.wall_s, "
                f"r.total_s, r.points, r.metrics, r.{self._engine_column}, r.lcchain_version "
                "FROM tasks t LEFT JOIN records r ON r.key = t.key")

    def _task(self, index: SQLValue, key: SQLValue, label: SQLValue, status: SQLValue) -> tuple[int, str, str, str]:
        """A task's number, key, label and status ("pending" before it ran), as the store must hold them."""
        if not isinstance(index, int) or not isinstance(key, str) or not isinstance(label, str | None) or \
                not isinstance(status, str | None):
            raise self._tampered(f"task {str(index)[:20]} has a number, key, label or status of the wrong type")
        return index, key, label or "", status or "pending"

    def _stored(self, row: Row) -> StoredRun:
        (index, key, params, label, status, reason, log_tail, digest, wall_s, total_s, points, metrics, ngv,
         lcv) = row
        try:
            if not isinstance(params, str | bytes) or not (metrics is None or isinstance(metrics, str | bytes)):
                raise TypeError
            params = json.loads(params)
            metrics = json.loads(metrics) if metrics else None
        except (json.JSONDecodeError, TypeError):
            raise self._tampered(f"run {index!r} holds params or metrics that are not JSON") from None
        if not isinstance(params, dict) or not (metrics is None or isinstance(metrics, dict)):
            raise self._tampered(f"run {index!r} holds params or metrics that are not JSON objects")
        if status is not None and status not in _STATUSES:
            raise self._tampered(f"run {index!r} has the status {str(status)[:20]!r}")
        index, key, label, status = self._task(index, key, label, status)
        texts = (reason, log_tail, digest, ngv, lcv)
        if not all(isinstance(text, str | None) for text in texts) or not all(
                isinstance(number, int | float | None) for number in (wall_s, total_s)) or not isinstance(
                points, int | None):
            raise self._tampered(f"run {index} holds a column of the wrong type")
        reason, log_tail, digest, ngv, lcv = (str(text or "") for text in texts)
        engine, version = engine_of(ngv)
        return StoredRun(index, key, params, label, status, reason, log_tail, digest,
                         None if wall_s is None else float(wall_s), None if total_s is None else float(total_s),
                         points, metrics, version, lcv, engine)

    def light_runs(self) -> list[StoredRun]:
        """Every task in plan order with its params and status only (its metrics unread: a price is taken before
        they are parsed)."""
        runs = []
        for index, key, params, label, status in self._rows(
                "SELECT t.idx, t.key, t.params, t.label, r.status FROM tasks t LEFT JOIN records r ON r.key = t.key "
                "ORDER BY t.idx"):
            try:
                if not isinstance(params, str | bytes):
                    raise TypeError
                params = json.loads(params)
            except (json.JSONDecodeError, TypeError):
                raise self._tampered(f"run {index!r} holds params that are not JSON") from None
            if not isinstance(params, dict):
                raise self._tampered(f"run {index!r} holds params that are not a JSON object")
            number, name, title, state = self._task(index, key, label, status)
            runs.append(StoredRun(number, name, params, title, state))
        return runs

    def runs(self) -> list[StoredRun]:
        """Every task in plan order, with its record where it ran."""
        return [self._stored(row) for row in self._rows(f"{self._select} ORDER BY t.idx")]

    def check_runs(self) -> int:
        """Every task read and checked as :meth:`runs` reads it (a row changed outside lcchain is refused), a
        window of rows at a time and none kept: what a study checks before it resumes, whatever its size (a
        resumed batch of 100,000 runs held them all).  How many tasks the store holds."""
        count = 0
        with self._guard():
            cursor = self._db.execute(f"{self._select} ORDER BY t.idx")
            while rows := cursor.fetchmany(_KEYS_A_QUERY):
                for row in rows:
                    self._stored(row)
                count += len(rows)
        return count

    def statuses(self) -> dict[str, tuple[str, str]]:
        """Each stored run's (status, reason) by key, its metrics and arrays unread: what a study's summary
        counts (reading every run's metrics for it grew the driver with the study)."""
        found: dict[str, tuple[str, str]] = {}
        for key, status, reason in self._rows("SELECT key, status, reason FROM records"):
            if status not in _STATUSES or not isinstance(status, str):
                raise self._tampered(f"run {str(key)[:12]} has the status {str(status)[:20]!r}")
            if not isinstance(key, str) or not isinstance(reason, str | None):
                raise self._tampered(f"run {str(key)[:12]} has a key or reason that is not text")
            found[key] = (status, reason or "")
        return found

    def records(self, keys: Sequence[str]) -> list[StoredRun]:
        """The stored runs under these keys, in their order (as the first task with each key)."""
        found = []
        for key in keys:
            rows = self._rows(f"{self._select} WHERE t.key = ? AND r.key IS NOT NULL ORDER BY t.idx LIMIT 1",
                              (key,))
            if not rows:
                raise self._refuse(f"a store holding the run {key[:12]}")
            found.append(self._stored(rows[0]))
        return found

    def waveforms(self, key: str) -> dict[str, np.ndarray] | None:
        """The saved arrays of a stored run (``"time"`` and each vector; an AC run's ``"frequency"`` and its
        complex vectors), or None; checked against its digest."""
        import numpy as np
        rows = self._rows("SELECT arrays, digest FROM records WHERE key = ?", (key,))
        if not rows or rows[0][0] is None:
            return None
        blob, digest = self._blob(key, rows[0][0]), rows[0][1]
        try:
            with np.load(io.BytesIO(blob), allow_pickle=False) as npz:
                names = [str(n) for n in npz["names"]]
                arrays = {name: _saved(npz[f"v{i}"]) for i, name in enumerate(names)}
        except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
            raise self._tampered(f"the arrays of run {key[:12]} are not lcchain's .npz") from None
        axis = next((name for name in ARRAY_AXES if name in arrays), None)
        if axis is None or np.iscomplexobj(arrays[axis]) or (digest and waveform_digest(
                arrays[axis], {k: v for k, v in arrays.items() if k != axis}, axis) != digest):
            raise self._tampered(f"the arrays of run {key[:12]} do not match its digest")
        return arrays

    def vector_names(self, key: str) -> list[str] | None:
        """The names of a stored run's saved vectors (without ``"time"`` or ``"frequency"``), or None when it
        saved none."""
        import numpy as np
        rows = self._rows("SELECT arrays FROM records WHERE key = ?", (key,))
        if not rows or rows[0][0] is None:
            return None
        try:
            with np.load(io.BytesIO(self._blob(key, rows[0][0])), allow_pickle=False) as npz:
                return [str(n) for n in npz["names"] if str(n) not in ARRAY_AXES]
        except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
            raise self._tampered(f"the arrays of run {key[:12]} are not lcchain's .npz") from None

    def __iter__(self) -> Iterator[StoredRun]:
        return iter(self.runs())

    def _shown(self) -> list[tuple[str, object]]:
        try:
            runs = self.light_runs()
        except LcchainError as error:  # closed (a with block's store, shown after it), or no longer readable
            why = "closed" if isinstance(error, _Closed) else "see Store.runs()"
            return [("store", str(self.path)), ("runs", f"not readable now ({why})")]
        counts: dict[str, int] = {}
        for run in runs:
            counts[run.status] = counts.get(run.status, 0) + 1
        statuses = ", ".join(f"{count} {status}" for status, count in sorted(counts.items()))
        dims, _ = study_dims([run for run in runs if not run.member])
        return [("store", str(self.path)), ("runs", f"{len(runs)} ({statuses or 'none'})"),
                ("dimensions", ", ".join(dims) if runs else "none")]

    def __repr__(self) -> str:
        """A few lines: the file, its runs by status, the study's dimensions (the runs: :meth:`runs`,
        :meth:`to_dataframe`, :meth:`to_xarray`)."""
        return short_repr("Store", self._shown())

    def _repr_html_(self) -> str:
        return html_table("Store", self._shown())

    def plot(self, ax: object = None, metric: str = "peak") -> Figure:
        """The figure the study's results call for, as ``lcchain results --plot`` draws it: tolerance samples'
        histogram (``metric``: ``peak``, ``energy`` or ``loss``), or the first arrival's loss against N.

        Returns
        -------
        matplotlib.figure.Figure
            Never shown.  matplotlib is imported here, not by ``import lcchain``.
        """
        return plot("store", self, ax=ax, metric=metric)

    def metrics_bytes(self) -> int:
        """Bytes of the stored metrics (JSON text), every row's."""
        return self._count("SELECT COALESCE(SUM(LENGTH(metrics)), 0) FROM records")

    def array_sizes(self, key: str) -> tuple[int, dict[str, tuple[int, int]]] | None:
        """The bytes the store holds for a run's saved arrays, and each array's (points, bytes per value) by name,
        read from their headers only; None when it saved none."""
        rows = self._rows("SELECT arrays FROM records WHERE key = ?", (key,))
        if not rows or rows[0][0] is None:
            return None
        blob = self._blob(key, rows[0][0])
        try:
            sizes = _array_headers(blob)
        except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
            raise self._tampered(f"the arrays of run {key[:12]} are not lcchain's .npz") from None
        return len(blob), sizes

    # ------------------------------------------------------------------ other shapes (lcchain.studies.exports)
    def to_dataframe(self) -> pd.DataFrame:
        """The runs as a pandas DataFrame (:func:`lcchain.studies.exports.to_dataframe`)."""
        return to_dataframe(self)

    def to_xarray(self, waveforms: bool = False) -> xr.Dataset:
        """The runs as an xarray Dataset whose dimensions are the study's axes, with each run's saved vectors
        when ``waveforms`` (:func:`lcchain.studies.exports.to_xarray`)."""
        return to_xarray(self, waveforms)

    def export_size(self, waveforms: bool = False) -> ExportSize:
        """What :meth:`to_xarray` (and the other exports) will hold (:func:`lcchain.studies.exports.export_size`)."""
        return export_size(self, waveforms)
