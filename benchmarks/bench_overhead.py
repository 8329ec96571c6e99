"""lcchain's own overhead per small run (N = 30): everything but ngspice's own process time.

Run from the repository root:

    .venv/bin/python benchmarks/bench_overhead.py > benchmarks/overhead.md

A study of thousands of small runs is bounded by what lcchain adds to each:
writing the netlist, starting ngspice, reading its raw file, the theory and
the comparison.  ngspice's time is the wall time of its process (RunResult.wall_s).
"""

from __future__ import annotations

import platform
import statistics
import subprocess
import time

import numpy as np

import lcchain
from lcchain.runs.execute import execute
from lcchain.runs.simulate import simulation_spec
from lcchain.spice.runner import run
from lcchain.spice.simulator import find_simulator

N = 30
REPEAT = 40


def median_ms(values: list[float]) -> str:
    return f"{1e3 * statistics.median(values):.1f}"


def main() -> None:
    simulator = find_simulator("batch")
    chain = lcchain.chain_for_case("two-mass", N)
    modes = lcchain.normal_modes(chain)
    spec, _, _ = simulation_spec(chain, dt=0.05, modes=modes)
    execute(spec, simulator)  # warm caches, imports and the BLAS limit

    rows: dict[str, list[float]] = {k: [] for k in ("build", "ngspice", "run", "execute", "simulate", "version")}
    for _ in range(REPEAT):
        start = time.perf_counter()
        spec, _, _ = simulation_spec(chain, dt=0.05, modes=modes)
        rows["build"].append(time.perf_counter() - start)

        start = time.perf_counter()
        result = run(spec.netlist, spec.vectors, spec.tstop, simulator=simulator)
        rows["run"].append(time.perf_counter() - start - result.wall_s)
        rows["ngspice"].append(result.wall_s)

        start = time.perf_counter()
        record = execute(spec, simulator)
        rows["execute"].append(time.perf_counter() - start - record.wall_s)

        start = time.perf_counter()
        report = lcchain.simulate(chain, dt=0.05, simulator=simulator)
        rows["simulate"].append(time.perf_counter() - start - report.run.wall_s)

        start = time.perf_counter()
        subprocess.run([simulator.executable, "-v"], capture_output=True, check=True)
        rows["version"].append(time.perf_counter() - start)

    print("# lcchain's overhead per small run\n")
    print("Command: `.venv/bin/python benchmarks/bench_overhead.py > benchmarks/overhead.md`  ")
    print(f"Machine: {platform.machine()}, 2 cores, Python "
          f"{platform.python_version()}, numpy {np.__version__}, ngspice {simulator.version}  ")
    print(f"Chain: optimal two-mass N = {N}, kick, dt = 0.05, one transit ({result.points} time points). "
          f"Median of {REPEAT} runs, milliseconds.\n")
    print("| what | ms |")
    print("|---|---:|")
    print(f"| ngspice's own process (netlist in, raw file out) | {median_ms(rows['ngspice'])} |")
    print(f"| lcchain: describing the run (step, netlist, spec) | {median_ms(rows['build'])} |")
    print(f"| lcchain: around ngspice in `spice.run` (start, read, validate) | {median_ms(rows['run'])} |")
    print(f"| lcchain: `execute` beyond ngspice (run + theory + comparison + digest) | {median_ms(rows['execute'])} |")
    print(f"| lcchain: `simulate` beyond ngspice (all of the above) | {median_ms(rows['simulate'])} |")
    print(f"| `ngspice -v`, which every run used to start as well | {median_ms(rows['version'])} |")


if __name__ == "__main__":
    main()
