"""Extrapolation in a study (issue 14): a sweep whose points are pairs and triples, each member a task.

Run from the repository root (about a minute):

    .venv/bin/python benchmarks/bench_extrapolate_sweep.py > benchmarks/extrapolate-sweep.md

The sweep is ``lcchain sweep --case two-mass --N 100,1000 --accuracy 1e-7`` on the process pool (2 workers),
into a new store: ``--accuracy`` chooses as ``lcchain simulate`` does (a pair at N = 100, a triple at
N = 1000), each member runs as a task of its own, and the store combines them.  It is run three times, each
into a new store; the table gives each point's combination from the last store, the wall time of the three
(spawning the pool, planning, every run, combining and storing), and the members' ngspice times summed (one
core's cost).  The single runs that meet 1e-7 take 6.97 s (N = 100) and 482 s (N = 1000)
(``benchmarks/extrapolate.md``).
"""

from __future__ import annotations

import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

from lcchain.spice.ngspice.find import find_simulator
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import SweepAxes, sweep_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store

COMMAND = "lcchain sweep --case two-mass --N 100,1000 --accuracy 1e-7 --store S --workers 2"
REPEATS = 3


def main() -> None:
    walls = []
    with tempfile.TemporaryDirectory() as folder:
        for k in range(REPEATS):
            path = Path(folder) / f"s{k}.sqlite"
            clock = time.perf_counter()
            plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[100, 1000], accuracies=[1e-7]))
            summary = run_plan(plan, path, RunOptions(executor="process", workers=2))
            walls.append(time.perf_counter() - clock)
            assert summary.complete, summary
        with Store(path) as store:
            rows = store.runs()
    simulator = find_simulator("batch")
    print("# Extrapolation in a sweep: each member a task of the store\n")
    print(f"Machine: {os.cpu_count()} cores, Python {platform.python_version()}, ngspice {simulator.version}. "
          "Command: `.venv/bin/python benchmarks/bench_extrapolate_sweep.py > benchmarks/extrapolate-sweep.md`, "
          f"which times `{COMMAND}` ({REPEATS} times, each into a new store).\n")
    print("| N | runs | dt | members' errors | combined error | predicted | members' ngspice s (summed) |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        if row.kind != "combined":
            continue
        members = [r for r in rows if r.kind == "member" and row.index - row.params["runs"] <= r.index < row.index]
        steps = ", ".join(format(r.params["dt"], ".4g") for r in members)
        errors = ", ".join(format((r.metrics or {}).get("max_abs_error", float("nan")), ".1e") for r in members)
        metrics = row.metrics or {}
        print(f"| {row.params['N']} | {row.params['runs']} | {steps} | {errors} | "
              f"{metrics.get('max_abs_error', float('nan')):.3e} | "
              f"{metrics.get('predicted_error', float('nan')):.3e} | {sum(r.wall_s or 0.0 for r in members):.2f} |")
    print(f"\nWall time of the whole sweep (pool start-up, planning, {len([r for r in rows if r.kind == 'member'])} "
          f"runs, combining, storing): median {statistics.median(walls):.1f} s "
          f"({', '.join(f'{w:.1f}' for w in walls)} s). The single runs that meet 1e-7: 6.97 s + 482 s "
          "(benchmarks/extrapolate.md).")


if __name__ == "__main__":
    main()
