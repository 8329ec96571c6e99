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
* The engine that ran it is in the ``ngspice_version`` column (and the meta
  row of that name), whose name is kept so that every store made before
  there were engines reads as it did: ngspice's version alone (``"39"``), any
  other engine's name and version (``"gnucap 2017.10.03"``;
  :func:`engine_text`, :func:`engine_of`).
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
import math
import os
import secrets
import sqlite3
import stat
import time
import urllib.parse
import zipfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np

from ..core import __version__
from ..core.errors import LcchainError, ParameterError
from ..core.extras import optional_module
from ..core.physical import vector_units
from ..core.show import html_table, plot, short_repr
from ..core.types import RUN_STATUSES
from ..runs.execute import RunRecord, waveform_digest
from ..spice.engines import DEFAULT_ENGINE
from ..spice.inputs import file_kind
from ..spice.measure import MEASURE_REASONS, MEASUREMENTS, measurement_fields

__all__ = ["Store", "StoredRun", "StoreMode", "FORMAT", "engine_text", "engine_of", "study_axes", "study_constants",
           "study_dims", "ExportSize", "PARTS"]

#: Version of the store's tables.
FORMAT = "1"
#: The key of a run's metrics that holds a tolerance or preferred-value sample's realised part values,
#: ``{"L": [...], "C": [...]}`` (henry, farad): ``lcchain results --json`` prints it as the run's ``parts``.
PARTS = "parts"
#: How a store is opened: to read it (``lcchain results``) or to run a study into it.
StoreMode = Literal["read", "write"]

_SCHEMA = """
CREATE TABLE meta (name TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE tasks (idx INTEGER PRIMARY KEY, key TEXT NOT NULL, params TEXT NOT NULL, label TEXT);
CREATE TABLE records (
    key TEXT PRIMARY KEY, status TEXT NOT NULL, reason TEXT, log_tail TEXT, digest TEXT,
    wall_s REAL, total_s REAL, ngspice_version TEXT, lcchain_version TEXT, points INTEGER,
    metrics TEXT, arrays BLOB, finished REAL
);
"""
#: The tables a store holds, and their columns: anything else is not an lcchain store.
_TABLES = {
    "meta": ("name", "value"),
    "tasks": ("idx", "key", "params", "label"),
    "records": ("key", "status", "reason", "log_tail", "digest", "wall_s", "total_s", "ngspice_version",
                "lcchain_version", "points", "metrics", "arrays", "finished"),
}
_HEADER = b"SQLite format 3\x00"
#: What a record's status may be (:data:`lcchain.core.types.RunStatus`); a store made before there were refusals
#: simply holds none.
_STATUSES = RUN_STATUSES
#: Seconds after which a hidden ``.NAME.*.new`` that no driver holds is a leftover of a killed one.
_STALE_SECONDS = 60.0
#: What a store's owner can do about a row or a page that is not as lcchain wrote it.
_RESTORE = "restore it from a copy, or run the study into a new store"


def engine_text(engine: str, version: str) -> str:
    """What the ``ngspice_version`` column (and meta row) holds: ngspice's version alone, as in every store made
    before there were engines (``"39"``); another engine's name and version (``"gnucap 2017.10.03"``)."""
    return version if engine == DEFAULT_ENGINE else f"{engine} {version}"


def engine_of(text: str) -> tuple[str, str]:
    """(engine, version) from :func:`engine_text`'s text (ngspice versions hold no space)."""
    engine, _, version = text.partition(" ")
    return (engine, version) if version else (DEFAULT_ENGINE, text)


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


@dataclass(frozen=True)
class StoredRun:
    """One task of a study as the store has it (``status`` is ``"pending"`` until it ran; ``"refused"``: a batch's
    netlist lcchain would not run, ``reason`` says why)."""

    index: int
    key: str
    params: dict[str, Any]
    label: str
    status: str
    reason: str = ""
    log_tail: str = ""
    digest: str = ""
    wall_s: float | None = None
    total_s: float | None = None
    points: int | None = None
    metrics: dict[str, Any] | None = None
    engine_version: str = ""
    lcchain_version: str = ""
    engine: str = DEFAULT_ENGINE

    @property
    def ngspice_version(self) -> str:
        """ngspice's version when ngspice ran it, else ""."""
        return self.engine_version if self.engine == DEFAULT_ENGINE else ""

    @property
    def kind(self) -> str:
        """``"run"``; ``"member"``, a run made to be extrapolated with others; or ``"combined"``, their
        extrapolation (its params hold ``runs``): the result, where the members are its ingredients."""
        return "member" if "member" in self.params else "combined" if "runs" in self.params else "run"

    @property
    def member(self) -> bool:
        return self.kind == "member"

    @property
    def spectral(self) -> bool:
        """An AC run compared with its theory (its metrics are :data:`lcchain.compare.spectral.SPECTRAL_METRICS`)."""
        return self.metrics is not None and self.metrics.get("analysis") == "ac"

    @property
    def measurements(self) -> dict[str, float | None]:
        """The netlist's ``.meas`` values by name (None: ngspice could not make it, :attr:`measure_reasons`
        says why); empty for a run without any."""
        return dict((self.metrics or {}).get(MEASUREMENTS) or {})

    @property
    def measure_reasons(self) -> dict[str, str]:
        """ngspice's reason for each missing measurement."""
        return dict((self.metrics or {}).get(MEASURE_REASONS) or {})

    @property
    def judged(self) -> bool:
        """Compared with a theory: its metrics hold more than measurements."""
        return self.metrics is not None and any(k not in (MEASUREMENTS, MEASURE_REASONS, PARTS)
                                                for k in self.metrics)

    @property
    def parts(self) -> dict[str, list[float | None]] | None:
        """A tolerance or preferred-value sample's realised part values: ``{"L": L_1..L_N (henry), "C": C_01..
        C_N,N+1 (farad; None where a wall is a wire)}``; None for a nominal chain, and in stores made before."""
        value = (self.metrics or {}).get(PARTS)
        return dict(value) if isinstance(value, dict) else None

    def record(self) -> RunRecord:
        """The run as a record without its arrays (:meth:`Store.waveforms` has them)."""
        if self.status not in _STATUSES:
            raise ParameterError("run", self.index, "a run that finished (this one is pending)")
        return RunRecord(key=self.key, status=self.status, reason=self.reason,
                         log_tail=self.log_tail, digest=self.digest, wall_s=self.wall_s or 0.0,
                         total_s=self.total_s or 0.0, engine=self.engine, engine_version=self.engine_version,
                         lcchain_version=self.lcchain_version, label=self.label)

    def to_dict(self) -> dict[str, Any]:
        """The object ``lcchain results --json`` prints for this task."""
        data: dict[str, Any] = {"index": self.index, "key": self.key, "kind": self.kind, "status": self.status,
                                "params": self.params, "label": self.label, "digest": self.digest or None,
                                "wall_s": self.wall_s, "points": self.points}
        if self.spectral:
            from ..compare.spectral import SPECTRAL_METRICS  # with an AC run only: a batch starts without it

            assert self.metrics is not None
            data.update({name: self.metrics.get(name) for name in SPECTRAL_METRICS})
        elif self.judged:
            assert self.metrics is not None
            data["max_abs_error"] = self.metrics.get("max_abs_error")
            data["predicted_error"] = self.metrics.get("predicted_error")
            data["arrivals"] = self.metrics.get("arrivals")
            if "effects" in self.metrics:  # against the circuit's own theory: what its effects cost the pulse
                data["effects"] = self.metrics["effects"]
        if self.parts is not None:
            data[PARTS] = self.parts
        if self.measurements:
            data[MEASUREMENTS] = self.measurements
            data[MEASURE_REASONS] = self.measure_reasons
        if self.status in ("failed", "timeout", "refused"):  # a refusal's reason: the netlist, line and field
            data["error"] = self.reason + (f"\n{self.engine} said:\n{self.log_tail}" if self.log_tail else "")
        return data


def study_axes(runs: list[StoredRun]) -> list[str]:
    """The parameters that vary across the study's tasks, in the plan's order. A constant one is no axis (every
    run shares it), nor one only some tasks have (an extrapolation's ``dt`` and ``runs`` where other points
    ran once, a member's ``member``). A study of a single task has no axes."""
    values: dict[str, set[str]] = {}
    for run in runs:
        for key, value in run.params.items():
            values.setdefault(key, set()).add(repr(value))
    keys = list(dict.fromkeys(key for run in runs for key in run.params))
    return [key for key in keys if len(values[key]) > 1 and all(key in run.params for run in runs)]


def study_constants(runs: list[StoredRun]) -> dict[str, Any]:
    """The parameters every task (extrapolation members aside) shares, with their one value."""
    runs = [run for run in runs if not run.member]
    axes = set(study_axes(runs))
    keys = list(dict.fromkeys(key for run in runs for key in run.params))
    return {key: runs[0].params[key] for key in keys
            if key not in axes and all(key in run.params for run in runs)} if runs else {}


def _value_key(value: Any) -> str:
    return json.dumps(value, sort_keys=True, default=str)


def study_dims(runs: list[StoredRun]) -> tuple[list[str], list[str]]:
    """The dimensions of a study's dataset (:meth:`Store.to_xarray`), and the axes that are coordinates along them.

    Its axes (:func:`study_axes`), in order, except an axis whose value the dimensions before it already fix for
    every run: a worst case's ``signs``, one per ``corner``, is a coordinate along ``corner``, not a dimension of
    its own (259 corners made a grid of 259 x 259 points, all but 259 of them empty, 2.5 GB of waveforms). Runs
    that are no grid (two at the same point) have the task number, ``index``, as their one dimension.
    """
    axes = study_axes(runs)
    points = [tuple(_value_key(run.params.get(axis)) for axis in axes) for run in runs]
    if not axes or len(set(points)) < len(points):
        return ["index"], []
    dims: list[int] = []
    along: list[int] = []
    for i in range(len(axes)):
        fixed: dict[tuple[str, ...], str] = {}
        if dims and all(fixed.setdefault(tuple(point[d] for d in dims), point[i]) == point[i] for point in points):
            along.append(i)
        else:
            dims.append(i)
    return [axes[i] for i in dims], [axes[i] for i in along]


@dataclass(frozen=True)
class ExportSize:
    """What exporting a store holds at once: the numbers ``lcchain results`` is priced by
    (:func:`lcchain.core.budget.export_estimate`).

    Attributes
    ----------
    runs : int
        Runs exported (extrapolation members left out).
    cells : int
        Points of the dataset's grid: the product of its dimensions' sizes (:func:`study_dims`).
    metrics : int
        Bytes of the stored metrics (JSON text), every row's.
    stored : int
        Bytes of the saved arrays read back (finished runs; 0 without waveforms).
    longest : int
        Points of the longest saved array (0 without waveforms).
    per_point : int
        Bytes per point of the dataset's waveform variables: every saved vector's and its axis's, each at its
        type's size (0 without waveforms).
    """

    runs: int
    cells: int
    metrics: int
    stored: int = 0
    longest: int = 0
    per_point: int = 0


def _array_headers(blob: bytes) -> dict[str, tuple[int, int]]:
    """Each saved array's (points, bytes per value) from a run's ``.npz`` without reading its values."""
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


#: The axis of a run's saved arrays: a transient's time, or an AC run's frequency.
_AXES = ("time", "frequency")


def _saved(values: np.ndarray) -> np.ndarray:
    """A stored array as lcchain wrote it: complex128 (an AC run's vectors) or float64; nothing else."""
    if values.dtype.kind not in "fc":
        raise ValueError("not a float or complex array")
    return np.asarray(values, dtype=complex if values.dtype.kind == "c" else float)


def _on_frequency(dataset: Any, axes: list[np.ndarray], longest: int, mixed: bool) -> Any:
    """AC runs' spectra on a ``frequency`` coordinate (Hz): the dimension itself when every run is an AC run that
    swept the same frequencies, else a coordinate beside the ``point`` dimension (NaN where a run swept fewer, or
    is a transient: ``mixed``)."""
    if not axes:
        return dataset
    same = all(axis.shape == axes[0].shape and np.array_equal(axis, axes[0]) for axis in axes)
    if same and not mixed and axes[0].size == longest:
        dataset = dataset.drop_vars("frequency").rename({"point": "frequency"})
        return dataset.assign_coords(frequency=axes[0])
    return dataset.set_coords("frequency")


def _number(value: Any) -> float:
    """A metric as a float column's value: NaN where the run has none (a batch run, a pulse's energy)."""
    return math.nan if value is None else float(value)


def measurement_column(name: str, row: Mapping[str, Any]) -> str:
    """A measurement's column in a run's row: its name, or ``meas_NAME`` when the row has a column of that name
    already (a parameter, ``status``, a metric)."""
    return f"meas_{name}" if name in row else name


#: The root's variables with a unit of their own; every other numeric one is dimensionless ("1").
_ROOT_UNITS = {"wall_s": "s", "total_s": "s", "L": "H", "C": "F", "time": "s", "frequency": "Hz"}
_ROOT_NAMES = {"t_sim": "first arrival's time (simulation), units of sqrt(L0 C0)",
               "t_theory": "first arrival's time (theory), units of sqrt(L0 C0)",
               "dt": "maximum time step, units of sqrt(L0 C0)", "wall_s": "simulator's wall time",
               "peak_sim": "first arrival's peak I_N / I_1(0) (simulation)",
               "peak_theory": "first arrival's peak I_N / I_1(0) (theory)",
               "max_abs_error": "max |simulation - theory|, units of I_1(0)", "points": "number of points",
               "L": "a sample's realised inductance L_i of coil i", "coil": "coil i = 1..N",
               "C": "a sample's realised capacitance C_j between masses j and j + 1 (NaN: a wire)",
               "capacitor": "capacitor j = 0..N (0 and N: the walls)"}


def _described(dataset: Any, runs: list[StoredRun]) -> Any:
    """The study's Dataset with every variable's ``long_name``, and its ``units`` where lcchain knows them (a
    ``.meas`` result's unit is whatever the netlist measured: named as such, no unit)."""
    measured = {str(name) for run in runs for name in run.measurements}
    measured |= {f"meas_{name}" for name in measured}
    for name in list(dataset.variables):
        variable = dataset[name]
        if str(name) in measured:
            variable.attrs.setdefault("long_name", f"{name}: a .meas result, in the unit of what the netlist "
                                      "measured (lcchain does not know it)")
            continue
        variable.attrs.setdefault("long_name", _ROOT_NAMES.get(str(name), str(name)))
        if variable.dtype.kind in "fiubc":
            variable.attrs.setdefault("units", _ROOT_UNITS.get(str(name), "1"))
    return dataset


def _optional(module: str) -> Any:
    """An optional package (pandas, xarray), or a one-line error saying how to install it."""
    return optional_module(module, "data", "a study's results as a table (pandas, xarray)")


def _arrays(record: RunRecord) -> bytes | None:
    """The saved arrays: ngspice's (time in seconds, each vector; an AC run's frequency in Hz and its complex
    vectors), or for an extrapolation, which has no run of its own, the combined signals it was compared by
    (dimensionless time, ``loop0``, ``loop1``...)."""
    if record.result is not None:
        arrays = {"time": record.result.time, **record.result.vectors}
    elif record.ac is not None:
        arrays = {"frequency": record.ac.frequency, **record.ac.vectors}
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
        for table, columns in _TABLES.items():
            found = tuple(row[1] for row in db.execute(f"PRAGMA table_info({table})"))
            if found != columns:
                raise self._refuse(f"an lcchain store (its table {table} has the columns {', '.join(found)})")
        meta = dict(db.execute("SELECT name, value FROM meta").fetchall())
        if meta.get("format") != FORMAT:
            raise self._refuse(f"a store of format {FORMAT} (this one is {meta.get('format', 'of none')})")
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
            return

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

    def _rows(self, sql: str, args: Sequence[Any] = ()) -> list[Any]:
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

    # ------------------------------------------------------------------ the plan
    def meta(self) -> dict[str, str]:
        return dict(self._rows("SELECT name, value FROM meta"))

    def check_plan(self, fingerprint: str, description: dict[str, Any], rows: int, ngspice_version: str) -> None:
        """Refuse a store that holds another plan (nothing is written).

        Raises
        ------
        ParameterError
            The store holds another plan.
        """
        meta = self.meta()
        if "plan" not in meta or meta["plan"] == fingerprint:
            return
        try:
            same = json.loads(meta.get("description", "null")) == json.loads(json.dumps(description))
        except json.JSONDecodeError:
            raise self._tampered("its description is not JSON") from None
        if same:
            held = self._rows("SELECT COUNT(*) FROM tasks")[0][0]
            raise self._refuse("a new store: it holds this very study as another lcchain or ngspice planned it "
                               f"({held} rows; lcchain {meta.get('lcchain_version', '?')}, ngspice "
                               f"{meta.get('ngspice_version', '?')}; now {rows} rows, ngspice {ngspice_version}), "
                               "and lcchain never mixes two")
        raise self._refuse("a new store, or the store of this very study: it holds another "
                           f"({meta.get('description', '?')}, ngspice {meta.get('ngspice_version', '?')}), and "
                           "lcchain never mixes two")

    def adopt(self, fingerprint: str, description: dict[str, Any], tasks: Sequence[tuple[str, dict[str, Any], str]],
              ngspice_version: str) -> None:
        """Make this the store of a plan, or check that it already is.

        A new store is made whole: built under a hidden name beside it, its plan
        written in one transaction, then linked under its own name.

        Parameters
        ----------
        fingerprint : str
            The plan's fingerprint (its ordered task keys, hashed).
        description : dict
            What the user asked for, in words and values (for ``lcchain results``).
        tasks : sequence of (key, params, label)
            The plan's tasks in order.
        ngspice_version : str

        Raises
        ------
        ParameterError
            The store holds another plan, or another driver made it meanwhile and writes it.
        """
        if self.mode != "write":
            raise self._refuse("a store opened for writing")
        self.check_plan(fingerprint, description, len(tasks), ngspice_version)
        if "plan" in self.meta():
            return
        meta = (("format", FORMAT), ("plan", fingerprint), ("description", json.dumps(description)),
                ("created", time.strftime("%Y-%m-%dT%H:%M:%S")), ("lcchain_version", __version__),
                ("ngspice_version", ngspice_version))
        rows = [(i, key, json.dumps(params), label) for i, (key, params, label) in enumerate(tasks)]
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
            self.adopt(fingerprint, description, tasks, ngspice_version)
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

    def description(self) -> dict[str, Any]:
        try:
            described = json.loads(self.meta().get("description", "{}"))
        except json.JSONDecodeError:
            raise self._tampered("its description is not JSON") from None
        return described if isinstance(described, dict) else {}

    # ------------------------------------------------------------------ records
    def finished(self) -> set[str]:
        """The keys of every run stored (ok, failed, timed out, or refused)."""
        return {row[0] for row in self._rows("SELECT key FROM records")}

    def failed(self) -> set[str]:
        """The keys of every run stored as failed or timed out (``--retry-failed`` runs them again)."""
        return {row[0] for row in self._rows("SELECT key FROM records WHERE status IN ('failed', 'timeout')")}

    def add(self, record: RunRecord, points: int | None = None, *, parts: Mapping[str, Any] | None = None) -> None:
        """Store one finished run, in one transaction (in the log when this returns: a killed driver keeps it);
        ``points`` when it has no result of its own (an extrapolation: its members' points together); ``parts``: its
        sample's realised part values (``{"L": [...], "C": [...]}``, :func:`lcchain.studies.plan.realised_parts`)."""
        self.add_many([(record, points)], parts=None if parts is None else {record.key: parts})

    def add_many(self, records: Sequence[tuple[RunRecord, int | None]], *,
                 parts: Mapping[str, Mapping[str, Any]] | None = None) -> None:
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

    _SELECT = ("SELECT t.idx, t.key, t.params, t.label, r.status, r.reason, r.log_tail, r.digest, r.wall_s, "
               "r.total_s, r.points, r.metrics, r.ngspice_version, r.lcchain_version "
               "FROM tasks t LEFT JOIN records r ON r.key = t.key")

    def _stored(self, row: tuple[Any, ...]) -> StoredRun:
        (index, key, params, label, status, reason, log_tail, digest, wall_s, total_s, points, metrics, ngv,
         lcv) = row
        try:
            params = json.loads(params)
            metrics = json.loads(metrics) if metrics else None
        except (json.JSONDecodeError, TypeError):
            raise self._tampered(f"run {index} holds params or metrics that are not JSON") from None
        if not isinstance(params, dict) or not (metrics is None or isinstance(metrics, dict)):
            raise self._tampered(f"run {index} holds params or metrics that are not JSON objects")
        if status is not None and status not in _STATUSES:
            raise self._tampered(f"run {index} has the status {str(status)[:20]!r}")
        engine, version = engine_of(ngv or "")
        return StoredRun(index, key, params, label or "", status or "pending", reason or "",
                         log_tail or "", digest or "", wall_s, total_s, points, metrics, version, lcv or "", engine)

    def _light_runs(self) -> list[StoredRun]:
        """Every task in plan order with its params and status only (its metrics unread: a price is taken before
        they are parsed)."""
        runs = []
        for index, key, params, label, status in self._rows(
                "SELECT t.idx, t.key, t.params, t.label, r.status FROM tasks t LEFT JOIN records r ON r.key = t.key "
                "ORDER BY t.idx"):
            try:
                params = json.loads(params)
            except (json.JSONDecodeError, TypeError):
                raise self._tampered(f"run {index} holds params that are not JSON") from None
            if not isinstance(params, dict):
                raise self._tampered(f"run {index} holds params that are not a JSON object")
            runs.append(StoredRun(index, key, params, label or "", status or "pending"))
        return runs

    def runs(self) -> list[StoredRun]:
        """Every task in plan order, with its record where it ran."""
        return [self._stored(row) for row in self._rows(f"{self._SELECT} ORDER BY t.idx")]

    def statuses(self) -> dict[str, tuple[str, str]]:
        """Each stored run's (status, reason) by key, its metrics and arrays unread: what a study's summary
        counts (reading every run's metrics for it grew the driver with the study)."""
        found = {}
        for key, status, reason in self._rows("SELECT key, status, reason FROM records"):
            if status not in _STATUSES:
                raise self._tampered(f"run {str(key)[:12]} has the status {str(status)[:20]!r}")
            found[key] = (status, reason or "")
        return found

    def records(self, keys: Sequence[str]) -> list[StoredRun]:
        """The stored runs under these keys, in their order (as the first task with each key)."""
        found = []
        for key in keys:
            rows = self._rows(f"{self._SELECT} WHERE t.key = ? AND r.key IS NOT NULL ORDER BY t.idx LIMIT 1",
                              (key,))
            if not rows:
                raise self._refuse(f"a store holding the run {key[:12]}")
            found.append(self._stored(rows[0]))
        return found

    def waveforms(self, key: str) -> dict[str, np.ndarray] | None:
        """The saved arrays of a stored run (``"time"`` and each vector; an AC run's ``"frequency"`` and its
        complex vectors), or None; checked against its digest."""
        rows = self._rows("SELECT arrays, digest FROM records WHERE key = ?", (key,))
        if not rows or rows[0][0] is None:
            return None
        blob, digest = rows[0]
        try:
            with np.load(io.BytesIO(blob), allow_pickle=False) as npz:
                names = [str(n) for n in npz["names"]]
                arrays = {name: _saved(npz[f"v{i}"]) for i, name in enumerate(names)}
        except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
            raise self._tampered(f"the arrays of run {key[:12]} are not lcchain's .npz") from None
        axis = next((name for name in _AXES if name in arrays), None)
        if axis is None or np.iscomplexobj(arrays[axis]) or (digest and waveform_digest(
                arrays[axis], {k: v for k, v in arrays.items() if k != axis}, axis) != digest):
            raise self._tampered(f"the arrays of run {key[:12]} do not match its digest")
        return arrays

    def vector_names(self, key: str) -> list[str] | None:
        """The names of a stored run's saved vectors (without ``"time"`` or ``"frequency"``), or None when it
        saved none."""
        rows = self._rows("SELECT arrays FROM records WHERE key = ?", (key,))
        if not rows or rows[0][0] is None:
            return None
        try:
            with np.load(io.BytesIO(rows[0][0]), allow_pickle=False) as npz:
                return [str(n) for n in npz["names"] if str(n) not in _AXES]
        except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
            raise self._tampered(f"the arrays of run {key[:12]} are not lcchain's .npz") from None

    def __iter__(self) -> Iterator[StoredRun]:
        return iter(self.runs())

    def _shown(self) -> list[tuple[str, object]]:
        try:
            runs = self._light_runs()
        except ParameterError:  # closed (a with block's store, shown after it), or no longer readable
            return [("store", str(self.path)), ("runs", "not readable now (closed)")]
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

    def plot(self, ax: Any = None, metric: str = "peak") -> Any:
        """The figure the study's results call for, as ``lcchain results --plot`` draws it: tolerance samples'
        histogram (``metric``: ``peak``, ``energy`` or ``loss``), or the first arrival's loss against N.

        Returns
        -------
        matplotlib.figure.Figure
            Never shown.  matplotlib is imported here, not by ``import lcchain``.
        """
        return plot("store", self, ax=ax, metric=metric)

    # ------------------------------------------------------------------ other shapes
    def to_dataframe(self) -> Any:
        """The runs as a pandas DataFrame: one row per task (index: the task's number), the study's parameters
        as columns, then kind, status, key, digest, points, the simulator's wall time and the metrics (NaN or
        None where a run has none). A sample's realised part values are left out of the table (N + 1 columns
        each would bury the metrics): they are :meth:`to_xarray`'s ``L`` and ``C``, and each
        :attr:`StoredRun.parts`. pandas is optional: ``pip install 'lcchain[data]'``."""
        pd = _optional("pandas")
        return pd.DataFrame(self._table_rows(self.runs())).set_index("index")


    def to_xarray(self, waveforms: bool = False) -> Any:
        """The runs as an xarray Dataset whose dimensions are the study's axes.

        Each axis (a parameter that varies across the study's results: ``N``, ``case``, ``dt``, ``sample``,
        ``netlist``...) is a dimension with its values as coordinate; every metric is a variable on them (NaN
        where a combination did not run or has no such metric). An extrapolation's members are left out: its
        combined result is the point's. A study whose runs do not form a grid (two runs at the same point)
        has the task number as its one dimension, ``index``.

        Tolerance or preferred-value samples also have their realised part values: ``L`` (henry) on the
        dimension ``coil`` (1..N) and ``C`` (farad) on ``capacitor`` (0..N: C_j joins masses j and j + 1, 0 and N
        the walls; NaN where a wall is a wire, or a run had no such part).

        Parameters
        ----------
        waveforms : bool
            Also each run's saved vectors and their time, on a ``point`` dimension (a run's own time values,
            padded with NaN to the longest run): the variable ``time`` and one per vector.

        xarray is optional: ``pip install 'lcchain[data]'``.
        """
        _optional("xarray")
        results = [run for run in self.runs() if not run.member]
        dims, along = study_dims(results)
        constants = study_constants(results)
        frame = _optional("pandas").DataFrame(self._table_rows(results))
        dataset = frame.drop(columns=list(constants)).set_index(dims).to_xarray().set_coords(along)
        dataset.attrs.update({"store": str(self.path), **{key: str(value) for key, value in constants.items()}})
        dataset = self._with_parts(dataset, dims, results)
        if waveforms:
            dataset = self._with_waveforms(dataset, dims, [run for run in results if run.status == "ok"])
        return _described(dataset, results)

    def export_size(self, waveforms: bool = False) -> ExportSize:
        """What :meth:`to_xarray` (and the other exports) will hold, read without building any of it: the runs,
        the grid of the study's dimensions, the metrics' text and, with ``waveforms``, each finished run's saved
        arrays (their headers only, a run at a time)."""
        results = [run for run in self._light_runs() if not run.member]
        dims, _ = study_dims(results)
        cells = len(results) if dims == ["index"] else math.prod(
            len({_value_key(run.params.get(d)) for run in results}) for d in dims)
        metrics = int(self._rows("SELECT COALESCE(SUM(LENGTH(metrics)), 0) FROM records")[0][0])
        if not waveforms:
            return ExportSize(len(results), cells, metrics)
        stored = longest = 0
        per_name: dict[str, int] = {}
        for run in results:
            if run.status != "ok":
                continue
            rows = self._rows("SELECT arrays FROM records WHERE key = ?", (run.key,))
            if not rows or rows[0][0] is None:
                continue
            blob = rows[0][0]
            stored += len(blob)
            try:
                sizes = _array_headers(blob)
            except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
                raise self._tampered(f"the arrays of run {run.key[:12]} are not lcchain's .npz") from None
            for name, (points, itemsize) in sizes.items():
                longest = max(longest, points)
                per_name[name] = max(per_name.get(name, 0), itemsize)
        return ExportSize(len(results), cells, metrics, stored, longest, sum(per_name.values()))

    @staticmethod
    def _table_rows(runs: list[StoredRun]) -> list[dict[str, Any]]:
        """One row per run: its parameters, status and metrics (a transient's, an AC run's, or both kinds' in a
        store that holds both)."""
        spectral = any(run.spectral for run in runs)
        transient = not spectral or any(run.metrics is not None and not run.spectral for run in runs)
        costs = any(run.metrics is not None and "effects" in run.metrics for run in runs)
        measured = list(dict.fromkeys(name for run in runs for name in run.measurements))
        rows = []
        for run in runs:
            metrics = run.metrics or {}
            arrivals = metrics.get("arrivals") or []
            first = arrivals[0] if arrivals else {}
            row = {"index": run.index, **run.params, "kind": run.kind, "status": run.status, "key": run.key,
                   "digest": run.digest or None, "points": run.points, "wall_s": run.wall_s,
                   # the engine's name and its version apart (engine_text's "39" is the store's column, not a name)
                   "engine": run.engine if run.status != "pending" else None,
                   "engine_version": run.engine_version if run.status != "pending" else None}
            if transient:
                row.update({name: _number(metrics.get(name)) for name in ("max_abs_error", "predicted_error")})
                row.update({name: _number(first.get(name)) for name in ("t_sim", "t_theory", "peak_sim",
                                                                          "peak_theory", "energy_sim")})
            if costs:  # runs against their circuit's own theory: what the effects cost the ideal chain's pulse
                cost = metrics.get("effects") or {}
                row.update({f"effects_{name}": _number(cost.get(name))
                            for name in ("peak_ideal", "energy_ideal", "energy_loss", "delay")})
            if spectral:
                from ..compare.spectral import SPECTRAL_METRICS  # with an AC run only: a batch starts without it

                row.update({name: _number(metrics.get(name)) for name in SPECTRAL_METRICS})
            values = run.measurements
            row.update({measurement_column(name, row): _number(values.get(name)) for name in measured})
            rows.append(row)
        return rows

    @staticmethod
    def _with_parts(dataset: Any, dims: list[str], runs: list[StoredRun]) -> Any:
        """The dataset with the samples' part values, ``L`` on ``coil`` and ``C`` on ``capacitor``."""
        pd = _optional("pandas")
        rows: dict[str, list[dict[str, Any]]] = {"L": [], "C": []}
        for run in runs:
            parts = run.parts
            if parts is None:
                continue
            at = {dim: run.index if dim == "index" else run.params.get(dim) for dim in dims}
            rows["L"] += [{**at, "coil": i + 1, "L": _number(v)} for i, v in enumerate(parts.get("L") or [])]
            rows["C"] += [{**at, "capacitor": j, "C": _number(v)} for j, v in enumerate(parts.get("C") or [])]
        for name, dim in (("L", "coil"), ("C", "capacitor")):
            if rows[name]:
                values = pd.DataFrame(rows[name]).set_index([*dims, dim]).to_xarray()
                dataset = dataset.merge(values, join="left")
                dataset[name].attrs["units"] = "H" if name == "L" else "F"
        return dataset

    def _with_waveforms(self, dataset: Any, dims: list[str], runs: list[StoredRun]) -> Any:
        arrays = {run.index: self.waveforms(run.key) or {} for run in runs}
        longest = max((a[axis].size for a in arrays.values() for axis in _AXES if axis in a), default=0)
        names = list(dict.fromkeys(name for a in arrays.values() for name in a))
        shape = [dataset.sizes[d] for d in dims] + [longest]
        positions = {d: {value: i for i, value in enumerate(dataset.indexes[d])} for d in dims}
        for name in names:
            complex_values = any(np.iscomplexobj(a[name]) for a in arrays.values() if name in a)
            # a complex vector's padding is NaN in both parts (nan + 0j would read as a real part of NaN and an
            # imaginary part of 0)
            values = np.full(shape, complex(np.nan, np.nan) if complex_values else np.nan,
                             dtype=complex if complex_values else float)
            for run in runs:
                series = arrays[run.index].get(name)
                if series is not None:
                    where = tuple(positions[d][run.index if d == "index" else run.params[d]] for d in dims)
                    values[where][: series.size] = series
            units = {"time": "s", "frequency": "Hz"}.get(name) or vector_units(name)
            dataset[name] = ([*dims, "point"], values, {"units": units, "long_name": name})
        sweeps = [a["frequency"] for a in arrays.values() if "frequency" in a]
        mixed = any("time" in a for a in arrays.values())  # a batch of .tran and .ac netlists: one point axis
        return _on_frequency(dataset, sweeps, longest, mixed)
