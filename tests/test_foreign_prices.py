"""Runs of netlists lcchain did not write are held to their limits while they go (issue 29, item 2).

The warm worker checked its memory only after a run (2.6 GiB under --max-memory 600M): now every transport (a
``ngspice -b`` process, the warm worker, the shared-library child) watches the resident memory of its child and
what it prints while the run goes, and stops it with a reason that says so.  No assert here is on a time: a
stopped run is checked by its status and reason.
"""

from __future__ import annotations

import pytest

from lcchain.core.errors import SimulationError
from lcchain.spice import processes, warm
from lcchain.spice.runner import run
from lcchain.spice.simulator import find_simulator

RC = "R1 in out 50\nC1 out 0 1p\n"


def _netlist(title: str, body: str, tran: str, save: str = ".save v(out)") -> str:
    return f"{title}\n{body}{tran}\n{save}\n.end\n"


# --------------------------------------------------------------------------- watched while they run

#: 60,000 resistors: ngspice holds about 60 MB before its first time point.
MANY = _netlist("many", "V1 n0 0 DC 1\n" + "".join(f"R{k} n0 0 1meg\n" for k in range(60_000)), ".tran 1n 10n",
                ".save v(n0)")
LIMIT = 40 * 2**20


@pytest.fixture(autouse=True)
def _no_worker_outlives_a_test():
    yield
    warm.close_workers(kill=True)


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "warm", "shared"])
def test_every_transport_stops_a_run_past_its_memory(backend: str) -> None:
    """The warm worker checked its memory only after a run (2.6 GiB under --max-memory 600M); now every transport
    watches the resident memory of its child while it runs."""
    simulator = find_simulator("shared" if backend == "shared" else "batch")
    if backend == "warm":
        simulator = warm.warm_simulator(simulator)
    with pytest.raises(SimulationError) as caught:
        run(MANY, ["v(n0)"], 1e-8, simulator=simulator, max_resident_bytes=LIMIT)
    assert caught.value.status == "failed"
    assert "memory grew past 40 MiB resident" in caught.value.reason and "was stopped" in caught.value.reason
    assert run(MANY, ["v(n0)"], 1e-8, simulator=simulator, max_resident_bytes=512 * 2**20).points > 1


@pytest.mark.ngspice
def test_a_warm_run_that_prints_past_its_limit_is_stopped(monkeypatch: pytest.MonkeyPatch) -> None:
    """What the warm worker's ngspice prints streams to a file the parent watches, as a ngspice -b run's does."""
    simulator = warm.warm_simulator(find_simulator("batch"))
    long = _netlist("t" * 200, "V1 in 0 SIN(0 1 1meg)\n" + RC, ".tran 1p 1u 0 1p")  # a million points
    monkeypatch.setattr(processes, "MAX_LOG_BYTES", 100)
    with pytest.raises(SimulationError, match="printed more than 100 B"):
        run(long, ["v(out)"], 1e-6, simulator=simulator, max_output_bytes=1e9)
    assert not [w for w in warm._workers if w.alive]  # the worker went with the run


@pytest.mark.ngspice
def test_a_warm_worker_keeps_its_log_per_run() -> None:
    simulator = warm.warm_simulator(find_simulator("batch"))
    first = run(_netlist("first title", "V1 in 0 DC 1\n" + RC, ".tran 1n 10n"), ["v(out)"], 1e-8, simulator=simulator)
    second = run(_netlist("second title", "V1 in 0 DC 1\n" + RC, ".tran 1n 10n"), ["v(out)"], 1e-8,
                 simulator=simulator)
    assert "first title" in first.log and "first title" not in second.log and "second title" in second.log
