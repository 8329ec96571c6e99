"""lcchain's own overhead per small run (N = 30): everything but ngspice's own process time.

Run from the repository root:

    .venv/bin/python benchmarks/bench_overhead.py > benchmarks/overhead.md

A study of thousands of small runs is bounded by what lcchain adds to each:
writing the netlist, starting ngspice, reading its raw file, the theory and
the comparison.  ngspice's own time is measured by itself: the same netlist
run as ``ngspice -n -b -r RAW FILE`` from ``subprocess.run``, with no lcchain
around it; lcchain's share of a run is what a call takes beyond that.  The
process time lcchain records (``RunResult.wall_s``, from the start of the
child to the exit its pidfd reports) is shown beside it.
"""

from __future__ import annotations

import platform
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import lcchain
from lcchain.runs.execute import execute
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.ngspice.warm import close_workers, warm_simulator

N = 30
REPEAT = 40


def median_ms(values: list[float]) -> str:
    return f"{1e3 * statistics.median(values):.1f}"


def main() -> None:
    simulator = find_simulator("batch")
    chain = lcchain.chain_for_case("two-mass", N)
    modes = lcchain.normal_modes(chain)
    spec, _, _ = simulation_spec(chain, ChainOptions(dt=0.05), modes=modes)
    execute(spec, simulator)  # warm caches, imports and the BLAS limit

    rows: dict[str, list[float]] = {k: [] for k in ("build", "alone", "ngspice", "run", "execute", "simulate",
                                                     "version", "warm")}
    hot = warm_simulator(simulator)
    folder = tempfile.TemporaryDirectory(prefix="lcchain-bench-")
    netlist, raw = Path(folder.name) / "run.cir", Path(folder.name) / "run.raw"
    netlist.write_text(spec.netlist)
    run(RunJob(spec.netlist, spec.vectors, spec.tstop, trusted=True, foreign=False), hot)  # its worker started
    for _ in range(REPEAT):
        start = time.perf_counter()
        subprocess.run([simulator.executable, "-n", "-b", "-r", str(raw), str(netlist)], capture_output=True,
                       check=True)
        rows["alone"].append(time.perf_counter() - start)

        start = time.perf_counter()
        spec, _, _ = simulation_spec(chain, ChainOptions(dt=0.05), modes=modes)
        rows["build"].append(time.perf_counter() - start)

        start = time.perf_counter()
        result = run(RunJob(spec.netlist, spec.vectors, spec.tstop), simulator)
        rows["run"].append(time.perf_counter() - start)
        rows["ngspice"].append(result.wall_s)

        start = time.perf_counter()
        run(RunJob(spec.netlist, spec.vectors, spec.tstop, trusted=True, foreign=False), hot)
        rows["warm"].append(time.perf_counter() - start)

        start = time.perf_counter()
        execute(spec, simulator)
        rows["execute"].append(time.perf_counter() - start)

        start = time.perf_counter()
        lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.05), simulator=simulator)
        rows["simulate"].append(time.perf_counter() - start)

        start = time.perf_counter()
        subprocess.run([simulator.executable, "-v"], capture_output=True, check=True)
        rows["version"].append(time.perf_counter() - start)

    close_workers()
    folder.cleanup()
    alone = statistics.median(rows["alone"])

    def beyond(key: str) -> str:
        return f"{1e3 * (statistics.median(rows[key]) - alone):.1f}"

    print("# lcchain's overhead per small run\n")
    print("Command: `.venv/bin/python benchmarks/bench_overhead.py > benchmarks/overhead.md`  ")
    print(f"Machine: {platform.machine()}, 2 cores, Python "
          f"{platform.python_version()}, numpy {np.__version__}, ngspice {simulator.version}  ")
    print(f"Chain: optimal two-mass N = {N}, kick, dt = 0.05, one transit ({result.points} time points). "
          f"Median of {REPEAT} runs, milliseconds. \"Beyond ngspice\": a call's median wall time minus the median "
          "of ngspice's process by itself.\n")
    print("| what | ms |")
    print("|---|---:|")
    print(f"| ngspice's process by itself (`ngspice -n -b -r RAW FILE` from `subprocess.run`, no lcchain) | "
          f"{1e3 * alone:.1f} |")
    print(f"| the same process as lcchain records it (`RunResult.wall_s`: its start to the exit its pidfd "
          f"reports) | {median_ms(rows['ngspice'])} |")
    print(f"| lcchain: describing the run (step, netlist, spec) | {median_ms(rows['build'])} |")
    print(f"| lcchain: `spice.run` beyond ngspice (start, wait, read, validate) | {beyond('run')} |")
    print(f"| lcchain: `execute` beyond ngspice (run + theory + comparison + digest) | {beyond('execute')} |")
    print(f"| lcchain: `simulate` beyond ngspice (all of the above) | {beyond('simulate')} |")
    print(f"| one run in a warm worker (`lcchain.spice.ngspice.warm`), whole call | {median_ms(rows['warm'])} |")
    print(f"| `ngspice -v`, which every run used to start as well | {median_ms(rows['version'])} |")

if __name__ == "__main__":
    main()
