"""The result store: one SQLite file that survives a crash and never mixes two studies.

* stdlib ``sqlite3`` in WAL mode with ``synchronous = FULL``: every finished
  run is one transaction, durable when it returns, so killing the driver
  (Ctrl-C or SIGKILL) loses no finished run; only the driver writes.
* A run is stored under its key (:meth:`lcchain.runs.spec.RunSpec.key`: the
  netlist text, saved vectors, stop time, backend, theory, lcchain and ngspice
  versions); a study that finds its key stored skips the run.
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
numpy ``.npz``).
"""

from __future__ import annotations

import io
import json
import sqlite3
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..core import __version__
from ..core.errors import ParameterError
from ..runs.execute import RunRecord

__all__ = ["Store", "StoredRun", "FORMAT"]

#: Version of the store's tables.
FORMAT = "1"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (name TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS tasks (idx INTEGER PRIMARY KEY, key TEXT NOT NULL, params TEXT NOT NULL, label TEXT);
CREATE TABLE IF NOT EXISTS records (
    key TEXT PRIMARY KEY, status TEXT NOT NULL, reason TEXT, log_tail TEXT, digest TEXT,
    wall_s REAL, total_s REAL, ngspice_version TEXT, lcchain_version TEXT, points INTEGER,
    metrics TEXT, arrays BLOB, finished REAL
);
"""


@dataclass(frozen=True)
class StoredRun:
    """One task of a study as the store has it (``status`` is ``"pending"`` until it ran)."""

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
    ngspice_version: str = ""
    lcchain_version: str = ""

    @property
    def kind(self) -> str:
        """``"run"``; ``"member"``, a run made to be extrapolated with others; or ``"combined"``, their
        extrapolation (its params hold ``runs``): the result, where the members are its ingredients."""
        return "member" if "member" in self.params else "combined" if "runs" in self.params else "run"

    @property
    def member(self) -> bool:
        return self.kind == "member"

    def record(self) -> RunRecord:
        """The run as a record without its arrays (:meth:`Store.waveforms` has them)."""
        if self.status not in ("ok", "failed", "timeout"):
            raise ParameterError("run", self.index, "a run that finished (this one is pending)")
        return RunRecord(key=self.key, status=self.status, reason=self.reason,  # type: ignore[arg-type]
                         log_tail=self.log_tail, digest=self.digest, wall_s=self.wall_s or 0.0,
                         total_s=self.total_s or 0.0, ngspice_version=self.ngspice_version,
                         lcchain_version=self.lcchain_version, label=self.label)

    def to_dict(self) -> dict[str, Any]:
        """The object ``lcchain results --json`` prints for this task."""
        data: dict[str, Any] = {"index": self.index, "key": self.key, "kind": self.kind, "status": self.status,
                                "params": self.params, "label": self.label, "digest": self.digest or None,
                                "wall_s": self.wall_s, "points": self.points}
        if self.metrics is not None:
            data["max_abs_error"] = self.metrics.get("max_abs_error")
            data["predicted_error"] = self.metrics.get("predicted_error")
            data["arrivals"] = self.metrics.get("arrivals")
        if self.status in ("failed", "timeout"):
            data["error"] = self.reason + (f"\nngspice said:\n{self.log_tail}" if self.log_tail else "")
        return data


def _arrays(record: RunRecord) -> bytes | None:
    """The saved arrays: ngspice's (time in seconds, each vector), or for an extrapolation, which has no run of
    its own, the combined signals it was compared by (dimensionless time, ``loop0``, ``loop1``...)."""
    if record.result is not None:
        arrays = {"time": record.result.time, **record.result.vectors}
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
        The ``.sqlite`` file (created with its tables when missing).
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)
        try:
            self._db = sqlite3.connect(self.path, timeout=60.0, isolation_level=None)
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("PRAGMA synchronous=FULL")
            self._db.executescript(_SCHEMA)
        except sqlite3.Error as error:
            raise ParameterError("--store", str(path), f"an SQLite file lcchain can write ({error})") from None
        found = self.meta().get("format")
        if found is not None and found != FORMAT:
            raise ParameterError("--store", str(path), f"a store of format {FORMAT} (this one is {found})")

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ the plan
    def meta(self) -> dict[str, str]:
        return dict(self._db.execute("SELECT name, value FROM meta").fetchall())

    def adopt(self, fingerprint: str, description: dict[str, Any], tasks: Sequence[tuple[str, dict[str, Any], str]],
              ngspice_version: str) -> None:
        """Make this the store of a plan, or check that it already is.

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
            The store holds another plan.
        """
        meta = self.meta()
        if "plan" in meta:
            if meta["plan"] != fingerprint:
                if json.loads(meta.get("description", "null")) == json.loads(json.dumps(description)):
                    held = self._db.execute("SELECT COUNT(*) FROM tasks").fetchone()[0]
                    raise ParameterError("--store", str(self.path), "a new store: it holds this very study as "
                                         f"another lcchain or ngspice planned it ({held} rows; lcchain "
                                         f"{meta.get('lcchain_version', '?')}, ngspice "
                                         f"{meta.get('ngspice_version', '?')}; now {len(tasks)} rows, ngspice "
                                         f"{ngspice_version}), and lcchain never mixes two")
                raise ParameterError("--store", str(self.path), "a new store, or the store of this very study: it "
                                     f"holds another ({meta.get('description', '?')}, ngspice "
                                     f"{meta.get('ngspice_version', '?')}), and lcchain never mixes two")
            return
        with self._db:
            self._db.execute("BEGIN")
            for name, value in (("format", FORMAT), ("plan", fingerprint), ("description", json.dumps(description)),
                                ("created", time.strftime("%Y-%m-%dT%H:%M:%S")), ("lcchain_version", __version__),
                                ("ngspice_version", ngspice_version)):
                self._db.execute("INSERT INTO meta VALUES (?, ?)", (name, value))
            self._db.executemany("INSERT INTO tasks VALUES (?, ?, ?, ?)",
                                 [(i, key, json.dumps(params), label) for i, (key, params, label) in enumerate(tasks)])

    def description(self) -> dict[str, Any]:
        return json.loads(self.meta().get("description", "{}"))

    # ------------------------------------------------------------------ records
    def finished(self) -> set[str]:
        """The keys of every run stored (ok, failed or timed out)."""
        return {row[0] for row in self._db.execute("SELECT key FROM records")}

    def add(self, record: RunRecord, points: int | None = None) -> None:
        """Store one finished run, in one transaction (durable when this returns); ``points`` when it has no
        result of its own (an extrapolation: its members' points together)."""
        metrics = record.metrics.to_dict() if record.metrics is not None else None
        points = record.result.points if record.result is not None else points
        with self._db:
            self._db.execute("BEGIN")
            self._db.execute(
                "INSERT OR REPLACE INTO records VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (record.key, record.status, record.reason, record.log_tail, record.digest, record.wall_s,
                 record.total_s, record.ngspice_version, record.lcchain_version, points,
                 json.dumps(metrics) if metrics is not None else None, _arrays(record), time.time()))

    _SELECT = ("SELECT t.idx, t.key, t.params, t.label, r.status, r.reason, r.log_tail, r.digest, r.wall_s, "
               "r.total_s, r.points, r.metrics, r.ngspice_version, r.lcchain_version "
               "FROM tasks t LEFT JOIN records r ON r.key = t.key")

    @staticmethod
    def _stored(row: tuple[Any, ...]) -> StoredRun:
        (index, key, params, label, status, reason, log_tail, digest, wall_s, total_s, points, metrics, ngv,
         lcv) = row
        return StoredRun(index, key, json.loads(params), label or "", status or "pending", reason or "",
                         log_tail or "", digest or "", wall_s, total_s, points,
                         json.loads(metrics) if metrics else None, ngv or "", lcv or "")

    def runs(self) -> list[StoredRun]:
        """Every task in plan order, with its record where it ran."""
        return [self._stored(row) for row in self._db.execute(f"{self._SELECT} ORDER BY t.idx").fetchall()]

    def records(self, keys: Sequence[str]) -> list[StoredRun]:
        """The stored runs under these keys, in their order (as the first task with each key)."""
        found = []
        for key in keys:
            row = self._db.execute(f"{self._SELECT} WHERE t.key = ? AND r.key IS NOT NULL ORDER BY t.idx LIMIT 1",
                                   (key,)).fetchone()
            if row is None:
                raise ParameterError("--store", str(self.path), f"a store holding the run {key[:12]}")
            found.append(self._stored(row))
        return found

    def waveforms(self, key: str) -> dict[str, np.ndarray] | None:
        """The saved arrays of a stored run (``"time"`` and each vector), or None."""
        row = self._db.execute("SELECT arrays FROM records WHERE key = ?", (key,)).fetchone()
        if row is None or row[0] is None:
            return None
        with np.load(io.BytesIO(row[0]), allow_pickle=False) as npz:
            names = [str(n) for n in npz["names"]]
            return {name: npz[f"v{i}"] for i, name in enumerate(names)}

    def __iter__(self) -> Iterator[StoredRun]:
        return iter(self.runs())

    # ------------------------------------------------------------------ other shapes
    def to_dataframe(self) -> Any:
        """The runs as a pandas DataFrame, one row per task, params as columns (pandas is optional)."""
        import pandas as pd  # optional: only for those who have it

        rows = []
        for run in self.runs():
            row = {"index": run.index, "kind": run.kind, "status": run.status, **run.params, "digest": run.digest,
                   "wall_s": run.wall_s, "max_abs_error": (run.metrics or {}).get("max_abs_error")}
            arrivals = (run.metrics or {}).get("arrivals") or []
            if arrivals:
                row["peak_sim"], row["peak_theory"] = arrivals[0]["peak_sim"], arrivals[0]["peak_theory"]
            rows.append(row)
        return pd.DataFrame(rows).set_index("index")

    def to_xarray(self) -> Any:
        """The runs as an xarray Dataset along ``index`` (xarray is optional)."""
        return self.to_dataframe().to_xarray()
