"""The CPU time of a command's fixed start beside numpy's (issue 35): less sensitive to a shared machine's load
than the wall time of ``benchmarks/bench_start.py``.

Run from the repository root:

    .venv/bin/python benchmarks/bench_start_cpu.py [--repeat 9]

Each command runs ``--repeat`` times, interleaved, with bytecode read and written as an installed lcchain does;
the CPU time (user + system, the process and its threads: numpy's BLAS threads spin at its start) is the change
in this process's children's resource usage, median.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys

ENV = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
PY = sys.executable
COMMANDS = {
    "`python -c pass`": [PY, "-c", "pass"],
    "`python -c 'import numpy'`": [PY, "-c", "import numpy"],
    "numpy and the standard modules a batch needs": [PY, "-c", "import numpy, sqlite3, subprocess, argparse, json, "
                                                              "hashlib"],
    "`lcchain --version`": [PY, "-m", "lcchain", "--version"],
    "`lcchain batch --help`": [PY, "-m", "lcchain", "batch", "--help"],
}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=9)
    args = parser.parse_args()
    times: dict[str, list[float]] = {name: [] for name in COMMANDS}
    before = os.getloadavg()[0]
    for _ in range(args.repeat):
        for name, command in COMMANDS.items():
            start = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run(command, env=ENV, capture_output=True, check=True)
            end = resource.getrusage(resource.RUSAGE_CHILDREN)
            times[name].append(end.ru_utime - start.ru_utime + end.ru_stime - start.ru_stime)
    print(f"CPU time, median of {args.repeat}; load average (1 min) {before:.2f} to {os.getloadavg()[0]:.2f}.\n")
    print("| command | CPU (ms) |\n|---|---:|")
    for name, values in times.items():
        print(f"| {name} | {1e3 * statistics.median(values):.1f} |")


if __name__ == "__main__":
    main()
