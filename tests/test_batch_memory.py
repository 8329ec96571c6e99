"""A batch's driver keeps nothing a run while its runs go (issue 35: flat memory from 100 to 100,000 runs): the
names listed (--from LIST) are read as the batch is planned, its rows (keys, names, prices, flags) are in the
spool's temporary SQLite database, and the store's description lists the netlists from the spool as it is written.
Guarded by the Python memory traced in the driver for two batch sizes, with real ngspice (the plan before kept 196
bytes a run, this one 15 to 21); measurements at 100,000 runs are in benchmarks/batch_memory.md."""

from __future__ import annotations

import gc
import json
import tracemalloc
from pathlib import Path
from typing import Any

import pytest
from helpers.netlists import RC_NETLIST
from helpers.tolerances import MAX_BATCH_BYTES_PER_RUN

from lcchain.app.batch import BatchRequest, batch
from lcchain.app.studies import StudyOptions
from lcchain.studies import executors, stream
from lcchain.studies.store import Store

pytestmark = pytest.mark.ngspice

SMALL, LARGE = 80, 400
#: The runs at whose start the memory is read: the same in both batches (the least of more samples is lower).
SAMPLED = range(16, SMALL, 16)


def _listed(folder: Path, count: int) -> Path:
    """``count`` distinct RC netlists in ``folder`` and a list of them (names relative to nothing: absolute)."""
    folder.mkdir()
    names = []
    for i in range(count):
        path = folder / f"rc{i:04d}.cir"
        path.write_text(RC_NETLIST.replace("R1 in out 1000", f"R1 in out {1000 + i}"))
        names.append(str(path))
    listed = folder / "names.txt"
    listed.write_text("\n".join(names) + "\n")
    return listed


def _kept(listed: Path, store: Path, monkeypatch: pytest.MonkeyPatch) -> int:
    """The least Python memory traced at the starts of the runs :data:`SAMPLED` of a batch of the listed netlists
    (their groups of one: a batch's runs go one at a time)."""
    seen: list[int] = []
    execute_group = executors.execute_group

    def sampled(group: Any, *args: Any, **kwargs: Any) -> Any:
        if group[0][0] in SAMPLED:
            gc.collect()
            seen.append(tracemalloc.get_traced_memory()[0])
        return execute_group(group, *args, **kwargs)

    monkeypatch.setattr(executors, "execute_group", sampled)
    tracemalloc.start()
    try:
        result = batch(BatchRequest((), listed=str(listed), study=StudyOptions(workers=1, store=str(store))))
    finally:
        tracemalloc.stop()
    assert result.summary.ok == result.summary.total
    assert len(seen) == len(SAMPLED)
    return min(seen)


def test_a_batch_keeps_nothing_a_run_while_it_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(stream, "HELD", 0)  # every run spooled (a batch holds its first HELD, ~5 MB, at any size)
    monkeypatch.setattr(stream, "WINDOW", 16)  # the rows a batch reads at a time: fewer than either batch's
    # what a first batch loads or caches once (modules, the engine's version, compiled patterns) before either
    warm_up = _listed(tmp_path / "warm", 8)
    batch(BatchRequest((), listed=str(warm_up), study=StudyOptions(workers=2, store=str(tmp_path / "warm.sqlite"))))
    small = _kept(_listed(tmp_path / "small", SMALL), tmp_path / "small.sqlite", monkeypatch)
    large = _kept(_listed(tmp_path / "large", LARGE), tmp_path / "large.sqlite", monkeypatch)
    assert (large - small) / (LARGE - SMALL) < MAX_BATCH_BYTES_PER_RUN, (small, large)
    with Store(tmp_path / "large.sqlite", "read") as stored:  # the description lists every netlist, as given
        listed = (tmp_path / "large" / "names.txt").read_text().split()
        assert json.loads(stored.meta()["description"])["netlists"] == listed
