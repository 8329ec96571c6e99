"""A batch of foreign netlists planned with flat memory: its tasks on disk, not in the driver (issue 35).

:func:`lcchain.studies.plan.batch_plan` keeps every task (its checked text, ~2 KB a run) for the whole batch: 400 MB
of driver at 100,000 runs.  :func:`streamed_batch_plan` checks, prices and keys every netlist the same way
(:func:`lcchain.studies.plan._batch_task`, before anything runs: refusals, ``strict`` and the budget as there), but
keeps of each run only its key (32 bytes), its predicted seconds and a few flags; the run itself, past the first
:data:`HELD`, is pickled into :class:`TaskSpool`, an unnamed temporary file beside the store (nothing of it outlives
the driver, even killed).
:func:`lcchain.studies.run.run_plan` reads the runs back one by one as the executor asks for them: a
:class:`~lcchain.spice.foreign.CheckedText` unpickled is checked again by the allow-list, so what runs is what was
checked, whatever happened to the spool or to the netlist's file meanwhile.

The executors whose runs go in this process's threads stream it (``serial``, ``process``: a batch's runs have no
theory, and go to threads); the others (Dask, an executor of one's own) take the whole plan.
"""

from __future__ import annotations

import hashlib
import math
import pickle
import tempfile
from array import array
from collections.abc import Callable, Iterator, Sequence
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
from .executors import EXECUTOR_TRAITS, executor_cost
from .plan import Plan, Refusal, Task, _batch_task, _compare_seconds, _ForeignRuns, _refusal_key, _version_of

if TYPE_CHECKING:
    pass

__all__ = ["TaskSpool", "StreamedPlan", "streamed_batch_plan", "streams", "WINDOW", "HELD"]

#: Runs a batch keeps in memory as they were planned (at most ~5 MB of them) before it spools the rest: a run read
#: back from the spool has its text checked again by the allow-list (~0.3 ms, in the driver), which a batch of a
#: few thousand runs need not pay.
HELD = 2048
#: Netlists planned before their keys are made (the engine's version, which every key holds, is found meanwhile)
#: and runs read back from the spool at a time.
WINDOW = 256
_DIGEST = 32  # bytes of a key (a SHA-256)
#: Rows up to which :meth:`TaskSpool.first` compares keys in a set (a few hundred KB at most), not with numpy.
_SMALL = 4096


class TaskSpool:
    """A batch's rows in plan order: each run's spec pickled into an unnamed temporary file in ``folder``, and of
    every row (runs and refusals) its key, its seconds, its price's seconds and flags in arrays (~50 bytes a row).
    """

    def __init__(self, folder: str | None = None) -> None:
        try:
            self._file = tempfile.TemporaryFile(dir=folder)
        except OSError:  # a folder it cannot write in (the store's: its own error comes where it is made)
            self._file = tempfile.TemporaryFile()
        self._ends = array("Q")  # where each row's pickle ends (a refusal's, and a held run's, is empty)
        self._held: list[RunSpec] = []  # the first HELD runs, as they were planned
        self._first: bytearray | None = None  # made once every row is added (:meth:`first`)
        self.keys = bytearray()  # each row's key, 32 bytes
        self.seconds = array("d")  # each run's predicted seconds (a refusal's 0)
        self.cost = array("d")  # each run's seconds and its comparison's (the study's price)
        self.runs = bytearray()  # 1 for a run, 0 for a refusal
        self.warm = bytearray()  # 1 for a run an engine's warm transport may carry (its engine, analysis, text)
        self.memory = 0.0  # the largest run's memory, bytes
        self.light = True  # no run has a theory to compute

    def __len__(self) -> int:
        return len(self._ends)

    def add(self, item: Task | Refusal, key: str) -> None:
        blob = b""
        if isinstance(item, Task):
            spec = item.spec
            if len(self._held) < HELD:
                self._held.append(spec)
            else:
                blob = pickle.dumps(spec, protocol=pickle.HIGHEST_PROTOCOL)
            self.memory = max(self.memory, item.memory)
            self.light = self.light and spec.theory is None
            engine = ENGINES[spec.engine]
            self.warm.append(int(spec.engine == engine.name and not spec.trusted
                                 and spec.analysis in engine.warm_analyses))
            self.seconds.append(item.seconds)
            self.cost.append(item.seconds + _compare_seconds(spec))
            self.runs.append(1)
        else:
            self.warm.append(0)
            self.seconds.append(0.0)
            self.cost.append(0.0)
            self.runs.append(0)
        try:
            self._file.write(blob)
        except OSError as error:
            why = error.strerror or str(error)
            raise LcchainError(f"the batch's runs could not be spooled to disk beside its store ({why}): make room "
                               "and run the same command again") from None
        self._ends.append((self._ends[-1] if self._ends else 0) + len(blob))
        self.keys += bytes.fromhex(key)

    def key(self, index: int) -> str:
        return self.keys[_DIGEST * index:_DIGEST * (index + 1)].hex()

    def first(self) -> bytearray:
        """1 for each row whose key no earlier row has (two netlists of the same text, path and options are one
        run).  Rows are ranked by their keys' first 8 bytes (2 MB for 100,000 rows; ``numpy.unique`` of the whole
        keys took 15 MB); only rows that share those are compared whole."""
        if self._first is None and len(self) <= _SMALL:  # a set of the keys: no numpy before a small batch runs
            first = bytearray(b"\x01" * len(self))
            known: set[bytes] = set()
            for index in range(len(self)):
                whole = bytes(self.keys[_DIGEST * index:_DIGEST * (index + 1)])
                if whole in known:
                    first[index] = 0
                known.add(whole)
            self._first = first
        if self._first is None:
            import numpy as np

            first = bytearray(b"\x01" * len(self))
            prefix = np.frombuffer(self.keys, dtype=np.uint64)[::_DIGEST // 8]
            order = np.argsort(prefix, kind="stable")  # among equal prefixes, the earlier row first
            ranked = prefix[order]
            del prefix  # a view of the keys: released before any row is added
            shared = np.flatnonzero(ranked[1:] == ranked[:-1]).tolist()
            seen: set[str] = set()
            for at, position in enumerate(shared):
                if at == 0 or shared[at - 1] != position - 1:  # a new run of rows sharing a prefix
                    seen = {self.key(int(order[position]))}
                later = int(order[position + 1])
                key = self.key(later)
                if key in seen:
                    first[later] = 0
                seen.add(key)
            self._first = first
        return self._first

    def specs(self, chosen: bytearray) -> Iterator[tuple[int, RunSpec]]:
        """The spec of each row marked in ``chosen``, in plan order: held, or read back from disk (and its text
        checked again) as it is asked for."""
        self._file.flush()
        start = 0
        held = iter(self._held)
        for index, end in enumerate(self._ends):
            if self.runs[index] and end == start:  # a held run
                spec = next(held)
                if chosen[index]:
                    yield index, spec
            elif chosen[index] and end > start:
                self._file.seek(start)
                spec = pickle.loads(self._file.read(end - start))  # the spool is this driver's own, unnamed file
                if not isinstance(spec, RunSpec):
                    raise TypeError(f"row {index} of the spool is not a run")
                yield index, spec
            start = end

    def close(self) -> None:
        self._held.clear()
        self._file.close()


@dataclass(frozen=True)
class StreamedPlan(Plan):
    """A batch's plan whose runs are on disk (:class:`TaskSpool`), keyed for the engine ``version``; its
    :attr:`~Plan.tasks` is empty, its :attr:`~Plan.refusals` hold every refusal."""

    spool: TaskSpool = field(default_factory=TaskSpool, compare=False, repr=False)
    version: str = ""
    paths: tuple[str, ...] = ()

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
        for index, path in enumerate(self.paths):
            yield self.spool.key(index), {"netlist": path}, Path(path).name

    def fingerprint(self, ngspice_version: str) -> str:
        self._keyed(ngspice_version)
        digest = hashlib.sha256()
        for index in range(len(self.spool)):
            digest.update((b"\n" if index else b"") + self.spool.key(index).encode())
        return digest.hexdigest()

    def distinct(self) -> tuple[int, float]:
        """The distinct runs (refusals not counted) and their seconds together, with their comparisons (summed
        exactly: ``math.fsum``)."""
        first, spool = self.spool.first(), self.spool
        chosen = [index for index, (one, run) in enumerate(zip(first, spool.runs, strict=True)) if one and run]
        return len(chosen), math.fsum(spool.cost[index] for index in chosen)

    def estimate(self) -> float:
        return self.distinct()[1]

    def price(self, workers: int, executor: str = "process") -> Estimate:
        runs, seconds = self.distinct()
        used = max(1, min(workers, runs)) if EXECUTOR_TRAITS[executor].parallel else 1
        cost = executor_cost(executor, used, light=self.spool.light)
        warm = WARM_WORKER_BYTES if any(self.spool.warm) else 0.0
        return Estimate(f"{runs} runs on {used} worker{'s' if used > 1 else ''}",
                        cost.fixed + used * (cost.per_worker + self.spool.memory + warm),
                        self.planning + cost.start + seconds / used)

    def check(self, budget: Budget, workers: int, executor: str = "process", option: str | None = None) -> None:
        self.price(workers, executor).check(budget, option or self._made_by(), f"{self.distinct()[0]} runs",
                                            "fewer runs, fewer or more workers, or a larger --max-time or "
                                            "--max-memory")


def streams(executor: object, workers: int) -> bool:
    """Whether a batch on ``executor`` with ``workers`` runs in this process's threads, and so can be streamed."""
    return EXECUTOR_TRAITS.accept("--executor", executor).threads_here(workers) > 0


def streamed_batch_plan(paths: Sequence[str | Path], key_version: Callable[[], str], *, allow_control: bool = False,
                        backend: Backend = "batch", timeout: float = DEFAULT_TIMEOUT, budget: Budget | None = None,
                        strict: bool = False, engine_version: Callable[[], str] | None = None, check: bool = False,
                        folder: str | None = None) -> StreamedPlan:
    """:func:`lcchain.studies.plan.batch_plan`'s plan (the same checks, refusals, prices, keys and rows), its runs
    spooled to disk in ``folder`` (the store's; default the temporary folder) as they are planned.

    ``key_version`` gives the version of the engine that will run the batch (every key holds it): asked once the
    first :data:`WINDOW` netlists are planned (an engine found meanwhile is not waited for).
    """
    budget = budget if budget is not None else Budget()
    version = engine_version if engine_version is not None else _version_of(backend)
    runs = _ForeignRuns(backend, timeout, budget, version, trusted=allow_control, check=check)
    spool = TaskSpool(folder)
    refusals: list[Refusal] = []
    first: ParameterError | None = None
    window: list[Task | Refusal] = []
    keyed = ""
    planned = 0
    try:
        for index, name in enumerate(paths):
            path = Path(name)
            read: list[str] = []
            try:
                window.append(_batch_task(index, path, read, runs))
                planned += 1
            except ParameterError as error:
                if strict:
                    raise
                first = first or error
                refusal = Refusal(index, FrozenMap({"netlist": str(path)}), str(error),
                                  _refusal_key(str(path), read[0] if read else ""), path.name)
                refusals.append(refusal)
                window.append(refusal)
            if len(window) >= WINDOW:
                keyed = keyed or key_version()
                _spool(spool, window, keyed)
        if first is not None and not planned:  # nothing of it can run: bad input, as with strict
            raise first
        keyed = keyed or key_version()
        _spool(spool, window, keyed)
    except BaseException:
        spool.close()
        raise
    description: dict[str, JSON] = {"command": "batch", "netlists": [str(p) for p in paths],
                                    "allow_control": allow_control, "backend": backend}
    if check:
        description["check"] = True
    return StreamedPlan("batch", FrozenMap(description), (), backend, ("netlist",),
                        engine=DEFAULT_ENGINE, refusals=tuple(refusals), spool=spool, version=keyed,
                        paths=tuple(str(p) for p in paths))


def _spool(spool: TaskSpool, window: list[Task | Refusal], version: str) -> None:
    for item in window:
        spool.add(item, item.spec.key(version) if isinstance(item, Task) else item.key)
    window.clear()
