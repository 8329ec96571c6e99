"""CPU (all processes: the driver, the sandbox, ngspice) of one foreign netlist run REPEAT times through one of
ngspice's transports, in one process: what ``--transport auto``'s threshold trades.

    for R in 5 25; do perf stat -e task-clock -x, .venv/bin/python benchmarks/transport_cpu.py {warm|process} N $R; done

prints the run's price (``foreign_price``'s seconds) and its median wall; the difference of ``perf stat``'s
task-clock (CPU ms, children included: the sandbox, ngspice, the warm worker) between 25 and 5 runs, divided by 20,
is a run's CPU through that transport, without the interpreter's start, the imports and the worker's start (``none``
runs nothing: that fixed part alone).  CPU, unlike wall time, changes little with the load of a shared machine.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

import lcchain
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.ngspice.warm import close_workers, warm_simulator
from lcchain.studies.plan import batch_plan

transport, N, repeat = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", N), ChainOptions(dt=0.04))
with tempfile.TemporaryDirectory() as folder:
    path = Path(folder) / "n.cir"
    path.write_text(spec.netlist)
    task = batch_plan([path]).tasks[0]
if transport != "none":
    batch = find_simulator("batch")
    simulator = warm_simulator(batch) if transport == "warm" else batch
    walls = []
    for _ in range(repeat):
        start = time.perf_counter()
        run(RunJob(task.spec.netlist, task.spec.vectors, task.spec.tstop, foreign=True), simulator)
        walls.append(time.perf_counter() - start)
    close_workers()
    print(f"N={N} {transport} price {task.seconds:.3f} s, wall median {1e3 * statistics.median(walls):.1f} ms")
