"""What a command costs before it does anything: ``lcchain --version``, ``--help`` and a one-netlist batch.

Run from the repository root, on a quiet machine:

    .venv/bin/python benchmarks/bench_startup.py > benchmarks/startup.md

Each time is the wall time of the whole process, median of 21 runs, interleaved with the interpreter alone
(``python -c pass``) and with ``import numpy``, the two floors.  The one-netlist batch also shows its CPU time
(user + system, children included) and its own ``wall_s`` (from planning to the last record stored).
"""

from __future__ import annotations

import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import lcchain
from lcchain.runs.simulate import ChainOptions, simulation_spec

REPEAT = 21


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="lcchain-bench-startup-") as folder:
        netlist = Path(folder) / "n10.cir"
        spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", 10), ChainOptions(dt=0.05))
        netlist.write_text(spec.netlist)
        commands = {
            "`python -c pass` (the interpreter alone)": [sys.executable, "-c", "pass"],
            "`python -c 'import numpy'`": [sys.executable, "-c", "import numpy"],
            "`lcchain --version`": [sys.executable, "-m", "lcchain", "--version"],
            "`lcchain --help`": [sys.executable, "-m", "lcchain", "--help"],
            "`lcchain batch --help`": [sys.executable, "-m", "lcchain", "batch", "--help"],
        }
        walls: dict[str, list[float]] = {name: [] for name in commands}
        batch: dict[str, list[float]] = {"wall": [], "cpu": [], "inside": []}
        for r in range(REPEAT):
            for name, command in commands.items():
                start = time.perf_counter()
                subprocess.run(command, capture_output=True, check=True)
                walls[name].append(time.perf_counter() - start)
            store = Path(folder) / f"s{r}.sqlite"
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "lcchain", "batch", str(netlist), "--store", str(store),
                                   "--json"], capture_output=True, check=True)
            batch["wall"].append(time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            batch["cpu"].append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
            batch["inside"].append(json.loads(done.stdout)["wall_s"])
    print("# What a command costs before it does anything\n")
    print("Command: `.venv/bin/python benchmarks/bench_startup.py > benchmarks/startup.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"lcchain {lcchain.__version__}. Wall time of the whole process, median of {REPEAT}, interleaved.\n")
    print("| command | wall (s) |")
    print("|---|---:|")
    for name, values in walls.items():
        print(f"| {name} | {statistics.median(values):.3f} |")
    print(f"| `lcchain batch ONE.cir` (N = 10, its sandbox and store included) | "
          f"{statistics.median(batch['wall']):.3f} |")
    print(f"\nThat one-netlist batch: {statistics.median(batch['cpu']):.3f} s of CPU (user + system, ngspice "
          f"and bubblewrap included), {statistics.median(batch['inside']):.3f} s from planning to the record "
          "stored (its `wall_s`).")


if __name__ == "__main__":
    main()
