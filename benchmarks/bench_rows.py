"""Every row of the validation report's tables, timed: each must sit on the smooth cost curve (issue 12).

Run from the repository root:

    .venv/bin/python benchmarks/bench_rows.py > benchmarks/rows.md

One design per row, one process, one BLAS thread; the evaluations column is
how many times the optimiser computed the first-arrival amplitude.
"""

from __future__ import annotations

import os
import platform
import time

import numpy as np

from lcchain.report.validation import REPORT_N
from lcchain.theory.design import optimal_design


def main() -> None:
    print("# Cost of every row of Tables I and II\n")
    print("Command: `.venv/bin/python benchmarks/bench_rows.py > benchmarks/rows.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"numpy {np.__version__}\n")
    print("| case | N | wall s | evaluations | s per 1000 masses |")
    print("|---|---:|---:|---:|---:|")
    totals = {}
    for case in ("one-mass", "two-mass"):
        total = 0.0
        for N in REPORT_N[case]:
            seen: list[float] = []
            start = time.perf_counter()
            optimal_design(case, N, progress=seen.append)
            wall = time.perf_counter() - start
            total += wall
            print(f"| {case} | {N} | {wall:.2f} | {len(seen)} | {1000 * wall / N:.3f} |", flush=True)
        totals[case] = total
    print()
    for case, total in totals.items():
        print(f"Total {case}: {total:.1f} s over {len(REPORT_N[case])} rows.  ")


if __name__ == "__main__":
    main()
